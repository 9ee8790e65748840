#!/usr/bin/env python3
"""Formal reachability of every bin of the coverage model, on the twin.

The command of pmu50_formal/coverage.py (`hdl/formal/coverage.py --help`); Python puts this
folder, which holds the package, first on the module path.
"""

import sys

from pmu50_formal.coverage import main

if __name__ == "__main__":
    sys.exit(main())
