"""Fault detectability as condition monitoring measures it: detection against false alarms.

Model-agnostic statistics on two populations of measurements of one or more sensors
(outputs): *healthy* and *faulty*. Each measurement is one value (one wind record of one
parameter point plus measurement noise), never an average. Measurements rest on *units*
(:func:`layout`): the parameter point (turbine) and the wind record(s). A study evaluates every
fault level on the same points and records (common random numbers), so a faulty value and its
healthy twin share both; a monitoring system never compares those. Every statistic therefore
compares only measurements that share **no** unit (an exact estimator for independent draws),
and every interval re-draws whole units. For one sensor the detector raises an alarm when a
measurement passes a threshold set on healthy measurements:

- **threshold** ``t``: the smallest healthy order statistic with at most ``alpha`` of the healthy
  measurements beyond it (a tie with ``t`` does not alarm, so a cluster of equal values never
  passes at once);
- **false-alarm rate**, measured out of sample: each healthy measurement against the threshold
  of the healthy measurements it shares no unit with;
- **probability of detection** ``POD``: each faulty measurement against the threshold of the
  healthy measurements it shares no unit with;
- **ROC AUC** ``P(faulty beyond healthy)`` (Mann-Whitney over the pairs that share no unit, ties
  count one half);
- **intervals**: a two-way (pigeonhole) bootstrap re-draws points and records independently
  (each within the units of the healthy population, the faulty, or both); the percentile
  half-widths are widened by ``t_(G-1)/z sqrt(G/(G-1))`` for ``G`` effective units, and joined with
  a Clopper-Pearson interval on the effective count (POD: ``G`` measurements; AUC:
  ``3 G_h G_f / (G_h + G_f)``, the count whose binomial variance is Mann-Whitney's at 1/2);
- **effective size** ``G``: independent measurements worth the same, var(ranks) over the
  bootstrap variance of their mean, less one for the bootstrap's ``(G - 1)/G`` (a population
  resting on 4 records that dominate is worth about 4);
- **effect size** ``|mean_f - mean_h| / std_h``.

The side of the threshold (``direction``: +1 alarms above, -1 below) is the side the faulty
population lies on (AUC >= 1/2). A sensor is ``detectable`` when the lower end of the POD
interval reaches the POD target; a verdict is refused (``None``, with a reason) when any
measurement failed or is not finite, when the healthy population has zero spread, or when it
cannot resolve the false-alarm rate: fewer than ``1/alpha`` measurements, or an effective size
below ``1/alpha`` ("4 realisations: POD resolution 0.25; add realisations").

Several sensors are combined by Fisher's linear discriminant ``w = S^+ (mu_f - mu_h)``
(``S`` the pooled covariance of the standardised sensors) trained on one half of the points
and scored on the other, and vice versa; the held-out scores are then one sensor to the
statistics above, and their interval re-trains the discriminant on every bootstrap re-draw
(training variability). :func:`select_sensors` chooses a subset greedily and validates it on
points that took no part in the choice.

For Gaussian populations ``N(0, sigma^2)`` and ``N(Delta, sigma^2)``:
``POD = Phi(Delta/sigma - z_(1-alpha))`` and ``AUC = Phi(Delta / (sigma sqrt 2))``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from scipy import stats

from ddgsa.errors import DdgsaError

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

COMBINED = "combined"
"""Name of the multi-sensor detector in the tables."""

Seed = int | np.random.SeedSequence


class DetectionError(DdgsaError, ValueError):
    """Invalid input to a detection statistic (shapes, rates, levels)."""


@dataclass(frozen=True)
class Detection:
    """Detection statistics of one sensor (or the combined detector) for one fault level.

    Attributes
    ----------
    output : str
        Sensor name (``"combined"`` for the multi-sensor detector).
    n_healthy, n_faulty : int
        Measurements in each population.
    mean_healthy, mean_faulty, std_healthy : float
        Population statistics [output unit]; ``std_healthy`` with ``ddof=1``.
    effect_size : float
        ``|mean_f - mean_h| / std_h`` [-].
    direction : int
        +1: alarm above the threshold, -1: below.
    threshold : float
        Alarm threshold [output unit].
    false_alarm : float
        Healthy measurements beyond the threshold, fraction [-] (at most the stated rate).
    pod, pod_low, pod_high : float
        Probability of detection and its interval [-].
    auc, auc_low, auc_high : float
        ROC AUC and its bootstrap interval [-].
    detectable : bool or None
        ``pod_low >= target``; None when the verdict is refused.
    reason : str
        Why the verdict is refused (empty otherwise), or a note.
    n_eff_healthy, n_eff_faulty : float
        Independent measurements each population is worth (clustered measurements are worth fewer).
    """

    output: str
    n_healthy: int
    n_faulty: int
    mean_healthy: float = math.nan
    mean_faulty: float = math.nan
    std_healthy: float = math.nan
    effect_size: float = math.nan
    direction: int = 0
    threshold: float = math.nan
    false_alarm: float = math.nan
    pod: float = math.nan
    pod_low: float = math.nan
    pod_high: float = math.nan
    auc: float = math.nan
    auc_low: float = math.nan
    auc_high: float = math.nan
    detectable: bool | None = None
    reason: str = ""
    n_eff_healthy: float = math.nan
    n_eff_faulty: float = math.nan


@dataclass(frozen=True)
class DetectionSettings:
    """How detection is judged.

    Attributes
    ----------
    false_alarm : float
        Stated false-alarm rate ``alpha`` in (0, 0.5) [-].
    target : float
        POD the lower confidence bound must reach, in (0, 1] [-].
    confidence : float
        Two-sided confidence level of the intervals, in (0.5, 1) [-].
    bootstrap : int
        Bootstrap replicates.
    """

    false_alarm: float = 0.05
    target: float = 0.9
    confidence: float = 0.95
    bootstrap: int = 1000

    def __post_init__(self) -> None:
        checks = (("false_alarm", 0.0 < self.false_alarm < 0.5, "in (0, 0.5)"),
                  ("target", 0.0 < self.target <= 1.0, "in (0, 1]"),
                  ("confidence", 0.5 < self.confidence < 1.0, "in (0.5, 1)"),
                  ("bootstrap", int(self.bootstrap) == self.bootstrap and self.bootstrap >= 100, "an integer >= 100"))
        for name, ok, allowed in checks:
            if not ok:
                raise DetectionError(f"detection setting {name} = {getattr(self, name)!r}; allowed: {allowed}")


def _rng(seed: Seed) -> np.random.Generator:
    return np.random.default_rng(seed)


def add_noise(values: ArrayLike, absolute: float = 0.0, relative: float = 0.0,
              seed: Seed = 0) -> NDArray[np.float64]:
    """Measurement noise: each value plus an independent ``N(0, absolute^2 + (relative * value)^2)`` draw.

    Parameters
    ----------
    values : array_like
        Noise-free measurements [output unit].
    absolute : float
        Standard deviation of additive noise [output unit].
    relative : float
        Standard deviation of noise proportional to the value [-].
    seed : int or SeedSequence
        Seed of the noise draws.
    """
    if absolute < 0 or relative < 0:
        raise DetectionError(f"noise must be >= 0, got absolute={absolute!r}, relative={relative!r}")
    y = np.asarray(values, dtype=float)
    sd = np.sqrt(absolute ** 2 + (relative * y) ** 2)
    return y + sd * _rng(seed).standard_normal(y.shape)


def threshold_at(healthy: NDArray[np.float64], false_alarm: float, direction: int = 1) -> float:
    """Alarm threshold with at most ``false_alarm`` of ``healthy`` beyond it (alarm: ``direction * (x - t) > 0``).

    The ``ceil((1 - alpha) n)``-th smallest of ``direction * healthy`` (times ``direction``).
    """
    s = np.sort(direction * np.asarray(healthy, dtype=float))
    return float(direction * s[_order(len(s), false_alarm)])


def _order(n: int, false_alarm: float) -> int:
    """Index (0-based) of the threshold among ``n`` sorted healthy measurements."""
    return max(math.ceil((1.0 - false_alarm) * n - 1e-9), 1) - 1


def clopper_pearson(k: float, n: float, confidence: float) -> tuple[float, float]:
    """Exact two-sided binomial interval for ``k`` successes in ``n`` trials.

    ``k`` and ``n`` may be effective (non-integer) counts of clustered measurements: the beta
    quantiles take real parameters.
    """
    a = (1.0 - confidence) / 2
    lo = float(stats.beta.ppf(a, k, n - k + 1)) if k > 0 else 0.0
    hi = float(stats.beta.ppf(1 - a, k + 1, n - k)) if k < n else 1.0
    return lo, hi


@dataclass
class _Layout:
    """Which random units (parameter points, wind records) each measurement of both populations rests on.

    ``point_h``/``point_f``: one code per measurement; ``real_h``/``real_f``: (n, m) codes of the
    records it rests on (m = 0: none named, 1: one record, 2: a difference of two records). A code
    shared between the populations is the same unit (common random numbers).
    """

    point_h: NDArray[np.intp]
    point_f: NDArray[np.intp]
    real_h: NDArray[np.intp]
    real_f: NDArray[np.intp]
    _cache: dict[str, NDArray[Any]] = field(default_factory=dict, repr=False, compare=False)

    def keep_f32(self) -> NDArray[np.float32]:
        """:meth:`keep` of healthy against faulty as float32 (cached)."""
        if "hf32" not in self._cache:
            self._cache["hf32"] = self.keep("h", "f").astype(np.float32)
        return self._cache["hf32"]

    def keep(self, a: str, b: str) -> NDArray[np.bool_]:
        """Pairs (rows of ``a``, columns of ``b``; ``"h"`` or ``"f"``) that share no unit: independent draws (cached)."""
        if a + b not in self._cache:
            self._cache[a + b] = self._keep(a, b)
        return self._cache[a + b]

    def _keep(self, a: str, b: str) -> NDArray[np.bool_]:
        pa, pb = getattr(self, f"point_{a}"), getattr(self, f"point_{b}")
        ra, rb = getattr(self, f"real_{a}"), getattr(self, f"real_{b}")
        out = pa[:, None] != pb[None, :]
        for c in range(ra.shape[1]):
            for d in range(rb.shape[1]):
                out &= ra[:, c, None] != rb[None, :, d]
        return out

    def weights(self, n_boot: int, rng: np.random.Generator) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
        """Multiplicities of every measurement in ``n_boot`` two-way (pigeonhole) bootstrap re-draws.

        Points and records are re-drawn independently, with replacement, each within its stratum
        (units of the healthy population only, of the faulty only, shared); a measurement counts
        the product of its units' multiplicities.
        """
        mp = _redraw(self.point_h, self.point_f, n_boot, rng)
        rh, rf = self.real_h.reshape(len(self.real_h), -1), self.real_f.reshape(len(self.real_f), -1)
        mr = _redraw(rh.ravel(), rf.ravel(), n_boot, rng)
        out = []
        for p, r in ((self.point_h, rh), (self.point_f, rf)):
            w = mp[:, p].astype(np.float32)
            for c in range(r.shape[1]):
                again = np.zeros(len(r), bool)
                for d in range(c):
                    again |= r[:, c] == r[:, d]
                w *= np.where(again, 1, mr[:, r[:, c]]).astype(np.float32)
            out.append(w)
        return out[0], out[1]


def _redraw(codes_h: NDArray[np.intp], codes_f: NDArray[np.intp], n_boot: int,
            rng: np.random.Generator) -> NDArray[np.int64]:
    """(n_boot, max code + 1) multiplicities of every unit code, re-drawn within its stratum."""
    size = int(max(codes_h.max(initial=-1), codes_f.max(initial=-1))) + 1
    out = np.zeros((n_boot, size), np.int64)
    in_h, in_f = np.zeros(size, bool), np.zeros(size, bool)
    in_h[codes_h], in_f[codes_f] = True, True
    for stratum in (in_h & in_f, in_h & ~in_f, ~in_h & in_f):
        units = np.flatnonzero(stratum)
        if units.size:
            g = units.size
            pick = rng.integers(0, g, (n_boot, g)) + g * np.arange(n_boot)[:, None]
            out[:, units] = np.bincount(pick.ravel(), minlength=n_boot * g).reshape(n_boot, g)
    return out


def layout(units_healthy: ArrayLike | None, units_faulty: ArrayLike | None, n_h: int, n_f: int) -> _Layout:
    """The unit layout of two populations from per-measurement labels.

    Parameters
    ----------
    units_healthy, units_faulty : array_like, shape (n,) or (n, 1 + m), optional
        Column 0: the parameter point (turbine) a measurement comes from; columns 1..m: the wind
        records it rests on (two for a difference of records). Equal labels are the same unit,
        also across the populations (common random numbers). None for both: every measurement
        an independent draw.
    n_h, n_f : int
        Measurements in each population.
    """
    if (units_healthy is None) != (units_faulty is None):
        raise DetectionError("give the units of both populations or of neither")
    if units_healthy is None or units_faulty is None:
        empty = np.zeros((0,), np.intp)
        return _Layout(np.arange(n_h), n_h + np.arange(n_f), empty.reshape(n_h, 0), empty.reshape(n_f, 0))
    uh, uf = np.asarray(units_healthy), np.asarray(units_faulty)
    uh, uf = (u.reshape(len(u), -1) if u.ndim == 1 else u for u in (uh, uf))
    if uh.shape != (n_h, uh.shape[1]) or uf.shape != (n_f, uh.shape[1]):
        raise DetectionError(f"units must give one row of labels per measurement and the same columns in both "
                             f"populations: got {uh.shape} for {n_h} healthy, {uf.shape} for {n_f} faulty")
    _, points = np.unique(np.r_[uh[:, 0], uf[:, 0]], return_inverse=True)
    _, reals = np.unique(np.r_[uh[:, 1:].ravel(), uf[:, 1:].ravel()], return_inverse=True)
    m = uh.shape[1] - 1
    if reals.size and reals.max() == 0:         # one record under every measurement: a constant, not a unit
        m, reals = 0, reals[:0]
    return _Layout(points[:n_h], points[n_h:], reals[:n_h * m].reshape(n_h, m), reals[n_h * m:].reshape(n_f, m))


def _alarms(below: NDArray[np.floating], total: NDArray[np.floating], false_alarm: float) -> NDArray[np.bool_]:
    """Alarm when a value lies above the threshold of :func:`threshold_at` on ``total`` healthy values,
    ``below`` of which lie strictly below it (a tie with the threshold does not alarm)."""
    need = np.maximum(np.ceil((1.0 - false_alarm) * total - 1e-6), 1.0)
    return (below >= need) & (total > 0)


@dataclass(frozen=True)
class _Pairs:
    """Comparison matrices of oriented values on the pairs that share no unit (see :class:`_Layout`)."""

    ho: NDArray[np.float64]
    less: NDArray[np.float32]           # (n_h, n_f): h < f on kept pairs
    ties: NDArray[np.float32] | None    # (n_h, n_f): h = f on kept pairs; None when there is none
    keep: NDArray[np.float32]           # (n_h, n_f): kept pairs
    keep_hh: NDArray[np.bool_]          # (n_h, n_h): healthy pairs that share no unit

    @classmethod
    def of(cls, ho: NDArray[np.float64], fo: NDArray[np.float64], lay: _Layout) -> "_Pairs":
        k = lay.keep("h", "f")
        lt, eq = (ho[:, None] < fo[None, :]) & k, (ho[:, None] == fo[None, :]) & k
        return cls(ho, lt.astype(np.float32), eq.astype(np.float32) if eq.any() else None,
                   lay.keep_f32(), lay.keep("h", "h"))

    def stats(self, wh: NDArray[np.float32], wf: NDArray[np.float32], false_alarm: float,
              with_false_alarm: bool = True) -> NDArray[np.float64]:
        """(B, 3) AUC, POD and false-alarm rate for B rows of multiplicities (``wh`` (B, n_h), ``wf`` (B, n_f)).

        AUC: Mann-Whitney over the kept pairs; POD: each faulty value against the threshold of the
        healthy values it shares no unit with; false alarms (NaN unless ``with_false_alarm``): each
        healthy value likewise, out of sample.
        """
        with np.errstate(invalid="ignore", divide="ignore"):      # a re-draw may miss a population: NaN
            tot, below = wh @ self.keep, wh @ self.less
            num = below if self.ties is None else below + 0.5 * (wh @ self.ties)
            auc = np.sum(num * wf, axis=1) / np.sum(tot * wf, axis=1)
            pod = np.sum(_alarms(below, tot, false_alarm) * wf, axis=1) / np.sum(wf, axis=1)
            fa = np.full(len(wh), np.nan)
            if with_false_alarm:
                less_hh = ((self.ho[:, None] < self.ho[None, :]) & self.keep_hh).astype(np.float32)
                hit = _alarms(wh @ less_hh, wh @ self.keep_hh.astype(np.float32), false_alarm)
                fa = np.sum(hit * wh, axis=1) / np.sum(wh, axis=1)
        return np.column_stack([auc, pod, fa]).astype(float)


@dataclass(frozen=True)
class _Independent:
    """:class:`_Pairs` for measurements that are all independent (no unit shared): sorted counts, O(n) a re-draw."""

    ho: NDArray[np.float64]
    order: NDArray[np.intp]         # sorting permutation of ho
    lo_f: NDArray[np.intp]          # healthy values strictly below each faulty one (positions in the sorted ho)
    hi_f: NDArray[np.intp]          # ... at most equal
    lo_h: NDArray[np.intp]          # healthy values strictly below each healthy one

    @classmethod
    def of(cls, ho: NDArray[np.float64], fo: NDArray[np.float64]) -> "_Independent":
        order = np.argsort(ho, kind="stable")
        hs = ho[order]
        return cls(ho, order, np.searchsorted(hs, fo, "left"), np.searchsorted(hs, fo, "right"),
                   np.searchsorted(hs, ho, "left"))

    def stats(self, wh: NDArray[np.float32], wf: NDArray[np.float32], false_alarm: float,
              with_false_alarm: bool = True) -> NDArray[np.float64]:
        """As :meth:`_Pairs.stats` (the false-alarm rate costs nothing extra here)."""
        cum = np.zeros((len(wh), len(self.ho) + 1))
        cum[:, 1:] = np.cumsum(wh[:, self.order], axis=1, dtype=float)
        tot = cum[:, -1:]
        below, upto = cum[:, self.lo_f], cum[:, self.hi_f]
        auc = np.sum((below + 0.5 * (upto - below)) * wf, axis=1) / np.maximum(tot[:, 0] * wf.sum(axis=1), 1e-30)
        pod = np.sum(_alarms(below, tot, false_alarm) * wf, axis=1) / np.sum(wf, axis=1)
        fa_hit = _alarms(cum[:, self.lo_h], tot - wh, false_alarm)
        fa = np.sum(fa_hit * wh, axis=1) / np.sum(wh, axis=1)
        return np.column_stack([auc, pod, fa])


def _pairs(ho: NDArray[np.float64], fo: NDArray[np.float64], lay: _Layout) -> "_Pairs | _Independent":
    """The comparison counts of two oriented populations: sorted when no unit is shared, else dense."""
    independent = lay.real_h.shape[1] == 0 and len(np.unique(np.r_[lay.point_h, lay.point_f])) == len(ho) + len(fo)
    return _Independent.of(ho, fo) if independent else _Pairs.of(ho, fo, lay)


def _effective_n(x: NDArray[np.float64], w: NDArray[np.float32]) -> float:
    """Independent measurements worth the same as ``x`` for a mean: var(ranks) / bootstrap var(mean of ranks)."""
    r = stats.rankdata(x) / len(x)
    v = float(np.var(r, ddof=1))
    w = w[w.sum(axis=1) > 0]                 # a re-draw can miss every measurement (all rest on missed records)
    vb = float(np.var((w @ r) / w.sum(axis=1)))
    if vb <= 0 or v <= 0:
        return float(len(x))
    g = v / vb                  # a bootstrap of G units under-states the variance by (G - 1)/G
    return float(min(len(x), max(g - 1.0, 1.0)))


def _interval(est: float, boot: NDArray[np.float64], confidence: float, n_eff: float) -> tuple[float, float]:
    """Percentile interval of the bootstrap re-draws about ``est``, widened for few effective units.

    Its half-widths are scaled by ``t_(n_eff - 1) / z`` and ``sqrt(n_eff / (n_eff - 1))`` (the
    bootstrap of ``G`` units under-states the variance by ``(G - 1)/G`` and a t quantile fits
    an estimated spread); clipped to [0, 1].
    """
    a = (1.0 - confidence) / 2
    lo, hi = np.quantile(boot, [a, 1 - a])
    g = max(n_eff, 2.0)
    k = float(stats.t.ppf(1 - a, g - 1) / stats.norm.ppf(1 - a) * math.sqrt(g / (g - 1)))
    return max(0.0, est - k * max(est - lo, 0.0)), min(1.0, est + k * max(hi - est, 0.0))


def detect(healthy: ArrayLike, faulty: ArrayLike, output: str = "y",
           settings: DetectionSettings | None = None, seed: Seed = 0,
           units_healthy: ArrayLike | None = None, units_faulty: ArrayLike | None = None,
           direction: int | None = None) -> Detection:
    """Detection statistics of one sensor; see the module docstring for the definitions.

    Parameters
    ----------
    healthy, faulty : array_like
        One measurement per entry [output unit]; NaN marks a failed evaluation.
    output : str
        Sensor name for the result.
    settings : DetectionSettings
        False-alarm rate, POD target, confidence, bootstrap replicates (defaults when None).
    seed : int or SeedSequence
        Seed of the bootstrap.
    units_healthy, units_faulty : array_like, optional
        Per measurement, the parameter point and the wind records it rests on (:func:`layout`);
        equal labels are shared units, also across the populations. Statistics compare only
        measurements that share no unit, and the bootstrap re-draws whole units.
    direction : {+1, -1}, optional
        Alarm side; by default the side of the faulty population (AUC >= 1/2).

    Returns
    -------
    Detection

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> d = detect(rng.normal(0, 1, 400), rng.normal(4, 1, 400), seed=1)   # POD = Phi(4 - 1.645) = 0.991
    >>> bool(d.detectable), round(d.pod, 3), round(d.auc, 3)
    (True, 0.988, 0.997)
    """
    s = settings or DetectionSettings()
    h, f = np.asarray(healthy, dtype=float).ravel(), np.asarray(faulty, dtype=float).ravel()
    lay = layout(units_healthy, units_faulty, len(h), len(f))
    base = Detection(output, len(h), len(f))
    bad_h, bad_f = int(np.sum(~np.isfinite(h))), int(np.sum(~np.isfinite(f)))
    if bad_h or bad_f:
        return _refused(base, f"{bad_h} of {len(h)} healthy and {bad_f} of {len(f)} faulty measurements "
                              "failed or are not finite; the verdict is refused, not computed on the rest")
    need = math.ceil(1.0 / s.false_alarm - 1e-9)
    if len(h) < need or len(f) < 2:
        return _refused(base, f"{len(h)} healthy / {len(f)} faulty measurements cannot resolve a false-alarm "
                              f"rate of {s.false_alarm:g} (need >= {need} healthy, >= 2 faulty)")
    mh, mf, sd = float(np.mean(h)), float(np.mean(f)), float(np.std(h, ddof=1))
    moments = {"mean_healthy": mh, "mean_faulty": mf, "std_healthy": sd}
    if np.ptp(h) == 0.0:
        if np.ptp(f) == 0.0 and f[0] == h[0]:
            return _replace(base, **{**moments, "std_healthy": 0.0}, effect_size=0.0, detectable=False,
                            reason="output constant and unchanged by the fault")
        return _refused(_replace(base, **{**moments, "std_healthy": 0.0}),
                        "zero spread in the healthy population: no false-alarm threshold can be set "
                        "(state measurement noise for this output)")
    pairs = _pairs(h, f, lay)
    ones_h, ones_f = np.ones((1, len(h)), np.float32), np.ones((1, len(f)), np.float32)
    auc_raw = float(pairs.stats(ones_h, ones_f, s.false_alarm, False)[0, 0])
    d = direction if direction is not None else (1 if auc_raw >= 0.5 else -1)
    if d not in (1, -1):
        raise DetectionError(f"direction must be +1 or -1, got {direction!r}")
    if d == -1:
        pairs = _pairs(-h, -f, lay)
    wh, wf = lay.weights(s.bootstrap, _rng(seed))
    boot = np.vstack([pairs.stats(wh[i:i + 100], wf[i:i + 100], s.false_alarm, with_false_alarm=False)
                      for i in range(0, s.bootstrap, 100)])
    return _verdict(base, moments, d, threshold_at(d * h, s.false_alarm) * d,
                    pairs.stats(ones_h, ones_f, s.false_alarm)[0], boot, d * h, d * f, lay, wh, wf, s)


def _verdict(base: Detection, moments: dict[str, float], d: int, threshold: float, est: NDArray[np.float64],
             boot: NDArray[np.float64], ho: NDArray[np.float64], fo: NDArray[np.float64], lay: _Layout,
             wh: NDArray[np.float32], wf: NDArray[np.float32], s: DetectionSettings) -> Detection:
    """Intervals, effective sizes and the verdict from the estimates (AUC, POD, false alarms) and re-draws."""
    auc, pod, fa = (float(v) for v in est)
    boot = boot[np.isfinite(boot[:, :2]).all(axis=1)]      # re-draws that missed a whole population say nothing
    ne_h, ne_f = _effective_n(ho, wh), _effective_n(fo, wf)
    a_lo, a_hi = _interval(auc, boot[:, 0], s.confidence, min(ne_h, ne_f))
    p_lo, p_hi = _interval(pod, boot[:, 1], s.confidence, min(ne_h, ne_f))
    n_pod = min(ne_h, ne_f)                         # the threshold rests on the healthy units
    cp = clopper_pearson(pod * n_pod, n_pod, s.confidence)
    p_lo, p_hi = min(p_lo, cp[0]), max(p_hi, cp[1])
    n_auc = 3.0 * ne_h * ne_f / (ne_h + ne_f)       # binomial variance A(1-A)/n_auc = Mann-Whitney's at A = 1/2
    cp = clopper_pearson(auc * n_auc, n_auc, s.confidence)
    a_lo, a_hi = min(a_lo, cp[0]), max(a_hi, cp[1])
    reason, detectable = "", bool(p_lo >= s.target)
    need = 1.0 / s.false_alarm
    if ne_h < need - 1e-9:
        n_real, n_pts = (len(np.unique(lay.real_h)) if lay.real_h.size else 1), len(np.unique(lay.point_h))
        worth = f"{len(ho)} healthy measurements ({n_pts} points x {n_real} realisations) vary like {ne_h:.1f} " \
                "independent ones"
        if n_real < need:
            reason = (f"{n_real} realisations: POD resolution {1 / max(min(ne_h, n_real), 1.0):.2f}; add realisations "
                      f"({worth}: record-to-record variation dominates)")
        else:
            reason = (f"{worth}: POD resolution {1 / ne_h:.2f} cannot resolve a false-alarm rate of "
                      f"{s.false_alarm:g}; add parameter points or realisations")
        detectable = None
    mh, mf, sd = moments["mean_healthy"], moments["mean_faulty"], moments["std_healthy"]
    return Detection(base.output, base.n_healthy, base.n_faulty, mh, mf, sd, abs(mf - mh) / sd, d, threshold,
                     fa, pod, p_lo, p_hi, auc, a_lo, a_hi, detectable, reason, ne_h, ne_f)


def _replace(d: Detection, **kw: Any) -> Detection:
    return Detection(**{**asdict(d), **kw})


def _refused(d: Detection, reason: str) -> Detection:
    return _replace(d, detectable=None, reason=reason)


def _fisher(xh: NDArray[np.float64], xf: NDArray[np.float64], wh: NDArray[np.float64],
            wf: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Centre, scale and weights ``w = S^+ (mu_f - mu_h)`` of Fisher's discriminant on weighted measurements."""
    def moments(x: NDArray[np.float64], w: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        mu = (w @ x) / w.sum()
        d = x - mu
        return mu, (d * w[:, None]).T @ d
    mh, ch = moments(xh, wh)
    centre, scale = mh, np.sqrt(np.diag(ch) / max(wh.sum() - 1, 1.0))
    scale = np.where(scale > 0, scale, 1.0)
    mf, cf = moments(xf, wf)
    pooled = (ch + cf) / np.outer(scale, scale) / max(wh.sum() + wf.sum() - 2, 1.0)
    if not (np.isfinite(pooled).all() and np.isfinite(mf).all()):       # a population with no weight: no direction
        return centre, scale, np.full(len(scale), np.nan)
    return centre, scale, np.linalg.pinv(np.atleast_2d(pooled), rtol=1e-10) @ ((mf - mh) / scale)


def fisher_scores(healthy: NDArray[np.float64], faulty: NDArray[np.float64], seed: Seed = 0,
                  units_healthy: ArrayLike | None = None, units_faulty: ArrayLike | None = None,
                  weights: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Held-out scores of Fisher's linear discriminant, two-fold.

    The parameter points (every measurement its own when no units are given) are split at random
    into halves A and B, a point shared by both populations going to one half; the discriminant
    ``w = S^+ (mu_f - mu_h)`` of the standardised sensors (``S`` the pooled within-population
    covariance, pseudo-inverse for collinear sensors) is trained on A and scores B, and the other
    way round. Faulty scores tend to be larger.

    Parameters
    ----------
    healthy, faulty : ndarray, shape (n, n_sensors)
        Finite measurements.
    seed : int or SeedSequence
        Seed of the split.
    units_healthy, units_faulty : array_like, optional
        Units of the measurements (:func:`layout`).
    weights : tuple of ndarray, optional
        Multiplicities of the measurements in training (a bootstrap re-draw); default 1.

    Returns
    -------
    tuple of ndarray
        Held-out scores of every healthy and every faulty measurement [-].
    """
    lay = layout(units_healthy, units_faulty, len(healthy), len(faulty))
    n_points = int(max(lay.point_h.max(), lay.point_f.max())) + 1
    half = _rng(seed).permutation(n_points) % 2
    in_h, in_f = half[lay.point_h], half[lay.point_f]
    wh, wf = weights if weights is not None else (np.ones(len(healthy)), np.ones(len(faulty)))
    out_h, out_f = np.empty(len(healthy)), np.empty(len(faulty))
    for train in (0, 1):
        th, tf = in_h == train, in_f == train
        centre, scale, w = _fisher(healthy[th], faulty[tf], wh[th], wf[tf])
        out_h[~th] = ((healthy[~th] - centre) / scale) @ w
        out_f[~tf] = ((faulty[~tf] - centre) / scale) @ w
    return out_h, out_f


def detect_combined(healthy: ArrayLike, faulty: ArrayLike, settings: DetectionSettings | None = None,
                    seed: Seed = 0, units_healthy: ArrayLike | None = None,
                    units_faulty: ArrayLike | None = None) -> Detection:
    """Detection statistics of the multi-sensor detector (:func:`fisher_scores`, alarm above).

    The interval includes the training's variability: each bootstrap re-draw trains the
    discriminant again on the re-drawn measurements (``settings.bootstrap // 5`` re-draws, at
    least 100) before its held-out scores are counted.

    Parameters
    ----------
    healthy, faulty : array_like, shape (n, n_sensors)
        Measurements of every sensor; a row with any non-finite entry refuses the verdict.
    settings, seed, units_healthy, units_faulty
        As in :func:`detect` (``seed`` also splits the halves).
    """
    h, f = np.atleast_2d(np.asarray(healthy, dtype=float)), np.atleast_2d(np.asarray(faulty, dtype=float))
    if h.shape[1] != f.shape[1] or h.shape[1] < 2:
        raise DetectionError(f"the combined detector needs >= 2 sensors in both populations, got {h.shape[1]} "
                             f"and {f.shape[1]}")
    ok_h, ok_f = np.isfinite(h).all(axis=1), np.isfinite(f).all(axis=1)
    if not (ok_h.all() and ok_f.all()):
        return _refused(Detection(COMBINED, len(h), len(f)),
                        f"{int((~ok_h).sum())} of {len(h)} healthy and {int((~ok_f).sum())} of {len(f)} faulty "
                        "measurements failed or are not finite in some sensor")
    return _combined(h, f, settings, seed, units_healthy, units_faulty)[0]


def _combined(h: NDArray[np.float64], f: NDArray[np.float64], settings: DetectionSettings | None, seed: Seed,
              units_h: ArrayLike | None, units_f: ArrayLike | None
              ) -> tuple[Detection, tuple[NDArray[np.float64], NDArray[np.float64]]]:
    s = settings or DetectionSettings()
    split, boot = _seq(seed).spawn(2)
    sh, sf = fisher_scores(h, f, split, units_h, units_f)
    point = detect(sh, sf, COMBINED, s, boot, units_h, units_f, direction=1)
    if point.detectable is None and not np.isfinite(point.pod):
        return point, (sh, sf)
    lay = layout(units_h, units_f, len(h), len(f))
    n_boot = max(100, s.bootstrap // 5)
    wh, wf = lay.weights(n_boot, _rng(boot))
    reps = np.empty((n_boot, 3))
    for b in range(n_boot):
        with np.errstate(invalid="ignore", divide="ignore"):
            bh, bf = fisher_scores(h, f, split, units_h, units_f, (wh[b].astype(float), wf[b].astype(float)))
        ok = np.isfinite(bh).all() and np.isfinite(bf).all()      # a re-draw that misses a training half: none
        reps[b] = _pairs(bh, bf, lay).stats(wh[b:b + 1], wf[b:b + 1], s.false_alarm, False)[0] if ok else np.nan
    ones = _pairs(sh, sf, lay).stats(np.ones((1, len(h)), np.float32), np.ones((1, len(f)), np.float32),
                                        s.false_alarm)[0]
    moments = {"mean_healthy": point.mean_healthy, "mean_faulty": point.mean_faulty, "std_healthy": point.std_healthy}
    d = _verdict(Detection(COMBINED, len(h), len(f)), moments, 1, point.threshold, ones, reps, sh, sf, lay, wh, wf, s)
    return d, (sh, sf)


def select_sensors(healthy: pd.DataFrame, faulty: pd.DataFrame, settings: DetectionSettings | None = None,
                   seed: Seed = 0, units_healthy: ArrayLike | None = None, units_faulty: ArrayLike | None = None,
                   min_gain: float = 0.005) -> dict[str, Any]:
    """Greedy forward choice of the combined detector's sensors, validated on held-out points.

    The parameter points are split at random into a selection half and a validation half (a point
    shared by both populations goes to one half). On the selection half, sensors are added one at
    a time, each time the one whose Fisher detector (:func:`fisher_scores`, two-fold within the
    half) has the highest held-out AUC (over pairs sharing no unit), while the AUC grows by at least
    ``min_gain``. The chosen set and, for reference, all sensors are then trained on the whole
    selection half and scored on the validation half, which took no part in the choice: those
    statistics (:func:`detect`, with intervals) say what the choice is worth on new turbines.

    Parameters
    ----------
    healthy, faulty : DataFrame
        Finite measurements, one column per candidate sensor (>= 2).
    settings, seed, units_healthy, units_faulty
        As in :func:`detect`.
    min_gain : float
        Smallest AUC gain that adds a sensor [-].

    Returns
    -------
    dict
        ``sensors`` (chosen, in order), ``path`` (selection AUC after each addition) and
        ``validation`` / ``validation_all`` (:class:`Detection` of the chosen and of all sensors on
        the validation half).
    """
    s = settings or DetectionSettings()
    names = list(healthy.columns)
    if len(names) < 2:
        raise DetectionError(f"sensor selection needs >= 2 candidate sensors, got {names}")
    h, f = healthy.to_numpy(float), faulty.to_numpy(float)
    lay = layout(units_healthy, units_faulty, len(h), len(f))
    uh = np.column_stack([lay.point_h, lay.real_h]) if units_healthy is not None else None
    uf = np.column_stack([lay.point_f, lay.real_f]) if units_faulty is not None else None
    split, inner, boot = _seq(seed).spawn(3)
    half = _rng(split).permutation(int(max(lay.point_h.max(), lay.point_f.max())) + 1) % 2
    sel_h, sel_f = half[lay.point_h] == 0, half[lay.point_f] == 0
    sub = (lambda u, m: None if u is None else u[m])
    ones = (np.ones((1, int(sel_h.sum())), np.float32), np.ones((1, int(sel_f.sum())), np.float32))
    lay_sel = layout(sub(uh, sel_h), sub(uf, sel_f), int(sel_h.sum()), int(sel_f.sum()))

    def auc(cols: list[int]) -> float:
        sh, sf = fisher_scores(h[sel_h][:, cols], f[sel_f][:, cols], inner, sub(uh, sel_h), sub(uf, sel_f))
        return float(_pairs(sh, sf, lay_sel).stats(*ones, s.false_alarm, False)[0, 0])

    chosen: list[int] = []
    path: list[float] = []
    while len(chosen) < len(names):
        score, best = max((auc(chosen + [j]), j) for j in range(len(names)) if j not in chosen)
        if path and score < path[-1] + min_gain:
            break
        chosen.append(best)
        path.append(score)

    def validate(cols: list[int], out: str) -> Detection:
        centre, scale, w = _fisher(h[sel_h][:, cols], f[sel_f][:, cols], np.ones(int(sel_h.sum())),
                                   np.ones(int(sel_f.sum())))
        vh, vf = ((x[~m][:, cols] - centre) / scale @ w for x, m in ((h, sel_h), (f, sel_f)))
        return detect(vh, vf, out, s, boot, sub(uh, ~sel_h), sub(uf, ~sel_f), direction=1)

    return {"sensors": [names[j] for j in chosen], "path": path,
            "validation": validate(chosen, "selected"), "validation_all": validate(list(range(len(names))), "all")}


def _seq(seed: Seed) -> np.random.SeedSequence:
    """A fresh SeedSequence equal to ``seed`` (spawning from it does not change the caller's)."""
    if isinstance(seed, np.random.SeedSequence):
        return np.random.SeedSequence(seed.entropy, spawn_key=seed.spawn_key)
    return np.random.SeedSequence(seed)


@dataclass
class FaultDetectability:
    """Detection of one fault over its levels, per sensor and for the combined detector.

    Built by :func:`assess`. ``table`` holds one row per level and sensor (the
    :class:`Detection` fields plus ``level``); the measurements are kept for the histograms.
    """

    healthy_level: float
    settings: DetectionSettings
    table: pd.DataFrame
    healthy: pd.DataFrame
    faulty: dict[float, pd.DataFrame]
    scores: dict[float, tuple[NDArray[np.float64], NDArray[np.float64]]] = field(default_factory=dict)
    subsets: pd.DataFrame = field(default_factory=pd.DataFrame)
    """Per level, the greedy sensor choice and its held-out validation (:func:`select_sensors`)."""

    def to_frame(self) -> pd.DataFrame:
        """One row per fault level and sensor (``combined``: the multi-sensor detector)."""
        return self.table.copy()

    def best(self, level: float) -> str | None:
        """The single sensor with the highest POD lower bound at a level (None when all are refused)."""
        t = self.table[(self.table["level"] == level) & (self.table["output"] != COMBINED)
                       & self.table["detectable"].notna()]
        return None if t.empty else str(t.sort_values(["pod_low", "auc"], ascending=False)["output"].iloc[0])

    def deciding_output(self) -> str | None:
        """The single sensor that detects the smallest fault (POD lower bound), else the best at the
        most severe level; None when every verdict is refused."""
        sm = self.smallest_detectable()
        sm = sm[(sm["output"] != COMBINED) & np.isfinite(sm["level_at_target_lower"])]
        if len(sm):
            dist = np.abs(sm["level_at_target_lower"].to_numpy(float) - self.healthy_level)
            return str(sm["output"].iloc[int(np.argmin(dist))])
        levels = self.table["level"].to_numpy(float)
        return self.best(float(levels[np.argmax(np.abs(levels - self.healthy_level))]))

    def smallest_detectable(self) -> pd.DataFrame:
        """Per sensor: the fault level where POD, and its lower bound, reach the target.

        Levels are ordered by distance from the healthy level; POD is interpolated linearly in
        the level between the healthy level (where POD equals the false-alarm rate) and the
        faulty levels, at the first crossing. NaN with a reason when the target is not reached
        or a level's verdict is refused.
        """
        rows = []
        target = self.settings.target
        for out, g in self.table.groupby("output", sort=False):
            g = g.iloc[np.argsort(np.abs(g["level"].to_numpy(float) - self.healthy_level), kind="stable")]
            row: dict[str, Any] = {"output": out, "target": target, "false_alarm": self.settings.false_alarm}
            refused = g[g["detectable"].isna()]
            if len(refused):
                row.update(level_at_target=math.nan, level_at_target_lower=math.nan,
                           reason=f"level {refused['level'].iloc[0]:g}: {refused['reason'].iloc[0]}")
            else:
                levels = np.r_[self.healthy_level, g["level"].to_numpy(float)]
                for col, key in (("pod", "level_at_target"), ("pod_low", "level_at_target_lower")):
                    row[key] = _first_crossing(levels, np.r_[self.settings.false_alarm, g[col].to_numpy(float)],
                                               target)
                row["reason"] = "" if np.isfinite(row["level_at_target_lower"]) else \
                    "the POD lower bound does not reach the target within the levels"
            rows.append(row)
        return pd.DataFrame(rows)

    def plot_curve(self, ax: "Axes | None" = None, level_label: str = "fault level") -> "Axes":
        """The detectability curve: POD (with its interval) against fault level per sensor.

        ``level_label`` names the fault level's axis, with its unit (e.g. ``"k_front_z [N/m]"``);
        the legend stands right of the axes (a curve per sensor covers the plot otherwise)."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(6.5, 4))
        for out, g in self.table.groupby("output", sort=False):
            g = g.sort_values("level")
            x = np.r_[self.healthy_level, g["level"].to_numpy(float)]
            order = np.argsort(x)
            pod = np.r_[self.settings.false_alarm, g["pod"].to_numpy(float)][order]
            lo = np.r_[self.settings.false_alarm, g["pod_low"].to_numpy(float)][order]
            hi = np.r_[self.settings.false_alarm, g["pod_high"].to_numpy(float)][order]
            style = {"ls": "--", "lw": 2.0, "color": "k"} if out == COMBINED else {"ls": "-", "lw": 1.2}
            line, = ax.plot(x[order], pod, marker="o", ms=3, label=str(out), **style)
            ax.fill_between(x[order], lo, hi, color=line.get_color(), alpha=0.12, lw=0)
        ax.axhline(self.settings.target, color="tab:red", lw=0.8, ls=":", label=f"target {self.settings.target:g}")
        ax.axhline(self.settings.false_alarm, color="0.5", lw=0.8, ls=":",
                   label=f"false-alarm rate {self.settings.false_alarm:g}")
        ax.axvline(self.healthy_level, color="0.5", lw=0.6)
        ax.set_ylim(-0.02, 1.02)
        ax.set_xlabel(f"{level_label} (healthy {self.healthy_level:g}: grey line)")
        ax.set_ylabel("probability of detection [-]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
        return ax

    def plot_histograms(self, level: float, output: str | None = None, ax: "Axes | None" = None,
                        unit: str = "") -> "Axes":
        """Healthy and faulty measurements of one sensor (default: the best at ``level``) with the
        threshold; bars are each population's share of measurements per bin [-] (not a density,
        whose value would carry the inverse of the output's unit); ``unit``: the output's."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(5, 3.2))
        out = output or self.best(level)
        if out is None:
            ax.text(0.5, 0.5, "no verdict at this level", ha="center", transform=ax.transAxes)
            return ax
        if out == COMBINED:
            h, f = self.scores[level]
        else:
            h, f = self.healthy[out].to_numpy(float), self.faulty[level][out].to_numpy(float)
        row = self.table[(self.table["level"] == level) & (self.table["output"] == out)].iloc[0]
        both = np.r_[h, f]
        both = both[np.isfinite(both)]
        bins = np.histogram_bin_edges(both, bins=30) if np.ptp(both) > 0 else 10
        for values, label in ((h[np.isfinite(h)], "healthy"), (f[np.isfinite(f)], f"faulty {level:g}")):
            ax.hist(values, bins=bins, alpha=0.55, weights=np.full(len(values), 1.0 / max(len(values), 1)),
                    label=label)
        if np.isfinite(row["threshold"]):
            ax.axvline(row["threshold"], color="k", ls="--", lw=0.9,
                       label=f"threshold (false alarms {row['false_alarm']:.3f})")
        verdict = {True: "detectable", False: "not detectable"}.get(row["detectable"], "refused")
        ax.set_title(f"level {level:g}: {verdict}\nPOD {row['pod']:.2f} [{row['pod_low']:.2f}, {row['pod_high']:.2f}], "
                     f"AUC {row['auc']:.2f}", fontsize=8)
        ax.ticklabel_format(axis="x", style="sci", scilimits=(-2, 4), useOffset=False)
        ax.set_xlabel("Fisher score [-]" if out == COMBINED else f"{out} [{unit or '-'}]")
        ax.set_ylabel("share of measurements [-]")
        ax.legend(fontsize=7)
        return ax


def _varies(x: NDArray[np.float64]) -> bool:
    """True unless every value is finite and equal."""
    return not np.isfinite(x).all() or bool(np.ptp(x) > 0)


def _first_crossing(levels: NDArray[np.float64], pod: NDArray[np.float64], target: float) -> float:
    """Level where ``pod`` first reaches ``target`` along ``levels`` (linear interpolation; NaN if never)."""
    hit = np.flatnonzero(pod >= target)
    if not hit.size:
        return math.nan
    i = int(hit[0])
    if i == 0:
        return float(levels[0])
    frac = (target - pod[i - 1]) / (pod[i] - pod[i - 1])
    return float(levels[i - 1] + frac * (levels[i] - levels[i - 1]))


def assess(healthy: pd.DataFrame, faulty: Mapping[float, pd.DataFrame], healthy_level: float,
           settings: DetectionSettings | None = None, seed: Seed = 0, units: ArrayLike | None = None,
           combine: Sequence[str] | None = None, units_faulty: ArrayLike | None = None) -> FaultDetectability:
    """Detection of a fault at each level by each sensor and by the combined detector.

    Parameters
    ----------
    healthy : DataFrame
        One row per measurement, one column per sensor [output units]; NaN: failed.
    faulty : mapping of level -> DataFrame
        The same for each fault level (level in the fault parameter's unit).
    healthy_level : float
        The fault parameter's healthy value.
    settings : DetectionSettings
        False-alarm rate, POD target, confidence, bootstrap replicates.
    seed : int or SeedSequence
        Root seed; each level and sensor gets its own stream.
    units : array_like, optional
        Units (parameter point, wind records) of each healthy row (:func:`layout`).
    combine : sequence of str, optional
        Sensors of the combined detector (default: every column with healthy spread, when
        there are >= 2); the greedy sensor choice (:func:`select_sensors`) runs on them.
    units_faulty : array_like, optional
        Units of each faulty row, the same layout at every level (default: ``units``, the same
        points and records as the healthy rows: common random numbers).

    Returns
    -------
    FaultDetectability
    """
    s = settings or DetectionSettings()
    outputs = list(healthy.columns)
    if combine is None:      # a finite sensor without healthy spread cannot be standardised (refused alone);
        combine = [o for o in outputs if _varies(healthy[o].to_numpy(float))]     # failures stay in and refuse
    combine = list(combine)
    uf = units if units_faulty is None else units_faulty
    ss = _seq(seed)
    rows, scores, chosen = [], {}, []
    for level, (lev, frame) in zip(ss.spawn(len(faulty)), faulty.items()):
        if list(frame.columns) != outputs:
            raise DetectionError(f"fault level {lev:g}: columns {list(frame.columns)} differ from healthy {outputs}")
        streams = level.spawn(len(outputs) + 2)
        for out, stream in zip(outputs, streams):
            d = detect(healthy[out], frame[out], str(out), s, stream, units, uf)
            rows.append({"level": float(lev), **asdict(d)})
        if len(combine) >= 2:
            xh, xf = healthy[combine].to_numpy(float), frame[combine].to_numpy(float)
            if np.isfinite(xh).all() and np.isfinite(xf).all():
                d, scores[float(lev)] = _combined(xh, xf, s, streams[-2], units, uf)
                pick = select_sensors(healthy[combine], frame[combine], s, streams[-1], units, uf)
                chosen.append(_selection_row(float(lev), pick))
            else:
                d = detect_combined(xh, xf, s, streams[-2], units, uf)
            rows.append({"level": float(lev), **asdict(d), "output": COMBINED,
                         "reason": d.reason or "sensors: " + ", ".join(combine)})
    table = pd.DataFrame(rows)
    table["detectable"] = table["detectable"].astype(object)
    return FaultDetectability(healthy_level, s, table, healthy, {float(k): v for k, v in faulty.items()}, scores,
                              pd.DataFrame(chosen))


def _selection_row(level: float, pick: dict[str, Any]) -> dict[str, Any]:
    """One row of the sensor-choice table: the chosen set, its selection AUC and both validations."""
    row: dict[str, Any] = {"level": level, "sensors": ", ".join(pick["sensors"]), "n_sensors": len(pick["sensors"]),
                           "selection_auc": pick["path"][-1]}
    for key, d in (("", pick["validation"]), ("all_", pick["validation_all"])):
        row.update({f"{key}{k}": getattr(d, k) for k in ("auc", "auc_low", "auc_high", "pod", "pod_low", "pod_high",
                                                         "false_alarm", "detectable")})
    row["validation_n_healthy"] = pick["validation"].n_healthy
    row["reason"] = pick["validation"].reason
    return row
