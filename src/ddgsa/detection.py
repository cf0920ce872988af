"""Fault detectability as condition monitoring measures it: detection against false alarms.

Model-agnostic statistics on two populations of measurements of one or more sensors
(outputs): *healthy* and *faulty*. Each measurement is one value (one wind realisation of one
parameter point plus measurement noise), never an average. For one sensor the detector
raises an alarm when the measurement passes a threshold set on the healthy population:

- **false-alarm rate** ``alpha``: the threshold ``t`` is the smallest healthy order statistic
  with at most ``alpha`` of the healthy measurements beyond it;
- **probability of detection** ``POD = P(faulty beyond t)``, with the union of a Clopper-Pearson
  interval on the count of detected faulty measurements (binomial sampling, honest when all
  or none are detected) and a percentile bootstrap interval that re-draws both populations and
  the threshold (the threshold's own uncertainty; whole groups are re-drawn when the
  measurements come in correlated groups, e.g. the realisations of one parameter point);
- **ROC AUC** ``P(faulty beyond healthy)`` (Mann-Whitney, ties count one half) with a percentile
  bootstrap interval;
- **effect size** ``|mean_f - mean_h| / std_h``.

The side of the threshold (``direction``: +1 alarms above, -1 below) is the side the faulty
population lies on (AUC >= 1/2). A sensor is ``detectable`` when the lower end of the POD
interval reaches the POD target; a verdict is refused (``None``, with a reason) when any
measurement failed or is not finite, when the healthy population has zero spread, or when
it is too small to resolve the false-alarm rate (fewer than ``1/alpha`` measurements).

Several sensors are combined by Fisher's linear discriminant ``w = S^+ (mu_f - mu_h)``
(``S`` the pooled covariance of the standardised sensors) trained on one half of each
population and scored on the other, and vice versa; the held-out scores are then one
sensor to the statistics above.

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


def _auc(h: NDArray[np.float64], f: NDArray[np.float64]) -> float:
    """Mann-Whitney ``P(f > h) + P(f = h) / 2``."""
    hs = np.sort(h)
    below = np.searchsorted(hs, f, side="left")
    upto = np.searchsorted(hs, f, side="right")
    return float(np.mean(below + 0.5 * (upto - below)) / len(hs))


def _pod(h: NDArray[np.float64], f: NDArray[np.float64], false_alarm: float) -> float:
    """POD of an upper-tail alarm (``h`` and ``f`` already oriented)."""
    return float(np.mean(f > threshold_at(h, false_alarm)))


def clopper_pearson(k: int, n: int, confidence: float) -> tuple[float, float]:
    """Exact two-sided binomial interval for ``k`` successes in ``n`` trials."""
    a = (1.0 - confidence) / 2
    lo = float(stats.beta.ppf(a, k, n - k + 1)) if k > 0 else 0.0
    hi = float(stats.beta.ppf(1 - a, k + 1, n - k)) if k < n else 1.0
    return lo, hi


def _members(groups: ArrayLike | None, n: int) -> NDArray[np.intp] | list[NDArray[np.intp]]:
    """Indices of each group: a 2-D array when the groups have equal sizes (one row each), else a list."""
    if groups is None:
        return np.arange(n)[:, None]
    g = np.asarray(groups)
    if g.shape != (n,):
        raise DetectionError(f"groups must give one label per measurement ({n}), got shape {g.shape}")
    members = [np.flatnonzero(g == u) for u in np.unique(g)]
    return np.vstack(members) if len({len(m) for m in members}) == 1 else members


def _resample(members: NDArray[np.intp] | list[NDArray[np.intp]], rng: np.random.Generator) -> NDArray[np.intp]:
    """A bootstrap re-draw of whole groups (with replacement), as measurement indices."""
    pick = rng.integers(0, len(members), len(members))
    if isinstance(members, np.ndarray):
        return members[pick].ravel()
    return np.concatenate([members[i] for i in pick])


def detect(healthy: ArrayLike, faulty: ArrayLike, output: str = "y",
           settings: DetectionSettings | None = None, seed: Seed = 0,
           groups_healthy: ArrayLike | None = None, groups_faulty: ArrayLike | None = None,
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
    groups_healthy, groups_faulty : array_like, optional
        Group label per measurement; the bootstrap re-draws whole groups (correlated
        measurements, e.g. realisations of one parameter point).
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
    base = Detection(output, len(h), len(f))
    bad_h, bad_f = int(np.sum(~np.isfinite(h))), int(np.sum(~np.isfinite(f)))
    if bad_h or bad_f:
        return _refused(base, f"{bad_h} of {len(h)} healthy and {bad_f} of {len(f)} faulty measurements "
                              "failed or are not finite; the verdict is refused, not computed on the rest")
    if len(h) < math.ceil(1.0 / s.false_alarm - 1e-9) or len(f) < 2:
        return _refused(base, f"{len(h)} healthy / {len(f)} faulty measurements cannot resolve a false-alarm "
                              f"rate of {s.false_alarm:g} (need >= {math.ceil(1 / s.false_alarm - 1e-9)} healthy, "
                              ">= 2 faulty)")
    mh, mf, sd = float(np.mean(h)), float(np.mean(f)), float(np.std(h, ddof=1))
    moments = {"mean_healthy": mh, "mean_faulty": mf, "std_healthy": sd}
    if np.ptp(h) == 0.0:
        if np.ptp(f) == 0.0 and f[0] == h[0]:
            return _replace(base, **{**moments, "std_healthy": 0.0}, effect_size=0.0, detectable=False,
                            reason="output constant and unchanged by the fault")
        return _refused(_replace(base, **{**moments, "std_healthy": 0.0}),
                        "zero spread in the healthy population: no false-alarm threshold can be set "
                        "(state measurement noise for this output)")
    auc_raw = _auc(h, f)
    d = direction if direction is not None else (1 if auc_raw >= 0.5 else -1)
    if d not in (1, -1):
        raise DetectionError(f"direction must be +1 or -1, got {direction!r}")
    ho, fo = d * h, d * f
    t = threshold_at(ho, s.false_alarm)
    k = int(np.sum(fo > t))
    pod = k / len(f)
    cp = clopper_pearson(k, len(f), s.confidence)
    mem_h, mem_f = _members(groups_healthy, len(h)), _members(groups_faulty, len(f))
    boot = _bootstrap(ho, fo, mem_h, mem_f, s.false_alarm, s.bootstrap, _rng(seed))
    a = (1.0 - s.confidence) / 2
    (pb_lo, ab_lo), (pb_hi, ab_hi) = np.quantile(boot, [a, 1 - a], axis=0)
    pod_low, pod_high = min(cp[0], float(pb_lo)), max(cp[1], float(pb_hi))
    return Detection(output, len(h), len(f), mh, mf, sd, abs(mf - mh) / sd, d, d * t, float(np.mean(ho > t)),
                     pod, pod_low, pod_high, _auc(ho, fo), float(ab_lo), float(ab_hi),
                     bool(pod_low >= s.target), "")


def _bootstrap(ho: NDArray[np.float64], fo: NDArray[np.float64], mem_h: NDArray[np.intp] | list[NDArray[np.intp]],
               mem_f: NDArray[np.intp] | list[NDArray[np.intp]], false_alarm: float, n_boot: int,
               rng: np.random.Generator, chunk: int = 100) -> NDArray[np.float64]:
    """POD and AUC (columns) of ``n_boot`` re-draws of both populations (oriented: alarm above)."""
    out = np.empty((n_boot, 2))
    if isinstance(mem_h, list) or isinstance(mem_f, list):        # unequal groups: one re-draw at a time
        for b in range(n_boot):
            hb, fb = ho[_resample(mem_h, rng)], fo[_resample(mem_f, rng)]
            out[b] = _pod(hb, fb, false_alarm), _auc(hb, fb)
        return out
    # every re-draw takes values from the same pool: count with dense integer codes of the pooled
    # values, one histogram per re-draw, instead of sorting each re-draw
    _, codes = np.unique(np.r_[ho, fo], return_inverse=True)
    code_h, code_f, n_codes = codes[:len(ho)], codes[len(ho):], int(codes.max()) + 1
    k = _order(mem_h.size, false_alarm)
    for start in range(0, n_boot, chunk):                           # vectorised, ``chunk`` re-draws at once
        m = min(chunk, n_boot - start)
        ch = code_h[mem_h[rng.integers(0, len(mem_h), (m, len(mem_h)))].reshape(m, -1)]
        cf = code_f[mem_f[rng.integers(0, len(mem_f), (m, len(mem_f)))].reshape(m, -1)]
        rows = np.arange(m)[:, None]
        hist = np.bincount((ch + n_codes * rows).ravel(), minlength=m * n_codes).reshape(m, n_codes)
        upto = np.cumsum(hist, axis=1)                              # healthy values <= each code
        t = np.argmax(upto > k, axis=1)                             # code of the (k+1)-th smallest
        out[start:start + m, 0] = np.mean(cf > t[:, None], axis=1)
        below = (upto - hist)[rows, cf]
        out[start:start + m, 1] = np.mean(below + 0.5 * hist[rows, cf], axis=1) / ch.shape[1]
    return out


def _replace(d: Detection, **kw: Any) -> Detection:
    return Detection(**{**asdict(d), **kw})


def _refused(d: Detection, reason: str) -> Detection:
    return _replace(d, detectable=None, reason=reason)


def fisher_scores(healthy: NDArray[np.float64], faulty: NDArray[np.float64],
                  seed: Seed = 0) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Held-out scores of Fisher's linear discriminant, two-fold.

    Each population is split at random into halves A and B; the discriminant
    ``w = S^+ (mu_f - mu_h)`` of the standardised sensors (``S`` the pooled within-population
    covariance, pseudo-inverse for collinear sensors) is trained on A and scores B, and the
    other way round. Faulty scores tend to be larger.

    Parameters
    ----------
    healthy, faulty : ndarray, shape (n, n_sensors)
        Finite measurements.
    seed : int or SeedSequence
        Seed of the split.

    Returns
    -------
    tuple of ndarray
        Held-out scores of every healthy and every faulty measurement [-].
    """
    rng = _rng(seed)
    halves = [np.array_split(rng.permutation(len(x)), 2) for x in (healthy, faulty)]
    out_h, out_f = np.empty(len(healthy)), np.empty(len(faulty))
    for train, test in ((0, 1), (1, 0)):
        xh, xf = healthy[halves[0][train]], faulty[halves[1][train]]
        centre, scale = xh.mean(axis=0), xh.std(axis=0, ddof=1)
        scale = np.where(scale > 0, scale, 1.0)
        zh, zf = (xh - centre) / scale, (xf - centre) / scale
        pooled = (np.cov(zh, rowvar=False, ddof=1) * (len(zh) - 1)
                  + np.cov(zf, rowvar=False, ddof=1) * (len(zf) - 1)) / (len(zh) + len(zf) - 2)
        w = np.linalg.pinv(np.atleast_2d(pooled), rtol=1e-10) @ (zf.mean(axis=0) - zh.mean(axis=0))
        out_h[halves[0][test]] = ((healthy[halves[0][test]] - centre) / scale) @ w
        out_f[halves[1][test]] = ((faulty[halves[1][test]] - centre) / scale) @ w
    return out_h, out_f


def detect_combined(healthy: ArrayLike, faulty: ArrayLike, settings: DetectionSettings | None = None,
                    seed: Seed = 0, groups_healthy: ArrayLike | None = None,
                    groups_faulty: ArrayLike | None = None) -> Detection:
    """Detection statistics of the multi-sensor detector (:func:`fisher_scores`, alarm above).

    Parameters
    ----------
    healthy, faulty : array_like, shape (n, n_sensors)
        Measurements of every sensor; a row with any non-finite entry refuses the verdict.
    settings, seed, groups_healthy, groups_faulty
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
    return _combined(h, f, settings, seed, groups_healthy, groups_faulty)[0]


def _combined(h: NDArray[np.float64], f: NDArray[np.float64], settings: DetectionSettings | None, seed: Seed,
              groups_h: ArrayLike | None, groups_f: ArrayLike | None
              ) -> tuple[Detection, tuple[NDArray[np.float64], NDArray[np.float64]]]:
    split, boot = _seq(seed).spawn(2)
    sh, sf = fisher_scores(h, f, seed=split)
    return detect(sh, sf, COMBINED, settings, boot, groups_h, groups_f, direction=1), (sh, sf)


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
           settings: DetectionSettings | None = None, seed: Seed = 0, groups: ArrayLike | None = None,
           combine: Sequence[str] | None = None) -> FaultDetectability:
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
    groups : array_like, optional
        Group label per row (the same layout in every population): bootstrap by group.
    combine : sequence of str, optional
        Sensors of the combined detector (default: every column with healthy spread, when
        there are >= 2).

    Returns
    -------
    FaultDetectability
    """
    s = settings or DetectionSettings()
    outputs = list(healthy.columns)
    if combine is None:      # a finite sensor without healthy spread cannot be standardised (refused alone);
        combine = [o for o in outputs if _varies(healthy[o].to_numpy(float))]     # failures stay in and refuse
    combine = list(combine)
    ss = _seq(seed)
    rows, scores = [], {}
    for level, (lev, frame) in zip(ss.spawn(len(faulty)), faulty.items()):
        if list(frame.columns) != outputs:
            raise DetectionError(f"fault level {lev:g}: columns {list(frame.columns)} differ from healthy {outputs}")
        streams = level.spawn(len(outputs) + 1)
        for out, stream in zip(outputs, streams):
            d = detect(healthy[out], frame[out], str(out), s, stream, groups, groups)
            rows.append({"level": float(lev), **asdict(d)})
        if len(combine) >= 2:
            xh, xf = healthy[combine].to_numpy(float), frame[combine].to_numpy(float)
            if np.isfinite(xh).all() and np.isfinite(xf).all():
                d, scores[float(lev)] = _combined(xh, xf, s, streams[-1], groups, groups)
            else:
                d = detect_combined(xh, xf, s, streams[-1], groups, groups)
            rows.append({"level": float(lev), **asdict(d), "output": COMBINED,
                         "reason": d.reason or "sensors: " + ", ".join(combine)})
    table = pd.DataFrame(rows)
    table["detectable"] = table["detectable"].astype(object)
    return FaultDetectability(healthy_level, s, table, healthy, {float(k): v for k, v in faulty.items()}, scores)
