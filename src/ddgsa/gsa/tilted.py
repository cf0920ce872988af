"""Sobol' indices of a resonant output by a Saltelli design tilted towards its resonance (issue 46, item 6).

Where an output has a lightly damped resonance inside the parameter ranges (the rig's coast-down started
near its first critical speed), the total index's pick-freeze terms ``(f(A) - f(AB_i))^2`` are carried by the
few runs that land on the peak: their Pareto tail shape stays above one at every sample size
(docs/confirm.md), so a plain sample's mean does not settle and its bootstrap interval is too narrow. A
model *feature* says where the peak lies before anything runs: the ratio ``s`` of the running speed to the
lowest lateral natural frequency, predicted smoothly from a pilot (a Gaussian process of the rig's control
feature). This module samples the runs on purpose where the single-mode amplification of that ratio is large
and weighs them back (importance sampling; Owen, *Monte Carlo theory, methods and examples*, 2013, ch. 9):

* **The proposal** ``q(u) = p(u) h(u)``, ``h = (1 - mix) + mix g(u) / Z``: the input law ``p`` (uniform on
  the unit cube, mapped by the space's inverse CDFs) tilted by ``g >= 0`` (:class:`Tilt`), ``Z = E_p[g]``
  (quasi-Monte Carlo on :data:`MEAN_POINTS` points). The *defensive* share ``1 - mix`` of the input law keeps
  every weight below ``1 / (1 - mix)`` (Hesterberg, *Technometrics* 37, 1995). Draws of ``p g / Z`` are exact
  rejection sampling against ``g``'s stated bound.
* **The design** is Saltelli's without its second-order part: a base ``A`` (n, d) drawn from ``q``, a second
  matrix ``B`` from ``p``, and for every input ``i`` the mixed rows ``AB_i`` (``A`` with column ``i`` from
  ``B``) and ``BA_i`` (``B`` with column ``i`` from ``A``): ``n (2 d + 1)`` runs.
* **The estimates** (Jansen's, with the pairs' weights). A pair ``(a, o)`` whose tilted end ``a`` came from
  ``q`` and whose other end ``o`` from redrawing some columns from ``p`` is weighed by
  ``w = 2 / (h(a) + h(o))``: the pair's law under ``p`` is symmetric in its two ends, so
  ``E[w t(a, o)] = E_p[t]`` for any symmetric ``t`` (the balance heuristic of multiple importance sampling,
  Veach & Guibas 1995, with the proposal's two ends as its two strategies). Then, self-normalised
  (each weighted mean divided by its weights' mean, whose expectation is one):

  ``V = E_q[(f(A) - m)^2 / h(A)]``, ``V_Ti = E[w_i (f(A) - f(AB_i))^2] / 2`` with ``w_i = 2 / (h(A) + h(AB_i))``,
  ``V - V_i = E[v_i (f(A) - f(BA_i))^2] / 2`` with ``v_i = 2 / (h(A) + h(BA_i))``; ``ST_i = V_Ti / V``,
  ``S1_i = 1 - (V - V_i) / V``.

  With ``g`` the squared amplification ``1 / |1 - s^2 + 2 i zeta s|^2`` of a resonant output, a weighted term
  is the squared output over its own amplification: bounded where the unweighted one is not.
* **A control variate** ``g`` (a cheap surrogate of the output: :func:`control_moments` takes its moments from
  a large tilted design on ``g`` itself) makes each moment ``g``'s plus the design's estimate of ``f``'s minus
  ``g``'s on the same rows, pairs and weights: only what ``g`` misses is sampled (as
  :func:`ddgsa.gsa.control.controlled_saltelli` does for the untilted design).
* **Intervals** by the bootstrap over the base rows (every estimate of a resample from the same rows, so the
  variance and the pairs stay correlated as in the sample), and the weighted terms' Pareto tail shapes
  (:func:`~ddgsa.gsa.trust.pareto_shape`) beside them: an interval is a fair one only where the shape is below
  :func:`~ddgsa.gsa.trust.pareto_limit`.

Consistent for any ``g`` (a poor tilt costs variance, never correctness; the self-normalised ratios carry
a bias of order ``1 / n``, 0.02 at a base of 32 and unseen at 256), and with ``mix = 0`` it is the plain design: the tests compare both against indices by quadrature of a resonant function
(``tests/gsa/test_tilted.py``); ``benchmarks/tilted_coastdown.py`` measures it on the rig's coast-down.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
import pandas as pd
from numpy.typing import NDArray
from scipy.stats import qmc

from ddgsa.errors import MethodError
from ddgsa.gsa.space import ParameterSpace
from ddgsa.gsa.trust import pareto_shape

Array = NDArray[np.float64]
MEAN_POINTS = 2**16
"""Scrambled Sobol' points of the tilt's mean ``Z`` (relative error about 1e-4 on a resonance of 2 % damping)."""
CANDIDATES = 4096
"""Candidates drawn at a time by the rejection sampler."""


@dataclass(frozen=True)
class Tilt:
    """The tilt ``g(u) >= 0`` of unit-cube points (n, d) -> (n,), its bound ``sup g`` and the share ``mix`` of
    the proposal drawn along it (see the module); ``mean`` is ``E_p[g]`` (:func:`make_tilt` computes it)."""

    g: Callable[[Array], Array]
    bound: float
    mean: float
    mix: float = 0.5

    def __post_init__(self) -> None:
        if not 0.0 <= self.mix < 1.0:
            raise MethodError(f"tilted design: mix must lie in [0, 1) (the input law's share keeps the weights "
                              f"bounded), got {self.mix!r}")
        if not (np.isfinite(self.bound) and self.bound > 0.0 and np.isfinite(self.mean) and self.mean > 0.0):
            raise MethodError(f"tilted design: the tilt's bound and mean must be positive and finite, got "
                              f"{self.bound!r} and {self.mean!r}")

    def h(self, u: Array) -> Array:
        """The proposal's density over the input law's, ``(1 - mix) + mix g(u) / mean`` (n,) [-]."""
        return (1.0 - self.mix) + self.mix * self.g(u) / self.mean


def make_tilt(g: Callable[[Array], Array], bound: float, dim: int, mix: float = 0.5, seed: int = 0) -> Tilt:
    """A :class:`Tilt` of ``g`` on the ``dim``-dimensional unit cube, its mean by quasi-Monte Carlo.

    Raises :class:`~ddgsa.errors.MethodError` for a ``mix`` outside [0, 1), a bound that is not positive and
    finite, or a ``g`` that is negative, not finite, or above its bound at the mean's points."""
    if not 0.0 <= mix < 1.0:
        raise MethodError(f"tilted design: mix must lie in [0, 1) (the input law's share keeps the weights "
                          f"bounded), got {mix!r}")
    if not (np.isfinite(bound) and bound > 0.0):
        raise MethodError(f"tilted design: the tilt's bound must be positive and finite, got {bound!r}")
    u = qmc.Sobol(dim, scramble=True, rng=np.random.default_rng(seed)).random(MEAN_POINTS)
    values = np.asarray(g(u), dtype=float)
    if values.shape != (MEAN_POINTS,) or not np.all(np.isfinite(values)) or values.min() < 0.0:
        raise MethodError("tilted design: the tilt must give one finite, non-negative value per point")
    if values.max() > bound * (1.0 + 1e-12):
        raise MethodError(f"tilted design: the tilt reaches {values.max():.6g}, above its stated bound {bound:.6g}")
    if values.mean() <= 0.0:
        raise MethodError("tilted design: the tilt is zero over the whole space")
    return Tilt(g, float(bound), float(values.mean()), float(mix))


def resonance_tilt(ratio: Callable[[Array], Array], damping: float, dim: int, mix: float = 0.5,
                   seed: int = 0) -> Tilt:
    """The tilt of a resonance: the squared single-mode amplification ``1 / ((1 - s^2)^2 + (2 zeta s)^2)`` of a
    predicted frequency ratio ``s = ratio(u)`` [-] with damping ratio ``damping`` (``zeta``, 0 < zeta < 0.7)
    [-]. Its bound ``1 / (4 zeta^2 (1 - zeta^2))`` is the amplification's peak. A damping above the mode's
    own widens the tilt (a predicted ratio's error, a resonance's spread across outputs)."""
    if not 0.0 < damping < 0.7:
        raise MethodError(f"resonance tilt: the damping ratio must lie in (0, 0.7), got {damping!r}")

    def g(u: Array) -> Array:
        s = np.asarray(ratio(u), dtype=float)
        return 1.0 / ((1.0 - s * s) ** 2 + (2.0 * damping * s) ** 2)

    return make_tilt(g, 1.0 / (4.0 * damping**2 * (1.0 - damping**2)), dim, mix, seed)


@dataclass(frozen=True)
class TiltedDesign:
    """Unit-cube points of a tilted Saltelli design and the proposal's density ratio at each.

    ``u`` (n (2 d + 1), d): the base ``A`` (n rows), then ``AB_i`` for each input ``i`` (n rows each), then
    ``BA_i``; ``h`` (same rows,) :meth:`Tilt.h` there."""

    u: Array
    h: Array
    n: int
    dim: int

    def points(self, space: ParameterSpace) -> Array:
        """The design's parameter values (rows, d) in ``space``'s units."""
        return space.ppf(self.u)


def _from_tilt(tilt: Tilt, n: int, dim: int, rng: np.random.Generator) -> Array:
    """``n`` exact draws (n, dim) of ``p g / mean`` by rejection against ``tilt.bound``."""
    out: list[Array] = [np.empty((0, dim))]
    have = 0
    while have < n:
        u = rng.random((CANDIDATES, dim))
        keep = u[rng.random(CANDIDATES) * tilt.bound < tilt.g(u)]
        out.append(keep)
        have += len(keep)
    return np.vstack(out)[:n]


def _proposal(tilt: Tilt, n: int, dim: int, rng: np.random.Generator) -> Array:
    """``n`` draws (n, dim) of the proposal as a deterministic mixture in a random order: ``round(mix n)`` along
    the tilt, the rest from the input law (:func:`_drawn`: the share the weights then take)."""
    along = int(round(tilt.mix * n))
    return np.vstack([rng.random((n - along, dim)), _from_tilt(tilt, along, dim, rng)])[rng.permutation(n)]


def proposal_sample(tilt: Tilt, n: int, dim: int, seed: int = 0) -> Array:
    """``n`` unit-cube points (n, dim) drawn as a tilted design's base is: a pilot for controls that must learn
    the resonance the tilt samples (seeded)."""
    return _proposal(tilt, n, dim, np.random.default_rng(seed))


def tilted_design(tilt: Tilt, n: int, dim: int, seed: int = 0) -> TiltedDesign:
    """A tilted Saltelli design of base size ``n`` in ``dim`` inputs (see the module): ``n (2 d + 1)`` rows.

    The base's rows are drawn from the proposal as a deterministic mixture: ``round(mix n)`` along the tilt, the
    rest from the input law, in a random order, and the weights take that share (``round(mix n) / n``, which is
    ``mix`` where ``mix n`` is whole); ``B`` from the input law. Seeded."""
    if not isinstance(n, (int, np.integer)) or n < 2:
        raise MethodError(f"tilted design: the base size n must be an integer >= 2, got {n!r}")
    rng = np.random.default_rng(seed)
    a = _proposal(tilt, n, dim, rng)
    b = rng.random((n, dim))
    ab = np.repeat(a[None], dim, axis=0)
    ba = np.repeat(b[None], dim, axis=0)
    for i in range(dim):
        ab[i, :, i], ba[i, :, i] = b[:, i], a[:, i]
    u = np.vstack([a, ab.reshape(-1, dim), ba.reshape(-1, dim)])
    drawn = replace(tilt, mix=round(tilt.mix * n) / n)
    return TiltedDesign(u, drawn.h(u), int(n), int(dim))


def _moments(design: TiltedDesign, y: Array) -> Callable[[Array], tuple[Array, Array, Array]]:
    """The estimator of the variance, ``V_Ti`` and ``V - V_i`` of ``y`` (rows of ``design``,) from base rows
    counted ``c`` (b, n) times: (b,), (b, d), (b, d) (``c`` all ones: the design's own estimate)."""
    n, d = design.n, design.dim
    fa, fab, fba = y[:n], y[n:n + n * d].reshape(d, n), y[n + n * d:].reshape(d, n)
    ha, hab, hba = design.h[:n], design.h[n:n + n * d].reshape(d, n), design.h[n + n * d:].reshape(d, n)
    w0 = 1.0 / ha
    wt, w1 = 2.0 / (ha + hab), 2.0 / (ha + hba)
    tt, t1 = 0.5 * (fa - fab) ** 2, 0.5 * (fa - fba) ** 2
    fc = fa - (w0 * fa).sum() / w0.sum()                 # centred (a shift leaves every variance as it is)

    def estimate(c: Array) -> tuple[Array, Array, Array]:
        sw = c @ w0
        var = c @ (w0 * fc * fc) / sw - (c @ (w0 * fc) / sw) ** 2
        return var, (c @ (wt * tt).T) / (c @ wt.T), (c @ (w1 * t1).T) / (c @ w1.T)

    return estimate


def _checked(design: TiltedDesign, y: Array, what: str) -> Array:
    n, d = design.n, design.dim
    y = np.asarray(y, dtype=float)
    if y.shape != (n * (2 * d + 1),):
        raise MethodError(f"tilted design: expected {n * (2 * d + 1)} {what}, got shape {y.shape}")
    if not np.all(np.isfinite(y)):
        raise MethodError(f"tilted design: {int(np.sum(~np.isfinite(y)))} {what} are not finite")
    return y


@dataclass(frozen=True)
class ControlMoments:
    """A control variate's variance ``var``, the total variances ``rest`` (d,) of all inputs but each one
    (``V - V_i``, ``V_i`` the first-order variance) and the total variances ``total`` (d,) under the input law
    [its unit^2], and ``replicates``: their bootstrap resamples ((b,), (b, d), (b, d)), whose spread
    :func:`tilted_indices` adds to its own (:func:`control_moments`)."""

    var: float
    rest: Array
    total: Array
    replicates: tuple[Array, Array, Array]


def control_moments(g: Callable[[Array], Array], tilt: Tilt, dim: int, n: int = 8192, seed: int = 0,
                    n_boot: int = 1000) -> ControlMoments:
    """The moments a control ``g`` (unit-cube points (m, dim) -> (m,)), cheap to evaluate, gives
    :func:`tilted_indices`: from a tilted design of base ``n`` on ``g`` itself, with ``n_boot`` bootstrap
    resamples of them (their spread enters the controlled intervals; it shrinks as ``1 / sqrt(n)``, so ``n``
    many times the design's base keeps it small)."""
    design = tilted_design(tilt, n, dim, seed)
    estimate = _moments(design, _checked(design, g(design.u), "control values"))
    (var,), (vt,), (v1,) = estimate(np.ones((1, n)))
    counts = np.random.default_rng(seed + 1).multinomial(n, np.full(n, 1.0 / n), size=n_boot).astype(float)
    return ControlMoments(float(var), v1, vt, estimate(counts))


def tilted_indices(design: TiltedDesign, y: Array, names: list[str] | tuple[str, ...] | None = None,
                   n_boot: int = 1000, conf_level: float = 0.95, seed: int = 0,
                   control: tuple[Array, ControlMoments] | None = None) -> pd.DataFrame:
    """First-order and total indices of the output ``y`` (rows of ``design``,) from a tilted design.

    Returns a frame indexed by input name with ``S1``, ``S1_conf``, ``ST``, ``ST_conf`` (half-widths of the
    bootstrap's central ``conf_level`` intervals), ``ST_tail`` and ``S1_tail`` (the Pareto shapes of the
    weighted pick-freeze terms) and ``variance``; ``attrs["ST_difference_conf"]`` (d x d): the bootstrap's
    half-widths of each difference ``ST_i - ST_j`` (narrower than the rows' own where their errors move
    together, as on a near tie). A row whose ``y`` is not finite is refused (a failed
    evaluation is never imputed: rerun or drop its whole base row).

    ``control``: a control variate's values at the design's rows and its moments (:func:`control_moments`):
    each of the three moments is then the control's plus the design's estimate of the difference of ``y``'s
    and the control's (the same rows, pairs and weights), so only the part of ``y`` the control misses is
    sampled, whatever the control; each bootstrap resample adds one of the moments' own resamples, so the
    intervals hold their error too. The tail shapes stay ``y``'s."""
    n, d = design.n, design.dim
    y = _checked(design, y, "outputs")
    if names is not None and len(names) != d:
        raise MethodError(f"tilted design: {len(names)} names for {d} inputs")
    estimate = _moments(design, y)
    if control is not None:
        of_f, of_g, mom = estimate, _moments(design, _checked(design, control[0], "control values")), control[1]

        def controlled(c: Array) -> tuple[Array, Array, Array]:
            (vf, tf, cf), (vg, tg, cg) = of_f(c), of_g(c)
            if len(c) == 1:                                    # the estimate: the control's own moments
                base = (mom.var, mom.total, mom.rest)
            else:                                              # a resample: an independent one of them too
                pick = np.arange(len(c)) % len(mom.replicates[0])
                base = tuple(r[pick] for r in mom.replicates)
            return base[0] + vf - vg, base[1] + tf - tg, base[2] + cf - cg

        estimate = controlled

    (var,), (vt,), (v1,) = estimate(np.ones((1, n)))
    counts = np.random.default_rng(seed).multinomial(n, np.full(n, 1.0 / n), size=n_boot).astype(float)
    bvar, bvt, bv1 = estimate(counts)                                  # the bootstrap's resamples of the rows
    alpha = 0.5 * (1.0 - conf_level)

    def half_width(samples: Array) -> Array:
        lo, hi = np.quantile(samples, [alpha, 1.0 - alpha], axis=0)
        return 0.5 * (hi - lo)

    with np.errstate(divide="ignore", invalid="ignore"):
        st, s1 = vt / var, 1.0 - v1 / var
        bst = bvt / bvar[:, None]
        st_conf, s1_conf = half_width(bst), half_width(1.0 - bv1 / bvar[:, None])
        pairs = half_width(bst[:, :, None] - bst[:, None, :])
    labels = list(names) if names is not None else [f"x{i + 1}" for i in range(d)]
    out = pd.DataFrame({"S1": s1, "S1_conf": s1_conf, "ST": st, "ST_conf": st_conf,
                        "ST_tail": _tails(design, y, n), "S1_tail": _tails(design, y, n + n * d), "variance": var},
                       index=pd.Index(labels, name="parameter"))
    out.attrs["ST_difference_conf"] = pd.DataFrame(pairs, index=labels, columns=labels)
    return out


def _tails(design: TiltedDesign, y: Array, start: int) -> list[float]:
    """Pareto shapes of the weighted pick-freeze terms of the pairs of the base with the rows from ``start``
    (``AB_i``: the total indices'; ``BA_i``: the first-order ones')."""
    n, d = design.n, design.dim
    other, h_other = y[start:start + n * d].reshape(d, n), design.h[start:start + n * d].reshape(d, n)
    w = 2.0 / (design.h[:n] + h_other)
    return [pareto_shape(w[i] * 0.5 * (y[:n] - other[i]) ** 2) for i in range(d)]
