"""What every report section is made of: the folder it reads, its charts, and the page's small parts.

A section (:class:`Section`) has a place on the page (anchor, heading), the CSV tables it writes from a
study's result, the charts it draws from a folder's files (:class:`Chart`: one function returning a
matplotlib figure, saved as a PNG into the folder by :mod:`ddgsa.report.write` and inlined as SVG by
:mod:`ddgsa.report.html`), and its HTML part. Sections read a folder through :class:`Folder`, so the page
of a committed folder (``ddgsa html DIR``) is drawn from its files alone, by the same functions.
"""

from __future__ import annotations

import io
import json
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from html import escape
from pathlib import Path
from typing import TYPE_CHECKING, Any

import matplotlib

matplotlib.use("Agg")
import markdown  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from ruamel.yaml import YAML  # noqa: E402

from ddgsa.errors import DdgsaError, OutputFolderError  # noqa: E402
from ddgsa.models import get as get_model  # noqa: E402

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from ddgsa.execute.kinds.common import StudyResult
    from ddgsa.models.base import ModelOutput

TABLE_ROWS = 400
"""Tables longer than this show their first rows and name the CSV file that holds all of them."""
AXIS_UNITS = {"speed_rad_s": "rad/s", "speed_rpm": "rpm", "frequency_hz": "Hz", "n_evals": "runs"}
"""Units of the columns the report's own tables add and its charts use as axes (``campbell.csv``,
``accuracy_cost.csv``); scene fields, parameters and outputs take theirs from the model's declarations
(:meth:`ddgsa.models.base.Model.units`)."""
SVG_RC = {"svg.hashsalt": "ddgsa", "svg.fonttype": "none"}
"""SVG the same bytes on every run (fixed hash salt), text as ``<text>`` (smaller, searchable, selectable)."""
SVG_ID_SLOT = "@"
"""The id prefix of an SVG drawn before its place on the page is known (replaced there by the chart's own)."""
SERIES_GID = re.compile(r'id="ddgsa-([slm])(\d*)"')
"""Group ids :func:`tag_marks` gives the artists, turned into classes by :func:`svg_of`."""


@dataclass(frozen=True)
class Chart:
    """One chart of a section: ``draw()`` builds its matplotlib figure from the folder's tables.

    Attributes
    ----------
    png : str or None
        File name the report writes it under into the folder (``bars_scene0.png``); ``None`` for a chart
        drawn only on the page.
    caption : str
        What it shows, under it on the page.
    kind : str
        Its kind on the page (``data-kind``: bars, heatmap, sweep, pod, ...).
    draw : callable
        Returns a new figure (the caller saves and closes it).
    """

    png: str | None
    caption: str
    kind: str
    draw: Callable[[], "Figure"]


Tables = list[tuple[str, pd.DataFrame]]
"""A section's CSV tables of a result: ``(file name, table)``, written in this order."""
ResultFigure = tuple[str, Callable[[], "Figure"]]
"""A PNG the report draws from the in-memory result alone (raw measurements no table holds)."""


def no_tables(result: "StudyResult", info: dict[str, "ModelOutput"]) -> Tables:
    """A section that writes no table (it shows what another writes, or a tool's own files)."""
    return []


def no_charts(folder: "Folder") -> list[Chart]:
    """A section without charts."""
    return []


def no_figures(result: "StudyResult") -> list[ResultFigure]:
    """A section without figures drawn from the result alone."""
    return []


@dataclass(frozen=True)
class Section:
    """A part of the report.

    Attributes
    ----------
    anchor, heading : str
        Its ``id`` and ``<h2>`` on the page.
    html : callable
        ``html(folder)``: its HTML part, empty when the folder holds nothing for it; charts go in with
        :meth:`Folder.figure`.
    tables : callable
        ``tables(result, info)``: the CSV files it writes from a study's result (``info``: the declared outputs).
    charts : callable
        ``charts(folder)``: its charts, drawn from the folder's files.
    figures : callable
        ``figures(result)``: PNGs drawn from the result alone (what no table holds: raw measurements, a
        model's own plots); the page inlines them as images.
    shows : tuple of str
        The CSV files its HTML part shows (the "Other tables" section leaves them out).
    """

    anchor: str
    heading: str
    html: Callable[["Folder"], str]
    tables: Callable[["StudyResult", dict[str, "ModelOutput"]], Tables] = no_tables
    charts: Callable[["Folder"], list[Chart]] = no_charts
    figures: Callable[["StudyResult"], list[ResultFigure]] = no_figures
    shows: tuple[str, ...] = ()


@dataclass
class Folder:
    """A results folder as the sections read it: its CSV tables (read once), provenance, study file and units."""

    path: Path
    study_file: Path | None = None
    """The study file to read instead of the folder's ``study.yaml`` (a report written where none is copied)."""
    charted: set[str] = field(default_factory=set)
    """The PNG names the sections' charts have (the page draws them, it does not inline the PNGs)."""
    shown: set[str] = field(default_factory=set)
    """The CSV names the sections show (the rest go to "Other tables")."""
    record: dict[str, Any] | None = None
    """The provenance to read instead of the folder's ``provenance.json``: a report being written draws its
    charts before that file is (their units come from its model)."""
    svgs: dict[str, str] = field(default_factory=dict)
    """Charts already drawn as SVG (ids in :data:`SVG_ID_SLOT`) by PNG name: the report's writer draws each
    figure once for its PNG and the page."""
    _tables: dict[str, pd.DataFrame | None] = field(default_factory=dict, repr=False)
    _figures: list[int] = field(default_factory=lambda: [0], repr=False)

    def csv(self, name: str) -> pd.DataFrame | None:
        """``name`` as a table (a copy; ``None`` when the folder has no such file or it is empty)."""
        if name not in self._tables:
            path = self.path / name
            self._tables[name] = pd.read_csv(path) if path.is_file() and path.stat().st_size else None
        df = self._tables[name]
        return None if df is None else df.copy()

    @cached_property
    def provenance(self) -> dict[str, Any]:
        return self.record if self.record is not None else read_json(self.path / "provenance.json")

    @cached_property
    def study(self) -> dict[str, Any]:
        """The folder's ``study.yaml`` (or :attr:`study_file`; {} where there is none)."""
        path = self.study_file or self.path / "study.yaml"
        data = YAML(typ="safe").load(path.read_text()) if path.is_file() else None
        return data if isinstance(data, dict) else {}

    @cached_property
    def model(self) -> Any:
        """The provenance's model (None where it names none or it is not registered here)."""
        model = self.provenance.get("model") or {}
        if not model.get("name"):
            return None
        try:
            return get_model(model["name"], fidelity=model.get("fidelity"), **(model.get("options") or {}))
        except (DdgsaError, TypeError):
            return None

    def title_fields(self, fields: Sequence[str]) -> list[str]:
        """The scene label ``fields`` a chart title names: those the model reads
        (:attr:`ddgsa.models.base.Model.scene_fields_read`; the analytic model reads ``wind_speed`` only),
        all of them where it does not say or reads none of them."""
        read = getattr(self.model, "scene_fields_read", None)
        return [f for f in fields if read is None or f in read] or list(fields)

    @cached_property
    def units(self) -> dict[str, str]:
        """Units by column name: the report's own axes, the model's scene fields, parameters and outputs
        (:meth:`ddgsa.models.base.Model.units`, when the model of the provenance is registered), a unit the
        study file writes beside an output (``outputs: [{name, unit}]`` or ``output_units``: the tables hold
        that output in it; not a parameter's, whose values the tables hold in the model's SI unit), then the
        units the folder's tables state."""
        units = dict(AXIS_UNITS)
        if self.model is not None:
            units.update(self.model.units())
        # a parameter's unit written in the study is not used: the tables hold its values in the model's SI unit
        for spec in self.study.get("outputs") or []:
            if isinstance(spec, dict) and spec.get("name") and spec.get("unit"):
                units[str(spec["name"])] = str(spec["unit"])
        given = self.study.get("output_units")
        units.update({str(k): str(v) for k, v in given.items()} if isinstance(given, dict) else {})
        for table, col, unit in (("indices.csv", "output", "output_unit"), ("output_moments.csv", "output", "unit")):
            df = self.csv(table)
            if df is not None and unit in df:
                units.update({o: u for o, u in zip(df[col], df[unit]) if isinstance(u, str)})
        return units

    def label(self, name: str) -> str:
        """``name [unit]``; ``[?]`` where no unit is known."""
        return f"{name} [{self.units.get(name) or '?'}]"

    def figure(self, chart: Chart) -> str:
        """``chart`` as a ``<figure>`` with its SVG inline (ids made unique on the page) and its caption."""
        self._figures[0] += 1
        prefix = f"f{self._figures[0]}-"
        if chart.png in self.svgs:
            svg = self.svgs[chart.png].replace(f'id="{SVG_ID_SLOT}', f'id="{prefix}').replace(f"#{SVG_ID_SLOT}",
                                                                                            f"#{prefix}")
        else:
            fig = chart.draw()
            try:
                svg = svg_of(fig, prefix)
            finally:
                plt.close(fig)
        width = re.search(r'width="([\d.]+)pt"', svg)
        style = f' style="max-width:{float(width[1]) * 4 / 3:.0f}px"' if width else ""     # its own size, at most
        return (f'<figure class="plot" data-kind="{chart.kind}"{style}>{svg}'
                f"<figcaption>{escape(chart.caption)}</figcaption></figure>")


def read_json(path: Path) -> dict[str, Any]:
    """The JSON file at ``path`` ({} where there is none); :class:`OutputFolderError` where it is not JSON."""
    if not path.is_file():
        return {}
    try:
        return json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise OutputFolderError(f"{path}: not a JSON file ddgsa wrote ({exc}); rerun the study or "
                                f"`ddgsa report` its folder to rewrite it") from None


def trusted(df: pd.DataFrame, column: str = "trusted") -> np.ndarray:
    """A table's ``trusted`` column as booleans (a CSV holds ``True``/``False``; missing: untrusted)."""
    if column not in df:
        return np.zeros(len(df), bool)
    return df[column].astype(str).str.lower().eq("true").to_numpy()


# --- charts as SVG -------------------------------------------------------------------------------------------------


def tag_marks(fig: "Figure") -> None:
    """Give the figure's data artists group ids the page's script and tests use: a legend entry and the
    artists of the same label ``ddgsa-l<k>`` and ``ddgsa-s<k>`` (the k-th label of the figure's legends,
    shared across its panels), any other data artist (bars, images, unlabelled lines) ``ddgsa-m``."""
    order: dict[str, int] = {}
    for leg in [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None] + list(fig.legends):
        for handle, text in zip(leg.legend_handles, leg.get_texts()):
            k = order.setdefault(text.get_text(), len(order))
            for artist in (handle, text):
                if artist is not None:
                    artist.set_gid(f"ddgsa-l{k}")

    def gid(label: str) -> str:
        return f"ddgsa-s{order[label]}" if label in order else "ddgsa-m"

    for ax in fig.axes:
        inside: set[int] = set()
        for c in ax.containers:
            for child in c.get_children():
                if child is not None:
                    child.set_gid(gid(str(c.get_label())))
                    inside.add(id(child))
        for artist in [*ax.lines, *ax.collections, *ax.patches, *ax.images]:
            if id(artist) not in inside:
                artist.set_gid(gid(str(artist.get_label())))


def svg_of(fig: "Figure", prefix: str) -> str:
    """``fig`` as an inline ``<svg>`` element: no XML header or metadata, the same bytes on every run, tagged
    marks (:func:`tag_marks`) as classes ``series``/``legend-item`` with ``data-series="k"`` and ``mark``;
    compacted: coordinates to 0.1 pt, no layout whitespace, only the ids something refers to, each prefixed
    by ``prefix`` (charts share one page)."""
    tag_marks(fig)
    buf = io.StringIO()
    with matplotlib.rc_context(SVG_RC):
        fig.savefig(buf, format="svg", bbox_inches="tight", metadata={"Date": None, "Creator": None})
    text = buf.getvalue()
    text = text[text.index("<svg"):]
    text = re.sub(r"<metadata>.*?</metadata>", "", text, flags=re.S)
    text = re.sub(r">\s+<", "><", text)
    text = re.sub(r'\b(d|x|y|x1|x2|y1|y2|points)="([^"]*)"',
                  lambda m: f'{m[1]}="{_short(m[2])}"', text)
    text = re.sub(r' transform="rotate\(-?0 [^)]*\)"', "", text)                  # no-op rotations
    family = re.search(r"font-family: ('DejaVu Sans'[^;\"]*)", text)
    if family:                                                                  # said once, on the <svg>
        text = text.replace(f"font-family: {family[1]}", "").replace("<svg ", f'<svg font-family="{family[1]}" ', 1)
        text = re.sub(r';\s*(?=[;"])|(?<=")\s*;\s*', "", text)
    text = re.sub(r"(<g[^>]*>)((?:<use [^>]*/>)+)(?=</g>)",                       # a mark drawn twice in one place
                  lambda m: m[1] + "".join(dict.fromkeys(re.findall(r"<use [^>]*/>", m[2]))), text)
    kinds = {"s": "series", "l": "legend-item", "m": "mark"}
    text = SERIES_GID.sub(lambda m: f'class="{kinds[m[1]]}"' + (f' data-series="{m[2]}"' if m[2] else ""), text)
    text = re.sub(r'(<g[^>]*)>((?:<use [^>]*/>)+)(?=</g>)', _hoist_style, text)
    used = set(re.findall(r"#([A-Za-z_][\w.-]*)", text))
    ids = {name: f"{prefix}{k:x}"                                         # in order of appearance
           for k, name in enumerate(n for n in dict.fromkeys(re.findall(r'\sid="([^"]*)"', text)) if n in used)}
    text = re.sub(r'\sid="([^"]*)"', lambda m: f' id="{ids[m[1]]}"' if m[1] in ids else "", text)
    return re.sub(r'(href="#|url\(#)([^")]*)', lambda m: m[1] + ids.get(m[2], m[2]), text)


def _hoist_style(m: re.Match[str]) -> str:
    """``<g><use style=S/>...</g>`` as ``<g style=S><use/>...</g>`` where every ``<use>`` has the same style
    and the group none (the uses inherit it)."""
    styles = re.findall(r'<use [^>]*?( style="[^"]*")?/>', m[2])
    if len(set(styles)) != 1 or not styles[0] or "style=" in m[1]:
        return m[0]
    style = styles[0]
    return m[1] + style + ">" + m[2].replace(style, "")


def _short(value: str) -> str:
    """An SVG attribute's numbers to one decimal, its whitespace single."""
    value = re.sub(r"(-?\d+)\.(\d)\d*", lambda m: m[1] if m[2] == "0" else f"{m[1]}.{m[2]}", value)
    return re.sub(r"\s+", " ", value).strip()


# --- the page's parts ----------------------------------------------------------------------------------------------


def md_html(text: str) -> str:
    """Markdown as HTML; its tables sortable and scrolling inside the column."""
    out = markdown.markdown(text, extensions=["tables"])
    return out.replace("<table>", '<div class="scroll"><table class="sortable">').replace("</table>", "</table></div>")


def inline_code(text: str) -> str:
    """``text`` escaped, its backquoted words as ``<code>``."""
    return re.sub(r"`([^`]+)`", r"<code>\1</code>", escape(text))


def _cell(v: Any) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "yes" if v else "no"
    if isinstance(v, (float, np.floating)):
        return "" if np.isnan(v) else f"{v:.4g}"
    return escape(str(v))


def table(df: pd.DataFrame, ident: str, source: str, rows: int = TABLE_ROWS) -> str:
    """A sortable table with a filter box (shown with JavaScript); rows whose ``trusted`` column is
    false get the class ``untrusted``."""
    ident = re.sub(r"[^A-Za-z0-9_-]", "_", ident)
    shown = df.head(rows)
    bad = ~trusted(shown) if "trusted" in shown else np.zeros(len(shown), bool)
    head = "".join(f"<th>{escape(str(c))}</th>" for c in shown.columns)
    body = "".join(('<tr class="untrusted">' if b else "<tr>") + "".join(f"<td>{_cell(v)}</td>" for v in row)
                   + "</tr>" for row, b in zip(shown.itertuples(index=False), bad))
    more = f'<p class="note">First {rows} of {len(df)} rows; all of them: <code>{escape(source)}</code>.</p>' \
        if len(df) > rows else ""
    return (f'<input class="filter" type="search" placeholder="filter rows" aria-label="filter {escape(source)}" '
            f'data-table="t-{ident}"><div class="scroll"><table class="sortable data" id="t-{ident}">'
            f"<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table></div>{more}")


def csv_tables(folder: Folder, names: Sequence[str], rows: dict[str, int] | None = None) -> str:
    """Each named CSV of the folder that has rows, under its name as a heading."""
    parts = []
    for name in names:
        df = folder.csv(name)
        if df is not None and len(df):
            parts.append(f"<h3>{escape(name)}</h3>" + table(df, name.removesuffix(".csv"), name,
                                                             (rows or {}).get(name, TABLE_ROWS)))
    return "".join(parts)
