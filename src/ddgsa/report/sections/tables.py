"""Other tables: every CSV of the folder no other section shows; the per-evaluation tables (``evaluations.csv``,
``sweep.csv``) named with their size, not copied into the page. Writes ``evaluations.csv``."""

from __future__ import annotations

from html import escape
from typing import TYPE_CHECKING

from ddgsa.report.sections.base import Folder, Section, Tables, table

if TYPE_CHECKING:  # pragma: no cover
    from ddgsa.execute.kinds.common import StudyResult
    from ddgsa.models.base import ModelOutput

RAW_TABLES = ("evaluations.csv", "sweep.csv")
"""Per-evaluation tables: named with their size, not copied into the page."""


def tables(result: "StudyResult", info: dict[str, "ModelOutput"]) -> Tables:
    return [("evaluations.csv", result.evaluations.drop(columns=["key"], errors="ignore"))]


def html(folder: Folder) -> str:
    parts = []
    for path in sorted(folder.path.glob("*.csv")):
        if path.name in folder.shown:
            continue
        if path.name in RAW_TABLES:
            n = sum(1 for _ in path.open()) - 1
            parts.append(f"<p><code>{escape(path.name)}</code>: {n} rows, one per evaluation "
                         "(not copied into this page).</p>")
            continue
        df = folder.csv(path.name)
        if df is not None:
            parts.append(f"<h3>{escape(path.name)}</h3>" + table(df, path.stem, path.name))
    return "".join(parts)


SECTION = Section("tables", "Other tables", html, tables=tables)
