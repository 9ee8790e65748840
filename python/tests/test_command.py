"""The wheel installs the `pmu50` command beside the environment's python (pyproject.toml,
`[tool.maturin] data`): the same program as the release build, working from any folder."""

import hashlib
import os
import subprocess
import sys
from pathlib import Path

from conftest import PMU50_BIN, ROOT


def _installed() -> Path:
    return Path(sys.executable).parent / "pmu50"


def test_wheel_installs_the_command():
    cmd = _installed()
    assert cmd.is_file(), f"{cmd} missing: the wheel did not carry scripts/pmu50 (make python)"
    assert os.access(cmd, os.X_OK), f"{cmd} is not executable"

    # The very binary `make python` built: the wheel is not a stale copy.
    def digest(p):
        return hashlib.sha256(p.read_bytes()).hexdigest()

    assert digest(cmd) == digest(PMU50_BIN)


def test_command_runs_a_scenario_from_another_folder(tmp_path):
    scenario = ROOT / "scenarios" / "fig15a.toml"
    out = tmp_path / "out"
    r = subprocess.run(
        [str(_installed()), "run", str(scenario), "--out-dir", str(out)],
        cwd=tmp_path,
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr
    ref = tmp_path / "ref"
    subprocess.run(
        [str(PMU50_BIN), "run", str(scenario), "--out-dir", str(ref)],
        check=True,
        capture_output=True,
    )
    # Byte-identical waveform to the checkout's build.
    assert (out / "fig15a.vcd").read_bytes() == (ref / "fig15a.vcd").read_bytes()
    # It finds its HDL kit without the checkout: the kit it carries lists the twin.
    r = subprocess.run(
        [str(_installed()), "hdl", "export", str(tmp_path / "kit")],
        cwd=tmp_path,
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "kit" / "pmu50.v").is_file()
