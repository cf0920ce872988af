"""Groups: closed and total indices of parameter groups (:mod:`ddgsa.gsa.groups`): ``groups.csv`` (one row per
scene, method, output and group) and ``groups_scene<k>.png``."""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ddgsa.report.beyond import group_table
from ddgsa.report.sections.base import Chart, Folder, Section, Tables, table

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from ddgsa.execute.kinds.common import StudyResult
    from ddgsa.models.base import ModelOutput


def tables(result: "StudyResult", info: dict[str, "ModelOutput"]) -> Tables:
    groups = group_table(result) if len(result.indices) else []
    return [("groups.csv", groups)] if len(groups) else []


def plot_groups(rows: pd.DataFrame) -> "Figure":
    """Closed (S_closed) and total (ST) index of each group and method, one panel per output, error bars
    the bounds; groups down the y axis (``group (method)``), so long names read without rotation."""
    outputs = list(dict.fromkeys(rows["output"]))
    n = int((rows["output"] == outputs[0]).sum())
    fig, axes = plt.subplots(1, len(outputs), figsize=(3.6 * len(outputs) + 1.5, 0.35 * n + 1.2), squeeze=False,
                             sharey=True)
    for ax, out in zip(axes[0], outputs):
        g = rows[rows["output"] == out]
        y = np.arange(len(g))
        for k, (q, color) in enumerate((("S_closed", "tab:blue"), ("ST", "tab:orange"))):
            err = g[f"{q}_conf"].to_numpy(float)
            ax.barh(y + (k - 0.5) * 0.38, g[q], 0.38, label=q, color=color,
                    xerr=np.where(np.isfinite(err), err, 0.0), capsize=2)
        ax.set_yticks(y, [f"{grp} ({m})" for grp, m in zip(g["group"], g["method"])], fontsize=8)
        ax.set_title(out, fontsize=9)
        ax.set_xlim(0, 1.05)
        ax.set_xlabel("group index [-]", fontsize=8)
    axes[0][0].invert_yaxis()
    axes[0][-1].legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    return fig


def charts(folder: Folder) -> list[Chart]:
    groups = folder.csv("groups.csv")
    if groups is None or not len(groups):
        return []
    return [Chart(f"groups_scene{scene}.png", f"scene {scene}: closed and total index of each group, whiskers: the "
                  "method's error bound", "bars", functools.partial(plot_groups, groups[groups["scene"] == scene]))
            for scene in sorted(groups["scene"].unique())]


def html(folder: Folder) -> str:
    found = charts(folder)
    if not found:
        return ""
    return "".join(folder.figure(c) for c in found) + table(folder.csv("groups.csv"), "groups", "groups.csv")


SECTION = Section("groups", "Groups of parameters", html, tables=tables, charts=charts, shows=("groups.csv",))
