"""Polynomial chaos expansion (PCE) Sobol indices, from the expansion's coefficients.

The basis is the total-degree set of products of one-dimensional orthonormal polynomials
(chaospy's three-term recurrences, one per input measure), so
:math:`\\mathrm{Var}\\, h = \\sum_{\\alpha \\ne 0} c_\\alpha^2`,
:math:`S_i = \\sum_{\\alpha \\in A_i} c_\\alpha^2 / \\mathrm{Var}` over multi-indices that
involve input *i* only and :math:`S_{T,i}` over those that involve it at all
(Sudret 2008, *Reliab. Eng. Syst. Saf.* 93).

Coefficients by ``fit="quadrature"`` (tensor Gauss rule, ``(order+1)^d`` points, spectral
projection) or ``fit="regression"`` (least squares on a scrambled Sobol' sample of
``n`` points, default the power of two at or above twice the number of terms).

Diagnostics:

- ``pce_loo_error`` (untrusted, regression): relative leave-one-out error above ``loo_max``.
- ``pce_unresolved`` (untrusted, order >= 3): the highest polynomial order holds more than
  ``resolution_tol`` of the variance (the expansion has not converged; discontinuity?).
- ``pce_underdetermined`` (untrusted, regression): fewer points than basis terms.
"""

from __future__ import annotations

from itertools import combinations_with_replacement
from typing import Any

import chaospy
import numpy as np
from numpy.typing import NDArray

from ddgsa.errors import MethodError
from ddgsa.gsa.base import (Design, GsaMethod, PartialIndices, check_choice, check_fraction,
                            check_int, register)
from ddgsa.gsa.result import Diagnostic
from ddgsa.space import ParameterSpace

_MAX_TENSOR_POINTS = 200_000


def total_degree_indices(dim: int, order: int) -> NDArray[np.int64]:
    """All multi-indices of ``dim`` integers with sum <= ``order``, graded (shape (P, dim))."""
    rows = [np.zeros(dim, dtype=np.int64)]
    for degree in range(1, order + 1):
        for combo in combinations_with_replacement(range(dim), degree):
            alpha = np.zeros(dim, dtype=np.int64)
            np.add.at(alpha, list(combo), 1)
            rows.append(alpha)
    return np.array(rows)


def basis_matrix(space: ParameterSpace, alphas: NDArray[np.int64], x: NDArray[np.float64]) -> NDArray[np.float64]:
    """Orthonormal product polynomials of multi-indices ``alphas`` at points ``x``: shape (n, P)."""
    order = int(alphas.max()) if alphas.size else 0
    psi = np.ones((x.shape[0], alphas.shape[0]))
    for i, p in enumerate(space.parameters):
        polys = chaospy.generate_expansion(order, p.distribution, normed=True)
        phi = np.asarray(polys(x[:, i]), dtype=float).reshape(order + 1, -1)   # (order+1, n)
        psi *= phi[alphas[:, i]].T
    return psi


@register("pce")
class PCE(GsaMethod):
    """Sobol indices from a polynomial chaos expansion (see the module docstring).

    Options: ``order`` (total degree, default 4), ``fit`` (``regression`` or ``quadrature``),
    ``n`` (regression sample size, default the power of two >= ``2 P``), ``seed``, ``loo_max`` (0.05),
    ``resolution_tol`` (0.01).
    """

    defaults = {"order": 4, "fit": "regression", "n": None, "seed": 0, "loo_max": 0.05,
                "resolution_tol": 0.01}

    def check_options(self, space: ParameterSpace, opts: dict[str, Any]) -> None:
        order = check_int(self.name, "order", opts["order"], 1, 30)
        check_choice(self.name, "fit", opts["fit"], ("regression", "quadrature"))
        check_int(self.name, "seed", opts["seed"], 0)
        check_fraction(self.name, "loo_max", opts["loo_max"], 0.0, 1e9)
        check_fraction(self.name, "resolution_tol", opts["resolution_tol"], 0.0, 1e9)
        if opts["fit"] == "quadrature":
            if opts["n"] is not None:
                raise MethodError("method 'pce': option 'n' applies to fit 'regression' only "
                                  "(quadrature uses (order+1)^d points)")
            if (order + 1) ** space.dim > _MAX_TENSOR_POINTS:
                raise MethodError(f"method 'pce': a tensor Gauss grid of order {order} in {space.dim} "
                                  f"dimensions needs {(order + 1) ** space.dim:.3g} points (limit "
                                  f"{_MAX_TENSOR_POINTS}); use fit 'regression'")
        elif opts["n"] is not None:
            check_int(self.name, "n", opts["n"], 2)

    def _design(self, space: ParameterSpace, opts: dict[str, Any]) -> Design:
        alphas = total_degree_indices(space.dim, opts["order"])
        if opts["fit"] == "quadrature":
            nodes, weights = chaospy.generate_quadrature(opts["order"], space.joint, rule="gaussian")
            x = np.asarray(nodes, dtype=float).reshape(space.dim, -1).T
            meta: dict[str, Any] = {"weights": np.asarray(weights, dtype=float)}
        else:
            # default: the power of two (Sobol' balance) at or above twice the number of terms
            n = opts["n"] if opts["n"] is not None else 1 << int(np.ceil(np.log2(2 * len(alphas))))
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
        if opts["fit"] == "quadrature":
            coef = psi.T @ (design.meta["weights"][:, None] * y)              # (P, k)
        else:
            coef, *_ = np.linalg.lstsq(psi, y, rcond=None)
            loo = _relative_loo_error(psi, y, coef)
            extras["loo_error"] = loo
            if psi.shape[0] < psi.shape[1]:
                diags.append(Diagnostic("pce_underdetermined", f"{psi.shape[0]} points for {psi.shape[1]} "
                                        "basis terms; raise 'n'", "untrusted"))
            for k in np.flatnonzero(~(loo <= opts["loo_max"])):
                diags.append(Diagnostic("pce_loo_error", f"output {outputs[k]!r}: relative leave-one-out "
                                        f"error {loo[k]:.3g} > {opts['loo_max']}; the expansion does not "
                                        "represent the output", "untrusted", output=outputs[k], value=float(loo[k])))
        energy = coef[1:] ** 2                                                 # (P-1, k)
        var = energy.sum(axis=0)
        involved = alphas[1:] > 0                                              # (P-1, d)
        alone = involved & (involved.sum(axis=1, keepdims=True) == 1)
        with np.errstate(divide="ignore", invalid="ignore"):
            S1 = (alone.T.astype(float) @ energy / var).T
            ST = (involved.T.astype(float) @ energy / var).T
            top = alphas[1:].sum(axis=1) == opts["order"]
            frac = energy[top].sum(axis=0) / var
        extras["top_order_fraction"] = frac
        # below order 3 a spectrum has no tail to judge decay by; the LOO error guards those
        for k in (np.flatnonzero(~(frac <= opts["resolution_tol"])) if opts["order"] >= 3 else []):
            diags.append(Diagnostic("pce_unresolved", f"output {outputs[k]!r}: {frac[k]:.1%} of the variance "
                                    f"is in order {opts['order']} terms (not converged; non-smooth output?)",
                                    "untrusted", output=outputs[k], value=float(frac[k])))
        return PartialIndices(S1=S1, ST=ST, diagnostics=diags, extras=extras)


def _relative_loo_error(psi: NDArray[np.float64], y: NDArray[np.float64],
                        coef: NDArray[np.float64]) -> NDArray[np.float64]:
    """Leave-one-out error of a least-squares fit over the output variance, per output."""
    q, _ = np.linalg.qr(psi)
    lev = np.clip((q ** 2).sum(axis=1), 0.0, 1.0 - 1e-12)
    resid = y - psi @ coef
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.mean((resid / (1.0 - lev)[:, None]) ** 2, axis=0) / np.var(y, axis=0)
