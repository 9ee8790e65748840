"""The three active agents of the contract's inputs, and the passive monitor of its outputs.

- ``KeyAgent``: ``ig``.
- ``CmpAgent``: ``cmp_s``, ``cmp_c`` and ``vs2_ok`` (the comparator decisions and the rail
  monitor of the sensor they come from).
- ``BusAgent``: ``bus_we``, ``bus_addr``, ``bus_wdata``.
- ``OutputMonitor``: the 23 outputs after every edge (and at tick 0, after reset).

Each agent is a sequencer, a driver and a monitor. Drivers apply an item at a falling edge and
hold it for its ``cycles`` edges; monitors publish, at every rising edge, the pins the edge
samples (a ``PortSample`` on ``ap``).
"""

from __future__ import annotations

from cocotb.triggers import ReadOnly, RisingEdge, Timer
from pyuvm import ConfigDB, uvm_agent, uvm_analysis_port, uvm_driver, uvm_monitor, uvm_sequencer

from .items import PortSample


class PinDriver(uvm_driver):
    """Applies items to its pins at falling edges; an item holds for ``item.cycles`` edges."""

    PINS: tuple[str, ...] = ()

    def build_phase(self):
        self.bfm = ConfigDB().get(self, "", "BFM")

    def apply(self, item) -> None:
        raise NotImplementedError

    async def hold(self, item, start: int) -> None:
        """Wait until the falling edge after the item's last edge."""
        await Timer(self.bfm.slot_ns(start + item.cycles) - self.bfm.now_ns(), unit="ns")

    async def run_phase(self):
        bfm = self.bfm
        await bfm.started.wait()
        while True:
            item = await self.seq_item_port.get_next_item()
            # the next falling edge (or the clock's start): drivers stay on the edge grid
            k = bfm.next_slot()
            wait = bfm.slot_ns(k) - bfm.now_ns()
            if wait > 0:
                await Timer(wait, unit="ns")
            self.apply(item)
            await self.hold(item, k)
            self.seq_item_port.item_done()


class KeyDriver(PinDriver):
    PINS = ("ig",)

    def apply(self, item) -> None:
        self.bfm.h["ig"].value = item.ig


class CmpDriver(PinDriver):
    PINS = ("cmp_s", "cmp_c", "vs2_ok")

    def apply(self, item) -> None:
        h = self.bfm.h
        h["cmp_s"].value = item.cmp_s
        h["cmp_c"].value = item.cmp_c
        if item.vs2_ok is not None:
            h["vs2_ok"].value = item.vs2_ok

    async def hold(self, item, start: int) -> None:
        if item.vs2_ok is not None:
            return await super().hold(item, start)
        # a rail that follows its enable: vs2_ok = vs2_en (of the tick before the edge that
        # samples it), low during a fault
        bfm = self.bfm
        ok, en = bfm.h["vs2_ok"], bfm.h["vs2_en"]
        for k in range(start, start + item.cycles):
            ok.value = 0 if item.fault else int(en.value)
            await Timer(bfm.slot_ns(k + 1) - bfm.now_ns(), unit="ns")


class BusDriver(PinDriver):
    PINS = ("bus_we", "bus_addr", "bus_wdata")

    def apply(self, item) -> None:
        h = self.bfm.h
        h["bus_we"].value = item.we
        h["bus_addr"].value = item.addr
        h["bus_wdata"].value = item.wdata


class PinMonitor(uvm_monitor):
    """Publishes the pins each rising edge samples, numbered by edge (tick k: rising edge k)."""

    PINS: tuple[str, ...] = ()

    def build_phase(self):
        self.bfm = ConfigDB().get(self, "", "BFM")
        self.ap = uvm_analysis_port("ap", self)

    async def run_phase(self):
        bfm = self.bfm
        await bfm.started.wait()
        handles = [(n, bfm.h[n]) for n in self.PINS]
        tick = 0
        while True:
            await RisingEdge(bfm.clk)
            tick += 1
            self.ap.write(PortSample(tick, {n: int(h.value) for n, h in handles}))


class KeyMonitor(PinMonitor):
    PINS = KeyDriver.PINS


class CmpMonitor(PinMonitor):
    PINS = CmpDriver.PINS


class BusMonitor(PinMonitor):
    PINS = BusDriver.PINS


class PinAgent(uvm_agent):
    """Sequencer, driver and monitor of one group of input pins."""

    DRIVER = PinDriver
    MONITOR = PinMonitor

    def build_phase(self):
        super().build_phase()
        self.monitor = self.MONITOR("monitor", self)
        if self.get_is_active():
            self.seqr = uvm_sequencer("seqr", self)
            self.driver = self.DRIVER("driver", self)

    def connect_phase(self):
        if self.get_is_active():
            self.driver.seq_item_port.connect(self.seqr.seq_item_export)


class KeyAgent(PinAgent):
    DRIVER, MONITOR = KeyDriver, KeyMonitor


class CmpAgent(PinAgent):
    DRIVER, MONITOR = CmpDriver, CmpMonitor


class BusAgent(PinAgent):
    DRIVER, MONITOR = BusDriver, BusMonitor


class OutputMonitor(uvm_monitor):
    """The DUT's 23 outputs: at tick 0 (after reset, before the first edge) and in the read-only
    phase after every rising edge."""

    def build_phase(self):
        self.bfm = ConfigDB().get(self, "", "BFM")
        self.ap = uvm_analysis_port("ap", self)

    async def run_phase(self):
        bfm = self.bfm
        await bfm.started.wait()
        names = bfm.outputs
        self.ap.write(PortSample(0, bfm.read(names)))
        tick = 0
        while True:
            await RisingEdge(bfm.clk)
            tick += 1
            await ReadOnly()
            self.ap.write(PortSample(tick, bfm.read(names)))
