"""``method: auto`` -- trust the cheap answer when it is right, escalate when it is not.

Stages, each run only if the previous one left an output untrusted, all within ``budget``
model evaluations and reusing every evaluation already made:

1. **M-DRM** (``points`` Gauss points per parameter on the cut lines plus its ``check``-point
   scrambled-Sobol' check sample: ``n (points) + 1 + check`` runs). Its diagnostics (cut value,
   sign change, unresolved cut functions, heavy tails, check-sample R^2 and variance) decide.
2. **PCE** by least-squares regression of total degree 3, 5, 7, ... on *all* points so far
   (the cut lines and the check sample included) plus more points of the same Sobol'
   sequence, so each fit has at least twice as many space-filling points as basis terms
   (rounded up to a power of two, the sequence's balance). An
   order is accepted when its leave-one-out error and top-order energy pass (``pce_loo_error``,
   ``pce_unresolved``); the next order is tried while the budget lasts.
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

Each output's indices come from the first stage that trusted them (column ``source``); an
output no stage trusted keeps the numbers of the stage that used the most evaluations, marked
untrusted with ``auto_budget_exhausted`` (every row of it: row-level ``trusted`` is recomputed
from the final diagnostics, so it always agrees with them). Every escalation is an ``auto_escalated`` info diagnostic naming the
diagnostics that caused it, and ``extras["auto_log"]`` keeps the decisions in words.

The driver is a small state machine so that the caller owns the evaluations (a Python function
in :func:`ddgsa.sobol`, the parallel runner with its cache in a study)::

    auto = AutoSobol(space, budget=2000)
    x = auto.start()
    while x is not None:
        x = auto.feed(f(x))
    result = auto.result
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.errors import MethodError
from ddgsa.gsa.base import Design, as_value_matrix, check_int, get_method
from ddgsa.gsa.pce import _MAX_MATRIX_ENTRIES, n_terms
from ddgsa.gsa.result import Diagnostic, SobolResult, trusted_mask
from ddgsa.gsa.trust import DEFAULT_TOLERANCE, check_tolerance
from ddgsa.space import ParameterSpace

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

    kind: str                      # "mdrm", "pce" or "saltelli"
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
        if stage.kind == "pce":
            design = Design("pce", self.x, {**get_method("pce").defaults, "order": stage.order, "fit": stage.fit,
                                            "n": self.x.shape[0], "seed": self.options["seed"],
                                            "tolerance": self.options["tolerance"]})
            res = get_method("pce").analyze(self.space, design, self.y, outputs=names)
            sparse = "sparse " if stage.fit == "sparse" else ""
            self._record(res, f"{sparse}pce order {stage.order} ({self.x.shape[0]} runs pooled)")
        else:
            assert stage.design is not None
            res = get_method(stage.kind).analyze(self.space, stage.design, y, outputs=names)
            size = f"N={stage.design.options['n']} " if stage.kind == "saltelli" else ""
            self._record(res, f"{stage.kind} ({size}{stage.design.n_points} runs)")
        return self._next()

    # -- stages ---------------------------------------------------------------------------
    def _untrusted_outputs(self) -> list[str]:
        trusted = set()
        for res, _ in self.stages:
            ok = res.indices.groupby("output")["trusted"].all()
            trusted |= set(ok[ok].index)
        return [o for o in self.names or [] if o not in trusted]

    def _record(self, res: SobolResult, label: str) -> None:
        self.stages.append((res, label))
        bad = self._untrusted_outputs()
        fired = sorted({d.name for d in res.diagnostics if d.severity == "untrusted"})
        self.log.append(f"{label}: " + ("all outputs trusted" if not bad else
                                        f"untrusted for {', '.join(bad)} ({', '.join(fired)})"))

    def _next(self) -> NDArray[np.float64] | None:
        if not self._untrusted_outputs():
            self._finish()
            return None
        left = self.options["budget"] - self.x.shape[0]
        if self.stages[-1][0].method in ("mdrm", "pce") and not self._sparse_done:
            while self._orders:
                q = self._orders.pop(0)
                self._next_order = q
                # space-filling points for order q: the power of two >= twice the basis size
                need = 1 << int(np.ceil(np.log2(2 * n_terms(self.space.dim, q))))
                add = max(0, need - self._n_sobol)
                if need * n_terms(self.space.dim, q) > _MAX_MATRIX_ENTRIES:
                    self.log.append(f"pce order {q} on {need} runs exceeds the regression size guard")
                    self._orders = []
                    break
                if add > left:
                    self.log.append(f"pce order {q} needs {add} more runs; {left} left in the budget")
                    self._orders = []
                    break
                sobol = self.space.sample(self._n_sobol + add, seed=self.options["seed"], rule="sobol")
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
        while order > 1 and n_total * n_terms(self.space.dim, order) > _MAX_MATRIX_ENTRIES:
            order -= 1
        self.log.append(f"sparse pce order {order} on all {n_total} runs ({left} more, the rest of the budget): "
                        "no full stage fits what is left")
        total = self._n_sobol + left                # a prefix of the power-of-two sample: same sequence
        sobol = self.space.sample(1 << int(np.ceil(np.log2(total))), seed=self.options["seed"], rule="sobol")
        self._pending = _Pending("pce", sobol[self._n_sobol:total], order=order, fit="sparse")
        self._n_sobol += left
        return self._pending.points

    def _finish(self) -> None:
        """Per output, the first stage that trusted it (else the last stage), with the decisions."""
        tables, diags = [], []
        for out in self.names or []:
            k = next((i for i, (r, _) in enumerate(self.stages)
                      if r.indices.loc[r.indices["output"] == out, "trusted"].all()), None)
            if k is None:       # nothing trusted: the smallest estimated index error, then the most runs
                k = min(range(len(self.stages)), key=lambda i: (_worst_error(self.stages[i][0], out),
                                                                -self.stages[i][0].n_evals, -i))
            res, label = self.stages[k]
            table = res.indices[res.indices["output"] == out].copy()
            table["source"] = res.method
            tables.append(table)
            diags += [d for d in res.diagnostics if d.output in (None, out)]
            for r, lab in self.stages[:k]:
                fired = sorted({d.name for d in r.diagnostics if d.severity == "untrusted" and d.output in (None, out)})
                diags.append(Diagnostic("auto_escalated", f"output {out!r}: {lab} untrusted ({', '.join(fired)}); "
                                        "escalated", "info", output=out))
            if not table["trusted"].all():
                diags.append(Diagnostic("auto_budget_exhausted", f"output {out!r}: no stage trusted within the "
                                        f"budget of {self.options['budget']} runs; the numbers are {label}'s",
                                        "untrusted", output=out))
        indices = pd.concat(tables, ignore_index=True)
        diags = _dedupe(diags)
        indices["trusted"] = indices["trusted"].to_numpy(bool) & trusted_mask(indices, diags)
        self.result = SobolResult(indices, n_evals=self.x.shape[0], method="auto", options=dict(self.options),
                                  diagnostics=diags,
                                  extras={"auto_log": list(self.log), "stages": [lab for _, lab in self.stages]})
        self._pending = None


def _worst_error(res: SobolResult, output: str) -> float:
    """Largest estimated index error of ``output``'s rows (inf if another diagnostic distrusts them)."""
    worst = 0.0
    for d in res.diagnostics:
        if d.severity == "untrusted" and d.output in (None, output):
            worst = max(worst, d.value if d.name.endswith("index_error") and np.isfinite(d.value) else np.inf)
    return worst


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
