"""The environment: three input agents, the output monitor, the predictor (``pmu50.Core``), the
scoreboard and the coverage subscriber (``pmu50.Coverage``).

    KeyAgent.monitor ──┐
    CmpAgent.monitor ──┼─> Predictor (pmu50.Core) ──> Scoreboard <── OutputMonitor
    BusAgent.monitor ──┘          │
                                  └─> CoverageSubscriber (pmu50.Coverage)
"""

from __future__ import annotations

import json
import os

from cocotb.triggers import Event
from pyuvm import (
    ConfigDB,
    uvm_analysis_export,
    uvm_analysis_port,
    uvm_component,
    uvm_env,
    uvm_scoreboard,
    uvm_subscriber,
)

import pmu50

from .agents import BusAgent, CmpAgent, KeyAgent, OutputMonitor
from .items import Prediction

_BINS = [b[0] for b in pmu50.Coverage.bins()]
FIG17 = [n.rsplit(".", 1)[1] for n in _BINS if n.startswith("fig17.path.")]
FIG18 = [n.rsplit(".", 1)[1] for n in _BINS if n.startswith("fig18.path.")]


def fig_path(fig17: int, fig18: int) -> str:
    """FIG. 17/18 path of an edge by the coverage bins' names, as `pmu50 regress` reports it
    (``s6_shorten/s23_detected_cs``; ``-`` where FIG. 17 did not run)."""
    if fig17 == 0:
        return "-"
    a = FIG17[fig17 - 1]
    return a if fig18 == 0 else f"{a}/{FIG18[fig18 - 1]}"


class _Imp(uvm_analysis_export):
    """An analysis export that hands each transaction to a function of its component."""

    def __init__(self, name, parent, fn):
        super().__init__(name, parent)
        self.fn = fn

    def write(self, tt):
        self.fn(tt)


class Mismatch(AssertionError):
    """The DUT and the model disagree."""


class Predictor(uvm_component):
    """The reference model: joins the three input monitors' samples of each edge, steps
    ``pmu50.Core`` with them and publishes the outputs it predicts after the edge (with the edge's
    FIG. 17/18 path) on ``ap``. Tick 0 is the model's reset state."""

    def build_phase(self):
        self.bfm = ConfigDB().get(self, "", "BFM")
        self.core = pmu50.Core(**self.bfm.config)
        self.key_export = _Imp("key_export", self, lambda t: self._join(0, t))
        self.cmp_export = _Imp("cmp_export", self, lambda t: self._join(1, t))
        self.bus_export = _Imp("bus_export", self, lambda t: self._join(2, t))
        self.ap = uvm_analysis_port("ap", self)
        self._pending: dict[int, list] = {}
        # what the sequences sent, per agent and edge (``expect_stimulus``): the bench's own
        # check that each driver applied each item on its edges
        self._sent: list | None = None
        self.stimulus_error: str | None = None

    def expect_stimulus(self, key: list, cmp_: list, bus: list) -> None:
        """The item lists of a run: the pins each edge must sample (``vs2_ok`` of a rail that
        follows ``vs2_en`` is not known in advance and is not checked)."""

        def expand(items, fields):
            out = []
            for it in items:
                out.extend([tuple(getattr(it, f) for f in fields)] * it.cycles)
            return out

        self._sent = [
            expand(key, ("ig",)),
            expand(cmp_, ("cmp_s", "cmp_c", "vs2_ok")),
            expand(bus, ("we", "addr", "wdata")),
        ]

    def reset_state(self):
        """The prediction of tick 0 (after reset)."""
        self.ap.write(Prediction(0, {}, self.core.peek(), "-"))

    def _join(self, part: int, t) -> None:
        parts = self._pending.setdefault(t.tick, [None, None, None])
        parts[part] = t.values
        if None in parts:
            return
        del self._pending[t.tick]
        inputs = {**parts[0], **parts[1], **parts[2]}
        if self._sent is not None and self.stimulus_error is None:
            self._check_sent(t.tick, inputs)
        if t.tick != self.core.tick + 1:
            raise RuntimeError(f"predictor: edge {t.tick} arrived after edge {self.core.tick}")
        tr = self.core.step_traced(**inputs)
        self.ap.write(
            Prediction(t.tick, inputs, tr.after, fig_path(tr.internals.fig17, tr.internals.fig18))
        )

    def _check_sent(self, tick: int, inputs: dict) -> None:
        k = tick - 1
        key, cmp_, bus = (s[k] if k < len(s) else None for s in self._sent)
        want = {}
        if key is not None:
            want["ig"] = key[0]
        if cmp_ is not None:
            want.update(cmp_s=cmp_[0], cmp_c=cmp_[1])
            if cmp_[2] is not None:
                want["vs2_ok"] = cmp_[2]
        if bus is not None:
            want.update(bus_we=bus[0], bus_addr=bus[1], bus_wdata=bus[2])
        off = {n: (v, inputs[n]) for n, v in want.items() if inputs[n] != v}
        if off:
            self.stimulus_error = (
                f"edge {tick} sampled inputs other than the sequences sent "
                f"(pin: (sent, sampled)): {off}"
            )
            self.logger.error(self.stimulus_error)


class Scoreboard(uvm_scoreboard):
    """Compares every output after every edge (and at tick 0) with the predictor. The first
    divergent tick ends the run; it is reported as `pmu50 regress` reports a failure: one
    ``MISMATCH tick=.. signal=.. expected=.. got=..`` line per differing signal, then the first
    divergence with the FIG. 17/18 path of the edge."""

    def build_phase(self):
        self.bfm = ConfigDB().get(self, "", "BFM")
        self.expected_export = _Imp("expected_export", self, self._expected)
        self.actual_export = _Imp("actual_export", self, self._actual)
        self._exp: dict[int, object] = {}
        self._act: dict[int, dict] = {}
        self.compared = 0
        self.failure: dict | None = None
        self.report = ""
        self.failed = Event()

    def _expected(self, p) -> None:
        a = self._act.pop(p.tick, None)
        if a is None:
            self._exp[p.tick] = p
        else:
            self._compare(p, a)

    def _actual(self, s) -> None:
        p = self._exp.pop(s.tick, None)
        if p is None:
            self._act[s.tick] = s.values
        else:
            self._compare(p, s.values)

    def _compare(self, p, got: dict) -> None:
        if self.failure is not None:
            return
        self.compared += 1
        bad = p.outputs.mismatches(got)
        if not bad:
            return
        fmt = lambda g: g if isinstance(g, str) else hex(g)  # noqa: E731
        lines = [
            f"MISMATCH tick={p.tick} signal={s} expected={e:#x} got={fmt(g)}" for s, e, g in bad
        ]
        s, e, g = bad[0]
        self.failure = {
            "kind": "dut",
            "tick": p.tick,
            "signal": f"pmu50.{s}",
            "expected": f"{e:#x}",
            "got": fmt(g),
            "block": "ports",
            "fig": p.fig,
            "detail": f"the DUT diverges from pmu50.Core: {lines[0]} ({len(bad)} MISMATCH lines)",
        }
        self.report = "\n".join(lines) + (
            f"\nFAIL: first divergence at tick {p.tick}: pmu50.{s} expected {e:#x} got {fmt(g)}"
            f" (FIG. path {p.fig}); {len(bad)} signal(s), time {p.tick * self.bfm.period_ns} ns"
        )
        self.logger.error(self.report)
        self.failed.set()

    def check_phase(self):
        if self.failure is not None:
            raise Mismatch(self.report)


class CoverageSubscriber(uvm_subscriber):
    """Functional coverage: ``pmu50.Coverage`` sampled at every edge the predictor saw, on a core
    of its own stepped with the same inputs. ``write_file`` writes the run's coverage.json, the
    format `pmu50 merge` merges."""

    def build_phase(self):
        self.bfm = ConfigDB().get(self, "", "BFM")
        self.core = pmu50.Core(**self.bfm.config)
        self.cov = pmu50.Coverage(self.core)

    def write(self, p):
        if p.tick == 0:
            return
        self.cov.step(self.core, **p.inputs)

    def write_file(self, path: str, run_id: str, verdict: str) -> None:
        self.cov.write(path, run_id, verdict)


class Pmu50Env(uvm_env):
    """Agents, predictor, scoreboard and coverage for the contract ports of one DUT."""

    def build_phase(self):
        self.key = KeyAgent("key", self)
        self.cmp = CmpAgent("cmp", self)
        self.bus = BusAgent("bus", self)
        self.outputs = OutputMonitor("outputs", self)
        self.predictor = Predictor("predictor", self)
        self.scoreboard = Scoreboard("scoreboard", self)
        self.coverage = CoverageSubscriber("coverage", self)

    def connect_phase(self):
        self.key.monitor.ap.connect(self.predictor.key_export)
        self.cmp.monitor.ap.connect(self.predictor.cmp_export)
        self.bus.monitor.ap.connect(self.predictor.bus_export)
        self.predictor.ap.connect(self.scoreboard.expected_export)
        self.predictor.ap.connect(self.coverage.analysis_export)
        self.outputs.ap.connect(self.scoreboard.actual_export)

    def finish(self, run_id: str) -> None:
        """Write the run's coverage.json (``PMU50_COVERAGE``) and failure record
        (``PMU50_FAILURE``, only when the run failed), each when its variable is set."""
        verdict = "fail" if self.scoreboard.failure else "pass"
        path = os.environ.get("PMU50_COVERAGE")
        if path:
            self.coverage.write_file(path, run_id, verdict)
        fpath = os.environ.get("PMU50_FAILURE")
        if fpath and self.scoreboard.failure:
            tmp = fpath + ".tmp"
            with open(tmp, "w", encoding="utf-8") as f:
                json.dump(self.scoreboard.failure, f)
            os.replace(tmp, fpath)
