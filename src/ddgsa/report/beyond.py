"""The report's tables and plot for what plain S1/ST do not show: group indices, Shapley effects
and HSIC screening (:mod:`ddgsa.gsa.groups`, :mod:`ddgsa.gsa.shapley`, :mod:`ddgsa.gsa.hsic`).

Shapley and HSIC columns are part of ``indices.csv``; group indices go to ``groups.csv`` (one
row per scene, method, output and group; its section: :mod:`ddgsa.report.sections.groups`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from ddgsa.gsa.groups import GROUP_COLUMNS

if TYPE_CHECKING:  # pragma: no cover
    from ddgsa.execute.kinds.common import StudyResult


def group_table(result: "StudyResult") -> pd.DataFrame:
    """Every method's group indices per scene: ``scene, method`` and :data:`GROUP_COLUMNS`."""
    rows = [res.groups.assign(scene=ps.index, method=res.method) for ps, res in result.results if len(res.groups)]
    if not rows:
        return pd.DataFrame(columns=["scene", "method", *GROUP_COLUMNS])
    return pd.concat(rows, ignore_index=True)[["scene", "method", *GROUP_COLUMNS]]


def _pm(value: float, conf: float) -> str:
    return f"{value:.3f}" + (f" ± {conf:.3f}" if np.isfinite(conf) else "")


def beyond_markdown(result: "StudyResult") -> list[str]:
    """``summary.md``'s sections on groups, Shapley effects and HSIC screening (empty when none ran)."""
    lines: list[str] = []
    groups = group_table(result)
    if len(groups):
        lines += ["## Groups: closed and total indices", "",
                  "S_closed = what the group explains alone (its members' interactions among themselves included); "
                  "ST = what it takes part in at all; ± the method's error bound (`groups.csv`); trusted = both "
                  "within the tolerance by that bound; rank = the confirmed place by ST.", "",
                  "| scene | output | method | group (members) | S_closed | ST | trusted | rank |",
                  "|---|---|---|---|---|---|---|---|"]
        lines += [f"| {r.scene} | `{r.output}` | {r.method} | {r.group} ({r.members}) | "
                  f"{_pm(r.S_closed, r.S_closed_conf)} | {_pm(r.ST, r.ST_conf)} | {'yes' if r.trusted else 'no'} | "
                  f"{r.rank or '-'} |" for r in groups.itertuples()]
        lines.append("")
    idx = result.indices
    if "Sh" in idx and idx["Sh"].notna().any():
        sh = idx[idx["Sh"].notna()]
        lines += ["## Shapley effects (dependent inputs)", "",
                  "Sh = the parameter's fair share of the variance, correlations included (the shares sum to 1); "
                  "S1 = full first-order index (with what it is correlated with), ST = independent total index "
                  "(beyond what it is correlated with); ± bootstrap half-width.", "",
                  "| scene | output | parameter | Sh | S1 (full) | ST (independent) |", "|---|---|---|---|---|---|"]
        lines += [f"| {r.scene} | `{r.output}` | {r.parameter} | {_pm(r.Sh, r.Sh_conf)} | {_pm(r.S1, r.S1_conf)} | "
                  f"{_pm(r.ST, r.ST_conf)} |" for r in sh.sort_values(["scene", "output", "Sh"],
                                                                      ascending=[True, True, False]).itertuples()]
        lines.append("")
    if "p_value" in idx and idx["p_value"].notna().any():
        h = idx[idx["p_value"].notna()]
        lines += ["## HSIC screening", "",
                  "R2_HSIC = normalised dependence of the output on the parameter (0: independent); p = permutation-"
                  "test p-value of independence; screened in where p < alpha.", "",
                  "| scene | output | parameter | R2_HSIC | p-value | screened in |", "|---|---|---|---|---|---|"]
        lines += [f"| {r.scene} | `{r.output}` | {r.parameter} | {r.R2_HSIC:.3f} | {r.p_value:.3f} | "
                  f"{'yes' if r.screened_in else 'no'} |"
                  for r in h.sort_values(["scene", "output", "R2_HSIC"], ascending=[True, True, False]).itertuples()]
        lines.append("")
    return lines
