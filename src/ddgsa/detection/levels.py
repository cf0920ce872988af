"""A fault over its levels: per sensor and combined detectability, the first level detected,
the chosen sensors (:func:`assess`, the fault study kind's statistics)."""


from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from ddgsa.detection.combined import _combined, detect_combined, select_sensors
from ddgsa.detection.single import COMBINED, DetectionError, DetectionSettings, Seed, _seq, detect

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes


def draw_pod(ax: "Axes", rows: pd.DataFrame, healthy: float, target: float, false_alarm: float, level_label: str,
             label_bands: bool = False) -> None:
    """The detectability curves on ``ax``: per sensor (``rows``' ``output``; the combined detector dashed black)
    its POD with the interval shaded against the fault ``level``, starting at the ``healthy`` level at the
    false-alarm rate; dotted lines at the POD ``target`` and the ``false_alarm`` rate; the healthy level a grey
    line. The one drawing of the curve: :meth:`FaultDetectability.plot_curve` and the report's fault section
    (from ``fault_verdicts.csv``) both call it. ``label_bands``: the shading carries its sensor's label too
    (a legend toggle then hides both)."""
    for out, g in rows.groupby("output", sort=False):
        g = g.sort_values("level")
        x = np.r_[healthy, g["level"].to_numpy(float)]
        order = np.argsort(x)
        pod = np.r_[false_alarm, g["pod"].to_numpy(float)][order]
        lo = np.r_[false_alarm, g["pod_low"].to_numpy(float)][order]
        hi = np.r_[false_alarm, g["pod_high"].to_numpy(float)][order]
        style = {"ls": "--", "lw": 2.0, "color": "k"} if out == COMBINED else {"ls": "-", "lw": 1.2}
        line, = ax.plot(x[order], pod, marker="o", ms=3, label=str(out), **style)
        ax.fill_between(x[order], lo, hi, color=line.get_color(), alpha=0.12, lw=0,
                        **({"label": str(out)} if label_bands else {}))
    ax.axhline(target, color="tab:red", lw=0.8, ls=":", label=f"target {target:g}")
    ax.axhline(false_alarm, color="0.5", lw=0.8, ls=":", label=f"false-alarm rate {false_alarm:g}")
    ax.axvline(healthy, color="0.5", lw=0.6)
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlabel(f"{level_label} (healthy {healthy:g}: grey line)")
    ax.set_ylabel("probability of detection [-]")
    ax.grid(alpha=0.3)


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
        draw_pod(ax, self.table, self.healthy_level, self.settings.target, self.settings.false_alarm, level_label)
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
