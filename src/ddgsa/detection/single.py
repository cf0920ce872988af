"""One sensor's detectability: threshold, false alarms, POD, ROC AUC and their intervals
over the units measurements rest on (the method: :mod:`ddgsa.detection`)."""


from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import stats

from ddgsa.errors import DdgsaError


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

def _seq(seed: Seed) -> np.random.SeedSequence:
    """A fresh SeedSequence equal to ``seed`` (spawning from it does not change the caller's)."""
    if isinstance(seed, np.random.SeedSequence):
        return np.random.SeedSequence(seed.entropy, spawn_key=seed.spawn_key)
    return np.random.SeedSequence(seed)

