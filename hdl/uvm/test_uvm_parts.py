"""The bench's parts that need no simulator: the parameter mapping, the run-length items of a
vector file, the random sequences' lengths and determinism, the FIG. path names."""

from __future__ import annotations

import random
from pathlib import Path

import pytest

import pmu50
from pmu50.hdl import PARAMETERS, core_config
from pmu50_uvm.env import fig_path
from pmu50_uvm.sequences import (
    INPUTS,
    RandomSeq,
    RegisterSeq,
    StimulusError,
    VectorSeq,
    bus_random,
    cmp_random,
    key_random,
    runs,
)

from test_uvm import RANDOM_CONFIGS


@pytest.mark.parametrize("cfg", [{}] + RANDOM_CONFIGS)
def test_parameters_map_back_onto_the_core(cfg):
    """The Verilog parameters of a configuration, read back into a configuration, give the same
    core (the BFM's path from the top's parameters to pmu50.Core)."""
    hdl = pmu50.Core(**cfg).hdl_parameters
    assert set(hdl) == set(PARAMETERS)
    assert pmu50.Core(**core_config(hdl)).hdl_parameters == hdl
    # a missing parameter takes the model's default
    partial = {k: v for k, v in hdl.items() if k != "CTH"}
    back = pmu50.Core(**core_config(partial)).hdl_parameters
    assert back == {**hdl, "CTH": pmu50.Core().hdl_parameters["CTH"]}


def test_fig_path_names_are_the_coverage_bins():
    assert fig_path(0, 0) == "-"
    assert fig_path(3, 0) == "s6_shorten"
    assert fig_path(3, 1) == "s6_shorten/s23_detected_cs"
    assert fig_path(6, 5) == "s10_expand/s25_no_change"
    assert fig_path(7, 0) == "fixed"


def test_runs_encode_every_row():
    rows = [(0,), (0,), (1,), (1,), (1,), (0,)]
    items = runs(rows, lambda v, n: (v, n))
    assert items == [((0,), 2), ((1,), 3), ((0,), 1)]
    assert runs([], lambda v, n: (v, n)) == []


def expand(items, fields):
    out = []
    for it in items:
        out += [tuple(getattr(it, f) for f in fields)] * it.cycles
    return out


def test_a_vector_file_splits_into_the_three_agents(tmp_path: Path):
    rng = random.Random(5)
    rows = []
    for _ in range(300):
        rows.append(
            [
                rng.getrandbits(1) if rng.random() < 0.1 else (rows[-1][i] if rows else 0)
                for i in range(4)
            ]
            + [rng.getrandbits(1), rng.getrandbits(8), rng.getrandbits(16)]
        )
    path = tmp_path / "t.vec"
    path.write_text(
        "// "
        + " ".join(INPUTS)
        + " outputs...\n"
        + "".join(" ".join(f"{v:x}" for v in r) + " 0 0\n" for r in rows)
    )
    seq = VectorSeq(path)
    key, cmp_, bus = seq.make(pmu50.Core().hdl_parameters)
    assert seq.ticks == 300
    col = {n: i for i, n in enumerate(INPUTS)}
    assert expand(key, ["ig"]) == [(r[col["ig"]],) for r in rows]
    assert expand(cmp_, ["cmp_s", "cmp_c", "vs2_ok"]) == [
        (r[col["cmp_s"]], r[col["cmp_c"]], r[col["vs2_ok"]]) for r in rows
    ]
    assert expand(bus, ["we", "addr", "wdata"]) == [
        (r[col["bus_we"]], r[col["bus_addr"]], r[col["bus_wdata"]]) for r in rows
    ]
    assert sum(i.cycles for i in key) == 300 and len(key) < 300
    cut = VectorSeq(path, max_ticks=50)
    k2, _, _ = cut.make({})
    assert cut.ticks == 50 and sum(i.cycles for i in k2) == 50


def test_a_bad_vector_file_says_where(tmp_path: Path):
    path = tmp_path / "bad.vec"
    path.write_text("0 1 0\n")
    with pytest.raises(StimulusError, match=r"bad.vec:1: 3 fields"):
        VectorSeq(path).make({})
    with pytest.raises(StimulusError, match="missing.vec"):
        VectorSeq(tmp_path / "missing.vec").make({})


@pytest.mark.parametrize("cfg", RANDOM_CONFIGS)
def test_random_sequences_fill_the_run_and_repeat_per_seed(cfg):
    hdl = pmu50.Core(**cfg).hdl_parameters
    a = RandomSeq(7, 2500).make(hdl)
    b = RandomSeq(7, 2500).make(hdl)
    c = RandomSeq(8, 2500).make(hdl)
    for items in a:
        assert sum(i.cycles for i in items) == 2500 and all(i.cycles >= 1 for i in items)
    assert [str(i) for i in a[2]] == [str(i) for i in b[2]]
    assert [str(i) for i in a[1]] != [str(i) for i in c[1]]
    # every kind of stimulus the mutants need is there
    keys = key_random(random.Random(1), 20000, hdl["SYNC_DEPTH"])
    assert {k.ig for k in keys} == {0, 1} and any(k.cycles <= hdl["SYNC_DEPTH"] for k in keys)
    cmps = cmp_random(random.Random(1), 20000)
    assert any(c.fault for c in cmps) and len({(c.cmp_s, c.cmp_c) for c in cmps}) == 4
    bus = bus_random(random.Random(1), 20000, hdl)
    assert any(b.we for b in bus) and any(b.we and b.addr == 0x14 for b in bus)


def test_the_register_sequence_stays_aligned():
    key, cmp_, bus = RegisterSeq().make(pmu50.Core().hdl_parameters)
    total = sum(i.cycles for i in bus)
    assert sum(i.cycles for i in key) == sum(i.cycles for i in cmp_) == total
    written = {b.addr for b in bus if b.we}
    assert {a for n, a, _, acc in pmu50.REGISTER_MAP if acc == "RW"} <= written
