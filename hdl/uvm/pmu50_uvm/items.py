"""Sequence items (what a sequence asks a driver to do) and the transactions monitors publish.

A sequence item holds its pins for ``cycles`` clock edges: a driver applies it at a falling
edge, and rising edges k+1 .. k+cycles sample it. Long stretches of the same inputs are one
item, which keeps a vector file's replay cheap.
"""

from __future__ import annotations

from pyuvm import uvm_sequence_item, uvm_transaction


class KeyItem(uvm_sequence_item):
    """The ignition key: ``ig`` for ``cycles`` edges."""

    def __init__(self, name: str = "key", ig: int = 0, cycles: int = 1):
        super().__init__(name)
        self.ig = ig
        self.cycles = cycles

    def __str__(self) -> str:
        return f"KeyItem(ig={self.ig}, cycles={self.cycles})"


class CmpItem(uvm_sequence_item):
    """The comparator bits and the Vs2 power-good for ``cycles`` edges.

    ``vs2_ok`` None: the rail follows the DUT's ``vs2_en`` (a healthy rail: power-good while
    enabled), forced low when ``fault``; 0 or 1: driven as given (a vector file's column).
    """

    def __init__(
        self,
        name: str = "cmp",
        cmp_s: int = 0,
        cmp_c: int = 0,
        vs2_ok: int | None = None,
        fault: bool = False,
        cycles: int = 1,
    ):
        super().__init__(name)
        self.cmp_s = cmp_s
        self.cmp_c = cmp_c
        self.vs2_ok = vs2_ok
        self.fault = fault
        self.cycles = cycles

    def __str__(self) -> str:
        rail = "follow" if self.vs2_ok is None else self.vs2_ok
        return (
            f"CmpItem(cmp_s={self.cmp_s}, cmp_c={self.cmp_c}, vs2_ok={rail}, "
            f"fault={self.fault}, cycles={self.cycles})"
        )


class BusItem(uvm_sequence_item):
    """One register bus cycle held for ``cycles`` edges: a write (``we`` = 1) or a read of
    ``addr`` (the read data is registered: ``bus_rdata`` shows it after the edge)."""

    def __init__(
        self, name: str = "bus", we: int = 0, addr: int = 0, wdata: int = 0, cycles: int = 1
    ):
        super().__init__(name)
        self.we = we
        self.addr = addr
        self.wdata = wdata
        self.cycles = cycles

    @classmethod
    def write(cls, addr: int, data: int) -> BusItem:
        return cls("write", 1, addr, data, 1)

    @classmethod
    def read(cls, addr: int, cycles: int = 1) -> BusItem:
        return cls("read", 0, addr, 0, cycles)

    def __str__(self) -> str:
        op = "write" if self.we else "read"
        return f"BusItem({op} addr={self.addr:#04x} wdata={self.wdata:#06x}, cycles={self.cycles})"


class PortSample(uvm_transaction):
    """What a monitor saw: pin values at edge ``tick`` (inputs: sampled by the edge; outputs:
    after it; tick 0: after reset)."""

    def __init__(self, tick: int, values: dict):
        super().__init__("sample")
        self.tick = tick
        self.values = values

    def __str__(self) -> str:
        return f"PortSample(tick={self.tick}, {self.values})"


class Prediction(uvm_transaction):
    """The predictor's outputs after edge ``tick`` for the inputs it saw, with the FIG. 17/18
    path of the edge (``-`` where FIG. 17 did not run)."""

    def __init__(self, tick: int, inputs: dict, outputs, fig: str):
        super().__init__("prediction")
        self.tick = tick
        self.inputs = inputs
        self.outputs = outputs
        self.fig = fig
