"""pytest driver of the cocotb testbench tb_pmu50.py: the Verilog twin on Icarus Verilog against
pmu50.Core (docs/python.md, "cocotb").

- every shipped scenario (scenarios/*.toml): its vector file, written by
  ``target/release/pmu50 vectors``, replayed into the twin, every output compared with the
  model every tick;
- seeded random stimulus on a few core configurations (short timing parameters, so that a few
  thousand cycles cover many key-off pulses, interval changes and register writes);
- functional coverage: the scoreboard samples ``pmu50.Coverage`` at every edge and each run
  writes its coverage.json (run id ``cocotb/vectors/<scenario>`` or ``cocotb/random/<seed>``);
  the random seeds' files are merged into target/cocotb/coverage_random.json and checked;
- mutants of hdl/mutants.txt (one-line bugs, `define): each must make the scoreboard fail, with a
  message naming the tick and the signal.

Work files: target/cocotb/ (one Icarus build per parameter set and mutant). Needs ``iverilog``
and the ``pmu50`` package (``make cocotb`` provides both). Environment: PMU50_COCOTB_SEEDS
(number of random seeds, default 12), PMU50_COCOTB_CYCLES (cycles per seed, default 3000),
PMU50_COCOTB_MUTANT (a mutant planted into the twin of the vector and random runs),
PMU50_COCOTB_MAX_TICKS (replay only the first N ticks of each vector file; default 0: all).
"""

from __future__ import annotations

import functools
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
from pmu50.hdl import core_config

HERE = Path(__file__).resolve().parent
HDL = HERE.parent
ROOT = HDL.parent
WORK = ROOT / "target" / "cocotb"
PMU50_BIN = ROOT / "target" / "release" / "pmu50"
# The RTL under test: the twin, or any RTL with the contract ports (PMU50_COCOTB_RTL=list.f,
# `make cocotb RTL=list.f`). The bench reads its ports only; the parameters its top lacks are
# fixed by the RTL (`pmu50 rtl-info` reads them back through the bus after reset), and every run
# keeps them.
RTL = Path(os.environ.get("PMU50_COCOTB_RTL") or HDL / "pmu50.f").resolve()


def _filelist(f: Path) -> list[Path]:
    out = []
    for line in f.read_text().splitlines():
        entry = line.split("//")[0].split("#")[0].strip()
        if entry:
            out.append((f.parent / entry).resolve())
    return out


SOURCES = _filelist(RTL)
TWIN = RTL == (HDL / "pmu50.f").resolve()


@functools.cache
def rtl_info() -> dict:
    """The top's parameters and the values the RTL fixes (`pmu50 rtl-info`)."""
    if TWIN:
        return {"parameters": list(pmu50.Core().hdl_parameters), "fixed": {}}
    out = subprocess.run(
        [str(PMU50_BIN), "rtl-info", "--rtl", str(RTL)], capture_output=True, text=True
    )
    assert out.returncode == 0, f"{RTL}: {out.stderr.strip()}"
    return json.loads(out.stdout)


def fixing(cfg: dict) -> dict:
    """A core configuration with the values the RTL fixes put in (the defaults where the result
    would be illegal)."""
    fixed = rtl_info()["fixed"]
    if not fixed:
        return cfg

    # the fixed values as Core keywords (durations in ticks of the default 10 us clock)
    keywords = core_config(fixed)
    del keywords["clock"]

    def put(c: dict) -> dict:
        return {**c, **keywords}

    try:
        pmu50.Core(**put(cfg))
        return put(cfg)
    except Exception:  # noqa: BLE001 - an illegal mix: the RTL's own values
        return put({})


def clash(hdl_parameters: dict) -> str | None:
    """Why a run with these parameters cannot run on the RTL (it fixes other values), or None."""
    fixed = rtl_info()["fixed"]
    bad = [
        f"{n}={fixed[n]} (the run needs {hdl_parameters[n]})"
        for n in fixed
        if hdl_parameters.get(n) != fixed[n]
    ]
    return f"the RTL {RTL} fixes {', '.join(bad)}" if bad else None


# every shipped scenario but days of parking (scenarios/park_30d.toml: 2.6e11 ticks, no vectors)
SHIPPED = [
    p
    for p in sorted((ROOT / "scenarios").glob("*.toml"))
    if pmu50.Scenario.load(p).ticks <= 1_000_000_000
]

SEEDS = int(os.environ.get("PMU50_COCOTB_SEEDS", "12"))
# Plant a mutant of hdl/mutants.txt into the twin of the vector and random runs, to see the
# scoreboard fail (docs/python.md): PMU50_COCOTB_MUTANT=MUT_CNT_C_SIGN make cocotb
PLANTED = os.environ.get("PMU50_COCOTB_MUTANT") or None
# Replay only the first N ticks of each vector file (0: whole runs, the default). The three long
# scenarios are 710 000 of the 752 800 ticks, about 2.5 CPU-minutes of the suite.
MAX_TICKS = int(os.environ.get("PMU50_COCOTB_MAX_TICKS", "0"))
CYCLES = int(os.environ.get("PMU50_COCOTB_CYCLES", "3000"))

# Core configurations of the random runs: short windows and intervals (ticks of 10 us), all three
# structural corners, both embodiments.
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

# Mutants the scoreboard must catch, with the random seed and configuration that exercise them.
MUTANTS = [
    ("MUT_SMP_LATE", 1, 0),
    ("MUT_SYNC_SHORT", 1, 0),
    ("MUT_CNT_C_SIGN", 1, 0),
    ("MUT_WRITE_KEY_OFF", 1, 0),
    ("MUT_CTH_OFF_BY_ONE", 1, 0),
    ("MUT_SR_IGNORES_VS2_OK", 1, 0),
]

MISMATCH = re.compile(r"MISMATCH tick=(\d+) signal=(\w+) expected=(0x[0-9a-f]+) got=(\S+)")


def build(params: dict, mutant: str | None = None) -> Path:
    """The RTL compiled with the Verilog parameters its top has (and mutant), cached per set."""
    params = {k: v for k, v in params.items() if k in rtl_info()["parameters"]}
    key = hashlib.sha1(
        json.dumps([sorted(params.items()), mutant, [str(p) for p in SOURCES]]).encode()
    ).hexdigest()[:12]
    d = WORK / "build" / f"{mutant or 'none'}_{key}"
    runner = get_runner("icarus")
    runner.build(
        sources=SOURCES,
        hdl_toplevel="pmu50",
        parameters=params,
        defines={mutant: 1} if mutant else {},
        build_dir=d,
        timescale=("1ns", "1ps"),
        build_args=["-Wall", "-Wno-timescale"],
    )
    return d


def simulate(build_dir: Path, env: dict, results: Path) -> tuple[bool, str]:
    """Run tb_pmu50 in the simulator; (passed, failure message)."""
    runner = get_runner("icarus")
    passed = True
    try:
        runner.test(
            test_module="tb_pmu50",
            hdl_toplevel="pmu50",
            hdl_toplevel_lang="verilog",
            build_dir=build_dir,
            test_dir=build_dir,
            extra_env=env,
            results_xml=str(results),
        )
    except SystemExit as e:  # cocotb's runner exits when a test failed under pytest
        passed = e.code in (0, None)
    root = ET.parse(results).getroot()
    cases = root.findall(".//testcase")
    assert len(cases) == 1, f"{results}: expected one test case, found {len(cases)}"
    fail = cases[0].find("failure")
    if fail is None:
        fail = cases[0].find("error")
    if fail is not None:
        passed = False
    return passed, "" if fail is None else (fail.get("message") or "") + (fail.text or "")


def run_twin(
    hdl_parameters: dict, mutant: str, name: str, core: dict, run_id: str, **stimulus: str
) -> tuple[bool, str, Path]:
    """Build the twin (or `mutant`) for `hdl_parameters` and run tb_pmu50 on it against the model
    configured with `core`, the stimulus given by the PMU50_* variables `stimulus`, the coverage
    sampled into results/NAME.coverage.json under `run_id`: (passed, failure message, that file)."""
    d = build(hdl_parameters, mutant)
    cov = WORK / "results" / f"{name}.coverage.json"
    cov.parent.mkdir(parents=True, exist_ok=True)
    cov.unlink(missing_ok=True)
    env = {
        "PMU50_CORE": json.dumps(core),
        **stimulus,
        "PMU50_COVERAGE": str(cov),
        "PMU50_RUN_ID": run_id,
    }
    ok, msg = simulate(d, env, WORK / "results" / f"{name}.xml")
    return ok, msg, cov


@pytest.fixture(scope="session")
def vectors() -> Path:
    """Vector files of the shipped scenarios, written by the CLI."""
    d = WORK / "vec"
    d.mkdir(parents=True, exist_ok=True)
    assert PMU50_BIN.exists(), (
        f"{PMU50_BIN} missing: build it with `cargo build --release --bin pmu50` (make does)"
    )
    for sc in SHIPPED:
        subprocess.run(
            [str(PMU50_BIN), "vectors", str(sc), "-o", str(d / f"{sc.stem}.vec")],
            check=True,
            stdout=subprocess.DEVNULL,
        )
    return d


def test_shipped_scenarios_exist():
    assert len(SHIPPED) >= 7, SHIPPED


@pytest.mark.parametrize("scenario", SHIPPED, ids=[p.stem for p in SHIPPED])
def test_scenario_vectors(scenario: Path, vectors: Path):
    sc = pmu50.Scenario.load(scenario)
    why = clash(sc.hdl_parameters)
    if why:
        pytest.skip(why)
    ok, msg, cov = run_twin(
        sc.hdl_parameters,
        PLANTED,
        f"vec_{scenario.stem}",
        sc.core,
        f"cocotb/vectors/{scenario.stem}",
        PMU50_VEC=str(vectors / f"{scenario.stem}.vec"),
        PMU50_MAX_TICKS=str(MAX_TICKS),
    )
    assert ok, msg
    assert json.loads(cov.read_text())["runs"] == [
        {"id": f"cocotb/vectors/{scenario.stem}", "verdict": "pass"}
    ]


@functools.cache
def random_run(seed: int) -> tuple[bool, str, Path]:
    """One seeded random run on the clean twin: (passed, failure message, its coverage.json)."""
    cfg = fixing(RANDOM_CONFIGS[seed % len(RANDOM_CONFIGS)])
    return run_twin(
        pmu50.Core(**cfg).hdl_parameters,
        PLANTED,
        f"random_{seed}",
        cfg,
        f"cocotb/random/{seed}",
        PMU50_SEED=str(seed),
        PMU50_CYCLES=str(CYCLES),
    )


@pytest.mark.parametrize("seed", range(1, SEEDS + 1))
def test_random(seed: int):
    ok, msg, _ = random_run(seed)
    assert ok, msg


def test_random_coverage():
    """Over all seeds, by the coverage model sampled in the scoreboard (the seeds' coverage.json
    merged as `pmu50 merge` does): the stimulus takes every FIG. 17 branch and FIG. 18 path,
    turns the key on and off, presets the counters, writes registers (some refused), and provokes
    a quadrant skip and a diagnosis."""
    if rtl_info()["fixed"]:
        pytest.skip(
            "the coverage goal is for the short timing of the random configurations; "
            f"the RTL fixes {rtl_info()['fixed']}"
        )
    files = []
    for seed in range(1, SEEDS + 1):
        ok, msg, cov = random_run(seed)
        assert ok, msg
        files.append(cov)
    merged = WORK / "coverage_random.json"
    hit, reachable, runs = pmu50.merge_coverage(files, merged)
    assert runs == SEEDS
    hits = {b["name"]: b["hits"] for b in json.loads(merged.read_text())["bins"]}

    def total(prefix: str) -> int:
        return sum(v for k, v in hits.items() if k.startswith(prefix))

    print(
        f"random coverage over {SEEDS} seeds x {CYCLES} cycles: "
        f"{hit} of {reachable} reachable bins hit ({merged})"
    )
    fig17 = {k for k, v in hits.items() if k.startswith("fig17.path.") and v}
    fig18 = {k for k, v in hits.items() if k.startswith("fig18.path.") and v}
    assert len(fig17) == 7, f"FIG. 17 branches taken: {sorted(fig17)} of 7"
    assert len(fig18) == 5, f"FIG. 18 paths taken: {sorted(fig18)} of 5"
    for what, prefix in (
        ("a key-on edge", "key.edge.on"),
        ("a key-off edge", "key.edge.off"),
        ("a first sample (counter preset)", "counter.preset."),
        ("a register write", "bus.write_reg."),
        ("a refused write", "bus.write_outcome.refused_"),
        ("a quadrant skip", "counter.quadrant_skip."),
        ("a diagnosis", "faults.diag."),
    ):
        assert total(prefix) > 0, f"random stimulus never produced {what} ({prefix}*)"


@pytest.mark.parametrize("mutant,seed,config", MUTANTS, ids=[m[0] for m in MUTANTS])
def test_mutant_is_caught(mutant: str, seed: int, config: int):
    if not TWIN:
        pytest.skip("the mutants are defines of the twin (hdl/mutants.txt)")
    listed = (HDL / "mutants.txt").read_text()
    assert re.search(rf"^{mutant}\s*\|", listed, re.M), f"{mutant} is not in hdl/mutants.txt"
    cfg = RANDOM_CONFIGS[config]
    ok, msg, cov = run_twin(
        pmu50.Core(**cfg).hdl_parameters,
        mutant,
        f"mutant_{mutant}",
        cfg,
        f"cocotb/mutant/{mutant}/{seed}",
        PMU50_SEED=str(seed),
        PMU50_CYCLES=str(CYCLES),
    )
    assert not ok, f"{mutant} escaped the scoreboard ({CYCLES} random cycles, seed {seed})"
    # a failing run still writes its coverage, up to the failing edge, with verdict "fail"
    assert json.loads(cov.read_text())["runs"] == [
        {"id": f"cocotb/mutant/{mutant}/{seed}", "verdict": "fail"}
    ]
    m = MISMATCH.search(msg)
    assert m, f"{mutant}: the failure does not name tick and signal:\n{msg}"
    print(
        f"{mutant}: caught at tick {m.group(1)}, signal {m.group(2)} "
        f"(expected {m.group(3)}, got {m.group(4)})"
    )
