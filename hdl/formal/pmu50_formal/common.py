"""What the property kit (kit.py) and the coverage proofs (coverage.py) share: the folders, the
top's contract (its ports and parameters, hdl/formal/pmu50_contract.json), the parameter sets,
Verilog file lists, running a tool, atomic writes and reading a VCD."""

import functools
import json
import math
import os
import re
import shutil
import signal
import subprocess
import tempfile

PACKAGE = os.path.dirname(os.path.abspath(__file__))
FORMAL = os.path.dirname(PACKAGE)  # hdl/formal
HDL = os.path.dirname(FORMAL)
ROOT = os.path.dirname(HDL)
# The top's contract, generated from the model by `pmu50 hdl coverage-monitor`.
CONTRACT = os.path.join(FORMAL, "pmu50_contract.json")

# Parameter sets of the kit beside the top's defaults (set `default`, from the contract; names
# of the Verilog parameters of pmu50). `small` is legal (spec 4) and short: a whole key-off
# period is 9 ticks, so deep behaviour (expansion, clamps) is near.
KIT_SETS = {
    "small": dict(
        SYNC_DEPTH=3,
        CNT_W=4,
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
    ),
    "sync1": dict(
        SYNC_DEPTH=1,
        CNT_W=2,
        ADAPTIVE=0,
        PW=0,
        PI=2,
        PS=1,
        SI_MAX=7,
        SI_MIN=7,
        T1=1,
        T2=1,
        CTH=1,
        SMP_ON=2,
    ),
}
SET_NAMES = ["default", *KIT_SETS]


class SetupError(Exception):
    """A setup or tool failure: the message says what, where and what is valid."""


def use_project_tools():
    """The project's virtual environment (target/venv: yices-smt2, yosys-smtbmc's solver) first
    on PATH, for the tools the kit runs."""
    venv = os.path.join(ROOT, "target", "venv", "bin")
    if not os.environ.get("PATH", "").startswith(venv + os.pathsep):
        os.environ["PATH"] = venv + os.pathsep + os.environ.get("PATH", "")


def _field(path, where, obj, key, kinds):
    """obj[key] when it is of one of `kinds`, else the SetupError that names it."""
    v = obj.get(key) if isinstance(obj, dict) else None
    if not isinstance(v, kinds) or (isinstance(v, bool) and bool not in kinds):
        raise SetupError(
            "%s: %s%s is %s, not %s (`pmu50 hdl coverage-monitor` regenerates the file)"
            % (
                path,
                where,
                key,
                "missing" if v is None else repr(v),
                " or ".join(k.__name__ for k in kinds),
            )
        )
    return v


@functools.cache
def contract(path=CONTRACT):
    """The top's contract: {"top", "clock", "reset", "parameters": [{name, field, default,
    min, max}], "ports": [{name, direction, width, max_width}]}."""
    try:
        with open(path) as f:
            doc = json.load(f)
    except (OSError, ValueError) as e:
        raise SetupError(
            "cannot read the top's contract %s: %s (`pmu50 hdl coverage-monitor` writes it)"
            % (path, e)
        ) from e
    for key in ("top", "clock", "reset"):
        _field(path, "", doc, key, (str,))
    for i, p in enumerate(_field(path, "", doc, "parameters", (list,))):
        _field(path, "parameters[%d]." % i, p, "name", (str,))
        for key in ("default", "min", "max"):
            _field(path, "parameters[%d]." % i, p, key, (int,))
    for i, p in enumerate(_field(path, "", doc, "ports", (list,))):
        where = "ports[%d]." % i
        _field(path, where, p, "name", (str,))
        _field(path, where, p, "width", (int, str))
        _field(path, where, p, "max_width", (int,))
        if _field(path, where, p, "direction", (str,)) not in ("in", "out"):
            raise SetupError("%s: %sdirection is %r, not in or out" % (path, where, p["direction"]))
    return doc


def inputs():
    """[(name, width)] of the top's inputs besides clock and reset, in vector-file order."""
    c = contract()
    skip = (c["clock"], c["reset"])
    return [
        (p["name"], p["max_width"])
        for p in c["ports"]
        if p["direction"] == "in" and p["name"] not in skip
    ]


def outputs():
    """The names of the top's outputs, in vector-file order."""
    return [p["name"] for p in contract()["ports"] if p["direction"] == "out"]


def digits(name):
    """Hexadecimal digits of a port's column in a vector file (its widest width)."""
    for p in contract()["ports"]:
        if p["name"] == name:
            return (p["max_width"] + 3) // 4
    raise SetupError("the top's contract %s has no port %s" % (CONTRACT, name))


def default_set():
    """The top's parameters at their defaults: {Verilog name: value}."""
    return {p["name"]: p["default"] for p in contract()["parameters"]}


def parameter_sets():
    """{name: {Verilog parameter: value}} of the kit's sets: `default` and KIT_SETS."""
    return {"default": default_set(), **KIT_SETS}


def illegal_values(params):
    """The parameters of a set outside their legal range, or not parameters of the top, or
    left out: a list of messages (empty: each value legal on its own)."""
    legal = {p["name"]: (p["min"], p["max"]) for p in contract()["parameters"]}
    bad = ["%s is not a parameter of the top" % k for k in params if k not in legal]
    bad += ["%s is missing" % k for k in legal if k not in params]
    bad += [
        "%s = %d is outside %d..%d" % (k, v, legal[k][0], legal[k][1])
        for k, v in params.items()
        if k in legal and not legal[k][0] <= v <= legal[k][1]
    ]
    return bad


def pmu50_binary():
    """The pmu50 command: $PMU50, else target/release/pmu50 of the checkout, else on PATH."""
    for cand in (
        os.environ.get("PMU50", ""),
        os.path.join(ROOT, "target", "release", "pmu50"),
        shutil.which("pmu50") or "",
    ):
        if cand and os.access(cand, os.X_OK):
            return os.path.abspath(cand)
    raise SetupError(
        "the pmu50 command is needed to read the file list (`pmu50 rtl-files`): set PMU50, or "
        "build it with `cargo build --release`"
    )


def cpu_limit(seconds):
    """A preexec_fn that gives the process (and each process it starts) at most `seconds` of
    CPU time: the kernel stops it there (SIGXCPU, then SIGKILL), however busy the machine is.
    None: no limit."""
    if seconds is None:
        return None
    import resource

    lim = max(1, int(math.ceil(seconds)))

    def set_limit():
        resource.setrlimit(resource.RLIMIT_CPU, (lim, lim + 5))

    return set_limit


def run(cmd, cwd, log, cpu=None):
    """Run `cmd` in `cwd` with its output in the file `log` there, with at most `cpu` seconds of
    CPU time (a budget that does not depend on the machine's load; None: none). Returns its exit
    code, None when it ran out of its CPU budget, 127 when it could not start."""
    with open(os.path.join(cwd, log), "w") as f:
        try:
            p = subprocess.run(
                cmd, cwd=cwd, stdout=f, stderr=subprocess.STDOUT, preexec_fn=cpu_limit(cpu)
            )
        except OSError as e:
            f.write(str(e))
            return 127
    if p.returncode in (-signal.SIGXCPU, -signal.SIGKILL) and cpu is not None:
        return None
    return p.returncode


def write_atomic(path, data):
    """Write a file by a temporary file beside it and a rename."""
    d = os.path.dirname(path)
    fd, tmp = tempfile.mkstemp(dir=d, prefix="." + os.path.basename(path) + ".")
    with os.fdopen(fd, "wb" if isinstance(data, bytes) else "w") as f:
        f.write(data)
    os.replace(tmp, path)


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
            scope.append(toks[i + 2])
            i += 4
            continue
        if tok == "$upscope":
            scope.pop()
            i += 2
            continue
        if tok == "$var":
            w, code, name = int(toks[i + 2]), toks[i + 3], toks[i + 4]
            j = i + 5
            while toks[j] != "$end":
                j += 1
            full = ".".join(scope + [name])
            sigs[full] = (w, [])
            ids.setdefault(code, []).append(full)
            i = j + 1
            continue
        if tok.startswith("$"):
            j = i
            while toks[j] != "$end":
                j += 1
            i = j + 1
            continue
        if tok.startswith("#"):
            t = int(tok[1:])
            tend = max(tend, t)
            i += 1
            continue
        if tok[0] in "bB":
            val, code = tok[1:], toks[i + 1]
            i += 2
        else:
            val, code = tok[0], tok[1:]
            i += 1
        v = None if re.search("[xXzZ]", val) else int(val, 2)
        for n in ids.get(code, []):
            sigs[n][1].append((t, v))
    return sigs, tend


def value_at(ch, t):
    """The value of a VCD change list at time t (x and z read as 0)."""
    v = 0
    for tt, vv in ch:
        if tt > t:
            break
        v = vv if vv is not None else 0
    return v


def seal(path, made_by, rtl_list, dut="formal"):
    """Seal a JSON file of evidence in place: its provenance (the RTL's file list and content
    hash, the tools) and its digest, by `pmu50 seal` (the kit's one implementation)."""
    p = subprocess.run(
        [pmu50_binary(), "seal", path, "--made-by", made_by, "--rtl", rtl_list, "--dut", dut],
        capture_output=True,
        text=True,
    )
    if p.returncode != 0:
        raise SetupError("pmu50 seal %s failed: %s" % (path, (p.stderr or p.stdout).strip()))
