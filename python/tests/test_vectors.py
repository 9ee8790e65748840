"""Core.step agrees with the vector files of the shipped scenarios, tick by tick.

The vector files are written by the CLI (`pmu50 vectors`, docs/spec.md 6.2): line k holds the
inputs applied at k·T and the outputs expected after edge k+1, which is what `Core.step` returns.
"""

from __future__ import annotations

from pathlib import Path

import pytest

import pmu50

from conftest import PER_TICK, SCENARIOS


def read_vectors(path: Path):
    """(header, rows): header lines as {key: value(s)}, rows as lists of ints."""
    params: dict[str, int] = {}
    header: dict[str, str] = {}
    rows: list[list[int]] = []
    with open(path, encoding="ascii") as f:
        for line in f:
            if line.startswith("//"):
                words = line[2:].split()
                if words and words[0] == "param":
                    params[words[1]] = int(words[2])
                elif words:
                    header[words[0]] = " ".join(words[1:])
            elif line.strip():
                rows.append([int(x, 16) for x in line.split()])
    return header, params, rows


def test_every_shipped_scenario_but_the_parked_days_has_vectors():
    assert len(PER_TICK) >= 7 and len(SCENARIOS) - len(PER_TICK) <= 1, (SCENARIOS, PER_TICK)


@pytest.mark.parametrize("scenario", PER_TICK, ids=[p.stem for p in PER_TICK])
def test_core_step_agrees_with_the_vector_file(scenario: Path, vector_dir: Path):
    sc = pmu50.Scenario.load(scenario)
    core = pmu50.Core(**sc.core)
    header, params, rows = read_vectors(vector_dir / f"{scenario.stem}.vec")

    # the header: parameters, clock, run length, columns from the same signal table
    assert params == core.hdl_parameters
    assert int(header["clock_ns"]) == core.clock_ns == sc.clock_ns
    assert int(header["ticks"]) == len(rows) == sc.ticks
    ins = [s.name for s in core.signals("input")]
    outs = [s.name for s in core.signals("output")]
    assert header["columns"].split() == ins + ["|"] + outs
    n = len(ins)

    for k, row in enumerate(rows):
        got = core.step(**dict(zip(ins, row[:n]))).values()
        if got != row[n:]:
            bad = [
                f"{s}: expected {e:#x} got {g:#x}" for s, e, g in zip(outs, row[n:], got) if e != g
            ]
            pytest.fail(f"{scenario.stem}: line {k} (after edge {k + 1}): " + "; ".join(bad))
    assert core.tick == sc.ticks


def test_a_wrong_row_is_noticed(vector_dir: Path):
    """The comparison above can fail: flip one expected bit and the first line differs."""
    sc = pmu50.Scenario.load(SCENARIOS[0])
    core = pmu50.Core(**sc.core)
    _, _, rows = read_vectors(vector_dir / f"{SCENARIOS[0].stem}.vec")
    ins = [s.name for s in core.signals("input")]
    row = rows[0][:]
    row[len(ins) + 16] ^= 1  # si
    assert core.step(**dict(zip(ins, row[: len(ins)]))).values() != row[len(ins) :]
