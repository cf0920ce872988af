"""``report.html``: one self-contained page per results folder, built from the files stored there.

The page is made from what a report folder holds (``summary.md``, the CSV tables, ``provenance.json``,
``study.yaml``, the PNGs), so it can be rebuilt for any folder -- a fresh run
(:func:`ddgsa.report.write.write_report` calls :func:`write_html` last) or a committed one (``ddgsa html
DIR...``) -- without the evaluation store. Each section of :data:`ddgsa.report.sections.SECTIONS` gives its
part, in that order; a section's charts are the matplotlib figures its functions draw from the folder's
tables -- the same functions that wrote the folder's PNGs -- inlined as SVG. PNGs no chart draws (a
model's order maps and spectra, histograms) are inlined as palette PNGs. No network, no CDN: the
stylesheet and a small script (sorting, filtering, legend toggles) are inlined, and the page reads fully
without JavaScript.
"""

from __future__ import annotations

import os
from html import escape
from importlib.resources import files
from pathlib import Path

from ddgsa.errors import OutputFolderError
from ddgsa.report.outdir import incompleteness
from ddgsa.report.sections import SECTIONS
from ddgsa.report.sections.base import Folder

HTML_NAME = "report.html"


def write_html(folder: Path, complete: bool | None = None, svgs: dict[str, str] | None = None) -> Path:
    """Write ``folder/report.html`` from the files in ``folder`` (whole or not at all: written
    beside and renamed); returns its path. ``complete``, ``svgs``: see :func:`render`."""
    path = Path(folder) / HTML_NAME
    tmp = path.with_name(f".{HTML_NAME}.{os.getpid()}.tmp")
    tmp.write_text(render(Path(folder), complete, svgs), encoding="utf-8")
    os.replace(tmp, path)
    return path


def render(folder: Path, complete: bool | None = None, svgs: dict[str, str] | None = None) -> str:
    """The report page of a results folder, as HTML text. A study's folder whose outputs are not
    complete (:func:`ddgsa.report.outdir.incompleteness`: its run was killed, or a file changed since)
    gets a banner saying so at the top; ``complete=True`` (the report being written) skips the check.
    ``svgs``: charts already drawn as SVG with their PNGs, by PNG name (:func:`ddgsa.report.write.render_figures`)."""
    if not folder.is_dir():
        raise OutputFolderError(f"{folder}: not a folder (ddgsa html takes results folders, e.g. results/quickstart)")
    f = Folder(folder, svgs=svgs or {})
    f.charted = {c.png for s in SECTIONS for c in s.charts(f) if c.png}
    f.shown = {name for s in SECTIONS for name in s.shows}
    sections = [(s.anchor, s.heading, body) for s in SECTIONS if (body := s.html(f))]
    if not sections:
        raise OutputFolderError(f"{folder}: not a results folder (no summary, tables, figures or provenance to "
                                f"report; ddgsa html takes the folders ddgsa run, modes and bench write)")
    title = str(f.provenance.get("study") or folder.resolve().name)
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
