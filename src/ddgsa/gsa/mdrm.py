"""Multiplicative dimensional reduction (M-DRM) with Gauss quadrature, and its self-checks.

With cut point :math:`c`, M-DRM approximates
:math:`h(x) \\approx h(c)^{1-n} \\prod_i h_i(x_i)` with
:math:`h_i(x_i) = h(c_1, \\dots, x_i, \\dots, c_n)`. With :math:`\\rho_i = E[h_i]` and
:math:`\\theta_i = E[h_i^2]` (one-dimensional Gauss quadratures in the measure of
:math:`X_i`; Gauss-Legendre for uniform, Gauss-Hermite for normal inputs, chaospy's
rules for lognormal and truncated normal, an exact Stieltjes rule for triangular:
see :mod:`ddgsa.quadrature`):

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
``mdrm_rho_nonpositive``       untrusted some rho_i <= 0
``mdrm_zero_variance``         untrusted no cut function varies on its nodes (indices 0/0)
``mdrm_near_zero``             warning   min |h| over the nodes < ``near_zero`` x max |h|
``mdrm_unresolved``            untrusted the orthogonal-polynomial spectrum of some h_i does
                                         not decay (top two orders hold more than
                                         ``resolution_tol`` of its variance; points >= 5;
                                         inputs with >= 1 % of the cut-function variance)
``mdrm_quadrature_coverage``   warning   more than 25 % of an input's probability lies
                                         beyond its outermost node (heavy tails);
                                         untrusted beyond 50 % (a node past the median)
``mdrm_check_r2``              untrusted check sample: R^2 of the multiplicative surrogate
                                         < ``check_r2``
``mdrm_check_variance``        untrusted check sample: |Var(surrogate) - Var(h)| / Var(h)
                                         > ``check_variance``
=============================  ========  =====================================================

The check sample (``check`` scrambled-Sobol' points, default 32) is the only test that
sees interactions (e.g. Ishigami shifted to be positive); set ``check=0`` to skip it.
"""

from __future__ import annotations

from typing import Any

import chaospy
import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import BarycentricInterpolator

from ddgsa.errors import MethodError
from ddgsa.gsa.base import (Design, GsaMethod, PartialIndices, check_fraction, check_int,
                            register)
from ddgsa.gsa.result import Diagnostic
from ddgsa.quadrature import gauss_rule
from ddgsa.space import ParameterSpace

_TAIL_LIMIT = 0.25
_TAIL_UNTRUSTED = 0.5


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
    check_r2, check_variance, near_zero, resolution_tol : float
        Diagnostic thresholds (0.9, 0.2, 0.01, 0.01).
    """

    defaults = {"points": 5, "cut": None, "check": 32, "seed": 0, "check_r2": 0.9,
                "check_variance": 0.2, "near_zero": 0.01, "resolution_tol": 0.01}

    def check_options(self, space: ParameterSpace, opts: dict[str, Any]) -> None:
        check_int(self.name, "points", opts["points"], 2, 40)
        check_int(self.name, "check", opts["check"], 0)
        check_int(self.name, "seed", opts["seed"], 0)
        check_fraction(self.name, "check_r2", opts["check_r2"], -1e9, 1.0)
        for key in ("check_variance", "near_zero", "resolution_tol"):
            check_fraction(self.name, key, opts[key], 0.0, 1e9)
        opts["cut"] = _resolve_cut(space, opts["cut"])

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

    def _analyze(self, space: ParameterSpace, design: Design, y: NDArray[np.float64],
                 outputs: list[str]) -> PartialIndices:
        opts = design.options
        n, n_nodes = space.dim, opts["points"]
        weights = np.stack(design.meta["weights"])                      # (n, N)
        h_c = y[0]                                                      # (k,)
        h = y[1:1 + n * n_nodes].reshape(n, n_nodes, -1)                # (n, N, k)
        rho = np.einsum("iq,iqk->ik", weights, h)                       # (n, k)
        var = np.einsum("iq,iqk->ik", weights, (h - rho[:, None, :]) ** 2)
        theta = var + rho ** 2
        with np.errstate(divide="ignore", invalid="ignore"):
            r = var / rho ** 2                                          # Var[h_i] / E[h_i]^2
            total = np.log1p(r).sum(axis=0)                             # log prod theta/rho^2
            S1 = (r / np.expm1(total)).T
            ST = ((r / (1.0 + r)) / -np.expm1(-total)).T
        diags = _value_diagnostics(space, outputs, h_c, h, rho, opts)
        for k in np.flatnonzero(~(np.abs(total) > 0)):
            # e.g. 2 nodes symmetric about the kink of |4x - 2| (Sobol G): every cut function is
            # flat on its nodes, so the indices are 0/0 -- an undefined answer, not a zero one
            diags.append(Diagnostic("mdrm_zero_variance", f"output {outputs[k]!r}: no cut function varies on "
                                    "its Gauss nodes; the indices are undefined (raise 'points')", "untrusted",
                                    output=outputs[k]))
        diags += _coverage_diagnostics(space, design)
        diags += _resolution_diagnostics(space, design, h, var, outputs, opts)
        extras: dict[str, Any] = {"rho": rho.T, "theta": theta.T, "h_cut": h_c}
        if opts["check"]:
            check_diags, metrics = _check_sample(space, design, y, outputs, opts)
            diags += check_diags
            extras.update(metrics)
        return PartialIndices(S1=S1, ST=ST, diagnostics=diags, extras=extras)


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
        for i in np.flatnonzero(~(rho[:, k] > 0)):
            diags.append(Diagnostic("mdrm_rho_nonpositive",
                                    f"output {out!r}: rho = E[h_i] = {rho[i, k]:.3g} <= 0 for "
                                    f"{space.names[i]!r}", "untrusted", output=out,
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
        basis = chaospy.generate_expansion(n_nodes - 1, p.distribution, normed=True)
        phi = np.asarray(basis(nodes), dtype=float)                    # (N, N) orders x nodes
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


def surrogate(space: ParameterSpace, design: Design, y: NDArray[np.float64],
              x: NDArray[np.float64]) -> NDArray[np.float64]:
    """The multiplicative surrogate h(c)^(1-n) prod h_i(x_i) at points ``x`` (m, n).

    Each cut function is the polynomial interpolating its Gauss nodes and the cut point.
    """
    n, n_nodes = space.dim, design.options["points"]
    cut = design.meta["cut"]
    h_c = y[0]
    log_abs = (1 - n) * np.log(np.abs(h_c))[None, :]
    sign = np.sign(h_c) ** (1 - n) * np.ones((x.shape[0], 1))
    for i in range(n):
        nodes = design.meta["nodes"][i]
        vals = y[1 + i * n_nodes:1 + (i + 1) * n_nodes]
        if np.min(np.abs(nodes - cut[i])) > 1e-12 * max(1.0, abs(cut[i])):
            nodes = np.append(nodes, cut[i])
            vals = np.vstack([vals, h_c[None, :]])
        hi = np.asarray(BarycentricInterpolator(nodes, vals)(x[:, i]), dtype=float).reshape(len(x), -1)
        log_abs = log_abs + np.log(np.abs(hi))
        sign = sign * np.sign(hi)
    return sign * np.exp(log_abs)


def _check_sample(space: ParameterSpace, design: Design, y: NDArray[np.float64], outputs: list[str],
                  opts: dict[str, Any]) -> tuple[list[Diagnostic], dict[str, Any]]:
    """Compare the surrogate with the true outputs on the check sample."""
    m = opts["check"]
    x_chk, y_chk = design.points[-m:], y[-m:]
    with np.errstate(all="ignore"):
        pred = surrogate(space, design, y, x_chk)
        sst = ((y_chk - y_chk.mean(axis=0)) ** 2).sum(axis=0)
        r2 = 1.0 - ((y_chk - pred) ** 2).sum(axis=0) / sst
        var_err = np.abs(pred.var(axis=0) - y_chk.var(axis=0)) / y_chk.var(axis=0)
    diags = []
    for k, out in enumerate(outputs):
        if sst[k] == 0.0:
            continue
        if not r2[k] >= opts["check_r2"]:
            diags.append(Diagnostic("mdrm_check_r2",
                                    f"output {out!r}: the multiplicative surrogate explains R^2 = {r2[k]:.3f} "
                                    f"of the check sample ({m} points; need >= {opts['check_r2']}); the "
                                    "output is not a product of one-variable functions (interactions?)",
                                    "untrusted", output=out, value=float(r2[k])))
        if not var_err[k] <= opts["check_variance"]:
            diags.append(Diagnostic("mdrm_check_variance",
                                    f"output {out!r}: surrogate variance is off by {var_err[k]:.1%} on the "
                                    f"check sample (allowed {opts['check_variance']:.0%})",
                                    "untrusted", output=out, value=float(var_err[k])))
    return diags, {"check_r2": r2, "check_variance_error": var_err}
