"""Which answers of a study are confirmed, and what confirming the rest would cost (issues 25, 51).

Each (scene, output) pair gets one **verdict** (:func:`confirmation_table`, written as
``confirmation.csv``; the console, the exit code, ``summary.md``, the HTML report and the NetCDF export
all read it):

* ``nothing to rank`` -- the output spreads over the design by no more than its declared resolution
  (:attr:`ddgsa.models.base.ModelOutput.resolution`, a sensor's noise) or the numerical floor
  (:func:`ddgsa.gsa.result.below_resolution`): whatever ranking the methods give is a ranking of noise;
* ``trusted`` -- some method's rows of it are all within the tolerance;
* ``rank-confirmed`` / ``confirmed tie`` -- some method's rows are all trusted or have a certain place in
  the order by ST (:func:`ddgsa.gsa.result.rank_structure`), with at least one confirmed tie for the latter;
* ``screened`` -- only a screening method (HSIC) ran for the pair: its dependence tests say which parameters
  are screened in at the study's level (``ranking``), a test's answer, not a confirmed ranking; the next step
  says how to rank them (no exit 3: the study asked a screening);
* ``unconfirmed`` -- none of these, with the cheapest next step and its cost.

For a pair that is not confirmed, :func:`cost_to_confirm` estimates
the cheapest Saltelli design that would confirm it
(:func:`ddgsa.gsa.salib.saltelli_n_to_confirm`): Saltelli's error bound (bootstrap and half-sample)
scales as ``SALTELLI_K sqrt(ST / N)``, and every row needs an error below the tolerance (trusted)
or below half its distance to zero and to every other row's ST (rank-confirmed), whichever is larger, each
pair's need weighed by the bound on its difference the scene's Saltelli stage measured where one ran
(:func:`ddgsa.gsa.result.difference_ratio`), and at least twice a Saltelli base that ran in the scene (plain or
the escalation's controlled one) and left the pair unconfirmed. The distances come from the study's best estimates of
the pair, so the figure is an estimate ("~"), not a promise. Where the study's ``confirm:`` escalation ended with the pair
unconfirmed, its cost rule's last ask -- the controlled Saltelli base its Gaussian-process control variate and
the measured bounds on the ST differences make cheaper (:func:`budget_cost`) -- is the other step: the
budget that pays for it. The advice leads with the cheaper of the two, and ``next_runs`` is its cost.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.gsa.base import sobol_rows
from ddgsa.gsa.escalate import MAX_BUDGET, SALTELLI_NAME
from ddgsa.gsa.result import CONFIRMED, CONSTANT_CV, VERDICTS, below_resolution, difference_ratio
from ddgsa.gsa.salib import MAX_N, saltelli_n_to_confirm

if TYPE_CHECKING:  # pragma: no cover
    from ddgsa.execute.kinds.common import StudyResult

CROSSCHECKS = ("pooled_pce", "given_data_s1")
"""Methods a study runs without being asked (cross-checks at zero extra runs): they may confirm a pair,
but an unconfirmed pair is shown with a requested method's estimate."""
CONFIRMATION_COLUMNS = ["scene", "output", "verdict", "method", "runs", "std", "resolution", "ranking",
                        "next_step", "next_runs", "next_seconds"]

SCREEN_RANK_TIME = "5 min"
"""The ``confirm:`` time a ``screened`` pair's next step names: the escalation from M-DRM ranks a seed study's
screened outputs in seconds (the direct drive's three at 256 runs, 11 s)."""

SHAPLEY_ADVICE = ("the inputs are correlated, so only method shapley applies: raise its n_o (outer draws per "
                  "subset; the bootstrap half-width falls as 1/sqrt(n_o)) and n_v")
"""What a correlated study's unconfirmed output needs (the independent-input methods would be refused)."""


def pair_status(indices: pd.DataFrame) -> pd.DataFrame:
    """Per (scene, output): ``confirmed`` (some method has every row trusted or rank-confirmed),
    ``trusted`` (some method has every row trusted), ``method`` (the first such, else the method
    with the most confirmed rows, then a requested one, the most finite indices, the most runs), ``unconfirmed``
    (that method's rows neither) and ``tie`` (that method's ranking has a confirmed tie)."""
    t = indices.assign(ok=indices["trusted"].astype(bool) | indices["rank_confirmed"].astype(bool),
                       tie=indices["rank"].astype(str).str.endswith("=") if "rank" in indices else False,
                       finite=np.isfinite(indices["ST"].to_numpy(float)) if "ST" in indices else True,
                       runs=indices["n_evals"] if "n_evals" in indices else 0,
                       asked=~indices["method"].isin(CROSSCHECKS))
    rows = []
    for (scene, out), g in t.groupby(["scene", "output"], sort=False):
        per = g.groupby("method", sort=False).agg(trusted=("trusted", "all"), confirmed=("ok", "all"),
                                                  n_ok=("ok", "sum"), n=("ok", "size"), tie=("tie", "any"),
                                                  finite=("finite", "sum"), runs=("runs", "max"), asked=("asked", "all"))
        # unconfirmed everywhere: the method with the most rows placed, a requested one, then the most finite
        # indices, then the most runs
        best = per.sort_values(["trusted", "confirmed", "n_ok", "asked", "finite", "runs"], ascending=False,
                               kind="stable").index[0]
        rows.append({"scene": scene, "output": out, "confirmed": bool(per["confirmed"].any()),
                     "trusted": bool(per["trusted"].any()), "method": best,
                     "unconfirmed": int(per.loc[best, "n"] - per.loc[best, "n_ok"]),
                     "tie": bool(per.loc[best, "tie"])})
    return pd.DataFrame(rows, columns=["scene", "output", "confirmed", "trusted", "method", "unconfirmed", "tie"])


def ranking_text(g: pd.DataFrame) -> str:
    """One method's confirmed ranking of one output as text: ``a > b = c > {d, e negligible}`` (rows
    not placed: ``?``)."""
    placed = g[g["rank"].astype(str).str.len() > 0] if "rank" in g else g.iloc[:0]
    if not len(placed):
        return ""
    parts, neg = [], []
    for rank, h in placed.groupby("rank", sort=False):
        if rank == "negligible":
            neg = list(h["parameter"])
            continue
        parts.append((int(str(rank).rstrip("=")), " = ".join(h["parameter"])))
    text = " > ".join(p for _, p in sorted(parts))
    if len(placed) < len(g):
        text += (" > " if text else "") + "? (" + ", ".join(g[g["rank"].astype(str).str.len() == 0]["parameter"]) + ")"
    if neg:
        text += (" > " if text else "") + "{" + ", ".join(neg) + " negligible}"
    return text


def verdicts(result: "StudyResult") -> pd.DataFrame:
    """The result's verdict table: the one the pipeline set (``result.confirmation``), else made now
    (:func:`confirmation_table`; a result built by hand)."""
    table = getattr(result, "confirmation", None)
    return table if isinstance(table, pd.DataFrame) else confirmation_table(result)


def confirmation_table(result: "StudyResult") -> pd.DataFrame:
    """The study's verdict per (scene, output) (see the module; columns :data:`CONFIRMATION_COLUMNS`).

    ``runs`` are the model runs of the method that gave the verdict (all realisations); ``std`` the
    output's standard deviation over the scene's design [output unit] against its ``resolution``;
    ``ranking`` the confirmed order by ST (:func:`ranking_text`); for an unconfirmed pair
    ``next_step`` says the cheapest way to confirm it, ``next_runs`` and ``next_seconds`` the cost of
    the step it leads with (:func:`leading_cost`: a plain Saltelli design added to the study, in every scene,
    or the ``confirm:`` budget or time that pays for the design the escalation asked for; model runs, model
    time on one worker [s], NaN when no run time was measured)."""

    sobol = sobol_rows(result.indices)
    info = result.study.output_declarations() if hasattr(result.study, "output_declarations") else {}
    mom = result.moments
    moments = {} if mom is None or not len(mom) else \
        {(int(r.scene), str(r.output)): (float(r.std), float(r.mean)) for r in mom.itertuples()}
    real = max(1, int(result.study.spec.scenes.realisations))
    rows = _screened(result, sobol, info, moments, real)
    if not len(sobol):
        return pd.DataFrame(rows, columns=CONFIRMATION_COLUMNS)
    tol = study_tolerance(result)
    for r in pair_status(sobol).itertuples():
        scene, out = int(r.scene), str(r.output)
        res = info[out].resolution if out in info else 0.0
        std, mean = moments.get((scene, out), (np.nan, np.nan))
        g = sobol[(sobol["scene"] == r.scene) & (sobol["output"] == out) & (sobol["method"] == r.method)]
        row = {"scene": scene, "output": out, "method": r.method, "std": std, "resolution": res,
               "runs": int(g["n_evals"].max()) * real if "n_evals" in g and len(g) else 0,
               "ranking": ranking_text(g), "next_step": "", "next_runs": 0, "next_seconds": 0.0}
        if below_resolution(std, mean, res):
            row.update(verdict="nothing to rank", ranking="", next_step=_nothing_to_rank(std, mean, res))
        elif r.trusted:
            row["verdict"] = "trusted"
        elif r.confirmed:
            row["verdict"] = "confirmed tie" if r.tie else "rank-confirmed"
        else:
            _, runs, sec, grow, leads = leading_cost(result, out, [scene], tol)
            if leads:                                     # the advice leads with the cheaper step
                assert grow is not None
                runs, sec = grow.runs, grow.seconds
            row.update(verdict="unconfirmed", next_step=next_step(result, out, [scene], tol),
                       next_runs=runs, next_seconds=sec)
        rows.append(row)
    return pd.DataFrame(rows, columns=CONFIRMATION_COLUMNS)


def _screened(result: "StudyResult", sobol: pd.DataFrame, info: dict[str, Any],
              moments: dict[tuple[int, str], tuple[float, float]], real: int) -> list[dict[str, Any]]:
    """The rows of the (scene, output) pairs only a screening method (no Sobol indices: HSIC) estimated:
    ``screened``, the parameters it screens in (``p_value`` under the method's level) as the ``ranking``, or
    ``nothing to rank`` where the output spreads within its resolution."""
    ind = result.indices
    if not len(ind) or "p_value" not in ind:
        return []
    known = set(zip(sobol["scene"].astype(int), sobol["output"].astype(str)))
    screen = ind.drop(index=sobol.index)
    screen = screen[screen["p_value"].notna()]
    sec = per_run_seconds(result)
    per_run = f"{sec:.3g} s a run measured here" if np.isfinite(sec) else "no run time measured here"
    rows = []
    for (scene, out), g in screen.groupby(["scene", "output"], sort=False):
        if (int(scene), str(out)) in known:
            continue
        method = str(g["method"].iloc[0])
        g = g[g["method"] == method].sort_values("p_value", kind="stable")
        res = info[out].resolution if out in info else 0.0
        std, mean = moments.get((int(scene), str(out)), (np.nan, np.nan))
        row = {"scene": int(scene), "output": str(out), "method": method, "std": std, "resolution": res,
               "runs": int(g["n_evals"].max()) * real if "n_evals" in g else 0, "next_runs": 0, "next_seconds": 0.0}
        if below_resolution(std, mean, res):
            row.update(verdict="nothing to rank", ranking="", next_step=_nothing_to_rank(std, mean, res))
        else:
            inside = g[g["screened_in"].astype(float) > 0]["parameter"].astype(str).tolist() \
                if "screened_in" in g else []
            row.update(verdict="screened",
                       ranking=("screened in: " + ", ".join(inside)) if inside else "none screened in",
                       next_step=(f"to rank the parameters by their share of the variance (Sobol indices, with "
                                  f"their own verdicts), add `confirm: {{time: {SCREEN_RANK_TIME}}}` to the study "
                                  f"or run it with `--confirm-time '{SCREEN_RANK_TIME}'`: the escalation starts "
                                  f"from M-DRM and spends "
                                  f"runs only where its rows are not yet trusted ({per_run}); {method}'s "
                                  f"p-values test dependence, and a parameter not screened in is absence of "
                                  f"evidence, not a confirmed independence"))
        rows.append(row)
    return rows


def _nothing_to_rank(std: float, mean: float, resolution: float) -> str:
    """The next step of a pair with nothing to rank: none, with the spread against the resolution it is within."""
    return (f"none: the output spreads by {std:.3g} over the design, within its resolution "
            f"{max(resolution, CONSTANT_CV * abs(mean)):.3g}")


def verdict_counts(table: pd.DataFrame, verdicts: tuple[str, ...] = VERDICTS) -> tuple[list[str], int]:
    """``(["3 trusted", "1 nothing to rank"], confirmed)``: each of ``verdicts`` the table holds, with its
    count, in :data:`~ddgsa.gsa.result.VERDICTS` order, and the number of confirmed pairs. The one count the
    console, ``summary.md`` and the HTML report say."""
    count = table["verdict"].value_counts()
    return ([f"{int(count[v])} {v}" for v in verdicts if count.get(v, 0)],
            int(table["verdict"].isin(CONFIRMED).sum()))


def verdict_line(table: pd.DataFrame) -> str:
    """The verdicts in one line: ``verdicts: 3 trusted, 1 nothing to rank; 4 of 4 (scene, output) pairs confirmed``."""
    parts, done = verdict_counts(table)
    return "verdicts: " + ", ".join(parts) + f"; {done} of {len(table)} (scene, output) pairs confirmed"


def study_tolerance(result: "StudyResult") -> float:
    """The study's trust tolerance (the smallest of its methods')."""
    tols = [res.options.get("tolerance") for _, res in result.results]
    return min([t for t in tols if t is not None], default=0.02)


def next_step(result: "StudyResult", output: str, scenes: list[int], tolerance: float) -> str:
    """The cheapest way to confirm ``output`` in ``scenes``: rerun failed evaluations when the indices
    were refused over them, Shapley's sizes for correlated inputs, else :func:`advice`."""
    d = result.diagnostics
    names = set(d[(d["output"].isin([output, None]) | d["output"].isna()) & (d["severity"] == "untrusted")
                  & d["scene"].isin(scenes)]["name"]) if len(d) else set()
    failed = (getattr(result, "provenance", None) or {}).get("failures", [])
    if failed and "nonfinite_values" in names:
        return ("no design confirms indices over failed evaluations: remove their cause (narrow the "
                "parameters' support away from the failing points; `ddgsa validate` checks the support), "
                "or, where the model was at fault and is fixed, run them again with `ddgsa run --retry-failed`")
    if getattr(getattr(result.study, "space", None), "dependent", False):
        return SHAPLEY_ADVICE
    return advice(result, output, scenes, tolerance)


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
    if n is None:            # a Saltelli base that ran there and left the pair unconfirmed: at least twice it
        ran = [int(res.options["n"]) for res in _saltelli_results(result, scene) if "n" in res.options]
        n = saltelli_n_to_confirm(st, tolerance, pair_ratio=_pair_ratio(result, scene, output, len(st)),
                                  ran=max(ran, default=0))
    study = result.study
    runs = n * (len(st) + 2) * study.spec.scenes.realisations
    sec = per_run_seconds(result)
    return Cost(n, runs, runs * sec)


def _pair_ratio(result: "StudyResult", scene: int, output: str, d: int) -> NDArray[np.float64] | None:
    """The bounds on ``output``'s ST differences over the sums of its rows' bounds (d, d) that the scene's
    largest Saltelli result measured (:func:`ddgsa.gsa.result.difference_ratio`, plain or controlled: both bound
    their differences by the same rule), or None (no such result, or a result loaded without its extras)."""
    salt = [res for res in _scene_results(result, scene)
            if "rank_diff_error" in res.extras and (res.indices["output"] == output).sum() == d]
    if not salt:
        return None
    return difference_ratio(max(salt, key=lambda r: r.n_evals), output)


def _scene_results(result: "StudyResult", scene: int) -> list[Any]:
    """The method results (:class:`~ddgsa.gsa.result.SobolResult`) the study made in ``scene`` (none for a
    result without them, e.g. one loaded from its folder)."""
    return [res for ps, res in getattr(result, "results", None) or [] if getattr(ps, "index", None) == scene]


def _saltelli_results(result: "StudyResult", scene: int) -> list[Any]:
    """``scene``'s Saltelli results: a plain ``saltelli`` method's and the ``confirm:`` escalation's."""
    return [res for res in _scene_results(result, scene) if res.method in ("saltelli", SALTELLI_NAME)]


@dataclass(frozen=True)
class BudgetCost:
    """What growing a study's ``confirm:`` budget (or its time) would take to confirm one output
    (:func:`budget_cost`)."""

    budget: int             # the budget (points per scene) that pays for the design in every scene named
    n: int                  # the controlled Saltelli base the escalation's cost rule asks for there
    runs: int               # new model runs at most (all realisations, every scene the budget lets escalate)
    seconds: float          # their model time at the measured cost per run [s]; NaN when none was measured
    scenes: tuple[int, ...]  # the scenes whose escalation asked for the design
    timed: bool             # the escalation stopped at its time limit there: more time, not a budget, runs it
    control: bool           # the cost rule counted on Gaussian-process control variates fitted there
    keyed: tuple[tuple[Any, int], ...] | None = None   # a per-value budget: every key with its (raised) budget

    @property
    def possible(self) -> bool:
        """Whether a study may set the step: the budget within :data:`~ddgsa.gsa.escalate.MAX_BUDGET` and the
        base below the cost rule's cap :data:`~ddgsa.gsa.salib.MAX_N` (at the cap it estimates nothing)."""
        return self.budget <= MAX_BUDGET and self.n < MAX_N


def budget_cost(result: "StudyResult", output: str, scenes: list[int]) -> BudgetCost | None:
    """The ``confirm:`` budget that would pay for the design the study's escalation asked for at its end to
    confirm ``output`` in ``scenes`` (:meth:`ddgsa.gsa.escalate.Escalation.asks`, in ``provenance.json``: its
    controlled Saltelli base, weighed by its control variate and the latest stage's bounds on the ST
    differences), with the new runs and their model time; None where the escalation asked nothing for it (no
    ``confirm:``, a provenance written before it recorded its asks, or the output confirmed there).

    A scene's escalation plans one design for every output it left unconfirmed: the budget pays for the
    scene's largest ask. A budget that is one number is every scene's: raised, each scene whose escalation
    ended with an output unconfirmed may spend up to it, and the runs count all of those (an upper bound: a
    scene stops once confirmed). A per-value budget (``budget: {startup: 16384, steady: 62000}``) is raised
    only at the keys of ``scenes`` (``keyed``), and the runs count the scenes under those keys. Where the
    escalation stopped at its time limit (``confirm: {time}``) the runs are those of the asked design in
    ``scenes``: more time, not points, runs it."""
    every = list((getattr(result, "provenance", None) or {}).get("confirm", []) or [])
    entries = [c for c in every if c.get("scene") in scenes and output in (c.get("asks") or {})]
    if not entries:
        return None
    need = {int(c["scene"]): max(int(a["points"]) for a in c["asks"].values()) for c in entries}
    n = max(int(a["n"]) for c in entries for a in c["asks"].values())
    timed = any(_stopped_by_time(c) for c in entries)
    real = max(1, int(result.study.spec.scenes.realisations))
    spec = result.study.spec
    given = getattr(getattr(spec, "confirm", None), "budget", None)
    # a budget that is one number is one key (None) that every scene shares
    grid = spec.scenes.grid() if isinstance(given, dict) else []
    key = {int(c["scene"]): spec.budget_key(grid[int(c["scene"])]) if grid else None for c in every}
    raised = {k: int(v) for k, v in given.items()} if isinstance(given, dict) else {None: 0}
    for c in entries:
        s = int(c["scene"])
        raised[key[s]] = max(raised[key[s]], int(c["spent"]) + need[s])
    budget = max(raised[key[s]] for s in need)
    grown = {key[s] for s in need}                      # the keys raised: the other scenes keep their budgets
    points = sum(need.values()) if timed else sum(max(0, raised[key[int(c["scene"])]] - int(c["spent"]))
                                                  for c in every if c.get("asks") and key[int(c["scene"])] in grown)
    keyed = tuple(raised.items()) if isinstance(given, dict) else None
    runs = points * real
    control = any(bool(a.get("control", True)) for c in entries for a in c["asks"].values())
    return BudgetCost(budget=budget, n=n, runs=runs, seconds=runs * per_run_seconds(result),
                      scenes=tuple(sorted(need)), timed=timed, control=control, keyed=keyed)


def _stopped_by_time(entry: dict[str, Any]) -> bool:
    """Whether a scene's escalation (provenance ``confirm`` entry) stopped at its time limit: its
    ``stopped_by_time`` flag (provenance written before the flag has none; its log line says it)."""
    if "stopped_by_time" in entry:
        return bool(entry["stopped_by_time"])
    return any(str(line).startswith("stopped by the time budget") for line in entry.get("log") or [])


def leading_cost(result: "StudyResult", output: str, scenes: list[int], tolerance: float = 0.02
                 ) -> tuple[int, int, float, BudgetCost | None, bool]:
    """The two ways to confirm ``output`` in ``scenes`` and which leads: ``(n, runs, seconds, grow,
    grow_leads)``, the plain Saltelli base with the runs and model time of adding it to the study
    (:func:`study_cost`), the ``confirm:`` step (:func:`budget_cost`, or None) and whether it leads: possible
    and fewer runs. ``confirmation.csv``'s ``next_runs`` and the advice's order both read it."""
    n, runs, sec = study_cost(result, output, scenes, tolerance)
    grow = budget_cost(result, output, scenes)
    return n, runs, sec, grow, grow is not None and grow.possible and grow.runs < runs


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


def study_cost(result: "StudyResult", output: str, scenes: list[int], tolerance: float = 0.02
               ) -> tuple[int, int, float]:
    """The Saltelli base ``n`` the worst of ``scenes`` needs to confirm ``output``, and the runs and
    model time [s] of adding it to the study, which runs it in every scene (:func:`advice` says it)."""
    n = max(cost_to_confirm(result, s, output, tolerance).n for s in scenes)
    every = [cost_to_confirm(result, s, output, tolerance, n=n) for s in sorted(result.indices["scene"].unique())]
    return n, sum(c.runs for c in every), sum(c.seconds for c in every)


def advice(result: "StudyResult", output: str, scenes: list[int], tolerance: float = 0.02) -> str:
    """How to confirm ``output`` in ``scenes``: the largest Saltelli ``n`` any of them needs, with the
    runs and model time of adding that method to the study, which runs it in every scene (one worker;
    divide by the workers), or the study's ``confirm`` budget (points per scene) that would pay for the
    design where it is needed (:mod:`ddgsa.gsa.escalate`): where the escalation ended with ``output``
    unconfirmed, the budget for the design its cost rule asked for then (:func:`budget_cost`; more time where
    its time limit stopped it), the cheaper of the two first (:func:`leading_cost`); with a caution where a
    Saltelli stage found the total index's terms too heavy-tailed for any size (:func:`tail_caution`)."""
    return _advice(result, output, scenes, tolerance) + tail_caution(result, output, scenes)


INFINITE_MEAN_SHAPE = 1.0
"""A tail shape (:func:`ddgsa.gsa.trust.pareto_shape`) at or above which the fitted Pareto tail has no finite
mean: a Saltelli estimate of a total index whose terms have it does not settle as the base grows."""


def tail_caution(result: "StudyResult", output: str, scenes: list[int]) -> str:
    """``"; caution: ..."`` where the largest Saltelli result (plain or the escalation's) of a scene of ``scenes``
    flagged ``output``'s total-index terms ``heavy_tail`` with a shape at or above :data:`INFINITE_MEAN_SHAPE`
    (the largest such shape, its parameter and the base it was measured at), else ``""``: the cost rule's sizes
    assume a mean that settles (on ``paper_a_subsystem``'s coast-down the shapes stayed at 1.1-3.5 from
    N = 2 048 to 8 192 while nothing confirmed). A smaller design's flag is not read: a larger one measured the
    tail again (the steady housing's 1.54 at N = 2 048 was 0.70 at 8 192)."""
    worst: tuple[float, str, int, int] | None = None
    for scene in scenes:
        salt = _saltelli_results(result, scene)
        if not salt:
            continue
        res = max(salt, key=lambda r: r.n_evals)
        for d in res.diagnostics:
            if d.name == "heavy_tail" and d.output == output and d.value is not None \
                    and d.value >= INFINITE_MEAN_SHAPE and (worst is None or d.value > worst[0]):
                worst = (float(d.value), str(d.parameter), int(res.options.get("n", 0)), scene)
    if worst is None:
        return ""
    shape, parameter, n, scene = worst
    at = f" at N = {n}" if n else ""
    return (f"; caution: in scene {scene} the total index's terms of {parameter} have a heavy tail (Pareto shape "
            f"{shape:.2g} >= {INFINITE_MEAN_SHAPE:g}{at}: a few rare runs carry it, and such a mean need not "
            "settle), so larger designs may not confirm it; narrower ranges that keep the rare points out (on the "
            "rig, the critical speed away from the operating speed) are the other lever")


def _advice(result: "StudyResult", output: str, scenes: list[int], tolerance: float) -> str:
    """:func:`advice` without its caution."""
    costs = [cost_to_confirm(result, s, output, tolerance) for s in scenes]
    n, runs, sec, grow, grow_leads = leading_cost(result, output, scenes, tolerance)
    per = per_run_seconds(result)
    at = f" at {per:.3g} s per run measured here" if np.isfinite(per) else ""
    points = max(c.runs // max(1, result.study.spec.scenes.realisations) for c in costs)
    salt = f"to confirm it add `saltelli` with n: {n} ({_num(runs)} runs, {duration(sec)} of model time{at})"
    if output in {t.name for t in getattr(result.study, "targets", [])}:
        return salt + " (a target output: `confirm:` escalates the model's own outputs only)"
    if grow is not None:
        where = ("scene " if len(grow.scenes) == 1 else "scenes ") + ", ".join(map(str, grow.scenes))
        design = f"a controlled Saltelli base N = {grow.n}"
        cheaper = ("; the Gaussian-process control variates and the measured bounds on the ST differences make it "
                   "cheaper than a plain design" if grow.control else
                   "; the measured bounds on the ST differences make it cheaper than a plain design")
        if grow.timed:
            larger = (f"give the study's `confirm:` more time (`time:`, or `ddgsa run --confirm-time`): its escalation "
                      f"stopped at its time limit in {where}, where its cost rule asks for {design} "
                      f"({_num(grow.runs)} new runs, {duration(grow.seconds)} of model time{at}{cheaper}; "
                      "every run is reused)")
        else:
            raised = grow.budget if grow.keyed is None else "{" + ", ".join(f"{k}: {v}" for k, v in grow.keyed) + "}"
            larger = (f"raise the study's `confirm: {{budget: {raised}}}` (points per scene): where its "
                      f"escalation ended in {where}, its cost rule asks for {design} (up to {_num(grow.runs)} new "
                      f"runs over the scenes left unconfirmed, {duration(grow.seconds)} of model time{at}{cheaper}; "
                      "every run is reused)")
        if grow.budget > MAX_BUDGET:
            larger += f", past the largest budget a study may set ({_num(MAX_BUDGET)})"
        elif grow.n >= MAX_N:
            larger += f", the cost rule's largest base (N = {MAX_N}): it estimates no base that confirms it"
        rest = sorted(set(scenes) - set(grow.scenes))
        if rest:
            larger += (f"; in scene{'s' if len(rest) > 1 else ''} {', '.join(map(str, rest))} the escalation asked "
                       "nothing for it")
        return (larger + "; or " + salt) if grow_leads else (salt + "; or " + larger)
    stopped = [c["scene"] for c in (getattr(result, "provenance", None) or {}).get("confirm", []) or []
               if c["scene"] in scenes and any(line.startswith("stopped with") for line in c["log"])]
    if stopped:
        return (salt + "; the study's `confirm:` escalation stopped in scene"
                + ("s " if len(stopped) > 1 else " ") + ", ".join(map(str, stopped))
                + ": the pooled PCE's bound did not shrink (a non-smooth output, e.g. a resonance inside the "
                  "ranges) and no Saltelli base within the budget (with its Gaussian-process control variate "
                  "where one fits) was estimated to confirm it; a larger `confirm:` budget helps only as far as "
                  "it pays for that Saltelli design")
    where = f"points per scene, in each of {len(scenes)} scenes" if len(scenes) > 1 else "points per scene"
    return (salt + f", or `confirm: {{budget: {points}}}` ({where}; it reuses every run, tries cheaper PCE "
            "points first and stops when confirmed)")


def _num(n: int) -> str:
    """``5 120``: thousands apart by a space."""
    return f"{n:,}".replace(",", " ")
