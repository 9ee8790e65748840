"""Cost of sampling the coverage model from Python, per edge (docs/python.md, "Coverage").

    target/venv/bin/python benches/python_coverage.py [EDGES]     (after `make python`)

Steps a core EDGES times (default 100 000) with the shared stimulus of
python/tests/test_coverage.py, four ways: Core.step, Coverage.step, Core.step_traced and
Coverage.step_traced, and prints the best of 5 runs of each in ns per edge.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python" / "tests"))

import pmu50  # noqa: E402
from test_coverage import CONFIG, stimulus  # noqa: E402


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 100_000
    rows = list(stimulus(n))

    def core_step():
        c = pmu50.Core(**CONFIG)
        for r in rows:
            c.step(**r)

    def cov_step():
        c = pmu50.Core(**CONFIG)
        cov = pmu50.Coverage(c)
        for r in rows:
            cov.step(c, **r)

    def core_traced():
        c = pmu50.Core(**CONFIG)
        for r in rows:
            c.step_traced(**r)

    def cov_traced():
        c = pmu50.Core(**CONFIG)
        cov = pmu50.Coverage(c)
        for r in rows:
            cov.step_traced(c, **r)

    for name, f in (("Core.step", core_step), ("Coverage.step", cov_step), ("Core.step_traced", core_traced), ("Coverage.step_traced", cov_traced)):
        best = float("inf")
        for _ in range(5):
            t0 = time.perf_counter()
            f()
            best = min(best, time.perf_counter() - t0)
        print(f"{name:22s} {best / n * 1e9:7.0f} ns/edge")


if __name__ == "__main__":
    main()
