"""pmu50.Coverage samples the same numbers as the Rust library and the C ABI.

The stimulus is the shared one of hdl/ffi/tests/coverage.rs (splitmix64 draws from state 1 turned
into port inputs; hdl/ffi/tests/coverage.c draws the same in C). That test stores the Rust
library's hits in hdl/ffi/tests/coverage_stimulus.json and checks the C ABI and a C program
against it; here ``pmu50.Coverage`` is checked against the same file, sampled two ways.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

import pmu50

from conftest import ROOT

GOLDEN = ROOT / "hdl" / "ffi" / "tests" / "coverage_stimulus.json"
# The stimulus configuration: short windows and intervals, ticks of 10 us (coverage.rs `params`).
CONFIG = dict(
    pw="10 us",
    pi="20 us",
    ps="10 us",
    min="100 us",
    x="300 us",
    t1="100 us",
    t2="50 us",
    cth=2,
    smp_on="30 us",
)
M64 = (1 << 64) - 1


def stimulus(n: int):
    """The shared stimulus: n input dicts (hdl/ffi/tests/coverage.rs `stimulus`)."""
    state = 1
    ig = fault = cs = cc = 0
    for _ in range(n):
        state = (state + 0x9E3779B97F4A7C15) & M64
        z = state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & M64
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & M64
        r = z ^ (z >> 31)
        ig ^= (r & 0xFF) < 3
        fault ^= ((r >> 8) & 0x3F) == 0
        cs ^= ((r >> 14) & 0x1F) == 0
        cc ^= ((r >> 19) & 0x1F) == 0
        yield {
            "ig": ig,
            "vs2_ok": 1 - fault,
            "cmp_s": cs,
            "cmp_c": cc,
            "bus_we": int(((r >> 24) & 0x1F) == 0),
            "bus_addr": (r >> 29) % 24,
            "bus_wdata": (r >> 40) % 64 if (r >> 34) & 1 else (r >> 40) % 1024,
        }


@pytest.fixture(scope="module")
def golden() -> dict:
    g = json.loads(GOLDEN.read_text())
    assert g["model"] == pmu50.Coverage.model(), (
        f"{GOLDEN} is of another model: cargo test -p pmu50-ffi --test coverage regenerates it"
    )
    return g


def nonzero(hits: dict[str, int]) -> dict[str, int]:
    return {k: v for k, v in hits.items() if v}


def test_python_sampling_equals_the_rust_and_c_sampling(golden):
    """Two ways through Python (step, step_traced on a core copy), both the stored Rust hits."""
    core = pmu50.Core(**CONFIG)
    cov = pmu50.Coverage(core)
    other = core.copy()
    cov2 = pmu50.Coverage(**CONFIG)
    for inp in stimulus(golden["edges"]):
        out = cov.step(core, **inp)
        t = cov2.step_traced(other, **inp)
        assert t.after == out
    assert cov.edges == cov2.edges == core.tick == golden["edges"]
    assert nonzero(cov.hits()) == golden["hits"]
    assert cov2.hits() == cov.hits()
    hit, reachable = cov.closure()
    assert hit == len(golden["hits"]) and reachable < len(cov.hits())


def test_sampled_steps_are_the_cores_steps():
    """Stepping through the coverage leaves the core exactly where core.step would."""
    a, b = pmu50.Core(**CONFIG), pmu50.Core(**CONFIG)
    cov = pmu50.Coverage(a)
    for inp in stimulus(3000):
        assert cov.step(a, **inp) == b.step(**inp)
    assert a.regs() == b.regs()


def test_write_is_the_merge_format_and_merges_like_the_cli(tmp_path: Path, golden):
    core = pmu50.Core(**CONFIG)
    cov = pmu50.Coverage(core)
    for inp in stimulus(5000):
        cov.step(core, **inp)
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    cov.write(a, "py/stimulus/a")
    cov.write(b, "py/stimulus/b", verdict="fail")
    assert a.read_text() == cov.to_json("py/stimulus/a")
    assert [p.name for p in tmp_path.iterdir()] and not list(tmp_path.glob(".*tmp")), (
        "no temporary file is left"
    )
    data = json.loads(a.read_text())
    assert data["runs"] == [{"id": "py/stimulus/a", "verdict": "pass"}]
    assert {x["name"]: x["hits"] for x in data["bins"]} == cov.hits()
    assert [x["name"] for x in data["bins"]] == [n for n, *_ in pmu50.Coverage.bins()]

    out = tmp_path / "merged.json"
    assert pmu50.merge_coverage([a, b], out) == (*cov.closure(), 2)
    merged = json.loads(out.read_text())
    assert {x["name"]: x["hits"] for x in merged["bins"]} == {
        k: 2 * v for k, v in cov.hits().items()
    }
    assert [r["id"] for r in merged["runs"]] == ["py/stimulus/a", "py/stimulus/b"]


def test_merge_errors_are_value_errors_naming_the_file(tmp_path: Path):
    core = pmu50.Core()
    cov = pmu50.Coverage(core)
    a = tmp_path / "a.json"
    cov.write(a, "run/1")
    out = tmp_path / "out.json"
    with pytest.raises(pmu50.CoverageError, match=r"run \"run/1\" is counted twice"):
        pmu50.merge_coverage([a, a], out)
    bad = tmp_path / "bad.json"
    bad.write_text(
        '{"format": "pmu50-coverage", "version": 1, "model": "x", "bins": [], "runs": []}'
    )
    with pytest.raises(ValueError, match=r"bad\.json: sampled with coverage model x"):
        pmu50.merge_coverage([a, bad], out)
    bad.write_text("{ not json")
    with pytest.raises(pmu50.CoverageError, match=r"bad\.json: not a coverage file: line 1"):
        pmu50.merge_coverage([bad], out)
    bad.write_text('{"format": "other", "version": 3}')
    with pytest.raises(pmu50.CoverageError, match=r"bad\.json: format \"other\" version 3"):
        pmu50.merge_coverage([bad], out)
    with pytest.raises(OSError, match="missing.json"):
        pmu50.merge_coverage([tmp_path / "missing.json"], out)
    with pytest.raises(ValueError, match="no input files"):
        pmu50.merge_coverage([], out)
    assert not out.exists(), "nothing is written when a merge fails"


def test_argument_errors():
    core = pmu50.Core()
    with pytest.raises(ValueError, match="either a core or keyword arguments"):
        pmu50.Coverage(core, cth=3)
    with pytest.raises(pmu50.ConfigError):
        pmu50.Coverage(min="7 ms")
    cov = pmu50.Coverage(core)
    with pytest.raises(ValueError, match="cnt_width"):
        cov.step(pmu50.Core(cnt_width=4), ig=1)
    with pytest.raises(TypeError, match="unexpected keyword argument `igg`"):
        cov.step(core, igg=1)
    with pytest.raises(ValueError, match="run id is empty"):
        cov.to_json("")
    with pytest.raises(OSError):
        cov.write(Path(os.devnull) / "x" / "coverage.json", "r")
    assert cov.edges == 0


def test_configuration_is_sampled_once_at_the_start():
    cov = pmu50.Coverage(clock="5 us", cth=1)
    h = nonzero(cov.hits())
    assert h["config.cth.one"] == 1 and h["config.clock.below_10us"] == 1
    assert all(k.startswith("config.") for k in h), h
    assert pmu50.Coverage(pmu50.Core(clock="5 us")).clock_ns == 5_000


def test_unreachable_bins_are_declared_with_a_reason():
    bins = pmu50.Coverage.bins()
    unreachable = [(n, why) for n, _, _, why in bins if why]
    assert "fig18.history.both" in dict(unreachable)
    assert all(why.strip() for _, why in unreachable)
    assert {k for _, k, _, _ in bins} == {"point", "cross"}


def test_writes_never_replace_a_fifo_or_a_device_nor_a_merge_input(tmp_path: Path):
    import stat

    cov = pmu50.Coverage(pmu50.Core())
    fifo = tmp_path / "fifo.json"
    os.mkfifo(fifo)
    with pytest.raises(OSError, match=r"fifo\.json: is a FIFO, not a regular file"):
        cov.write(fifo, "py/1")
    assert stat.S_ISFIFO(fifo.lstat().st_mode), "the FIFO is left as it was"
    null = tmp_path / "null.json"
    null.symlink_to("/dev/null")
    with pytest.raises(OSError, match=r"is a character device, not a regular file"):
        cov.write(null, "py/1")
    assert null.is_symlink()
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    cov.write(a, "py/a")
    cov.write(b, "py/b")
    before = a.read_bytes()
    with pytest.raises(pmu50.CoverageError, match=r"a\.json: the output is also input .*a\.json"):
        pmu50.merge_coverage([a, b], a)
    assert a.read_bytes() == before, "the input is left as it was"
    with pytest.raises(OSError, match=r"is a FIFO"):
        pmu50.merge_coverage([a, b], fifo)
