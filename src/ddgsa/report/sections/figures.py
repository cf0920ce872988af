"""Figures: the folder's PNGs that no section's chart draws (a model's own plots of each scene -- order maps,
spectra --, the fault's histograms, a benchmark's extra charts), inlined with a :data:`PNG_COLORS` palette.
Writes the model's scene plots (:meth:`ddgsa.models.base.Model.scene_figures`)."""

from __future__ import annotations

import base64
import io
from html import escape
from typing import TYPE_CHECKING

from PIL import Image

from ddgsa.report.sections.base import Folder, ResultFigure, Section
from ddgsa.study.spec import plan_scenes

if TYPE_CHECKING:  # pragma: no cover
    from ddgsa.execute.kinds.common import StudyResult

PNG_WIDTH = 800
"""Inlined PNGs wider than this are scaled down to it [px]."""
PNG_COLORS = 128
"""Palette size of the inlined PNGs (line plots and colour maps read the same with it)."""


def figures(result: "StudyResult") -> list[ResultFigure]:
    """A model's own signal plots of each scene at the study's nominal point (healthy fault level),
    for a model that draws them (:meth:`Model.scene_figures`, e.g. the rig's order maps and spectra)."""
    study = result.study
    draw = study.make_model().scene_figures
    point = {**study.spec.fixed, **(study.space.nominal if study.space is not None else {})}
    if study.spec.fault is not None:
        point[study.spec.fault.parameter] = study.spec.fault.healthy
    return [(f"{name}_scene{ps.index}.png", lambda fig=fig: fig)
            for ps in plan_scenes(study) for fig, name in draw(ps.scenes[0], point)]


def html(folder: Folder) -> str:
    parts = []
    for path in sorted(folder.path.glob("*.png")):
        if path.name in folder.charted:
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


SECTION = Section("figures", "Figures", html, figures=figures)
