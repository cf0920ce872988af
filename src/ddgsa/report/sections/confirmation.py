"""Verdicts: ``confirmation.csv``, one verdict per (scene, output) -- the table the console, the exit code,
the summary and the NetCDF export read too (:func:`ddgsa.execute.confirm.confirmation_table`)."""

from __future__ import annotations

import re
from html import escape
from typing import TYPE_CHECKING, Any

from ddgsa.execute.confirm import verdict_counts, verdicts
from ddgsa.report.sections.base import Folder, Section, Tables, md_html, table

if TYPE_CHECKING:  # pragma: no cover
    from ddgsa.execute.kinds.common import StudyResult
    from ddgsa.models.base import ModelOutput


def tables(result: "StudyResult", info: dict[str, "ModelOutput"]) -> Tables:
    pairs = verdicts(result) if len(result.indices) else []
    return [("confirmation.csv", pairs)] if len(pairs) else []


def escalation_lines(confirm: list[dict[str, Any]], realisations: int = 1) -> list[str]:
    """One Markdown line per scene of a study's ``confirm:`` escalation (provenance ``confirm``): the runs it
    spent against its budget and how it ended (its log's last line: every output confirmed and by which
    method, a budget spent, the time budget's stop); ``realisations``: runs per point."""
    lines = []
    for c in confirm:
        limits = ([f"{c['budget']} points per scene"] if c.get("budget") is not None else []) + \
                 ([f"{c['time_s']:g} s of wall time"] if c.get("time_s") is not None else [])
        end = (c["log"][-1] if c.get("log") else
               "nothing to escalate (the study's methods had confirmed or found nothing to rank in every output)")
        lines.append(f"- `confirm:` escalation, scene {c['scene']}: {int(c['spent']) * realisations} runs spent "
                     f"(budget: {' and '.join(limits) or 'none'}); last: {end}")
    return lines


def ranking_terms(pair: tuple[float | None, float | None]) -> str:
    """The tie margin and negligible floor a study's rankings are confirmed with (``pair``, the study's
    ``ranking:``, :class:`~ddgsa.study.spec.RankingSpec`; None: each method's trust tolerance), in words."""
    margin, floor = pair
    if margin is None and floor is None:
        return "Tie margin and negligible floor: each method's trust tolerance (the study sets no `ranking:`)."
    own = "each method's trust tolerance"
    return (f"Tie margin {own if margin is None else f'{margin:g}'}, negligible floor "
            f"{own if floor is None else f'{floor:g}'} (the study's `ranking:`).")


def _ranking_pair(ranking: Any) -> tuple[float | None, float | None]:
    """(tie margin, negligible floor) of a study file's ``ranking:`` mapping (None where not set)."""
    ranking = ranking if isinstance(ranking, dict) else {}
    return ranking.get("tie_margin"), ranking.get("negligible")


def html(folder: Folder) -> str:
    df = folder.csv("confirmation.csv")
    if df is None or not len(df):
        return ""
    scenes = folder.study.get("scenes")
    real = int(scenes.get("realisations", 1)) if isinstance(scenes, dict) else 1
    spent = escalation_lines(folder.provenance.get("confirm") or [], real)
    words = ", ".join(verdict_counts(df)[0])
    shown = df.assign(trusted=df["verdict"] != "unconfirmed")
    return (f"<p>One verdict per (scene, output): {escape(words)}. <em>trusted</em>: every index within the "
            "tolerance; <em>rank-confirmed</em> / <em>confirmed tie</em>: the order by ST certain, ties within the "
            "tie margin; <em>nothing to rank</em>: the output spreads by no more than its resolution; "
            "<em>screened</em>: only a screening method ran, its tests name the parameters the output depends on "
            "(a test's answer, not a ranking); "
            "<em>unconfirmed</em> rows are shaded, with the cheapest next step and its cost. "
            + re.sub(r"`([^`]*)`", r"<code>\1</code>", escape(ranking_terms(_ranking_pair(folder.study.get("ranking")))))
            + "</p>"
            + (md_html("\n".join(spent)) if spent else "") + table(shown, "confirmation", "confirmation.csv"))


SECTION = Section("confirmation", "Verdicts", html, tables=tables, shows=("confirmation.csv",))
