"""HTML views of results for Jupyter (``_repr_html_``): a heading, a few facts, the indices table
with untrusted rows marked. Inline styles only: a notebook page carries no report stylesheet."""

from __future__ import annotations

from collections.abc import Sequence
from html import escape

import numpy as np
import pandas as pd

MAX_ROWS = 60
"""Rows shown of a long table (the rest: ``result.indices``)."""
_UNTRUSTED = ' style="background:#fdecea"'


def _cell(v: object) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "yes" if v else "<b>no</b>"
    if isinstance(v, (float, np.floating)):
        return "" if np.isnan(v) else f"{v:.4g}"
    return escape(str(v))


def result_html(title: str, facts: Sequence[str], table: pd.DataFrame, rows: int = MAX_ROWS) -> str:
    """``title``, ``facts`` as a list, then ``table`` (its first ``rows`` rows; a row whose
    ``trusted`` is false shaded red)."""
    shown = table.head(rows)
    bad = ~shown["trusted"].astype(bool).to_numpy() if "trusted" in shown else np.zeros(len(shown), bool)
    head = "".join(f"<th>{escape(str(c))}</th>" for c in shown.columns)
    body = "".join(f"<tr{_UNTRUSTED if b else ''}>" + "".join(f"<td>{_cell(v)}</td>" for v in row) + "</tr>"
                   for row, b in zip(shown.itertuples(index=False), bad))
    more = f"<p>First {rows} of {len(table)} rows.</p>" if len(table) > rows else ""
    items = "".join(f"<li>{escape(f)}</li>" for f in facts)
    return (f"<div><strong>{escape(title)}</strong><ul>{items}</ul>"
            f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>{more}</div>")
