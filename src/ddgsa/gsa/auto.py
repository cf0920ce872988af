"""``method: auto`` -- trust the cheap answer when it is right, escalate when it is not.

Stages, each run only if the previous one left an output untrusted, all within ``budget``
model evaluations and reusing every evaluation already made:

1. **M-DRM** (``points`` Gauss points per parameter on the cut lines plus its ``check``-point
   scrambled-Sobol' check sample: ``n (points) + 1 + check`` runs). Its diagnostics (cut value,
   sign change, unresolved cut functions, heavy tails, check-sample R^2 and variance) decide.
   Where some inputs' rows are untrusted zeros (cut functions flat on their nodes), M-DRM's
   **inert check** (:mod:`ddgsa.gsa.inert`, ``check`` more runs) redraws them at the check
   points; inputs it proves inert for every output are left out of the PCE stages below, whose
   basis then spans the other inputs only (their rows: 0 with error 0, as proven).
2. **PCE** by least-squares regression of total degree 3, 5, 7, ... on *all* points so far
   (the cut lines and the check sample included) plus more points of the same Sobol'
   sequence, so each fit has at least twice as many space-filling points as basis terms
   (rounded up to a power of two, the sequence's balance, where the budget pays for it; else
   exactly twice, a prefix of the same sequence). An
   order is accepted when its leave-one-out error and top-order energy pass (``pce_loo_error``,
   ``pce_unresolved``; the leave-one-out mean square is taken over the points drawn from the
   input distribution, not the cut lines); the next order is tried while the budget lasts.
3. When the next order does not fit the remaining budget: **Saltelli** with the largest
   power-of-two base sample the remaining budget pays for (``N (d + 2)`` runs, at least
   ``saltelli_min_n`` = 256: below that its errors, 0.02-0.1 on the benchmark functions, are no
   better than an untrusted PCE's; its points share nothing with the others); when that does
   not fit either, a **sparse PCE** (least-angle regression, :mod:`ddgsa.gsa.pce`) of the order
   that did not fit -- lowered until its matrix passes the size guard -- on all points so far
   plus the rest of the budget from the same Sobol' sequence. Either way the budget is spent
   before ``auto`` answers untrusted, and the log says which stage was chosen and why.

Every stage judges its rows against the same ``tolerance`` (default 0.02, see
:mod:`ddgsa.gsa.trust`).

Each row (output, parameter) keeps the trusted estimate with the smallest error bound of any
stage (column ``source``); the stages go on while some row is trusted by none. A row no stage
trusted comes from the output's *home* stage (the one trusting most of its rows, so one
surrogate's indices stay together) unless that stage's row is not finite, then from the finite
stage that passes every rule but the error estimate with the smallest estimate: a non-finite
row is never preferred to a finite one. Untrusted findings are carried to exactly the rows taken
from the stage that made them (so row-level ``trusted`` always agrees with the final
diagnostics); ``auto_budget_exhausted`` (warning) names the rows no stage trusted, every
escalation is an ``auto_escalated`` info diagnostic naming the diagnostics that caused it, and
``extras["auto_log"]`` keeps the decisions in words. ``extras["moments"]`` holds each output's
mean and standard deviation over the points drawn from the input distribution (not the cut
lines).

The driver is a small state machine so that the caller owns the evaluations (a Python function
in :func:`ddgsa.sobol`, the parallel runner with its cache in a study)::

    auto = AutoSobol(space, budget=2000)
    x = auto.start()
    while x is not None:
        x = auto.feed(f(x))
    result = auto.result
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.errors import MethodError
from ddgsa.gsa.base import Design, as_value_matrix, check_int, get_method
from ddgsa.gsa.pce import _MAX_MATRIX_ENTRIES, n_terms
from ddgsa.gsa.result import Diagnostic, SobolResult, index_error_rule, rank_structure, trusted_mask
from ddgsa.gsa.trust import DEFAULT_TOLERANCE, check_tolerance
from ddgsa.gsa.space import ParameterSpace

DEFAULTS: dict[str, Any] = {"budget": 2000, "points": 5, "check": 32, "seed": 0, "pce_orders": (3, 5, 7, 9),
                            "saltelli_min_n": 256, "tolerance": DEFAULT_TOLERANCE}


def resolve_auto_options(space: ParameterSpace, options: dict[str, Any]) -> dict[str, Any]:
    """Defaults updated with ``options``, checked (unknown names and bad values raise :class:`MethodError`)."""
    unknown = set(options) - set(DEFAULTS)
    if unknown:
        raise MethodError(f"method 'auto': unknown option(s) {sorted(unknown)}; allowed: {', '.join(sorted(DEFAULTS))}")
    opts = {**DEFAULTS, **options}
    check_int("auto", "points", opts["points"], 2, 40)
    check_int("auto", "check", opts["check"], 1)
    check_int("auto", "seed", opts["seed"], 0)
    check_int("auto", "saltelli_min_n", opts["saltelli_min_n"], 4)
    check_tolerance("auto", opts["tolerance"])
    orders = opts["pce_orders"]
    if not (isinstance(orders, (list, tuple)) and all(isinstance(q, int) and 1 <= q <= 30 for q in orders)):
        raise MethodError(f"method 'auto': option 'pce_orders' must be a list of integers in [1, 30], got {orders!r}")
    first = space.dim * opts["points"] + 1 + opts["check"]
    check_int("auto", "budget", opts["budget"], first)
    opts["pce_orders"] = tuple(sorted(orders))
    return opts


@dataclass(frozen=True)
class _Pending:
    """The stage waiting for values: its kind, the points handed out, and what analyses them."""

    kind: str                      # "mdrm", "inert" (M-DRM's inert check), "pce" or "saltelli"
    points: NDArray[np.float64]
    design: Design | None = None   # mdrm and saltelli: their own design; pce: fitted on all points
    order: int = 0                 # pce
    fit: str = "regression"        # pce: "regression" or "sparse"


class AutoSobol:
    """The escalation state machine (see the module). ``start()``, then ``feed(values)`` until it returns None."""

    def __init__(self, space: ParameterSpace, outputs: list[str] | None = None, **options: Any) -> None:
        self.space, self.names = space, outputs
        self.options = resolve_auto_options(space, options)
        self.x = np.zeros((0, space.dim))
        self.y = np.zeros((0, 0))
        self.stages: list[tuple[SobolResult, str]] = []          # (result, label)
        self.log: list[str] = []
        self.result: SobolResult | None = None
        self._n_sobol = 0                                        # Sobol' points of the seed's sequence in x
        self._orders = list(self.options["pce_orders"])
        self._pending: _Pending | None = None
        self._sparse_done = False
        self._next_order = max(self.options["pce_orders"])
        self._drawn = np.zeros(0, dtype=bool)                    # rows of x drawn from the input distribution
        self._live = list(range(space.dim))                      # inputs not proven inert for every output

    # -- driver ---------------------------------------------------------------------------
    def start(self) -> NDArray[np.float64]:
        """The first points to evaluate: M-DRM's design with its check sample."""
        o = self.options
        design = get_method("mdrm").design(self.space, points=o["points"], check=o["check"], seed=o["seed"],
                                           tolerance=o["tolerance"])
        self._n_sobol = o["check"]
        self._pending = _Pending("mdrm", design.points, design)
        return design.points

    def feed(self, values: NDArray[np.float64] | pd.DataFrame | pd.Series) -> NDArray[np.float64] | None:
        """Values at the points last returned; the next points, or None when done (see ``result``)."""
        stage = self._pending
        if stage is None:
            raise MethodError("method 'auto': feed() without pending points (call start() first)")
        y, names = as_value_matrix(values, stage.points.shape[0], self.names)
        self.names = names
        self.x = np.vstack([self.x, stage.points])
        self.y = y if self.y.size == 0 else np.vstack([self.y, y])
        drawn = np.ones(len(stage.points), dtype=bool)       # every point a draw from the inputs' law...
        if stage.kind == "mdrm":
            drawn[:len(stage.points) - self.options["check"]] = False      # ...but M-DRM's cut lines
        self._drawn = np.concatenate([self._drawn, drawn])
        if stage.kind == "pce":
            design = Design("pce", self.x[:, self._live], {**get_method("pce").defaults, "order": stage.order,
                                                           "fit": stage.fit, "n": self.x.shape[0],
                                                           "seed": self.options["seed"],
                                                           "tolerance": self.options["tolerance"]},
                            {"drawn": self._drawn})
            res = _over(self.space, get_method("pce").analyze(self._pce_space(), design, self.y, outputs=names))
            sparse = "sparse " if stage.fit == "sparse" else ""
            over = f" in the {len(self._live)} inputs not proven inert" if len(self._live) < self.space.dim else ""
            self._record(res, f"{sparse}pce order {stage.order} ({self.x.shape[0]} runs pooled{over})")
        elif stage.kind == "inert":
            assert stage.design is not None
            n_mdrm = stage.design.meta["inert"]["n"]
            res = get_method("mdrm").analyze(self.space, stage.design, self.y[-stage.design.n_points:], outputs=names)
            self.stages.pop()
            self._record(res, f"mdrm ({n_mdrm} runs) with its inert check ({len(stage.points)} runs)")
            proven = np.asarray(res.extras.get("inert", []), dtype=bool)
            if proven.size and proven.all() and not self.space.groups:
                inert = {self.space.names.index(p) for p in res.extras["inert_group"]}
                self._live = [i for i in range(self.space.dim) if i not in inert]
        else:
            assert stage.design is not None
            res = get_method(stage.kind).analyze(self.space, stage.design, y, outputs=names)
            size = f"N={stage.design.options['n']} " if stage.kind == "saltelli" else ""
            self._record(res, f"{stage.kind} ({size}{stage.design.n_points} runs)")
            if stage.kind == "mdrm":
                more = get_method("mdrm").followup(self.space, stage.design, y, names)
                if more is not None and self._untrusted_rows() and \
                        more.n_points - stage.design.n_points <= self.options["budget"] - self.x.shape[0]:
                    self._pending = _Pending("inert", more.points[stage.design.n_points:], more)
                    return self._pending.points
        return self._next()

    def _pce_space(self) -> ParameterSpace:
        """The space the PCE stages fit in: the inputs not proven inert (all of them by default)."""
        if len(self._live) == self.space.dim:
            return self.space
        return ParameterSpace.from_parameters([self.space.parameters[i] for i in self._live])

    # -- stages ---------------------------------------------------------------------------
    def _untrusted_rows(self) -> dict[str, list[str]]:
        """Per output, the parameters whose row no stage so far has trusted."""
        trusted: set[tuple[str, str]] = set()
        for res, _ in self.stages:
            t = res.indices[res.indices["trusted"]]
            trusted |= set(zip(t["output"], t["parameter"]))
        bad = {o: [p for p in self.space.names if (o, p) not in trusted] for o in self.names or []}
        return {o: ps for o, ps in bad.items() if ps}

    def _record(self, res: SobolResult, label: str) -> None:
        self.stages.append((res, label))
        bad = self._untrusted_rows()
        fired = sorted({d.name for d in res.diagnostics if d.severity == "untrusted"})
        rows = "; ".join(f"{o} [{', '.join(ps)}]" for o, ps in bad.items())
        self.log.append(f"{label}: " + ("all outputs trusted" if not bad else
                                        f"untrusted rows: {rows} ({', '.join(fired)})"))

    def _next(self) -> NDArray[np.float64] | None:
        if not self._untrusted_rows():
            self._finish()
            return None
        left = self.options["budget"] - self.x.shape[0]
        if self.stages[-1][0].method in ("mdrm", "pce") and not self._sparse_done:
            while self._orders:
                q = self._orders.pop(0)
                self._next_order = q
                # space-filling points for order q: the power of two >= twice the basis size (the
                # sequence's balance) or, where that does not fit the budget, twice the basis size
                twice = 2 * n_terms(len(self._live), q)
                need = 1 << int(np.ceil(np.log2(twice)))
                if need - self._n_sobol > left:
                    need = twice
                add = max(0, need - self._n_sobol)
                if need * n_terms(len(self._live), q) > _MAX_MATRIX_ENTRIES:
                    self.log.append(f"pce order {q} on {need} runs exceeds the regression size guard")
                    self._orders = []
                    break
                if add > left:
                    self.log.append(f"pce order {q} needs {add} more runs; {left} left in the budget")
                    self._orders = []
                    break
                sobol = self._sobol(self._n_sobol + add)
                self._pending = _Pending("pce", sobol[self._n_sobol:], order=q)
                self._n_sobol += add
                if add == 0:                                     # nothing to run: fit at once
                    return self.feed(np.zeros((0, len(self.names or []))))
                return self._pending.points
            n = 1 << int(np.floor(np.log2(max(1, left // (self.space.dim + 2)))))
            if n >= self.options["saltelli_min_n"]:
                # seed + 1: with the same seed SALib's scrambling repeats the Sobol' stream's first point
                design = get_method("saltelli").design(self.space, n=n, seed=self.options["seed"] + 1,
                                                       tolerance=self.options["tolerance"])
                self._pending = _Pending("saltelli", design.points, design)
                return design.points
            self.log.append(f"saltelli needs >= {self.options['saltelli_min_n'] * (self.space.dim + 2)} runs; "
                            f"{left} left in the budget")
        sparse = self._sparse_stage(left)
        if sparse is not None:
            return sparse
        self._finish()
        return None

    def _sparse_stage(self, left: int) -> NDArray[np.float64] | None:
        """A sparse PCE on all points so far plus the ``left`` runs of the budget (once).

        Its order is the full order that did not fit, lowered until the regression matrix passes
        the size guard of :mod:`ddgsa.gsa.pce`.
        """
        if self._sparse_done or left <= 0:
            return None
        self._sparse_done = True
        n_total = self.x.shape[0] + left
        order = self._next_order
        while order > 1 and n_total * n_terms(len(self._live), order) > _MAX_MATRIX_ENTRIES:
            order -= 1
        self.log.append(f"sparse pce order {order} on all {n_total} runs ({left} more, the rest of the budget): "
                        "no full stage fits what is left")
        total = self._n_sobol + left
        sobol = self._sobol(total)
        self._pending = _Pending("pce", sobol[self._n_sobol:total], order=order, fit="sparse")
        self._n_sobol += left
        return self._pending.points

    def _sobol(self, n: int) -> NDArray[np.float64]:
        """The first ``n`` points of the seed's scrambled Sobol' sequence (a prefix of the power-of-two
        sample at or above ``n``: every stage draws from the same sequence)."""
        return self.space.sample(1 << int(np.ceil(np.log2(n))), seed=self.options["seed"], rule="sobol")[:n]

    def _finish(self) -> None:
        """Per row, the stage that trusted it with the smallest error estimate; a row no stage
        trusted comes from the output's home stage (the one trusting most of its rows) when finite
        there, else from the finite stage passing every rule but the error estimate with the
        smallest estimate (then the most runs). A non-finite row is never preferred to a finite one."""
        scored = [_row_scores(res) for res, _ in self.stages]
        tables, diags, st_err = [], [], []
        for out in self.names or []:
            used: set[int] = set()
            # the output's home stage, for its untrusted rows (one surrogate's indices hang together):
            # the most trusted rows, then every row finite, then the smallest worst error, the most runs
            home = min(range(len(self.stages)), key=lambda i: (
                -int(scored[i].loc[out, "trusted"].sum()), not scored[i].loc[out, "finite"].all(),
                scored[i].loc[out, "error"].max(), -self.stages[i][0].n_evals, -i))
            for par in self.space.names:
                keys = []
                for i, ((res, _), sc) in enumerate(zip(self.stages, scored)):
                    r = sc.loc[(out, par)]
                    keys.append((not r["trusted"], r["trusted"] and r["error"], not r["finite"], i != home,
                                 not r["passes_other"], r["error"], -res.n_evals, -i))
                k = min(range(len(self.stages)), key=lambda i: keys[i])
                used.add(k)
                res, _ = self.stages[k]
                t = res.indices
                row = t[(t["output"] == out) & (t["parameter"] == par)].copy()
                row["source"] = res.method
                tables.append(row)
                st_err.append(scored[k].loc[(out, par), "st_error"])
                for d in res.diagnostics:
                    if d.output not in (None, out) or d.parameter not in (None, par):
                        continue
                    # an untrusted finding is about this row only: other rows of the output may come
                    # from a stage it does not concern
                    diags.append(replace(d, output=out, parameter=par) if d.severity == "untrusted" else d)
            for r, lab in self.stages[:max(used)]:
                fired = sorted({d.name for d in r.diagnostics if d.severity == "untrusted" and d.output in (None, out)})
                if fired:
                    diags.append(Diagnostic("auto_escalated", f"output {out!r}: {lab} untrusted "
                                            f"({', '.join(fired)}); escalated", "info", output=out))
        indices = pd.concat(tables, ignore_index=True)
        diags = _dedupe(diags)
        indices["trusted"] = indices["trusted"].to_numpy(bool) & trusted_mask(indices, diags)
        for out, g in indices[~indices["trusted"]].groupby("output", sort=False):
            diags.append(Diagnostic("auto_budget_exhausted", f"output {out!r}: no stage trusted "
                                    f"{', '.join(g['parameter'])} within the budget of {self.options['budget']} "
                                    "runs; those rows are the best untrusted stage's (column source)", "warning",
                                    output=out, value=float(len(g))))
        st_err = np.asarray(st_err, dtype=float)
        claims, ranks = rank_structure(indices, st_err, diags, self.options["tolerance"])
        indices["rank_confirmed"] = claims > 0
        indices["rank"] = ranks
        self.result = SobolResult(indices, n_evals=self.x.shape[0], method="auto", options=dict(self.options),
                                  diagnostics=diags,
                                  extras={"auto_log": list(self.log), "stages": [lab for _, lab in self.stages],
                                          "moments": self._moments(), "rank_claims": claims,
                                          "rank_error": st_err})
        self._pending = None

    def _moments(self) -> dict[str, Any]:
        """Mean and standard deviation of each output over the points drawn from the input
        distribution (M-DRM's check sample, the PCE and Saltelli points; not the cut lines)."""
        y = self.y[self._drawn]
        y = y[np.isfinite(y).all(axis=1)]
        n = len(y)
        nan = np.full(self.y.shape[1], np.nan)
        return {"mean": y.mean(axis=0) if n else nan, "std": y.std(axis=0, ddof=1) if n > 1 else nan, "n": n,
                "drawn": int(self._drawn.sum())}


def _over(space: ParameterSpace, res: SobolResult) -> SobolResult:
    """``res`` (a fit in the inputs not proven inert) with a row for every input of ``space``: the inert
    ones 0 with error 0 and trusted, as the inert check proved them (the fit's model has no term in them)."""
    t = res.indices
    if len(t) == 0 or set(t["parameter"]) == set(space.names):
        return res
    full = pd.MultiIndex.from_product([list(dict.fromkeys(t["output"])), list(space.names)],
                                      names=["output", "parameter"])
    table = t.set_index(["output", "parameter"]).reindex(full).reset_index()
    inert = ~table["parameter"].isin(set(t["parameter"]))
    table.loc[inert, ["S1", "S1_conf", "ST", "ST_conf"]] = 0.0
    table["trusted"] = table["trusted"].fillna(True).astype(bool)
    if "rank_confirmed" in table:
        table["rank_confirmed"] = table["rank_confirmed"].fillna(False).astype(bool)
    if "rank" in table:
        table["rank"] = table["rank"].fillna("")
    return replace(res, indices=table)


def _row_scores(res: SobolResult) -> pd.DataFrame:
    """Per (output, parameter) of one stage: trusted, finite, passes the rules other than the error
    estimate, the estimated index error (max of S1's and ST's; inf when unknown) and ST's alone."""
    t = res.indices
    if "S1_error" in res.extras:                                   # SALib: bootstrap and half sample
        e1 = np.asarray(res.extras["S1_error"], dtype=float).ravel()
        et = np.asarray(res.extras["ST_error"], dtype=float).ravel()
    else:
        e1, et = t["S1_conf"].to_numpy(float), t["ST_conf"].to_numpy(float)
    with np.errstate(invalid="ignore"):
        err = np.fmax(e1, et)
    finite = np.isfinite(t["S1"].to_numpy(float)) & np.isfinite(t["ST"].to_numpy(float))
    return pd.DataFrame({"trusted": t["trusted"].to_numpy(bool), "finite": finite,
                         "passes_other": trusted_mask(t, [d for d in res.diagnostics if not index_error_rule(d.name)]),
                         "error": np.where(np.isfinite(err), err, np.inf), "st_error": et},
                        index=pd.MultiIndex.from_arrays([t["output"], t["parameter"]]))


def _dedupe(diags: list[Diagnostic]) -> list[Diagnostic]:
    seen, out = set(), []
    for d in diags:
        key = (d.name, d.output, d.parameter, d.message)
        if key not in seen:
            seen.add(key)
            out.append(d)
    return out


def run_auto(f: Any, space: ParameterSpace, outputs: list[str] | None = None, **options: Any) -> SobolResult:
    """Drive :class:`AutoSobol` with a vectorised function ``f(x)``."""
    auto = AutoSobol(space, outputs, **options)
    x: NDArray[np.float64] | None = auto.start()
    while x is not None:
        x = auto.feed(f(x))
    assert auto.result is not None
    return auto.result
