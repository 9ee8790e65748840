"""What the HDL testbenches of the twin share (the cocotb bench hdl/cocotb and the pyuvm bench
hdl/uvm, docs/python.md): a signal's value as the simulator shows it, and the top's Verilog
parameters as ``pmu50.Core`` keyword arguments. Pure Python: it imports neither cocotb nor the
extension, so it loads inside any simulator."""

from __future__ import annotations

# Verilog parameter of the twin -> keyword argument of pmu50.Core (docs/hdl-guide.md, section 0).
# The timing parameters are in ticks; Core takes durations.
PARAMETERS = {
    "SYNC_DEPTH": "sync_depth",
    "CNT_W": "cnt_width",
    "ADAPTIVE": "adaptive",
    "PW": "pw",
    "PI": "pi",
    "PS": "ps",
    "SI_MAX": "x",
    "SI_MIN": "min",
    "T1": "t1",
    "T2": "t2",
    "CTH": "cth",
    "SMP_ON": "smp_on",
}
# the keywords that take a count, not a duration (and adaptive, a bool)
_COUNTS = {"sync_depth", "cnt_width", "cth"}


def read_value(handle) -> int | str:
    """The integer value of a simulator signal (``handle.value``), or its text when it holds x
    or z."""
    v = handle.value
    try:
        return int(v)
    except ValueError:
        return str(v)


def core_config(values: dict[str, int], clock_us: int = 10) -> dict:
    """``pmu50.Core`` keyword arguments for these Verilog parameter values (ticks of a
    ``clock_us`` clock); a parameter left out takes the model's default. A name that is no
    parameter of the top raises ``KeyError`` naming the valid ones."""
    cfg: dict = {"clock": f"{clock_us} us"}
    for param, value in values.items():
        try:
            name = PARAMETERS[param]
        except KeyError:
            raise KeyError(
                f"{param} is no Verilog parameter of the twin; valid are {', '.join(PARAMETERS)}"
            ) from None
        if name == "adaptive":
            cfg[name] = bool(value)
        elif name in _COUNTS:
            cfg[name] = int(value)
        else:
            cfg[name] = f"{int(value) * clock_us} us"
    return cfg
