"""The test rig's speed rows (``ddgsa bench rig``): each ``linear`` path against the nonlinear rig, in one run.

For the scenes of ``studies/paper_a_subsystem.yaml`` (steady state at 1500 rpm synchronous, the
direct-on-line start-up, the coast-down; 1.2 s records at 2 kHz) the ``linear`` fidelity (steady:
harmonic solution of the rig linearised in non-rotating coordinates; start-up and coast-down: the
speed sweep) is timed at the nominal point and compared with the reference path of the same
model, the nonlinear ``kloss`` rig integrated by generalised-alpha at its accuracy step
(:data:`REFERENCE_STEP`), on the study's outputs (:data:`OUTPUTS`). The error is the largest
relative difference over those outputs, for the nominal jaw coupling and for an axisymmetric one
(``coupling_asymmetry = 0``): the linear fidelity builds the coupling at its mean stiffness and
carries its anisotropy as a load (:mod:`ddgsa.models.hss_rig.faults`), so the first error holds
that stated bias, the second the linearisation's alone. Times are the best of repeats (CPU and wall), as in
:mod:`ddgsa.bench.speed`; the direct drive's Radau reference of the same run turns them into
fractions (CPU) of one reference 600 s simulation.
"""

from __future__ import annotations

import math
import os
import platform
from typing import Any

from ddgsa.bench.timing import FULL, timed
from ddgsa.loads import generate

OUTPUTS = ("peak_disk_y", "order1x_disk_y", "peak_housing_1_y", "rms_housing_1_y", "order1x_housing_1_y",
           "rms_housing_2_z", "peak_motor_torque", "rms_motor_current")
"""The outputs of ``studies/paper_a_subsystem.yaml`` the errors are taken on."""
REFERENCE_STEP = 2.5e-4
"""Generalised-alpha step of the nonlinear ``kloss`` reference [s] (160 steps a revolution at 1500 rpm; the
step-halving and Radau checks of docs/hss_rig.md give 1e-3 at 5e-4 s, second order)."""
LINEAR_STEP = 5e-4
"""The speed sweep's step of ``paper_a_subsystem`` [s]."""


def direct_drive_reference(ref_seconds: float = 20.0) -> tuple[float, float]:
    """Wall and CPU seconds of the direct drive's reference 600 s simulation (``solve_ivp`` Radau on
    the flexible equations, :data:`ddgsa.bench.timing.FULL`), timed on ``ref_seconds`` and scaled, as
    :mod:`ddgsa.bench.speed` does: the yardstick the speed issues state study costs in."""
    import ddgsa.models as models

    window = FULL.replace(duration=ref_seconds)
    generate(window)
    model = models.get("direct_drive", fidelity="flexible", integrator="Radau")
    model.evaluate(None, FULL.replace(duration=1.0))
    wall, cpu, _ = timed(lambda: model.evaluate(None, window), min_total=0.0, max_repeat=1)
    return wall * FULL.duration / ref_seconds, cpu * FULL.duration / ref_seconds


def rig_speed(quick: bool = False) -> dict[str, Any]:
    """Each rig scene's ``linear`` time and error against the nonlinear ``kloss`` rig (see the module),
    and each time as a fraction of the direct drive's reference 600 s simulation of the same run.

    ``quick``: 0.6 s records and a 1 s reference window (checks the bench itself; the figures are
    not the study's).
    """
    import ddgsa.models as models
    from ddgsa.models.hss_rig.scenes import RigScene

    ref_wall_600s, ref_cpu_600s = direct_drive_reference(1.0 if quick else 20.0)

    duration = 0.6 if quick else 1.2
    linear = models.get("hss_rig", fidelity="linear", time_step=LINEAR_STEP)
    nonlinear = models.get("hss_rig", fidelity="kloss", time_step=REFERENCE_STEP)
    rows = []
    for kind in ("steady", "startup", "coastdown"):
        scene = RigScene(kind, speed_rpm=1500.0, duration=duration, sample_rate=2000.0, settle=0.2, seed=1)
        linear.evaluate(None, scene)                          # numba kernels loaded outside the timing
        for coupling, point in (("jaw (nominal)", None), ("axisymmetric", {"coupling_asymmetry": 0.0})):
            wall, cpu, out = timed(lambda: linear.evaluate(point, scene).iloc[0])
            ref_wall, ref_cpu, ref = timed(lambda: nonlinear.evaluate(point, scene).iloc[0], min_total=0.0,
                                           max_repeat=1)
            errors = {o: abs(out[o] / ref[o] - 1.0) for o in OUTPUTS if ref[o] != 0.0}
            worst = max(errors, key=lambda o: errors[o] if math.isfinite(errors[o]) else math.inf)
            row = {"scene": kind, "coupling": coupling, "duration_s": duration, "linear_wall_s": wall,
                   "linear_cpu_s": cpu, "reference": f"kloss, generalised-alpha {REFERENCE_STEP:g} s",
                   "reference_wall_s": ref_wall, "reference_cpu_s": ref_cpu, "speedup_cpu": ref_cpu / cpu,
                   "max_rel_error": errors[worst], "worst_output": worst,
                   "errors": {o: float(e) for o, e in errors.items()}}
            row["fraction_of_600s_reference"] = cpu / ref_cpu_600s         # CPU: a loaded machine inflates wall
            rows.append(row)
    return {"machine": f"{platform.machine()}, {os.cpu_count()} cores", "python": platform.python_version(),
            "quick": quick, "outputs": list(OUTPUTS), "direct_drive_reference_600s_wall_s": ref_wall_600s,
            "direct_drive_reference_600s_cpu_s": ref_cpu_600s, "rows": rows, "load_average": list(os.getloadavg())}


def format_rig_speed(res: dict[str, Any]) -> str:
    """A plain-text table of :func:`rig_speed`'s figures."""
    lines = [f"hss_rig, machine: {res['machine']}, load average {res['load_average']}"
             + (" (QUICK: 0.6 s records)" if res["quick"] else "")
             + f"; errors on {', '.join(res['outputs'])}; direct drive's Radau reference 600 s simulation "
             f"{res['direct_drive_reference_600s_cpu_s']:.1f} s CPU ({res['direct_drive_reference_600s_wall_s']:.1f} s wall)", "",
             f"{'scene':10s} {'coupling':14s} {'linear CPU [s]':>15s} {'kloss CPU [s]':>14s} {'speed-up':>9s} {'max rel. error':>15s}"
             f" {'of 600 s ref.':>14s}  worst output (fraction: CPU)"]
    for r in res["rows"]:
        lines.append(f"{r['scene']:10s} {r['coupling']:14s} {r['linear_cpu_s']:15.3f} {r['reference_cpu_s']:14.2f} "
                     f"{r['speedup_cpu']:8.1f}x {r['max_rel_error']:15.2%} "
                     f"{r['fraction_of_600s_reference']:14.4f}  {r['worst_output']}")
    return "\n".join(lines)


BLOCK_POINTS = 16
"""Points of a timed block (the runner hands ``run: {batch_size}`` points a call; the rig studies ask 8)."""


def block_speed(points: int = BLOCK_POINTS, reference_points: int = 4, quick: bool = False,
                kind: str = "steady") -> dict[str, Any]:
    """The rig's ``kind`` scene (``steady``, ``startup``, ``coastdown``) per run: the block path
    (:mod:`ddgsa.models.hss_rig.steady_block`, :mod:`ddgsa.models.hss_rig.sweep_block`) against the per-point
    ``linear`` path (:meth:`ddgsa.models.base.Model._evaluate_block`'s loop), timed in one run, both paths run
    once before (their kernels loaded or compiled outside the timing).

    Points are uniform draws of ``paper_a_subsystem``'s space, new ones for every timed repeat (so no
    per-parameter cache of the rig's sag or shaft modes is reused); the block path is repeated for at
    least :data:`~ddgsa.bench.timing.MIN_TIMED_S` and its best run kept, the per-point path is timed once
    on ``reference_points`` points. ``quick``: 0.6 s steady records (a start-up's or coast-down's record keeps
    its 1.2 s: in 0.6 s a start-up turns fewer than the 8 revolutions the ball-pass bands' 0.25 orders need,
    and every point fails on both paths). Returns CPU and wall seconds a run, the
    ratio (CPU) and, on the reference points, the largest relative difference of the two paths' outputs where
    it exceeds the output's declared resolution (issue 46's criterion: 1 % or the resolution; 0 where every
    difference is within its output's resolution) and how many outputs differ by more than that.
    """
    import numpy as np
    import pandas as pd

    import ddgsa.models as models
    from ddgsa.bench.timing import RIG_STUDY
    from ddgsa.models.base import Model
    from ddgsa.study.spec import load_study

    study = load_study(RIG_STUDY)
    model = models.get("hss_rig", fidelity="linear", time_step=LINEAR_STEP)
    scene = model._scene({"kind": kind, "speed_rpm": 1500.0, "duration": 0.6 if quick and kind == "steady" else 1.2,
                          "sample_rate": 2000.0, "settle": 0.2, "seed": 1})
    draws = iter(range(1_000_000))

    def block_of(n: int) -> pd.DataFrame:
        u = np.random.default_rng(next(draws)).random((n, study.space.dim))
        return model.resolve(pd.DataFrame(study.space.ppf(u), columns=list(study.space.names)))

    model._evaluate_block(block_of(2), scene)                # kernels loaded (or compiled) outside the timing:
    Model._evaluate_block(model, block_of(1), scene)          # both paths' (a fresh install's first per-point
                                                              # start-up compiled for 6 s a point, read as 264x)
    ref_params = block_of(reference_points)
    ref_wall, ref_cpu, ref = timed(lambda: Model._evaluate_block(model, ref_params, scene), min_total=0.0, max_repeat=1)
    fast = model._evaluate_block(ref_params, scene)
    wall, cpu, out = timed(lambda: model._evaluate_block(block_of(points), scene))
    resolution = np.array([next(o.resolution for o in model.outputs if str(o) == c) for c in ref.columns])
    gap = np.abs(fast.to_numpy() - ref.to_numpy())
    beyond = gap > resolution
    with np.errstate(divide="ignore", invalid="ignore"):
        diff = float(np.max(np.where(beyond, gap / np.abs(ref.to_numpy()), 0.0), initial=0.0))
    return {"kind": kind, "points": points, "reference_points": reference_points, "block_cpu_s_per_run": cpu / points,
            "block_wall_s_per_run": wall / points, "per_point_cpu_s_per_run": ref_cpu / reference_points,
            "per_point_wall_s_per_run": ref_wall / reference_points,
            "speedup_cpu": (ref_cpu / reference_points) / (cpu / points), "max_rel_difference": diff,
            "outputs_beyond_resolution": int(beyond.any(axis=0).sum()), "outputs": int(ref.shape[1]),
            "block_points": int(out.attrs["block_points"]), "load_average": list(os.getloadavg())}
