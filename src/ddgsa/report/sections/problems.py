"""Problems and what would fix them: each untrusting diagnostic of ``diagnostics.csv`` with where it fired
and its remedy, and the failed evaluations of ``provenance.json``."""

from __future__ import annotations

from html import escape

from ddgsa.report.sections.base import Folder, Section, inline_code

REMEDIES = {
    "mdrm_index_error": "M-DRM's product surrogate misses part of the output (interactions, additive "
                        "structure): add a cross-check (`pce` or `saltelli`) or use `method: auto` with a "
                        "`budget`, which escalates until the rows are trusted.",
    "mdrm_unchecked": "give M-DRM a check sample (`check: 32`); without one its error has no bound.",
    "mdrm_cut_value": "the output is zero or not finite at the cut point: use `pce`, `saltelli` or `auto`.",
    "mdrm_sign_change": "the output changes sign over the nodes, which M-DRM cannot represent: use `pce`, "
                        "`saltelli` or `auto`.",
    "mdrm_rho_sign": "a cut function's mean has the other sign: use `pce`, `saltelli` or `auto`.",
    "mdrm_unresolved": "a cut function is not smooth (kinks, steps): more Gauss `points` or a sampling "
                       "method (`saltelli`).",
    "mdrm_quadrature_coverage": "the Gauss nodes miss the input's tails: more `points`.",
    "salib_index_error": "raise `n` (the error falls like 1/sqrt(n): four times n halves it).",
    "negative_index": "raise `n`: an index below zero by more than its error estimate.",
    "fast_unverified": "FAST and RBD-FAST are cross-checks, never trusted: trust comes from M-DRM, PCE or Saltelli.",
    "pce_index_error": "raise the `order` or the points `n`, or `fit: sparse`.",
    "pce_underdetermined": "fewer points than terms: raise `n` or lower the `order`.",
    "auto_budget_exhausted": "raise `budget`: no stage trusted the output within it.",
    "nonfinite_values": "evaluations failed: see the failure reasons, then narrow the parameter ranges or "
                        "refine the model's step.",
    "zero_variance": "the output is constant over the sample: nothing to rank.",
    "mdrm_zero_variance": "the output is constant over the nodes: nothing to rank.",
}
"""What would fix each untrusting diagnostic (README's table says when each fires)."""


def html(folder: Folder) -> str:
    diag = folder.csv("diagnostics.csv")
    items = []
    if diag is not None and len(diag):
        bad = diag[diag["severity"] == "untrusted"]
        for name, g in bad.groupby("name", sort=False):
            outs = sorted({str(o) for o in g["output"].dropna()})
            where = f" on {', '.join(f'<code>{escape(o)}</code>' for o in outs[:8])}" + \
                (f" and {len(outs) - 8} more" if len(outs) > 8 else "") if outs else ""
            fix = REMEDIES.get(str(name), "see README, \"When M-DRM is not to be trusted\".")
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
