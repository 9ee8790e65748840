#!/usr/bin/env python3
"""Formal reachability of every bin of the coverage model, on the twin.

    hdl/formal/coverage.py [--rtl FILELIST.f] [--sets small,default,sync1,w8d4]
                           [--timeout S] [--cover-depth N] [--jobs 2] [--bins SUBSTR]
                           [--hits coverage.json] [--out DIR] [--no-cache]

The coverage monitor hdl/formal/pmu50_cov.sv (generated from the model by `pmu50 hdl
coverage-monitor`: one `hit_<bin>` per bin, the table hdl/formal/pmu50_cov.json) is bound to the
twin's ports and, with yosys `connect`, to its registers, internals and next-state nets. Per
parameter set, one AIGER model holds one output per check (hdl/formal/run.py's flow: ABC scorr
over every check at once, then each check's cone to the engines):

- a bin declared unreachable: `assert (!hit_<bin>)`, proven unbounded (scorr, or rIC3 / ABC pdr
  side by side) on every set of --sets (the declared reasons are structural: they hold for any
  parameter values, which the bus can change anyway). A refuted assertion is a wrong
  declaration: its trace (ABC bmc3 on the unreduced cone) becomes OUT/witness/<bin>.vec, the
  stimulus as a vector file (inputs; `// param` lines of the set), which the model replays
  (`cargo test --test coverage_witness`) and which must hit the bin there too;
- every other bin: `cover (hit_<bin>)`, a witness searched by ABC bmc3 to --cover-depth cycles
  on the first set of --sets where it is found (small first: its periods are 9 ticks). A cover
  that scorr or pdr shows unreachable on a set is tried on the next one.

A bin neither proven nor witnessed is `undecided`. With --hits (a regression's coverage.json),
bins with hits are also marked `hit`.

Output: OUT/coverage.json: per bin its status (proven_unreachable with the property and the
sets, witnessed with the set and cycle, wrong_declaration with the witness file, undecided with
what was tried), and the totals; one line per decided unreachable bin and a summary on stdout.
Exit 0: every declared-unreachable bin proven on every set and no bin undecided; 1: a wrong
declaration, an unproven unreachable bin or an undecided bin; 2: setup or tool failure.
"""
import argparse
import concurrent.futures as cf
import json
import os
import re
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import run as kit  # noqa: E402  (the formal kit's flow: models, cones, engines, cache)
from aiger import Aiger, AigerError, cone_map  # noqa: E402

HDL = kit.HDL
ROOT = kit.ROOT
TABLE = os.path.join(HERE, "pmu50_cov.json")
MONITOR = os.path.join(HERE, "pmu50_cov.sv")
TOP = "pmu50_cov_formal"
# Parameter sets of the kit, and one with the structural classes no kit set has (CNT_W in
# 8..15, SYNC_DEPTH 4), short like `small`.
SETS = dict(kit.SETS)
SETS["w8d4"] = dict(SYNC_DEPTH=4, CNT_W=8, ADAPTIVE=1, PW=1, PI=1, PS=1, SI_MAX=9, SI_MIN=4,
                    T1=3, T2=2, CTH=2, SMP_ON=3)
KIT_FILES = [os.path.abspath(__file__), TABLE, MONITOR] + kit.KIT_FILES


def load_table(path=TABLE):
    try:
        t = json.load(open(path))
    except (OSError, ValueError) as e:
        raise kit.SetupError("cannot read the monitor's table %s: %s (pmu50 hdl coverage-monitor "
                             "writes it)" % (path, e))
    return t


def formal_top(table, checks):
    """The formal top: reset in cycle 0, the twin, the monitor over its ports, and one check per
    (label, kind, bin index)."""
    ports = [s for s in table["signals"] if s["source"] == "port"]
    n = len(table["bins"])
    params = ",\n".join("    parameter integer %s = %d" % (k, v) for k, v in SETS["default"].items())
    lines = ["`default_nettype none", "module %s #(\n%s,\n    parameter integer CLOCK_NS = 10000\n) (" % (TOP, params),
             "    input wire clk, input wire ig, input wire vs2_ok, input wire cmp_s, input wire cmp_c,",
             "    input wire bus_we, input wire [7:0] bus_addr, input wire [15:0] bus_wdata\n);",
             "    reg f_started = 1'b0;",
             "    always @(posedge clk) f_started <= 1'b1;",
             "    wire rst_n = f_started;",
             "    wire sig, vr_hi, vm_en, vs1_en, vs2_en, vp_en, rail_hi, st, sr, ps_win, smp;",
             "    wire cs, cc, hist_s, hist_c, diag, quadrant_skip, bus_err;",
             "    wire [CNT_W-1:0] cnt_s, cnt_c;",
             "    wire [7:0] cnt_r;",
             "    wire [15:0] si, bus_rdata;",
             "    pmu50 #(.SYNC_DEPTH(SYNC_DEPTH), .CNT_W(CNT_W), .ADAPTIVE(ADAPTIVE), .PW(PW), .PI(PI),"
             " .PS(PS), .SI_MAX(SI_MAX), .SI_MIN(SI_MIN), .T1(T1), .T2(T2), .CTH(CTH),"
             " .SMP_ON(SMP_ON)) dut (.*);",
             "    wire [%d:0] hits;" % (n - 1),
             "    // the monitor's internal inputs are connected by yosys `connect` after `flatten`",
             "    pmu50_cov #(.SYNC_DEPTH(SYNC_DEPTH), .CNT_W(CNT_W), .CLOCK_NS(CLOCK_NS)) cov (.clk(clk), "
             + ", ".join(".%s(%s)" % (s["name"], s["name"]) for s in ports) + ", .hits(hits));",
             "    always @* begin"]
    for label, kind, i in checks:
        lines.append("        %s: %s (%shits[%d]);" % (label, kind, "!" if kind == "assert" else "", i))
    lines += ["    end", "endmodule", "`default_nettype wire", ""]
    return "\n".join(lines)


def build_model(setname, table, checks, files, incs, defs, out, timeout):
    """OUT/<set>/: the formal top, design.il, model.aig (+ .aim), scorr.aig -> kit.SetModel."""
    d = os.path.join(out, setname)
    os.makedirs(d, exist_ok=True)
    kit.write_atomic(os.path.join(d, "top.sv"), formal_top(table, checks))
    dflags = " ".join("-D" + x for x in defs)
    iflags = " ".join("-I" + x for x in incs)
    lines = ["read_verilog -formal -sv top.sv",
             "read_verilog -formal -sv %s %s %s" % (dflags, iflags, MONITOR)]
    for f in files:
        sv = "-sv " if f.endswith((".sv", ".svh")) else ""
        lines.append("read_verilog -formal %s%s %s %s" % (sv, dflags, iflags, f))
    for k, v in SETS[setname].items():
        lines.append("chparam -set %s %d %s" % (k, v, TOP))
    lines += ["hierarchy -top %s" % TOP, "proc", "flatten"]
    for s in table["signals"]:
        if s["source"] != "port":
            lines.append("connect -nounset -set cov.%s dut.%s" % (s["name"], s["source"]))
    # every monitor input driven: a net the RTL does not have would otherwise become a free input
    lines += ["prep -top %s" % TOP, "async2sync", "check -assert", "write_rtlil design.il"]
    kit.write_atomic(os.path.join(d, "design.ys"), "\n".join(lines) + "\n")
    rc = kit.run(["yosys", "-q", "design.ys"], d, "design.log")
    if rc != 0:
        raise kit.SetupError("yosys could not read the monitor over the RTL for set %s (rc %s): see "
                             "%s (a net of the monitor's table missing from the RTL?)"
                             % (setname, rc, os.path.join(d, "design.log")))
    text, names = kit.checks_to_outputs(open(os.path.join(d, "design.il")).read(), top=TOP)
    kit.write_atomic(os.path.join(d, "checks.il"), text)
    ys = ("read_rtlil checks.il\nsetundef -undriven -anyseq\nopt -fast\nmemory_map\nopt -fast\n"
          "techmap\nopt -fast\ndffunmap\naigmap\nopt_clean\nwrite_aiger -zinit -map model.aim model.aig\n")
    kit.write_atomic(os.path.join(d, "model.ys"), ys)
    rc = kit.run(["yosys", "-q", "model.ys"], d, "model.log")
    if rc != 0:
        raise kit.SetupError("yosys could not map the model of set %s: see %s"
                             % (setname, os.path.join(d, "model.log")))
    aim = open(os.path.join(d, "model.aim")).read()
    index = {}
    for line in aim.splitlines():
        f = line.split()
        if f and f[0] == "output" and f[3].startswith("chk__"):
            index[f[3][5:]] = int(f[1])
    missing = sorted(set(names) - set(index))
    if missing:
        raise kit.SetupError("set %s: checks missing from the model: %s" % (setname, ", ".join(missing[:5])))
    if os.path.exists(os.path.join(d, "scorr.aig")):
        os.remove(os.path.join(d, "scorr.aig"))
    rc = kit.run(["yosys-abc", "-c", "read_aiger model.aig; fold; strash; scorr; write_aiger scorr.aig"],
                 d, "scorr.log", timeout=max(timeout, 300))
    try:
        model = Aiger(open(os.path.join(d, "model.aig"), "rb").read())
        reduced = model
        if rc == 0 and os.path.exists(os.path.join(d, "scorr.aig")):
            reduced = Aiger(open(os.path.join(d, "scorr.aig"), "rb").read())
    except (AigerError, ValueError) as e:
        raise kit.SetupError("set %s: unreadable AIGER model: %s" % (setname, e))
    if len(reduced.outputs) != len(model.outputs):
        raise kit.SetupError("set %s: ABC changed the number of outputs" % setname)
    return kit.SetModel(d, index, model, reduced, aim)


def engines(names):
    es = [e for e in (kit.Ric3(), kit.AbcPdr()) if e.name.split("-")[0] in names.split(",") and e.available()]
    if not es:
        raise kit.SetupError("no engine available (asked for %s)" % names)
    return es


def prove(m, label, a, d):
    """An assertion `label`: (proven|refuted|unknown, frame, how)."""
    if m.proven_by_scorr(label):
        return "proven", None, "scorr"
    os.makedirs(d, exist_ok=True)
    data, _ = m.cone(label)
    kit.write_atomic(os.path.join(d, "cone.aig"), data)
    res = kit.run_engines(engines(a.engines), "cone.aig", d, a.timeout)
    v, frame, eng = kit.decisive(res)
    if v == "unknown":
        r = kit.run_engines([kit.AbcBmc(a.cover_depth)], "cone.aig", d, a.timeout)["abc-bmc"]
        if r[0] == "refuted":
            return "refuted", r[1], "abc-bmc"
        return "unknown", None, ", ".join("%s %s" % (k, x[0]) for k, x in res.items())
    return v, frame, eng


def cover(m, label, a, d):
    """A cover `label`: (reached|unreachable|unknown, frame, how)."""
    if m.proven_by_scorr(label):
        return "unreachable", None, "scorr"
    os.makedirs(d, exist_ok=True)
    data, _ = m.cone(label)
    kit.write_atomic(os.path.join(d, "cone.aig"), data)
    r = kit.run_engines([kit.AbcBmc(a.cover_depth)], "cone.aig", d, a.cover_timeout)["abc-bmc"]
    if r[0] == "refuted":
        return "reached", r[1], "abc-bmc"
    # not within the depth: perhaps unreachable on this set (a structural class of another)
    res = kit.run_engines([kit.AbcPdr()], "cone.aig", d, a.cover_timeout)
    v, frame, eng = kit.decisive(res)
    if v == "proven":
        return "unreachable", None, eng
    if v == "refuted":
        return "reached", frame, eng
    return "unknown", None, "abc-bmc %s" % ("no trace in %s cycles" % r[1] if r[0] == "bounded" else r[0])


def witness(m, setname, label, depth, binname, out):
    """The trace of a failing check (bmc3 on the unreduced cone) -> a vector file of its inputs
    (docs/spec.md 6.2 header, the set's parameters, one line per tick out of reset). Returns
    the path or None."""
    d = os.path.join(m.d, label)
    os.makedirs(d, exist_ok=True)
    data, latch_map = m.cone(label, reduced=False)
    kit.write_atomic(os.path.join(d, "cex.aig"), data)
    aim = cone_map(m.aim, latch_map)
    abc = "read_aiger cex.aig; fold; strash; bmc3 -F %d; write_cex -a trace.aiw" % (depth + 2)
    kit.run(["yosys-abc", "-c", abc], d, "abc_cex.log", timeout=600)
    path = os.path.join(d, "trace.aiw")
    if not os.path.exists(path):
        return None
    lines = [l.strip() for l in open(path) if l.strip()]
    # 1 / b0 / initial latches / one line of inputs per frame / .
    try:
        k = lines.index("b0") if "b0" in lines else 1
        frames = [l for l in lines[k + 2:] if l != "."]
    except ValueError:
        return None
    bits = {}  # input position -> (name, bit)
    for line in aim.splitlines():
        f = line.split()
        if f and f[0] == "input":
            bits[int(f[1])] = (f[3], int(f[2]))

    def value(frame, name):
        v = 0
        for pos, (n, b) in bits.items():
            if n == name and pos < len(frame) and frame[pos] == "1":
                v |= 1 << b
        return v

    # frame 0 is the reset cycle; the vector file starts out of reset
    rows = []
    for fr in frames[1:]:
        rows.append(" ".join("%0*x" % (kit.IN_DIGITS.get(n, 1), value(fr, n)) for n, _ in kit.INPUTS))
    text = ["// pmu50 vectors v1 (inputs only: a coverage witness)", "// bin %s" % binname,
            "// clock_ns 10000"]
    text += ["// param %s %d" % (k, v) for k, v in SETS[setname].items()]
    text += ["// ticks %d" % len(rows), "// columns " + " ".join(n for n, _ in kit.INPUTS)]
    os.makedirs(out, exist_ok=True)
    f = os.path.join(out, re.sub(r"[^A-Za-z0-9_.-]", "_", binname) + ".vec")
    kit.write_atomic(f, "\n".join(text + rows) + "\n")
    return f


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rtl", default=os.path.join(HDL, "pmu50.f"))
    ap.add_argument("--sets", default="small,default,sync1,w8d4",
                    help="parameter sets (proofs on each; covers on the first that reaches): "
                    + ", ".join(SETS))
    ap.add_argument("--timeout", type=int, default=120, help="seconds per proof engine run")
    ap.add_argument("--cover-depth", type=int, default=60, help="cycles of a cover's bounded search")
    ap.add_argument("--cover-timeout", type=int, default=20, help="seconds per cover search")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--engines", default="ric3,abc")
    ap.add_argument("--bins", default="", help="only bins whose name holds this string")
    ap.add_argument("--no-covers", action="store_true", help="the unreachable bins' proofs only")
    ap.add_argument("--hits", default="", help="a regression's coverage.json: its hit bins")
    ap.add_argument("--no-cache", action="store_true",
                    default=os.environ.get("FORMAL_CACHE", "1") == "0")
    ap.add_argument("--out", default=os.path.join(HDL, "build", "formal", "coverage"))
    a = ap.parse_args(argv)
    t0 = time.time()
    try:
        for tool in ("yosys", "yosys-abc"):
            if not shutil.which(tool):
                raise kit.SetupError("%s not found (Debian package yosys)" % tool)
        table = load_table()
        sets = a.sets.split(",")
        bad = [s for s in sets if s not in SETS]
        if bad:
            raise kit.SetupError("unknown parameter sets %s (valid: %s)" % (", ".join(bad), ", ".join(SETS)))
        files, incs, defs = kit.parse_filelist(a.rtl)
        bins = [b for b in table["bins"] if a.bins in b["name"]]
        if not bins:
            raise kit.SetupError("no bin's name holds %r" % a.bins)
        hit = set()
        if a.hits:
            try:
                cj = json.load(open(a.hits))
                for b in cj.get("bins", []):
                    if b.get("hits", 0) > 0:
                        hit.add(b["name"])
            except (OSError, ValueError, AttributeError) as e:
                raise kit.SetupError("--hits %s: %s" % (a.hits, e))
        cache = kit.Cache(os.path.join(a.out, "cache"), not a.no_cache)
        salt_files = files + KIT_FILES
        salt = (kit.sources_digest(salt_files, incs, defs, ""), a.engines, a.timeout, a.cover_depth,
                a.cover_timeout, kit.tool_versions(a.engines))
        unreach = [b for b in bins if b["unreachable"]]
        reach = [] if a.no_covers else [b for b in bins if not b["unreachable"]]
        checks = [("u_%d" % b["index"], "assert", b["index"]) for b in unreach]
        checks += [("c_%d" % b["index"], "cover", b["index"]) for b in reach]
        models = {}

        def model(s):
            if s not in models:
                models[s] = build_model(s, table, checks, files, incs, defs, a.out, a.timeout)
            return models[s]

        def cached(s, label, fn):
            key = kit.Cache.key(salt, s, SETS[s], label, [c[0] for c in checks])
            got = cache.get(key)
            if got:
                return tuple(got["r"]) + (True,)
            r = fn(model(s), label, a, os.path.join(a.out, s, label))
            if r[0] != "unknown":
                cache.put(key, {"r": list(r)})
            return r + (False,)

        status = {}
        # 1. proofs: every declared-unreachable bin on every set
        jobs = [(s, b) for s in sets for b in unreach]
        with cf.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
            # models first (yosys, once per set), two at a time
            list(ex.map(model, sets))
            futs = {ex.submit(cached, s, "u_%d" % b["index"], prove): (s, b) for s, b in jobs}
            proofs = {}
            for f in cf.as_completed(futs):
                s, b = futs[f]
                proofs[(s, b["name"])] = f.result()
        wrong = []
        for b in unreach:
            per = {s: proofs[(s, b["name"])] for s in sets}
            proven = [s for s in sets if per[s][0] == "proven"]
            refuted = [s for s in sets if per[s][0] == "refuted"]
            st = {"declared_unreachable": b["unreachable"], "property": "assert (!%s)" % b["wire"],
                  "proofs": {s: {"verdict": per[s][0], "how": per[s][2]} for s in sets}}
            if refuted:
                s = refuted[0]
                f = witness(model(s), s, "u_%d" % b["index"], per[s][1] or a.cover_depth, b["name"],
                            os.path.join(a.out, "witness"))
                st.update(status="wrong_declaration", set=s, witness=f and os.path.relpath(f, ROOT),
                          cycle=per[s][1])
                wrong.append(b["name"])
            elif len(proven) == len(sets):
                st.update(status="proven_unreachable", sets=proven)
            else:
                st.update(status="undecided", sets_proven=proven)
            status[b["name"]] = st
            print("%-72s %-18s %s" % (b["name"], st["status"], ", ".join(
                "%s %s (%s)" % (s, per[s][0], per[s][2]) for s in sets)), flush=True)
        # 2. covers: each reachable bin on the first set that reaches it
        todo = list(reach)
        for s in sets:
            if not todo:
                break
            with cf.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
                futs = {ex.submit(cached, s, "c_%d" % b["index"], cover): b for b in todo}
                left = []
                for f in cf.as_completed(futs):
                    b = futs[f]
                    v, frame, how, _ = f.result()
                    if v == "reached":
                        status[b["name"]] = {"status": "witnessed", "set": s,
                                             "cycle": max((frame or 1) - 1, 0), "property": "cover (%s)" % b["wire"]}
                    else:
                        left.append(b)
                        status.setdefault(b["name"], {"status": "undecided", "tried": {}})["tried"][s] = "%s (%s)" % (v, how)
            todo = sorted(left, key=lambda b: b["index"])
        for b in bins:
            st = status.setdefault(b["name"], {"status": "undecided", "tried": {}})
            st["hit"] = b["name"] in hit
            st["wire"] = b["wire"]
        counts = {}
        for st in status.values():
            counts[st["status"]] = counts.get(st["status"], 0) + 1
        undecided_not_hit = sorted(n for n, st in status.items() if st["status"] == "undecided" and not st["hit"])
        doc = {"model_id": table["model_id"], "sets": {s: SETS[s] for s in sets},
               "cover_depth": a.cover_depth, "timeout": a.timeout, "counts": counts,
               "seconds": round(time.time() - t0, 1),
               "bins": [dict(name=b["name"], index=b["index"], **status[b["name"]]) for b in bins]}
        os.makedirs(a.out, exist_ok=True)
        kit.write_atomic(os.path.join(a.out, "coverage.json"), json.dumps(doc, indent=1) + "\n")
        print("coverage-proofs: %d bins: %s; %d wrong declarations%s; %.0f s wall (%s, %d jobs) -> %s"
              % (len(bins), ", ".join("%s %d" % kv for kv in sorted(counts.items())), len(wrong),
                 (" (" + ", ".join(wrong) + ")") if wrong else "", time.time() - t0, ",".join(sets),
                 a.jobs, os.path.relpath(os.path.join(a.out, "coverage.json"), ROOT)), flush=True)
        if hit:
            print("coverage-proofs: %d undecided bins not hit by the regression" % len(undecided_not_hit))
        ok = not wrong and counts.get("undecided", 0) == 0
        return 0 if ok else 1
    except kit.SetupError as e:
        print("coverage-proofs: %s" % e, file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
