"""Cost of sampling the coverage model from Python, per edge (docs/python.md, "Coverage").

    PYTHONPATH=python/tests target/venv/bin/python benches/python_coverage.py [EDGES]

(after `make python`; python/tests holds the shared stimulus).

Steps a core EDGES times (default 100 000) with the shared stimulus of
python/tests/test_coverage.py, four ways: Core.step, Coverage.step, Core.step_traced and
Coverage.step_traced, and prints the best of 5 runs of each in ns per edge.
"""

from __future__ import annotations

import sys
import time

from test_coverage import CONFIG, stimulus

import pmu50


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 100_000
    rows = list(stimulus(n))

    def steps(method: str, sampled: bool):
        """Step a fresh core through the stimulus with `method` of the core, or of a coverage
        sampling it (which takes the core first); the same call shape either way."""

        def run():
            c = pmu50.Core(**CONFIG)
            obj, args = (pmu50.Coverage(c), (c,)) if sampled else (c, ())
            step = getattr(obj, method)
            for r in rows:
                step(*args, **r)

        return run

    for method in ("step", "step_traced"):
        for sampled in (False, True):
            name = f"{'Coverage' if sampled else 'Core'}.{method}"
            f = steps(method, sampled)
            best = float("inf")
            for _ in range(5):
                t0 = time.perf_counter()
                f()
                best = min(best, time.perf_counter() - t0)
            print(f"{name:22s} {best / n * 1e9:7.0f} ns/edge")


if __name__ == "__main__":
    main()
