"""Sweep: each output's mean over realisations (+- one standard deviation) against the swept parameter.

Tables: ``sweep.csv`` (one row per evaluation) and ``sweep_summary.csv`` (per scene, grid point and
variant: mean, standard deviation and the mean scaled by its maximum). Charts from ``sweep_summary.csv``:
``sweep_<output>.png``.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.ticker import EngFormatter

from ddgsa.report.sections.base import Chart, Folder, Section, Tables, table
from ddgsa.study.spec import WIND_LABEL_FIELDS

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from ddgsa.execute.kinds.common import StudyResult
    from ddgsa.models.base import ModelOutput


def sweep_keys(sweep: pd.DataFrame, grid: list[str], fields: Sequence[str] = WIND_LABEL_FIELDS) -> list[str]:
    """The columns that name a case of a sweep: variant (where there is one), scene, scene ``fields``, ``grid``."""
    return (["variant"] if "variant" in sweep else []) + ["scene", *fields, *grid]


def sweep_summary(sweep: pd.DataFrame, outputs: list[str], grid: list[str] | None = None,
                  fields: Sequence[str] = WIND_LABEL_FIELDS) -> pd.DataFrame:
    """Mean and standard deviation over realisations per scene (and grid point and variant), plus
    each mean scaled by its maximum; ``fields``: the scene fields that label a scene."""
    keys = sweep_keys(sweep, grid or [], fields)
    g = sweep.groupby(keys, sort=False)[outputs]
    mean, std = g.mean(), g.std(ddof=1).fillna(0.0)
    out = mean.add_suffix("_mean").join(std.add_suffix("_std")).reset_index()
    for o in outputs:
        out[f"{o}_scaled"] = out[f"{o}_mean"] / (out[f"{o}_mean"].abs().max() or 1.0)
    return out


def tables(result: "StudyResult", info: dict[str, "ModelOutput"]) -> Tables:
    if result.sweep is None:
        return []
    study = result.study
    return [("sweep.csv", result.sweep),
            ("sweep_summary.csv", sweep_summary(result.sweep, study.outputs, list(study.spec.grid),
                                                study.scene_fields))]


def _case_label(fields: list[str], values: Any, units: dict[str, str] | None = None) -> str:
    """``field value unit`` for numbers (the tables' SI value, e.g. ``wind_speed 5 m/s`` where the study wrote
    18 km/h), the value alone for labels such as a variant's."""
    def one(f: str, v: Any) -> str:
        if isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool):
            unit = (units or {}).get(f, "")
            return f"{f} {float(v):g}" + (f" {unit}" if unit and unit != "-" else "")
        return f"{v}"
    return ", ".join(one(f, v) for f, v in zip(fields, values))


def _label(name: str, units: dict[str, str] | None) -> str:
    unit = (units or {}).get(name)
    return f"{name} [{unit}]" if unit else name


GRID_TICKS = 8
"""Up to this many grid values, the x ticks are the grid's values themselves."""


def plot_sweep(summary: pd.DataFrame, output: str, grid: list[str] | None = None,
               units: dict[str, str] | None = None, fields: Sequence[str] = WIND_LABEL_FIELDS) -> "Figure":
    """``output`` (+- one std) against the first grid parameter, or against the first numeric scene
    field (wind speed) scaled by its maximum; one line per value of every other varying key (variant,
    scene fields, grid), labelled with the SI value and its unit; one bar per case where nothing varies
    along x. Axis labels carry the units; a grid parameter's ticks carry SI prefixes (``5 GN/m``)."""
    grid = grid or []
    o = output
    x = grid[0] if grid else next(f for f in fields if pd.api.types.is_numeric_dtype(summary[f]))
    others = [f for f in sweep_keys(summary, grid, fields) if f not in (x, "scene") and summary[f].nunique() > 1]
    if summary[x].nunique() == 1 and others:      # nothing to sweep along: one bar per case, real units
        labels = [_case_label(others, row, units) for row in summary[others].itertuples(index=False)]
        fig, ax = plt.subplots(figsize=(6.5, 0.45 * len(labels) + 1.2), layout="constrained")
        ax.barh(labels, summary[f"{o}_mean"], xerr=summary[f"{o}_std"], color="tab:blue")
        for k, v in enumerate(summary[f"{o}_mean"]):
            ax.annotate(f"{v:.4g}", (v, k), xytext=(3, 0), textcoords="offset points", va="center", fontsize=8)
        ax.invert_yaxis()
        ax.set_xlabel(_label(o, units))
        ax.grid(alpha=0.3, axis="x")
        return fig
    fig, ax = plt.subplots(figsize=(7.5 if others else 6, 3.6), layout="constrained")
    groups = summary.groupby(others, sort=False) if others else [((), summary)]
    scale = 1.0 if grid else (summary[f"{o}_mean"].abs().max() or 1.0)   # signed outputs: scale by |max|
    for key, g in groups:
        g = g.sort_values(x)
        label = _case_label(others, key if isinstance(key, tuple) else (key,), units)
        ax.errorbar(g[x], g[f"{o}_mean"] / scale, yerr=g[f"{o}_std"] / scale, capsize=2,
                    marker="o", ms=3, label=label or None)
    if grid and summary[x].min() > 0 and summary[x].max() / summary[x].min() > 50:
        ax.set_xscale("log")
    if grid:                                    # SI prefixes on the ticks (5 GN/m), no '1e10' offset
        if summary[x].nunique() <= GRID_TICKS:
            ax.set_xticks(sorted(summary[x].unique()))
            ax.xaxis.set_minor_formatter("")
        unit = (units or {}).get(x, "")
        ax.xaxis.set_major_formatter(EngFormatter(unit="" if unit == "-" else unit))
    ax.set_xlabel(_label(x, units) if grid or x != "wind_speed" else "mean wind speed [m/s]")
    ax.set_ylabel(_label(o, units) if grid else f"{o} / max [-]")
    ax.grid(alpha=0.3)
    if others:                                  # outside the axes: a line per case covers the data otherwise
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    return fig


def summary_columns(summary: pd.DataFrame, grid: Sequence[str]) -> tuple[list[str], list[str]]:
    """The outputs of a ``sweep_summary.csv`` (columns ``<o>_mean`` with ``<o>_std``) and its scene fields
    (the columns between ``scene`` and the outputs that are not ``grid``)."""
    outputs = [c[:-5] for c in summary.columns if c.endswith("_mean") and f"{c[:-5]}_std" in summary]
    stats = {f"{o}{s}" for o in outputs for s in ("_mean", "_std", "_scaled")}
    fields = [c for c in summary.columns if c not in stats and c not in ("variant", "scene") and c not in grid]
    return outputs, fields


def charts(folder: Folder) -> list[Chart]:
    sm = folder.csv("sweep_summary.csv")
    if sm is None or not len(sm):
        return []
    grid = [g for g in (folder.study.get("grid") or {}) if g in sm]
    outputs, fields = summary_columns(sm, grid)
    return [Chart(f"sweep_{o}.png", f"{o}: mean over realisations, whiskers: one standard deviation", "sweep",
                  functools.partial(plot_sweep, sm, o, grid, folder.units, fields)) for o in outputs]


def html(folder: Folder) -> str:
    found = charts(folder)
    if not found:
        return ""
    return "".join(folder.figure(c) for c in found) + "<h3>sweep_summary.csv</h3>" + table(
        folder.csv("sweep_summary.csv"), "sweep_summary", "sweep_summary.csv")


SECTION = Section("sweep", "Sweep", html, tables=tables, charts=charts, shows=("sweep_summary.csv",))
