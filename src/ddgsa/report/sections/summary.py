"""The summary: ``summary.md`` (written by :func:`ddgsa.report.write.summary_markdown`) as the page's first section."""

from __future__ import annotations

from ddgsa.report.sections.base import Folder, Section, md_html


def html(folder: Folder) -> str:
    path = folder.path / "summary.md"
    return f'<div class="md">{md_html(path.read_text())}</div>' if path.is_file() else ""


SECTION = Section("summary", "Summary", html)
