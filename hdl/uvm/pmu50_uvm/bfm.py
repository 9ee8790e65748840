"""The interface of the design under test: its contract ports (docs/signals.md), its clock and
reset, and the configuration read from its top-level parameters.

The bench touches ports only (and the top's parameters, read once): no hierarchical name, so
any RTL with the contract ports runs in it.
"""

from __future__ import annotations

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import Event, Timer
from cocotb.utils import get_sim_time

import pmu50
from pmu50.hdl import PARAMETERS, core_config, read_value


class ConfigurationError(RuntimeError):
    """The top's parameters do not make a legal pmu50.Core configuration."""


class Pmu50Bfm:
    """Handles of the contract ports, the clock and the reset of one DUT.

    ``params`` are the top's Verilog parameters that exist (read through the simulator's
    interface, no hierarchy); ``defaulted`` the ones the top does not have, which take the
    model's defaults. ``config`` is the matching ``pmu50.Core`` configuration.
    """

    def __init__(self, dut, clock_us: int = 10):
        self.dut = dut
        self.params: dict[str, int] = {}
        self.defaulted: list[str] = []
        for p in PARAMETERS:
            try:
                h = getattr(dut, p)
            except AttributeError:
                self.defaulted.append(p)
                continue
            self.params[p] = int(h.value)
        self.config = core_config(self.params, clock_us)
        try:
            core = pmu50.Core(**self.config)
        except pmu50.ConfigError as e:
            raise ConfigurationError(
                f"the top's parameters {self.params} are not a legal configuration: {e}"
            ) from None
        # what the top's parameters turn into must come back unchanged (ticks, flags, widths)
        got = core.hdl_parameters
        off = {p: (v, got[p]) for p, v in self.params.items() if got.get(p) != v}
        if off:
            raise ConfigurationError(
                f"the top's parameters {off} (value, model) do not map onto pmu50.Core"
            )
        self.hdl_parameters = got
        self.period_ns = core.clock_ns
        self.half_ns = self.period_ns // 2
        self.inputs = [s.name for s in core.signals("input")]
        self.outputs = [s.name for s in core.signals("output")]
        self.h = {n: getattr(dut, n) for n in self.inputs + self.outputs}
        self.clk = dut.clk
        # set at the instant the clock starts (tick 0, reset released): drivers apply their
        # first items then, monitors start counting edges
        self.started = Event()
        self.t0_ns: int | None = None

    def now_ns(self) -> int:
        return int(get_sim_time("ns"))

    def read(self, names) -> dict[str, int | str]:
        return {n: read_value(self.h[n]) for n in names}

    async def reset_and_start(self) -> None:
        """Inputs 0; ``rst_n`` high for a quarter period, then low for half a period (a falling
        edge on every simulator: Verilator starts it at 0, not x), released 3/4 period before
        the first rising edge; then the clock (low first) starts: tick 0."""
        for n in self.inputs:
            self.h[n].value = 0
        self.dut.rst_n.value = 1
        self.clk.value = 0
        await Timer(self.half_ns // 2, unit="ns")
        self.dut.rst_n.value = 0
        await Timer(self.half_ns, unit="ns")
        self.dut.rst_n.value = 1
        await Timer(self.half_ns - self.half_ns // 2, unit="ns")
        cocotb.start_soon(Clock(self.clk, self.period_ns, unit="ns").start(start_high=False))
        self.t0_ns = self.now_ns()
        self.started.set()

    def slot_ns(self, k: int) -> int:
        """Time of falling edge k (k = 0: the clock's start): inputs set then are sampled by
        rising edge k + 1."""
        assert self.t0_ns is not None
        return self.t0_ns + k * self.period_ns

    def next_slot(self) -> int:
        """The first slot at or after now."""
        assert self.t0_ns is not None
        d = self.now_ns() - self.t0_ns
        return -(-d // self.period_ns)
