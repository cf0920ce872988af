"""Indices of signals: per scene, method and signal, the total index of each parameter in each bin of the
signal's axis (frequency, order, time) with its error band, above the variance of each bin (the weight the
bin carries in the generalised index, Gamboa et al. 2014), and the generalised table.

Tables: ``signal_indices.csv`` (one row per scene, method, signal, bin and parameter) and
``signal_generalised.csv``. Charts (on the page only): one per (scene, method, signal).
"""

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

MAX_CHARTS = 12
"""Signal charts per page (scene x method x signal); the CSVs hold all."""
QUIET_BIN = 1e-4
"""Bins whose variance is below this fraction of the largest are not drawn on the index chart: their
indices are ratios of round-off and weigh nothing in the generalised index."""
SHOWN_INDEX = 0.02
"""Parameters whose ST stays below this in every bin are named in the caption, not drawn."""


def tables(result: "StudyResult", info: dict[str, "ModelOutput"]) -> Tables:
    return [(name, df) for df, name in ((result.signal_indices, "signal_indices.csv"),
                                        (result.signal_generalised, "signal_generalised.csv"))
            if df is not None and len(df)]


def plot_signal(g: pd.DataFrame, title: str) -> "Figure":
    """Top: ST of each parameter per (loud) bin, shaded +- its bound held in [-0.05, 1.05], open markers
    untrusted; bottom: the variance of each bin (log scale). ``g``: one (scene, method, signal) of
    ``signal_indices.csv``."""
    first = g.iloc[0]
    var = g.drop_duplicates("bin").set_index("bin")["variance"]
    loud = var.index[var.to_numpy(float) >= QUIET_BIN * np.nanmax(var.to_numpy(float))]
    fig, (ax, av) = plt.subplots(2, 1, figsize=(7.5, 5.2), sharex=True, height_ratios=(2.2, 1), layout="constrained")
    for k, (par, gp) in enumerate(g.groupby("parameter", sort=False)):
        gp = gp[gp["bin"].isin(loud)]
        st, err = gp["ST"].to_numpy(float), gp["ST_conf"].to_numpy(float)
        if not np.nanmax(st, initial=0.0) >= SHOWN_INDEX:
            continue
        err = np.where(np.isfinite(err), err, 0.0)
        x, ok = gp["axis"].to_numpy(float), trusted(gp)
        ax.plot(x, st, color=f"C{k % 10}", lw=1.2, label=str(par))
        ax.fill_between(x, np.clip(st - err, -0.05, 1.05), np.clip(st + err, -0.05, 1.05), color=f"C{k % 10}",
                        alpha=0.18, lw=0, label=str(par))
        ax.scatter(x[~ok], st[~ok], s=14, facecolors="white", edgecolors=f"C{k % 10}", zorder=3, label=str(par))
    ax.set_ylim(-0.05, 1.05)
    ax.set_ylabel("ST, total index [-]")
    ax.grid(alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        seen = [labels.index(lab) for lab in dict.fromkeys(labels)]
        ax.legend([handles[i] for i in seen], [labels[i] for i in seen], fontsize=7, loc="upper left",
                  bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    ax.set_title(title, fontsize=9)
    vx = g.drop_duplicates("bin")
    positive = vx["variance"].to_numpy(float) > 0
    av.plot(vx["axis"].to_numpy(float)[positive], vx["variance"].to_numpy(float)[positive], color="0.3", lw=1.0,
            marker=".", ms=3)
    if positive.any():
        av.set_yscale("log")
    av.set_ylabel(f"variance [{first['unit']}^2]")
    av.set_xlabel(f"{first['axis_name']} [{first['axis_unit']}]")
    av.grid(alpha=0.3)
    return fig


def charts(folder: Folder) -> list[Chart]:
    bins = folder.csv("signal_indices.csv")
    if bins is None or not len(bins):
        return []
    out = []
    for (scene, method, signal), g in list(bins.groupby(["scene", "method", "signal"], sort=False))[:MAX_CHARTS]:
        quiet = [str(p) for p, gp in g.groupby("parameter", sort=False)
                 if not np.nanmax(gp["ST"].to_numpy(float), initial=0.0) >= SHOWN_INDEX]
        below = f"; ST below {SHOWN_INDEX:g} in every bin: {', '.join(quiet)}" if quiet else ""
        out.append(Chart(None, f"scene {scene}, {method}: total index of each parameter against "
                         f"{g['axis_name'].iloc[0]}, and the variance of {signal} in each bin" + below, "signal",
                         functools.partial(plot_signal, g, f"{signal}: ST per bin ({method})")))
    return out


def html(folder: Folder) -> str:
    bins = folder.csv("signal_indices.csv")
    if bins is None or not len(bins):
        return ""
    parts = ["<p>Top of each chart: the total index ST of each parameter in each bin of the signal, shaded "
             "by the method's error bound, open markers untrusted (bins holding less than "
             f"{QUIET_BIN:g} of the largest bin's variance are left out). Below: the variance of each bin, the "
             "weight it carries in the generalised index (Gamboa et al. 2014) of the table.</p>"]
    parts += [folder.figure(c) for c in charts(folder)]
    n = bins.groupby(["scene", "method", "signal"], sort=False).ngroups
    if n > MAX_CHARTS:
        parts.append(f"<p>{n - MAX_CHARTS} more (scene, method, signal) combinations in "
                     "<code>signal_indices.csv</code>.</p>")
    gen = folder.csv("signal_generalised.csv")
    if gen is not None and len(gen):
        parts.append("<h3>Generalised indices</h3>" + table(gen, "signal_generalised", "signal_generalised.csv"))
    parts.append(f"<p><code>signal_indices.csv</code>: {len(bins)} rows, one per (scene, method, signal, bin, "
                 "parameter) (not copied into this page).</p>")
    return "".join(parts)


def summary_lines(generalised: pd.DataFrame | None) -> list[str]:
    """Markdown lines for ``summary.md``: per scene, signal and method the parameters ranked by
    generalised ST (with S1 and the bound), or nothing without signals."""
    if generalised is None or not len(generalised):
        return []
    lines = ["## Signals: generalised indices (variance-weighted over the bins)", "",
             "Per bin: `signal_indices.csv` and report.html; `*` marks an untrusted row (a bin holding >= 0.1 % of "
             "the variance is untrusted); [k] the place by generalised ST that the bounds confirm (`2=` tied).", "",
             "| scene | signal | method | ranking: parameter ST (S1) +- bound |",
             "|---|---|---|---|"]
    for (scene, signal, method), g in generalised.groupby(["scene", "signal", "method"], sort=False):
        top = g.sort_values("ST", ascending=False, na_position="last").head(5)
        rank = ", ".join(f"{r.parameter} {r.ST:.2f} ({r.S1:.2f}) +-{r.ST_conf:.2g}{'' if r.trusted else '*'}"
                         + _place(getattr(r, "rank", "")) for r in top.itertuples())
        lines.append(f"| {scene} | {signal} | {method} | {rank} |")
    return lines + [""]


def _place(rank: object) -> str:
    """`` [2=]`` for a confirmed place (a table read back from CSV has NaN where none is), else nothing."""
    return f" [{rank}]" if isinstance(rank, str) and rank else ""


SECTION = Section("signals", "Indices of signals", html, tables=tables, charts=charts,
                  shows=("signal_indices.csv", "signal_generalised.csv"))
