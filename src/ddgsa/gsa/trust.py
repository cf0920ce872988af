"""What ``trusted`` means, and the error bounds every method's trust rule is built from.

A row of an indices table is **trusted** when every index in it (``S1`` and ``ST``) is within
``tolerance`` (absolute, default :data:`DEFAULT_TOLERANCE`) of the truth, with the confidence
the method states. Each method turns what it can observe into an *estimate of the index error*
per row and distrusts the rows whose estimate exceeds the tolerance:

* surrogate methods (M-DRM, PCE) -- the indices they report are *exactly* the Sobol indices of
  a surrogate ``g`` (M-DRM: the product of the cut functions' Gauss-node interpolants; PCE: the
  expansion). If ``||h - (a g + b)|| <= delta`` in L2 for some affine map (Sobol indices do not
  change under one), every index of ``h`` lies within an angle ``asin(delta / sd g)`` of the
  surrogate's: :func:`surrogate_index_bounds`. ``delta`` comes
  from a check sample (M-DRM) or from the leave-one-out error (PCE).
* sampling methods (SALib) -- the bootstrap half-width and, where the design nests, the
  difference between the estimates from half and all of the sample. Both assume the estimator's
  per-row terms have a finite variance; where the terms' upper tail is too heavy for that
  (:func:`pareto_shape` above :func:`pareto_limit`), neither sees the error and the row has no
  error estimate at all (Saltelli's ``heavy_tail`` rule).

The constants that turn an observation into a bound with a stated confidence are calibrated by
``ddgsa bench trust`` (:mod:`ddgsa.bench.calibration`, results in ``results/trust_calibration/``).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ddgsa.errors import MethodError
from ddgsa.gsa.result import Diagnostic

DEFAULT_TOLERANCE = 0.02


def check_tolerance(method: str, value: Any) -> float:
    """The ``tolerance`` option, a number in (0, 1), or a :class:`MethodError` naming it."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) \
            or not 0.0 < float(value) < 1.0:
        raise MethodError(f"method {method!r}: option 'tolerance' must be a number in (0, 1) "
                          f"(absolute error allowed on every Sobol index), got {value!r}")
    return float(value)


def surrogate_index_bounds(index: NDArray[np.float64], eps: NDArray[np.float64] | float,
                           orthogonal: bool = False) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Interval that holds the true index when the surrogate's index is ``index``.

    Parameters
    ----------
    index : array
        Sobol index of the surrogate ``g`` (first-order or total) [-].
    eps : array or float
        ``delta / sd(g)``: the L2 distance between the output and the best affine map of the
        surrogate, relative to the surrogate's standard deviation [-]; broadcast against ``index``.
    orthogonal : bool
        True when the difference is orthogonal to the surrogate (a least-squares projection, as
        M-DRM's check-sample fit): the vector then turns by ``atan(eps)`` at most, else ``asin(eps)``.

    Returns
    -------
    low, high : arrays
        Split the centred output into the part the index measures (the main effect of
        ``x_i``, or every ANOVA term involving it) and the orthogonal rest: ``S = sin^2 theta``
        with ``theta`` the angle of the vector (rest, part). A perturbation of L2 norm
        ``delta`` turns that vector by at most ``phi = asin(eps)`` (``atan(eps)`` if orthogonal),
        so the true index lies in ``[sin^2(theta - phi), sin^2(theta + phi)]`` (clipped to
        [0, pi/2]); for ``eps >= 1``, not orthogonal, anything in [0, 1] is possible. The
        orthogonal bound is attained: ``g = x1 + x2``, ``h = (1 + c) x1 + (1 - c) x2`` (same
        input variances) has ``eps = c`` and ``S_1 = sin^2(pi/4 + atan c)``.

    Examples
    --------
    >>> low, high = surrogate_index_bounds(np.array([0.0, 0.5, 1.0]), 0.01)
    >>> np.round(high - np.array([0.0, 0.5, 1.0]), 5).tolist(), np.round(low, 5).tolist()
    ([0.0001, 0.01, 0.0], [0.0, 0.49, 0.9999])
    """
    theta = np.arcsin(np.sqrt(np.clip(np.asarray(index, dtype=float), 0.0, 1.0)))
    e = np.broadcast_to(np.asarray(eps, dtype=float), theta.shape)
    if orthogonal:
        phi = np.arctan(np.clip(e, 0.0, None))
    else:
        phi = np.where(e < 1.0, np.arcsin(np.clip(e, 0.0, 1.0)), np.pi / 2)
    low = np.sin(np.clip(theta - phi, 0.0, np.pi / 2)) ** 2
    high = np.sin(np.clip(theta + phi, 0.0, np.pi / 2)) ** 2
    return low, high


def surrogate_index_error(index: NDArray[np.float64], eps: NDArray[np.float64] | float,
                          orthogonal: bool = False) -> NDArray[np.float64]:
    """Largest absolute error of ``index`` allowed by :func:`surrogate_index_bounds` (NaN stays NaN)."""
    idx = np.asarray(index, dtype=float)
    low, high = surrogate_index_bounds(idx, eps, orthogonal)
    s = np.clip(idx, 0.0, 1.0)
    err = np.maximum(high - s, s - low) + np.abs(idx - s)     # an index outside [0, 1] is off by that much
    return np.where(np.isfinite(idx), err, np.nan)


def error_diagnostics(name: str, why: str, outputs: list[str], parameters: tuple[str, ...] | list[str],
                      err_s1: NDArray[np.float64], err_st: NDArray[np.float64],
                      tolerance: float) -> list[Diagnostic]:
    """One ``untrusted`` diagnostic per row whose estimated S1 or ST error exceeds ``tolerance``.

    ``err_s1`` and ``err_st`` are (n_outputs, n_params) error estimates [-]; NaN estimates (an
    index the method does not give) are ignored, a row with no estimate at all is not judged here.
    """
    diags = []
    with np.errstate(invalid="ignore"):
        worst = np.fmax(err_s1, err_st)
    for j, i in zip(*np.nonzero(worst > tolerance)):
        diags.append(Diagnostic(name, f"output {outputs[j]!r}: {parameters[i]}: estimated index error "
                                f"{worst[j, i]:.3g} > tolerance {tolerance:g} ({why})", "untrusted",
                                output=outputs[j], parameter=parameters[i], value=float(worst[j, i])))
    return diags


def pareto_shape(terms: NDArray[np.float64]) -> float:
    """Shape ``k`` of the generalised Pareto law fitted to the upper tail of ``terms`` [-].

    The estimate of Vehtari et al. (2024), *Pareto smoothed importance sampling*, J. Mach. Learn.
    Res. 25(72), sec. 3: the ``M = min(n / 5, 3 sqrt(n))`` largest of the ``n`` values, less the next
    largest, are fitted by the method of Zhang & Stephens (2009), *Technometrics* 51(3), 316-325,
    with its weak prior (``k`` pulled towards 0.5 by 10 pseudo-observations). A sample mean of the
    terms has a finite variance (the bootstrap's premise) only for ``k < 1/2``; for ``k >= 1`` not
    even the mean exists. Light tails give ``k <= 0`` (a bounded law: negative).

    Parameters
    ----------
    terms : array (n,)
        Non-negative per-row terms whose mean is estimated, e.g. squared differences [any unit].

    Returns
    -------
    float
        The shape ``k`` [-]; ``-inf`` when the tail has fewer than five distinct exceedances
        (constant, inert or few-valued terms: no tail to speak of).

    Examples
    --------
    A Pareto law with survival ``x^(-1/k)`` has shape ``k``:

    >>> u = np.random.default_rng(0).random(4096)
    >>> round(pareto_shape(u ** -0.8), 1), round(pareto_shape(u ** -0.2), 1)
    (0.8, 0.3)
    """
    t = np.sort(np.asarray(terms, dtype=float))
    n = len(t)
    m = int(min(0.2 * n, 3.0 * np.sqrt(n)))
    if m < 5:
        return -np.inf
    x = t[n - m:] - t[n - m - 1]
    x = x[x > 0.0]
    if len(x) < 5:
        return -np.inf
    # Zhang & Stephens: posterior mean of theta = -k / sigma over a grid of candidate values
    nx, grid = len(x), 30 + int(np.sqrt(len(x)))
    theta = 1.0 / x[-1] + (1.0 - np.sqrt(grid / (np.arange(1, grid + 1) - 0.5))) / (3.0 * x[int(nx / 4 + 0.5) - 1])
    k = np.log1p(-theta[:, None] * x).mean(axis=1)
    log_lik = nx * (np.log(-theta / k) - k - 1.0)
    weight = np.exp(log_lik - log_lik.max())
    weight /= weight.sum()
    k_hat = float(np.log1p(-np.sum(theta * weight) * x).mean())
    return (k_hat * nx + 10 * 0.5) / (nx + 10)


def pareto_limit(n: int) -> float:
    """Largest tail shape (:func:`pareto_shape`) at which a mean of ``n`` terms is still reliable [-].

    ``min(1 - 1 / log10(n), 0.7)`` (Vehtari et al. 2024, sec. 3.2.2): above it the mean's error
    converges too slowly for ``n`` terms to pin it down, and an interval from the sample's own
    spread (bootstrap, half sample, a replicate of the same kind) is too narrow. 0.67 at
    ``n = 1024``, 0.7 from ``n = 2154``.
    """
    return min(1.0 - 1.0 / np.log10(max(n, 11)), 0.7)


REMEDIES = {
    "mdrm_index_error": "M-DRM's product surrogate misses part of the output (interactions, additive "
                        "structure): add a cross-check (`pce` or `saltelli`) or use `method: auto` with a "
                        "`budget`, which escalates until the rows are trusted.",
    "mdrm_unchecked": "give M-DRM a check sample (`check: 32`); without one its error has no bound.",
    "mdrm_cut_value": "the output is zero or not finite at the cut point: use `pce`, `saltelli` or `auto`.",
    "mdrm_sign_change": "the output changes sign over the nodes, which M-DRM cannot represent: use `pce`, "
                        "`saltelli` or `auto`.",
    "mdrm_rho_sign": "a cut function's mean has the other sign: use `pce`, `saltelli` or `auto`.",
    "mdrm_unresolved": "a cut function is not smooth (kinks, steps): more Gauss `points` or a sampling "
                       "method (`saltelli`).",
    "mdrm_quadrature_coverage": "the Gauss nodes miss the input's tails: more `points`.",
    "salib_index_error": "raise `n` (the error falls like 1/sqrt(n): four times n halves it).",
    "negative_index": "raise `n`: an index below zero by more than its error estimate.",
    "heavy_tail": "a few rare runs carry the total index, which no sample's spread bounds: analyse a transform "
                  "of the output (e.g. its logarithm) or use `pce`.",
    "fast_unverified": "FAST and RBD-FAST are cross-checks, never trusted: trust comes from M-DRM, PCE or Saltelli.",
    "pce_index_error": "raise the `order` or the points `n`, or `fit: sparse`.",
    "pce_underdetermined": "fewer points than terms: raise `n` or lower the `order`.",
    "auto_budget_exhausted": "raise `budget`: no stage trusted the output within it.",
    "nonfinite_values": "evaluations failed: see the failure reasons, then narrow the parameter ranges or "
                        "refine the model's step.",
    "zero_variance": "the output is constant over the sample: nothing to rank.",
    "mdrm_zero_variance": "the output is constant over the nodes: nothing to rank.",
}
"""What would fix each untrusting diagnostic, by its name (docs/methods.md says when each fires); the
report's Problems section shows it beside the rows it untrusted."""
