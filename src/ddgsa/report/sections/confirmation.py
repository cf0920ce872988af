"""Verdicts: ``confirmation.csv``, one verdict per (scene, output) -- the table the console, the exit code,
the summary and the NetCDF export read too (:func:`ddgsa.execute.confirm.confirmation_table`)."""

from __future__ import annotations

from html import escape
from typing import TYPE_CHECKING

from ddgsa.execute.confirm import verdicts
from ddgsa.report.sections.base import Folder, Section, Tables, table

if TYPE_CHECKING:  # pragma: no cover
    from ddgsa.execute.kinds.common import StudyResult
    from ddgsa.models.base import ModelOutput


def tables(result: "StudyResult", info: dict[str, "ModelOutput"]) -> Tables:
    pairs = verdicts(result) if len(result.indices) else []
    return [("confirmation.csv", pairs)] if len(pairs) else []


def html(folder: Folder) -> str:
    df = folder.csv("confirmation.csv")
    if df is None or not len(df):
        return ""
    count = df["verdict"].value_counts()
    words = ", ".join(f"{int(n)} {v}" for v, n in count.items())
    shown = df.assign(trusted=df["verdict"] != "unconfirmed")
    return (f"<p>One verdict per (scene, output): {escape(words)}. <em>trusted</em>: every index within the "
            "tolerance; <em>rank-confirmed</em> / <em>confirmed tie</em>: the order by ST certain, ties within the "
            "tie margin; <em>nothing to rank</em>: the output spreads by no more than its resolution; "
            "<em>unconfirmed</em> rows are shaded, with the cheapest next step and its cost.</p>"
            + table(shown, "confirmation", "confirmation.csv"))


SECTION = Section("confirmation", "Verdicts", html, tables=tables, shows=("confirmation.csv",))
