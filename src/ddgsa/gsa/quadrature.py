"""One-dimensional Gauss rules in the measure of each input distribution.

Uniform and normal inputs get Gauss-Legendre and Gauss-Hermite rules from numpy (exact
recurrences). The triangular density is piecewise linear, so a Gauss-Legendre rule on
each of its two pieces is an exact discrete copy of its moments; the Stieltjes procedure
on that copy gives its Gauss rule to round-off (chaospy's own triangular rule is only
accurate to ~1e-8). Lognormal and truncated-normal rules come from chaospy
(``rule="gaussian"``; chaospy's default rule is Clenshaw-Curtis, not Gauss).
"""

from __future__ import annotations

import chaospy
import numpy as np
from numpy.typing import NDArray

from ddgsa.gsa.space import Parameter

_PIECE_NODES = 200


def gauss_rule(param: Parameter, points: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``points``-node Gauss rule in the measure of ``param``.

    Returns
    -------
    nodes : ndarray (points,)
        Abscissae [unit of the parameter], ascending.
    weights : ndarray (points,)
        Probability weights, summing to one; the rule integrates polynomials of degree
        ``2 points - 1`` exactly against the distribution.
    """
    a = param.args
    if param.dist == "uniform":
        x, w = np.polynomial.legendre.leggauss(points)
        return a["low"] + 0.5 * (x + 1.0) * (a["high"] - a["low"]), 0.5 * w
    if param.dist == "normal":
        x, w = np.polynomial.hermite_e.hermegauss(points)
        return a["mean"] + a["std"] * x, w / w.sum()
    if param.dist == "triangular":
        return _stieltjes_gauss(*_triangular_discrete(a["low"], a["mode"], a["high"]), points)
    nodes, weights = chaospy.generate_quadrature(points - 1, param.distribution, rule="gaussian")
    return np.asarray(nodes, dtype=float).ravel(), np.asarray(weights, dtype=float).ravel()


def _triangular_discrete(low: float, mode: float, high: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """A discrete measure with the triangular distribution's moments up to degree ~400."""
    xs, ws = [], []
    x, w = np.polynomial.legendre.leggauss(_PIECE_NODES)
    for lo, hi in ((low, mode), (mode, high)):
        if hi <= lo:
            continue
        t = lo + 0.5 * (x + 1.0) * (hi - lo)
        dens = np.where(t <= mode, 2 * (t - low) / ((high - low) * (mode - low) or 1.0),
                        2 * (high - t) / ((high - low) * (high - mode) or 1.0))
        xs.append(t)
        ws.append(0.5 * (hi - lo) * w * dens)
    return np.concatenate(xs), np.concatenate(ws)


def _stieltjes_gauss(x: NDArray[np.float64], w: NDArray[np.float64],
                     points: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Gauss rule of the discrete measure (x, w) by the Stieltjes procedure and Golub-Welsch."""
    w = w / w.sum()
    alpha, beta = np.zeros(points), np.zeros(points)
    p_prev, p = np.zeros_like(x), np.ones_like(x)
    norm_prev = 1.0
    for k in range(points):
        norm = w @ p ** 2
        alpha[k] = (w @ (x * p ** 2)) / norm
        beta[k] = norm / norm_prev if k else 1.0
        p_prev, p = p, (x - alpha[k]) * p - (beta[k] if k else 0.0) * p_prev
        norm_prev = norm
    jacobi = np.diag(alpha) + np.diag(np.sqrt(beta[1:]), 1) + np.diag(np.sqrt(beta[1:]), -1)
    nodes, vecs = np.linalg.eigh(jacobi)
    return nodes, vecs[0] ** 2
