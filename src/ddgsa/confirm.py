"""Which answers of a study are confirmed, and what confirming the rest would cost (issue 25).

A (scene, output) pair is **confirmed** when some method's rows of it are all ``trusted`` (value
within the tolerance) or ``rank_confirmed`` (place in the order by ST certain:
:func:`ddgsa.gsa.result.rank_claims`). For a pair that is not, :func:`cost_to_confirm` estimates
the cheapest Saltelli design that would confirm it: Saltelli's error bound (bootstrap and
half-sample, :mod:`ddgsa.gsa.salib`) scales as ``SALTELLI_K sqrt(ST / N)``, and every row needs an
error below the tolerance (trusted) or below half its distance to zero and to every other row's
ST (rank-confirmed), whichever is larger. The distances come from the study's best estimates of
the pair, so the figure is an estimate ("~"), not a promise.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

if TYPE_CHECKING:  # pragma: no cover
    from ddgsa.pipeline import StudyResult

SALTELLI_K = 3.3
"""Saltelli's error bound on a total index ``ST`` is about ``SALTELLI_K sqrt(ST / N)``: the 75th
percentile of ``bound sqrt(N / ST)`` over the 3 360 Saltelli rows of ``results/trust_calibration``
(median 2.8, steady from ST = 0.001 to 1; rows with ST < 0.001 are taken at 0.001, which
overstates their bound tenfold)."""
MIN_N, MAX_N = 64, 1 << 20


def pair_status(indices: pd.DataFrame) -> pd.DataFrame:
    """Per (scene, output): ``confirmed`` (some method has every row trusted or rank-confirmed),
    ``trusted`` (some method has every row trusted), ``method`` (the first such, else the method
    with the most confirmed rows) and ``unconfirmed`` (that method's rows neither)."""
    t = indices.assign(ok=indices["trusted"].astype(bool) | indices["rank_confirmed"].astype(bool))
    rows = []
    for (scene, out), g in t.groupby(["scene", "output"], sort=False):
        per = g.groupby("method", sort=False).agg(trusted=("trusted", "all"), confirmed=("ok", "all"),
                                                  n_ok=("ok", "sum"), n=("ok", "size"))
        best = per.sort_values(["trusted", "confirmed", "n_ok"], ascending=False, kind="stable").index[0]
        rows.append({"scene": scene, "output": out, "confirmed": bool(per["confirmed"].any()),
                     "trusted": bool(per["trusted"].any()), "method": best,
                     "unconfirmed": int(per.loc[best, "n"] - per.loc[best, "n_ok"])})
    return pd.DataFrame(rows, columns=["scene", "output", "confirmed", "trusted", "method", "unconfirmed"])


def saltelli_n_to_confirm(st: np.ndarray, tolerance: float) -> int:
    """Smallest power-of-two Saltelli base sample whose typical error bound ``SALTELLI_K sqrt(ST / N)``
    confirms every row of an output with total indices ``st``: below ``tolerance`` (trusted) or
    below half the row's distance to zero and to every other row (rank-confirmed), whichever is
    larger. A NaN row is taken as ST = 1 needing the tolerance."""
    st = np.asarray(st, dtype=float)
    known = np.where(np.isfinite(st), np.clip(st, 0.0, 1.0), np.nan)
    need = np.full(len(st), tolerance)
    for i in range(len(st)):
        if np.isfinite(known[i]):
            gap = min(known[i], np.nanmin(np.abs(known[i] - np.delete(known, i)), initial=np.inf))
            need[i] = max(tolerance, gap / 2.0)
    level = np.where(np.isfinite(known), np.maximum(known, 1e-3), 1.0)
    n = float(np.max(SALTELLI_K ** 2 * level / need ** 2))
    return int(min(MAX_N, max(MIN_N, 1 << int(np.ceil(np.log2(n))))))


@dataclass(frozen=True)
class Cost:
    """What confirming one (scene, output) pair would take."""

    n: int                  # Saltelli base sample
    runs: int               # model runs (all realisations)
    seconds: float          # model time at the measured cost per run [s]; NaN when none was measured


def cost_to_confirm(result: "StudyResult", scene: int, output: str, tolerance: float = 0.02) -> Cost:
    """Saltelli design that would likely confirm ``output`` in ``scene`` (see the module)."""
    t = result.indices
    g = t[(t["scene"] == scene) & (t["output"] == output)]
    st = (g.groupby("parameter", sort=False)["ST"]
          .agg(lambda s: s.dropna().median() if s.notna().any() else np.nan).to_numpy(float))
    n = saltelli_n_to_confirm(st, tolerance)
    study = result.study
    runs = n * (len(st) + 2) * study.spec.scenes.realisations
    sec = per_run_seconds(result)
    return Cost(n, runs, runs * sec)


def per_run_seconds(result: "StudyResult") -> float:
    """Mean model time of one stored evaluation [s] (NaN when none recorded one)."""
    ev = result.evaluations
    if "seconds" not in ev or not len(ev):
        return float("nan")
    s = pd.to_numeric(ev["seconds"], errors="coerce")
    return float(s[s > 0].mean()) if (s > 0).any() else float("nan")


def duration(seconds: float) -> str:
    """``~40 s``, ``~9 min``, ``~3.2 h`` (``time unknown`` for NaN)."""
    if not np.isfinite(seconds):
        return "time unknown (no measured cost per run)"
    if seconds < 90:
        return f"~{seconds:.0f} s"
    if seconds < 5400:
        return f"~{seconds / 60:.0f} min"
    return f"~{seconds / 3600:.1f} h"


def advice(result: "StudyResult", output: str, scenes: list[int], tolerance: float = 0.02) -> str:
    """How to confirm ``output`` in ``scenes``: the largest Saltelli ``n`` any of them needs and the
    runs and model time of all of them (one worker; divide by the workers), or the study's
    ``confirm`` budget (points per scene) that would pay for that design (:mod:`ddgsa.gsa.escalate`)."""
    costs = [cost_to_confirm(result, s, output, tolerance) for s in scenes]
    n = max(c.n for c in costs)
    runs = sum(c.runs for c in costs)
    sec = sum(c.seconds for c in costs)
    per = per_run_seconds(result)
    at = f" at {per:.3g} s per run measured here" if np.isfinite(per) else ""
    points = max(c.runs // max(1, result.study.spec.scenes.realisations) for c in costs)
    return (f"to confirm it add `saltelli` with n: {n} ({_num(runs)} runs, {duration(sec)} of model time{at}), "
            f"or `confirm: {{budget: {points}}}` (points per scene; it reuses every run, tries cheaper PCE points "
            "first and stops when confirmed)")


def _num(n: int) -> str:
    """``5 120``: thousands apart by a space."""
    return f"{n:,}".replace(",", " ")
