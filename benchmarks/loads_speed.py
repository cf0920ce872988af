"""Benchmark: wall time of one 600 s load realisation (reported, not asserted).

Run: ``python benchmarks/loads_speed.py``. The first call compiles the numba rotor loop
(cached on disk afterwards) and is reported separately.
"""

from __future__ import annotations

import time

from ddgsa.loads import Scene, _generate
from ddgsa.loads.rotor import NREL5MW


def main() -> None:
    t0 = time.perf_counter()
    _generate(Scene(wind_speed=8.0, duration=10.0, seed=99), NREL5MW)
    print(f"first call (compile or load numba cache): {time.perf_counter() - t0:.2f} s")
    for v in (6.0, 11.0, 18.0):
        times = []
        for seed in range(3):
            t0 = time.perf_counter()
            _generate(Scene(wind_speed=v, turbulence_intensity=0.12, duration=600.0, dt=0.05, seed=seed), NREL5MW)
            times.append(time.perf_counter() - t0)
        print(f"V = {v:4.1f} m/s: 600 s realisation (81-point field, 12 000 steps): "
              f"best {min(times):.3f} s, mean {sum(times) / len(times):.3f} s")


if __name__ == "__main__":
    main()
