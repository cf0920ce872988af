"""The report a decision is made from: counts that agree, failure reasons, S1 and ST, mean and CV,
units, no self-comparison, readable plots."""

from __future__ import annotations

import json
import re
from pathlib import Path

import matplotlib
import numpy as np
import pandas as pd
import pytest
from matplotlib.container import ErrorbarContainer

from ddgsa.cli import main
from ddgsa.models import get
from ddgsa.report.sections.indices import accuracy_table, plot_heatmap, plot_scene_bars
from ddgsa.report.write import sampling_markdown
from studytext import ishigami_study

matplotlib.use("Agg")


def pce_study(name: str, methods: str) -> str:
    """A one-scene Ishigami study with ``methods`` (a YAML list)."""
    return ishigami_study(name, f"methods: {methods}\n")


def _evaluation_line(summary: str) -> str:
    return re.search(r"^- evaluations: (.*)$", summary, re.M).group(1)  # type: ignore[union-attr]


def test_summary_mean_cv_ranking_and_sentence_against_closed_forms(write_study, tmp_path: Path, capsys) -> None:
    """y_positive = 12 + (8/11) Ishigami(a=7, b=0.1). Closed forms: E = 12 + 3.5 (8/11) = 14.545,
    Var[Ishigami] = a^2/8 + b pi^4/5 + b^2 pi^8/18 + 1/2 = 13.845, CV = sqrt(13.845)(8/11)/14.545
    = 0.186; ST = (0.558, 0.442, 0.244), S1 = (0.314, 0.442, 0). Sample moments of the 1024 PCE
    points: mean within 0.05, CV within 0.005."""
    out = tmp_path / "pce"
    study = write_study("pce", text=pce_study(name="pce", methods="[{method: pce, order: 10, n: 1024, seed: 0}]"))
    assert main(["run", str(study), "--out", str(out)]) == 0
    cli_line = capsys.readouterr().out
    summary = (out / "summary.md").read_text()
    assert _evaluation_line(summary) in cli_line                        # the same counts, word for word
    assert _evaluation_line(summary).startswith("1024 model evaluations (1024 run now, 0 from the store), 0 failed")
    mom = pd.read_csv(out / "output_moments.csv").iloc[0]
    var = 7 ** 2 / 8 + 0.1 * np.pi ** 4 / 5 + 0.01 * np.pi ** 8 / 18 + 0.5
    assert mom["mean"] == pytest.approx(12 + 3.5 * 8 / 11, abs=0.05)
    assert mom["cv"] == pytest.approx(np.sqrt(var) * 8 / 11 / (12 + 3.5 * 8 / 11), abs=0.005)
    assert mom["unit"] == "-" and mom["source"] == "pce sample (1024 points)"
    assert set(pd.read_csv(out / "indices.csv")["output_unit"]) == {"-"}
    assert "| `y_positive` | - | y + 12" in summary
    assert "`y_positive`: shared by `x1` (ST 0.56, S1 0.31), `x2` (ST 0.44, S1 0.44), `x3` (ST 0.24, S1 0.00), " \
           "by pce. ST - S1 shows interactions." in summary
    assert "| pce | ±0.02 | yes | yes | x1 0.56 (0.31), x2 0.44 (0.44), x3 0.24 (0.00) |" in summary
    prov = json.loads((out / "provenance.json").read_text())
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\+00:00", prov["created_utc"])
    assert prov["code"]["ddgsa"] and "commit" in prov["code"] and prov["study_file"] == "pce.yaml"


def test_counts_agree_in_a_fresh_folder_when_methods_share_points(write_study, tmp_path: Path, capsys) -> None:
    """M-DRM and auto's M-DRM stage ask for the same 48 points: counted once, none 'cached' in a
    fresh folder; a rerun runs nothing and says so in the same words as the summary."""
    study = write_study("both", text=pce_study(name="both", methods="[{method: mdrm}, {method: auto, budget: 200}]"))
    out = tmp_path / "both"
    main(["run", str(study), "--out", str(out), "--allow-untrusted"])
    first = json.loads((out / "provenance.json").read_text())["evaluations"]
    assert first["cached"] == 0 and first["evaluated"] == first["total"] > 48
    assert _evaluation_line((out / "summary.md").read_text()) in capsys.readouterr().out
    main(["run", str(study), "--out", str(out), "--allow-untrusted"])
    again = json.loads((out / "provenance.json").read_text())["evaluations"]
    assert again["evaluated"] == 0 and again["cached"] == again["total"] == first["total"]
    acc = pd.read_csv(out / "accuracy.csv")
    assert "auto" not in set(acc["crosscheck"]) or set(
        pd.read_csv(out / "indices.csv").query("method == 'auto'")["source"]) != {"mdrm"}


def test_summary_lists_failure_reasons(write_study, tmp_path: Path) -> None:
    out = tmp_path / "fail"
    assert main(["-q", "run", str(write_study("failing", options="{fail_above: 2.5}")), "--out", str(out)]) == 3
    summary = (out / "summary.md").read_text()
    prov = json.loads((out / "provenance.json").read_text())
    n = len(prov["failures"])
    assert n == prov["evaluations"]["failed"] > 0
    assert f"Failed evaluations ({n};" in summary and "RuntimeError: x1 = " in summary
    # reasons that differ only in the failing value are one line, saying how many it stands for
    reasons = [line for line in summary.splitlines() if line.startswith(f"- {n}x: ") or line.startswith("- 1x: ")]
    # and the way forward is the failures' cause, not a larger design
    assert "no design confirms indices over failed evaluations" in summary and "add `saltelli`" not in summary
    distinct = len({f["error"] for f in prov["failures"]})
    assert distinct > 1 and reasons == [f"- {n}x: {prov['failures'][0]['error']} (and {distinct - 1} alike, other numbers)"]
    assert f", {n} failed" in _evaluation_line(summary)


def _rows(methods: dict[str, float], trusted: bool = True, source: str | None = None) -> pd.DataFrame:
    rows = []
    for meth, conf in methods.items():
        for j, par in enumerate(["a", "b"]):
            rows.append({"scene": 0, "wind_speed": 11.0, "turbulence_intensity": 0.1, "inclination_deg": 0.0,
                         "shear_exponent": 0.2, "output": "y", "method": meth, "parameter": par,
                         "S1": 0.5 - 0.1 * j, "S1_conf": conf, "ST": 0.6 - 0.1 * j, "ST_conf": conf,
                         "trusted": trusted, "n_evals": 10, "source": source or meth})
    return pd.DataFrame(rows)


def test_accuracy_never_compares_mdrm_with_autos_own_mdrm_stage() -> None:
    idx = pd.concat([_rows({"mdrm": np.nan, "pce": np.nan}), _rows({"auto": np.nan}, source="mdrm")])
    assert set(accuracy_table(idx)["crosscheck"]) == {"pce"}
    idx = pd.concat([_rows({"mdrm": np.nan}), _rows({"auto": np.nan}, source="pce")])
    assert set(accuracy_table(idx)["crosscheck"]) == {"auto"}             # auto's PCE is independent


def test_bars_have_a_y_label_and_error_bars_only_where_there_is_an_interval() -> None:
    """Issue 48.6: one panel per output, the bars of the method the pair's verdict names (titled with
    it), every other requested method's ST a marker beside them; cross-checks left out."""
    info = {"y": get("analytic").output("y").unit}
    rows = pd.concat([_rows({"pce": np.nan, "saltelli": 0.05}), _rows({"given_data_s1": 0.1})])
    fig = plot_scene_bars(rows, info)
    assert len([ax for ax in fig.axes if ax.get_visible()]) == 1             # one output, one panel
    ax = fig.axes[0]
    assert ax.get_xlabel() == "Sobol index [-]"                              # horizontal bars: parameters down y
    assert not [c for c in ax.containers if isinstance(c, ErrorbarContainer)]   # pce: no interval
    assert ax.get_title() == "y [-]\npce"
    marks = [ln for ln in ax.get_lines() if ln.get_marker() not in (None, "None", "")]
    assert len(marks) == 1 and marks[0].get_xdata().tolist() == [0.6, 0.5]   # saltelli's ST; given_data_s1 not drawn
    legend = [t.get_text() for t in fig.legends[0].get_texts()]              # one legend, outside the panels
    assert legend == ["S1", "ST", "ST, saltelli"] and "untrusted" not in fig._suptitle.get_text()
    verdicts = pd.DataFrame({"scene": [0], "output": ["y"], "method": ["saltelli"], "verdict": ["rank-confirmed"]})
    ax = plot_scene_bars(rows, info, verdicts=verdicts).axes[0]
    assert len([c for c in ax.containers if isinstance(c, ErrorbarContainer)]) == 2    # S1 and ST of saltelli
    assert ax.get_title() == "y [-]\nsaltelli: rank-confirmed"
    rows = pd.concat([_rows({"pce": np.nan}), _rows({"mdrm": np.nan}, trusted=False)])
    mdrm = verdicts.assign(method="mdrm", verdict="unconfirmed")
    fig = plot_scene_bars(rows, info, verdicts=mdrm)
    assert [t.get_text() for t in fig.legends[0].get_texts()] == ["S1", "ST", "untrusted", "ST, pce"]


def test_heatmap_tick_labels_overlap_no_neighbouring_panel() -> None:
    """Four outputs x ten long parameter names x three scenes: every tick label's and title's
    bounding box (pixels, after drawing) is disjoint from every other panel's labels and image."""
    params = [f"shaft_bending_stiffness_{i}" for i in range(10)]
    outputs = ["rms_deflection_hub", "rms_deflection_gen", "damage_front", "damage_rear"]
    rows = pd.DataFrame([{"scene": s, "wind_speed": w, "output": o, "method": "mdrm", "parameter": p,
                          "ST": 0.1 * (i % 10)} for s, w in enumerate((6.0, 11.0, 18.0))
                         for o in outputs for i, p in enumerate(params)])
    model = get("direct_drive", fidelity="rigid")
    fig = plot_heatmap(rows, {o: model.output(o).unit for o in outputs})
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    panels = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"][:len(outputs)]
    boxes = []
    for k, ax in enumerate(panels):
        texts = [t for t in ax.get_xticklabels() + ax.get_yticklabels() + [ax.title] if t.get_visible() and t.get_text()]
        boxes.append(([t.get_window_extent(renderer) for t in texts], ax.get_window_extent(renderer)))
    assert len(boxes[0][0]) > len(boxes[1][0])                        # parameter names only on the first panel
    for i, (labels_i, _) in enumerate(boxes):
        for j, (labels_j, area_j) in enumerate(boxes):
            if i == j:
                continue
            for b in labels_i:
                assert not b.overlaps(area_j), f"a label of panel {i} lies over panel {j}"
                assert not any(b.overlaps(c) for c in labels_j), f"labels of panels {i} and {j} overlap"


def test_mdrm_surrogate_moments_are_exact_for_a_product() -> None:
    """f = (1 + x1)(2 + x2), x ~ U(0, 1)^2: E f = 1.5 x 2.5 = 3.75, E f^2 = (7/3)(19/3), so
    Var f = 133/9 - 3.75^2 = 0.71528; M-DRM's surrogate is exact for products (to 1e-12)."""
    from ddgsa.gsa.base import get_method
    from ddgsa.execute.kinds.gsa import moments
    from ddgsa.gsa.space import ParameterSpace

    space = ParameterSpace.from_dict({"x1": {"low": 0.0, "high": 1.0}, "x2": {"low": 0.0, "high": 1.0}})
    mdrm = get_method("mdrm")
    design = mdrm.design(space, points=4, check=0)
    y = ((1 + design.points[:, 0]) * (2 + design.points[:, 1]))[:, None]
    (got,) = moments(space, "mdrm", design, y, mdrm.analyze(space, design, y, outputs=["f"]), ["f"])  # type: ignore[misc]
    assert got["source"] == "M-DRM surrogate"
    assert got["mean"] == pytest.approx(3.75, abs=1e-12)
    assert got["std"] == pytest.approx(np.sqrt(133 / 9 - 3.75 ** 2), abs=1e-12)


def test_pngs_carry_no_software_metadata_and_repeat_byte_for_byte(tmp_path: Path) -> None:
    from ddgsa.report.write import PNG_METADATA

    blobs = []
    for k in range(2):
        fig = plot_scene_bars(_rows({"pce": np.nan}))
        fig.savefig(tmp_path / f"{k}.png", dpi=100, bbox_inches="tight", metadata=PNG_METADATA)
        blobs.append((tmp_path / f"{k}.png").read_bytes())
    assert blobs[0] == blobs[1] and b"matplotlib" not in blobs[0]


def test_heatmap_hatches_exactly_the_untrusted_cells() -> None:
    """A cell whose row is untrusted is hatched and the title says what hatching means; a map with
    every row trusted has no hatching and no such words."""
    rows = pd.DataFrame([{"scene": s, "wind_speed": w, "output": "rms_deflection_hub", "method": "mdrm",
                          "parameter": p, "ST": 0.3, "trusted": not (s == 1 and p == "b")}
                         for s, w in enumerate((6.0, 11.0)) for p in ("a", "b", "c")])
    fig = plot_heatmap(rows)
    patches = [p for ax in fig.axes for p in ax.patches if p.get_hatch()]
    assert len(patches) == 1 and patches[0].get_xy() == (0.5, 0.5)       # scene column 1, parameter row 1
    assert "hatched: untrusted" in fig._suptitle.get_text()
    fig = plot_heatmap(rows.assign(trusted=True))
    assert not [p for ax in fig.axes for p in ax.patches if p.get_hatch()]
    assert "hatched" not in fig._suptitle.get_text()


def test_a_constant_output_is_not_a_problem_but_an_untrusted_varying_one_is() -> None:
    """The direct drive's rear_Fa_mean is 0 at every point (the rear bearing carries no axial
    load), so M-DRM refuses its indices (0/0); that alone must not turn a run into exit 3."""
    from types import SimpleNamespace

    from ddgsa.report.write import problems

    idx = pd.DataFrame({"output": ["flat", "flat", "wavy", "wavy"], "scene": 0, "method": "mdrm",
                        "parameter": ["a", "b", "a", "b"], "trusted": False, "rank_confirmed": False,
                        "ST": [np.nan, np.nan, 0.7, 0.3]})
    diags = pd.DataFrame({"output": ["flat", "wavy"], "scene": 0, "severity": "untrusted",
                          "name": ["mdrm_zero_variance", "mdrm_index_error"]})
    mom = pd.DataFrame({"scene": [0, 0], "output": ["flat", "wavy"], "mean": [0.0, 1.0], "std": [0.0, 0.3]})
    study = SimpleNamespace(spec=SimpleNamespace(scenes=SimpleNamespace(realisations=2)))
    res = SimpleNamespace(indices=idx, diagnostics=diags, moments=mom, sweep=None, results=[], study=study,
                          evaluations=pd.DataFrame({"seconds": [0.5, 1.5]}))
    # ST 0.7 is 0.4 from 0.3 and 0.3 is 0.3 from zero: errors 3.3 sqrt(ST / N) <= 0.2 and 0.15 at
    # N = 191 and 145 -> 256; 256 x (2 + 2) points x 2 realisations = 2 048 runs at 1 s each
    assert problems(res) == ["output 'wavy': no method's indices are confirmed (trusted or rank-confirmed) in "
                             "scene 0 (mdrm_index_error); to confirm it add `saltelli` with n: 256 (2 048 runs, "
                             "~34 min of model time at 1 s per run measured here), or `confirm: {budget: 1024}` "
                             "(points per scene; it reuses every run, tries cheaper PCE points first and stops "
                             "when confirmed)"]
    res.moments = mom.assign(std=[1e-3, 0.3])                            # varies a little: counted
    assert len(problems(res)) == 2
    # the test rig's steady motor current: 6.90963 A, spread 9.1e-10 A (CV 1.3e-10, solver noise) is
    # constant; its coast-down current (CV 8.5e-7) varies, however little, and is counted
    res.moments = mom.assign(mean=[6.90963, 1.0], std=[9.12e-10, 0.3])
    assert len(problems(res)) == 1
    res.moments = mom.assign(mean=[0.142622, 1.0], std=[1.2157e-7, 0.3])
    assert len(problems(res)) == 2


def test_a_constant_outputs_sentence_says_there_is_nothing_to_rank() -> None:
    """The ranking sentence of an output constant to its numerical noise says so (it named no cause
    and sent the user to a Saltelli design of 61 440 runs)."""
    from ddgsa.report.write import _dominance

    g = pd.DataFrame({"method": "mdrm", "parameter": ["a", "b"], "trusted": False, "rank_confirmed": False,
                      "ST": [np.nan, np.nan], "S1": [np.nan, np.nan]})
    from types import SimpleNamespace

    flat = SimpleNamespace(verdict="nothing to rank", std=9.12e-10, resolution=0.02, ranking="")
    text = _dominance(g, "rms_motor_current", {"mean": 6.90963, "std": 9.12e-10, "cv": 1.32e-10}, flat)
    assert "nothing to rank" in text and "9.12e-10" in text and "0.02" in text
    open_ = SimpleNamespace(verdict="unconfirmed", std=1.2157e-7, resolution=0.0, ranking="")
    assert "do not rank" in _dominance(g, "rms_motor_current", {"mean": 0.142622, "std": 1.2157e-7, "cv": 8.5e-7},
                                       open_)


def test_an_output_within_its_declared_resolution_has_nothing_to_rank() -> None:
    """Issue 51: the test rig's steady peak motor torque spreads by 3e-6 N m against its torque
    transducer's noise (0.05 N m a sample; a record's peak moves by 0.33 of that, the model's
    declaration): verdict "nothing to rank", no problem
    (exit 0), no advice to spend runs; the same spread on an output declared without a resolution
    (a deterministic one, numerical floor 1e-9 of the mean) is unconfirmed and advised a design."""
    from types import SimpleNamespace

    from ddgsa.execute.confirm import confirmation_table
    from ddgsa.models import get
    from ddgsa.report.write import problems

    rig = get("hss_rig")
    # Gumbel: the largest of n = 2 000 normal samples has standard deviation pi / sqrt(12 ln n) = 0.329
    assert rig.output("peak_motor_torque").resolution == pytest.approx(0.05 * np.pi / np.sqrt(12 * np.log(2000)))
    assert rig.output("rms_motor_current").resolution == pytest.approx(0.02 * np.sqrt(2 / 2000))
    outs = ["peak_motor_torque", "mean_speed_rpm"]
    idx = pd.DataFrame({"output": np.repeat(outs, 2), "scene": 0, "method": "mdrm", "parameter": ["a", "b"] * 2,
                        "trusted": False, "rank_confirmed": False, "ST": [0.6, 0.5] * 2, "n_evals": 37})
    diags = pd.DataFrame({"output": outs, "scene": 0, "severity": "untrusted", "name": "mdrm_index_error"})
    mom = pd.DataFrame({"scene": [0, 0], "output": outs, "mean": [1.2e-5, 1.2e-5], "std": [3e-6, 3e-6]})
    study = SimpleNamespace(spec=SimpleNamespace(scenes=SimpleNamespace(realisations=1)), make_model=lambda: rig,
                            output_declarations=lambda: {o: rig.output(o) for o in outs}, analysed_outputs=outs)
    res = SimpleNamespace(indices=idx, diagnostics=diags, moments=mom, sweep=None, results=[], study=study,
                          evaluations=pd.DataFrame({"seconds": [0.1]}))
    table = confirmation_table(res)
    assert table.set_index("output")["verdict"].to_dict() == {"peak_motor_torque": "nothing to rank",
                                                              "mean_speed_rpm": "unconfirmed"}
    assert table.set_index("output").loc["peak_motor_torque", "next_runs"] == 0
    bad = problems(res)
    assert len(bad) == 1 and bad[0].startswith("output 'mean_speed_rpm'")


def test_sampling_table_has_a_variant_column_only_when_the_study_has_variants() -> None:
    """Newcomer trial: a study without variants showed an empty ``variant`` column."""
    row = {"interval": "scene dt", "interval_s": 0.05, "mode": "drivetrain", "frequency_hz": 8.0,
           "samples_per_period": 2.5, "verdict": "warn", "consequence": "aliased"}
    ok = {**row, "verdict": "ok"}
    plain = sampling_markdown([row, ok])
    assert plain[2] == "| interval | [s] | mode | [Hz] | samples/period | verdict | consequence |"
    assert plain[4] == "| scene dt | 0.05 | drivetrain | 8 | 2.5 | warn | aliased |"
    assert len(plain) == 6  # the ok row is left out
    varied = sampling_markdown([{"variant": "stiff", **row}])
    assert varied[2].startswith("| variant | interval |")
    assert varied[4].startswith("| stiff | scene dt |")
    assert sampling_markdown([ok]) == []


def _fails() -> None:
    raise ValueError("a figure that cannot be drawn")


def test_figures_drawn_in_forked_processes_are_the_bytes_drawn_in_one(tmp_path: Path) -> None:
    """render_figures draws a report's figures in forked processes (issue 27): the same files as drawn
    here, every one written; a figure that fails in a process raises here."""
    import functools
    import sys

    from ddgsa.report.write import render_figures

    if not sys.platform.startswith("linux"):
        pytest.skip("figures are drawn in forked processes on Linux only")
    rows = [_rows({"pce": 0.3}), _rows({"pce": np.nan}), _rows({"mdrm": 0.2, "pce": 0.25}, trusted=False)]
    jobs = {d: [(functools.partial(plot_scene_bars, r), tmp_path / d / f"{i}.png") for i, r in enumerate(rows)]
            for d in ("one", "forked")}
    for d in jobs:
        (tmp_path / d).mkdir()
    render_figures(jobs["one"], processes=1)
    render_figures(jobs["forked"], processes=2)
    for (_, one), (_, forked) in zip(jobs["one"], jobs["forked"]):
        assert one.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and one.read_bytes() == forked.read_bytes()
    with pytest.raises(ValueError, match="cannot be drawn"):
        render_figures(jobs["one"][:2] + [(_fails, tmp_path / "x.png")], processes=2)


def test_the_rigs_peak_resolution_is_the_noise_peaks_own_spread() -> None:
    """The declared resolution of a peak (Gumbel's limit, 0.329 sd for 2 000 samples) against the spread
    of the largest of 2 000 simulated noise samples over 4 000 records (0.335 sd): within 5 %, and not
    above it, so "nothing to rank" is never claimed for a spread a record's noise would not hide."""
    from ddgsa.models import get

    sd = 0.05                                                   # the torque transducer's noise [N m]
    peaks = sd * np.random.default_rng(0).standard_normal((4000, 2000)).max(axis=1)
    declared = get("hss_rig").output("peak_motor_torque").resolution
    assert declared == pytest.approx(peaks.std(), rel=0.05) and declared <= peaks.std()


def test_the_page_a_run_writes_is_the_page_ddgsa_html_rebuilds_from_the_files(write_study, tmp_path: Path) -> None:
    """A run draws each chart once, saving its PNG and the page's SVG from one figure; ``ddgsa html`` draws
    it again from the folder's CSVs alone: the same page, byte for byte (so a committed folder's page is
    the run's), with an inline SVG for every PNG a chart of the run wrote."""
    out = tmp_path / "two"
    study = write_study("two", text=pce_study(name="two", methods="[{method: mdrm, points: 4, check: 8}, "
                                                                "{method: pce, order: 4, n: 64, seed: 0}]"))
    assert main(["-q", "run", str(study), "--out", str(out), "--allow-untrusted"]) == 0
    page = (out / "report.html").read_text()
    assert main(["-q", "html", str(out)]) == 0
    assert (out / "report.html").read_text() == page
    pngs = sorted(p.name for p in out.glob("*.png"))
    assert pngs == ["bars_scene0.png", "mdrm_vs_crosscheck.png"]
    assert page.count("<svg ") >= len(pngs) + 1 and "data:image/png" not in page       # + S1 against ST


SWEEP = """name: sw
kind: sweep
model: {name: analytic}
grid: {x1: [0.5, 1.0, 2.0]}
scenes: {wind_speed: {value: [18, 36], unit: km/h}}
outputs: [y]
"""


def test_a_fresh_sweeps_report_says_units_and_heads_its_table_apart(write_study, tmp_path: Path) -> None:
    """Newcomer trial (nc_sweep): in a fresh folder the charts had no units (drawn before provenance.json named
    the model), the legend said 'wind_speed=5' for 18 km/h, the summary's sweep table had no units and its
    Outputs table only '-', and report.html had two 'Sweep' headings."""
    out = tmp_path / "out"
    assert main(["-q", "run", str(write_study("sw", text=SWEEP)), "--out", str(out)]) == 0
    summary = (out / "summary.md").read_text()
    outputs = summary.split("## Outputs")[1].split("##")[0]
    assert "| `y` | - |" in outputs and "| - | - |" not in outputs and "mean" not in outputs
    assert "| scene | wind_speed [m/s] | x1 [-] | y_mean [-] |" in summary
    assert "| 0 | 5 | 0.5 |" in summary and "| 1 | 10 | 2 |" in summary          # 18 and 36 km/h in SI
    page = (out / "report.html").read_text()
    headings = re.findall(r"<h[23][^>]*>([^<]*)<", page)
    assert len(headings) == len(set(headings)) and "Sweep" in headings
    assert ">wind_speed 5 m/s<" in page and ">wind_speed 10 m/s<" in page and ">y [-]<" in page
    assert ">x1 [-]<" in page and "1e" not in "".join(re.findall(r">([^<]*)</text>", page))
