"""pmu50.hdl, the part the HDL testbenches share: a signal's value, and the top's Verilog
parameters mapped back onto pmu50.Core."""

from __future__ import annotations

import pytest

import pmu50
from pmu50.hdl import PARAMETERS, core_config, read_value


class Handle:
    """A simulator handle as cocotb gives it: ``.value`` converts with int() or fails."""

    def __init__(self, value):
        self.value = value


class Logic:
    def __init__(self, text: str):
        self.text = text

    def __int__(self) -> int:
        if any(c in "xXzZ" for c in self.text):
            raise ValueError(f"{self.text} holds x or z")
        return int(self.text, 2)

    def __str__(self) -> str:
        return self.text


def test_read_value_is_the_integer_or_the_text_with_x_or_z():
    assert read_value(Handle(Logic("0101"))) == 5
    assert read_value(Handle(Logic("01x1"))) == "01x1"
    assert read_value(Handle(Logic("z"))) == "z"


CONFIGS = [
    {},
    dict(
        cnt_width=4, sync_depth=3, x="90 us", min="40 us", pw="10 us", pi="10 us", ps="10 us", cth=2
    ),
    dict(adaptive=False, x="70 us", min="70 us", pw="0 us", pi="20 us", ps="10 us", smp_on="30 us"),
]


@pytest.mark.parametrize("cfg", CONFIGS)
def test_the_verilog_parameters_map_back_onto_the_core(cfg):
    hdl = pmu50.Core(**cfg).hdl_parameters
    # every parameter of the model is mapped, and the mapping gives the same core back
    assert set(hdl) == set(PARAMETERS)
    assert set(PARAMETERS.values()) == set(pmu50.CORE_PARAMETERS) - {"clock"}
    assert pmu50.Core(**core_config(hdl)).hdl_parameters == hdl
    # a parameter left out takes the model's default
    partial = {k: v for k, v in hdl.items() if k != "CTH"}
    back = pmu50.Core(**core_config(partial)).hdl_parameters
    assert back == {**hdl, "CTH": pmu50.Core().hdl_parameters["CTH"]}


def test_a_clock_scales_the_durations():
    assert core_config({"SI_MAX": 66, "CTH": 3}, clock_us=100) == {
        "clock": "100 us",
        "x": "6600 us",
        "cth": 3,
    }


def test_an_unknown_parameter_names_the_valid_ones():
    with pytest.raises(KeyError, match="NOPE is no Verilog parameter of the twin; valid are SYNC"):
        core_config({"NOPE": 1})
