"""Shared fixtures of the pmu50 package tests: paths, the CLI binary, vector files."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENARIOS = sorted((ROOT / "scenarios").glob("*.toml"))
# Days of parking (scenarios/park_30d.toml, 2.6e11 ticks) have no vector file and no VCD of every
# tick: the per-tick comparisons take the others (as tests/golden.rs does).
DAYS = 1_000_000_000


def per_tick(paths: list[Path]) -> list[Path]:
    import pmu50

    return [p for p in paths if pmu50.Scenario.load(p).ticks <= DAYS]


PER_TICK = per_tick(SCENARIOS)
PMU50_BIN = ROOT / "target" / "release" / "pmu50"


def cli(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Run the `pmu50` CLI (built by `make`: cargo build --release --bin pmu50)."""
    assert PMU50_BIN.exists(), (
        f"{PMU50_BIN} missing: `cargo build --release --bin pmu50` (make pytest does it)"
    )
    return subprocess.run([str(PMU50_BIN), *args], capture_output=True, text=True, check=check)


@pytest.fixture(scope="session")
def vector_dir(tmp_path_factory) -> Path:
    """The vector files of every shipped scenario, written by `pmu50 vectors`."""
    d = tmp_path_factory.mktemp("vectors")
    for sc in PER_TICK:
        cli("vectors", str(sc), "-o", str(d / f"{sc.stem}.vec"))
    return d
