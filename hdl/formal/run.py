#!/usr/bin/env python3
"""Formal property kit of the PMU 50 core: every property proven unbounded, each one not vacuous.

The command of pmu50_formal/kit.py (`hdl/formal/run.py --help`); Python puts this folder,
which holds the package, first on the module path.
"""

import sys

from pmu50_formal.kit import main

if __name__ == "__main__":
    sys.exit(main())
