"""Polynomial chaos expansion (PCE) Sobol indices, from the expansion's coefficients.

The basis is the total-degree set of products of one-dimensional orthonormal polynomials
(chaospy's three-term recurrences, one per input measure), so
:math:`\\mathrm{Var}\\, h = \\sum_{\\alpha \\ne 0} c_\\alpha^2`,
:math:`S_i = \\sum_{\\alpha \\in A_i} c_\\alpha^2 / \\mathrm{Var}` over multi-indices that
involve input *i* only and :math:`S_{T,i}` over those that involve it at all
(Sudret 2008, *Reliab. Eng. Syst. Saf.* 93).

Coefficients by ``fit="quadrature"`` (tensor Gauss rule, ``(order+1)^d`` points, spectral
projection), ``fit="regression"`` (least squares on a scrambled Sobol' sample of ``n`` points,
default the power of two at or above twice the number of terms) or ``fit="sparse"`` (least-angle
regression, scikit-learn's ``lars_path``, then least squares on each prefix of the active set;
the prefix with the smallest corrected leave-one-out error wins -- Blatman & Sudret 2011,
*J. Comput. Phys.* 230; default ``n`` the power of two at or above half the number of terms).

Trust (:mod:`ddgsa.gsa.trust`): the indices are exactly the expansion's, so the leave-one-out
error (the expansion's error on points it was not fitted to; for ``sparse`` with Chapelle's
correction ``n/(n - p) (1 + tr(C^-1)/n)`` for the selection; on a pooled design whose
``meta["drawn"]`` marks the points drawn from the input distribution, the mean square over those
only) times ``_LOO_FACTOR`` is taken as
the squared L2 distance between output and expansion, and
:func:`~ddgsa.gsa.trust.surrogate_index_error` bounds every index by it. Quadrature has no
leave-one-out error; the variance in the top order (the truncation, if the spectrum decays
no faster than geometrically) stands in for it. A full least-squares fit (``regression``) has a
second, tighter bound, second order in that distance (:func:`second_order_error`: the residual outside
the basis is orthogonal to every index's terms, so only the coefficients' own sampling error, their
HC3 covariance, enters at first order); each row keeps the smaller. Not for ``sparse``: conditional on
the selected terms that covariance ignores the selection and was measured to undercover (held-out
``block_sum_5010``, order 5 on 1 000 points, six seeds: the largest ST error 1.0-2.1 times the bound).

Diagnostics: ``pce_index_error`` (untrusted, per row: the bound exceeds ``tolerance``),
``pce_underdetermined`` (untrusted, regression: fewer points than basis terms).

Size guard: a regression matrix of more than ``_MAX_MATRIX_ENTRIES`` entries (``n`` x terms;
160 MB) is refused before any point is run, with the order that fits and the sparse option.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from itertools import combinations_with_replacement
from math import comb
from typing import Any

import chaospy
import numpy as np
from numpy.typing import NDArray

from ddgsa.errors import MethodError
from ddgsa.gsa.base import Design, GsaMethod, PartialIndices, check_choice, check_int, register
from ddgsa.gsa.groups import GroupIndices, from_coefficients, group_terms
from ddgsa.gsa.result import Diagnostic
from ddgsa.gsa.trust import DEFAULT_TOLERANCE, check_tolerance, error_diagnostics, surrogate_index_error
from ddgsa.gsa.space import ParameterSpace

_MAX_TENSOR_POINTS = 200_000
_MAX_MATRIX_ENTRIES = 20_000_000
# leave-one-out error -> squared L2 error of the expansion (calibrated by ``ddgsa bench trust``)
_LOO_FACTOR = 2.0
# standard errors of an index's sampling part in its second-order bound (at 3, one held-out row of a
# lognormal product was falsely trusted: docs/methods.md)
_SAMPLING_Z = 4.0


@dataclass(frozen=True)
class _Sampling:
    """One output's least-squares fit, kept for the sampling error of its indices.

    ``c = R^-1 Q^T y`` on the fitted columns ``cols`` (the constant first): with the
    heteroscedasticity-consistent (HC3: leave-one-out residuals ``e``) covariance
    ``Cov c = R^-1 Q^T diag(e^2) Q R^-T``, a linear function ``g^T c`` has the standard error
    ``|| diag(e) Q R^-T g ||``; ``qe`` is ``diag(e) Q`` (n, m), ``rinv`` is ``R^-1`` (m, m).
    """

    cols: NDArray[np.int64]
    qe: NDArray[np.float64]
    rinv: NDArray[np.float64]

    def index_sd(self, coef: NDArray[np.float64], parts: NDArray[np.bool_]) -> NDArray[np.float64]:
        """Standard errors of the indices ``S = sum_{part} c^2 / sum_{nonconstant} c^2`` (r,) by the delta
        method; ``coef`` (P,) holds every basis term's coefficient, ``parts`` (P, r) each index's terms
        (row 0, the constant, never in a part)."""
        c = coef[self.cols]
        live = self.cols != 0
        var = float(np.sum(c[live] ** 2))
        if not var > 0.0:
            return np.full(parts.shape[1], np.inf)
        inside = parts[self.cols].astype(float)                                # (m, r)
        s = (inside * c[:, None] ** 2).sum(axis=0) / var
        grad = 2.0 * c[:, None] * (inside - s) / var * live[:, None]           # dS/dc (m, r)
        return np.sqrt(((self.qe @ (self.rinv.T @ grad)) ** 2).sum(axis=0))


def second_order_error(index: NDArray[np.float64], sd: NDArray[np.float64],
                       rel_err2: NDArray[np.float64] | float) -> NDArray[np.float64]:
    """Error bound of a least-squares expansion's index: ``_SAMPLING_Z`` standard errors plus
    ``max(S, 1 - S) eps^2 / (1 + eps^2)`` [-].

    The true output is ``f = g + r``, ``g`` the fit. Split ``r`` into the part outside the fitted
    terms (L2-orthogonal to them) and the coefficients' own error ``e`` inside. An index's part of
    ``g`` is a sum of fitted terms, so the cross term of the part's variance with the outside part
    is zero and with ``e`` it is linear in ``e``: the first-order change of the index, whose
    standard error :meth:`_Sampling.index_sd` gives. What is left is second order: with ``b`` the
    outside part's energy (at most ``||r||^2 = eps^2 Var g``) and ``a`` in ``[0, b]`` its share in
    the index's terms, the index ``S = N / V`` becomes ``(N + a) / (V + b)``, a change of
    ``(a - S b) / (V + b)``: between ``-S`` and ``1 - S`` times ``eps^2 / (1 + eps^2)`` (both ends
    attained: the outside energy all in the index's terms, or none of it). ``S`` there is the index
    after the first-order change, so ``max(S, 1 - S)`` is widened by the standard errors' term
    (at most 1). Far tighter than :func:`~ddgsa.gsa.trust.surrogate_index_error`'s worst case
    (first order in ``eps``) when the fit is good; each row keeps the smaller.

    Parameters
    ----------
    index : array
        The expansion's index ``S`` [-].
    sd : array
        Standard error of its first-order (sampling) part, :meth:`_Sampling.index_sd` [-].
    rel_err2 : array or float
        ``eps^2``: the squared L2 distance between output and expansion over ``Var g`` [-].

    Returns
    -------
    array
        The bound on ``|S_true - S|`` [-]; NaN where ``index`` is not finite.

    Examples
    --------
    An index of 0.25 and ``eps^2 = 0.2``, no sampling error: the outside energy all in the
    index's terms moves it to ``(0.25 + 0.2) / 1.2 = 0.375``, a shift of 0.125: exactly the bound
    ``max(S, 1 - S) eps^2 / (1 + eps^2)`` (``eps^2 / (1 + eps^2)`` alone would say 0.167):

    >>> round(float(second_order_error(np.array([0.25]), np.array([0.0]), 0.2)[0]), 6)
    0.125
    """
    e2 = np.asarray(rel_err2, dtype=float)
    idx = np.asarray(index, dtype=float)
    first = _SAMPLING_Z * sd
    s = np.clip(idx, 0.0, 1.0)
    side = np.minimum(np.maximum(s, 1.0 - s) + first, 1.0)
    err = first + side * e2 / (1.0 + e2) + np.abs(idx - s)
    return np.where(np.isfinite(idx), err, np.nan)


def n_terms(dim: int, order: int) -> int:
    """Number of total-degree basis terms, ``C(dim + order, order)``."""
    return comb(dim + order, order)


def default_n(dim: int, order: int, fit: str = "regression") -> int:
    """Default regression sample: the power of two (Sobol' balance) >= 2 P (sparse: >= P / 2, >= 64)."""
    target = 2 * n_terms(dim, order) if fit == "regression" else max(64, n_terms(dim, order) // 2)
    return 1 << int(np.ceil(np.log2(target)))


def check_size(dim: int, order: int, n: int, fit: str = "regression") -> None:
    """Refuse a regression whose matrix (``n`` x terms) exceeds ``_MAX_MATRIX_ENTRIES``; name cheaper options."""
    p = n_terms(dim, order)
    if n * p <= _MAX_MATRIX_ENTRIES:
        return
    fits = [q for q in range(order - 1, 0, -1)
            if default_n(dim, q) * n_terms(dim, q) <= _MAX_MATRIX_ENTRIES]
    lower = (f"order {fits[0]} ({n_terms(dim, fits[0])} terms, {default_n(dim, fits[0])} points)"
             if fits else "no full order")
    n_sparse = _MAX_MATRIX_ENTRIES // p
    raise MethodError(f"method 'pce': fit {fit!r} of order {order} on {dim} inputs has {p} basis terms; with "
                      f"n = {n} points its matrix holds {n * p:.3g} entries ({8 * n * p / 1e9:.3g} GB), over "
                      f"the limit of {_MAX_MATRIX_ENTRIES:.3g} ({8 * _MAX_MATRIX_ENTRIES / 1e6:.0f} MB); use "
                      f"{lower}" + (f", or fit 'sparse' with n <= {n_sparse}" if n_sparse >= 2 * dim else ""))


def total_degree_indices(dim: int, order: int) -> NDArray[np.int64]:
    """All multi-indices of ``dim`` integers with sum <= ``order``, graded (shape (P, dim))."""
    rows = [np.zeros(dim, dtype=np.int64)]
    for degree in range(1, order + 1):
        for combo in combinations_with_replacement(range(dim), degree):
            alpha = np.zeros(dim, dtype=np.int64)
            np.add.at(alpha, list(combo), 1)
            rows.append(alpha)
    return np.array(rows)


@lru_cache(maxsize=256)
def _orthonormal(dist: str, args: tuple[tuple[str, float], ...], order: int) -> Any:
    """chaospy's orthonormal polynomials up to ``order`` for one input (cached: building them is slow)."""
    from ddgsa.gsa.space import Parameter

    return chaospy.generate_expansion(order, Parameter("p", dist, dict(args), 0.0).distribution, normed=True)


def _hermite_orthonormal(z: NDArray[np.float64], order: int) -> NDArray[np.float64]:
    """Orthonormal probabilists' Hermite polynomials He_k(z) / sqrt(k!), k = 0..order, at ``z``: (order+1, n)."""
    he = np.empty((order + 1, z.size))
    he[0] = 1.0
    if order >= 1:
        he[1] = z
    for k in range(1, order):
        he[k + 1] = z * he[k] - k * he[k - 1]
    return he / np.sqrt(np.cumprod(np.concatenate([[1.0], np.arange(1, order + 1)])))[:, None]


def basis_matrix(space: ParameterSpace, alphas: NDArray[np.int64], x: NDArray[np.float64]) -> NDArray[np.float64]:
    """Orthonormal product polynomials of multi-indices ``alphas`` at points ``x``: shape (n, P)."""
    order = int(alphas.max()) if alphas.size else 0
    psi = np.ones((x.shape[0], alphas.shape[0]))
    for i, p in enumerate(space.parameters):
        if p.dist == "lognormal":
            # Hermite polynomials of z = (ln x - mu) / sigma ~ N(0, 1): orthonormal to round-off,
            # where polynomials in x itself (moments exp(k^2 sigma^2 / 2)) lose orthogonality
            # for sigma ~ 1 and give wrong indices from a good fit (borehole's r: 1.0 for 0)
            z = (np.log(x[:, i]) - p.args["mu"]) / p.args["sigma"]
            psi *= _hermite_orthonormal(z, order)[alphas[:, i]].T
            continue
        polys = _orthonormal(p.dist, tuple(sorted(p.args.items())), order)
        phi = np.asarray(polys(x[:, i]), dtype=float).reshape(order + 1, -1)   # (order+1, n)
        psi *= phi[alphas[:, i]].T
    return psi


@register("pce")
class PCE(GsaMethod):
    """Sobol indices from a polynomial chaos expansion (see the module docstring).

    Options: ``order`` (total degree, default 4), ``fit`` (``regression``, ``sparse`` or
    ``quadrature``), ``n`` (regression sample size, default :func:`default_n`), ``seed``,
    ``tolerance`` (0.02).
    """

    sobol_sizes = ("n",)
    defaults = {"order": 4, "fit": "regression", "n": None, "seed": 0, "tolerance": DEFAULT_TOLERANCE}
    gives_groups = True

    def check_options(self, space: ParameterSpace, opts: dict[str, Any]) -> None:
        order = check_int(self.name, "order", opts["order"], 1, 30)
        fit = check_choice(self.name, "fit", opts["fit"], ("regression", "sparse", "quadrature"))
        check_int(self.name, "seed", opts["seed"], 0)
        check_tolerance(self.name, opts["tolerance"])
        if opts["fit"] == "quadrature":
            if opts["n"] is not None:
                raise MethodError("method 'pce': option 'n' applies to fit 'regression' only "
                                  "(quadrature uses (order+1)^d points)")
            if (order + 1) ** space.dim > _MAX_TENSOR_POINTS:
                raise MethodError(f"method 'pce': a tensor Gauss grid of order {order} in {space.dim} "
                                  f"dimensions needs {(order + 1) ** space.dim:.3g} points (limit "
                                  f"{_MAX_TENSOR_POINTS}); use fit 'regression'")
        else:
            n = check_int(self.name, "n", opts["n"], 2) if opts["n"] is not None else default_n(space.dim, order, fit)
            check_size(space.dim, order, n, fit)

    def _n_points(self, space: ParameterSpace, opts: dict[str, Any]) -> int:
        if opts["fit"] == "quadrature":
            return (opts["order"] + 1) ** space.dim
        return int(opts["n"]) if opts["n"] is not None else default_n(space.dim, opts["order"], opts["fit"])

    def _design(self, space: ParameterSpace, opts: dict[str, Any]) -> Design:
        if opts["fit"] == "quadrature":
            nodes, weights = chaospy.generate_quadrature(opts["order"], space.joint, rule="gaussian")
            x = np.asarray(nodes, dtype=float).reshape(space.dim, -1).T
            meta: dict[str, Any] = {"weights": np.asarray(weights, dtype=float)}
        else:
            n = opts["n"] if opts["n"] is not None else default_n(space.dim, opts["order"], opts["fit"])
            opts = {**opts, "n": int(n)}
            x = space.sample(int(n), seed=opts["seed"], rule="sobol")
            meta = {}
        return Design(self.name, x, opts, meta)

    def _analyze(self, space: ParameterSpace, design: Design, y: NDArray[np.float64],
                 outputs: list[str]) -> PartialIndices:
        opts = design.options
        alphas = total_degree_indices(space.dim, opts["order"])
        psi = basis_matrix(space, alphas, design.points)
        diags: list[Diagnostic] = []
        extras: dict[str, Any] = {"n_terms": len(alphas)}
        n_pts = psi.shape[0]
        sampling: list[_Sampling | None] = [None] * y.shape[1]
        if opts["fit"] == "quadrature":
            coef = psi.T @ (design.meta["weights"][:, None] * y)              # (P, k)
        elif opts["fit"] == "sparse":
            coef, loo = _sparse_fit(psi, y, design.meta.get("drawn"))
            extras["loo_error"] = loo
            extras["n_active"] = (coef != 0).sum(axis=0)
        else:
            coef, loo, sampling = _least_squares(psi, y, design.meta.get("drawn"))
            extras["loo_error"] = loo
            if n_pts < psi.shape[1]:
                diags.append(Diagnostic("pce_underdetermined", f"{n_pts} points for {psi.shape[1]} "
                                        "basis terms; raise 'n'", "untrusted"))
        energy = coef[1:] ** 2                                                 # (P-1, k)
        var = energy.sum(axis=0)
        involved = alphas[1:] > 0                                              # (P-1, d)
        alone = involved & (involved.sum(axis=1, keepdims=True) == 1)
        with np.errstate(divide="ignore", invalid="ignore"):
            S1 = (alone.T.astype(float) @ energy / var).T
            ST = (involved.T.astype(float) @ energy / var).T
            top = alphas[1:].sum(axis=1) == opts["order"]
            frac = energy[top].sum(axis=0) / var
            if opts["fit"] == "quadrature":
                rel_err2, why = frac, f"variance in the top order {opts['order']}"
            else:
                # delta^2 / Var(g): the LOO mean square over the expansion's own (population) variance,
                # not the sample's -- pooled designs (auto: M-DRM's Gauss nodes far in a lognormal
                # tail) have a sample variance that says little about the input distribution
                rel_err2 = _LOO_FACTOR * loo * np.var(y, axis=0) / var
                why = f"leave-one-out error on {n_pts} points"
            eps = np.where(np.isfinite(rel_err2) & (rel_err2 >= 0), np.sqrt(rel_err2), np.inf)
        extras["top_order_fraction"] = frac
        extras["variance"] = var                                                # sum of c^2 over alpha != 0
        err_s1 = _bound(S1, eps, sampling, coef, alone)
        err_st = _bound(ST, eps, sampling, coef, involved)
        diags += error_diagnostics("pce_index_error", why, outputs, space.names, err_s1, err_st,
                                   opts["tolerance"])
        groups = None
        if space.groups:
            members = [m for _, m in space.group_members()]
            closed, total = from_coefficients(alphas[1:], energy, members)
            inside, touches = group_terms(alphas[1:], members)
            groups = GroupIndices(closed, total, _bound(closed, eps, sampling, coef, inside),
                                  _bound(total, eps, sampling, coef, touches))
        return PartialIndices(S1=S1, ST=ST, S1_conf=err_s1, ST_conf=err_st, diagnostics=diags, extras=extras,
                              groups=groups)


def _bound(index: NDArray[np.float64], eps: NDArray[np.float64], sampling: list[_Sampling | None],
           coef: NDArray[np.float64], parts: NDArray[np.bool_]) -> NDArray[np.float64]:
    """Each index's (k, r) error bound: the smaller of the worst case
    (:func:`~ddgsa.gsa.trust.surrogate_index_error`) and, for a least-squares fit,
    :func:`second_order_error`; ``parts`` (P - 1, r) are the non-constant terms of each index."""
    worst = surrogate_index_error(index, eps[:, None])
    full = np.vstack([np.zeros((1, parts.shape[1]), dtype=bool), parts])
    for k, fit in enumerate(sampling):
        if fit is not None and np.isfinite(eps[k]):
            worst[k] = np.fmin(worst[k], second_order_error(index[k], fit.index_sd(coef[:, k], full), eps[k] ** 2))
    return worst


def _sparse_fit(psi: NDArray[np.float64], y: NDArray[np.float64],
                drawn: NDArray[np.bool_] | None = None) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Hybrid least-angle regression per output: coefficients (P, k) and corrected relative LOO errors (k,).

    The least-angle path orders the terms; one QR of the constant plus the terms in that order
    gives, for every prefix of the path, the least-squares fit, its leverages and
    ``tr(C^-1) = n ||R_m^-1||_F^2`` by cumulative sums, so all prefixes cost one factorisation.
    The prefix is chosen by the corrected LOO error over all points; ``drawn`` (a mask of the
    points drawn from the input distribution, e.g. M-DRM's check sample beside its cut lines)
    makes the returned error that of the chosen prefix over those points only: the mean square
    over a design that is mostly cut lines (fitted almost exactly by one-input terms) would
    understate the error under the input distribution.
    """
    from scipy.linalg import solve_triangular
    from sklearn.linear_model import lars_path

    n, p = psi.shape
    coef = np.zeros((p, y.shape[1]))
    loo = np.full(y.shape[1], np.inf)
    x = psi[:, 1:] - psi[:, 1:].mean(axis=0)
    for k in range(y.shape[1]):
        yk = y[:, k]
        _, active, _ = lars_path(x, yk - yk.mean(), method="lar", max_iter=min(p - 1, n // 3))
        cols = np.concatenate([[0], np.asarray(active, dtype=int) + 1])
        q, r = np.linalg.qr(psi[:, cols])
        proj = q.T @ yk                                                        # (m,)
        fitted = np.cumsum(q * proj, axis=1)                                   # (n, m): prefix fits
        lev = np.clip(np.cumsum(q ** 2, axis=1), 0.0, 1.0 - 1e-12)
        loo_sq = ((yk[:, None] - fitted) / (1.0 - lev)) ** 2 / np.var(yk)      # (n, m)
        press = np.mean(loo_sq, axis=0)
        rinv = solve_triangular(r, np.eye(len(cols)))
        # ||R_m^-1||_F^2 of each leading block (R^-1 is upper triangular: whole columns)
        tr = np.cumsum((rinv ** 2).sum(axis=0))
        m_terms = np.arange(1, len(cols) + 1)
        with np.errstate(divide="ignore", invalid="ignore"):
            corrected = press * n / np.clip(n - m_terms, 1, None) * (1.0 + tr)   # Chapelle: 1 + tr(C^-1)/n
        best = int(np.nanargmin(np.where(m_terms < n, corrected, np.inf)))
        loo[k] = corrected[best] if drawn is None else \
            corrected[best] * _mean_over(loo_sq[:, best], drawn) / max(press[best], 1e-300)
        c = solve_triangular(r[:best + 1, :best + 1], proj[:best + 1])
        coef[cols[:best + 1], k] = c
    return coef, loo

def _least_squares(psi: NDArray[np.float64], y: NDArray[np.float64], drawn: NDArray[np.bool_] | None = None
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64], list["_Sampling | None"]]:
    """Least-squares coefficients (P, k), relative leave-one-out errors (k,) and each output's
    :class:`_Sampling` from one QR factorisation (``drawn``: the mean square over those points only,
    as in :func:`_sparse_fit`); a rank-deficient or underdetermined fit has no sampling (None)."""
    from scipy.linalg import solve_triangular

    if psi.shape[0] > psi.shape[1]:
        q, r = np.linalg.qr(psi)
        diag = np.abs(np.diag(r))
        if diag.min() > 1e-10 * diag.max():
            coef = solve_triangular(r, q.T @ y)
            lev = np.clip((q ** 2).sum(axis=1), 0.0, 1.0 - 1e-12)
            with np.errstate(divide="ignore", invalid="ignore"):
                loo_resid = (y - psi @ coef) / (1.0 - lev)[:, None]
                loo = _mean_over(loo_resid ** 2, drawn) / np.var(y, axis=0)
            rinv = solve_triangular(r, np.eye(r.shape[0]))
            cols = np.arange(psi.shape[1])
            return coef, loo, [_Sampling(cols, q * loo_resid[:, k:k + 1], rinv) for k in range(y.shape[1])]
    coef, *_ = np.linalg.lstsq(psi, y, rcond=None)                  # rank-deficient or underdetermined
    return coef, _relative_loo_error(psi, y, coef, drawn), [None] * y.shape[1]


def _relative_loo_error(psi: NDArray[np.float64], y: NDArray[np.float64], coef: NDArray[np.float64],
                        drawn: NDArray[np.bool_] | None = None) -> NDArray[np.float64]:
    """Leave-one-out error of a least-squares fit over the output variance, per output."""
    q, _ = np.linalg.qr(psi)
    lev = np.clip((q ** 2).sum(axis=1), 0.0, 1.0 - 1e-12)
    resid = y - psi @ coef
    with np.errstate(divide="ignore", invalid="ignore"):
        return _mean_over((resid / (1.0 - lev)[:, None]) ** 2, drawn) / np.var(y, axis=0)


def _mean_over(sq: NDArray[np.float64], drawn: NDArray[np.bool_] | None) -> NDArray[np.float64]:
    """Mean of squared LOO residuals (n, k) over all points, or over the ``drawn`` ones only."""
    return np.mean(sq if drawn is None else sq[drawn], axis=0)
