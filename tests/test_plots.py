"""Every plot kind reads at a glance: its axis labels carry units, no text lies outside the figure
(nothing is clipped when it is saved as it is), and where a plot is dense its legend stands
outside every axes (it covers no data). Each kind is drawn from small synthetic inputs."""

from __future__ import annotations

import re

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402

from ddgsa.detection import DetectionSettings, assess  # noqa: E402
from ddgsa.mbs.campbell import CampbellDiagram, campbell_from_tables  # noqa: E402
from ddgsa.mbs.modal import plot_modes  # noqa: E402
from ddgsa.models import get  # noqa: E402
from ddgsa.report.sections.fault import plot_detectability, plot_fault_histograms  # noqa: E402
from ddgsa.report.sections.indices import plot_agreement, plot_heatmap, plot_scene_bars  # noqa: E402
from ddgsa.report.sections.sweep import plot_sweep, sweep_summary  # noqa: E402
from ddgsa.models.signals import plot_order_map, plot_spectrum  # noqa: E402

UNIT = re.compile(r"\[[^\]]+\]")


def _check(fig, dense_legend: bool = False) -> None:
    """Units on every labelled axis, every text inside the figure, a dense plot's legends off the axes."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    box = fig.bbox
    for ax in fig.axes:
        for label in (ax.get_xlabel(), ax.get_ylabel()):
            assert not label or UNIT.search(label), f"axis label without a unit: {label!r}"
    texts = [t for ax in fig.axes for t in (ax.title, ax.xaxis.label, ax.yaxis.label, *ax.texts)]
    texts += [t for leg in [ax.get_legend() for ax in fig.axes] + list(fig.legends) if leg for t in leg.get_texts()]
    texts += list(fig.texts) + ([fig._suptitle] if fig._suptitle is not None else [])
    for t in texts:                                           # titles, labels, annotations, legends (not ticks)
        if t.get_visible() and t.get_text().strip() and (t.axes is None or t.axes.get_visible()):
            b = t.get_window_extent(renderer)
            assert box.x0 - 1 <= b.x0 and b.x1 <= box.x1 + 1 and box.y0 - 1 <= b.y0 and b.y1 <= box.y1 + 1, \
                f"text {t.get_text()!r} leaves the figure"
    titles = [t for t in [fig._suptitle, *(ax.title for ax in fig.axes if ax.get_visible())]
              if t is not None and t.get_visible() and t.get_text().strip()]
    for leg in [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None] + list(fig.legends):
        lb = leg.get_window_extent(renderer)
        for t in titles:
            assert not lb.overlaps(t.get_window_extent(renderer)), f"a legend covers the title {t.get_text()!r}"
    if dense_legend:
        legends = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None] + list(fig.legends)
        assert legends
        for leg in legends:
            lb = leg.get_window_extent(renderer)
            for ax in fig.axes:
                assert not lb.overlaps(ax.get_window_extent(renderer)), "a legend covers an axes"
    plt.close(fig)


def _ticks_inside(ax) -> None:
    renderer = ax.figure.canvas.get_renderer()
    for t in ax.get_xticklabels() + ax.get_yticklabels() + [ax.title]:
        if t.get_visible() and t.get_text():
            b = t.get_window_extent(renderer)
            assert ax.figure.bbox.x0 - 1 <= b.x0 and b.x1 <= ax.figure.bbox.x1 + 1, t.get_text()


def _campbell(n_modes: int, spacing: float = 0.07) -> CampbellDiagram:
    speeds = np.linspace(0.0, 20.0 * np.pi / 30.0, 5)
    tables = {s: pd.DataFrame({"frequency_hz": [0.2 + spacing * k + 0.01 * s for k in range(n_modes)],
                               "damping_ratio": 0.01, "label": [f"mode_with_a_long_name_{k}" for k in range(n_modes)]})
              for s in speeds}
    return campbell_from_tables(tables, orders=(1.0, 3.0))


def test_campbell() -> None:
    diagram = _campbell(14)
    ax = diagram.plot()
    fig = ax.figure
    colours = [line.get_color() for line in ax.get_lines()[:14]]
    assert len({tuple(np.atleast_1d(c)) if not isinstance(c, str) else c for c in colours}) == 14   # none repeats
    assert all("(unknown)" not in t.get_text() for t in ax.get_legend().get_texts())
    # the axis ends at 1.5 x the 3P line at 20 rpm (1 Hz), or just above the highest mode where that is lower
    top, highest = ax.get_ylim()[1], diagram.frame["frequency_hz"].max()
    assert top == pytest.approx(min(1.5, 1.05 * highest), rel=1e-9)
    wide = _campbell(14, spacing=0.7).plot()                 # modes up to 9 Hz: those above 1.5 Hz are counted
    assert wide.get_ylim()[1] == pytest.approx(1.5) and "12 modes above 1.5 Hz not shown" in wide.get_title()
    plt.close(wide.figure)
    # a diagram cut to a model's band (a wind drive: no mode near 1P or 3P) shows every mode it holds
    tables = {s: grp.drop(columns="mode") for s, grp in _campbell(14, spacing=0.7).frame.groupby("speed_rad_s")}
    banded = campbell_from_tables(tables, orders=(1.0, 3.0), band_hz=25.0)
    band_ax = banded.plot()
    assert band_ax.get_ylim()[1] == pytest.approx(1.12 * banded.frame["frequency_hz"].max())
    assert "not shown" not in band_ax.get_title() and len(band_ax.get_legend().get_texts()) == 14
    plt.close(band_ax.figure)
    texts = [t.get_text() for t in ax.texts]
    assert "1P" in texts and "3P" in texts
    _check(fig, dense_legend=True)


def test_mode_bars() -> None:
    table = pd.DataFrame({"frequency_hz": [1.0, 3.0, 30.0], "damping_ratio": 0.01,
                          "label": ["a_long_mode_label_1", "b", "c"]})
    ax = plot_modes(table)
    assert ax.get_xscale() == "log"                      # 1 to 30 Hz: a factor 30
    _no_tick_overlap(ax)
    assert {t.get_text() for t in ax.get_xticklabels() if t.get_visible()} >= {"1", "10"}
    _check(ax.figure)


def _no_tick_overlap(ax) -> None:
    ax.figure.canvas.draw()
    renderer = ax.figure.canvas.get_renderer()
    left, right = sorted(ax.get_xlim())
    ticks = [t for t, v in zip(ax.get_xticklabels(), ax.get_xticks()) if t.get_text() and left <= v <= right]
    boxes = sorted((t.get_window_extent(renderer) for t in ticks), key=lambda b: b.x0)
    assert len(boxes) >= 2
    assert all(a.x1 <= b.x0 for a, b in zip(boxes, boxes[1:])), [t.get_text() for t in ticks]


def test_mode_bars_of_nearly_equal_frequencies_use_a_linear_axis_from_zero() -> None:
    """Newcomer trial (`ddgsa modes generator_radial`): 34.212040 and 34.212043 Hz on a log axis gave
    overlapping tick labels and bars of very different lengths. Under a factor 10 the axis is linear
    from 0: the two bars end 3e-6 Hz apart, i.e. look equal, and the tick labels do not overlap."""
    table = pd.DataFrame({"frequency_hz": [34.212040, 34.212043, 48.55], "damping_ratio": 0.02,
                          "label": ["bearing_radial", "bearing_radial_vertical", "tower"]})
    ax = plot_modes(table)
    assert ax.get_xscale() == "linear" and ax.get_xlim()[0] == 0.0
    assert ax.get_xlim()[1] == pytest.approx(1.05 * 48.55)
    _no_tick_overlap(ax)
    assert "34.21 Hz" in ax.get_yticklabels()[0].get_text()
    _check(ax.figure)


def _indices(outputs: list[str], methods: list[str], params: list[str]) -> pd.DataFrame:
    rng = np.random.default_rng(0)
    return pd.DataFrame([{"scene": s, "wind_speed": w, "turbulence_intensity": 0.12, "inclination_deg": 0.0,
                          "shear_exponent": 0.2, "output": o, "method": m, "parameter": p,
                          "S1": rng.random() / 3, "S1_conf": 0.02, "ST": rng.random() / 2, "ST_conf": 0.02,
                          "trusted": p != params[0], "n_evals": 10}
                         for s, w in enumerate((6.0, 11.0)) for o in outputs for m in methods for p in params])


def test_scene_bars_and_heatmap() -> None:
    model = get("direct_drive", fidelity="rigid")
    outputs = ["damage_front", "damage_rear", "rms_deflection_hub", "front_Fr_mean"]
    params = [p.name for p in model.parameters[:11]]
    rows = _indices(outputs, ["mdrm"], params)
    rows.loc[rows["output"] == "front_Fr_mean", ["S1", "ST"]] = np.nan            # refused: said in the panel
    units = {o: model.output(o).unit for o in outputs}
    fig = plot_scene_bars(rows[rows["scene"] == 0], units)
    assert any("refused" in t.get_text() for ax in fig.axes for t in ax.texts)
    assert len({round(ax.get_position().x0, 3) for ax in fig.axes if ax.get_visible()}) == 3   # three panels a row
    _check(fig, dense_legend=True)
    _check(plot_heatmap(rows, units))


def test_scene_bars_legend_leaves_the_title_free() -> None:
    """Newcomer trial: in the quickstart's bars (two methods, five parameters) the legend, outside upper
    right, covered the end of the title (the scene description); _check now fails on any legend over a title."""
    model = get("direct_drive", fidelity="rigid")
    outputs = ["damage_front", "damage_rear", "rms_deflection_hub", "front_Fr_mean"]
    rows = _indices(outputs, ["mdrm", "pce"], [p.name for p in model.parameters[:5]])
    rows["rank_confirmed"] = rows["parameter"] == rows["parameter"].iloc[0]
    fig = plot_scene_bars(rows[rows["scene"] == 1], {o: model.output(o).unit for o in outputs})
    legend = fig.legends[0]
    assert [t.get_text() for t in legend.get_texts()] == ["S1", "ST", "untrusted, rank confirmed", "ST, pce"]
    assert [getattr(h, "get_hatch", lambda: None)() for h in legend.legend_handles] == [None, None, "..", None]
    shown = [ax for ax in fig.axes if ax.get_visible()]
    assert len(shown) == 4 and all(ax.yaxis_inverted() for ax in shown)       # one panel an output; first parameter on top
    assert shown[0].get_yticklabels()[0].get_text() == rows["parameter"].iloc[0]
    _check(fig, dense_legend=True)


def test_sweep() -> None:
    sweep = pd.DataFrame([{"scene": s, "wind_speed": w, "turbulence_intensity": ti, "inclination_deg": 0.0,
                           "shear_exponent": 0.2, "realisation": r, "damage_front": 1e-9 * w * (1 + r),
                           "error": None} for s, (w, ti) in enumerate([(6.0, 0.1), (11.0, 0.1), (6.0, 0.2), (11.0, 0.2)])
                          for r in range(2)])
    summary = sweep_summary(sweep, ["damage_front"])
    model = get("direct_drive", fidelity="rigid")
    fig = plot_sweep(summary, "damage_front", units={"damage_front": model.output("damage_front").unit})
    _check(fig)


def test_detectability_curve_and_histograms() -> None:
    rng = np.random.default_rng(1)
    healthy = pd.DataFrame({f"s{k}": rng.normal(0.0, 1e-4, 200) for k in range(6)})
    faulty = {lv: pd.DataFrame({f"s{k}": rng.normal(lv * 1e-5 * (k + 1), 1e-4, 200) for k in range(6)})
              for lv in (2.0, 5.0, 10.0)}
    det = assess(healthy, faulty, 0.0, DetectionSettings(bootstrap=100))
    fig, ax = plt.subplots(figsize=(8.5, 4.2))
    det.plot_curve(ax=ax, level_label="k_front_z [N/m]")
    assert ax.get_xlabel().startswith("k_front_z [N/m]")
    fig.tight_layout()
    _check(fig, dense_legend=True)
    fig = plot_fault_histograms(det, "scene", {f"s{k}": "m" for k in range(6)})
    hist = fig.axes[0]
    assert hist.get_ylabel() == "share of measurements [-]" and re.search(r"\[m\]|\[-\]", hist.get_xlabel())
    heights = [p.get_height() for p in hist.patches[:30]]
    assert sum(heights) == pytest.approx(1.0)                # each population's bars sum to one: no 1/unit density
    _check(fig)


def test_spectrum_and_order_map() -> None:
    t = np.arange(0.0, 2.0, 1 / 5000)
    x = 1e-5 * np.sin(2 * np.pi * 25 * t) + 1e-7 * np.sin(2 * np.pi * 406 * t)
    fig, ax = plt.subplots(figsize=(7, 4))
    plot_spectrum(t, x, {"1x": 25.0, "3 x BPFI": 406.0, "beyond": 3000.0}, max_hz=2000.0, ax=ax, unit="[m/s^2]")
    assert ax.get_xlim()[1] == pytest.approx(2000.0, rel=1e-3)
    low, high = ax.get_ylim()
    assert high / low == pytest.approx(3e6)                  # six decades below the peak, not down to 1e-300
    assert [t.get_text() for t in ax.texts] == ["1x", "3 x BPFI"]   # a mark beyond the range is left out
    renderer = fig.canvas.get_renderer()
    fig.canvas.draw()
    for t in ax.texts:                                        # the labels sit inside the axes
        assert ax.get_window_extent(renderer).contains(*t.get_window_extent(renderer).p1)
    _check(fig)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    plot_order_map(np.linspace(600, 1500, 5), np.linspace(0, 10, 41), np.abs(np.random.default_rng(0).normal(
        size=(5, 41))) + 1e-3, max_order=8.0, ax=ax, unit="[m/s^2]")
    _check(fig)


def test_detectability_chart_from_the_verdict_table() -> None:
    """The report's POD chart reads ``fault_verdicts.csv``'s columns: one curve per sensor starting at the
    healthy level at the false-alarm rate, the band its interval, one legend entry per sensor and line."""
    rows = pd.DataFrame([{"output": o, "healthy": 0.0, "faulty": lv, "pod": p, "pod_low": p - 0.1, "pod_high": p + 0.05}
                         for o, pods in (("s0", (0.2, 0.6)), ("combined", (0.4, 0.95))) for lv, p in zip((0.2, 0.4), pods)])
    fig = plot_detectability(rows, "looseness [-]", 0.9, 0.05, "scene 0", 0.95)
    ax = fig.axes[0]
    assert ax.get_xlabel().startswith("looseness [-]") and "confidence 0.95" in ax.get_title()
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["s0", "combined", "target 0.9", "false-alarm rate 0.05"]
    x, y = ax.lines[0].get_data()
    assert list(x) == [0.0, 0.2, 0.4] and list(y) == [0.05, 0.2, 0.6]
    _check(fig, dense_legend=True)


def test_agreement_chart_shows_every_point_and_only_the_checks_it_draws() -> None:
    """Newcomer trials: a given-data S1 of -0.4 was cut off by fixed [-0.05, 1.05] axes, and an M-DRM refused
    on every row (NaN) left an empty chart whose legend listed the cross-checks."""
    rows = []
    for p, (s1, st, given) in {"a": (0.6, 0.7, 0.62), "b": (0.3, 0.35, -0.4)}.items():
        rows += [dict(scene=0, output="y", parameter=p, method="mdrm", S1=s1, ST=st, trusted=p == "a"),
                 dict(scene=0, output="y", parameter=p, method="given_data_s1", S1=given, ST=np.nan, trusted=False),
                 dict(scene=0, output="y", parameter=p, method="pce", S1=s1 + 0.01, ST=st + 0.01, trusted=True)]
    fig = plot_agreement(pd.DataFrame(rows))
    s1_axes, st_axes = fig.axes
    assert s1_axes.get_xlim()[0] < -0.4 and s1_axes.get_ylim() == st_axes.get_ylim()      # one scale for both
    assert [t.get_text() for t in s1_axes.get_legend().get_texts()] == ["vs given_data_s1", "vs pce"]
    plt.close(fig)
    refused = pd.DataFrame([dict(r, S1=np.nan, ST=np.nan) if r["method"] == "mdrm" else r for r in rows])
    fig = plot_agreement(refused)
    assert fig.axes[0].get_legend() is None
    assert "no finite M-DRM index" in " ".join(t.get_text() for t in fig.axes[0].texts)
    plt.close(fig)


def test_scene_bars_and_heatmap_say_one_thing_per_panel_and_only_what_they_draw() -> None:
    """Newcomer trial: RBD-FAST's bars (S1 only) had an ST legend entry; a panel of an output with nothing to
    rank was titled "nothing to rank" over the text "indices refused"; its heatmap panel was blank and unsaid."""
    rows = _indices(["y", "flat"], ["rbd_fast"], ["x1", "x2", "x3"]).assign(ST=np.nan, ST_conf=np.nan)
    rows.loc[rows["output"] == "flat", "S1"] = np.nan
    rows["verdict"] = np.where(rows["output"] == "flat", "nothing to rank", "unconfirmed")
    verdicts = pd.DataFrame({"scene": [0, 0], "output": ["y", "flat"], "method": ["rbd_fast"] * 2,
                             "verdict": ["unconfirmed", "nothing to rank"]})
    fig = plot_scene_bars(rows[rows["scene"] == 0], {"y": "-", "flat": "-"}, verdicts=verdicts)
    assert [t.get_text() for t in fig.legends[0].get_texts()] == ["S1", "untrusted"]
    flat = [ax for ax in fig.axes if ax.get_title().startswith("flat")][0]
    said = " ".join(t.get_text() for t in flat.texts)
    assert flat.get_title().endswith("nothing to rank") and "nothing to rank" in said and "refused" not in said
    _check(fig)
    both = rows.assign(ST=0.5)
    both.loc[both["output"] == "flat", "ST"] = np.nan
    fig = plot_heatmap(both, {"y": "-", "flat": "-"})
    panel = [ax for ax in fig.axes if ax.get_title().startswith("flat")][0]
    assert "nothing to rank" in " ".join(t.get_text() for t in panel.texts)
    assert not [ax for ax in fig.axes if ax.get_title().startswith("y")][0].texts     # a drawn panel: no text
    _check(fig)


def test_chart_titles_name_only_the_scene_fields_the_model_reads(tmp_path) -> None:
    """Newcomer trial: the analytic model (Ishigami x wind_speed / 11) had bars titled 'wind_speed=8,
    turbulence_intensity=0.12, inclination_deg=0, shear_exponent=0.2', fields it never reads; a wind
    turbine model's titles keep all four."""
    from ddgsa.report.sections import indices
    from ddgsa.report.sections.base import Folder

    _indices(["y"], ["mdrm"], ["x1", "x2", "x3"]).to_csv(tmp_path / "indices.csv", index=False)
    titles = {}
    for model in ("analytic", "direct_drive"):
        folder = Folder(tmp_path, record={"model": {"name": model}})
        chart = next(c for c in indices.charts(folder) if c.png == "bars_scene0.png")
        fig = chart.draw()
        titles[model] = (fig._suptitle.get_text(), chart.caption)
        plt.close(fig)
    assert titles["analytic"][0] == "Sobol indices, wind_speed=6" and "turbulence" not in titles["analytic"][1]
    assert titles["direct_drive"][0] == ("Sobol indices, wind_speed=6, turbulence_intensity=0.12, inclination_deg=0, "
                                         "shear_exponent=0.2")
