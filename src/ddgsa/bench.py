"""Speed benchmarks: each fidelity of the direct drive against the solve_ivp reference.

Ratios are measured in one run on one machine (reported, never asserted). The reference,
``solve_ivp(Radau, rtol 1e-6)`` on the same equations (flexible model), needs minutes per
simulated minute, so it is timed on the first ``ref_seconds`` of the scene and its cost is
scaled to the full record (cost per simulated second is steady); each fidelity's objective
functions are compared with the reference on that window.
"""

from __future__ import annotations

import platform
import time
from pathlib import Path
from typing import Any

from ddgsa.loads import generate
from ddgsa.loads.scene import Scene

FULL = Scene(wind_speed=11.0, turbulence_intensity=0.12, duration=600.0, seed=1)


def _best(fn: Any, repeat: int = 1) -> tuple[float, Any]:
    best, out = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def speed(ref_seconds: float = 20.0, quickstart: Path | None = None) -> dict[str, Any]:
    """Time a 600 s scene per fidelity and the reference; optionally a whole quickstart study."""
    import ddgsa.models as models

    window = FULL.replace(duration=ref_seconds)
    generate(FULL)                                  # loads are cached: time the drive train only
    generate(window)
    ref_model = models.get("direct_drive", fidelity="flexible", integrator="Radau")
    ref_model.evaluate(None, FULL.replace(duration=1.0))          # compile / load kernels outside the timing
    w_ref, ref = _best(lambda: ref_model.evaluate(None, window))
    ref_full = w_ref * FULL.duration / ref_seconds
    nonzero = [c for c in ref.columns if abs(ref[c].iloc[0]) > 0]
    rows = []
    for fidelity in ("flexible", "rigid", "linear"):
        model = models.get("direct_drive", fidelity=fidelity)
        _, short = _best(lambda: model.evaluate(None, window))          # also compiles / loads numba cache
        wall, _ = _best(lambda: model.evaluate(None, FULL), repeat=2)
        err = max(abs(short[c].iloc[0] / ref[c].iloc[0] - 1) for c in nonzero)
        rows.append({"fidelity": fidelity, "wall_s": round(wall, 4), "speedup_vs_reference": round(ref_full / wall, 1),
                     "max_rel_error": float(f"{err:.3g}"), "time_step_s": model.time_step})
    out: dict[str, Any] = {
        "machine": f"{platform.machine()}, {platform.processor() or 'cpu'}", "python": platform.python_version(),
        "scene": FULL.to_dict(), "reference": {"integrator": "solve_ivp Radau rtol 1e-6 (flexible)",
                                               "timed_seconds": ref_seconds, "wall_s": round(w_ref, 2),
                                               "wall_s_scaled_to_600s": round(ref_full, 1)},
        "fidelities": rows}
    if quickstart is not None:
        import tempfile

        from ddgsa.pipeline import execute
        from ddgsa.runner import EvaluationStore
        from ddgsa.study import load_study

        study = load_study(quickstart)
        with tempfile.TemporaryDirectory() as tmp:
            store = EvaluationStore(Path(tmp) / "evaluations.sqlite")
            wall, res = _best(lambda: execute(study, store, quiet=True))
            store.close()
        out["quickstart"] = {"study": str(quickstart), "wall_s": round(wall, 2),
                             "evaluations": res.provenance["evaluations"]["evaluated"],
                             "jobs": study.spec.run.jobs}
    return out


def format_speed(res: dict[str, Any]) -> str:
    """A plain-text table of :func:`speed`'s figures."""
    ref = res["reference"]
    lines = [f"machine: {res['machine']}, python {res['python']}",
             f"reference: {ref['integrator']}: {ref['wall_s']} s for {ref['timed_seconds']:g} s of scene "
             f"-> {ref['wall_s_scaled_to_600s']} s for 600 s", "",
             f"{'fidelity':10s} {'600 s scene [s]':>16s} {'speed-up':>10s} {'max rel. error':>15s} {'step [s]':>9s}"]
    for r in res["fidelities"]:
        lines.append(f"{r['fidelity']:10s} {r['wall_s']:16.3f} {r['speedup_vs_reference']:9.0f}x "
                     f"{r['max_rel_error']:15.2%} {r['time_step_s']:9.3g}")
    if "quickstart" in res:
        q = res["quickstart"]
        lines += ["", f"quickstart study: {q['evaluations']} model runs in {q['wall_s']} s ({q['jobs']} jobs)"]
    return "\n".join(lines)


#: objective functions of the indirect drive compared in its benchmark rows
INDIRECT_OUTPUTS = ("gear_force_mean", "gear_force_rms", "housing_rx_mean", "housing_rx_rms", "housing_dz_rms",
                    "damage_main", "damage_hss2", "housing_torque_mean")


def indirect_speed(window_seconds: float = 0.5) -> dict[str, Any]:
    """The indirect drive's fidelities, each against its reference, ratios in one run.

    Every fidelity is timed on the full 600 s scene. Errors: ``rigid`` against the kernel's
    ``solve_ivp`` (Radau) on the same rigid system and ``flexible`` against itself at half the
    step, both on the first ``window_seconds`` (the reference needs ~8 min a simulated second; its
    cost is scaled to 600 s); ``linear`` against ``flexible`` on the full scene.
    """
    import ddgsa.models as models

    window = FULL.replace(duration=window_seconds)
    generate(FULL)
    generate(window)

    def run(scene: Scene, **options: Any) -> tuple[float, Any]:
        model = models.get("indirect_drive", **options)
        return _best(lambda: model.evaluate(None, scene).iloc[0])

    def err(a: Any, b: Any) -> float:
        return float(f"{max(abs(a[c] / b[c] - 1) for c in INDIRECT_OUTPUTS if b[c] != 0):.3g}")

    run(window, fidelity="rigid")                       # compile the kernel outside the timings
    w_ref, ref = run(window, fidelity="rigid", integrator="Radau")
    _, rig_window = run(window, fidelity="rigid")
    _, flex_window = run(window, fidelity="flexible")
    _, flex_half = run(window, fidelity="flexible", time_step=0.0025)
    w_rig, _ = run(FULL, fidelity="rigid")
    w_flex, flex = run(FULL, fidelity="flexible")
    w_lin, lin = run(FULL, fidelity="linear")
    ref_full = w_ref * FULL.duration / window_seconds
    rows = [{"fidelity": "rigid", "reference": "rigid, solve_ivp Radau", "wall_s_600s": round(w_rig, 1),
             "speedup_vs_reference": round(ref_full / w_rig, 1), "max_rel_error": err(rig_window, ref)},
            {"fidelity": "flexible", "reference": "flexible, half step", "wall_s_600s": round(w_flex, 1),
             "speedup_vs_reference": None, "max_rel_error": err(flex_window, flex_half)},
            {"fidelity": "linear", "reference": "flexible, generalised-alpha", "wall_s_600s": round(w_lin, 2),
             "speedup_vs_reference": round(w_flex / w_lin, 1), "max_rel_error": err(lin, flex)}]
    return {"machine": f"{platform.machine()}, {platform.processor() or 'cpu'}", "scene": FULL.to_dict(),
            "window_seconds": window_seconds, "reference_wall_s_window": round(w_ref, 1),
            "outputs": list(INDIRECT_OUTPUTS), "fidelities": rows}


def format_indirect_speed(res: dict[str, Any]) -> str:
    """A plain-text table of :func:`indirect_speed`'s figures."""
    lines = [f"indirect drive, machine: {res['machine']}; 600 s scene; rigid and flexible errors on the first "
             f"{res['window_seconds']:g} s; errors on {', '.join(res['outputs'])}", "",
             f"{'fidelity':10s} {'600 s scene [s]':>16s} {'speed-up':>10s} {'max rel. error':>15s}  reference"]
    for r in res["fidelities"]:
        speedup = "" if r["speedup_vs_reference"] is None else f"{r['speedup_vs_reference']:g}x"
        lines.append(f"{r['fidelity']:10s} {r['wall_s_600s']:16.1f} {speedup:>10s} {r['max_rel_error']:15.2%}  "
                     f"{r['reference']}")
    return "\n".join(lines)
