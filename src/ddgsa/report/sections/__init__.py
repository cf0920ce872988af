"""The report's sections, in the order of the page: each module is one section -- the CSV tables it writes
from a study's result, the charts it draws from a folder's files (saved as PNG by :mod:`ddgsa.report.write`,
inlined as SVG by :mod:`ddgsa.report.html`), its HTML part and captions (:class:`~.base.Section`).

Adding a section: write a module with a ``SECTION`` and list it here; see docs/report_sections.md.
"""

from __future__ import annotations

from ddgsa.report.sections import (accuracy_cost, campbell, confirmation, fault, figures, groups, indices, problems,
                                   provenance, sample_size, signals, summary, sweep, tables)
from ddgsa.report.sections.base import Section

SECTIONS: list[Section] = [summary.SECTION, problems.SECTION, confirmation.SECTION, indices.SECTION, groups.SECTION,
                           fault.SECTION, sweep.SECTION, campbell.SECTION, accuracy_cost.SECTION, signals.SECTION,
                           sample_size.SECTION, tables.SECTION, figures.SECTION, provenance.SECTION]
"""Every section, in the order of the page."""
