"""Write a study's tables, plots, provenance and summary into its output folder.

Outputs are labelled with their declared unit (``rms_deflection_hub [m]``); ``summary.md``
opens with what each output is, its mean and coefficient of variation, then ranks parameters
by S1 and ST with a sentence per output naming what dominates, and lists every problem (refused
or untrusted outputs, failure reasons, implausible values). Files an earlier report wrote that
this one does not are removed (:mod:`ddgsa.report.outdir`). PNGs carry no software/date metadata.
``report.html`` (:mod:`ddgsa.report.html`) is written last, from the files written here.
"""

from __future__ import annotations

import functools
import json
import os
import re
import sys
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path
from collections.abc import Callable, Sequence
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from ddgsa.report.beyond import beyond_markdown, group_table, plot_groups
from ddgsa.execute.confirm import CONFIRMED, CROSSCHECKS, VERDICTS, next_step, study_tolerance, verdicts  # noqa: E402
from ddgsa.detection import FaultDetectability  # noqa: E402
from ddgsa.gsa.base import sobol_rows  # noqa: E402
from ddgsa.gsa.result import CONSTANT_CV, draw_index_bars  # noqa: E402
from ddgsa.report.html import HTML_NAME, model_words, write_html  # noqa: E402
from ddgsa.loads.scene import AUTO_BEM_INCLINATION_DEG  # noqa: E402
from ddgsa.models.base import ModelOutput, declared  # noqa: E402
from ddgsa.report.outdir import COMPLETE_NAME, mark_complete, previous_files, remove_stale, unmark_complete  # noqa: E402
from ddgsa.execute.kinds.common import StudyResult  # noqa: E402
from ddgsa.report.signals import summary_lines as signal_summary_lines  # noqa: E402
from ddgsa.study.spec import WIND_LABEL_FIELDS, plan_scenes, scene_text  # noqa: E402

PNG_METADATA = {"Software": None}
"""No matplotlib version in the PNGs: a rerun on the same machine writes the same bytes."""


def output_info(result: StudyResult) -> dict[str, ModelOutput]:
    """The declared outputs of the study's model (undeclared names get no unit)."""
    model = result.study.make_model()
    return {o: result.study.output_declaration(model, o) for o in result.study.analysed_outputs}


def write_report(result: StudyResult, out: Path) -> list[Path]:
    """Write every file of the report and remove the earlier report's files it did not write;
    returns the paths written."""
    out.mkdir(parents=True, exist_ok=True)
    unmark_complete(out)
    before = previous_files(out)
    written: list[Path] = []
    info = output_info(result)

    def save_csv(df: pd.DataFrame, name: str) -> None:
        path = out / name
        df.to_csv(path, index=False, float_format="%.6g")
        written.append(path)

    def save_fig(fig: Any, name: str) -> None:
        _save_figure(fig, out / name)
        written.append(out / name)

    figures: list[tuple[Callable[[], Any], Path]] = []

    def later_fig(make: Callable[[], Any], name: str) -> None:
        """A figure drawn and saved with the others after the tables (:func:`render_figures`)."""
        figures.append((make, out / name))
        written.append(out / name)

    save_csv(result.evaluations.drop(columns=["key"], errors="ignore"), "evaluations.csv")
    if result.sweep is not None:
        save_csv(result.sweep, "sweep.csv")
        fields = result.study.scene_fields
        summary = sweep_summary(result.sweep, result.study.outputs, list(result.study.spec.grid), fields)
        save_csv(summary, "sweep_summary.csv")
        for fig, name in plot_sweep(summary, result.study.outputs, list(result.study.spec.grid), info, fields):
            save_fig(fig, name)
    if len(result.indices):
        pairs = verdicts(result)
        if len(pairs):
            save_csv(pairs, "confirmation.csv")
        save_csv(with_verdicts(result.indices, pairs).assign(
            output_unit=result.indices["output"].map(lambda o: info[o].unit)), "indices.csv")
        save_csv(result.diagnostics, "diagnostics.csv")
        if result.moments is not None and len(result.moments):
            save_csv(result.moments.assign(unit=result.moments["output"].map(lambda o: info[o].unit)),
                     "output_moments.csv")
        acc = accuracy_table(result.indices)
        if len(acc):
            save_csv(acc, "accuracy.csv")
            later_fig(functools.partial(plot_agreement, result.indices), "mdrm_vs_crosscheck.png")
        sobol = sobol_rows(result.indices)
        for scene in sorted(sobol["scene"].unique()):
            later_fig(functools.partial(plot_scene_bars, sobol[sobol["scene"] == scene], info,
                                        result.study.scene_fields, pairs), f"bars_scene{scene}.png")
        groups = group_table(result)
        if len(groups):
            save_csv(groups, "groups.csv")
            for scene in sorted(groups["scene"].unique()):
                later_fig(functools.partial(plot_groups, groups[groups["scene"] == scene]), f"groups_scene{scene}.png")
        if result.indices["scene"].nunique() > 1:
            for method in result.indices["method"].unique():
                rows = result.indices[result.indices["method"] == method]
                if rows["ST"].notna().any():                 # no map of a method without ST (given_data_s1)
                    later_fig(functools.partial(plot_heatmap, rows, info, result.study.scene_fields),
                              f"heatmap_ST_{method}.png")
    for df, name in ((result.signal_indices, "signal_indices.csv"),
                     (result.signal_generalised, "signal_generalised.csv"), (result.convergence, "convergence.csv")):
        if df is not None and len(df):
            save_csv(df, name)
    for fig, name in scene_figures(result):
        save_fig(fig, name)
    if result.fidelity is not None and len(result.fidelity):
        save_csv(result.fidelity, "fidelity_selection.csv")
    if result.fault is not None:
        _write_fault(result, save_csv, save_fig)
    render_figures(figures)
    path = out / "summary.md"
    path.write_text(summary_markdown(result, info))
    written.append(path)
    path = out / "provenance.json"
    names = sorted({p.name for p in written} | {path.name, HTML_NAME, COMPLETE_NAME})
    result.provenance["files"] = names
    path.write_text(json.dumps(result.provenance, indent=2, default=str))
    written.append(path)
    written.append(write_html(out, complete=True))
    remove_stale(out, before, names)
    mark_complete(out, names)                       # last: the folder's outputs are whole
    written.append(out / COMPLETE_NAME)
    return written


def _save_figure(fig: Any, path: Path) -> None:
    """Save ``fig`` as a PNG without metadata (:data:`PNG_METADATA`) and close it."""
    fig.savefig(path, dpi=100, bbox_inches="tight", metadata=PNG_METADATA)
    plt.close(fig)


FIGURE_PROCESSES_FROM = 3
"""Fewest deferred figures drawn in forked processes (fewer: in this one; a fork costs ~0.1 s)."""
_FIGURES: list[tuple[Callable[[], Any], Path]] = []
"""The figures :func:`render_figures` hands to its forked processes (inherited, not pickled)."""


def render_figures(figures: list[tuple[Callable[[], Any], Path]], processes: int | None = None) -> None:
    """Draw and save each ``(make, path)``: ``make()`` returns the figure. A report's figures are
    independent and drawing them is most of its time (``indirect_drive_gsa``'s seven: ~10 s of its
    14 s), so on Linux, from :data:`FIGURE_PROCESSES_FROM` figures, they are drawn by ``processes``
    (default: the CPUs this process may use) processes forked from this one, each figure by one of them, with the same
    matplotlib state, so the files are the same bytes as drawn here (tested)."""
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    processes = min(len(figures), processes or usable or 1)
    if processes < 2 or len(figures) < FIGURE_PROCESSES_FROM or not sys.platform.startswith("linux"):
        for make, path in figures:
            _save_figure(make(), path)
        return
    _FIGURES[:] = figures
    try:
        with ProcessPoolExecutor(processes, mp_context=get_context("fork")) as pool:
            for done in [pool.submit(_render_one, i) for i in range(len(figures))]:
                done.result()                       # a failure in a process raises here
    finally:
        _FIGURES.clear()


def _render_one(i: int) -> None:
    """Draw and save the ``i``-th figure of :data:`_FIGURES` (in a forked process)."""
    make, path = _FIGURES[i]
    _save_figure(make(), path)


def scene_figures(result: StudyResult) -> list[tuple[Any, str]]:
    """A model's own signal plots of each scene at the study's nominal point (healthy fault level),
    for a model that draws them (:meth:`Model.scene_figures`, e.g. the rig's order maps and spectra)."""
    study = result.study
    draw = study.make_model().scene_figures
    point = {**study.spec.fixed, **(study.space.nominal if study.space is not None else {})}
    if study.spec.fault is not None:
        point[study.spec.fault.parameter] = study.spec.fault.healthy
    return [(fig, f"{name}_scene{ps.index}.png") for ps in plan_scenes(study) for fig, name in draw(ps.scenes[0], point)]


def evaluation_line(provenance: dict[str, Any]) -> str:
    """The run's counts in one sentence (the CLI prints it, ``summary.md`` repeats it)."""
    ev, t = provenance["evaluations"], provenance["timings_s"]["total"]
    now = f" ({ev['failed_now']} of them now)" if ev.get("failed_now", ev["failed"]) != ev["failed"] else ""
    return (f"{ev['total']} model evaluations ({ev['evaluated']} run now, {ev['cached']} from the store), "
            f"{ev['failed']} failed{now}, {t:.1f} s")


def problems(result: StudyResult) -> list[str]:
    """What makes the run's answer incomplete: an output left ``unconfirmed`` in some scene by
    :func:`ddgsa.execute.confirm.confirmation_table` (its indices refused, or neither trusted nor rank-confirmed;
    with the cheapest way to confirm it, :func:`ddgsa.execute.confirm.next_step`; an output with nothing to rank
    -- a spread within its resolution -- is not counted), failed sweep evaluations. Empty when all is well."""
    out = []
    table = verdicts(result)
    open_ = table[table["verdict"] == "unconfirmed"]
    for output, g in open_.groupby("output", sort=False):
        scenes = [int(s) for s in g["scene"]]
        d = result.diagnostics
        names = sorted(set(d[(d["output"].isin([output, None]) | d["output"].isna())
                             & (d["severity"] == "untrusted") & d["scene"].isin(scenes)]["name"])) if len(d) else []
        way = next_step(result, output, scenes, study_tolerance(result))
        out.append(f"output {output!r}: no method's indices are confirmed (trusted or rank-confirmed) in "
                   f"{_scenes(scenes)}" + (f" ({', '.join(names)})" if names else "")
                   + _first_failure(result, scenes) + "; " + way)
    if result.sweep is not None and result.sweep["error"].notna().any():
        n = int(result.sweep["error"].notna().sum())
        out.append(f"{n} of {len(result.sweep)} sweep evaluations failed (their values are refused)")
    return out


def _first_failure(result: StudyResult, scenes: list[int]) -> str:
    """``; N evaluations failed, the first: <reason>`` for the failed evaluations of ``scenes`` (any
    scene where they carry no index), so the console names the cause, not only its symptom."""
    fails = (getattr(result, "provenance", None) or {}).get("failures", [])
    if not fails:
        return ""
    fields = result.study.scene_fields
    grid = {i: f for i, f in enumerate(result.study.spec.scenes.grid())}
    mine = [f for f in fails if any(all(f["scene"].get(k) == grid[s].get(k) for k in fields) for s in scenes
                                    if s in grid)] or fails
    return f"; {len(mine)} evaluations failed, the first: {mine[0]['error']}" if mine else ""


def _scenes(scenes: list[int]) -> str:
    return f"scene {scenes[0]}" if len(scenes) == 1 else f"scenes {', '.join(map(str, scenes))}"


def _sweep_keys(sweep: pd.DataFrame, grid: list[str], fields: Sequence[str] = WIND_LABEL_FIELDS) -> list[str]:
    return (["variant"] if "variant" in sweep else []) + ["scene", *fields, *grid]


def sweep_summary(sweep: pd.DataFrame, outputs: list[str], grid: list[str] | None = None,
                  fields: Sequence[str] = WIND_LABEL_FIELDS) -> pd.DataFrame:
    """Mean and standard deviation over realisations per scene (and grid point and variant), plus
    each mean scaled by its maximum; ``fields``: the scene fields that label a scene."""
    keys = _sweep_keys(sweep, grid or [], fields)
    g = sweep.groupby(keys, sort=False)[outputs]
    mean, std = g.mean(), g.std(ddof=1).fillna(0.0)
    out = mean.add_suffix("_mean").join(std.add_suffix("_std")).reset_index()
    for o in outputs:
        out[f"{o}_scaled"] = out[f"{o}_mean"] / (out[f"{o}_mean"].abs().max() or 1.0)
    return out


def _case_label(fields: list[str], values: Any) -> str:
    """``field=value`` for numbers, the value alone for labels such as a variant's."""
    return ", ".join(f"{f}={v:g}" if isinstance(v, float) else f"{v}" for f, v in zip(fields, values))


def plot_sweep(summary: pd.DataFrame, outputs: list[str], grid: list[str] | None = None,
               info: dict[str, ModelOutput] | None = None,
               fields: Sequence[str] = WIND_LABEL_FIELDS) -> list[tuple[Any, str]]:
    """Each output (+- one std) against the first grid parameter, or against the first numeric
    scene field (wind speed) scaled by its maximum; one line per value of every other varying key
    (variant, scene fields, grid). Axis labels carry the outputs' units from ``info``."""
    grid = grid or []
    label_of = {o: (info or {}).get(o, declared(o)).label for o in outputs}
    x = grid[0] if grid else next(f for f in fields if pd.api.types.is_numeric_dtype(summary[f]))
    others = [f for f in _sweep_keys(summary, grid, fields) if f not in (x, "scene") and summary[f].nunique() > 1]
    figs = []
    if summary[x].nunique() == 1 and others:      # nothing to sweep along: one bar per case, real units
        labels = [_case_label(others, row) for row in summary[others].itertuples(index=False)]
        for o in outputs:
            fig, ax = plt.subplots(figsize=(6.5, 0.45 * len(labels) + 1.2), layout="constrained")
            ax.barh(labels, summary[f"{o}_mean"], xerr=summary[f"{o}_std"], color="tab:blue")
            for k, v in enumerate(summary[f"{o}_mean"]):
                ax.annotate(f"{v:.4g}", (v, k), xytext=(3, 0), textcoords="offset points", va="center", fontsize=8)
            ax.invert_yaxis()
            ax.set_xlabel(label_of[o])
            ax.grid(alpha=0.3, axis="x")
            figs.append((fig, f"sweep_{o}.png"))
        return figs
    for o in outputs:
        fig, ax = plt.subplots(figsize=(7.5 if others else 6, 3.6), layout="constrained")
        groups = summary.groupby(others, sort=False) if others else [((), summary)]
        scale = 1.0 if grid else (summary[f"{o}_mean"].abs().max() or 1.0)   # signed outputs: scale by |max|
        for key, g in groups:
            g = g.sort_values(x)
            label = _case_label(others, key if isinstance(key, tuple) else (key,))
            ax.errorbar(g[x], g[f"{o}_mean"] / scale, yerr=g[f"{o}_std"] / scale, capsize=2,
                        marker="o", ms=3, label=label or None)
        if grid and summary[x].min() > 0 and summary[x].max() / summary[x].min() > 50:
            ax.set_xscale("log")
        ax.set_xlabel(x if grid or x != "wind_speed" else "mean wind speed [m/s]")
        ax.set_ylabel(label_of[o] if grid else f"{o} / max [-]")
        ax.grid(alpha=0.3)
        if others:                                  # outside the axes: a line per case covers the data otherwise
            ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
        figs.append((fig, f"sweep_{o}.png"))
    return figs


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


def plot_agreement(indices: pd.DataFrame) -> Any:
    """Scatter of M-DRM indices against each cross-check (filled: M-DRM trusted, open: untrusted)."""
    fig, axes = plt.subplots(1, 2, figsize=(8, 4))
    key = ["scene", "output", "parameter"]
    m = indices[indices["method"] == "mdrm"]
    refs = _crosschecks(indices)
    for other in sorted(set(refs["method"])):
        j = m.merge(refs[refs["method"] == other], on=key, suffixes=("_m", "_r"))
        for ax, q in zip(axes, ("S1", "ST")):
            ok = j["trusted_m"].to_numpy(bool)
            pts = ax.scatter(j[f"{q}_r"][ok], j[f"{q}_m"][ok], s=14, label=f"vs {other}")
            ax.scatter(j[f"{q}_r"][~ok], j[f"{q}_m"][~ok], s=14, facecolors="none", edgecolors=pts.get_facecolor())
    for ax, q in zip(axes, ("S1", "ST")):
        ax.plot([0, 1], [0, 1], color="0.5", lw=0.8)
        ax.set_xlabel(f"{q}, cross-check")
        ax.set_ylabel(f"{q}, M-DRM")
        ax.set_xlim(-0.05, 1.05)
        ax.set_ylim(-0.05, 1.05)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    untrusted = not m["trusted"].astype(bool).all()
    fig.suptitle("M-DRM against cross-check" + (" (open markers: M-DRM untrusted)" if untrusted else ""))
    fig.tight_layout()
    return fig


_MARKERS = ("D", "s", "^", "v", "P", "X")


def plot_scene_bars(scene_rows: pd.DataFrame, info: dict[str, ModelOutput] | None = None,
                    fields: Sequence[str] = WIND_LABEL_FIELDS, verdicts: pd.DataFrame | None = None) -> Any:
    """One panel per output (at most three a row), parameters down the y axis: S1/ST bars of the
    estimate the summary reports -- the method of the pair's verdict (``verdicts``,
    :func:`ddgsa.execute.confirm.confirmation_table`), said in the panel's title with the verdict -- with
    confidence bars where it gives an interval, and the ST of every other requested method as a
    marker beside it (cross-checks, :data:`CROSSCHECKS`, are left to their own table). Hatched bars
    are untrusted (said in the legend, below the panels, only when some are); an output whose indices
    are refused says so; the title names the scene by its label ``fields``."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

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
                        markeredgecolor="0.15", markeredgewidth=0.8)
        ax.set_title(f"{(info or {}).get(out, declared(out)).label}\n{meth}" + (f": {verdict}" if verdict else ""),
                     fontsize=8)
        ax.set_xlim(min(-0.05, float(np.nanmin(g[["S1", "ST"]].to_numpy(float), initial=0))), 1.05)
        ax.tick_params(axis="x", labelsize=7)
        if not np.isfinite(t[["S1", "ST"]].to_numpy(float)).any():
            ax.text(0.5, 0.5, "indices refused\n(see summary.md)", transform=ax.transAxes,
                    ha="center", va="center", fontsize=8, color="0.3")
    for ax in list(axes.flat)[len(outputs):]:
        ax.set_visible(False)
    handles: list[Any] = [Patch(facecolor="tab:blue", label="S1"), Patch(facecolor="tab:orange", label="ST")]
    shown = rows[rows.apply(lambda r: chosen.get(r["output"], (None,))[0] in (None, r["method"]), axis=1)]
    untrusted = ~shown["trusted"].astype(bool)
    placed = shown["rank_confirmed"].astype(bool) if "rank_confirmed" in shown else untrusted & False
    if (untrusted & placed).any():
        handles.append(Patch(facecolor="tab:blue", edgecolor="white", hatch="..", label="untrusted, rank confirmed"))
    if (untrusted & ~placed).any():
        handles.append(Patch(facecolor="tab:blue", edgecolor="white", hatch="///", label="untrusted"))
    handles += [Line2D([], [], linestyle="none", marker=m, markerfacecolor="none", markeredgecolor="0.15",
                       label=f"ST, {meth}") for meth, m in marks.items()]
    fig.legend(handles=handles, fontsize=7, loc="outside lower center", ncols=min(len(handles), 5))
    fig.suptitle("Sobol indices, " + scene_text({f: rows[f].iloc[0] for f in fields}), fontsize=9)
    return fig


def plot_heatmap(rows: pd.DataFrame, info: dict[str, ModelOutput] | None = None,
                 fields: Sequence[str] = WIND_LABEL_FIELDS) -> Any:
    """ST as parameter x scene, one panel per output; the panels share the parameter axis, so
    its labels are drawn once, left of the first panel, and never over a neighbour. Scenes are
    labelled by their wind speed, or by their label ``fields`` for a model's own scene type."""
    outputs = list(rows["output"].unique())
    params = sorted(rows["parameter"].unique())
    fig, axes = plt.subplots(1, len(outputs), figsize=(2.4 * len(outputs) + 3.0, 0.3 * len(params) + 2.2),
                             squeeze=False, sharey=True, layout="constrained")
    hatched = False
    for ax, out in zip(axes[0], outputs):
        t = rows[rows["output"] == out].pivot(index="parameter", columns="scene", values="ST").reindex(params)
        im = ax.imshow(t.to_numpy(float), vmin=0, vmax=1, cmap="viridis", aspect="auto")
        ok = (rows[rows["output"] == out].pivot(index="parameter", columns="scene", values="trusted")
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
        o = (info or {}).get(out, declared(out))
        ax.set_title(f"{o}\n[{o.unit}]" if o.unit else str(o), fontsize=8)
    fig.colorbar(im, ax=axes[0].tolist(), shrink=0.8, label="ST [-]")
    fig.suptitle(f"total Sobol index per scene ({rows['method'].iloc[0]})"
                 + ("; hatched: untrusted (not within the tolerance by the method's own estimate)" if hatched else ""),
                 fontsize=9)
    return fig


def _write_fault(result: StudyResult, save_csv: Any, save_fig: Any) -> None:
    """The fault study's tables and figures (see :mod:`ddgsa.detection`)."""
    assert result.fault is not None and result.fault_smallest is not None and result.fault_indices is not None
    save_csv(result.fault, "fault_verdicts.csv")
    save_csv(result.fault_smallest, "fault_smallest.csv")
    save_csv(result.fault_indices, "fault_indices.csv")
    if result.fault_subsets is not None:
        save_csv(result.fault_subsets, "fault_sensor_choice.csv")
    fault = result.study.spec.fault
    assert fault is not None
    model = result.study.make_model()
    units = {o: d.unit for o, d in output_info(result).items()}
    for ps, det in result.fault_detection:
        title = scene_text(ps.fields)
        fig, ax = plt.subplots(figsize=(8.5, 4.2))
        det.plot_curve(ax=ax, level_label=f"{fault.parameter} [{model.parameter(fault.parameter).unit or '-'}]")
        ax.set_title(f"detectability curve, {title}\nshaded: POD interval at confidence {fault.confidence:g}",
                     fontsize=9)
        fig.tight_layout()
        save_fig(fig, f"fault_detectability_scene{ps.index}.png")
        save_fig(plot_fault_histograms(det, title, units), f"fault_histograms_scene{ps.index}.png")
        save_fig(plot_fault_indices(result.fault_indices[result.fault_indices["scene"] == ps.index], fault.parameter,
                                    title), f"fault_indices_scene{ps.index}.png")


def plot_fault_histograms(det: FaultDetectability, title: str, units: dict[str, str] | None = None) -> Any:
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


_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def _failure_reasons(failures: list[dict[str, Any]], most: int = 10) -> list[str]:
    """Failure reasons with how often each occurred, most frequent first (the first ``most``).

    Reasons that differ only in their numbers (a time, a point's value) are one reason: the first
    is shown, with how many others it stands for."""
    errors = pd.Series([f["error"] for f in failures], dtype=object)
    keys = errors.map(lambda e: _NUMBER.sub("#", str(e)))
    counts = keys.value_counts()
    first = errors.groupby(keys, sort=False).first()
    distinct = errors.groupby(keys, sort=False).nunique()
    lines = []
    for key, n in counts.head(most).items():
        alike = f" (and {distinct[key] - 1} alike, other numbers)" if distinct[key] > 1 else ""
        lines.append(f"- {n}x: {first[key]}{alike}")
    if len(counts) > most:
        lines.append(f"- ... and {int(counts.iloc[most:].sum())} more with {len(counts) - most} other reasons")
    return lines


def _outputs_section(result: StudyResult, info: dict[str, ModelOutput]) -> list[str]:
    """What each output is, its unit, and how much it varies (mean, CV) per scene."""
    lines = ["## Outputs", "", "| output | unit | what it is | scene | mean | CV | from |", "|---|---|---|---|---|---|---|"]
    mom = result.moments if result.moments is not None else pd.DataFrame(columns=["scene", "output"])
    for name, o in info.items():
        rows = mom[mom["output"] == name].to_dict("records") or [{}]
        for r in rows:
            stats = (f"{r['scene']} | {r['mean']:.4g} | {r['cv']:.2%} | {r['source']}" if r else "- | - | - | -")
            lines.append(f"| `{name}` | {o.unit or '?'} | {o.description} | {stats} |")
    return lines + [""]


def _mark(trusted: bool, rank_confirmed: bool) -> str:
    """``""`` for a trusted value, ``*`` for an untrusted one whose place is confirmed, ``?`` else."""
    return "" if trusted else "*" if rank_confirmed else "?"


def _confirmed_section(result: StudyResult) -> list[str]:
    """The count of each verdict over the (scene, output) pairs (:func:`ddgsa.execute.confirm.confirmation_table`,
    ``confirmation.csv``) and the runs spent."""
    table = verdicts(result)
    n_runs = result.provenance.get("evaluations", {}).get("total", len(result.evaluations))
    count = table["verdict"].value_counts()
    done = int(table["verdict"].isin(CONFIRMED).sum())
    parts = [f"{int(count[v])} {v}" for v in VERDICTS[:4] if count.get(v, 0)]
    flat = table[table["verdict"] == "nothing to rank"]
    lines = [f"Confirmed: {done} of {len(table)} (scene, output) pairs" + (f" ({', '.join(parts)})" if parts else "")
             + f" at a cost of {n_runs} model runs" + (" (unconfirmed ones: see Problems)." if done < len(table) else "."),
             ""]
    if len(flat):
        lines += ["Nothing to rank (the spread over the design is within the output's resolution, a sensor's noise "
                  "or the numerical floor; no runs are advised): "
                  + ", ".join(f"`{r.output}` in scene {r.scene} ({r.std:.2g} against {r.resolution:.2g})"
                              for r in flat.itertuples()) + ".", ""]
    return lines


def crosscheck_lines(sobol: pd.DataFrame) -> list[str]:
    """``summary.md``'s section on the cross-checks the study ran without being asked
    (:data:`CROSSCHECKS`, at zero extra runs): per scene and output, whether each agrees with the
    study's own methods' ST within their bounds, and its trust; none when the study has no other rows."""
    cross = sobol[sobol["method"].isin(CROSSCHECKS)] if len(sobol) else sobol
    own = sobol[~sobol["method"].isin(CROSSCHECKS)] if len(sobol) else sobol
    if not len(cross) or not len(own):
        return []
    lines = ["## Cross-checks (not requested; fitted on the study's own runs at no extra cost)", "",
             "They check the requested methods, they are not the study's answer: `pooled_pce` is a sparse PCE on "
             "every point of a scene, `given_data_s1` first-order indices from the drawn points (never trusted: "
             "it has no ST).", "", "| scene | output | method | trusted rows | largest S1 (parameter) |",
             "|---|---|---|---|---|"]
    for (scene, out, meth), g in cross.groupby(["scene", "output", "method"], sort=False):
        top = g.loc[g["S1"].astype(float).idxmax()] if g["S1"].notna().any() else None
        big = f"{top['S1']:.2f} ({top['parameter']})" if top is not None else "-"
        lines.append(f"| {scene} | `{out}` | {meth} | {int(g['trusted'].astype(bool).sum())} of {len(g)} | {big} |")
    return lines + [""]


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


def _dominance(g: pd.DataFrame, output: str, moment: dict[str, Any] | None, verdict: Any = None) -> str:
    """One sentence on what drives ``output`` in one scene, from its first trusted method (``verdict``:
    the pair's row of :func:`ddgsa.execute.confirm.confirmation_table`, which says when there is nothing to rank),
    and the confirmed ranking as tied groups where the verdict has one."""
    trusted = [(m, gm) for m, gm in g.groupby("method", sort=False) if gm["trusted"].all()]
    ranked = [(m, gm) for m, gm in g.groupby("method", sort=False)
              if (gm["trusted"] | gm.get("rank_confirmed", False)).all()]
    if verdict is not None and verdict.verdict == "nothing to rank":
        return (f"`{output}`: nothing to rank here: it spreads by {verdict.std:.3g} over the design, within its "
                f"resolution (a sensor's noise, {verdict.resolution:.3g}, or the numerical floor, {CONSTANT_CV:.0e} of "
                "its mean): no parameter moves it by more than the model can tell.")
    if not trusted and not ranked:
        return (f"`{output}`: no method's indices are trusted or rank-confirmed here; do not rank its parameters "
                "(see Problems for what would confirm them).")
    meth, gm = (trusted or ranked)[0]
    named = verdict.method if verdict is not None else None            # the verdict's method, as everywhere
    for m, g_m in trusted + ranked:
        if m == named:
            meth, gm = m, g_m
            break
    if not gm["trusted"].all():
        meth += " (order confirmed by its error bounds; values not within the tolerance)"
    top = gm.sort_values("ST", ascending=False)
    first = top.iloc[0]
    quiet = f" It hardly varies (CV {moment['cv']:.2%}), so this ranks small differences." \
        if moment is not None and moment["cv"] < 1e-3 else ""
    share = top[top["ST"] >= 0.1]
    if first["ST"] >= 0.5 and (len(top) < 2 or top.iloc[1]["ST"] < 0.5 * first["ST"]):
        what = f"`{first['parameter']}` dominates (ST {first['ST']:.2f}, S1 {first['S1']:.2f})"
    elif len(share):
        what = "shared by " + ", ".join(f"`{r.parameter}` (ST {r.ST:.2f}, S1 {r.S1:.2f})" for r in share.head(3).itertuples())
    else:
        what = f"no parameter reaches ST 0.1 (largest: `{first['parameter']}`, {first['ST']:.2f})"
    inter = " ST - S1 shows interactions." if (top["ST"] - top["S1"]).max() > 0.1 else ""
    order = (f" Confirmed ranking ({verdict.verdict}): {verdict.ranking}." if verdict is not None and verdict.ranking
             and (verdict.verdict in ("rank-confirmed", "confirmed tie") or "=" in verdict.ranking) else "")
    return f"`{output}`: {what}, by {meth}.{inter}{quiet}{order}"


def plot_fault_indices(rows: pd.DataFrame, fault: str, title: str) -> Any:
    """Paper A's view: total index of each other parameter per output, healthy and at each faulty level."""
    method = rows["method"].iloc[0]
    rows = rows[rows["method"] == method]
    outputs, levels = list(rows["output"].unique()), list(rows["level"].unique())
    params = list(rows["parameter"].unique())
    fig, axes = plt.subplots(1, len(outputs), figsize=(3.2 * len(outputs) + 0.5, 3.4), squeeze=False, sharey=True)
    width = 0.8 / len(levels)
    for ax, out in zip(axes[0], outputs):
        t = rows[rows["output"] == out]
        for k, level in enumerate(levels):
            st = t[t["level"] == level].set_index("parameter").reindex(params)["ST"]
            ax.bar(np.arange(len(params)) + (k - (len(levels) - 1) / 2) * width, st, width,
                   label=f"{fault} = {level:g}" + (" (healthy)" if k == 0 else ""))
        ax.set_xticks(range(len(params)), params, rotation=60, fontsize=7, ha="right")
        ax.set_title(out, fontsize=8)
        ax.grid(alpha=0.3, axis="y")
    axes[0, 0].set_ylabel(f"ST ({method}) [-]")
    axes[0, 0].legend(fontsize=6)
    fig.suptitle(f"indices of the other parameters with and without the fault, {title}", fontsize=9)
    fig.tight_layout()
    return fig


def _fault_markdown(result: StudyResult) -> list[str]:
    """The fault section of ``summary.md``: verdicts, smallest detectable fault, index shifts."""
    assert result.fault is not None and result.fault_smallest is not None and result.fault_indices is not None
    fault = result.study.spec.fault
    assert fault is not None
    n = fault.samples * result.study.spec.scenes.realisations
    noise = ", ".join(f"{o}: {v.absolute:g} abs, {v.relative:g} rel" for o, v in fault.noise.items()) or "none"
    design = ("population: healthy and faulty measurements compared only where they share no parameter point "
              "and no wind record (what a monitoring system faces; the levels share points and records only to "
              "keep the curves smooth)" if fault.design == "population" else
              "paired: each measurement is a point's change from its own healthy record r to its record r + 1 "
              "(one turbine against its own baseline, in other wind); compared only where no point or record is "
              "shared")
    lines = ["## Fault detectability", "",
             f"Fault `{fault.parameter}`: healthy {fault.healthy:g}, "
             f"faulty {', '.join(f'{v:g}' for v in fault.levels)}. "
             f"Each population: {fault.samples} points of the other parameters x "
             f"{result.study.spec.scenes.realisations} realisations = {n} measurements (not averaged); "
             f"measurement noise (std): {noise}. Design {design}. Alarm threshold at false-alarm rate "
             f"{fault.false_alarm:g} (`false alarms`: the rate measured out of sample); "
             f"detectable when the lower end of the POD interval (two-way bootstrap over points and records, "
             f"union Clopper-Pearson on the effective count, confidence {fault.confidence:g}) reaches "
             f"{fault.pod_target:g}; refused when the measurements are worth fewer than 1/false-alarm independent "
             "ones. `combined`: Fisher discriminant of the outputs, trained on one half of the points and scored "
             "on the other; its interval re-trains on every bootstrap re-draw.", "",
             "| scene | output | faulty | ST fault | effect size | AUC [interval] | POD [interval] | false alarms "
             "| n eff | detectable |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in result.fault.itertuples():
        verdict = {True: "yes", False: "no"}.get(r.detectable, f"refused: {r.reason}")
        st = "-" if pd.isna(r.ST_fault) else f"{r.ST_fault:.2f}"
        lines.append(f"| {r.scene} | {r.output} | {r.faulty:g} | {st} | {r.effect_size:.2f} | "
                     f"{r.auc:.2f} [{r.auc_low:.2f}, {r.auc_high:.2f}] | {r.pod:.2f} [{r.pod_low:.2f}, "
                     f"{r.pod_high:.2f}] | {r.false_alarm:.3f} | {r.n_eff_healthy:.0f} | {verdict} |")
    if result.fault_subsets is not None:
        lines += ["", "### Sensor choice (greedy forward on the Fisher detector, validated on held-out points)", "",
                  "| scene | faulty | chosen sensors | selection AUC | validation AUC [interval] | validation POD "
                  "[interval] | all sensors, validation AUC / POD |", "|---|---|---|---|---|---|---|"]
        lines += [_subset_row(r) for r in result.fault_subsets.itertuples()]
    lines += ["", f"### Smallest detectable fault (POD {fault.pod_target:g} at false-alarm rate "
                  f"{fault.false_alarm:g}, interpolated)", "",
              "| scene | output | level (POD) | level (POD lower bound) | note |", "|---|---|---|---|---|"]
    lines += [f"| {r.scene} | {r.output} | {r.level_at_target:.4g} | {r.level_at_target_lower:.4g} | {r.reason} |"
              for r in result.fault_smallest.itertuples()]
    fi = result.fault_indices
    lines += ["", "### Sensitivity indices with and without the fault (other parameters, paper A)", "",
              "| scene | method | output | parameter | ST healthy | " +
              " | ".join(f"dST at {v:g}" for v in fault.levels) + " |",
              "|---|---|---|---|---|" + "---|" * len(fault.levels)]
    for (scene, method, out, par), g in fi.groupby(["scene", "method", "output", "parameter"], sort=False):
        g = g.set_index("level")
        shifts = " | ".join(f"{g.loc[v, 'dST']:+.2f}" for v in fault.levels)
        lines.append(f"| {scene} | {method} | {out} | {par} | {g.loc[fault.healthy, 'ST']:.2f} | {shifts} |")
    lines.append("")
    return lines


RANKED = 5
"""Parameters a ranking row of ``summary.md`` names (it says how many more ``indices.csv`` holds)."""


def no_effect_lines(result: StudyResult) -> list[str]:
    """``summary.md``'s list of the uncertain parameters without effect, by name with the reason:
    those the model ignores at the study's fidelity (:meth:`~ddgsa.models.base.Model.unused_parameters`)
    and those whose ST is exactly 0 for every output, scene and method of the run."""
    unused = result.study.make_model().unused_parameters()
    st = result.indices.groupby("parameter", sort=False)["ST"].agg(lambda v: bool((v.fillna(1.0) == 0.0).all()))
    reasons = {name: unused[name] for name in result.study.spec.parameters if name in unused}
    reasons.update({name: "ST = 0 for every output, scene and method (no effect in this study)"
                    for name, zero in st.items() if zero and name not in reasons})
    if not reasons:
        return []
    return (["## Parameters without effect", "", "Their indices are 0 (by construction, or in this run); they rank last everywhere:", ""]
            + [f"- `{name}`: {why}" for name, why in reasons.items()] + [""])


LOADS_MEANING = {"bem": "blade-element momentum rotor; docs/loads.md",
                 "auto": "blade-element momentum rotor where |inclination_deg| >= "
                         f"{AUTO_BEM_INCLINATION_DEG:g}, else the Cp/Ct table rotor; docs/loads.md"}
"""The summary's line on a wind study's hub loads where they are not the default table rotor's."""


def _loads_line(result: StudyResult) -> list[str]:
    """``- loads: ...`` where the study's wind scenes use another rotor than the default table one
    (nothing for the default, so summaries of table-rotor studies are unchanged)."""
    loads = getattr(result.study.spec.scenes, "loads", None)
    fidelity = getattr(loads, "fidelity", "table")
    return [f"- loads: `{fidelity}` ({LOADS_MEANING[fidelity]})"] if fidelity in LOADS_MEANING else []


def _basis_lines(p: dict[str, Any]) -> list[str]:
    """``- shaft basis: ...`` lines (the rig's and the direct drive's modal basis and its convergence
    in each scene's band, :func:`ddgsa.study.checks.study_basis`); none for other models or older runs."""
    from ddgsa.study.checks import basis_messages

    return [f"- {text}" + ("" if ok else " (**not converged**)")
            for ok, text in basis_messages(p.get("basis", []))]


def summary_markdown(result: StudyResult, info: dict[str, ModelOutput] | None = None) -> str:
    """A short Markdown summary: what ran, the outputs (unit, meaning, mean, CV), problems, then
    per scene and output a sentence on what dominates and parameters ranked by ST with S1."""
    p = result.provenance
    info = info if info is not None else output_info(result)
    code = p.get("code", {})
    lines = [f"# {result.study.name}", "", result.study.spec.description or "", "",
             f"- model: `{p['model']['name']}` ({model_words(p['model'])})", *_loads_line(result),
             *_basis_lines(p),
             f"- evaluations: {evaluation_line(p)}",
             f"- ddgsa {code.get('ddgsa', '?')}" + (f", commit {code['commit'][:12]}"
                                                   + (" (modified)" if code.get("modified") else "")
                                                   if code.get("commit") else ""), ""]
    lines += _outputs_section(result, info)
    bad = problems(result)
    if bad or p["failures"] or p.get("implausible"):
        lines += ["## Problems", ""] + [f"- {b}" for b in bad] + [f"- implausible: {m}" for m in p.get("implausible", [])]
        if p["failures"]:
            lines += ["", f"Failed evaluations ({len(p['failures'])}; their indices are refused, never imputed; "
                          "details in `provenance.json`):", ""] + _failure_reasons(p["failures"])
        lines.append("")
    if result.fidelity is not None and len(result.fidelity):
        lines += ["## Fidelity chosen per scene (`fidelity: auto`)", "",
                  f"| scene | {'wind speed' if result.study.wind else 'scene fields'} | chosen | " + " | ".join(
                      f"max rel. error {c[len('max_rel_error_'):]}" for c in result.fidelity.columns
                      if c.startswith("max_rel_error_")) + " |",
                  "|---|---|---|" + "---|" * sum(c.startswith("max_rel_error_") for c in result.fidelity.columns)]
        for r in result.fidelity.to_dict("records"):
            errs = " | ".join(f"{v:.2%}" for k, v in r.items() if k.startswith("max_rel_error_"))
            where = (f"{r['wind_speed']:g}" if result.study.wind
                     else scene_text({f: r[f] for f in result.study.scene_fields}))
            lines.append(f"| {r['scene']} | {where} | {r['chosen']} | {errs} |")
        lines.append("")
    if len(result.indices):
        mom = {(r["scene"], r["output"]): r for r in (result.moments.to_dict("records")
                                                      if result.moments is not None else [])}
        tols = {res.method: res.options.get("tolerance") for _, res in result.results}
        ranked = len(sobol_rows(result.indices)) > 0          # HSIC-only studies rank nothing
        lines += [] if not ranked else ["## Parameters ranked by total index (ST, with S1)", "",
                  "trusted = every index of the row (S1 and ST) within ±tolerance (absolute) of the truth, "
                  "by the method's own error estimate (docs/methods.md: \"When M-DRM is not to be trusted\"); "
                  "a method is `yes` when all its rows are. rank confirmed = every row trusted or placed by its "
                  "error bounds (negligible, or apart from zero and, against every other row, apart or a confirmed "
                  "tie: their ST difference within the tie margin). In the ranking `*` marks "
                  "an untrusted value whose place is confirmed, `?` one that is neither. A method's runs (indices.csv "
                  "`n_evals`) count its whole design, any check sample of its own included; the evaluation count "
                  "above counts each distinct point once, as methods share equal points.", ""]
        lines += _confirmed_section(result) if ranked else []
        by_pair = {(int(r.scene), r.output): r for r in verdicts(result).itertuples()} if ranked else {}
        for (scene, out), g in sobol_rows(result.indices).groupby(["scene", "output"]):
            fields = scene_text({f: g[f].iloc[0] for f in result.study.scene_fields})
            lines.append(f"### scene {scene} ({fields}) - `{out}` [{info.get(out, declared(out)).unit or '?'}]")
            lines.append("")
            lines += [_dominance(g, out, mom.get((scene, out)), by_pair.get((int(scene), out))), ""]
            if "n_evals" in g and g["n_evals"].notna().all():
                runs = g.groupby("method", sort=False)["n_evals"].first()
                lines += ["runs per method (indices.csv `n_evals`): " + ", ".join(f"{m} {int(n)}" for m, n in runs.items()),
                          ""]
            lines.append("| method | tolerance | trusted | rank confirmed | ranking: parameter ST (S1) |")
            lines.append("|---|---|---|---|---|")
            for meth, gm in g.groupby("method", sort=False):
                if meth in CROSSCHECKS and len(set(g["method"]) - set(CROSSCHECKS)):
                    continue                                         # in "Cross-checks" below
                by = "ST" if gm["ST"].notna().any() else "S1"        # a first-order-only method (given_data_s1)
                top = gm.sort_values(by, ascending=False, na_position="last").head(RANKED)
                rank = ", ".join((f"{r.parameter} {r.ST:.2f} ({r.S1:.2f})" if by == "ST" else
                                  f"{r.parameter} - ({r.S1:.2f})") + _mark(r.trusted, r.rank_confirmed)
                                 for r in top.itertuples())
                rank += f"; {len(gm) - len(top)} more in indices.csv" if len(gm) > len(top) else ""
                label = (f"{meth} (from {', '.join(gm['source'].drop_duplicates())})" if meth == "auto" else meth)
                tol = tols.get(meth)
                lines.append(f"| {label} | {'' if tol is None else f'±{tol:g}'} | "
                             f"{'yes' if gm['trusted'].all() else '**no**'} | "
                             f"{'yes' if (gm['trusted'] | gm['rank_confirmed']).all() else '**no**'} | {rank} |")
            lines.append("")
        lines += crosscheck_lines(sobol_rows(result.indices))
        lines += no_effect_lines(result)
        lines += signal_summary_lines(result.signal_generalised)
        lines += beyond_markdown(result)
        logs = [(ps, res) for ps, res in result.results if res.method == "auto"]
        if logs:
            lines += ["## `method: auto` decisions", ""]
            for ps, res in logs:
                lines.append(f"- scene {ps.index}, {res.n_evals} runs: " + "; ".join(res.extras["auto_log"]))
            lines.append("")
        if len(result.diagnostics):
            lines += ["## Diagnostics", ""]
            counts = result.diagnostics.groupby(["method", "name", "severity"]).size()
            lines += [f"- {m} `{n}` ({s}): {c}x" for (m, n, s), c in counts.items()]
            lines.append("")
    lines += sampling_markdown(result.provenance.get("sampling", []))
    if result.fault is not None:
        lines += _fault_markdown(result)
    if result.sweep is not None:
        lines += ["## Sweep", "", "See `sweep_summary.csv` and `sweep_*.png` (means over realisations, +- one std).",
                  ""]
        grid = list(result.study.spec.grid)
        summary = sweep_summary(result.sweep, result.study.outputs, grid)
        if len(summary) <= 40:
            keys = [k for k in _sweep_keys(summary, grid) if k == "variant" or k in grid or summary[k].nunique() > 1]
            cols = keys + [f"{o}_mean" for o in result.study.outputs]
            lines += ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
            lines += ["| " + " | ".join(f"{v:.6g}" if isinstance(v, float) else str(v) for v in row) + " |"
                      for row in summary[cols].itertuples(index=False)]
            lines.append("")
    return "\n".join(lines)


def sampling_markdown(rows: list[dict]) -> list[str]:
    """The summary's "Sampling (aliasing guard)" section for the guard's flagged rows.

    Parameters
    ----------
    rows : list of dict
        The provenance's ``sampling`` rows (keys ``interval``, ``interval_s`` [s], ``mode``,
        ``frequency_hz`` [Hz], ``samples_per_period``, ``verdict``, ``consequence`` and, for a study
        with variants, ``variant``).

    Returns
    -------
    list of str
        Markdown lines; empty when every row's verdict is ``ok``. The ``variant`` column is shown only
        when some row names a variant.
    """
    flagged = [r for r in rows if r.get("verdict") != "ok"]
    if not flagged:
        return []
    variant = any(r.get("variant") for r in flagged)
    head = ["interval", "[s]", "mode", "[Hz]", "samples/period", "verdict", "consequence"]
    head = ["variant"] * variant + head
    lines = ["## Sampling (aliasing guard)", "", "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in flagged:
        cells = [str(r['interval']), f"{r.get('interval_s', float('nan')):.4g}", str(r.get('mode', '')),
                 f"{r.get('frequency_hz', float('nan')):.4g}", f"{r.get('samples_per_period', float('nan')):.3g}",
                 str(r['verdict']), str(r['consequence'])]
        lines.append("| " + " | ".join([str(r.get("variant", ""))] * variant + cells) + " |")
    return lines + [""]


def _subset_row(r: Any) -> str:
    """One row of the sensor-choice table; a validation the statistics refused shows its reason, not NaN."""
    head = f"| {r.scene} | {r.faulty:g} | {r.sensors} | {r.selection_auc:.3f} | "
    if not np.isfinite(r.auc):
        why = getattr(r, "reason", "") or "no validation statistics"
        return head + f"refused: {why} | - | - |"
    return head + (f"{r.auc:.2f} [{r.auc_low:.2f}, {r.auc_high:.2f}] | {r.pod:.2f} [{r.pod_low:.2f}, "
                   f"{r.pod_high:.2f}] | {r.all_auc:.2f} / {r.all_pod:.2f} |")
