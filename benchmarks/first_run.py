"""Benchmark: first-run compilation, what a fresh install (and the test run of a fresh clone) waits for;
wall seconds in new processes on a quiet machine (reported, not asserted).

Run: ``python benchmarks/first_run.py [out.json]`` (~2.5 min). Each case runs in three new Python
processes, one after the other, with the same, initially empty, numba cache folder (``NUMBA_CACHE_DIR``):

* ``cold``: the first process compiles every kernel the case reaches and writes the cache;
* ``cached``: a later process loads them from that cache (what every later run of an install does; the
  faster of two processes);
* ``warm``: the case run again in such a process, nothing left to load (the run's own cost; the best of
  three calls).

Cases:

* ``rig_kloss``: the test rig's nonlinear ``kloss`` fidelity, 0.2 s of generalised-alpha at 2e-4 s on the
  packed System from its sag (the general compiled kernel: the assembly, the accelerations, the
  residual Jacobians of its sag, the loop);
* ``direct_drive_flexible``: the direct drive's ``flexible`` fidelity on a 10 s scene at 11 m/s (the
  single-body kernel: statics, loop, outputs; the wind field's generation included).

numba's first compilation is dominated by LLVM optimising and emitting machine code, and numba compiles
a full copy of a function's compiled callees into each compiled caller: docs/kernel.md, "First-run
compilation", says how the kernel keeps those copies few.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time

CASES = {
    "rig_kloss": """
from ddgsa import models
from ddgsa.mbs import genalpha
from ddgsa.models.hss_rig.scenes import RigScene
kloss = models.get("hss_rig", fidelity="kloss")
scene = RigScene(kind="steady", speed_rpm=1500.0, duration=1.2, sample_rate=2000.0, settle=0.2)
p = kloss.resolve({"coupling_asymmetry": 0.0}).iloc[0].to_dict()
def case():
    rig, drive, spin = kloss.build(p, scene)
    q0, qd0 = kloss.initial_state(rig, p)
    genalpha.simulate(rig.system, 0.2, 2e-4, q0=q0, qd0=qd0, output_every=1)
""",
    "direct_drive_flexible": """
from ddgsa import models
from ddgsa.models.base import Scene
model = models.get("direct_drive", fidelity="flexible")
scene = Scene(wind_speed=11.0, turbulence_intensity=0.12, duration=10.0, seed=1)
def case():
    model.simulate(scene)
""",
}

TIMER = """
import time
t0 = time.perf_counter()
{setup}
t1 = time.perf_counter()
case()
t2 = time.perf_counter()
warm = []
for _ in range(3):
    t3 = time.perf_counter()
    case()
    warm.append(time.perf_counter() - t3)
print("TIMES", t1 - t0, t2 - t1, min(warm))
"""


def run_case(code: str, cache: str) -> tuple[float, float, float]:
    """``(setup, first call, best later call)`` wall seconds of ``code`` in a new process using ``cache``."""
    env = {**os.environ, "NUMBA_CACHE_DIR": cache}
    out = subprocess.run([sys.executable, "-c", TIMER.format(setup=code)], env=env, capture_output=True,
                         text=True, check=True)
    line = next(ln for ln in out.stdout.splitlines() if ln.startswith("TIMES"))
    setup, first, second = (float(x) for x in line.split()[1:])
    return setup, first, second


def main(out_path: str | None = None) -> dict:
    """Cold, cached and warm seconds of every case (see the module)."""
    results: dict = {"load_before": os.getloadavg()[0], "cpus": os.cpu_count(), "cases": {}}
    for name, code in CASES.items():
        with tempfile.TemporaryDirectory(prefix="numba_cache_") as cache:
            t = time.perf_counter()
            setup_c, cold, _ = run_case(code, cache)
            later = [run_case(code, cache) for _ in range(2)]
            results["cases"][name] = {"cold_s": round(setup_c + cold, 2),
                                      "cached_s": round(min(s + f for s, f, _ in later), 2),
                                      "warm_s": round(min(w for _, _, w in later), 3),
                                      "wall_s": round(time.perf_counter() - t, 1)}
        print(name, results["cases"][name], flush=True)
    results["load_after"] = os.getloadavg()[0]
    if out_path:
        with open(out_path, "w") as fh:
            json.dump(results, fh, indent=2)
    return results


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
