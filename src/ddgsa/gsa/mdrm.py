"""Multiplicative dimensional reduction (M-DRM) with Gauss quadrature, and its self-checks.

With cut point :math:`c`, M-DRM approximates
:math:`h(x) \\approx h(c)^{1-n} \\prod_i h_i(x_i)` with
:math:`h_i(x_i) = h(c_1, \\dots, x_i, \\dots, c_n)`. With :math:`\\rho_i = E[h_i]` and
:math:`\\theta_i = E[h_i^2]` (one-dimensional Gauss quadratures in the measure of
:math:`X_i`; Gauss-Legendre for uniform, Gauss-Hermite for normal inputs, chaospy's
rules for lognormal and truncated normal, an exact Stieltjes rule for triangular:
see :mod:`ddgsa.gsa.quadrature`):

.. math::

    S_i = \\frac{\\theta_i/\\rho_i^2 - 1}{\\prod_k \\theta_k/\\rho_k^2 - 1}, \\qquad
    S_{T,i} = \\frac{1 - \\rho_i^2/\\theta_i}{1 - \\prod_k \\rho_k^2/\\theta_k}

for :math:`nN + 1` evaluations (Zhang & Pandey 2014, *Probab. Eng. Mech.* 38; seed 001 §3).
Computed here as :math:`r_i = \\mathrm{Var}[h_i]/\\rho_i^2`,
:math:`S_i = r_i / \\mathrm{expm1}(\\sum_k \\log1p\\, r_k)` and
:math:`S_{T,i} = (r_i/(1+r_i)) / -\\mathrm{expm1}(-\\sum_k \\log1p\\, r_k)`, which keeps
precision for small variances and does not overflow for many parameters.

M-DRM is exact for products of one-variable functions and can be badly wrong elsewhere.
Its diagnostics (all named, all in ``result.diagnostics``):

=============================  ========  =====================================================
name                           severity  fires when
=============================  ========  =====================================================
``mdrm_cut_value``             untrusted h(c) is zero or not finite
``mdrm_sign_change``           untrusted the output changes sign over the quadrature nodes
``mdrm_rho_sign``              untrusted some rho_i = E[h_i] is zero or of the other sign than
                                         h(c) (a sign-consistent output, all negative
                                         included, is as good as a positive one)
``mdrm_zero_variance``         untrusted no cut function varies on its nodes (indices 0/0); the
                                         message says when the check sample varies (a
                                         limit no input axis reaches: use saltelli)
``mdrm_indicator``             info      a two-valued output (an exceedance indicator) is
                                         analysed as the indicator of its cut-point value
                                         (same indices; h(c) = 1 instead of 0)
``mdrm_near_zero``             warning   min |h| over the nodes < ``near_zero`` x max |h|
``mdrm_unresolved``            untrusted the orthogonal-polynomial spectrum of some h_i does
                                         not decay (top two orders hold more than
                                         ``resolution_tol`` of its variance; points >= 5;
                                         inputs with >= 1 % of the cut-function variance)
``mdrm_quadrature_coverage``   warning   more than 25 % of an input's probability lies
                                         beyond its outermost node (heavy tails);
                                         untrusted beyond 50 % (a node past the median)
``mdrm_index_error``           untrusted the check sample's estimate of the index error of a row
                                         exceeds ``tolerance`` (see below)
``mdrm_unchecked``             untrusted ``check`` < 8: no estimate of the index error exists
=============================  ========  =====================================================

**The index-error estimate.** The M-DRM indices are exactly the Sobol indices of the surrogate
:math:`g(x) = h(c)^{1-n} \\prod_i p_i(x_i)`, :math:`p_i` the polynomial interpolating
:math:`h_i` on its Gauss nodes (the N-node rule integrates :math:`p_i^2`, degree 2N - 2,
exactly). On the check sample (``check`` scrambled-Sobol' points, default 32) the output is
regressed on :math:`a g + b`; the residual variance, raised to its one-sided
``_CHECK_CONFIDENCE`` chi-square bound, gives :math:`\\delta`, and
:func:`ddgsa.gsa.trust.surrogate_index_error` turns :math:`\\delta / \\mathrm{sd}(a g)` into a
bound on every index. The check sample is the only test that sees interactions (Ishigami
shifted to be positive, Bratley's K function + 20); without it (``check < 8``) no row is trusted.

**The cross-check** (zero extra runs). That bound is a worst case: it lets the whole residual
turn one row's index, and an output that is near-additive rather than near-multiplicative
(``0.5 + x1 + 0.8 x2 + ...``: indices right to 0.008, bound 0.13) is never trusted by it. So a
sparse PCE (:mod:`ddgsa.gsa.pooled`) is fitted on the same points (cut lines and check sample at
their input values), its leave-one-out error taken over the check sample only, and its rows
bounded by the PCE's own rule; by the triangle inequality ``|S - S_pce| + e_pce`` bounds M-DRM's
error as well, and each index keeps the smaller of the two bounds (``extras["cross_S1"]``,
``extras["cross_ST"]`` hold the PCE's indices; NaN for an output whose rows the check sample
already vouches for, which is not cross-checked). A row is thus trusted when either estimate
vouches for M-DRM's value; the other rules (sign change, unresolved cut functions, coverage)
still refuse it.

**The inert check** (:meth:`MDRM.followup`, option ``inert_check``, default on): a cut function flat
on its nodes gives an input indices of exactly 0 that the cut lines cannot vouch for (an interaction
``x_i (x_j - c_j)`` vanishes on them). Where such rows are untrusted, a second round redraws all those
inputs at once at the check points (``check`` more runs, :mod:`ddgsa.gsa.inert`); every pair equal to
round-off proves them inert (error 0), any difference proves nothing (``mdrm_inert_check`` says which).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray
from scipy.interpolate import BarycentricInterpolator
from scipy.stats import chi2

from ddgsa.errors import MethodError
from ddgsa.gsa.base import Design, GsaMethod, PartialIndices, as_value_matrix, check_fraction, check_int, register
from ddgsa.gsa.groups import GroupIndices, product_form
from ddgsa.gsa.inert import group_test, partners
from ddgsa.gsa.pooled import pooled_pce
from ddgsa.gsa.result import Diagnostic, index_error_rule, trusted_mask
from ddgsa.gsa.trust import DEFAULT_TOLERANCE, check_tolerance, error_diagnostics, surrogate_index_error
from ddgsa.gsa.quadrature import gauss_rule
from ddgsa.gsa.space import ParameterSpace

_TAIL_LIMIT = 0.25
_TAIL_UNTRUSTED = 0.5
_MIN_CHECK = 8
_PARTNER_SEED = 7919
"""Added to ``seed`` for the inert check's fresh columns (a draw apart from the check sample's)."""
# one-sided confidence of the residual-variance bound (calibrated by ``ddgsa bench trust``)
_CHECK_CONFIDENCE = 0.95


@register("mdrm")
class MDRM(GsaMethod):
    """M-DRM Sobol indices by Gauss quadrature (see the module docstring).

    Options
    -------
    points : int
        Gauss nodes per input (N), default 5; cost ``n N + 1`` plus ``check``.
    cut : dict or sequence, optional
        Cut point (parameter -> value); default the input means.
    check : int
        Size of the quasi-random check sample, default 32 (0 to skip).
    seed : int
        Seed of the check sample.
    tolerance : float
        Absolute error allowed on every index of a trusted row, default 0.02.
    near_zero, resolution_tol : float
        Diagnostic thresholds (0.01, 0.01).
    inert_check : bool
        Default True: where some inputs' rows are untrusted zeros (cut functions flat on their nodes),
        a second round of ``check`` runs bounds their interactions (:mod:`ddgsa.gsa.inert`,
        :meth:`followup`).
    """

    sobol_sizes = ("check",)
    defaults = {"points": 5, "cut": None, "check": 32, "seed": 0, "tolerance": DEFAULT_TOLERANCE,
                "near_zero": 0.01, "resolution_tol": 0.01, "inert_check": True}

    centre = False
    gives_groups = True

    def unscale_extras(self, extras: dict[str, Any], shift: NDArray[np.float64],
                       scale: NDArray[np.float64]) -> dict[str, Any]:
        """``rho``, ``theta`` and ``h_cut`` back in the output's units (the rest is relative)."""
        out = dict(extras)
        out["rho"] = extras["rho"] * scale[:, None]
        out["theta"] = extras["theta"] * scale[:, None] ** 2
        out["h_cut"] = extras["h_cut"] * scale
        return out

    def check_options(self, space: ParameterSpace, opts: dict[str, Any]) -> None:
        check_int(self.name, "points", opts["points"], 2, 40)
        check_int(self.name, "check", opts["check"], 0)
        check_int(self.name, "seed", opts["seed"], 0)
        check_tolerance(self.name, opts["tolerance"])
        for key in ("near_zero", "resolution_tol"):
            check_fraction(self.name, key, opts[key], 0.0, 1e9)
        if not isinstance(opts["inert_check"], (bool, np.bool_)):
            raise MethodError(f"method 'mdrm': option 'inert_check' must be true or false, got {opts['inert_check']!r}")
        opts["cut"] = _resolve_cut(space, opts["cut"])

    def _n_points(self, space: ParameterSpace, opts: dict[str, Any]) -> int:
        return 1 + space.dim * opts["points"] + opts["check"]

    def _design(self, space: ParameterSpace, opts: dict[str, Any]) -> Design:
        n_nodes = opts["points"]
        cut = np.asarray(opts["cut"], dtype=float)
        rules = [gauss_rule(p, n_nodes) for p in space.parameters]
        blocks = [cut[None, :]]
        for i, (nodes, _) in enumerate(rules):
            block = np.repeat(cut[None, :], n_nodes, axis=0)
            block[:, i] = nodes
            blocks.append(block)
        if opts["check"]:
            blocks.append(space.sample(opts["check"], seed=opts["seed"], rule="sobol"))
        meta = {"nodes": [r[0] for r in rules], "weights": [r[1] for r in rules], "cut": cut}
        opts = {**opts, "cut": dict(zip(space.names, cut.tolist()))}
        return Design(self.name, np.vstack(blocks), opts, meta)

    def followup(self, space: ParameterSpace, design: Design,
                 values: NDArray[np.float64] | pd.DataFrame | pd.Series,
                 outputs: Sequence[str] | None = None) -> Design | None:
        """The inert check's partners (:mod:`ddgsa.gsa.inert`): the check sample with the columns of the
        inputs drawn anew whose cut functions are flat on their nodes for every output (M-DRM's
        indices exactly 0) and whose rows are untrusted for some; None when there are none, ``inert_check``
        is off or the check sample is under :data:`_MIN_CHECK` points. (A group that holds one live
        input proves nothing, so an input with any effect on its cut lines stays out of it.)"""
        opts = design.options
        if not opts.get("inert_check") or opts["check"] < _MIN_CHECK or "inert" in design.meta:
            return None
        y, _ = as_value_matrix(values, design.n_points, outputs)
        n_nodes = opts["points"]
        lines = y[1:1 + space.dim * n_nodes].reshape(space.dim, n_nodes, -1)
        if not (np.ptp(lines, axis=1) == 0).all(axis=1).any():
            return None              # no cut function flat on its nodes (the only zeros): spare the analysis below
        t = self.analyze(space, design, values, outputs).indices
        st = t["ST"].to_numpy(float).reshape(-1, space.dim)
        trusted = t["trusted"].to_numpy(bool).reshape(-1, space.dim)
        with np.errstate(invalid="ignore"):
            group = np.flatnonzero((st == 0.0).all(axis=0) & (~trusted).any(axis=0))
        if group.size == 0:
            return None
        start = design.n_points - opts["check"]
        extra = partners(space, design.points[start:], group.tolist(), opts["seed"] + _PARTNER_SEED)
        meta = {**design.meta, "inert": {"group": group, "base": start, "n": design.n_points}}
        return Design(self.name, np.vstack([design.points, extra]), opts, meta)

    def _analyze(self, space: ParameterSpace, design: Design, y: NDArray[np.float64],
                 outputs: list[str]) -> PartialIndices:
        if "inert" in design.meta:
            return self._with_inert_check(space, design, y, outputs)
        opts = design.options
        n, n_nodes = space.dim, opts["points"]
        y, span, indicators = _indicator_of_cut_value(y, outputs)
        weights = np.stack(design.meta["weights"])                      # (n, N)
        h_c = y[0]                                                      # (k,)
        h = y[1:1 + n * n_nodes].reshape(n, n_nodes, -1)                # (n, N, k)
        rho = np.einsum("iq,iqk->ik", weights, h)                       # (n, k)
        var = np.einsum("iq,iqk->ik", weights, (h - rho[:, None, :]) ** 2)
        var[np.ptp(h, axis=1) == 0] = 0.0         # flat on its nodes: no round-off variance (weights sum to 1 - eps)
        theta = var + rho ** 2
        with np.errstate(divide="ignore", invalid="ignore"):
            r = var / rho ** 2                                          # Var[h_i] / E[h_i]^2
            total = np.log1p(r).sum(axis=0)                             # log prod theta/rho^2
            S1 = (r / np.expm1(total)).T
            ST = ((r / (1.0 + r)) / -np.expm1(-total)).T
        diags = indicators + _value_diagnostics(space, outputs, h_c, h, rho, opts)
        checked = y[1 + n * n_nodes:]
        for k in np.flatnonzero(~(np.abs(total) > 0)):
            # e.g. 2 nodes symmetric about the kink of |4x - 2| (Sobol G): every cut function is
            # flat on its nodes, so the indices are 0/0 -- an undefined answer, not a zero one
            if len(checked) and np.ptp(checked[:, k]) > 0:      # a limit no input axis through c reaches
                why = ("the output varies on the check sample but along no input axis through the cut point "
                       "(a threshold or limit the axes do not reach): M-DRM cannot see what moves it; analyse it "
                       "with saltelli (hsic to screen), or move 'cut' to where the axes cross the limit")
            else:
                why = "no cut function varies on its Gauss nodes; the indices are undefined (raise 'points')"
            diags.append(Diagnostic("mdrm_zero_variance", f"output {outputs[k]!r}: {why}", "untrusted",
                                    output=outputs[k]))
        diags += _coverage_diagnostics(space, design)
        diags += _resolution_diagnostics(space, design, h, var, outputs, opts)
        extras: dict[str, Any] = {"rho": rho.T, "theta": theta.T, "h_cut": h_c,
                                  "variance": _surrogate_variance(h_c, rho, var) * span ** 2}
        err_s1 = err_st = np.full_like(S1, np.nan)
        groups = None
        if space.groups:
            closed, total = product_form(r, [m for _, m in space.group_members()])
            groups = GroupIndices(closed, total, np.full_like(closed, np.nan), np.full_like(total, np.nan))
        if opts["check"] >= _MIN_CHECK:
            eps, r2 = _check_sample(space, design, y, rho, var)
            err_s1 = surrogate_index_error(S1, eps[:, None], orthogonal=True)
            err_st = surrogate_index_error(ST, eps[:, None], orthogonal=True)
            if groups is not None:
                groups.S_closed_conf = surrogate_index_error(groups.S_closed, eps[:, None], orthogonal=True)
                groups.ST_conf = surrogate_index_error(groups.ST, eps[:, None], orthogonal=True)
            why = f"check sample of {opts['check']} points"
            # outputs some row (or group) of which the check sample cannot vouch for (the others need no
            # second bound)
            with np.errstate(invalid="ignore"):
                worst = np.fmax(err_s1, err_st).max(axis=1, initial=0.0)
                if groups is not None:
                    worst = np.fmax(worst, np.fmax(groups.S_closed_conf, groups.ST_conf).max(axis=1, initial=0.0))
                loose = np.flatnonzero(~(worst <= opts["tolerance"]))
            cross = _cross_check(space, design, y[:, loose], [outputs[k] for k in loose], opts["tolerance"]) \
                if loose.size else None
            if cross is not None:
                # a second, independent bound: the distance to the cross-check's indices plus its
                # own bound (the triangle inequality); each row keeps the smaller of the two
                p1, pt = np.full_like(S1, np.nan), np.full_like(ST, np.nan)
                p1[loose], pt[loose], e1, et = cross.S1, cross.ST, cross.S1_error, cross.ST_error
                err_s1[loose] = np.fmin(err_s1[loose], np.abs(S1[loose] - p1[loose]) + e1)
                err_st[loose] = np.fmin(err_st[loose], np.abs(ST[loose] - pt[loose]) + et)
                if groups is not None and cross.groups is not None:
                    g = cross.groups
                    groups.S_closed_conf[loose] = np.fmin(groups.S_closed_conf[loose],
                                                          np.abs(groups.S_closed[loose] - g.S_closed) + g.S_closed_conf)
                    groups.ST_conf[loose] = np.fmin(groups.ST_conf[loose], np.abs(groups.ST[loose] - g.ST) + g.ST_conf)
                why += "; cross-checked by a sparse PCE on the same points"
                extras.update({"cross_S1": p1, "cross_ST": pt})
            diags += error_diagnostics("mdrm_index_error", why, outputs, space.names, err_s1, err_st,
                                       opts["tolerance"])
            extras.update({"check_r2": r2, "surrogate_eps": eps})
        else:
            diags.append(Diagnostic("mdrm_unchecked", f"check sample of {opts['check']} points (< {_MIN_CHECK}): "
                                    "the index error cannot be estimated, no row is trusted; set check >= 32",
                                    "untrusted"))
        return PartialIndices(S1=S1, ST=ST, S1_conf=err_s1, ST_conf=err_st, diagnostics=diags, extras=extras,
                              groups=groups)


    def _with_inert_check(self, space: ParameterSpace, design: Design, y: NDArray[np.float64],
                          outputs: list[str]) -> PartialIndices:
        """The first round's indices; for an output where the inert check (:func:`ddgsa.gsa.inert.group_test`)
        finds every pair equal, its group's rows get error bound 0 and lose their ``mdrm_index_error``; an
        ``mdrm_inert_check`` note per output says what it found."""
        info = design.meta["inert"]
        n = info["n"]
        meta = {k: v for k, v in design.meta.items() if k != "inert"}
        part = self._analyze(space, Design(self.name, design.points[:n], design.options, meta), y[:n], outputs)
        group, pairs = info["group"], len(y) - n
        estimate, inert = group_test(y[info["base"]:n], y[n:])
        names = ", ".join(space.names[i] for i in group)
        diags = list(part.diagnostics)
        for k, out in enumerate(outputs):
            if inert[k]:
                for err, idx in ((part.S1_conf, part.S1), (part.ST_conf, part.ST)):
                    err[k, group] = np.abs(idx[k, group])
                found = f"every pair equal: inert (an effect on more than ~{3 / pairs:.0%} of the space ruled out)"
            else:
                found = (f"their total index {estimate[k]:.3g} is not zero: nothing is proven (a bound from "
                         f"{pairs} pairs is not trusted, docs/methods.md)")
            diags.append(Diagnostic("mdrm_inert_check", f"output {out!r}: {names} drawn anew at {pairs} check "
                                    f"points; {found}", "info", output=out, value=float(estimate[k])))
        proven = {(outputs[k], space.names[i]) for k in np.flatnonzero(inert) for i in group}
        diags = [d for d in diags if not (d.name == "mdrm_index_error" and (d.output, d.parameter) in proven)]
        extras = {**part.extras, "inert_group": [space.names[i] for i in group], "inert_estimate": estimate,
                  "inert": inert}
        return PartialIndices(S1=part.S1, ST=part.ST, S1_conf=part.S1_conf, ST_conf=part.ST_conf, diagnostics=diags,
                              extras=extras, groups=part.groups)


def _indicator_of_cut_value(y: NDArray[np.float64], outputs: list[str]) -> tuple[NDArray[np.float64],
                                                                                   NDArray[np.float64],
                                                                                   list[Diagnostic]]:
    """``y`` with each two-valued column (an exceedance indicator, :mod:`ddgsa.gsa.target`) replaced by the
    indicator of its value at the cut point (row 0), the factor (k,) that takes the new column's variance
    back to the old's (the squared gap of the two values; 1 for the others), and an ``mdrm_indicator``
    note for each.

    An affine map leaves Sobol indices unchanged, and this one makes ``h(c) = 1``: M-DRM's product
    ``h(c)^(1-n) prod h_i`` is undefined for the exceedance indicator itself wherever the cut point
    lies within the limit (``h(c) = 0``), the usual case for a limit in the output's tail.
    """
    out = y.copy()
    span = np.ones(y.shape[1])
    diags = []
    for k in range(y.shape[1]):
        values = np.unique(y[:, k])
        if values.size != 2:
            continue
        out[:, k] = (y[:, k] == y[0, k]).astype(float)
        span[k] = values[1] - values[0]
        diags.append(Diagnostic("mdrm_indicator", f"output {outputs[k]!r} takes two values: analysed as 1 where it "
                                "equals its value at the cut point, 0 elsewhere (the same Sobol indices, and "
                                "non-zero at the cut point as M-DRM needs)", "info", output=outputs[k]))
    return out, span, diags


def _resolve_cut(space: ParameterSpace, cut: Any) -> list[float]:
    """Cut point as a list in the space's order (default: the means)."""
    if cut is None:
        return space.means.tolist()
    if isinstance(cut, dict):
        unknown = set(cut) - set(space.names)
        if unknown:
            raise MethodError(f"method 'mdrm': option 'cut' names unknown parameter(s) {sorted(unknown)}; "
                              f"known: {', '.join(space.names)}")
        return [float(cut.get(p.name, p.mean)) for p in space.parameters]
    values = np.asarray(cut, dtype=float).ravel()
    if values.size != space.dim:
        raise MethodError(f"method 'mdrm': option 'cut' needs {space.dim} values, got {values.size}")
    return values.tolist()


def _value_diagnostics(space: ParameterSpace, outputs: list[str], h_c: NDArray[np.float64],
                       h: NDArray[np.float64], rho: NDArray[np.float64],
                       opts: dict[str, Any]) -> list[Diagnostic]:
    """Cut value, sign, positivity and near-zero checks, per output."""
    diags = []
    for k, out in enumerate(outputs):
        vals = np.concatenate([[h_c[k]], h[:, :, k].ravel()])
        scale = np.max(np.abs(vals))
        if not np.isfinite(h_c[k]) or abs(h_c[k]) <= 1e-12 * scale or scale == 0.0:
            diags.append(Diagnostic("mdrm_cut_value",
                                    f"output {out!r}: h(c) = {h_c[k]:.3g} at the cut point; M-DRM needs "
                                    "h(c) != 0 (the multiplicative surrogate is undefined)",
                                    "untrusted", output=out, value=float(h_c[k])))
        if vals.min() < 0.0 < vals.max():
            diags.append(Diagnostic("mdrm_sign_change",
                                    f"output {out!r} changes sign over the quadrature nodes "
                                    f"(min {vals.min():.3g}, max {vals.max():.3g}); M-DRM assumes a "
                                    "one-signed output", "untrusted", output=out))
        elif scale > 0 and np.min(np.abs(vals)) < opts["near_zero"] * scale:
            diags.append(Diagnostic("mdrm_near_zero",
                                    f"output {out!r} comes near zero on the nodes "
                                    f"(min|h|/max|h| = {np.min(np.abs(vals)) / scale:.2g}); indices are "
                                    "sensitive to the cut point", "warning", output=out,
                                    value=float(np.min(np.abs(vals)) / scale)))
        for i in np.flatnonzero(~(rho[:, k] * np.sign(h_c[k]) > 0)):
            diags.append(Diagnostic("mdrm_rho_sign",
                                    f"output {out!r}: rho = E[h_i] = {rho[i, k]:.3g} for {space.names[i]!r} "
                                    f"is zero or of the other sign than h(c) = {h_c[k]:.3g}", "untrusted", output=out,
                                    parameter=space.names[i], value=float(rho[i, k])))
    return diags


def _coverage_diagnostics(space: ParameterSpace, design: Design) -> list[Diagnostic]:
    """Inputs whose outermost nodes leave much probability uncovered (heavy tails)."""
    diags = []
    for p, nodes in zip(space.parameters, design.meta["nodes"]):
        lo, hi = p.cdf(np.array([nodes.min(), nodes.max()]))
        tail = max(float(lo), float(1.0 - hi))
        if tail > _TAIL_LIMIT:
            # beyond half, a node sits past the median: the rule no longer samples the bulk of the
            # input (lognormal sigma = 1, 5 nodes: 56 % below the smallest node, 0.05 index error
            # on an additive function, measured, that the 32-point check sample does not see)
            bulk = tail > _TAIL_UNTRUSTED
            diags.append(Diagnostic("mdrm_quadrature_coverage",
                                    f"{p.name!r}: {tail:.0%} of its probability lies beyond the outermost "
                                    f"Gauss node ({p.dist}, heavy tail?); the quadrature relies on moments only"
                                    + ("; the nodes miss the bulk of the distribution" if bulk else ""),
                                    "untrusted" if bulk else "warning", parameter=p.name, value=tail))
    return diags


def _resolution_diagnostics(space: ParameterSpace, design: Design, h: NDArray[np.float64],
                            var: NDArray[np.float64], outputs: list[str], opts: dict[str, Any]) -> list[Diagnostic]:
    """Spectral decay of each h_i in its orthonormal polynomials (points >= 5).

    Only inputs carrying at least 1 % of the summed cut-function variance are judged: the
    spectrum of a nearly flat cut function is round-off and model noise, and its error cannot
    move any index.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        share = var / var.sum(axis=0, keepdims=True)                   # (n, k)
    n_nodes = opts["points"]
    if n_nodes < 5:
        return []
    diags = []
    for i, p in enumerate(space.parameters):
        nodes, weights = design.meta["nodes"][i], design.meta["weights"][i]
        phi = _orthonormal_at_nodes(nodes, weights)                    # (N, N) orders x nodes
        coef = phi @ (weights[:, None] * h[i])                         # (N, k)
        energy = coef[1:] ** 2
        total = energy.sum(axis=0)
        scale = np.abs(coef[0]) + 1e-300
        with np.errstate(divide="ignore", invalid="ignore"):
            frac = energy[-2:].sum(axis=0) / total
        # a cut function that is constant to round-off has no spectrum to judge
        varies = np.sqrt(total) > 1e-10 * scale
        for k in np.flatnonzero((frac > opts["resolution_tol"]) & varies & (share[i] >= 0.01)):
            diags.append(Diagnostic("mdrm_unresolved",
                                    f"output {outputs[k]!r}: the cut function of {p.name!r} is not resolved "
                                    f"by {n_nodes} nodes ({frac[k]:.1%} of its variance in the two highest "
                                    "polynomial orders; non-smooth output?); raise 'points'",
                                    "untrusted", output=outputs[k], parameter=p.name, value=float(frac[k])))
    return diags


def _orthonormal_at_nodes(nodes: NDArray[np.float64], weights: NDArray[np.float64]) -> NDArray[np.float64]:
    """Orthonormal polynomials of degree 0..N-1 of the input's measure at its N Gauss nodes, (N, N).

    The Gauss rule is exact up to degree 2N - 1, so the polynomials orthonormal for the discrete
    measure (nodes, weights) are the measure's own; the discrete Stieltjes recurrence builds them
    on the (standardised) nodes directly.
    """
    t = (nodes - weights @ nodes) / max(np.sqrt(weights @ (nodes - weights @ nodes) ** 2), 1e-300)
    n = len(nodes)
    phi = np.zeros((n, n))
    phi[0] = 1.0
    prev, b = np.zeros(n), 0.0
    for k in range(n - 1):
        a = weights @ (t * phi[k] ** 2)
        q = (t - a) * phi[k] - b * prev
        b = np.sqrt(weights @ q ** 2)
        prev, phi[k + 1] = phi[k], q / b
    return phi


def surrogate(space: ParameterSpace, design: Design, y: NDArray[np.float64],
              x: NDArray[np.float64]) -> NDArray[np.float64]:
    """The multiplicative surrogate h(c)^(1-n) prod p_i(x_i) at points ``x`` (m, n).

    ``p_i`` is the polynomial interpolating the cut function ``h_i`` on its Gauss nodes, so
    the M-DRM indices are exactly this surrogate's Sobol indices.
    """
    n, n_nodes = space.dim, design.options["points"]
    h_c = y[0]
    log_abs = (1 - n) * np.log(np.abs(h_c))[None, :]
    sign = np.sign(h_c) ** (1 - n) * np.ones((x.shape[0], 1))
    for i in range(n):
        nodes = design.meta["nodes"][i]
        vals = y[1 + i * n_nodes:1 + (i + 1) * n_nodes]
        hi = np.asarray(BarycentricInterpolator(nodes, vals)(x[:, i]), dtype=float).reshape(len(x), -1)
        log_abs = log_abs + np.log(np.abs(hi))
        sign = sign * np.sign(hi)
    return sign * np.exp(log_abs)


def _surrogate_variance(h_c: NDArray[np.float64], rho: NDArray[np.float64],
                        var: NDArray[np.float64]) -> NDArray[np.float64]:
    """Variance (k,) of the multiplicative surrogate, ``(E g)^2 (prod theta_i / rho_i^2 - 1)`` with
    ``E g = h(c)^(1-n) prod rho_i`` (exact from the quadrature; in logs, no overflow for many inputs)."""
    n = rho.shape[0]
    with np.errstate(all="ignore"):
        log_mean = (1 - n) * np.log(np.abs(h_c)) + np.log(np.abs(rho)).sum(axis=0)
        return np.exp(2.0 * log_mean) * np.expm1(np.log1p(var / rho ** 2).sum(axis=0))


@dataclass
class _Cross:
    """The cross-check's indices and error bounds (each (k, n); the groups' (k, G)), infinite where a
    rule other than the error estimate refuses the row (or the group's output)."""

    S1: NDArray[np.float64]
    ST: NDArray[np.float64]
    S1_error: NDArray[np.float64]
    ST_error: NDArray[np.float64]
    groups: GroupIndices | None


def _cross_check(space: ParameterSpace, design: Design, y: NDArray[np.float64], outputs: list[str],
                 tolerance: float) -> _Cross | None:
    """S1, ST and their error bounds of a sparse PCE fitted on M-DRM's own points, with its group indices.

    The cut lines and the check sample, each point at its input values, are one scattered design
    (:mod:`ddgsa.gsa.pooled`, of the degree it picks); the expansion's leave-one-out error is taken
    over the check sample only (the cut lines are fitted almost exactly by one-input terms and say
    nothing of interactions). Rows a rule other than the error estimate refuses carry an infinite
    bound, and so do the groups of an output such a rule refuses whole. None when the points are too
    few for even a linear expansion.
    """
    drawn = np.zeros(design.n_points, dtype=bool)
    drawn[-design.options["check"]:] = True
    res = pooled_pce(space, design.points, y, outputs, tolerance, drawn=drawn)
    if res is None:
        return None
    t = res.indices
    rules = [d for d in res.diagnostics if not index_error_rule(d.name)]
    usable = trusted_mask(t, rules)
    shape = (len(outputs), space.dim)

    def bound(values: NDArray[np.float64], ok: NDArray[np.bool_]) -> NDArray[np.float64]:
        e = np.where(ok, values, np.inf)
        return np.where(np.isfinite(e), e, np.inf)

    e1 = bound(t["S1_conf"].to_numpy(float), usable).reshape(shape)
    et = bound(t["ST_conf"].to_numpy(float), usable).reshape(shape)
    groups = None
    if len(res.groups):
        g = res.groups
        whole = {d.output for d in rules if d.severity == "untrusted" and d.parameter is None}
        ok = ~g["output"].isin(whole).to_numpy() & (None not in whole)
        gshape = (len(outputs), len(space.groups))
        groups = GroupIndices(g["S_closed"].to_numpy(float).reshape(gshape), g["ST"].to_numpy(float).reshape(gshape),
                              bound(g["S_closed_conf"].to_numpy(float), ok).reshape(gshape),
                              bound(g["ST_conf"].to_numpy(float), ok).reshape(gshape))
    return _Cross(t["S1"].to_numpy(float).reshape(shape), t["ST"].to_numpy(float).reshape(shape), e1, et, groups)


def _check_sample(space: ParameterSpace, design: Design, y: NDArray[np.float64], rho: NDArray[np.float64],
                  var: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Relative distance ``eps = delta / sd(a g)`` of the output from the surrogate, and the check R^2.

    ``delta`` is the residual standard deviation of the least-squares fit ``h ~ a g + b`` on the
    check sample, raised to the one-sided ``_CHECK_CONFIDENCE`` chi-square bound with ``m - 2``
    degrees of freedom; ``sd(g)`` is exact from the quadrature (``E g`` and ``Var g`` of a product).
    """
    m = design.options["check"]
    n = space.dim
    x_chk, y_chk = design.points[-m:], y[-m:]
    h_c = y[0]
    with np.errstate(all="ignore"):
        g = surrogate(space, design, y, x_chk)
        g_c = g - g.mean(axis=0)
        y_c = y_chk - y_chk.mean(axis=0)
        slope = (g_c * y_c).sum(axis=0) / (g_c ** 2).sum(axis=0)
        ssr = ((y_c - slope * g_c) ** 2).sum(axis=0)
        r2 = 1.0 - ssr / (y_c ** 2).sum(axis=0)
        delta = np.sqrt(ssr / chi2.ppf(1.0 - _CHECK_CONFIDENCE, m - 2))
        # sd(g) = |E g| sqrt(prod(theta/rho^2) - 1), E g = h(c)^(1-n) prod rho_i, in logs
        log_mean = (1 - n) * np.log(np.abs(h_c)) + np.log(np.abs(rho)).sum(axis=0)
        rel_var = np.expm1(np.log1p(var / rho ** 2).sum(axis=0))
        sd_g = np.abs(slope) * np.exp(log_mean) * np.sqrt(rel_var)
        eps = np.where(ssr == 0.0, 0.0, delta / sd_g)
    return np.where(np.isfinite(eps), eps, np.inf), r2
