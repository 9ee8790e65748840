"""Shared fixtures of the pmu50 package tests: paths, the CLI binary, vector files."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENARIOS = sorted((ROOT / "scenarios").glob("*.toml"))
PMU50_BIN = ROOT / "target" / "release" / "pmu50"


def cli(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Run the `pmu50` CLI (built by `make`: cargo build --release --bin pmu50)."""
    assert PMU50_BIN.exists(), f"{PMU50_BIN} missing: `cargo build --release --bin pmu50` (make pytest does it)"
    return subprocess.run([str(PMU50_BIN), *args], capture_output=True, text=True, check=check)


@pytest.fixture(scope="session")
def vector_dir(tmp_path_factory) -> Path:
    """The vector files of every shipped scenario, written by `pmu50 vectors`."""
    d = tmp_path_factory.mktemp("vectors")
    for sc in SCENARIOS:
        cli("vectors", str(sc), "-o", str(d / f"{sc.stem}.vec"))
    return d
