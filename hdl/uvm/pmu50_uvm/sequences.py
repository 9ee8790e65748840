"""Sequences: per-agent item lists and generators, and the virtual sequences that run one on
each agent at once.

- ``VectorSeq``: a vector file's input columns (docs/spec.md 6.2), split into the three agents'
  items (run-length: one item per stretch of equal pins). ``ScenarioSeq`` makes the file of a
  scenario (``pmu50 vectors``), ``RegressSeedSeq`` of the scenario `pmu50 regress` runs for a
  seed (``pmu50 random --regress``, the regression's own generator).
- ``RandomSeq``: seeded random key, shaft and rail, and bus traffic (``KeyRandomSeq``,
  ``CmpRandomSeq``, ``BusRandomSeq``).
- ``RegisterSeq``: the register bus, directed: every register read, legal writes read back,
  illegal, read-only and unmapped writes, the write-1-to-clear bits, a write with the key off.
"""

from __future__ import annotations

import os
import random
import shutil
import subprocess
import tempfile
from pathlib import Path

from cocotb.triggers import gather
from pyuvm import uvm_sequence

import pmu50

from .items import BusItem, CmpItem, KeyItem

REPO = Path(__file__).resolve().parents[3]


class StimulusError(RuntimeError):
    """A stimulus could not be made (a missing binary, a bad vector file)."""


def pmu50_bin() -> str:
    """The `pmu50` command: ``PMU50_BIN``, else the checkout's release build, else PATH."""
    for cand in (
        os.environ.get("PMU50_BIN"),
        str(REPO / "target" / "release" / "pmu50"),
        shutil.which("pmu50"),
    ):
        if cand and Path(cand).is_file():
            return cand
    raise StimulusError(
        "the `pmu50` command was not found: set PMU50_BIN, or build it with "
        "`cargo build --release --bin pmu50`"
    )


def run_cli(*args: str) -> None:
    r = subprocess.run([pmu50_bin(), *args], capture_output=True, text=True)
    if r.returncode != 0:
        raise StimulusError(
            f"`pmu50 {' '.join(args)}` failed (exit {r.returncode}): {r.stderr.strip()}"
        )


REG = {name: (addr, width, access) for name, addr, width, access in pmu50.REGISTER_MAP}
INPUTS = [s.name for s in pmu50.signal_table("input")]


class ItemListSeq(uvm_sequence):
    """Sends a list of items to one agent, in order."""

    def __init__(self, name: str, items: list):
        super().__init__(name)
        self.items = items

    @staticmethod
    def items_of(sub) -> list:
        """The items of a sub-sequence: a list, or an ``ItemListSeq``."""
        return sub if isinstance(sub, list) else sub.items

    async def body(self):
        for item in self.items:
            await self.start_item(item)
            await self.finish_item(item)


class Pmu50VirtualSeq(uvm_sequence):
    """Runs one sequence on each of the three agents at once. Subclasses fill ``key``, ``cmp``
    and ``bus`` (item lists or sequences) in ``make``; ``ticks`` is the run's length."""

    def __init__(self, name: str = "pmu50_vseq"):
        super().__init__(name)
        self.ticks = 0

    def make(self, cfg: dict) -> tuple:
        """The (key, cmp, bus) sub-sequences or item lists for a DUT whose Verilog parameters
        are ``cfg`` (ticks); sets ``ticks``."""
        raise NotImplementedError

    async def run(self, env, subs: tuple) -> None:
        """Run the three sub-sequences ``make`` made on the env's sequencers, to their end."""
        seqs = []
        for seq, agent in zip(subs, (env.key, env.cmp, env.bus)):
            if isinstance(seq, list):
                seq = ItemListSeq(f"{self.get_name()}.{agent.get_name()}", seq)
            seqs.append(seq.start(agent.seqr))
        await gather(*seqs)


def runs(rows: list[tuple], make) -> list:
    """Run-length items: ``make(values, cycles)`` for each stretch of equal rows."""
    items = []
    prev, n = None, 0
    for r in rows:
        if r == prev:
            n += 1
            continue
        if prev is not None:
            items.append(make(prev, n))
        prev, n = r, 1
    if prev is not None:
        items.append(make(prev, n))
    return items


class VectorSeq(Pmu50VirtualSeq):
    """A vector file's inputs, its first ``max_ticks`` lines when that is not 0."""

    def __init__(self, path: str | Path, max_ticks: int = 0, name: str = "vectors"):
        super().__init__(name)
        self.path = Path(path)
        self.max_ticks = max_ticks

    def rows(self) -> list[list[int]]:
        out = []
        try:
            with open(self.path, encoding="ascii") as f:
                for n, line in enumerate(f, 1):
                    if line.startswith("//") or not line.strip():
                        continue
                    if self.max_ticks and len(out) >= self.max_ticks:
                        break
                    fields = line.split()
                    if len(fields) < len(INPUTS):
                        raise StimulusError(
                            f"{self.path}:{n}: {len(fields)} fields, expected at least the "
                            f"{len(INPUTS)} inputs {INPUTS}"
                        )
                    out.append([int(x, 16) for x in fields[: len(INPUTS)]])
        except (OSError, ValueError) as e:
            raise StimulusError(f"{self.path}: {e}") from None
        return out

    def make(self, cfg):
        rows = self.rows()
        self.ticks = len(rows)
        col = {n: i for i, n in enumerate(INPUTS)}
        key = runs([(r[col["ig"]],) for r in rows], lambda v, n: KeyItem("key", v[0], n))
        cmp_ = runs(
            [(r[col["cmp_s"]], r[col["cmp_c"]], r[col["vs2_ok"]]) for r in rows],
            lambda v, n: CmpItem("cmp", v[0], v[1], v[2], False, n),
        )
        bus = runs(
            [(r[col["bus_we"]], r[col["bus_addr"]], r[col["bus_wdata"]]) for r in rows],
            lambda v, n: BusItem("bus", v[0], v[1], v[2], n),
        )
        return key, cmp_, bus


class ScenarioSeq(VectorSeq):
    """The inputs of a scenario file, as `pmu50 vectors` writes them."""

    def __init__(self, scenario: str | Path, max_ticks: int = 0):
        self.scenario = Path(scenario)
        super().__init__(
            self.scenario.with_suffix(".vec"), max_ticks, name=f"scenario_{self.scenario.stem}"
        )

    def make(self, cfg):
        with tempfile.TemporaryDirectory(prefix="pmu50_uvm_") as d:
            self.path = Path(d) / f"{self.scenario.stem}.vec"
            run_cli("vectors", str(self.scenario), "-o", str(self.path))
            return super().make(cfg)


class RegressSeedSeq(VectorSeq):
    """The stimulus `pmu50 regress` runs for ``seed`` (uniform random: ``pmu50 random --seed N
    --regress``, then its vectors)."""

    def __init__(self, seed: int, max_ticks: int = 0):
        self.seed = seed
        super().__init__(f"seed_{seed}.vec", max_ticks, name=f"regress_seed_{seed}")

    def make(self, cfg):
        with tempfile.TemporaryDirectory(prefix="pmu50_uvm_") as d:
            toml = Path(d) / f"seed_{self.seed}.toml"
            self.path = Path(d) / f"seed_{self.seed}.vec"
            run_cli("random", "--seed", str(self.seed), "--regress", "-o", str(toml))
            run_cli("vectors", str(toml), "-o", str(self.path))
            return super().make(cfg)


# --- random -------------------------------------------------------------------------------------


def fill(items: list, cycles: int) -> list:
    """Cut the items' total length to exactly ``cycles``."""
    out, total = [], 0
    for it in items:
        if total >= cycles:
            break
        it.cycles = min(it.cycles, cycles - total)
        total += it.cycles
        out.append(it)
    return out


def key_random(rng: random.Random, cycles: int, sync_depth: int) -> list[KeyItem]:
    """Key-on and key-off stretches of random length, some very short (a storm), some pulses
    shorter than the synchronizer (glitches that must not reach ``sig``)."""
    items, total, ig = [], 0, rng.getrandbits(1)
    while total < cycles:
        r = rng.random()
        if r < 0.08:
            n = rng.randint(1, sync_depth)  # a glitch
        elif r < 0.25:
            n = rng.randint(sync_depth + 1, 40)  # a storm
        else:
            n = rng.randint(50, 700) if ig else rng.randint(100, 1500)
        items.append(KeyItem("key", ig, n))
        total += n
        ig ^= 1
    return fill(items, cycles)


# the shaft's quadrants in rotation order, as (cmp_s, cmp_c)
GRAY = [(1, 1), (1, 0), (0, 0), (0, 1)]


def cmp_random(rng: random.Random, cycles: int) -> list[CmpItem]:
    """The shaft moving like a motor: turns of a few quadrants in one direction or the other
    (the comparator bits stepping in Gray order), each step held for a random time, sometimes
    two quadrants at once (a skip if no sample falls between), stops; comparator noise of one
    tick; and Vs2 rail faults (``vs2_ok`` low while enabled)."""
    items, total = [], 0
    q = rng.randrange(4)
    fault_left = 0
    while total < cycles:
        direction = rng.choice((1, -1))
        fast = rng.random() < 0.3
        for _ in range(rng.randint(1, 16)):
            q = (q + direction * (2 if rng.random() < 0.06 else 1)) % 4
            if fault_left <= 0 and rng.random() < 0.05:
                fault_left = rng.randint(5, 300)
            s, c = GRAY[q]
            n = rng.randint(1, 12) if fast else rng.randint(5, 150)
            if rng.random() < 0.04:
                # noise: one tick of a wrong sine bit
                items.append(CmpItem("cmp", s ^ 1, c, None, fault_left > 0, 1))
                total += 1
            items.append(CmpItem("cmp", s, c, None, fault_left > 0, n))
            total += n
            fault_left -= n
        # the shaft stands still for a while
        n = rng.randint(20, 800)
        items.append(CmpItem("cmp", s, c, None, fault_left > 0, n))
        total += n
        fault_left -= n
    return fill(items, cycles)


def bus_random(rng: random.Random, cycles: int, hdl: dict) -> list[BusItem]:
    """Register traffic: reads of mapped and unmapped addresses held for a while, and writes:
    timing registers near their reset value (mostly legal), any writable register, the W1C bits
    of STATUS, read-only and unmapped addresses. The key is not looked at: some writes come with
    the key off and must be refused."""
    mapped = [a for a, _, _ in REG.values()]
    writable = [n for n, (_, _, acc) in REG.items() if "RW" in acc]
    timing = [
        n
        for n in ("PW", "PI", "PS", "SI_MAX", "SI_MIN", "T1", "T2", "CTH", "SMP_ON")
        if n in REG and n in hdl
    ]
    items, total = [], 0
    counters = [REG[n][0] for n in ("CNT_S", "CNT_C", "CNT_R", "SI", "STATUS") if n in REG]
    while total < cycles:
        r = rng.random()
        addr = (
            rng.choice(counters)
            if r < 0.3
            else rng.choice(mapped)
            if r < 0.9
            else rng.getrandbits(8)
        )
        n = rng.randint(1, 40)
        items.append(BusItem.read(addr, n))
        total += n
        if rng.random() < 0.45:
            w = rng.random()
            if w < 0.45:
                name = rng.choice(timing)
                item = BusItem.write(
                    REG[name][0], max(0, min(0xFFFF, hdl[name] + rng.randint(-3, 3)))
                )
            elif w < 0.65:
                name = rng.choice(writable)
                item = BusItem.write(
                    REG[name][0], rng.getrandbits(16) if rng.random() < 0.3 else rng.getrandbits(3)
                )
            elif w < 0.8:
                item = BusItem.write(
                    REG["STATUS"][0],
                    rng.choice([1 << 5, 1 << 9, (1 << 5) | (1 << 9), rng.getrandbits(10)]),
                )
            else:
                item = BusItem.write(rng.getrandbits(8), rng.getrandbits(16))
            items.append(item)
            total += 1
    return fill(items, cycles)


class RandomSeq(Pmu50VirtualSeq):
    """Seeded random stimulus on the three agents for ``cycles`` edges: each agent draws from a
    generator of its own, seeded from ``seed``, so a change of one agent's sequence leaves the
    others' stimulus as it was."""

    def __init__(self, seed: int, cycles: int):
        super().__init__(f"random_{seed}")
        self.seed = seed
        self.cycles = cycles

    def make(self, cfg):
        rngs = [random.Random(f"{self.seed}/{part}") for part in ("key", "cmp", "bus")]
        self.ticks = self.cycles
        return (
            key_random(rngs[0], self.cycles, cfg["SYNC_DEPTH"]),
            cmp_random(rngs[1], self.cycles),
            bus_random(rngs[2], self.cycles, cfg),
        )


# --- register bus, directed --------------------------------------------------------------------


class RegisterSeq(Pmu50VirtualSeq):
    """The register bus, directed, with the key on (then off), the shaft still and the rail
    healthy:

    1. every mapped register read (and a few unmapped addresses);
    2. every parameter register written with its reset value (legal), then read back;
    3. illegal values (CTH = 0, PS = 0, SI_MIN above SI_MAX, SI_MAX below SI_MIN), read-only and
       unmapped addresses: each refused, ``bus_err`` set, cleared by STATUS bit 9 (W1C);
    4. a legal change of CTH and SMP_ON, read back;
    5. the key off, with SI_MAX written at every edge until ``sig`` falls (the write of the
       key-off edge sets the x the interval starts from); then a parameter write refused.
    The shaft stands in quadrant 3 (Cs = 0, Cc = 1), which the first sample presets.
    """

    def __init__(self):
        super().__init__("registers")

    def make(self, cfg):
        sd = cfg["SYNC_DEPTH"]
        bus: list[BusItem] = [BusItem.read(0, sd + 3)]  # the key comes on, sig follows
        rd = lambda a: BusItem.read(a, 2)  # noqa: E731
        status = REG["STATUS"][0]
        clear = BusItem.write(status, 1 << 9)
        for addr, _, _ in REG.values():
            bus.append(rd(addr))
        bus += [rd(a) for a in (0x0D, 0x0F, 0x15, 0x80, 0xFF)]
        params = {
            "PW": "PW",
            "PI": "PI",
            "PS": "PS",
            "SI_MAX": "SI_MAX",
            "SI_MIN": "SI_MIN",
            "T1": "T1",
            "T2": "T2",
            "CTH": "CTH",
            "SMP_ON": "SMP_ON",
        }
        for name, p in params.items():
            if name in REG:
                bus += [BusItem.write(REG[name][0], cfg[p]), rd(REG[name][0])]
        if "CTRL" in REG:
            bus += [BusItem.write(REG["CTRL"][0], cfg["ADAPTIVE"]), rd(REG["CTRL"][0])]
        illegal = [
            ("CTH", 0),
            ("CTH", 0x100),
            ("PS", 0),
            ("SI_MIN", cfg["SI_MAX"] + 1),
            ("SI_MAX", max(cfg["SI_MIN"] - 1, 0)),
            ("T1", 0),
        ]
        for name, v in illegal:
            bus += [BusItem.write(REG[name][0], v), rd(status), rd(REG[name][0]), clear, rd(status)]
        for addr in (REG["ID"][0], REG["SI"][0], 0x0D, 0xFF):
            bus += [BusItem.write(addr, 0xA5A5), rd(status), clear, rd(status)]
        bus += [
            BusItem.write(REG["CTH"][0], cfg["CTH"] + 1),
            rd(REG["CTH"][0]),
            BusItem.write(REG["SMP_ON"][0], cfg["SMP_ON"] + 2),
            rd(REG["SMP_ON"][0]),
        ]
        bus += [BusItem.write(status, (1 << 5) | (1 << 9)), rd(status)]
        on = sum(b.cycles for b in bus)
        # key off: SI_MAX written with a new value at every edge until sig has fallen (the write
        # of the key-off edge itself is accepted, and the interval starts at the new x), then
        # a refused write
        bus += [BusItem.write(REG["SI_MAX"][0], cfg["SI_MAX"] + 1 + k) for k in range(sd + 2)]
        bus += [
            rd(REG["SI_MAX"][0]),
            rd(REG["SI"][0]),
            BusItem.write(REG["PW"][0], cfg["PW"]),
            rd(status),
            rd(REG["PW"][0]),
        ]
        total = sum(b.cycles for b in bus)
        self.ticks = total
        key = [KeyItem("key", 1, on), KeyItem("key", 0, total - on)]
        # the shaft still in quadrant 3 (Cs = 0, Cc = 1): the first sample presets the counters
        # from it
        cmp_ = [CmpItem("cmp", 0, 1, None, False, total)]
        return key, cmp_, bus
