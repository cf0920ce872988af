"""Report sections for indices of signals and indices against sample size (SVG charts from the CSVs).

:func:`signals_section` reads ``signal_indices.csv`` and ``signal_generalised.csv``: per scene, method
and signal, the total index of each parameter against the signal's axis (frequency, order, time)
with its error band, above the variance of each bin (the weight that bin carries in the generalised
index), and the generalised table. :func:`convergence_section` reads ``convergence.csv``: per method
and output of the first scene, each parameter's ``ST`` against the runs of nested sub-samples with
the method's error bound shaded; the last point is the study's own index.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd

from ddgsa.report.svgplot import Line, xy_chart

MAX_CHARTS = 12
"""Signal charts per page (scene x method x signal); the CSVs hold all."""
MAX_CURVES = 8
"""Convergence charts per page (method x output of the first scene)."""
QUIET_BIN = 1e-4
"""Bins whose variance is below this fraction of the largest are not drawn on the index chart: their
indices are ratios of round-off and weigh nothing in the generalised index."""
SHOWN_INDEX = 0.02
"""Parameters whose ST stays below this in every bin are named in the caption, not drawn."""
SIGNAL_TABLES = ("signal_indices.csv", "signal_generalised.csv", "convergence.csv")

Figure = Callable[[str, str, str], str]
Table = Callable[[pd.DataFrame, str, str], str]


def _band(value: np.ndarray, err: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The shaded band ``value +- err`` held inside the charts' index range [-0.05, 1.05]."""
    return np.clip(value - err, -0.05, 1.05), np.clip(value + err, -0.05, 1.05)


def _read(folder: Path, name: str) -> pd.DataFrame | None:
    path = folder / name
    if not path.is_file():
        return None
    df = pd.read_csv(path)
    if "trusted" in df:
        df["trusted"] = df["trusted"].astype(str).str.lower().eq("true")
    return df if len(df) else None


def signals_section(folder: Path, figure: Figure, table: Table) -> str:
    """HTML of the signals section (empty when the folder has no signal indices)."""
    bins = _read(folder, "signal_indices.csv")
    if bins is None:
        return ""
    parts = ["<p>Top of each pair: the total index ST of each parameter in each bin of the signal, shaded "
             "by the method's error bound, open markers untrusted (bins holding less than "
             f"{QUIET_BIN:g} of the largest bin's variance are left out). Below: the variance of each bin, the "
             "weight it carries in the generalised index (Gamboa et al. 2014) of the table.</p>"]
    groups = list(bins.groupby(["scene", "method", "signal"], sort=False))
    for (scene, method, signal), g in groups[:MAX_CHARTS]:
        first = g.iloc[0]
        xlab = f"{first['axis_name']} [{first['axis_unit']}]"
        var = g.drop_duplicates("bin").set_index("bin")["variance"]
        loud = var.index[var.to_numpy(float) >= QUIET_BIN * np.nanmax(var.to_numpy(float))]
        lines, quiet = [], []
        for k, (par, gp) in enumerate(g.groupby("parameter", sort=False)):
            gp = gp[gp["bin"].isin(loud)]
            st, err = gp["ST"].to_numpy(float), gp["ST_conf"].to_numpy(float)
            if not np.nanmax(st, initial=0.0) >= SHOWN_INDEX:
                quiet.append(str(par))
                continue
            err = np.where(np.isfinite(err), err, 0.0)
            lines.append(Line(str(par), gp["axis"].to_numpy(float), st, band=_band(st, err),
                              hollow=~gp["trusted"].to_numpy(bool), color=k))
        below = f"; ST below {SHOWN_INDEX:g} in every bin: {', '.join(quiet)}" if quiet else ""
        parts.append(figure(xy_chart(lines, xlab, "ST, total index [-]", f"{signal}: ST per bin ({method})",
                                     ylim=(-0.05, 1.05)),
                            f"scene {scene}, {method}: total index of each parameter against {first['axis_name']}"
                            + below, "signal"))
        vx = g.drop_duplicates("bin")
        positive = vx["variance"].to_numpy(float) > 0
        parts.append(figure(xy_chart([Line("variance", vx["axis"].to_numpy(float)[positive],
                                           vx["variance"].to_numpy(float)[positive])],
                                     xlab, f"variance [{first['unit']}^2]", f"{signal}: variance per bin ({method})",
                                     ylog=True, height=160.0),
                            f"scene {scene}, {method}: variance of {signal} in each bin", "signal"))
    if len(groups) > MAX_CHARTS:
        parts.append(f"<p>{len(groups) - MAX_CHARTS} more (scene, method, signal) combinations in "
                     "<code>signal_indices.csv</code>.</p>")
    gen = _read(folder, "signal_generalised.csv")
    if gen is not None:
        parts.append("<h3>Generalised indices</h3>" + table(gen, "signal_generalised", "signal_generalised.csv"))
    parts.append(f"<p><code>signal_indices.csv</code>: {len(bins)} rows, one per (scene, method, signal, bin, "
                 "parameter) (not copied into this page).</p>")
    return "".join(parts)


def convergence_section(folder: Path, figure: Figure, table: Table) -> str:
    """HTML of the indices-against-sample-size section (empty without ``convergence.csv``)."""
    conv = _read(folder, "convergence.csv")
    if conv is None or not {"scene", "method", "parameter"} <= set(conv.columns):   # another tool's table of that name
        return ""
    first = conv[conv["scene"] == conv["scene"].min()]
    parts = ["<p>The study's indices recomputed on nested sub-samples of its own runs (no new run): each "
             "parameter's ST against the runs, the method's error bound shaded, open markers untrusted; the "
             "last point is the study's index. A curve that still moves at the right, or a band wider than the "
             "differences that matter, asks for more runs. M-DRM and quadrature PCE have no nested "
             "sub-sample and no curve.</p>"]
    groups = list(first.groupby(["method", "output"], sort=False))
    for (method, output), g in groups[:MAX_CURVES]:
        lines = []
        for k, (par, gp) in enumerate(g.groupby("parameter", sort=False)):
            gp = gp.sort_values("n_evals")
            st, err = gp["ST"].to_numpy(float), gp["ST_conf"].to_numpy(float)
            err = np.where(np.isfinite(err), err, 0.0)
            lines.append(Line(str(par), gp["n_evals"].to_numpy(float), st, band=_band(st, err),
                              hollow=~gp["trusted"].to_numpy(bool), color=k))
        runs = g["n_evals"].to_numpy(float)
        parts.append(figure(xy_chart(lines, "model runs [runs]", "ST, total index [-]",
                                     f"{output}: ST against runs ({method})", xlog=runs.max() >= 10 * runs.min(),
                                     ylim=(-0.05, 1.05)),
                            f"scene {int(g['scene'].iloc[0])}, {method}: ST of {output} on nested sub-samples",
                            "convergence"))
    if len(groups) > MAX_CURVES:
        parts.append(f"<p>{len(groups) - MAX_CURVES} more (method, output) curves in <code>convergence.csv</code>.</p>")
    parts.append(table(conv, "convergence", "convergence.csv"))
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
