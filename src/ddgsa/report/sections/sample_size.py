"""Indices against sample size: ``convergence.csv``, the study's indices recomputed on nested sub-samples of
its own runs; per method and output of the first scene, each parameter's ST against the runs with the
method's error bound shaded (the last point is the study's own index). Charts on the page only."""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ddgsa.report.sections.base import Chart, Folder, Section, Tables, table, trusted

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from ddgsa.execute.kinds.common import StudyResult
    from ddgsa.models.base import ModelOutput

MAX_CURVES = 8
"""Convergence charts per page (method x output of the first scene)."""


def tables(result: "StudyResult", info: dict[str, "ModelOutput"]) -> Tables:
    conv = result.convergence
    return [("convergence.csv", conv)] if conv is not None and len(conv) else []


def plot_sample_size(g: pd.DataFrame, title: str) -> "Figure":
    """ST of each parameter against the runs of nested sub-samples, +- the bound shaded (held in
    [-0.05, 1.05]), open markers untrusted; log runs where they span a decade."""
    fig, ax = plt.subplots(figsize=(7.0, 3.8), layout="constrained")
    for k, (par, gp) in enumerate(g.groupby("parameter", sort=False)):
        gp = gp.sort_values("n_evals")
        x, st, err = gp["n_evals"].to_numpy(float), gp["ST"].to_numpy(float), gp["ST_conf"].to_numpy(float)
        err = np.where(np.isfinite(err), err, 0.0)
        ok = trusted(gp)
        color = f"C{k % 10}"
        ax.plot(x, st, color=color, lw=1.2, marker="o", ms=3, label=str(par))
        ax.fill_between(x, np.clip(st - err, -0.05, 1.05), np.clip(st + err, -0.05, 1.05), color=color, alpha=0.15,
                        lw=0, label=str(par))
        ax.scatter(x[~ok], st[~ok], s=16, facecolors="white", edgecolors=color, zorder=3, label=str(par))
    runs = g["n_evals"].to_numpy(float)
    runs = runs[np.isfinite(runs) & (runs > 0) & np.isfinite(g["ST"].to_numpy(float))]     # what is drawn
    if runs.size and runs.max() >= 10 * runs.min():
        ax.set_xscale("log")
    ax.set_ylim(-0.05, 1.05)
    ax.set_xlabel("model runs [runs]")
    ax.set_ylabel("ST, total index [-]")
    ax.grid(alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    seen = [labels.index(lab) for lab in dict.fromkeys(labels)]
    ax.legend([handles[i] for i in seen], [labels[i] for i in seen], fontsize=7, loc="upper left",
              bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    ax.set_title(title, fontsize=9)
    return fig


def _table(folder: Folder) -> pd.DataFrame | None:
    conv = folder.csv("convergence.csv")
    if conv is None or not len(conv) or not {"scene", "method", "parameter"} <= set(conv.columns):
        return None                                    # another tool's table of that name
    return conv


def charts(folder: Folder) -> list[Chart]:
    conv = _table(folder)
    if conv is None:
        return []
    first = conv[conv["scene"] == conv["scene"].min()]
    return [Chart(None, f"scene {int(g['scene'].iloc[0])}, {method}: ST of {output} on nested sub-samples",
                  "convergence", functools.partial(plot_sample_size, g, f"{output}: ST against runs ({method})"))
            for (method, output), g in list(first.groupby(["method", "output"], sort=False))[:MAX_CURVES]]


def html(folder: Folder) -> str:
    conv = _table(folder)
    if conv is None:
        return ""
    parts = ["<p>The study's indices recomputed on nested sub-samples of its own runs (no new run): each "
             "parameter's ST against the runs, the method's error bound shaded, open markers untrusted; the "
             "last point is the study's index. A curve that still moves at the right, or a band wider than the "
             "differences that matter, asks for more runs. M-DRM and quadrature PCE have no nested "
             "sub-sample and no curve.</p>"]
    parts += [folder.figure(c) for c in charts(folder)]
    n = conv[conv["scene"] == conv["scene"].min()].groupby(["method", "output"], sort=False).ngroups
    if n > MAX_CURVES:
        parts.append(f"<p>{n - MAX_CURVES} more (method, output) curves in <code>convergence.csv</code>.</p>")
    parts.append(table(conv, "convergence", "convergence.csv"))
    return "".join(parts)


SECTION = Section("sample_size", "Indices against sample size", html, tables=tables, charts=charts,
                  shows=("convergence.csv",))
