"""The UVM tests: one virtual sequence each, on the env of the DUT at ``cocotb.top``.

Knobs (environment variables, set by test_uvm.py or by hand):
  PMU50_SEED, PMU50_CYCLES   RandomTest: seed and length; RegressSeedTest: the regression seed
  PMU50_VEC                  VectorTest: the vector file to replay
  PMU50_SCENARIO             ScenarioTest: the scenario file (its vectors are made by
                             `pmu50 vectors`)
  PMU50_MAX_TICKS            vector, scenario and regress-seed tests: only the first N ticks
                             (0: all)
  PMU50_CLOCK_US             clock period of the model, microseconds (default 10)
  PMU50_COVERAGE             the run's coverage.json (merge format of `pmu50 merge`), run id
                             PMU50_RUN_ID
  PMU50_FAILURE              where a failing run writes its first divergence as JSON (the fields
                             of a `pmu50 regress` failure: kind, tick, signal, expected, got,
                             block, fig, detail)
"""

from __future__ import annotations

import os

import cocotb
from cocotb.triggers import Timer, select
from pyuvm import ConfigDB, uvm_test

from .bfm import Pmu50Bfm
from .env import Mismatch, Pmu50Env
from .sequences import (
    ItemListSeq,
    Pmu50VirtualSeq,
    RandomSeq,
    RegisterSeq,
    RegressSeedSeq,
    ScenarioSeq,
    VectorSeq,
)


def _env_int(name: str, default: int) -> int:
    v = os.environ.get(name)
    if v is None or v == "":
        return default
    try:
        return int(v)
    except ValueError:
        raise ValueError(f"{name}={v!r}: expected a whole number") from None


class Pmu50Test(uvm_test):
    """Reset, then the virtual sequence of ``sequence()`` on the three agents; the scoreboard
    ends the run at the first divergent tick."""

    def sequence(self) -> Pmu50VirtualSeq:
        raise NotImplementedError

    def build_phase(self):
        self.bfm = Pmu50Bfm(cocotb.top, _env_int("PMU50_CLOCK_US", 10))
        ConfigDB().set(None, "*", "BFM", self.bfm)
        self.env = Pmu50Env("env", self)
        self.error: str | None = None

    def end_of_elaboration_phase(self):
        b = self.bfm
        given = ", ".join(f"{k}={v}" for k, v in b.params.items()) or "none"
        self.logger.info(
            f"DUT parameters: {given}; model defaults for: {', '.join(b.defaulted) or 'none'}"
        )

    async def run_phase(self):
        self.raise_objection()
        seq = self.sequence()
        subs = seq.make(self.bfm.hdl_parameters)
        ticks = seq.ticks
        self.ticks = ticks
        self.env.predictor.expect_stimulus(*(ItemListSeq.items_of(x) for x in subs))
        await self.bfm.reset_and_start()
        self.env.predictor.reset_state()
        sb = self.env.scoreboard
        limit = Timer((ticks + 4) * self.bfm.period_ns, unit="ns")
        ended, _ = await select(seq.run(self.env, subs), sb.failed.wait(), limit)
        if ended == 2 and sb.failure is None:
            self.error = f"the sequence did not end within {ticks + 4} ticks"
        elif sb.failure is None and sb.compared != ticks + 1:
            self.error = (
                f"the scoreboard compared {sb.compared} ticks, expected {ticks + 1} "
                f"(tick 0 and {ticks} edges)"
            )
        run_id = os.environ.get("PMU50_RUN_ID") or f"uvm/{seq.get_name()}"
        self.env.finish(run_id)
        if sb.failure is None and self.error is None:
            hit, reachable = self.env.coverage.cov.closure()
            self.logger.info(
                f"PASS {seq.get_name()}: {ticks} ticks, 23 outputs each; "
                f"coverage {hit} of {reachable} reachable bins"
            )
        self.drop_objection()

    def check_phase(self):
        if self.error:
            raise AssertionError(self.error)
        if self.env.predictor.stimulus_error:
            raise AssertionError(self.env.predictor.stimulus_error)


class RandomTest(Pmu50Test):
    def sequence(self):
        return RandomSeq(_env_int("PMU50_SEED", 1), _env_int("PMU50_CYCLES", 3000))


class VectorTest(Pmu50Test):
    def sequence(self):
        path = os.environ.get("PMU50_VEC")
        if not path:
            raise ValueError("VectorTest needs PMU50_VEC, the vector file to replay")
        return VectorSeq(path, _env_int("PMU50_MAX_TICKS", 0))


class ScenarioTest(Pmu50Test):
    def sequence(self):
        path = os.environ.get("PMU50_SCENARIO")
        if not path:
            raise ValueError("ScenarioTest needs PMU50_SCENARIO, the scenario file")
        return ScenarioSeq(path, _env_int("PMU50_MAX_TICKS", 0))


class RegressSeedTest(Pmu50Test):
    def sequence(self):
        return RegressSeedSeq(_env_int("PMU50_SEED", 1), _env_int("PMU50_MAX_TICKS", 0))


class RegisterTest(Pmu50Test):
    def sequence(self):
        return RegisterSeq()


__all__ = [
    "Mismatch",
    "Pmu50Test",
    "RandomTest",
    "RegisterTest",
    "RegressSeedTest",
    "ScenarioTest",
    "VectorTest",
]
