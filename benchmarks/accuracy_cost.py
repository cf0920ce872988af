"""Benchmark: Sobol-index error against cost for every method (reported, not asserted).

Run: ``ddgsa bench accuracy`` (same as ``python benchmarks/accuracy_cost.py``); writes
``results/accuracy_cost/`` (CSV + charts, about 15 minutes on 2 cores; ``--quick``: one minute).
See :mod:`ddgsa.bench.accuracy_cost` for what is compared against what.
"""

from __future__ import annotations

import sys

from ddgsa.cli import main

if __name__ == "__main__":
    sys.exit(main(["bench", "accuracy", *sys.argv[1:]]))
