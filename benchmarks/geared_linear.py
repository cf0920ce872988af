"""Benchmark: the geared drive's ``linear`` 600 s run against its ``flexible`` reference, CPU, one process
(reported, not asserted).

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/geared_linear.py [out.json]`` (~1 min). The ``linear`` and
``flexible`` rows of ``ddgsa bench indirect`` without its Radau window (10-30 min a simulated second): the
bench scene (11 m/s, I 0.12, 600 s, seed 1), ``linear`` best of 8 after a warm-up, ``flexible``
(generalised-alpha, 5 ms) once, and the relative error of every bench output.
"""

from __future__ import annotations

import json
import os
import sys
import time
from typing import Any

import ddgsa.models as models
from ddgsa.bench.speed import INDIRECT_OUTPUTS
from ddgsa.bench.timing import FULL
from ddgsa.loads import generate


def cpu(fn: Any) -> tuple[float, Any]:
    """CPU seconds of ``fn()`` and its value."""
    t = time.process_time()
    out = fn()
    return time.process_time() - t, out


def main(path: str | None = None) -> dict[str, Any]:
    generate(FULL)
    lin = models.get("indirect_drive", fidelity="linear")
    flex = models.get("indirect_drive", fidelity="flexible")
    _, low = cpu(lambda: lin.evaluate(None, FULL).iloc[0])          # compile or load the kernels
    best = min(cpu(lambda: lin.evaluate(None, FULL).iloc[0])[0] for _ in range(8))
    seconds, ref = cpu(lambda: flex.evaluate(None, FULL).iloc[0])
    errors = {c: float(abs(low[c] / ref[c] - 1)) for c in INDIRECT_OUTPUTS if ref[c] != 0}
    res = {"scene": FULL.to_dict(), "linear_cpu_s_best_of_8": best, "flexible_cpu_s": seconds,
           "speedup_cpu": seconds / best, "errors": errors, "max_rel_error": max(errors.values()),
           "worst_output": max(errors, key=errors.__getitem__), "load_average": list(os.getloadavg())}
    print(json.dumps(res, indent=1))
    if path:
        with open(path, "w") as fh:
            json.dump(res, fh, indent=1)
    return res


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
