"""``report.html``: one self-contained page per results folder, built from the files stored there.

The page is made from what a report folder holds (``summary.md``, ``indices.csv``,
``diagnostics.csv``, ``fault_*.csv``, ``sweep_summary.csv``, ``campbell.csv``,
``accuracy_cost.csv``, ``provenance.json``, the PNGs), so it can be rebuilt for any folder --
a fresh run (:func:`ddgsa.report.write_report` calls :func:`write_html` last) or a committed one
(``ddgsa html DIR...``) -- without the evaluation store.

What it holds: the summary; the problems with what would fix each; sortable, filterable tables
(untrusted rows marked); and charts drawn as inline SVG from the tables (indices by scene with
their error bars, ST heatmaps, S1 against ST, POD curves with their intervals, the fault's index
shifts, sweeps, Campbell diagrams, index error against cost), units on every axis. Figures the
tables cannot redraw (order maps, spectra, histograms) are inlined as palette PNGs. No network, no
CDN: the stylesheet and a small script (sorting, filtering, legend toggles) are inlined, and the
page reads fully without JavaScript (hover tooltips are SVG ``<title>`` elements).
"""

from __future__ import annotations

import base64
import io
import json
import os
import re
from collections.abc import Sequence
from html import escape
from importlib.resources import files
from pathlib import Path
from typing import Any

import markdown
import numpy as np
import pandas as pd
from PIL import Image
from ruamel.yaml import YAML

from ddgsa.errors import DdgsaError, OutputFolderError
from ddgsa.gsa.result import ROW_COLUMNS
from ddgsa.models import get as get_model
from ddgsa.outdir import incompleteness
from ddgsa.signal_report import SIGNAL_TABLES, convergence_section, signals_section
from ddgsa.svgplot import Bars, Guide, Heat, Line, bar_chart, heatmap, num, xy_chart

HTML_NAME = "report.html"
TABLE_ROWS = 400
"""Tables longer than this show their first rows and name the CSV file that holds all of them."""
DIAGNOSTIC_ROWS = 60
"""Diagnostics are many and alike (one per untrusted row): the page shows the first ones; the
problems section counts them all."""
BAR_PARAMETERS = 10
"""Bar charts show the parameters of largest ST; the heatmap and the table show all."""
RAW_TABLES = ("evaluations.csv", "sweep.csv")
"""Per-evaluation tables: named with their size, not copied into the page."""
REDRAWN = re.compile(r"^(bars_scene\d+|heatmap_ST_\w+|sweep_\w+|fault_detectability_scene\d+|"
                     r"fault_indices_scene\d+|campbell|accuracy_\w+)\.png$")
"""PNGs the page redraws from the tables as SVG (not inlined a second time)."""
PNG_WIDTH = 800
"""Inlined PNGs wider than this are scaled down to it [px]."""
PNG_COLORS = 128
"""Palette size of the inlined PNGs (line plots and colour maps read the same with it)."""

FIELD_UNITS = {"wind_speed": "m/s", "turbulence_intensity": "-", "shear_exponent": "-", "inclination_deg": "deg",
               "speed_rpm": "rpm", "duration": "s", "sample_rate": "Hz", "settle": "s", "ramp_time": "s",
               "speed_rad_s": "rad/s", "frequency_hz": "Hz", "n_evals": "runs"}
"""Units of scene fields and of the columns the charts use as axes (model parameters and outputs get
theirs from the model's declarations)."""

REMEDIES = {
    "mdrm_index_error": "M-DRM's product surrogate misses part of the output (interactions, additive "
                        "structure): add a cross-check (`pce` or `saltelli`) or use `method: auto` with a "
                        "`budget`, which escalates until the rows are trusted.",
    "mdrm_unchecked": "give M-DRM a check sample (`check: 32`); without one its error has no bound.",
    "mdrm_cut_value": "the output is zero or not finite at the cut point: use `pce`, `saltelli` or `auto`.",
    "mdrm_sign_change": "the output changes sign over the nodes, which M-DRM cannot represent: use `pce`, "
                        "`saltelli` or `auto`.",
    "mdrm_rho_sign": "a cut function's mean has the other sign: use `pce`, `saltelli` or `auto`.",
    "mdrm_unresolved": "a cut function is not smooth (kinks, steps): more Gauss `points` or a sampling "
                       "method (`saltelli`).",
    "mdrm_quadrature_coverage": "the Gauss nodes miss the input's tails: more `points`.",
    "salib_index_error": "raise `n` (the error falls like 1/sqrt(n): four times n halves it).",
    "negative_index": "raise `n`: an index below zero by more than its error estimate.",
    "heavy_tail": "a few rare runs carry the total index, which no sample's spread bounds: analyse a transform "
                  "of the output (e.g. its logarithm) or use `pce`.",
    "fast_unverified": "FAST and RBD-FAST are cross-checks, never trusted: trust comes from M-DRM, PCE or Saltelli.",
    "pce_index_error": "raise the `order` or the points `n`, or `fit: sparse`.",
    "pce_underdetermined": "fewer points than terms: raise `n` or lower the `order`.",
    "auto_budget_exhausted": "raise `budget`: no stage trusted the output within it.",
    "nonfinite_values": "evaluations failed: see the failure reasons, then narrow the parameter ranges or "
                        "refine the model's step.",
    "zero_variance": "the output is constant over the sample: nothing to rank.",
    "mdrm_zero_variance": "the output is constant over the nodes: nothing to rank.",
}
"""What would fix each untrusting diagnostic (README's table says when each fires)."""


def write_html(folder: Path, complete: bool | None = None) -> Path:
    """Write ``folder/report.html`` from the files in ``folder`` (whole or not at all: written
    beside and renamed); returns its path. ``complete``: see :func:`render`."""
    path = Path(folder) / HTML_NAME
    tmp = path.with_name(f".{HTML_NAME}.{os.getpid()}.tmp")
    tmp.write_text(render(Path(folder), complete), encoding="utf-8")
    os.replace(tmp, path)
    return path


def render(folder: Path, complete: bool | None = None) -> str:
    """The report page of a results folder, as HTML text. A study's folder whose outputs are not
    complete (:func:`ddgsa.outdir.incompleteness`: its run was killed, or a file changed since)
    gets a banner saying so at the top; ``complete=True`` (the report being written) skips the check."""
    if not folder.is_dir():
        raise OutputFolderError(f"{folder}: not a folder (ddgsa html takes results folders, e.g. results/quickstart)")
    prov = read_json(folder / "provenance.json")
    units = _units(folder, prov)
    title = str(prov.get("study") or folder.resolve().name)
    sections: list[tuple[str, str, str]] = []       # (anchor, heading, html)

    def add(anchor: str, heading: str, body: str) -> None:
        if body:
            sections.append((anchor, heading, body))

    add("summary", "Summary", _summary(folder))
    add("problems", "Problems and what would fix them", _problems(folder))
    add("confirmation", "Verdicts", _confirmation(folder))
    add("indices", "Sensitivity indices", _indices(folder, units))
    add("fault", "Fault detectability", _fault(folder, units))
    add("sweep", "Sweep", _sweep(folder, units))
    add("campbell", "Campbell diagram", _campbell(folder))
    add("convergence", "Index error against cost", _convergence(folder))
    add("signals", "Indices of signals", signals_section(folder, _figure, _table))
    add("sample_size", "Indices against sample size", convergence_section(folder, _figure, _table))
    add("tables", "Other tables", _other_tables(folder))
    add("figures", "Figures", _figures(folder))
    add("provenance", "Provenance", _provenance(prov))
    if not sections:
        raise OutputFolderError(f"{folder}: not a results folder (no summary, tables, figures or provenance to "
                                f"report; ddgsa html takes the folders ddgsa run, modes and bench write)")
    missing = None if complete else incompleteness(folder, ignore=(HTML_NAME,))
    banner = (f'<p class="incomplete"><b>Incomplete outputs:</b> {escape(missing)}; what follows may be partial or '
              "from an earlier run. Rerun <code>ddgsa run</code> on the same study to finish it (stored evaluations "
              "are reused).</p>") if missing else ""
    nav = " · ".join(f'<a href="#{a}">{escape(h)}</a>' for a, h, _ in sections)
    body = "".join(f'<section id="{a}"><h2 class="section">{escape(h)}</h2>{b}</section>' for a, h, b in sections)
    asset = files("ddgsa") / "data"
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
            f"<title>{escape(title)} - ddgsa report</title><style>{(asset / 'report.css').read_text()}</style>"
            f"</head><body><header>{banner}<p class=\"kicker\">ddgsa report</p><h1>{escape(title)}</h1>"
            f"<nav>{nav}</nav></header><main>{body}</main>"
            f"<script>{(asset / 'report.js').read_text()}</script></body></html>\n")


# --- reading the folder -------------------------------------------------------------------------------------


def read_json(path: Path) -> dict[str, Any]:
    """The JSON file at ``path`` ({} where there is none); :class:`OutputFolderError` where it is not JSON."""
    if not path.is_file():
        return {}
    try:
        return json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise OutputFolderError(f"{path}: not a JSON file ddgsa wrote ({exc}); rerun the study or "
                                f"`ddgsa report` its folder to rewrite it") from None


def _csv(folder: Path, name: str) -> pd.DataFrame | None:
    path = folder / name
    return pd.read_csv(path) if path.is_file() and path.stat().st_size else None


def _study_yaml(folder: Path) -> dict[str, Any]:
    path = folder / "study.yaml"
    data = YAML(typ="safe").load(path.read_text()) if path.is_file() else None
    return data if isinstance(data, dict) else {}


def _units(folder: Path, prov: dict[str, Any]) -> dict[str, str]:
    """Units by column name: scene fields, the model's parameters and outputs (when the model of the
    provenance is registered), then the units the folder's tables state."""
    units = dict(FIELD_UNITS)
    model = prov.get("model") or {}
    if model.get("name"):
        try:
            m = get_model(model["name"], fidelity=model.get("fidelity"), **(model.get("options") or {}))
        except (DdgsaError, TypeError):
            m = None
        if m is not None:
            units.update({r.name: r.unit for r in m.parameter_table().itertuples()})
            units.update({r.name: r.unit for r in m.output_table().itertuples()})
    for name, spec in (_study_yaml(folder).get("parameters") or {}).items():
        if isinstance(spec, dict) and spec.get("unit"):
            units[name] = str(spec["unit"])
    for table, col, unit in (("indices.csv", "output", "output_unit"), ("output_moments.csv", "output", "unit")):
        df = _csv(folder, table)
        if df is not None and unit in df:
            units.update({o: u for o, u in zip(df[col], df[unit]) if isinstance(u, str)})
    return units


def _label(name: str, units: dict[str, str]) -> str:
    """``name [unit]``; ``[?]`` where no unit is known."""
    return f"{name} [{units.get(name) or '?'}]"


# --- sections ---------------------------------------------------------------------------------------------------


def _markdown(text: str) -> str:
    out = markdown.markdown(text, extensions=["tables"])
    return out.replace("<table>", '<div class="scroll"><table class="sortable">').replace("</table>", "</table></div>")


def _summary(folder: Path) -> str:
    path = folder / "summary.md"
    return f'<div class="md">{_markdown(path.read_text())}</div>' if path.is_file() else ""


def _problems(folder: Path) -> str:
    """Each untrusting diagnostic with where it fired and its remedy; failed evaluations."""
    diag = _csv(folder, "diagnostics.csv")
    prov = read_json(folder / "provenance.json")
    items = []
    if diag is not None and len(diag):
        bad = diag[diag["severity"] == "untrusted"]
        for name, g in bad.groupby("name", sort=False):
            outs = sorted({str(o) for o in g["output"].dropna()})
            where = f" on {', '.join(f'<code>{escape(o)}</code>' for o in outs[:8])}" + \
                (f" and {len(outs) - 8} more" if len(outs) > 8 else "") if outs else ""
            fix = REMEDIES.get(str(name), "see README, \"When M-DRM is not to be trusted\".")
            items.append(f"<li><code>{escape(str(name))}</code> ({', '.join(sorted(set(g['method'].astype(str))))}, "
                         f"{len(g)} rows{where}). <b>Fix:</b> {_inline_code(fix)}</li>")
    failures = prov.get("failures") or []
    if failures:
        items.append(f"<li>{len(failures)} evaluations failed (their indices are refused, never imputed). "
                     f"<b>Fix:</b> {_inline_code(REMEDIES['nonfinite_values'])}</li>")
    if not items:
        return "<p>None: every method's rows are trusted and no evaluation failed.</p>" if diag is not None else ""
    return f"<ul>{''.join(items)}</ul>"


def _inline_code(text: str) -> str:
    return re.sub(r"`([^`]+)`", r"<code>\1</code>", escape(text))


def _figure(svg: str, caption: str, kind: str) -> str:
    return f'<figure class="plot" data-kind="{kind}">{svg}<figcaption>{escape(caption)}</figcaption></figure>'


def _confirmation(folder: Path) -> str:
    """The study's verdict per (scene, output), as ``confirmation.csv`` holds it (the one table the
    console, the exit code, the summary and the NetCDF export read too)."""
    table = _csv(folder, "confirmation.csv")
    if table is None or not len(table):
        return ""
    count = table["verdict"].value_counts()
    words = ", ".join(f"{int(n)} {v}" for v, n in count.items())
    shown = table.assign(trusted=table["verdict"] != "unconfirmed")
    return (f"<p>One verdict per (scene, output): {escape(words)}. <em>trusted</em>: every index within the "
            "tolerance; <em>rank-confirmed</em> / <em>confirmed tie</em>: the order by ST certain, ties within the "
            "tie margin; <em>nothing to rank</em>: the output spreads by no more than its resolution; "
            "<em>unconfirmed</em> rows are shaded, with the cheapest next step and its cost.</p>"
            + _table(shown.drop(columns=["trusted"]).assign(trusted=shown["trusted"]), "confirmation",
                     "confirmation.csv"))


def _indices(folder: Path, units: dict[str, str]) -> str:
    idx = _csv(folder, "indices.csv")
    if idx is None or not len(idx):
        return ""
    idx["trusted"] = idx["trusted"].astype(str).str.lower().eq("true")
    meta = ROW_COLUMNS
    fields = [c for c in idx.columns if c not in meta]
    parts = ['<p>Bars: S1 and ST of each method, whiskers: each method\'s error estimate '
             '(M-DRM, PCE: a bound; SALib: bootstrap half-width). Pale, dashed bars and open markers are '
             'untrusted rows. Click a legend entry to hide a series; hover a mark for its values.</p>']
    conf = _csv(folder, "confirmation.csv")
    verdict = {} if conf is None else {(int(r.scene), str(r.output)): r for r in conf.fillna("").itertuples()}
    for scene, gs in idx.groupby("scene", sort=True):
        label = _scene_label(gs.iloc[0], fields)
        for out, g in gs.groupby("output", sort=False):
            v = verdict.get((int(scene), str(out)))
            said = "" if v is None else f"; verdict {v.verdict} ({v.method})" + (
                f", confirmed ranking {v.ranking}" if v.ranking else "")
            top = g.groupby("parameter", sort=False)["ST"].max().sort_values(ascending=False, na_position="last")
            params = list(top.index[:BAR_PARAMETERS])
            more = f"; the {len(top) - len(params)} others in the heatmap and table" if len(top) > len(params) else ""
            series = []
            for meth, gm in g.groupby("method", sort=False):
                gm = gm.set_index("parameter").reindex(params)
                faded = ~gm["trusted"].fillna(False).to_numpy(bool)
                for q in ("S1", "ST"):
                    series.append(Bars(f"{q} {meth}", gm[q].to_numpy(float), gm[f"{q}_conf"].to_numpy(float), faded))
            parts.append(_figure(bar_chart(params, series, "Sobol index [-]", f"{out} [{units.get(out) or '?'}]",
                                           xlim=(-0.05, 1.05)),
                                 f"scene {scene} ({label}): indices of {out}"
                                 + (f", the {len(params)} parameters of largest ST{more}" if more else "") + said,
                                 "bars"))
    outputs = list(dict.fromkeys(idx["output"]))
    params = list(dict.fromkeys(idx["parameter"]))
    if len(outputs) > 1 or idx["scene"].nunique() > 1:
        for (meth, scene), g in idx.groupby(["method", "scene"], sort=False):
            st = g.pivot_table(index="output", columns="parameter", values="ST", aggfunc="first", dropna=False)
            tr = g.pivot_table(index="output", columns="parameter", values="trusted", aggfunc="first", dropna=False)
            st, tr = st.reindex(index=outputs, columns=params), tr.reindex(index=outputs, columns=params)
            parts.append(_figure(heatmap(outputs, params, Heat(st.to_numpy(float), ~tr.fillna(False).to_numpy(bool)),
                                         "ST [-]", f"total indices, {meth}, scene {scene}"),
                                 f"ST of every output and parameter, {meth}, scene {scene} "
                                 f"({_scene_label(g.iloc[0], fields)}); red corner: untrusted", "heatmap"))
    lines = [Line(str(m), g["S1"].to_numpy(float), g["ST"].to_numpy(float), points=True,
                  hollow=~g["trusted"].to_numpy(bool),
                  notes=[f"{r.output}, {r.parameter}, scene {r.scene}" for r in g.itertuples()])
             for m, g in idx.groupby("method", sort=False)]
    parts.append(_figure(xy_chart(lines, "S1, first-order index [-]", "ST, total index [-]", "S1 against ST",
                                  guides=[Guide((0, 1), (0, 1), "ST = S1: no interactions")],
                                  xlim=(-0.05, 1.05), ylim=(-0.05, 1.05)),
                         "every row: ST above the line S1 = ST means interactions; open markers: untrusted", "scatter"))
    parts.append(_table(idx.drop(columns=["study"], errors="ignore"), "indices", "indices.csv"))
    for name in ("output_moments.csv", "accuracy.csv", "diagnostics.csv", "fidelity_selection.csv"):
        df = _csv(folder, name)
        if df is not None and len(df):
            rows = DIAGNOSTIC_ROWS if name == "diagnostics.csv" else TABLE_ROWS
            parts.append(f"<h3>{escape(name)}</h3>" + _table(df, name.removesuffix(".csv"), name, rows))
    return "".join(parts)


def _scene_label(row: pd.Series, fields: Sequence[str]) -> str:
    return ", ".join(f"{f}={row[f]:g}" if isinstance(row[f], (int, float, np.number)) else f"{f}={row[f]}"
                     for f in fields)


def _fault(folder: Path, units: dict[str, str]) -> str:
    ver = _csv(folder, "fault_verdicts.csv")
    if ver is None or not len(ver):
        return ""
    small = _csv(folder, "fault_smallest.csv")
    target = float(small["target"].iloc[0]) if small is not None and len(small) else float("nan")
    fault = str(ver["fault"].iloc[0])
    xlab = _label(fault, units)
    parts = []
    for scene, g in ver.groupby("scene", sort=True):
        lines = []
        for out, go in g.groupby("output", sort=False):
            go = go.sort_values("faulty")
            lines.append(Line(str(out), go["faulty"].to_numpy(float), go["pod"].to_numpy(float),
                              band=(go["pod_low"].to_numpy(float), go["pod_high"].to_numpy(float)),
                              notes=[f"AUC {num(a)} [{num(lo)}, {num(hi)}]" for a, lo, hi in
                                     zip(go["auc"], go["auc_low"], go["auc_high"])]))
        x = g["faulty"].to_numpy(float)
        guides = [Guide((float(x.min()), float(x.max())), (target, target), f"POD target {target:g}")] \
            if np.isfinite(target) else []
        fa = float(g["false_alarm"].iloc[0])
        parts.append(_figure(xy_chart(lines, xlab, "probability of detection [-]",
                                      f"detectability, scene {scene}", guides=guides, ylim=(-0.03, 1.03)),
                             f"POD at false-alarm rate {fa:g} against the fault level, shaded: its confidence "
                             f"interval; dashed: the target {target:g}", "pod"))
    fi = _csv(folder, "fault_indices.csv")
    if fi is not None and len(fi):
        for (scene, meth), g in fi.groupby(["scene", "method"], sort=False):
            g = g.assign(row=g["output"].astype(str) + ": " + g["parameter"].astype(str))
            rows = list(dict.fromkeys(g["row"]))
            levels = sorted(g["level"].unique())
            st = g.pivot_table(index="row", columns="level", values="ST", aggfunc="first", dropna=False)
            tr = g.assign(t=g["trusted"].astype(str).str.lower().eq("true")).pivot_table(
                index="row", columns="level", values="t", aggfunc="first", dropna=False)
            st, tr = st.reindex(index=rows, columns=levels), tr.reindex(index=rows, columns=levels)
            parts.append(_figure(heatmap(rows, [f"{fault}={v:g}" for v in levels],
                                         Heat(st.to_numpy(float), ~tr.fillna(False).to_numpy(bool)), "ST [-]",
                                         f"indices of the other parameters against the fault level ({meth})"),
                                 f"scene {scene}: ST of each (output, parameter) healthy and at each faulty level; "
                                 "red corner: untrusted", "heatmap"))
    for name in ("fault_verdicts.csv", "fault_smallest.csv", "fault_indices.csv"):
        df = _csv(folder, name)
        if df is not None and len(df):
            parts.append(f"<h3>{escape(name)}</h3>" + _table(df, name.removesuffix(".csv"), name))
    return "".join(parts)


def _sweep(folder: Path, units: dict[str, str]) -> str:
    """Each output's mean (band: +- one std over realisations) against the first grid parameter or
    the first varying numeric scene field; one line per value of the other varying keys."""
    sm = _csv(folder, "sweep_summary.csv")
    if sm is None or not len(sm):
        return ""
    outputs = [c[:-5] for c in sm.columns if c.endswith("_mean") and f"{c[:-5]}_std" in sm]
    keys = [c for c in sm.columns if not any(c == f"{o}{s}" for o in outputs for s in ("_mean", "_std", "_scaled"))
            and c != "scene"]
    grid = [g for g in (_study_yaml(folder).get("grid") or {}) if g in sm]
    varying = [k for k in keys if sm[k].nunique() > 1]
    numeric = [k for k in grid + varying if pd.api.types.is_numeric_dtype(sm[k]) and sm[k].nunique() > 1]
    parts = []
    if not numeric:      # nothing to sweep along: the cases as bars
        cases = [", ".join(f"{k}={v}" for k, v in zip(varying, row)) for row in sm[varying].itertuples(index=False)]
        for o in outputs:
            parts.append(_figure(bar_chart(cases, [Bars("mean", sm[f"{o}_mean"].to_numpy(float),
                                                        sm[f"{o}_std"].to_numpy(float))], _label(o, units), o),
                                 f"{o}: mean over realisations, whiskers: one standard deviation", "bars"))
    else:
        x = numeric[0]
        others = [k for k in varying if k != x]
        xv = sm[x].to_numpy(float)
        xlog = bool(xv.min() > 0 and xv.max() / xv.min() > 50)
        for o in outputs:
            lines = []
            for key, g in (sm.groupby(others, sort=False) if others else [((), sm)]):
                key = key if isinstance(key, tuple) else (key,)
                g = g.sort_values(x)
                m, s = g[f"{o}_mean"].to_numpy(float), g[f"{o}_std"].to_numpy(float)
                lines.append(Line(", ".join(f"{k}={v}" for k, v in zip(others, key)) or o, g[x].to_numpy(float), m,
                                  band=(m - s, m + s)))
            parts.append(_figure(xy_chart(lines, _label(x, units), _label(o, units), o, xlog=xlog),
                                 f"{o}: mean over realisations against {x}; shaded: +- one standard deviation",
                                 "sweep"))
    parts.append("<h3>sweep_summary.csv</h3>" + _table(sm, "sweep_summary", "sweep_summary.csv"))
    return "".join(parts)


def _campbell(folder: Path) -> str:
    cb = _csv(folder, "campbell.csv")
    if cb is None or not len(cb):
        return ""
    lines = [Line(str(lab), g["speed_rpm"].to_numpy(float), g["frequency_hz"].to_numpy(float),
                  notes=[f"whirl {w}, damping ratio {num(z)}" for w, z in zip(g["whirl"], g["damping_ratio"])])
             for lab, g in cb.groupby("label", sort=False)]
    rpm = cb["speed_rpm"].to_numpy(float)
    top = float(cb["frequency_hz"].max())
    guides = [Guide((0.0, float(rpm.max())), (0.0, float(rpm.max()) / 60.0), "1x: shaft speed")]
    return (_figure(xy_chart(lines, "shaft speed [rpm]", "natural frequency [Hz]", "Campbell diagram",
                             guides=guides, ylim=(0.0, top * 1.05), height=360),
                    "natural frequencies against shaft speed; dashed: the 1x excitation line", "campbell")
            + _table(cb, "campbell_table", "campbell.csv"))


def _convergence(folder: Path) -> str:
    """Median ST error against median cost per method and setting, one chart per reference function."""
    ac = _csv(folder, "accuracy_cost.csv")
    if ac is None or not len(ac):
        return ""
    parts = []
    color = {m: k for k, m in enumerate(sorted(ac["method"].unique()))}     # a method's colour on every chart
    for fn, g in ac.groupby("function", sort=False):
        med = g.groupby(["method", "options"], sort=False)[["n_evals", "err_ST"]].median().reset_index()
        lines = [Line(str(m), gm["n_evals"].to_numpy(float), np.maximum(gm["err_ST"].to_numpy(float), 1e-16),
                      notes=list(gm["options"].astype(str)), color=color[m])
                 for m, gm in med.sort_values(["method", "n_evals"]).groupby("method", sort=True)]
        parts.append(_figure(xy_chart(lines, "model runs [runs]", "median max |ST error| [-]", str(fn),
                                      xlog=True, ylog=True),
                             f"{fn}: median over seeds of the largest ST error against the runs spent", "convergence"))
    return "".join(parts)


_SHOWN = {"indices.csv", "confirmation.csv", "output_moments.csv", "accuracy.csv", "diagnostics.csv", "fidelity_selection.csv",
          "fault_verdicts.csv", "fault_smallest.csv", "fault_indices.csv", "sweep_summary.csv", "campbell.csv",
          *SIGNAL_TABLES}


def _other_tables(folder: Path) -> str:
    parts = []
    for path in sorted(folder.glob("*.csv")):
        if path.name in _SHOWN:
            continue
        if path.name in RAW_TABLES:
            n = sum(1 for _ in path.open()) - 1
            parts.append(f"<p><code>{escape(path.name)}</code>: {n} rows, one per evaluation "
                         "(not copied into this page).</p>")
            continue
        df = _csv(folder, path.name)
        if df is not None:
            parts.append(f"<h3>{escape(path.name)}</h3>" + _table(df, path.stem, path.name))
    return "".join(parts)


def _figures(folder: Path) -> str:
    """The folder's PNGs that the page does not redraw, re-encoded with a :data:`PNG_COLORS` palette."""
    parts = []
    for path in sorted(folder.glob("*.png")):
        if REDRAWN.match(path.name):
            continue
        with Image.open(path) as im:
            im = im.convert("RGB")
            if im.width > PNG_WIDTH:
                im = im.resize((PNG_WIDTH, round(im.height * PNG_WIDTH / im.width)), Image.Resampling.LANCZOS)
            buf = io.BytesIO()
            im.quantize(PNG_COLORS).save(buf, "PNG", optimize=True)
            w, h = im.size
        data = base64.b64encode(buf.getvalue()).decode()
        parts.append(f'<figure class="plot" data-kind="png"><img src="data:image/png;base64,{data}" width="{w}" '
                     f'height="{h}" alt="{escape(path.stem)}"><figcaption>{escape(path.name)}</figcaption></figure>')
    return "".join(parts)


def model_words(model: dict[str, Any]) -> str:
    """``fidelity`` and the study's model options (``linear; bending_rayleigh=printed``) of a
    provenance's ``model``: a reader sees which variant ran (seed 000's printed readings are
    options, not fidelities)."""
    options = model.get("options") or {}
    return "; ".join([str(model.get("fidelity", "?")), *(f"{k}={v}" for k, v in options.items())])


def _provenance(prov: dict[str, Any]) -> str:
    if not prov:
        return ""
    model, code, ev = prov.get("model") or {}, prov.get("code") or {}, prov.get("evaluations") or {}
    rows = [("study file", prov.get("study_file")), ("study sha256", prov.get("study_sha256")),
            ("created (UTC)", prov.get("created_utc")),
            ("code", f"ddgsa {code.get('ddgsa', '?')}, commit {str(code.get('commit', '?'))[:12]}"
                     + (" (modified)" if code.get("modified") else "")),
            ("model", f"{model.get('name', '?')} ({model_words(model)})" if model else None),
            ("evaluations", ", ".join(f"{k} {v}" for k, v in ev.items()) if ev else None),
            ("timings [s]", ", ".join(f"{k} {v}" for k, v in (prov.get("timings_s") or {}).items()) or None),
            ("versions", ", ".join(f"{k} {v}" for k, v in (prov.get("versions") or {}).items()) or None),
            ("seeds", json.dumps(prov.get("seeds")) if prov.get("seeds") else None)]
    items = "".join(f"<dt>{escape(k)}</dt><dd>{escape(str(v))}</dd>" for k, v in rows if v)
    return f"<dl>{items}</dl><p>Everything else: <code>provenance.json</code>.</p>"


# --- tables -----------------------------------------------------------------------------------------------------


def _cell(v: Any) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "yes" if v else "no"
    if isinstance(v, (float, np.floating)):
        return "" if np.isnan(v) else f"{v:.4g}"
    return escape(str(v))


def _table(df: pd.DataFrame, ident: str, source: str, rows: int = TABLE_ROWS) -> str:
    """A sortable table with a filter box (shown with JavaScript); rows whose ``trusted`` column is
    false get the class ``untrusted``."""
    ident = re.sub(r"[^A-Za-z0-9_-]", "_", ident)
    shown = df.head(rows)
    if "trusted" in shown:
        bad = ~shown["trusted"].astype(str).str.lower().eq("true").to_numpy()
    else:
        bad = np.zeros(len(shown), bool)
    head = "".join(f"<th>{escape(str(c))}</th>" for c in shown.columns)
    body = "".join(('<tr class="untrusted">' if b else "<tr>") + "".join(f"<td>{_cell(v)}</td>" for v in row)
                   + "</tr>" for row, b in zip(shown.itertuples(index=False), bad))
    more = f'<p class="note">First {rows} of {len(df)} rows; all of them: <code>{escape(source)}</code>.</p>' \
        if len(df) > rows else ""
    return (f'<input class="filter" type="search" placeholder="filter rows" aria-label="filter {escape(source)}" '
            f'data-table="t-{ident}"><div class="scroll"><table class="sortable data" id="t-{ident}">'
            f"<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table></div>{more}")
