"""pmu50.Core: stepping, peek/regs/read, the signal table, parameters and their errors."""

from __future__ import annotations

import copy

import pytest

import pmu50

INPUTS = ["ig", "vs2_ok", "cmp_s", "cmp_c", "bus_we", "bus_addr", "bus_wdata"]


def test_issue_example():
    c = pmu50.Core()
    out = c.step(ig=True)
    assert isinstance(out, pmu50.Outputs)
    assert c.tick == 1
    assert out.si == 660 and out.vp_en == 1
    assert repr(out).startswith("Outputs(sig=0, vr_hi=0,")


def test_key_on_reaches_sig_after_the_synchronizer():
    # sig is the last flop of the ig synchronizer ([0213]): it rises at edge sync_depth.
    for depth in (1, 2, 4):
        c = pmu50.Core(sync_depth=depth)
        seen = [c.step(ig=1).sig for _ in range(depth + 2)]
        assert seen == [0] * (depth - 1) + [1] * 3, (depth, seen)


def test_peek_is_the_last_step_and_does_not_advance():
    c = pmu50.Core()
    out = c.step(ig=1, vs2_ok=1)
    assert c.peek() == out
    assert c.peek() == out
    assert c.tick == 1


def test_reset_and_copy():
    c = pmu50.Core()
    for _ in range(30):
        c.step(ig=1)
    snap = c.copy()
    deep = copy.deepcopy(c)
    c.step(ig=0)
    assert snap.tick == deep.tick == 30 and c.tick == 31
    assert snap.regs() == deep.regs() != c.regs()
    c.reset()
    assert c.tick == 0
    assert c.regs() == pmu50.Core().regs()


def test_signal_table_matches_every_view():
    c = pmu50.Core(cnt_width=6, sync_depth=3)
    table = c.signals()
    kinds = {
        k: [s for s in table if s.kind == k] for k in ("input", "output", "register", "internal")
    }
    assert [s.name for s in kinds["input"]] == INPUTS
    out = c.peek()
    assert [s.name for s in kinds["output"]] == out.names() and len(out) == 23
    assert {s.name: s.width for s in kinds["output"]} == out.widths()
    assert out.widths()["cnt_s"] == 6 and out.widths()["bus_rdata"] == 16
    regs = c.regs()
    assert [s.name for s in kinds["register"]] == [f"{b}.{r}" for b, rs in regs.items() for r in rs]
    assert {s.name: s.width for s in kinds["register"]}["action_switching.sync"] == 3
    tr = c.step_traced()
    assert [s.name for s in kinds["internal"]] == tr.internals.names()
    assert c.signals("output") == kinds["output"]
    assert pmu50.signal_table("register", sync_depth=3, cnt_width=6) == kinds["register"]
    with pytest.raises(ValueError, match="unknown signal kind `port`"):
        c.signals("port")
    # the table's documentation comes along
    by_name = {s.name: s for s in table}
    assert by_name["cnt_s"].signed and not by_name["si"].signed
    assert by_name["cnt_s"].patent == "[0096]-[0097]" and by_name["cnt_s"].meaning
    assert by_name["drive_interval.si"].reset == 660 and by_name["si"].reset is None
    assert (
        pmu50.Core(x="5 ms")
        .signals("register")[[s.name for s in kinds["register"]].index("drive_interval.si")]
        .reset
        == 500
    )


def test_every_input_reaches_its_own_port():
    c = pmu50.Core()
    widths = {s.name: s.width for s in c.signals("input")}
    for name, w in widths.items():
        tr = c.step_traced(**{name: (1 << w) - 1})
        want = {n: ((1 << w) - 1 if n == name else 0) for n in widths}
        assert tr.inputs.to_dict() == want, name


class Index:
    """An integer-like object that is not an int (as numpy integers and simulator values are)."""

    def __init__(self, v: int) -> None:
        self.v = v

    def __index__(self) -> int:
        return self.v


def test_bools_ints_and_integer_likes_are_the_same_input():
    a, b, c = pmu50.Core(), pmu50.Core(), pmu50.Core()
    for _ in range(10):
        assert (
            a.step(ig=True, vs2_ok=True)
            == b.step(ig=1, vs2_ok=1)
            == c.step(ig=Index(1), vs2_ok=Index(1))
        )
    assert c.step_traced(bus_addr=Index(0x13)).inputs.bus_addr == 0x13


def test_bad_inputs():
    c = pmu50.Core()
    with pytest.raises(
        ValueError, match=r"input `bus_addr` = 256 does not fit its 8 bit\(s\); valid is 0..=255"
    ):
        c.step(bus_addr=256)
    with pytest.raises(ValueError, match="input `ig` = 2"):
        c.step(ig=2)
    with pytest.raises(ValueError, match="input `bus_wdata` = -1"):
        c.step(bus_wdata=-1)
    with pytest.raises(
        TypeError, match="unexpected keyword argument `clk`; the inputs are ig, vs2_ok"
    ):
        c.step(clk=1)
    with pytest.raises(TypeError, match="input `ig` takes an int or a bool, got str"):
        c.step(ig="1")
    with pytest.raises(TypeError, match="input `ig` takes an int or a bool, got float"):
        c.step(ig=1.0)
    assert c.tick == 0, "a refused step takes no edge"


def test_read_is_what_bus_rdata_shows_one_edge_later():
    c = pmu50.Core(cnt_width=5)
    # some state: key on, samples taken, counters moving
    for k in range(400):
        c.step(ig=1, vs2_ok=1, cmp_s=(k // 50) % 2, cmp_c=(k // 70) % 2)
    for addr in range(256):
        want = c.read(addr)
        assert c.step(ig=1, vs2_ok=1, bus_addr=addr).bus_rdata == want, hex(addr)
    with pytest.raises(ValueError, match="address 256 is not 0..=255"):
        c.read(256)


def test_register_write_changes_a_parameter():
    c = pmu50.Core()
    for _ in range(5):
        c.step(ig=1)
    assert c.regs()["register_file"]["t2"] == 110
    t2 = next(a for n, a, _, _ in pmu50.REGISTER_MAP if n == "T2")
    c.step(ig=1, bus_we=1, bus_addr=t2, bus_wdata=120)
    assert c.regs()["register_file"]["t2"] == 120


def test_outputs_compare_with_a_mapping():
    out = pmu50.Core().peek()
    got = out.to_dict()
    assert out.mismatches(got) == []
    assert out == got
    got["si"] = 5
    got["sig"] = "x"
    assert out.mismatches(got) == [("sig", 0, "x"), ("si", 660, 5)]
    with pytest.raises(KeyError, match="no value for signal `sig`"):
        out.mismatches({})
    with pytest.raises(AttributeError, match="Outputs has no signal `sgi`; signals are sig, vr_hi"):
        _ = out.sgi
    assert out["si"] == out.si == 660 and "si" in out and "clk" not in out


def test_config_round_trip_and_hdl_parameters():
    c = pmu50.Core(x="5 ms", t2="0.5 ms", cth=7, adaptive=False)
    assert c.config["x"] == "5 ms" and c.config["t2"] == "500 us" and c.config["adaptive"] is False
    assert pmu50.Core(**c.config).hdl_parameters == c.hdl_parameters
    assert (
        c.hdl_parameters["SI_MAX"] == 500
        and c.hdl_parameters["T2"] == 50
        and c.hdl_parameters["CTH"] == 7
    )
    assert c.clock_ns == 10_000
    assert pmu50.CORE_PARAMETERS == list(c.config)


# (keyword arguments, the same value as TOML) -> the message must equal the CLI's after
# `file:line: `
BAD = [
    (dict(t2="1.105 ms"), 't2 = "1.105 ms"'),
    (dict(pw="5"), 'pw = "5"'),
    (dict(pw="5 min"), 'pw = "5 min"'),
    (dict(pw="-1 us"), 'pw = "-1 us"'),
    (dict(clock="0 ns"), 'clock = "0 ns"'),
    (dict(clock="10 ns"), 'clock = "10 ns"'),
    (dict(x="1 s"), 'x = "1 s"'),
    (dict(sync_depth=0), "sync_depth = 0"),
    (dict(sync_depth=5), "sync_depth = 5"),
    (dict(cnt_width=17), "cnt_width = 17"),
    (dict(cth=0), "cth = 0"),
    (dict(cth=256), "cth = 256"),
    (dict(ps="0 us"), 'ps = "0 us"'),
    (dict(pw="0 us", pi="0 us"), 'pw = "0 us"\npi = "0 us"'),
    (dict(min="7 ms"), 'min = "7 ms"'),
    (dict(pi="3 ms"), 'pi = "3 ms"'),
    (dict(min="100 us", adaptive=True), 'min = "100 us"\nadaptive = true'),
]


@pytest.mark.parametrize("kwargs,toml", BAD, ids=[t.replace("\n", ";") for _, t in BAD])
def test_config_errors_are_the_clis(kwargs, toml):
    with pytest.raises(pmu50.ConfigError) as e:
        pmu50.Core(**kwargs)
    assert isinstance(e.value, ValueError)
    with pytest.raises(pmu50.ScenarioError) as s:
        pmu50.Scenario.from_str(f'duration = "10 ms"\n[core]\n{toml}\n', "bad.toml")
    cli_msg = str(s.value)
    assert cli_msg.startswith("bad.toml:"), cli_msg
    assert str(e.value) == cli_msg.split(": ", 1)[1]


def test_config_errors_outside_the_storage_of_the_field():
    """Values no register could hold get the CLI's words too (the range of
    pmu50::scenario::CORE_INTS)."""
    with pytest.raises(
        pmu50.ConfigError,
        match=r"^`core.sync_depth`: 300 is out of range; "
        r"valid is a whole number of flip-flops from 1 to 4$",
    ):
        pmu50.Core(sync_depth=300)
    with pytest.raises(
        pmu50.ConfigError,
        match=r"^`core.cth`: -1 is out of range; "
        r"valid is a whole number of quiet pulses from 1 to 255$",
    ):
        pmu50.Core(cth=-1)
    with pytest.raises(
        pmu50.ConfigError,
        match=r"^`core.cth`: 99999999999999999999999 is out of range; "
        r"valid is a whole number of quiet pulses from 1 to 255$",
    ):
        pmu50.Core(cth=99999999999999999999999)


def test_config_type_errors():
    with pytest.raises(
        TypeError,
        match=r"`core.pw` takes a duration string with a unit, e.g. \"2.2 ms\".*got int 5",
    ):
        pmu50.Core(pw=5)
    with pytest.raises(TypeError, match="`core.adaptive` takes True or False, got int 1"):
        pmu50.Core(adaptive=1)
    with pytest.raises(TypeError, match="`core.sync_depth` takes an integer, got bool True"):
        pmu50.Core(sync_depth=True)
    with pytest.raises(
        TypeError,
        match="unexpected keyword argument `t3`; the \\[core\\] parameters are clock, sync_depth",
    ):
        pmu50.Core(t3="1 ms")


def test_register_map():
    names = [r[0] for r in pmu50.REGISTER_MAP]
    assert names[:3] == ["ID", "VERSION", "CTRL"] and "STATUS" in names
    c = pmu50.Core()
    assert c.read(dict((n, a) for n, a, _, _ in pmu50.REGISTER_MAP)["SI_MAX"]) == 660


def test_signal_table_checks_its_structural_parameters():
    with pytest.raises(
        pmu50.ConfigError, match="core.cnt_width = 1 is out of range; valid is 2..=16"
    ):
        pmu50.signal_table(cnt_width=1)
