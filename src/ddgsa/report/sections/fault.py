"""Fault detectability: the verdict per sensor and level, the smallest detectable fault, the indices of
the other parameters with and without the fault (:mod:`ddgsa.detection`).

Tables: ``fault_verdicts.csv``, ``fault_smallest.csv``, ``fault_indices.csv`` and, where sensors were
chosen, ``fault_sensor_choice.csv``. Charts from them: ``fault_detectability_scene<k>.png`` (POD against
the fault level per sensor) and ``fault_indices_scene<k>.png``; from the result alone (the raw
measurements no table holds): ``fault_histograms_scene<k>.png``.
"""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ddgsa.detection.levels import draw_pod
from ddgsa.report.sections.base import Chart, Folder, ResultFigure, Section, Tables, csv_tables
from ddgsa.study.spec import scene_text

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from ddgsa.detection import FaultDetectability
    from ddgsa.execute.kinds.common import StudyResult
    from ddgsa.models.base import ModelOutput

PANELS_PER_ROW = 4
"""Panels a row of the index-shift chart."""
TABLES = ("fault_verdicts.csv", "fault_smallest.csv", "fault_indices.csv", "fault_sensor_choice.csv")


def tables(result: "StudyResult", info: dict[str, "ModelOutput"]) -> Tables:
    if result.fault is None:
        return []
    out = [("fault_verdicts.csv", result.fault), ("fault_smallest.csv", result.fault_smallest),
           ("fault_indices.csv", result.fault_indices)]
    if result.fault_subsets is not None:
        out.append(("fault_sensor_choice.csv", result.fault_subsets))
    return out


def figures(result: "StudyResult") -> list[ResultFigure]:
    """The healthy and faulty histograms of each scene's deciding output (raw measurements: no table holds them)."""
    if result.fault is None:
        return []
    units = {o: d.unit for o, d in result.study.output_declarations().items()}
    return [(f"fault_histograms_scene{ps.index}.png",
             functools.partial(plot_fault_histograms, det, scene_text(ps.fields), units))
            for ps, det in result.fault_detection]


def plot_fault_histograms(det: "FaultDetectability", title: str, units: dict[str, str] | None = None) -> "Figure":
    """Healthy/faulty histograms of the deciding output, one panel per faulty level (``units``: per output)."""
    levels = sorted(det.faulty, key=lambda v: abs(v - det.healthy_level))
    out = det.deciding_output()
    ncols = min(3, len(levels))
    nrows = -(-len(levels) // ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.2 * ncols, 3.3 * nrows), squeeze=False)
    for ax, level in zip(axes.flat, levels):
        det.plot_histograms(level, output=out, ax=ax, unit=(units or {}).get(str(out), ""))
    for ax in axes.flat[len(levels):]:
        ax.set_visible(False)
    fig.suptitle(f"deciding output {out}, {title}", fontsize=9)
    fig.tight_layout()
    return fig


def plot_detectability(rows: pd.DataFrame, level_label: str, target: float, false_alarm: float, title: str,
                       confidence: float | None = None) -> "Figure":
    """POD (with its interval) against the fault level per sensor, the healthy level at the false-alarm
    rate; dotted: the POD ``target`` and the ``false_alarm`` rate; ``level_label``: the fault's axis with
    its unit; the legend right of the axes (a curve per sensor covers the plot otherwise)."""
    fig, ax = plt.subplots(figsize=(8.5, 4.2))
    draw_pod(ax, rows.rename(columns={"faulty": "level"}), float(rows["healthy"].iloc[0]), target, false_alarm,
             level_label, label_bands=True)
    handles, labels = ax.get_legend_handles_labels()
    ax.legend([h for h, lab, k in zip(handles, labels, range(len(labels))) if labels.index(lab) == k],
              list(dict.fromkeys(labels)), fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    shaded = f"POD interval at confidence {confidence:g}" if confidence else "POD interval"
    ax.set_title(f"detectability curve, {title}\nshaded: {shaded}", fontsize=9)
    fig.tight_layout()
    return fig


def plot_fault_indices(rows: pd.DataFrame, fault: str, title: str) -> "Figure":
    """Paper A's view: total index of each other parameter per output, healthy and at each faulty level;
    one panel per output, at most :data:`PANELS_PER_ROW` a row (more made the figure too wide to read)."""
    method = rows["method"].iloc[0]
    rows = rows[rows["method"] == method]
    outputs, levels = list(rows["output"].unique()), list(rows["level"].unique())
    params = list(rows["parameter"].unique())
    ncols = min(PANELS_PER_ROW, len(outputs))
    nrows = -(-len(outputs) // ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(3.2 * ncols + 0.5, 3.4 * nrows), squeeze=False, sharey=True)
    width = 0.8 / len(levels)
    for ax, out in zip(axes.flat, outputs):
        t = rows[rows["output"] == out]
        for k, level in enumerate(levels):
            st = t[t["level"] == level].set_index("parameter").reindex(params)["ST"]
            ax.bar(np.arange(len(params)) + (k - (len(levels) - 1) / 2) * width, st, width,
                   label=f"{fault} = {level:g}" + (" (healthy)" if k == 0 else ""))
        ax.set_xticks(range(len(params)), params, rotation=60, fontsize=7, ha="right")
        ax.set_title(out, fontsize=8)
        ax.grid(alpha=0.3, axis="y")
    for ax in list(axes.flat)[len(outputs):]:
        ax.set_visible(False)
    for row in axes:
        row[0].set_ylabel(f"ST ({method}) [-]")
    axes[0, 0].legend(fontsize=6)
    fig.suptitle(f"indices of the other parameters with and without the fault, {title}", fontsize=9)
    fig.tight_layout()
    return fig


def _scene_titles(ver: pd.DataFrame) -> dict[int, str]:
    """Each scene's label (``kind=steady, speed_rpm=1500``): the columns of ``fault_verdicts.csv`` between
    ``scene`` and ``fault``."""
    cols = list(ver.columns)
    fields = cols[cols.index("scene") + 1:cols.index("fault")] if "fault" in cols else []
    return {int(s): scene_text(dict(g[fields].iloc[0])) for s, g in ver.groupby("scene", sort=True)}


def charts(folder: Folder) -> list[Chart]:
    ver = folder.csv("fault_verdicts.csv")
    if ver is None or not len(ver):
        return []
    small = folder.csv("fault_smallest.csv")
    target = float(small["target"].iloc[0]) if small is not None and len(small) else float("nan")
    false_alarm = float(small["false_alarm"].iloc[0]) if small is not None and len(small) else float("nan")
    fault = str(ver["fault"].iloc[0])
    confidence = (folder.study.get("fault") or {}).get("confidence")
    titles = _scene_titles(ver)
    fi = folder.csv("fault_indices.csv")
    out = []
    for scene, g in ver.groupby("scene", sort=True):
        out.append(Chart(f"fault_detectability_scene{scene}.png",
                         f"scene {scene}: POD at false-alarm rate {false_alarm:g} against the fault level, shaded: its "
                         f"confidence interval; dotted: the target {target:g}", "pod",
                         functools.partial(plot_detectability, g, f"{fault} [{folder.units.get(fault) or '-'}]",
                                           target, false_alarm, titles[int(scene)], confidence)))
        rows = fi[fi["scene"] == scene] if fi is not None else None
        if rows is not None and len(rows):
            out.append(Chart(f"fault_indices_scene{scene}.png",
                             f"scene {scene}: ST of each other parameter per output, healthy and at each faulty level",
                             "bars", functools.partial(plot_fault_indices, rows, fault, titles[int(scene)])))
    return out


def html(folder: Folder) -> str:
    found = charts(folder)
    if not found:
        return ""
    return "".join(folder.figure(c) for c in found) + csv_tables(folder, TABLES)


SECTION = Section("fault", "Fault detectability", html, tables=tables, charts=charts, figures=figures, shows=TABLES)
