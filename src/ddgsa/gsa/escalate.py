"""Confirm on request: add runs until every row is confirmed or a budget is spent (issue 25).

A (scene's) set of results *confirms* an output when one of them has every row of it
``trusted`` or ``rank_confirmed`` (:func:`ddgsa.gsa.result.rank_claims`). :class:`Escalation`
starts from every point a scene already has (any method's design, at its true input values) and
the results already computed there, and while some output is unconfirmed and budget is left it
chooses the next design by what the pooled data say is cheapest:

* **more PCE points** -- scrambled Sobol' points of the input distribution (one sequence, its
  prefixes nest), after which the sparse PCE is refitted on *every* point (:mod:`ddgsa.gsa.pooled`).
  Its degree is the highest (<= :data:`MAX_ORDER`) the points and :data:`MAX_ENTRIES` allow. Its
  bound shrinks as ``n^-r``: the points needed are ``n (e / e_need)^(1/r)`` with ``e`` the worst
  row's current bound and ``e_need`` the bound that would confirm it (below the tolerance, or
  below half its distance to zero and to every other row, whichever is larger). The rate ``r`` is
  measured from the last two fits (clipped to [:data:`MIN_RATE`, 1]; 1/2, Monte Carlo's, before
  there are two), so an expansion that converges slowly (a kink, a jump) soon looks expensive. A
  step at most doubles the pool; then the estimate is made again from the refitted expansion.
* **a Saltelli base** -- the power of two whose typical bound ``SALTELLI_K sqrt(ST / N)``
  confirms every unconfirmed output (:func:`ddgsa.gsa.salib.saltelli_n_to_confirm`, from the best
  current ST), or, after a Saltelli stage that did not confirm, twice its base. Saltelli designs of
  one seed nest: a larger base reuses every point of the smaller (and of the study's own Saltelli
  design when the seeds agree). For independent inputs the stage is estimated with a
  Gaussian-process **control variate** per unconfirmed output (:mod:`ddgsa.gsa.control`), fitted on
  the pooled points that are not Saltelli rows and fixed from the first Saltelli stage on (so the
  estimate stays unbiased): the bound then goes as ``sqrt(min(ST, 2 e^2) / N)``, ``e`` the
  process's leave-one-out error, and the base needed shrinks accordingly. Until a Saltelli stage
  runs, the processes are refitted whenever the pool has doubled, and the pool is doubled with PCE
  points (the pilot) while it is below half the planned Saltelli stage (:meth:`Escalation._pilot_step`).

The cheaper of the two estimates runs; when Saltelli's does not fit, the largest base that does runs
if it is at least an eighth of the base estimated for the cheapest unconfirmed output
(:data:`SHORT_BASE`); when neither fits, the rest of the budget goes to PCE points (they always refit the pooled expansion) and the escalation stops -- unless the
rate has been measured and even the cheapest unconfirmed output needs more than :data:`HOPELESS`
times what is left: then it stops at once and says so (an output with a resonance inside the
parameter ranges, whose bound does not shrink, would otherwise take the whole budget for nothing). Only the
newest pooled expansion and the newest Saltelli stage are reported (methods ``confirm_pce`` and
``confirm_saltelli``): earlier stages are superseded, never shopped among.

Where an unconfirmed output's control variate is a process of a power of it (a peak,
:class:`~ddgsa.gsa.control.TransformedSurrogate`), every other pilot step is of **focus points**:
points where that surrogate is least certain (:meth:`Escalation._focus_points`). They train the
processes only (whose leave-one-out errors are taken over the other points): the pooled expansion
is fitted without them, since its leave-one-out bound estimates the error under the input
distribution only from points drawn from it.

Where the model declares **control features** (:meth:`ddgsa.models.base.Model.control_features`, e.g. the
rig's lateral natural frequencies against the 1x order), the escalation is given them with the values
(``features``, and with every :meth:`Escalation.feed`) and each control may take them as inputs
(:class:`~ddgsa.gsa.control.FeatureSurrogate`), kept only where its leave-one-out error is the smaller.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ddgsa.errors import MethodError
from ddgsa.gsa.base import Design, as_value_matrix, evaluate, get_method
from ddgsa.gsa.pooled import pooled_pce
from ddgsa.gsa.result import SobolResult, difference_ratio, need_per_row, nothing_to_rank
from ddgsa.gsa.salib import multi_groups, saltelli_n_to_confirm
from ddgsa.gsa.trust import DEFAULT_TOLERANCE
from ddgsa.gsa.space import ParameterSpace

PCE_NAME, SALTELLI_NAME = "confirm_pce", "confirm_saltelli"
FOCUS_CANDIDATES = 8
"""Candidates per focus point: the pilot's focus points are the top eighth of a Sobol' sample by the
control variates' uncertainty (:meth:`Escalation._focus_points`)."""
MIN_STEP = 32
"""Fewest points a PCE stage adds (smaller steps cost a refit for little change)."""
MIN_RATE = 0.05
"""Slowest convergence rate of the pooled expansion's bound assumed (a bound that did not shrink)."""
HOPELESS = 4.0
"""Stop before the budget is spent when, with the expansion's convergence rate measured (two fits)
and no Saltelli base within what is left, even the cheapest unconfirmed output needs more than this
many times the runs left: they would be spent without confirming anything."""
SHORT_BASE = 8
"""When the Saltelli base the estimate asks for does not fit in what is left but one at least
``1 / SHORT_BASE`` of the base estimated for the cheapest unconfirmed output does (and the pooled
expansion looks no cheaper), that base runs rather than the escalation stopping: the estimate is a
typical bound, some outputs may be confirmed by it, and the budget is the user's to spend."""
MAX_ORDER = 10
"""Highest degree of the escalation's pooled expansion (``auto`` fits up to 9 by regression)."""
MAX_BUDGET = 1_000_000
"""Largest ``confirm: budget`` a study may set (points per scene; :class:`ddgsa.study.spec.ConfirmSpec`)."""
TIME_ONLY = MAX_BUDGET + 1
"""The point budget of an escalation given only a wall-clock time (``confirm: {time}``): a cap, not a
budget the user set (one above any a study may set), so the log counts the runs spent without it."""
MAX_ENTRIES = 1_000_000
"""Largest regression matrix (points x terms) of a refit: its least-angle path costs seconds."""


def confirming_methods(results: Sequence[SobolResult], outputs: Sequence[str],
                       ranking: tuple[float | None, float | None] = (None, None)) -> dict[str, str | None]:
    """Per output: the method of the first result with every row of it ``trusted``, else of the first with
    every row ``trusted`` or ``rank_confirmed`` -- the preference of ``confirmation.csv``
    (:func:`ddgsa.execute.confirm.pair_status`) -- or None (rank claims made with ``ranking`` = (tie margin,
    negligible floor), :meth:`SobolResult.rerank`; None: the tolerance)."""
    trusted: dict[str, str] = {}
    placed: dict[str, str] = {}
    for res in results:
        t = res.rerank(*ranking).indices if ranking != (None, None) else res.indices
        rows = t.assign(ok=t["trusted"].astype(bool) | t["rank_confirmed"].astype(bool),
                        tr=t["trusted"].astype(bool)).groupby("output")[["tr", "ok"]].all()
        for o, r in rows.iterrows():
            if r["tr"]:
                trusted.setdefault(str(o), res.method)
            if r["ok"]:
                placed.setdefault(str(o), res.method)
    return {o: trusted.get(o, placed.get(o)) for o in outputs}


def confirmed_outputs(results: Sequence[SobolResult], outputs: Sequence[str],
                      ranking: tuple[float | None, float | None] = (None, None)) -> dict[str, bool]:
    """Per output: some result has every row of it ``trusted`` or ``rank_confirmed``
    (:func:`confirming_methods`)."""
    return {o: m is not None for o, m in confirming_methods(results, outputs, ranking).items()}


@dataclass
class Escalation:
    """The escalation of one scene (see the module): ``start()``, then ``feed(values)`` until None.

    Parameters
    ----------
    space : ParameterSpace
    outputs : list of str
    budget : int
        Most new points this escalation may ask for (each point is one model run per realisation).
    x, y : arrays (n, d) and (n, k)
        Every point the scene already has and its (aggregated) values; NaN rows are failed points.
    results : list of SobolResult
        The results already computed in the scene (they may already confirm outputs).
    tolerance : float
    seed : int
        Seed of the PCE points' Sobol' sequence (``seed + 2``) and of the Saltelli designs (``seed + 1``).
    saltelli : (Design, values), optional
        A Saltelli design the scene already ran; a larger base of the same seed extends it.
    ranking : (float or None, float or None)
        The study's tie margin and negligible floor [-] (``ranking:``; None: the tolerance).
    resolution : dict, optional
        Each output's declared resolution [its unit] (:attr:`ddgsa.models.base.ModelOutput.resolution`):
        an output that spreads no more over the pool has nothing to rank and is not escalated.
    features : array (n, m), optional
        The model's control features at the points ``x`` (:meth:`ddgsa.models.base.Model.control_features`,
        recorded with the runs): the control variates may take them as inputs
        (:func:`ddgsa.gsa.control.fit_control`), each keeping whichever control has the smaller
        leave-one-out error. :meth:`feed` then takes them with every stage's values.
    """

    space: ParameterSpace
    outputs: list[str]
    budget: int
    x: NDArray[np.float64]
    y: NDArray[np.float64]
    results: list[SobolResult] = field(default_factory=list)
    tolerance: float = DEFAULT_TOLERANCE
    seed: int = 0
    saltelli: tuple[Design, NDArray[np.float64]] | None = None
    resolution: dict[str, float] = field(default_factory=dict)
    ranking: tuple[float | None, float | None] = (None, None)
    features: NDArray[np.float64] | None = None
    spent: int = 0
    log: list[str] = field(default_factory=list)
    pce: SobolResult | None = None
    salt: SobolResult | None = None

    def __post_init__(self) -> None:
        if isinstance(self.budget, bool) or not isinstance(self.budget, (int, np.integer)) or self.budget < 0:
            raise MethodError(f"confirm: 'budget' must be a whole number of runs >= 0, got {self.budget!r}")
        self.x = np.asarray(self.x, dtype=float).reshape(-1, self.space.dim)
        self.y = np.asarray(self.y, dtype=float).reshape(len(self.x), len(self.outputs))
        if self.features is not None:
            self.features = np.asarray(self.features, dtype=float).reshape(len(self.x), -1)
        self._n_sobol = 0
        self._pending: tuple[str, NDArray[np.float64], Design | None] | None = None
        self._history: list[tuple[int, float]] = []     # (points, worst bound / needed bound) per fit
        self._salt_seed = self.seed + 1
        self._salt_n = 0
        self._surrogates: dict[str, Any] = {}
        self._fitted_at = 0                              # pool size at the processes' last fit
        self._frozen = False                             # fixed once a Saltelli stage has run
        self._not_saltelli = np.ones(len(self.x), dtype=bool)
        self._drawn = np.ones(len(self.x), dtype=bool)   # False: focus points (not draws of the inputs)
        self._n_focus = 0
        self._last_pilot = ""
        if self.saltelli is not None:
            design, yv = self.saltelli
            self._salt_seed, self._salt_n = int(design.options["seed"]), int(design.options["n"])
            rows = self._salt_n * (self.space.dim + 2)   # Saltelli's rows; then a pilot or a group's rows
            self._salt_y = np.asarray(yv, dtype=float)[:rows]
            own = {row.tobytes() for row in np.asarray(design.points, dtype=float)[:rows]}
            self._not_saltelli = np.array([row.tobytes() not in own for row in self.x])   # never trained on

    # -- state ---------------------------------------------------------------------------
    @property
    def stages(self) -> list[SobolResult]:
        """The escalation's own current results (newest pooled PCE and newest Saltelli)."""
        return [r for r in (self.pce, self.salt) if r is not None]

    def unconfirmed(self) -> list[str]:
        """Outputs no result (the scene's or the escalation's) confirms and that spread over the pool by
        more than their resolution (:func:`~ddgsa.gsa.result.nothing_to_rank`)."""
        ok = confirmed_outputs(self.results + self.stages, self.outputs, self.ranking)
        return [o for j, o in enumerate(self.outputs)
                if not ok[o] and not nothing_to_rank(self.y[:, j], self.resolution.get(o, 0.0))]

    def start(self) -> NDArray[np.float64] | None:
        """The first points to evaluate (None: nothing to confirm or no budget)."""
        return self._next()

    def feed(self, values: NDArray[np.float64],
             features: NDArray[np.float64] | None = None) -> NDArray[np.float64] | None:
        """Values (n, k) at the points last returned, and there the control features (n, m) where the
        escalation has them (without them, the rest is escalated without features); the next points, or
        None when done."""
        if self._pending is None:
            raise MethodError("confirm: feed() without pending points (call start() first)")
        kind, pts, design = self._pending
        yv, _ = as_value_matrix(values, len(pts), self.outputs)
        if self.features is not None:
            self.features = None if features is None else \
                np.vstack([self.features, np.asarray(features, dtype=float).reshape(len(pts), -1)])
        self._pending = None
        self.spent += len(pts)
        self.x, self.y = np.vstack([self.x, pts]), np.vstack([self.y, yv])
        self._not_saltelli = np.concatenate([self._not_saltelli, np.full(len(pts), kind != "saltelli")])
        self._drawn = np.concatenate([self._drawn, np.full(len(pts), kind != "focus")])
        if kind == "saltelli":
            assert design is not None
            # Saltelli's rows of the bases that ran, then this stage's: new Saltelli rows and every group row
            # (the design's layout; the smaller base's group rows are run again, not kept)
            keep = self._salt_n * (self.space.dim + 2)
            self._salt_y = yv if self._salt_n == 0 else np.vstack([self._salt_y[:keep], yv])
            self._salt_n = int(design.options["n"])
            self.salt = self._saltelli_result(design)
        if kind != "focus":                              # the drawn points, and so the expansion, are as they were
            self._refit()
        bad = self.unconfirmed()
        spent = f"{self.spent} so far" if self.budget >= TIME_ONLY else f"{self.spent} of {self.budget}"
        self.log.append(f"{kind} (+{len(pts)} runs, {spent}): " + self._verdict_words(bad))
        return self._next()

    def _verdict_words(self, bad: list[str]) -> str:
        """``every output confirmed (by confirm_pce)`` / ``unconfirmed: a; b confirmed by mdrm``: the
        confirming method named, since a stage's runs may confirm through another result than its own (a
        Saltelli stage's rows refit the pooled expansion too)."""
        by = {o: m for o, m in confirming_methods(self.results + self.stages, self.outputs, self.ranking).items()
              if m is not None}
        named = (f"by {next(iter(set(by.values())))}" if len(set(by.values())) == 1
                 else ", ".join(f"{o} by {m}" for o, m in by.items()))
        if not bad:
            return "every output confirmed" + (f" ({named})" if by else "")
        return f"unconfirmed: {', '.join(bad)}" + (f"; {', '.join(by)} confirmed {named}" if len(set(by.values())) == 1
                                                   else f"; confirmed: {named}" if by else "")

    def drawn_values(self) -> NDArray[np.float64]:
        """Values (n, k) at the points this escalation added that are draws of the input distribution (its
        PCE points and Saltelli rows, not its focus points), failed rows included: a sample of the outputs."""
        start = len(self.x) - self.spent
        return self.y[start:][self._drawn[start:]]

    def _saltelli_result(self, design: Design) -> SobolResult:
        """The Saltelli stage's indices: with the control variates when any process was fitted (each in
        the standardised units :meth:`GsaMethod.analyze` gives the controlled estimator)."""
        from ddgsa.gsa.base import standardise

        if self._surrogates:
            shift, scale = standardise(np.where(np.isfinite(self._salt_y), self._salt_y, 0.0))
            mapped = {o: self._surrogates[o].affine(shift[j], scale[j]) for j, o in enumerate(self.outputs)
                      if o in self._surrogates}
            design = Design(design.method, design.points, {**design.options, "control": "gp"},
                            {**design.meta, "surrogates": mapped})
        res = get_method("saltelli").analyze(self.space, design, self._salt_y, outputs=self.outputs)
        res.method = SALTELLI_NAME
        return res

    def _fit_surrogates(self, bad: list[str]) -> None:
        """Gaussian processes of the outputs ``bad`` on the pooled points that are not Saltelli rows,
        refitted while no Saltelli stage has run and the pool has doubled since the last fit (see the
        module); none for dependent inputs or too few points."""
        from ddgsa.gsa.control import fit_control

        n_train = int(self._not_saltelli.sum())
        if self._frozen or self.space.dependent or n_train < max(2 * self._fitted_at, 2 * self.space.dim + 2):
            return
        self._fitted_at = n_train
        u = np.column_stack([self.space[p].cdf(self.x[self._not_saltelli, i]) for i, p in enumerate(self.space.names)])
        drawn = self._drawn[self._not_saltelli]
        phi = None if self.features is None else self.features[self._not_saltelli]
        cache: dict[Any, Any] = {}                       # the features' processes, shared by the outputs
        for o in bad:
            yo = self.y[self._not_saltelli, self.outputs.index(o)]
            ok = np.isfinite(yo)
            g = fit_control(u[ok], yo[ok], seed=self.seed, drawn=drawn[ok], features=None if phi is None else phi[ok],
                            cache=cache) if ok.sum() >= 2 * self.space.dim + 2 else None
            if g is not None:
                self._surrogates[o] = g
            else:
                self._surrogates.pop(o, None)

    def _refit(self) -> None:
        """The pooled expansion on the drawn points (focus points would make its bound optimistic)."""
        res = pooled_pce(self.space, self.x[self._drawn], self.y[self._drawn], self.outputs, self.tolerance,
                         MAX_ORDER, MAX_ENTRIES)
        if res is not None:
            res.method = PCE_NAME
            self.pce = res
            self._history.append((int(self._drawn.sum()), self._pce_ratio(res, self.outputs)))

    # -- choice --------------------------------------------------------------------------
    def _best_st(self, output: str) -> NDArray[np.float64]:
        """Median ST per parameter over every result of the scene (the current best guess)."""
        rows = [r.indices[r.indices["output"] == output].set_index("parameter")["ST"]
                for r in self.results + self.stages]
        if not rows:
            return np.full(self.space.dim, np.nan)
        table = np.array([[s.get(p, np.nan) for p in self.space.names] for s in rows], dtype=float)
        with np.errstate(all="ignore"):
            return np.array([np.nanmedian(c) if np.isfinite(c).any() else np.nan for c in table.T])

    def _pce_ratio(self, res: SobolResult, bad: list[str]) -> float:
        """Worst ratio of a row's bound to the bound that would confirm it, over the outputs ``bad``."""
        worst, t = 0.0, res.indices
        for o in bad:
            g = t[t["output"] == o]
            err = np.fmax(g["S1_conf"].to_numpy(float), g["ST_conf"].to_numpy(float))
            need = need_per_row(g["ST"].to_numpy(float), self.tolerance)
            with np.errstate(all="ignore"):
                worst = max(worst, float(np.max(np.where(np.isfinite(err), err / need, np.inf))))
        return worst

    def _pce_need(self, bad: list[str]) -> float:
        """Points the pooled expansion would need to confirm every output of ``bad`` (inf: unknown)."""
        current = self.pce if self.pce is not None else next(
            (r for r in self.results if r.method == "pooled_pce"), None)
        if current is None:
            return np.inf
        ratio = self._pce_ratio(current, bad)
        if not np.isfinite(ratio):
            return np.inf
        rate = 0.5
        if len(self._history) >= 2:
            (n0, r0), (n1, r1) = self._history[-2:]
            with np.errstate(all="ignore"):
                measured = np.log(r0 / r1) / np.log(n1 / n0) if n1 > n0 and r1 > 0 else np.nan
            rate = float(np.clip(measured, MIN_RATE, 1.0)) if np.isfinite(measured) else MIN_RATE
        with np.errstate(over="ignore"):
            return float(current.n_evals * max(ratio, 1.0) ** (1.0 / rate))

    def _saltelli_ns(self, bad: list[str], fit: bool = True) -> dict[str, int]:
        """Per unconfirmed output, the Saltelli base the cost rule estimates would confirm it (with its
        control variate's leave-one-out error where a process is fitted), at least twice a base that
        ran and did not confirm. ``fit``: first fit the processes where the pool has grown enough
        (:meth:`_fit_surrogates`); False takes those fitted so far."""
        if fit:
            self._fit_surrogates(bad)
        out = {}
        for o in bad:                                    # a Saltelli design that ran did not confirm: twice it
            out[o] = saltelli_n_to_confirm(self._best_st(o), self.tolerance,
                                           self._surrogates[o].loo if o in self._surrogates else None,
                                           None if self.salt is None else difference_ratio(self.salt, o), self._salt_n)
        return out

    def asks(self) -> dict[str, dict[str, int]]:
        """Per output left unconfirmed, what the cost rule asks for at the end: ``n``, the controlled Saltelli
        base it estimates would confirm it (:meth:`_saltelli_ns`: with its control variate's leave-one-out error
        and the latest stage's bounds on the ST differences, at least twice a base that ran and did not confirm;
        the control variates as last fitted, none where the escalation fitted none, e.g. a zero budget),
        ``points``, the new points of that design beyond the base that ran (each one run per realisation;
        :meth:`_stage_points`), and ``control``, whether a Gaussian-process control variate of the output was
        fitted (the estimate counts on it):
        what the ``confirm:`` budget would need to grow by in this scene (``confirmation.csv``'s next step,
        :func:`ddgsa.execute.confirm.advice`)."""
        bad = self.unconfirmed()
        if not bad:
            return {}
        # the processes as the escalation last fitted them (none fitted now: seconds)
        return {o: {"n": n, "points": self._stage_points(n), "control": o in self._surrogates}
                for o, n in self._saltelli_ns(bad, fit=False).items()}

    def _stage_points(self, n: int) -> int:
        """New points of a Saltelli stage of base ``n`` beyond the base that ran: Saltelli's rows past the
        first ``self._salt_n`` (d + 2) (the designs of one seed nest) and each multi-member group's ``AB_u``
        rows, n each (all of them: they follow Saltelli's rows, so none of a smaller base's is a prefix)."""
        return (n - self._salt_n) * (self.space.dim + 2) + n * len(multi_groups(self.space))

    def _saltelli_n(self, bad: list[str]) -> int:
        """The Saltelli base that would confirm every output of ``bad`` (:meth:`_saltelli_ns`)."""
        return max(self._saltelli_ns(bad).values())

    def _next(self) -> NDArray[np.float64] | None:
        bad = self.unconfirmed()
        left = self.budget - self.spent
        if not bad or left <= 0:
            if bad:
                self.log.append(f"budget of {self.budget} runs spent; unconfirmed: {', '.join(bad)}")
            return None
        d = self.space.dim
        per_output = self._saltelli_ns(bad)
        n_salt = max(per_output.values())
        add_salt = self._stage_points(n_salt)
        n_pool = int(self._drawn.sum())                  # the points the pooled expansion is fitted on
        add_pce = max(0.0, self._pce_need(bad) - n_pool)
        pilot = self._pilot_step(add_salt, add_pce, left)
        if pilot:
            peaks = [o for o in bad if o in self._surrogates and self._surrogates[o].fitted_to != "y"]
            why = f"their error sets the Saltelli base, now N={n_salt}, {add_salt} runs"
            if peaks and self._last_pilot == "pce":
                self._last_pilot = "focus"
                self.log.append(f"next: focus points +{pilot} (pilot where the control variates of "
                                f"{', '.join(peaks)} are least certain; {why})")
                return self._focus_points(pilot, peaks)
            self._last_pilot = "pce"
            self.log.append(f"next: pce points +{pilot} (pilot for the control variates: {why})")
            return self._sobol_points(pilot)
        n_fit = self._salt_n
        while self._stage_points(2 * max(n_fit, 1)) <= left and 2 * max(n_fit, 1) <= n_salt:
            n_fit = 2 * max(n_fit, 1)
        short = add_salt > left and len(self._history) >= 2 and n_fit > self._salt_n \
            and n_fit * SHORT_BASE >= min(per_output.values()) and add_salt <= add_pce
        if (add_salt <= add_pce and add_salt <= left) or short:
            n_run = n_salt if not short else n_fit
            design = get_method("saltelli").design(self.space, n=n_run, seed=self._salt_seed,
                                                   tolerance=self.tolerance)
            pts = design.points[self._salt_n * (d + 2):]
            self._frozen = True
            self._surrogates = {o: g.without_posterior() for o, g in self._surrogates.items()}
            control = "" if not self._surrogates else ", Gaussian-process control variates (leave-one-out " + \
                ", ".join(f"{o} {g.loo:.2g}" + ("" if g.fitted_to == "y" else f" of {g.fitted_to}")
                          for o, g in self._surrogates.items() if o in bad) + ")"
            why = "" if not short else f"; the largest base the budget allows, the estimate asks for N={n_salt}"
            self.log.append(f"next: saltelli N={n_run} ({len(pts)} new runs{control}{why}; pooled PCE estimate "
                            f"{_fmt(add_pce)} runs)")
            self._pending = ("saltelli", pts, design)
            return pts
        if len(self._history) >= 2 and add_salt > left:
            cheapest = min(max(0.0, self._pce_need([o]) - n_pool) for o in bad)
            if cheapest > HOPELESS * left:
                self.log.append(f"stopped with {left} of {self.budget} runs left: the pooled PCE's bound shrinks too "
                                f"slowly (the cheapest output needs {_fmt(cheapest)} more points) and saltelli "
                                f"N={n_salt} needs {add_salt} runs; unconfirmed: {', '.join(bad)}")
                return None
        step = int(min(left, max(MIN_STEP, min(add_pce, max(n_pool, MIN_STEP)))))
        why = "the rest of the budget" if step == left else f"estimate {_fmt(add_pce)} more"
        self.log.append(f"next: pce points +{step} ({why}; saltelli N={n_salt} would add {add_salt} runs)")
        return self._sobol_points(step)

    def _sobol_points(self, step: int) -> NDArray[np.float64]:
        """The next ``step`` points of the escalation's scrambled Sobol' sequence (PCE points), pending."""
        total = self._n_sobol + step
        sample = self.space.sample(1 << int(np.ceil(np.log2(total))), seed=self.seed + 2, rule="sobol")
        pts = sample[self._n_sobol:total]
        self._n_sobol = total
        self._pending = ("pce", pts, None)
        return pts

    def _focus_points(self, step: int, outputs: list[str]) -> NDArray[np.float64]:
        """``step`` pilot points where the transformed control variates of ``outputs`` are least certain
        (pending): of the next :data:`FOCUS_CANDIDATES` x ``step`` points of a Sobol' sequence of their
        own (``seed + 4``), those with the largest posterior standard deviation in the output's units,
        each output's scaled to its largest (:meth:`~ddgsa.gsa.control.TransformedSurrogate.error`).
        A resonance's peak is where a process of ``1 / y^2`` mapped back errs most; concentrating
        the pilot there shrinks the controlled estimate's heavy-tailed residual. Never used by the
        pooled expansion (not draws of the inputs) and never a Saltelli row, so every estimate stays
        unbiased."""
        total = self._n_focus + FOCUS_CANDIDATES * step
        sample = self.space.sample(1 << int(np.ceil(np.log2(total))), seed=self.seed + 4, rule="sobol")
        cand = sample[self._n_focus:total]
        self._n_focus = total
        u = np.column_stack([self.space[p].cdf(cand[:, i]) for i, p in enumerate(self.space.names)])
        score = np.zeros(len(cand))
        for o in outputs:
            e = np.nan_to_num(self._surrogates[o].error(u), nan=0.0, posinf=0.0)
            score = np.fmax(score, e / e.max() if e.max() > 0 else e)
        pts = cand[np.sort(np.argsort(-score, kind="stable")[:step])]
        self._pending = ("focus", pts, None)
        return pts

    def _pilot_step(self, add_salt: int, add_pce: float, left: int) -> int:
        """Points to add to the control variates' pilot before a first Saltelli stage (0: none). A
        process's leave-one-out error falls about as ``n^-1/2``, and the controlled base as its square:
        doubling the pilot about halves the Saltelli stage. So while Saltelli is the plan (cheaper than
        the pooled expansion), the pilot is below :data:`~ddgsa.gsa.control.MAX_TRAIN` and below half the
        Saltelli stage, the pilot doubles (within the budget) and the processes are refitted."""
        from ddgsa.gsa.control import MAX_TRAIN

        n_train = int(self._not_saltelli.sum())
        if self._frozen or self.space.dependent or add_salt > add_pce or n_train >= MAX_TRAIN \
                or 2 * n_train > add_salt:
            return 0
        step = min(max(n_train, MIN_STEP), MAX_TRAIN - n_train, left - 1)
        return step if step >= MIN_STEP else 0


def _fmt(n: float) -> str:
    """A run count for the log: 'unknown' (no estimate), the number, or 'more than 10^9' (a bound
    that does not shrink extrapolates to absurd counts)."""
    if not np.isfinite(n):
        return "unknown"
    return "more than 10^9" if n > 1e9 else f"{int(np.ceil(n))}"


@dataclass
class Confirmed:
    """What :func:`confirm` returns: every result (the method's, the pooled PCE on its design, the
    escalation's), whether each output is confirmed, the runs spent and the escalation's log."""

    results: list[SobolResult]
    confirmed: dict[str, bool]
    n_evals: int
    log: list[str]
    asks: dict[str, dict[str, int]] = field(default_factory=dict)
    """What the escalation's cost rule asked for at its end, per output left unconfirmed (:meth:`Escalation.asks`)."""


def confirm(f: Callable[[NDArray[np.float64]], Any], space: ParameterSpace, method: str = "mdrm", *,
            budget: int, outputs: Sequence[str] | None = None, **options: Any) -> Confirmed:
    """Run ``method`` on ``f``, then escalate (:class:`Escalation`) with at most ``budget`` more runs.

    Examples
    --------
    >>> from ddgsa.gsa.testfunctions import ishigami
    >>> tf = ishigami()
    >>> c = confirm(tf.f, tf.space, "mdrm", budget=3000)
    >>> c.confirmed, c.n_evals <= 3 * 7 + 1 + 32 + 3000
    ({'y': True}, True)
    """
    m = get_method(method)
    design, y, names = evaluate(m, space, f, options, outputs)
    first = m.analyze(space, design, y, outputs=names)
    tol = float(design.options.get("tolerance", DEFAULT_TOLERANCE))
    results = [first]
    pooled = pooled_pce(space, design.points, y, names, tol) if method != "pce" else None
    if pooled is not None:
        results.append(pooled)
    esc = Escalation(space, names, budget, design.points, y, results, tol,
                     seed=int(design.options.get("seed", 0) or 0),
                     saltelli=(design, y) if method == "saltelli" else None)
    x = esc.start()
    while x is not None:
        x = esc.feed(as_value_matrix(f(x), len(x), names)[0])
    every = results + esc.stages
    return Confirmed(every, confirmed_outputs(every, names), design.n_points + esc.spent, esc.log, esc.asks())
