"""cocotb testbench of the Verilog twin (hdl/pmu50.v) with pmu50.Core as the reference model.

Runs inside the simulator (Icarus Verilog, toplevel ``pmu50``), started by test_cocotb.py.
Three concurrent parts:

- a clock on ``clk`` (period from the configuration, docs/spec.md 6.1);
- a stimulus coroutine that drives the seven inputs at every falling edge, either from the input
  columns of a vector file (``PMU50_VEC``) or seeded random (``PMU50_SEED``): key edges at random
  times, comparator bits, Vs2 rail faults (``vs2_ok`` low while ``vs2_en``), register writes
  (legal, illegal, read-only, unmapped, with the key off) and bus reads;
- a scoreboard that samples the inputs the DUT sees at each rising edge, steps ``pmu50.Core``
  with them through ``pmu50.Coverage`` (which samples the functional coverage model at every
  edge), and compares all 23 top-level outputs after the edge. The first mismatching tick
  fails the test with one line per differing signal::

      MISMATCH tick=4202 signal=si expected=0x226 got=0x1b8

Tick numbers are edge numbers (tick k = after rising edge k), as in docs/hdl-guide.md.

Configuration (environment variables, set by test_cocotb.py):
  PMU50_CORE   JSON object of ``pmu50.Core`` keyword arguments (the twin was built with the
               matching Verilog parameters, ``Core.hdl_parameters``)
  PMU50_VEC    vector file to replay (inputs only; expected outputs come from the model), its
               first PMU50_MAX_TICKS lines when that is set and not 0
  PMU50_SEED   random seed, PMU50_CYCLES cycles
  PMU50_COVERAGE  where to write the run's coverage.json (the merge format of `pmu50 merge`),
               with run id PMU50_RUN_ID
"""

from __future__ import annotations

import json
import os
import random

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge, Timer

import pmu50
from pmu50.hdl import read_value


class Mismatch(AssertionError):
    """The twin and the model disagree."""


def vector_inputs(path: str, names: list[str], max_ticks: int = 0):
    """The input columns of a vector file (docs/spec.md 6.2), one dict per line; only the first
    `max_ticks` lines when it is not 0."""
    n = len(names)
    k = 0
    with open(path, encoding="ascii") as f:
        for line in f:
            if line.startswith("//") or not line.strip():
                continue
            if max_ticks and k >= max_ticks:
                return
            k += 1
            fields = line.split()
            yield {name: int(x, 16) for name, x in zip(names, fields[:n])}


def random_inputs(seed: int, cycles: int, core: pmu50.Core):
    """Seeded random stimulus, chosen from the model's outputs of the current tick (a
    stimulus reacting to the design, as an MPU would)."""
    rng = random.Random(seed)
    rmap = {name: (addr, width, access) for name, addr, width, access in pmu50.REGISTER_MAP}
    addrs = [a for a, _, _ in rmap.values()]
    writable = [n for n, (_, _, acc) in rmap.items() if "RW" in acc or "W1C" in acc]
    hdl = core.hdl_parameters
    # timing registers and the Verilog parameter of their reset value
    timing = [
        n for n in ("PW", "PI", "PS", "SI_MAX", "SI_MIN", "T1", "T2", "CTH", "SMP_ON") if n in rmap
    ]
    ig = 0
    fault = 0
    cmp_s = rng.getrandbits(1)
    cmp_c = rng.getrandbits(1)
    for _ in range(cycles):
        now = core.peek()
        r = rng.random()
        # key edges at random times: key-on and key-off stretches of random length
        if r < 0.004 or (r < 0.02 and rng.random() < 0.1):
            ig ^= 1
        # rail faults: a dead Vs2 for a while
        if rng.random() < 0.01:
            fault ^= 1
        # the shaft turns: comparator bits step through the quadrants (Gray order), sometimes noisy
        if rng.random() < 0.05:
            q = cmp_s << 1 | cmp_c
            q = (
                {0b11: 0b10, 0b10: 0b00, 0b00: 0b01, 0b01: 0b11}[q]
                if rng.random() < 0.7
                else {0b10: 0b11, 0b00: 0b10, 0b01: 0b00, 0b11: 0b01}[q]
            )
            cmp_s, cmp_c = q >> 1, q & 1
        noise = rng.random() < 0.02
        inp = {
            "ig": ig,
            "vs2_ok": int(now.vs2_en and not fault),
            "cmp_s": cmp_s ^ int(noise),
            "cmp_c": cmp_c,
            "bus_we": 0,
            "bus_addr": rng.choice(addrs) if rng.random() < 0.8 else rng.getrandbits(8),
            "bus_wdata": 0,
        }
        if rng.random() < 0.03:
            # a register write (refused while the key is off, or when illegal: bus_err)
            inp["bus_we"] = 1
            w = rng.random()
            if w < 0.5:
                # a timing register, near its reset value: mostly legal, sometimes not
                name = rng.choice(timing)
                inp["bus_addr"] = rmap[name][0]
                inp["bus_wdata"] = max(0, min(0xFFFF, hdl[name] + rng.randint(-3, 3)))
            elif w < 0.8:
                name = rng.choice(writable)
                inp["bus_addr"] = rmap[name][0]
                inp["bus_wdata"] = rng.getrandbits(16) if rng.random() < 0.3 else rng.getrandbits(3)
            else:
                # any address (read-only and unmapped ones too), random data
                inp["bus_wdata"] = rng.getrandbits(16)
        yield inp


async def drive(dut, names, stimulus, clk):
    """Stimulus coroutine: new inputs at every falling edge (sampled by the next rising edge)."""
    handles = [getattr(dut, n) for n in names]
    for inp in stimulus:
        await FallingEdge(clk)
        for n, h in zip(names, handles):
            h.value = inp[n]


async def run(dut, stimulus_factory, state: dict):
    """Run the scoreboard; `state["cov"]` is the run's coverage from the first edge on (also
    when a mismatch ends the run)."""
    cfg = json.loads(os.environ.get("PMU50_CORE", "{}"))
    model = pmu50.Core(**cfg)
    in_names = [s.name for s in model.signals("input")]
    out_names = [s.name for s in model.signals("output")]
    in_h = [getattr(dut, n) for n in in_names]
    out_h = [getattr(dut, n) for n in out_names]
    period_ns = model.clock_ns
    half = period_ns // 2

    # Reset: inputs 0, rst_n low for half a period, released 3/4 period before the first rising
    # edge.
    for h in in_h:
        h.value = 0
    dut.rst_n.value = 0
    dut.clk.value = 0
    await Timer(half, unit="ns")
    dut.rst_n.value = 1
    await Timer(half - half // 2, unit="ns")

    def check(tick: int, expected: pmu50.Outputs) -> None:
        got = {n: read_value(h) for n, h in zip(out_names, out_h)}
        bad = expected.mismatches(got)
        if bad:
            lines = [
                f"MISMATCH tick={tick} signal={s} expected={e:#x} "
                f"got={g if isinstance(g, str) else hex(g)}"
                for s, e, g in bad
            ]
            raise Mismatch(
                "\n".join(lines) + f"\nFAIL: the twin differs from pmu50.Core at tick {tick} "
                f"({len(bad)} signal(s)), time {tick * period_ns} ns"
            )

    # Tick 0: the reset values.
    check(0, model.peek())

    stimulus = stimulus_factory(model)
    cocotb.start_soon(Clock(dut.clk, period_ns, unit="ns").start(start_high=False))
    cov = state["cov"] = pmu50.Coverage(model)
    # first inputs before the first edge
    first = next(stimulus, None)
    if first is None:
        return 0, cov
    for n, h in zip(in_names, in_h):
        h.value = first[n]
    driver = cocotb.start_soon(drive(dut, in_names, stimulus, dut.clk))

    tick = 0
    clk = dut.clk
    while True:
        await RisingEdge(clk)
        seen = {n: read_value(h) for n, h in zip(in_names, in_h)}
        after = cov.step(model, **seen)
        tick += 1
        await ReadOnly()
        check(tick, after)
        if driver.done():
            break
    return tick, cov


def save_coverage(cov: pmu50.Coverage, verdict: str) -> None:
    """Write the run's coverage.json (PMU50_COVERAGE, run id PMU50_RUN_ID), atomically."""
    path = os.environ.get("PMU50_COVERAGE")
    if path:
        cov.write(
            path, os.environ.get("PMU50_RUN_ID") or f"cocotb/{os.path.basename(path)}", verdict
        )


@cocotb.test()
async def twin_matches_model(dut):
    """The twin and pmu50.Core agree on every output, every tick."""
    vec = os.environ.get("PMU50_VEC")
    state: dict = {}
    verdict = "fail"
    try:
        if vec:
            names = [s.name for s in pmu50.signal_table("input")]
            limit = int(os.environ.get("PMU50_MAX_TICKS", "0"))
            ticks, cov = await run(dut, lambda core: vector_inputs(vec, names, limit), state)
            dut._log.info(
                "PASS %s: %d ticks, 23 outputs each; %s", os.path.basename(vec), ticks, cov
            )
        else:
            seed = int(os.environ["PMU50_SEED"])
            cycles = int(os.environ.get("PMU50_CYCLES", "2000"))
            ticks, cov = await run(dut, lambda core: random_inputs(seed, cycles, core), state)
            dut._log.info("PASS seed %d: %d ticks, 23 outputs each; %s", seed, ticks, cov)
        verdict = "pass"
    finally:
        if "cov" in state:
            save_coverage(state["cov"], verdict)
