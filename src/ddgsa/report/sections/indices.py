"""Sensitivity indices: ``indices.csv`` and its companions, the bars of each scene, the ST heatmaps, M-DRM
against its cross-checks, and S1 against ST.

Tables: ``indices.csv`` (with each row's verdict and output unit), ``diagnostics.csv``,
``output_moments.csv``, ``accuracy.csv`` (M-DRM against each independent cross-check) and, for
``fidelity: auto``, ``fidelity_selection.csv``. Charts (drawn from those files): ``bars_scene<k>.png``,
``heatmap_ST_<method>.png`` (more than one scene), ``mdrm_vs_crosscheck.png`` and, on the page only,
S1 against ST of every row.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, Rectangle

from ddgsa.execute.confirm import CROSSCHECKS, verdicts
from ddgsa.execute.dataset import EXTRA_INDEX_VARS
from ddgsa.gsa.base import sobol_rows
from ddgsa.gsa.result import ROW_COLUMNS, draw_index_bars
from ddgsa.report.sections.base import Chart, Folder, Section, Tables, csv_tables, table, trusted
from ddgsa.study.spec import WIND_LABEL_FIELDS, scene_text

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from ddgsa.execute.kinds.common import StudyResult
    from ddgsa.models.base import ModelOutput

DIAGNOSTIC_ROWS = 60
"""Diagnostics are many and alike (one per untrusted row): the page shows the first ones; the
problems section counts them all."""
_MARKERS = ("D", "s", "^", "v", "P", "X")


def tables(result: "StudyResult", info: dict[str, "ModelOutput"]) -> Tables:
    """``indices.csv`` (with the verdict of its pair and the output's unit), ``diagnostics.csv``,
    ``output_moments.csv``, ``accuracy.csv``, ``fidelity_selection.csv`` where the result has them."""
    out: Tables = []
    if len(result.indices):
        out.append(("indices.csv", with_verdicts(result.indices, verdicts(result)).assign(
            output_unit=result.indices["output"].map(lambda o: info[o].unit))))
        out.append(("diagnostics.csv", result.diagnostics))
        if result.moments is not None and len(result.moments):
            out.append(("output_moments.csv",
                        result.moments.assign(unit=result.moments["output"].map(lambda o: info[o].unit))))
        acc = accuracy_table(result.indices)
        if len(acc):
            out.append(("accuracy.csv", acc))
    if result.fidelity is not None and len(result.fidelity):
        out.append(("fidelity_selection.csv", result.fidelity))
    return out


def with_verdicts(indices: pd.DataFrame, verdicts: pd.DataFrame) -> pd.DataFrame:
    """``indices`` with the verdict of each row's (scene, output) pair (:func:`ddgsa.execute.confirm.confirmation_table`)
    in a column ``verdict`` (empty for rows no verdict covers: screening methods)."""
    if not len(verdicts) or "scene" not in indices:
        return indices.assign(verdict="")
    key = verdicts.set_index(["scene", "output"])["verdict"]
    pairs = pd.MultiIndex.from_arrays([indices["scene"].astype(int), indices["output"]])
    got = key.reindex(pairs).to_numpy(object)
    screening = ~indices.index.isin(sobol_rows(indices).index)
    return indices.assign(verdict=np.where(pd.isna(got) | screening, "", got))


def _crosschecks(indices: pd.DataFrame) -> pd.DataFrame:
    """Rows of methods other than M-DRM that are independent of it: ``auto`` rows whose numbers
    come from its own M-DRM stage (``source == "mdrm"``) would compare M-DRM with itself."""
    other = indices[indices["method"] != "mdrm"]
    if "source" in other:
        other = other[~((other["method"] == "auto") & (other["source"] == "mdrm"))]
    return other


def accuracy_table(indices: pd.DataFrame) -> pd.DataFrame:
    """M-DRM against each independent cross-check per scene and output: max |dS1|, max |dST|, trust."""
    if "mdrm" not in set(indices["method"]):
        return pd.DataFrame()
    key = ["scene", "output", "parameter"]
    m = indices[indices["method"] == "mdrm"]
    refs = _crosschecks(indices)
    rows = []
    for other in sorted(set(refs["method"])):
        joined = m.merge(refs[refs["method"] == other], on=key, suffixes=("_mdrm", "_ref"))
        for (scene, output), g in joined.groupby(["scene", "output"]):
            rows.append({"scene": scene, "output": output, "crosscheck": other,
                         "max_abs_dS1": _max_abs(g["S1_mdrm"] - g["S1_ref"]),
                         "max_abs_dST": _max_abs(g["ST_mdrm"] - g["ST_ref"]),
                         "mdrm_trusted": bool(g["trusted_mdrm"].all()), "ref_trusted": bool(g["trusted_ref"].all()),
                         "evals_mdrm": int(g["n_evals_mdrm"].iloc[0]), "evals_ref": int(g["n_evals_ref"].iloc[0])})
    return pd.DataFrame(rows)


def _max_abs(diff: pd.Series) -> float:
    """Largest finite absolute difference (NaN when none is finite)."""
    a = np.abs(diff.to_numpy(float))
    a = a[np.isfinite(a)]
    return float(a.max()) if a.size else float("nan")


def _label(name: str, units: dict[str, str] | None) -> str:
    """``name [unit]`` where a unit is known, else the name."""
    unit = (units or {}).get(name)
    return f"{name} [{unit}]" if unit else name


def scene_fields(indices: pd.DataFrame) -> list[str]:
    """The columns of ``indices.csv`` that label a scene (every column neither :data:`ROW_COLUMNS` nor an
    extra index, :data:`EXTRA_INDEX_VARS`), the wind
    fields in the order of :data:`WIND_LABEL_FIELDS`."""
    fields = [c for c in indices.columns if c not in ROW_COLUMNS and c not in EXTRA_INDEX_VARS]
    return [f for f in WIND_LABEL_FIELDS if f in fields] + [f for f in fields if f not in WIND_LABEL_FIELDS]


AGREEMENT_MARKERS = ("o", "s", "^", "D", "v", "P")
"""One marker per cross-check in the M-DRM agreement chart (coincident points of two checks stay visible)."""


def plot_agreement(indices: pd.DataFrame) -> "Figure":
    """Scatter of M-DRM indices against each cross-check (filled: M-DRM trusted, open: untrusted), one
    marker per cross-check, axes wide enough for every point (a given-data S1 below zero included); a
    cross-check with no finite pair is left out of the legend, and a chart with none says why."""
    fig, axes = plt.subplots(1, 2, figsize=(8, 4))
    key = ["scene", "output", "parameter"]
    m = indices[indices["method"] == "mdrm"]
    refs = _crosschecks(indices)
    low, high, shown = 0.0, 1.0, 0
    for i, (other, marker) in enumerate(zip(sorted(set(refs["method"])), AGREEMENT_MARKERS)):
        j = m.merge(refs[refs["method"] == other], on=key, suffixes=("_m", "_r"))
        for ax, q in zip(axes, ("S1", "ST")):
            finite = np.isfinite(j[f"{q}_r"].to_numpy(float)) & np.isfinite(j[f"{q}_m"].to_numpy(float))
            if not finite.any():
                continue
            shown += 1
            low = min(low, float(j.loc[finite, [f"{q}_r", f"{q}_m"]].min().min()))
            high = max(high, float(j.loc[finite, [f"{q}_r", f"{q}_m"]].max().max()))
            ok = trusted(j, "trusted_m") & finite
            label, color = (f"vs {other}" if q == "S1" else None), f"C{i}"
            ax.scatter(j[f"{q}_r"][ok], j[f"{q}_m"][ok], s=16, marker=marker, alpha=0.8, color=color,
                       label=label if ok.any() else None)
            ax.scatter(j[f"{q}_r"][~ok & finite], j[f"{q}_m"][~ok & finite], s=16, marker=marker,
                       facecolors="none", edgecolors=color, label=None if ok.any() else label)
    pad = 0.05 * (high - low)
    for ax, q in zip(axes, ("S1", "ST")):
        ax.plot([low, high], [low, high], color="0.5", lw=0.8)
        ax.set_xlabel(f"{q}, cross-check [-]")
        ax.set_ylabel(f"{q}, M-DRM [-]")
        ax.set_xlim(low - pad, high + pad)
        ax.set_ylim(low - pad, high + pad)
        ax.grid(alpha=0.3)
    handles, labels = axes[0].get_legend_handles_labels()
    if handles:
        axes[0].legend(handles, labels, fontsize=8)
    if not shown:
        for ax in axes:
            ax.text(0.5, 0.5, "no finite M-DRM index to compare\n(M-DRM refused: see diagnostics.csv)",
                    transform=ax.transAxes, ha="center", va="center", fontsize=9,
                    bbox={"facecolor": "white", "edgecolor": "0.7"})
    untrusted = not trusted(m).all()
    fig.suptitle("M-DRM against cross-check" + (" (open markers: M-DRM untrusted)" if untrusted else ""))
    fig.tight_layout()
    return fig


NO_INDICES = ("indices refused\n(see summary.md)", "nothing to rank:\nits spread is within\nits resolution")
"""What a panel without a finite index says: refused, or (verdict ``nothing to rank``) why no index is worth drawing."""


def plot_scene_bars(scene_rows: pd.DataFrame, units: dict[str, str] | None = None,
                    fields: Sequence[str] = WIND_LABEL_FIELDS, verdicts: pd.DataFrame | None = None) -> "Figure":
    """One panel per output (at most three a row), parameters down the y axis: S1/ST bars of the
    estimate the summary reports -- the method of the pair's verdict (``verdicts``,
    :func:`ddgsa.execute.confirm.confirmation_table`), said in the panel's title with the verdict -- with
    confidence bars where it gives an interval, and the ST of every other requested method as a
    marker beside it (cross-checks, :data:`CROSSCHECKS`, are left to their own table). Hatched bars
    are untrusted (said in the legend, below the panels, only when some are; S1 and ST only when some such
    bar is drawn); an output whose indices are refused or that has nothing to rank says so (:data:`NO_INDICES`); the title names the scene by its label ``fields``; ``units``: per output."""
    rows = scene_rows[~scene_rows["method"].isin(CROSSCHECKS)]
    rows = rows if len(rows) else scene_rows
    outputs = list(rows["output"].unique())
    scene = int(rows["scene"].iloc[0]) if "scene" in rows else 0
    chosen = ({} if verdicts is None or not len(verdicts) else
              {r.output: (r.method, r.verdict) for r in verdicts[verdicts["scene"] == scene].itertuples()})
    ncols = min(3, len(outputs))
    nrows = -(-len(outputs) // ncols)
    n_par = rows["parameter"].nunique()
    fig, axes = plt.subplots(nrows, ncols, figsize=(3.8 * ncols + 1.2, (0.28 * n_par + 1.0) * nrows + 0.9),
                             squeeze=False, sharey=True, layout="constrained")
    marks: dict[str, str] = {}
    for ax, out in zip(axes.flat, outputs):
        g = rows[rows["output"] == out]
        meth, verdict = chosen.get(out, (str(g["method"].iloc[0]), ""))
        meth = meth if meth in set(g["method"]) else str(g["method"].iloc[0])
        t = g[g["method"] == meth]
        draw_index_bars(ax, t, fontsize=7, horizontal=True)
        y = np.arange(len(t))
        for other in [m for m in g["method"].unique() if m != meth]:
            st = g[g["method"] == other].set_index("parameter")["ST"].reindex(t["parameter"]).to_numpy(float)
            if np.isfinite(st).any():
                marker = marks.setdefault(other, _MARKERS[len(marks) % len(_MARKERS)])
                ax.plot(st, y + 0.19, linestyle="none", marker=marker, markersize=4, markerfacecolor="none",
                        markeredgecolor="0.15", markeredgewidth=0.8, label=f"ST, {other}")
        ax.set_title(f"{_label(out, units)}\n{meth}" + (f": {verdict}" if verdict else ""), fontsize=8)
        ax.set_xlim(min(-0.05, float(np.nanmin(g[["S1", "ST"]].to_numpy(float), initial=0))), 1.05)
        ax.tick_params(axis="x", labelsize=7)
        if not np.isfinite(t[["S1", "ST"]].to_numpy(float)).any():
            ax.text(0.5, 0.5, NO_INDICES[verdict == "nothing to rank"], transform=ax.transAxes,
                    ha="center", va="center", fontsize=8, color="0.3")
    for ax in list(axes.flat)[len(outputs):]:
        ax.set_visible(False)
    shown = rows[rows.apply(lambda r: chosen.get(r["output"], (None,))[0] in (None, r["method"]), axis=1)]
    handles: list[Any] = [Patch(facecolor=color, label=q) for q, color in (("S1", "tab:blue"), ("ST", "tab:orange"))
                          if np.isfinite(shown[q].to_numpy(float)).any()]        # RBD-FAST, given-data: no ST bars
    untrusted = ~trusted(shown) & np.isfinite(shown[["S1", "ST"]].to_numpy(float)).any(axis=1)   # drawn hatched
    placed = trusted(shown, "rank_confirmed") if "rank_confirmed" in shown else untrusted & False
    if (untrusted & placed).any():
        handles.append(Patch(facecolor="tab:blue", edgecolor="white", hatch="..", label="untrusted, rank confirmed"))
    if (untrusted & ~placed).any():
        handles.append(Patch(facecolor="tab:blue", edgecolor="white", hatch="///", label="untrusted"))
    handles += [Line2D([], [], linestyle="none", marker=m, markerfacecolor="none", markeredgecolor="0.15",
                       label=f"ST, {meth}") for meth, m in marks.items()]
    fig.legend(handles=handles, fontsize=7, loc="outside lower center", ncols=min(len(handles), 5))
    fig.suptitle("Sobol indices, " + scene_text({f: rows[f].iloc[0] for f in fields}), fontsize=9)
    return fig


def plot_heatmap(rows: pd.DataFrame, units: dict[str, str] | None = None,
                 fields: Sequence[str] = WIND_LABEL_FIELDS) -> "Figure":
    """ST as parameter x scene, one panel per output; the panels share the parameter axis, so
    its labels are drawn once, left of the first panel, and never over a neighbour. Scenes are
    labelled by their wind speed, or by their label ``fields`` for a model's own scene type;
    ``units``: per output. A panel without a finite ST says why (:data:`NO_INDICES`, from the rows'
    ``verdict`` where ``indices.csv`` gives one)."""
    outputs = list(rows["output"].unique())
    params = sorted(rows["parameter"].unique())
    fig, axes = plt.subplots(1, len(outputs), figsize=(2.4 * len(outputs) + 3.0, 0.3 * len(params) + 2.2),
                             squeeze=False, sharey=True, layout="constrained")
    hatched = False
    for ax, out in zip(axes[0], outputs):
        mine = rows[rows["output"] == out]
        t = mine.pivot(index="parameter", columns="scene", values="ST").reindex(params)
        im = ax.imshow(t.to_numpy(float), vmin=0, vmax=1, cmap="viridis", aspect="auto")
        if not np.isfinite(t.to_numpy(float)).any():             # a blank panel says why it is blank
            flat = "verdict" in mine and (mine["verdict"] == "nothing to rank").all()
            ax.text(0.5, 0.5, NO_INDICES[bool(flat)], transform=ax.transAxes, ha="center", va="center",
                    fontsize=7, color="0.3")
        ok = (mine.assign(ok=trusted(mine)).pivot(index="parameter", columns="scene", values="ok")
              .reindex(params).fillna(False).to_numpy(bool) if "trusted" in rows else np.ones(t.shape, bool))
        for i, j in zip(*np.nonzero(~ok)):
            ax.add_patch(Rectangle((j - 0.5, i - 0.5), 1, 1, fill=False, hatch="///", edgecolor="white",
                                   linewidth=0, label="untrusted"))
            hatched = True
        first = [rows[rows["scene"] == s].iloc[0] for s in t.columns]
        labels = ([f"{r['wind_speed']:g} m/s" for r in first] if "wind_speed" in fields
                  else [scene_text({f: r[f] for f in fields}) for r in first])
        ax.set_xticks(range(t.shape[1]), labels, rotation=45, ha="right", fontsize=7)
        ax.set_yticks(range(len(params)), params, fontsize=7)
        ax.tick_params(axis="y", labelleft=ax is axes[0, 0])
        unit = (units or {}).get(out)
        ax.set_title(f"{out}\n[{unit}]" if unit else str(out), fontsize=8)
    fig.colorbar(im, ax=axes[0].tolist(), shrink=0.8, label="ST [-]")
    fig.suptitle(f"total Sobol index per scene ({rows['method'].iloc[0]})"
                 + ("; hatched: untrusted (not within the tolerance by the method's own estimate)" if hatched else ""),
                 fontsize=9)
    return fig


def plot_s1_st(indices: pd.DataFrame) -> "Figure":
    """S1 against ST of every row, one colour per method, open markers untrusted; the line ST = S1
    (above it: interactions)."""
    fig, ax = plt.subplots(figsize=(5.5, 4.2), layout="constrained")
    ax.plot([0, 1], [0, 1], color="0.6", lw=0.8, ls="--", label="ST = S1: no interactions")
    for k, (meth, g) in enumerate(indices.groupby("method", sort=False)):
        ok = trusted(g)
        color = f"C{k}"
        ax.scatter(g["S1"][ok], g["ST"][ok], s=16, color=color, label=str(meth))
        ax.scatter(g["S1"][~ok], g["ST"][~ok], s=16, facecolors="none", edgecolors=color, label=str(meth))
    ax.set_xlim(-0.05, 1.05)
    ax.set_ylim(-0.05, 1.05)
    ax.set_xlabel("S1, first-order index [-]")
    ax.set_ylabel("ST, total index [-]")
    ax.grid(alpha=0.3)
    first: dict[str, Any] = {}
    for h, lab in zip(*ax.get_legend_handles_labels()):
        first.setdefault(lab, h)                                          # a method's filled marker, once
    ax.legend(list(first.values()), list(first), fontsize=7, loc="upper left")
    ax.set_title("S1 against ST", fontsize=9)
    return fig


def charts(folder: Folder) -> list[Chart]:
    """The bars of each scene, the ST heatmap of each method (more than one scene), M-DRM against its
    cross-checks (where ``accuracy.csv`` is), and S1 against ST of every row (on the page only)."""
    idx = folder.csv("indices.csv")
    if idx is None or not len(idx):
        return []
    units, fields = folder.units, folder.title_fields(scene_fields(idx))
    conf = folder.csv("confirmation.csv")
    sobol = sobol_rows(idx)
    out: list[Chart] = []
    for scene in sorted(sobol["scene"].unique()):
        rows = sobol[sobol["scene"] == scene]
        said = ([] if conf is None else [f"{r.output}: verdict {r.verdict} ({r.method})"
                                         for r in conf[conf["scene"] == scene].itertuples()])
        out.append(Chart(f"bars_scene{scene}.png",
                         f"scene {scene} ({scene_text({f: rows[f].iloc[0] for f in fields})}): S1 and ST of the "
                         "method each verdict names, whiskers its error estimate, other methods' ST as markers; "
                         "hatched: untrusted" + (". " + "; ".join(said) if said else ""), "bars",
                         functools.partial(plot_scene_bars, rows, units, fields, conf)))
    if idx["scene"].nunique() > 1:
        for method in idx["method"].unique():
            rows = idx[idx["method"] == method]
            if rows["ST"].notna().any():                 # no map of a method without ST (given_data_s1)
                out.append(Chart(f"heatmap_ST_{method}.png", f"ST of every output, parameter and scene, {method}; "
                                 "hatched: untrusted", "heatmap", functools.partial(plot_heatmap, rows, units, fields)))
    if folder.csv("accuracy.csv") is not None:
        out.append(Chart("mdrm_vs_crosscheck.png", "M-DRM's indices against each independent cross-check's; open "
                         "markers: M-DRM untrusted", "scatter", functools.partial(plot_agreement, idx)))
    out.append(Chart(None, "every row: ST above the line S1 = ST means interactions; open markers: untrusted",
                     "scatter", functools.partial(plot_s1_st, idx)))
    return out


def html(folder: Folder) -> str:
    idx = folder.csv("indices.csv")
    if idx is None or not len(idx):
        return ""
    parts = ["<p>Bars: S1 and ST of the method each verdict names, whiskers: its error estimate (M-DRM, PCE: a "
             "bound; SALib: bootstrap half-width), the ST of the other methods as markers. Hatched bars and open "
             "markers are untrusted rows. Click a legend entry to hide a series.</p>"]
    parts += [folder.figure(c) for c in charts(folder)]
    parts.append(table(idx.drop(columns=["study"], errors="ignore"), "indices", "indices.csv"))
    parts.append(csv_tables(folder, ("output_moments.csv", "accuracy.csv", "diagnostics.csv", "fidelity_selection.csv"),
                            {"diagnostics.csv": DIAGNOSTIC_ROWS}))
    return "".join(parts)


SECTION = Section("indices", "Sensitivity indices", html, tables=tables, charts=charts,
                  shows=("indices.csv", "output_moments.csv", "accuracy.csv", "diagnostics.csv",
                         "fidelity_selection.csv"))
