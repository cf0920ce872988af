"""Which answers of a study are confirmed, and what confirming the rest would cost (issue 25).

A (scene, output) pair is **confirmed** when some method's rows of it are all ``trusted`` (value
within the tolerance) or ``rank_confirmed`` (place in the order by ST certain:
:func:`ddgsa.gsa.result.rank_claims`). For a pair that is not, :func:`cost_to_confirm` estimates
the cheapest Saltelli design that would confirm it
(:func:`ddgsa.gsa.salib.saltelli_n_to_confirm`): Saltelli's error bound (bootstrap and half-sample)
scales as ``SALTELLI_K sqrt(ST / N)``, and every row needs an error below the tolerance (trusted)
or below half its distance to zero and to every other row's ST (rank-confirmed), whichever is larger. The distances come from the study's best estimates of
the pair, so the figure is an estimate ("~"), not a promise.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from ddgsa.gsa.salib import saltelli_n_to_confirm

if TYPE_CHECKING:  # pragma: no cover
    from ddgsa.pipeline import StudyResult

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


@dataclass(frozen=True)
class Cost:
    """What confirming one (scene, output) pair would take."""

    n: int                  # Saltelli base sample
    runs: int               # model runs (all realisations)
    seconds: float          # model time at the measured cost per run [s]; NaN when none was measured


def cost_to_confirm(result: "StudyResult", scene: int, output: str, tolerance: float = 0.02,
                    n: int | None = None) -> Cost:
    """Saltelli design that would likely confirm ``output`` in ``scene`` (see the module), or its cost
    with the base sample ``n`` given."""
    t = result.indices
    g = t[(t["scene"] == scene) & (t["output"] == output)]
    st = (g.groupby("parameter", sort=False)["ST"]
          .agg(lambda s: s.dropna().median() if s.notna().any() else np.nan).to_numpy(float))
    n = saltelli_n_to_confirm(st, tolerance) if n is None else n
    study = result.study
    runs = n * (len(st) + 2) * study.spec.scenes.realisations
    sec = per_run_seconds(result)
    return Cost(n, runs, runs * sec)


def per_run_seconds(result: "StudyResult") -> float:
    """Median model time of one stored evaluation [s] (NaN when none recorded one): the median, so
    the first evaluations of a fresh install, which compile the model's kernels (minutes), do not
    make every later run look as slow."""
    ev = result.evaluations
    if "seconds" not in ev or not len(ev):
        return float("nan")
    s = pd.to_numeric(ev["seconds"], errors="coerce")
    return float(s[s > 0].median()) if (s > 0).any() else float("nan")


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
    """How to confirm ``output`` in ``scenes``: the largest Saltelli ``n`` any of them needs, with the
    runs and model time of adding that method to the study, which runs it in every scene (one worker;
    divide by the workers), or the study's ``confirm`` budget (points per scene) that would pay for the
    design where it is needed (:mod:`ddgsa.gsa.escalate`)."""
    costs = [cost_to_confirm(result, s, output, tolerance) for s in scenes]
    n = max(c.n for c in costs)
    every = [cost_to_confirm(result, s, output, tolerance, n=n) for s in sorted(result.indices["scene"].unique())]
    runs = sum(c.runs for c in every)
    sec = sum(c.seconds for c in every)
    per = per_run_seconds(result)
    at = f" at {per:.3g} s per run measured here" if np.isfinite(per) else ""
    points = max(c.runs // max(1, result.study.spec.scenes.realisations) for c in costs)
    salt = f"to confirm it add `saltelli` with n: {n} ({_num(runs)} runs, {duration(sec)} of model time{at})"
    if output in {t.name for t in getattr(result.study, "targets", [])}:
        return salt + " (a target output: `confirm:` escalates the model's own outputs only)"
    stopped = [c["scene"] for c in (getattr(result, "provenance", None) or {}).get("confirm", []) or []
               if c["scene"] in scenes and any(line.startswith("stopped with") for line in c["log"])]
    if stopped:
        return (salt + "; the study's `confirm:` escalation stopped in scene"
                + ("s " if len(stopped) > 1 else " ") + ", ".join(map(str, stopped))
                + ": the pooled PCE's bound did not shrink (a non-smooth output, e.g. a resonance inside the "
                  "ranges) and no Saltelli base within the budget (with its Gaussian-process control variate "
                  "where one fits) was estimated to confirm it; a larger `confirm:` budget helps only as far as "
                  "it pays for that Saltelli design")
    return (salt + f", or `confirm: {{budget: {points}}}` (points per scene; it reuses every run, tries cheaper PCE "
            "points first and stops when confirmed)")


def _num(n: int) -> str:
    """``5 120``: thousands apart by a space."""
    return f"{n:,}".replace(",", " ")
