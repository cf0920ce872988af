"""Problems and what would fix them: each untrusting diagnostic of ``diagnostics.csv`` with where it fired
and its remedy (:data:`ddgsa.gsa.trust.REMEDIES`, beside the rules that raise them), and the failed
evaluations of ``provenance.json``."""

from __future__ import annotations

from html import escape

from ddgsa.gsa.trust import REMEDIES
from ddgsa.report.sections.base import Folder, Section, inline_code



def html(folder: Folder) -> str:
    diag = folder.csv("diagnostics.csv")
    items = []
    if diag is not None and len(diag):
        bad = diag[diag["severity"] == "untrusted"]
        for name, g in bad.groupby("name", sort=False):
            outs = sorted({str(o) for o in g["output"].dropna()})
            where = f" on {', '.join(f'<code>{escape(o)}</code>' for o in outs[:8])}" + \
                (f" and {len(outs) - 8} more" if len(outs) > 8 else "") if outs else ""
            fix = REMEDIES.get(str(name), "see docs/methods.md, \"When M-DRM is not to be trusted\".")
            items.append(f"<li><code>{escape(str(name))}</code> ({', '.join(sorted(set(g['method'].astype(str))))}, "
                         f"{len(g)} rows{where}). <b>Fix:</b> {inline_code(fix)}</li>")
    failures = folder.provenance.get("failures") or []
    if failures:
        items.append(f"<li>{len(failures)} evaluations failed (their indices are refused, never imputed). "
                     f"<b>Fix:</b> {inline_code(REMEDIES['nonfinite_values'])}</li>")
    if not items:
        return "<p>None: every method's rows are trusted and no evaluation failed.</p>" if diag is not None else ""
    return f"<ul>{''.join(items)}</ul>"


SECTION = Section("problems", "Problems and what would fix them", html)
