"""Benchmark: the single-body kernel (the direct drive's packing) against the general packed path on the
same System, CPU, one process (reported, not asserted).

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/single_body.py [out.json]`` (~20 s). The direct drive's
nominal System (:attr:`ddgsa.models.direct_drive.Assembly.kernel`) at its static state, spinning at the
rated 1.26 rad/s:

* one evaluation of the equations (mass matrix, forces, tangents): the single-body kernel's
  ``terms_into`` (:func:`ddgsa.mbs.system.evaluate_terms`) against the general packed assembly
  (:func:`ddgsa.mbs.compiled.evaluate`), each called from Python, best of repeats of one second;
* the non-rotating linearisation: the single-body kernel's ``linearise_spinning`` (with the input and
  spring-force Jacobians the ``linear`` fidelity reads) against :func:`ddgsa.mbs.nonrotating.linearise` on
  the System (without them);
* generalised-alpha steps (20 s at 5 ms, no load, Newton tolerance 1e-6, the ``flexible`` fidelity's): the
  single-body kernel's compiled loop (:func:`ddgsa.mbs.system.integrate`) against the same loop on the
  packed System (:func:`ddgsa.mbs.integrate.genalpha.simulate`), CPU, best of 3;
* the whole ``linear`` 600 s bench-scene run, for scale;
* the largest difference of the two evaluations' ``M, Q, K_t, C_t`` at rest, relative to each one's largest
  entry: 3e-4, all of it the generator torque law's damping between the spin and the elastic coordinates (the
  single-body kernel takes the body's axis as the section's, exact at zero deflection; tests/mbs/test_ffr.py
  holds the two equal to 1e-12 without the torque law and at zero deflection with it).

This is the bench that docs/architecture.md cites for keeping the specialisation.
"""

from __future__ import annotations

import json
import os
import sys
import time
from collections.abc import Callable
from typing import Any

import numpy as np

import ddgsa.models as models
from ddgsa.bench.timing import FULL
from ddgsa.loads import generate
from ddgsa.mbs import genalpha, nonrotating
from ddgsa.mbs.compiled import compile_terms, evaluate, pack
from ddgsa.mbs.linear import linearise_spinning
from ddgsa.mbs.system import evaluate_terms, integrate

SPIN = 1.26
"""Rotor speed [rad/s] of the comparison (rated, 12.1 rpm)."""


def best(fn: Callable[[], Any], seconds: float = 1.0, repeats: int = 3) -> float:
    """Best mean wall time [s] of ``fn()`` over ``repeats`` runs of at least ``seconds`` each."""
    fn()
    out = np.inf
    for _ in range(repeats):
        t, k = time.perf_counter(), 0
        while time.perf_counter() - t < seconds:
            fn()
            k += 1
        out = min(out, (time.perf_counter() - t) / k)
    return float(out)


def cpu_best(fn: Callable[[], Any], repeats: int = 3) -> float:
    """Best CPU time [s] of ``fn()`` over ``repeats`` runs after a warm-up."""
    fn()
    out = np.inf
    for _ in range(repeats):
        t = time.process_time()
        fn()
        out = min(out, time.process_time() - t)
    return float(out)


def main(path: str | None = None) -> dict[str, Any]:
    model = models.get("direct_drive", fidelity="linear")
    asm = model.build(None)
    zero = np.zeros(3)
    q = model.static(asm, zero, zero)
    qd = np.zeros_like(q)
    qd[3] = SPIN
    system = asm.kernel
    packed = pack(system)
    compile_terms(system)
    pairs = [(a - 1, b - 1) for a, b, _ in nonrotating.bending_pairs(system)]     # without the spin angle
    u0 = np.zeros(7)
    u0[6] = SPIN
    rest = np.zeros_like(qd)            # the System's own torque law has set speed 0: compare the two at rest
    general = evaluate(packed, q, rest, 0.0)
    special = evaluate_terms(asm.system, q, rest, zero, zero, 0.0)
    generate(FULL)
    n_t, dt_load, n_sub = 2001, 0.01, 2
    none, spin = np.zeros((n_t, 3)), np.zeros(n_t)
    steps = (n_t - 1) * n_sub
    res = {
        "step_single_body_us": 1e6 / steps * cpu_best(lambda: integrate(asm.system, q, rest, dt_load, n_sub, none, none,
                                                                        spin)),
        "step_general_packed_us": 1e6 / steps * cpu_best(lambda: genalpha.simulate(system, 20.0, dt_load / n_sub, q0=q,
                                                                                   qd0=rest, tol=1e-6, compiled=True)),
        "terms_single_body_us": 1e6 * best(lambda: evaluate_terms(asm.system, q, qd, zero, zero, SPIN)),
        "terms_general_packed_us": 1e6 * best(lambda: evaluate(packed, q, qd, 0.0)),
        "terms_max_rel_difference_at_rest": float(max(np.max(np.abs(g - s)) / np.max(np.abs(g))
                                              for g, s in zip(general[:4], special[:4]))),
        "linearise_single_body_ms": 1e3 * best(lambda: linearise_spinning(asm.system, np.delete(q, 3), SPIN, u0,
                                                                          pairs)),
        "linearise_general_ms": 1e3 * best(lambda: nonrotating.linearise(system, q, qd)),
        "linear_run_600s_ms": 1e3 * best(lambda: model.evaluate(None, FULL), seconds=2.0),
        "load_average": list(os.getloadavg()),
    }
    res["step_ratio"] = res["step_general_packed_us"] / res["step_single_body_us"]
    res["terms_ratio"] = res["terms_general_packed_us"] / res["terms_single_body_us"]
    res["linearise_ratio"] = res["linearise_general_ms"] / res["linearise_single_body_ms"]
    if path:
        with open(path, "w", encoding="utf-8") as fh:
            json.dump(res, fh, indent=1)
    return res


if __name__ == "__main__":
    print(json.dumps(main(sys.argv[1] if len(sys.argv) > 1 else None), indent=1))
