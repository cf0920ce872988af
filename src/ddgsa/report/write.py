"""Write a study's tables, plots, provenance and summary into its output folder.

Each section of :data:`ddgsa.report.sections.SECTIONS` gives its tables (written first), then its charts
are drawn from the files just written -- by the functions that draw them on ``report.html`` too -- and
saved as PNGs with the few figures drawn from the result alone. Outputs are labelled with their declared
unit (``rms_deflection_hub [m]``); ``summary.md`` opens with what each output is, its mean and coefficient
of variation, then ranks parameters by S1 and ST with a sentence per output naming what dominates, and
lists every problem (refused or untrusted outputs, failure reasons, implausible values). Files an earlier
report wrote that this one does not are removed (:mod:`ddgsa.report.outdir`). PNGs carry no
software/date metadata. ``report.html`` (:mod:`ddgsa.report.html`) is written last, from the files
written here.
"""

from __future__ import annotations

import json
import os
import re
import sys
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path
from collections.abc import Callable, Collection
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from ddgsa.report.beyond import beyond_markdown
from ddgsa.execute.confirm import (CROSSCHECKS, SCREEN_RANK_TIME, VERDICTS, next_step, study_tolerance, verdict_counts,  # noqa: E402
                                   verdicts)
from ddgsa.gsa.base import sobol_rows  # noqa: E402
from ddgsa.gsa.result import CONSTANT_CV  # noqa: E402
from ddgsa.report.html import HTML_NAME, write_html  # noqa: E402
from ddgsa.loads.scene import AUTO_BEM_INCLINATION_DEG  # noqa: E402
from ddgsa.models.base import ModelOutput, declared  # noqa: E402
from ddgsa.report.outdir import COMPLETE_NAME, mark_complete, previous_files, remove_stale, unmark_complete  # noqa: E402
from ddgsa.report.sections import SECTIONS  # noqa: E402
from ddgsa.report.sections.base import SVG_ID_SLOT, Folder, svg_of  # noqa: E402
from ddgsa.report.sections.confirmation import escalation_lines, ranking_terms  # noqa: E402
from ddgsa.report.sections.provenance import model_words  # noqa: E402
from ddgsa.report.sections.signals import summary_lines as signal_summary_lines  # noqa: E402
from ddgsa.report.sections.sweep import sweep_keys, sweep_summary  # noqa: E402
from ddgsa.execute.kinds.common import StudyResult  # noqa: E402
from ddgsa.study.spec import scene_text  # noqa: E402

PNG_METADATA = {"Software": None}
"""No matplotlib version in the PNGs: a rerun on the same machine writes the same bytes."""


def output_info(result: StudyResult) -> dict[str, ModelOutput]:
    """The declared outputs of the study's model (undeclared names get no unit)."""
    return result.study.output_declarations()


def write_report(result: StudyResult, out: Path) -> list[Path]:
    """Write every file of the report and remove the earlier report's files it did not write;
    returns the paths written."""
    out.mkdir(parents=True, exist_ok=True)
    unmark_complete(out)
    before = previous_files(out)
    written: list[Path] = []
    info = output_info(result)
    for section in SECTIONS:
        for name, df in section.tables(result, info):
            df.to_csv(out / name, index=False, float_format="%.6g")
            written.append(out / name)
    study_file = result.study.path if not (out / "study.yaml").is_file() else None
    folder = Folder(out, study_file=study_file,      # the charts read the tables just written, as report.html does,
                    record=result.provenance)         # and the provenance written after them
    figures = [(make, out / name) for section in SECTIONS for name, make in section.figures(result)]
    charts = [(chart.draw, out / chart.png) for section in SECTIONS for chart in section.charts(folder) if chart.png]
    svgs = render_figures(figures + charts, svg=[path for _, path in charts])
    written += [path for _, path in figures + charts]
    path = out / "summary.md"
    path.write_text(summary_markdown(result, info))
    written.append(path)
    path = out / "provenance.json"
    names = sorted({p.name for p in written} | {path.name, HTML_NAME, COMPLETE_NAME})
    result.provenance["files"] = names
    path.write_text(json.dumps(result.provenance, indent=2, default=str))
    written.append(path)
    written.append(write_html(out, complete=True, svgs=svgs))
    remove_stale(out, before, names)
    mark_complete(out, names)                       # last: the folder's outputs are whole
    written.append(out / COMPLETE_NAME)
    return written


def _save_figure(fig: Any, path: Path, svg: bool = False) -> str | None:
    """Save ``fig`` as a PNG without metadata (:data:`PNG_METADATA`) and close it; ``svg``: return it as
    the page's inline SVG too (:func:`ddgsa.report.sections.base.svg_of`, ids in :data:`SVG_ID_SLOT`)."""
    try:
        fig.savefig(path, dpi=100, bbox_inches="tight", metadata=PNG_METADATA)
        return svg_of(fig, SVG_ID_SLOT) if svg else None
    finally:
        plt.close(fig)


FIGURE_PROCESSES_FROM = 3
"""Fewest deferred figures drawn in forked processes (fewer: in this one; a fork costs ~0.1 s)."""
_FIGURES: list[tuple[Callable[[], Any], Path, bool]] = []
"""The figures :func:`render_figures` hands to its forked processes (inherited, not pickled)."""


def render_figures(figures: list[tuple[Callable[[], Any], Path]], processes: int | None = None,
                   svg: Collection[Path] = ()) -> dict[str, str]:
    """Draw and save each ``(make, path)``: ``make()`` returns the figure; returns the inline SVG of those
    whose path is in ``svg``, by file name (the page's charts: drawn once for the PNG and the page). A
    report's figures are independent and drawing them is most of its time (``indirect_drive_gsa``'s seven:
    ~10 s of its 14 s), so on Linux, from :data:`FIGURE_PROCESSES_FROM` figures, they are drawn by
    ``processes`` (default: the CPUs this process may use) processes forked from this one, each figure by
    one of them, with the same matplotlib state, so the files are the same bytes as drawn here (tested)."""
    jobs = [(make, path, path in set(svg)) for make, path in figures]
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    processes = min(len(figures), processes or usable or 1)
    if processes < 2 or len(figures) < FIGURE_PROCESSES_FROM or not sys.platform.startswith("linux"):
        texts = [_save_figure(make(), path, want) for make, path, want in jobs]
    else:
        _FIGURES[:] = jobs
        try:
            with ProcessPoolExecutor(processes, mp_context=get_context("fork")) as pool:
                texts = [done.result() for done in [pool.submit(_render_one, i) for i in range(len(jobs))]]
        finally:                                    # a failure in a process raises at its result()
            _FIGURES.clear()
    return {path.name: text for (_, path, _), text in zip(jobs, texts) if text is not None}


def _render_one(i: int) -> str | None:
    """Draw and save the ``i``-th figure of :data:`_FIGURES` (in a forked process)."""
    make, path, svg = _FIGURES[i]
    return _save_figure(make(), path, svg)


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
    """What each output is, its unit, and how much it varies (mean, CV) per scene; a study without moments
    (a sweep: no distributions to draw from) has no such columns."""
    mom = result.moments if result.moments is not None else pd.DataFrame(columns=["scene", "output"])
    if not len(mom):
        return (["## Outputs", "", "| output | unit | what it is |", "|---|---|---|"]
                + [f"| `{name}` | {o.unit or '?'} | {o.description} |" for name, o in info.items()] + [""])
    lines = ["## Outputs", "", "| output | unit | what it is | scene | mean | CV | from |", "|---|---|---|---|---|---|---|"]
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
    ``confirmation.csv``), the runs spent and, with ``confirm:``, what its escalation spent and how it ended
    (:func:`ddgsa.report.sections.confirmation.escalation_lines`)."""
    table = verdicts(result)
    n_runs = result.provenance.get("evaluations", {}).get("total", len(result.evaluations))
    parts, done = verdict_counts(table, VERDICTS[:4])
    flat = table[table["verdict"] == "nothing to rank"]
    lines = [f"Confirmed: {done} of {len(table)} (scene, output) pairs" + (f" ({', '.join(parts)})" if parts else "")
             + f" at a cost of {n_runs} model runs"
             + (" (unconfirmed ones: see Problems)." if (table["verdict"] == "unconfirmed").any() else "."), ""]
    screened = table[table["verdict"] == "screened"]
    if len(screened):
        lines += ["Screened (only a screening method ran: its tests say which parameters the output depends on, "
                  f"a test's answer, not a ranking by share of the variance; `--confirm-time '{SCREEN_RANK_TIME}'` ranks them): "
                  + "; ".join(f"`{r.output}` in scene {r.scene}: {r.ranking}" for r in screened.itertuples()) + ".",
                  ""]
    spent = escalation_lines(result.provenance.get("confirm") or [], max(1, int(result.study.spec.scenes.realisations)))
    lines += spent + ([""] if spent else [])
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
             "They check the requested methods and are left out of the rankings above: `pooled_pce` is a sparse "
             "PCE on every point of a scene, `given_data_s1` first-order indices from the drawn points (never "
             "trusted: it has no ST). Like any method, one whose rows of an output are all trusted or rank-confirmed "
             "confirms that (scene, output) pair: `confirmation.csv` then names it in `method`.", "", "| scene | output | method | trusted rows | largest S1 (parameter) |",
             "|---|---|---|---|---|"]
    for (scene, out, meth), g in cross.groupby(["scene", "output", "method"], sort=False):
        top = g.loc[g["S1"].astype(float).idxmax()] if g["S1"].notna().any() else None
        big = f"{top['S1']:.2f} ({top['parameter']})" if top is not None else "-"
        lines.append(f"| {scene} | `{out}` | {meth} | {int(g['trusted'].astype(bool).sum())} of {len(g)} | {big} |")
    return lines + [""]


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
                  f"tie: their ST difference within the tie margin). {ranking_terms(result.study.spec.ranking.pair)} "
                  "In the ranking `*` marks "
                  "an untrusted value whose place is confirmed, `?` one that is neither. A method's runs (indices.csv "
                  "`n_evals`) count its whole design, any check sample of its own included; the evaluation count "
                  "above counts each distinct point once, as methods share equal points.", ""]
        if ranked:
            lines += _confirmed_section(result)
        elif len(verdicts(result)):                          # screened pairs only (HSIC)
            lines += ["## Verdicts", ""] + _confirmed_section(result)
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
        lines += _sweep_lines(result, info)
    return "\n".join(lines)


def _sweep_lines(result: StudyResult, info: dict[str, ModelOutput]) -> list[str]:
    """The summary's table of a sweep's means, each column with its unit (SI, or the unit the study gave an
    output); headed apart from the page's own "Sweep" section."""
    lines = ["## Sweep means (per scene and grid point)", "",
             "See `sweep_summary.csv` and `sweep_*.png` (means over realisations, +- one std).", ""]
    grid = list(result.study.spec.grid)
    summary = sweep_summary(result.sweep, result.study.outputs, grid)
    if len(summary) <= 40:
        units = {**result.study.make_model().units(), **{o: d.unit for o, d in info.items()}}
        keys = [k for k in sweep_keys(summary, grid) if k == "variant" or k in grid or summary[k].nunique() > 1]
        cols = keys + [f"{o}_mean" for o in result.study.outputs]
        head = [c if c in ("variant", "scene") else
                f"{c} [{units.get(c[:-5] if c.endswith('_mean') and c not in keys else c) or '?'}]" for c in cols]
        lines += ["| " + " | ".join(head) + " |", "|" + "---|" * len(cols)]
        lines += ["| " + " | ".join(f"{v:.6g}" if isinstance(v, float) else str(v) for v in row) + " |"
                  for row in summary[cols].itertuples(index=False)]
        lines.append("")
    return lines


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
