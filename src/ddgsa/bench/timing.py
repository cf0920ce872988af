"""The benches' shared yardsticks: the reference scene, the rig's study and how a fast path is timed
(:mod:`ddgsa.bench.speed` and :mod:`ddgsa.bench.rig` both take them from here, so neither imports the other
for them)."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ddgsa.loads.scene import Scene

FULL = Scene(wind_speed=11.0, turbulence_intensity=0.12, duration=600.0, seed=1)
"""The reference scene: 600 s of turbulent wind at rated speed."""
MIN_TIMED_S = 1.0
"""A fast path is repeated until it has run this long [s] and its best run kept."""
REPO = Path(__file__).resolve().parents[3]
RIG_STUDY = REPO / "studies" / "paper_a_subsystem.yaml"


def timed(fn: Callable[[], Any], min_total: float = MIN_TIMED_S, max_repeat: int = 50) -> tuple[float, float, Any]:
    """Best wall and CPU seconds of ``fn()`` over repeats until ``min_total`` seconds have run."""
    best_wall, best_cpu, out, total, n = float("inf"), float("inf"), None, 0.0, 0
    while (total < min_total or n < 2) and n < max_repeat:
        w0, c0 = time.perf_counter(), time.process_time()
        out = fn()
        wall, cpu = time.perf_counter() - w0, time.process_time() - c0
        best_wall, best_cpu, total, n = min(best_wall, wall), min(best_cpu, cpu), total + wall, n + 1
        if wall >= min_total:           # one run of a slow path is enough
            break
    return best_wall, best_cpu, out
