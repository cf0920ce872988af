"""Provenance: what ran, on which code and model, how long (``provenance.json``, written by
:func:`ddgsa.report.write.write_report` after every table)."""

from __future__ import annotations

import json
from html import escape
from typing import Any

from ddgsa.report.sections.base import Folder, Section


def model_words(model: dict[str, Any]) -> str:
    """``fidelity`` and the study's model options (``linear; bending_rayleigh=printed``) of a
    provenance's ``model``: a reader sees which variant ran (seed 000's printed readings are
    options, not fidelities)."""
    options = model.get("options") or {}
    return "; ".join([str(model.get("fidelity", "?")), *(f"{k}={v}" for k, v in options.items())])


def html(folder: Folder) -> str:
    prov = folder.provenance
    if not prov:
        return ""
    model, code, ev = prov.get("model") or {}, prov.get("code") or {}, prov.get("evaluations") or {}
    rows = [("study file", prov.get("study_file")), ("study sha256", prov.get("study_sha256")),
            ("created (UTC)", prov.get("created_utc")),
            ("code", f"ddgsa {code.get('ddgsa', '?')}, commit {str(code.get('commit', '?'))[:12]}"
                     + (" (modified)" if code.get("modified") else "")),
            ("model", f"{model.get('name', '?')} ({model_words(model)})" if model else None),
            ("evaluations", ", ".join(f"{k} {v}" for k, v in ev.items()) if ev else None),
            ("timings [s]", ", ".join(f"{k} {v}" for k, v in (prov.get("timings_s") or {}).items()) or None),
            ("versions", ", ".join(f"{k} {v}" for k, v in (prov.get("versions") or {}).items()) or None),
            ("seeds", json.dumps(prov.get("seeds")) if prov.get("seeds") else None)]
    items = "".join(f"<dt>{escape(k)}</dt><dd>{escape(str(v))}</dd>" for k, v in rows if v)
    return f"<dl>{items}</dl><p>Everything else: <code>provenance.json</code>.</p>"


SECTION = Section("provenance", "Provenance", html)
