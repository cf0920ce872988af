"""Index error against cost: the benchmark's ``accuracy_cost.csv`` (``ddgsa bench accuracy``), one chart
per reference function: each method's largest index error against the model runs and the wall time.

Charts (``accuracy_<function>.png``, which the benchmark writes with :func:`plot_function`); no tables of a
study's result.
"""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from ddgsa.report.sections.base import Chart, Folder, Section

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

ISHIGAMI_MARKS = [("SALib Saltelli N=1024", 5120, 7e-3), ("SALib Saltelli N=16384", 81920, 4e-4),
                  ("Gauss-grid PCE", 1000, 2e-4)]
"""Published Ishigami errors drawn as stars for comparison (RMSE of S1 at the runs spent)."""


def plot_function(df: pd.DataFrame, name: str) -> "Figure":
    """Error against evaluations and wall time for one function of ``accuracy_cost.csv`` (log-log, hollow =
    untrusted; band: the seeds' min-max)."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 4), sharey=True)
    colors = {"mdrm": "tab:blue", "saltelli": "tab:orange", "rbd_fast": "tab:green", "pce": "tab:red",
              "auto": "black"}
    floor = 1e-6
    for ax, x in zip(axes, ("n_evals", "wall_s")):
        for method, g in df.groupby("method", sort=False):
            agg = g.groupby("options", sort=False).agg(x=(x, "mean"), s1=("err_S1", "mean"), st=("err_ST", "mean"),
                                                        lo=("err_S1", "min"), hi=("err_S1", "max"),
                                                        ok=("trusted", "all")).sort_values("x")
            c = colors.get(method, "gray")
            ax.plot(agg["x"], agg["s1"].clip(lower=floor), "-", color=c, label=f"{method} S1", lw=1.2)
            if agg["st"].notna().any():
                ax.plot(agg["x"], agg["st"].clip(lower=floor), "--", color=c, label=f"{method} ST", lw=1.0)
            if (agg["hi"] > agg["lo"]).any():
                ax.fill_between(agg["x"], agg["lo"].clip(lower=floor), agg["hi"].clip(lower=floor), color=c, alpha=0.15)
            ax.scatter(agg["x"], agg["s1"].clip(lower=floor), s=22, color=c,
                       facecolors=np.where(agg["ok"], c, "none"), zorder=3)
        if name == "ishigami" and x == "n_evals":
            for label, n, err in ISHIGAMI_MARKS:
                ax.scatter([n], [err], marker="*", s=90, color="purple", zorder=4)
                ax.annotate(label + " (RMSE S1)", (n, err), fontsize=7, xytext=(4, 4), textcoords="offset points")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("model evaluations" if x == "n_evals" else "wall time [s] (model + analysis, 1 core)")
        ax.grid(alpha=0.3, which="both")
    refused = sorted(m for m, g in df.groupby("method") if g["err_S1"].isna().all())
    if refused:
        axes[0].text(0.02, 0.02, f"no numbers (refused by their diagnostics): {', '.join(refused)}",
                     transform=axes[0].transAxes, fontsize=7)
    axes[0].set_ylabel("max |error| over parameters")
    axes[0].legend(fontsize=7, ncol=2)
    fig.suptitle(f"{name}: index error against cost (filled: method trusts itself; band: seeds min-max)")
    fig.tight_layout()
    return fig


def charts(folder: Folder) -> list[Chart]:
    ac = folder.csv("accuracy_cost.csv")
    if ac is None or not len(ac) or not {"function", "method", "options", "n_evals", "err_S1"} <= set(ac.columns):
        return []
    return [Chart(f"accuracy_{str(fn).replace(':', '_')}.png",
                  f"{fn}: largest index error of each method against the runs and the wall time it spent; filled: the "
                  "method trusts itself; band: seeds min-max", "convergence", functools.partial(plot_function, g, str(fn)))
            for fn, g in ac.groupby("function", sort=False)]


def html(folder: Folder) -> str:
    return "".join(folder.figure(c) for c in charts(folder))


SECTION = Section("convergence", "Index error against cost", html, charts=charts, shows=("accuracy_cost.csv",))
