"""Write a study's tables, plots, provenance and summary into its output folder."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from ddgsa.gsa.result import draw_index_bars  # noqa: E402
from ddgsa.pipeline import SCENE_FIELDS, StudyResult  # noqa: E402


def write_report(result: StudyResult, out: Path) -> list[Path]:
    """Write every file of the report; returns their paths."""
    out.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []

    def save_csv(df: pd.DataFrame, name: str) -> None:
        path = out / name
        df.to_csv(path, index=False, float_format="%.6g")
        written.append(path)

    def save_fig(fig: Any, name: str) -> None:
        path = out / name
        fig.savefig(path, dpi=100, bbox_inches="tight")
        plt.close(fig)
        written.append(path)

    save_csv(result.evaluations.drop(columns=["key"], errors="ignore"), "evaluations.csv")
    if result.sweep is not None:
        save_csv(result.sweep, "sweep.csv")
        summary = sweep_summary(result.sweep, result.study.outputs, list(result.study.spec.grid))
        save_csv(summary, "sweep_summary.csv")
        for fig, name in plot_sweep(summary, result.study.outputs, list(result.study.spec.grid)):
            save_fig(fig, name)
    if len(result.indices):
        save_csv(result.indices, "indices.csv")
        save_csv(result.diagnostics, "diagnostics.csv")
        acc = accuracy_table(result.indices)
        if len(acc):
            save_csv(acc, "accuracy.csv")
            save_fig(plot_agreement(result.indices), "mdrm_vs_crosscheck.png")
        for scene in sorted(result.indices["scene"].unique()):
            save_fig(plot_scene_bars(result.indices[result.indices["scene"] == scene]), f"bars_scene{scene}.png")
        if result.indices["scene"].nunique() > 1:
            for method in result.indices["method"].unique():
                save_fig(plot_heatmap(result.indices[result.indices["method"] == method]), f"heatmap_ST_{method}.png")
    if result.fidelity is not None and len(result.fidelity):
        save_csv(result.fidelity, "fidelity_selection.csv")
    if result.fault is not None:
        save_csv(result.fault, "fault_verdicts.csv")
        save_fig(plot_fault(result.fault, result.fault_samples), "fault_detectability.png")
    path = out / "provenance.json"
    path.write_text(json.dumps(result.provenance, indent=2, default=str))
    written.append(path)
    path = out / "summary.md"
    path.write_text(summary_markdown(result))
    written.append(path)
    return written


def _sweep_keys(sweep: pd.DataFrame, grid: list[str]) -> list[str]:
    return (["variant"] if "variant" in sweep else []) + ["scene", *SCENE_FIELDS, *grid]


def sweep_summary(sweep: pd.DataFrame, outputs: list[str], grid: list[str] | None = None) -> pd.DataFrame:
    """Mean and standard deviation over realisations per scene (and grid point and variant), plus
    each mean scaled by its maximum."""
    keys = _sweep_keys(sweep, grid or [])
    g = sweep.groupby(keys, sort=False)[outputs]
    mean, std = g.mean(), g.std(ddof=1).fillna(0.0)
    out = mean.add_suffix("_mean").join(std.add_suffix("_std")).reset_index()
    for o in outputs:
        out[f"{o}_scaled"] = out[f"{o}_mean"] / (out[f"{o}_mean"].abs().max() or 1.0)
    return out


def _case_label(fields: list[str], values: Any) -> str:
    """``field=value`` for numbers, the value alone for labels such as a variant's."""
    return ", ".join(f"{f}={v:g}" if isinstance(v, float) else f"{v}" for f, v in zip(fields, values))


def plot_sweep(summary: pd.DataFrame, outputs: list[str], grid: list[str] | None = None) -> list[tuple[Any, str]]:
    """Each output (+- one std) against the first grid parameter, or against wind speed scaled by
    its maximum; one line per value of every other varying key (variant, scene fields, grid)."""
    grid = grid or []
    x = grid[0] if grid else "wind_speed"
    others = [f for f in _sweep_keys(summary, grid) if f not in (x, "scene") and summary[f].nunique() > 1]
    figs = []
    if summary[x].nunique() == 1 and others:      # nothing to sweep along: one bar per case, real units
        labels = [_case_label(others, row) for row in summary[others].itertuples(index=False)]
        for o in outputs:
            fig, ax = plt.subplots(figsize=(6.5, 0.45 * len(labels) + 1.2))
            ax.barh(labels, summary[f"{o}_mean"], xerr=summary[f"{o}_std"], color="tab:blue")
            for k, v in enumerate(summary[f"{o}_mean"]):
                ax.annotate(f"{v:.4g}", (v, k), xytext=(3, 0), textcoords="offset points", va="center", fontsize=8)
            ax.invert_yaxis()
            ax.set_xlabel(o)
            ax.grid(alpha=0.3, axis="x")
            figs.append((fig, f"sweep_{o}.png"))
        return figs
    for o in outputs:
        fig, ax = plt.subplots(figsize=(6, 3.6))
        groups = summary.groupby(others, sort=False) if others else [((), summary)]
        scale = 1.0 if grid else (summary[f"{o}_mean"].abs().max() or 1.0)   # signed outputs: scale by |max|
        for key, g in groups:
            g = g.sort_values(x)
            label = _case_label(others, key if isinstance(key, tuple) else (key,))
            ax.errorbar(g[x], g[f"{o}_mean"] / scale, yerr=g[f"{o}_std"] / scale, capsize=2,
                        marker="o", ms=3, label=label or None)
        if grid and summary[x].min() > 0 and summary[x].max() / summary[x].min() > 50:
            ax.set_xscale("log")
        ax.set_xlabel(x if grid else "mean wind speed [m/s]")
        ax.set_ylabel(o if grid else f"{o} / max [-]")
        ax.grid(alpha=0.3)
        if others:
            ax.legend(fontsize=8)
        figs.append((fig, f"sweep_{o}.png"))
    return figs


def accuracy_table(indices: pd.DataFrame) -> pd.DataFrame:
    """M-DRM against each cross-check method per scene and output: max |dS1|, max |dST|, trust."""
    if "mdrm" not in set(indices["method"]):
        return pd.DataFrame()
    key = ["scene", "output", "parameter"]
    m = indices[indices["method"] == "mdrm"]
    rows = []
    for other in sorted(set(indices["method"]) - {"mdrm"}):
        joined = m.merge(indices[indices["method"] == other], on=key, suffixes=("_mdrm", "_ref"))
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
    for other in sorted(set(indices["method"]) - {"mdrm"}):
        j = m.merge(indices[indices["method"] == other], on=key, suffixes=("_m", "_r"))
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
    fig.suptitle("M-DRM against cross-check (open markers: M-DRM untrusted)")
    fig.tight_layout()
    return fig


def plot_scene_bars(scene_rows: pd.DataFrame) -> Any:
    """S1/ST bars with confidence bars: one row per output, one column per method."""
    outputs, methods = list(scene_rows["output"].unique()), list(scene_rows["method"].unique())
    fig, axes = plt.subplots(len(outputs), len(methods), figsize=(3.8 * len(methods), 2.6 * len(outputs)),
                             squeeze=False)
    for i, out in enumerate(outputs):
        for j, meth in enumerate(methods):
            t = scene_rows[(scene_rows["output"] == out) & (scene_rows["method"] == meth)]
            ax = axes[i, j]
            draw_index_bars(ax, t, fontsize=7, rotation=60)
            ax.set_title(f"{out} - {meth}", fontsize=9)
            ax.set_ylim(min(-0.05, float(np.nanmin(t[["S1", "ST"]].to_numpy(float), initial=0))), 1.05)
    axes[0, 0].legend(fontsize=7)
    fields = {f: scene_rows[f].iloc[0] for f in SCENE_FIELDS}
    fig.suptitle("Sobol indices, " + ", ".join(f"{k}={v:g}" for k, v in fields.items()) + " (hatched: untrusted)",
                 fontsize=9)
    fig.tight_layout()
    return fig


def plot_heatmap(rows: pd.DataFrame) -> Any:
    """ST as parameter x scene, one panel per output."""
    outputs = list(rows["output"].unique())
    fig, axes = plt.subplots(1, len(outputs), figsize=(3.2 * len(outputs) + 1, 0.35 * rows["parameter"].nunique() + 2),
                             squeeze=False)
    for ax, out in zip(axes[0], outputs):
        t = rows[rows["output"] == out].pivot(index="parameter", columns="scene", values="ST")
        im = ax.imshow(t.to_numpy(float), vmin=0, vmax=1, cmap="viridis", aspect="auto")
        labels = [f"{rows[rows['scene'] == s]['wind_speed'].iloc[0]:g} m/s" for s in t.columns]
        ax.set_xticks(range(t.shape[1]), labels, rotation=45, fontsize=7)
        ax.set_yticks(range(t.shape[0]), t.index.to_list(), fontsize=7)
        ax.set_title(out, fontsize=9)
    fig.colorbar(im, ax=axes[0].tolist(), shrink=0.8, label="ST")
    fig.suptitle(f"total Sobol index per scene ({rows['method'].iloc[0]})", fontsize=9)
    return fig


def plot_fault(verdicts: pd.DataFrame, samples: pd.DataFrame | None) -> Any:
    """Separation index per output and fault level (bars) with the threshold."""
    fig, ax = plt.subplots(figsize=(7, 3.5))
    labels = [f"{r.output}\n{r.faulty:g}, s{r.scene}" for r in verdicts.itertuples()]
    colors = ["tab:green" if d else "tab:red" for d in verdicts["detectable"]]
    ax.bar(range(len(verdicts)), verdicts["separation"].clip(upper=1e3), color=colors)
    ax.axhline(verdicts["threshold"].iloc[0], color="k", ls="--", lw=0.8, label="threshold")
    ax.set_yscale("log")
    ax.set_xticks(range(len(verdicts)), labels, fontsize=6, rotation=60, ha="right")
    ax.set_ylabel("|mean faulty - mean healthy| / std healthy")
    ax.set_title(f"fault detectability: {verdicts['fault'].iloc[0]} (green: detectable)", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def summary_markdown(result: StudyResult) -> str:
    """A short Markdown summary: what ran, then parameters ranked by ST per scene and output."""
    p = result.provenance
    lines = [f"# {result.study.name}", "", result.study.spec.description or "", "",
             f"- model: `{p['model']['name']}` ({p['model']['fidelity']})",
             f"- evaluations: {p['evaluations']['total']} ({p['evaluations']['cached']} cached, "
             f"{p['evaluations']['evaluated']} run, {len(p['failures'])} failed)",
             f"- time: {p['timings_s']['total']:.1f} s", ""]
    if result.fidelity is not None and len(result.fidelity):
        lines += ["## Fidelity chosen per scene (`fidelity: auto`)", "",
                  "| scene | wind speed | chosen | " + " | ".join(
                      f"max rel. error {c[len('max_rel_error_'):]}" for c in result.fidelity.columns
                      if c.startswith("max_rel_error_")) + " |",
                  "|---|---|---|" + "---|" * sum(c.startswith("max_rel_error_") for c in result.fidelity.columns)]
        for r in result.fidelity.to_dict("records"):
            errs = " | ".join(f"{v:.2%}" for k, v in r.items() if k.startswith("max_rel_error_"))
            lines.append(f"| {r['scene']} | {r['wind_speed']:g} | {r['chosen']} | {errs} |")
        lines.append("")
    if len(result.indices):
        lines += ["## Parameters ranked by total index", ""]
        for (scene, out), g in result.indices.groupby(["scene", "output"]):
            fields = ", ".join(f"{f}={g[f].iloc[0]:g}" for f in SCENE_FIELDS)
            lines.append(f"### scene {scene} ({fields}) - `{out}`")
            lines.append("")
            lines.append("| method | trusted | ranking (ST) |")
            lines.append("|---|---|---|")
            for meth, gm in g.groupby("method", sort=False):
                top = gm.sort_values("ST", ascending=False, na_position="last").head(5)
                rank = ", ".join(f"{r.parameter} {r.ST:.2f}" for r in top.itertuples())
                label = f"{meth} (from {gm['source'].iloc[0]})" if meth == "auto" else meth
                lines.append(f"| {label} | {'yes' if gm['trusted'].all() else '**no**'} | {rank} |")
            lines.append("")
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
    flagged = [r for r in result.provenance.get("sampling", []) if r.get("verdict") != "ok"]
    if flagged:
        lines += ["## Sampling (aliasing guard)", "",
                  "| variant | interval | [s] | mode | [Hz] | samples/period | verdict | consequence |",
                  "|---|---|---|---|---|---|---|---|"]
        lines += [f"| {r.get('variant', '')} | {r['interval']} | {r.get('interval_s', float('nan')):.4g} | "
                  f"{r.get('mode', '')} | {r.get('frequency_hz', float('nan')):.4g} | "
                  f"{r.get('samples_per_period', float('nan')):.3g} | {r['verdict']} | {r['consequence']} |"
                  for r in flagged]
        lines.append("")
    if result.fault is not None:
        lines += ["## Fault detectability", "", "| scene | output | faulty | ST fault | separation | detectable |",
                  "|---|---|---|---|---|---|"]
        lines += [f"| {r.scene} | {r.output} | {r.faulty:g} | {r.ST_fault:.2f} | {r.separation:.2f} | "
                  f"{'yes' if r.detectable else 'no'} |" for r in result.fault.itertuples()]
        lines.append("")
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
