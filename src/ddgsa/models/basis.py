"""How converged a flexible shaft's modal basis is in a scene's band of interest (issue 26).

The rig (``hss_rig``) and the direct drive (``direct_drive``) keep a few modes of a finite-element
shaft (model options ``bending_modes``, ``beam``, and the rig's ``shaft_elements``, ``shaft_axial``;
docs/physics.md). :func:`basis_report` says which basis a model uses and how far its modes below
the scene's **band of interest** -- 1.5 x the highest frequency an output reads -- are from a
converged basis (:data:`REFERENCE`, the same beam theory), and, above :data:`TOLERANCE`, the
smallest basis of :data:`LADDER` that would converge them.

The band: the rig's outputs read up to the highest frequency its sampling checks name (3 x BPFI,
2 x the supply, the 2x order), capped at the record's Nyquist frequency; the direct drive's read
its loads, whose band is the load interval's Nyquist frequency ``1 / (2 dt)``.

A mode's error is the distance to the nearest mode of the other basis, both ways (a mode the basis
misses counts against its nearest neighbour; one it adds, likewise). The frequencies are the
model's :meth:`modes` at standstill and nominal parameters: stored in :data:`TABLE` for the
bases the advice names (the rich reference costs the rig ~10 s), computed once per process for others.
"""

from __future__ import annotations

import functools
import json
from pathlib import Path
from typing import Any

import numpy as np

TOLERANCE = 0.005
"""Relative frequency error below which a basis counts as converged (the issue's 0.5 %)."""
BAND_FACTOR = 1.5
"""The band of interest is this times the highest frequency an output reads."""

REFERENCE: dict[str, dict[str, Any]] = {
    "hss_rig": {"bending_modes": 10, "shaft_elements": 64, "shaft_axial": True},
    "direct_drive": {"bending_modes": 10},
}
"""The converged basis each model is compared with (its beam theory is the study's): the rig's
5 modes on 32 elements move by <= 0.34 % below 600 Hz against it (docs/physics.md)."""

LADDER: dict[str, list[tuple[dict[str, Any], str]]] = {
    "hss_rig": [({"bending_modes": 3}, "about +11 % time per linear steady run against 2 modes"),
                ({"bending_modes": 5, "shaft_elements": 32, "shaft_axial": True},
                 "the default basis; about +27 % time per linear run and +4 to +15 % per kloss run against "
                 "2 modes on 8 elements")],
    "direct_drive": [({"bending_modes": 3}, "about the time of the default 5 (Timoshenko; 2 Euler-Bernoulli modes "
                                            "cost 0.7-0.85x)"),
                     ({"bending_modes": 5}, "the default; with Timoshenko elements +15 to +40 % per linear run "
                                            "against 2 Euler-Bernoulli modes"),
                     ({"bending_modes": 6}, "+10 % time per linear run against the default 5")],
}
"""Bases tried in order for the advice, with their cost, measured on the shared 2-core machine: the rig's
against the second stage's basis (:data:`LIGHT`; load 2-3, start-up, steady and coast-down at 1500 rpm,
1.2 s, and kloss 0.6 s records), the direct drive's CPU per point of a 64-point batch of 600 s at the
``linear`` fidelity as ``ddgsa bench`` times it (twice in one process, load 11-12; docs/physics.md "Cost of
more modes").
The direct drive's default (5) is converged below 284 Hz, 6 modes below 466 Hz."""

LIGHT: dict[str, dict[str, Any]] = {
    "hss_rig": {"bending_modes": 2, "shaft_elements": 8, "shaft_axial": False},
    "direct_drive": {"bending_modes": 2},
}
"""The second stage's default bases (the rig's 2 modes per plane on 8 elements, axially rigid, is 2.5 %
high on its first pair and 44 % low on the disk's 1x amplitude at the critical speed): tabulated
with the ladder's steps from them, for studies that keep them for speed."""

TABLE = Path(__file__).parents[1] / "data" / "basis_modes.json"
"""Stored standstill modes at nominal parameters of the bases of :data:`LADDER` and :data:`REFERENCE`
(and the defaults), both beam theories, so that a study on them costs no modal analysis;
:func:`tabulate` writes it, ``tests/models/test_basis.py`` checks it against fresh ones (slow)."""


def basis_of(model: Any) -> dict[str, Any] | None:
    """The model's shaft basis as model options, or ``None`` for a model (or fidelity) without one."""
    key = model_key(model)
    if key == "hss_rig":
        b = model.basis
        return {"bending_modes": b.bending_modes, "beam": b.beam, "shaft_elements": b.elements_per_span,
                "shaft_axial": b.axial}
    if key == "direct_drive" and model.fields:                            # not the rigid fidelity
        return {"bending_modes": sum(f.startswith("bending_y") for f in model.fields), "beam": model.beam,
                "axial": "axial" in model.fields, "shaft": model.shaft}
    return None


def model_key(model: Any) -> str | None:
    """``hss_rig`` or ``direct_drive`` for the models this module knows, else ``None``."""
    cls = type(model).__name__
    return {"HssRig": "hss_rig", "DirectDrive": "direct_drive"}.get(cls)


def band_hz(model: Any, scene: Any) -> float:
    """The scene's band of interest [Hz]: :data:`BAND_FACTOR` x the highest frequency the outputs read."""
    if model_key(model) == "hss_rig":
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rows = model.sampling_checks(scene)
        sc = model._scene(scene)
        return min(BAND_FACTOR * max(r["frequency_hz"] for r in rows), 0.5 * sc.sample_rate)
    return BAND_FACTOR * 0.5 / float(scene.dt)


def _options_key(options: dict[str, Any]) -> str:
    return json.dumps(options, sort_keys=True)


def _nominal_digest(key: str) -> str:
    """A digest of the model's nominal parameters: the stored table holds only while they do."""
    import hashlib

    from ddgsa.models import MODELS

    nominal = {p.name: p.nominal for p in MODELS.lookup(key).parameters}
    if key == "direct_drive":                   # the shaft readings' nominal values (issue 47), not the default's only
        from ddgsa.models.direct_drive import shaft_parameters
        from ddgsa.models.seed_readings import SHAFT

        nominal = {s: {p.name: p.nominal for p in shaft_parameters(s)} for s in SHAFT}  # type: ignore[misc]
    return hashlib.sha256(json.dumps(nominal, sort_keys=True).encode()).hexdigest()[:16]


@functools.lru_cache(maxsize=1)
def _stored() -> dict[str, Any]:
    return json.loads(TABLE.read_text()) if TABLE.exists() else {}


@functools.lru_cache(maxsize=32)
def _computed(key: str, options: str) -> tuple[tuple[float, str], ...]:
    """Standstill natural frequencies [Hz] and labels at nominal parameters for one basis (cached)."""
    from ddgsa.models import get as get_model

    fidelity = "kloss" if key == "hss_rig" else "flexible"
    modes = get_model(key, fidelity=fidelity, **json.loads(options)).modes()
    return tuple((float(f), str(lab)) for f, lab in zip(modes["frequency_hz"], modes["label"]))


def frequencies(key: str, options: dict[str, Any], stored: bool = True) -> tuple[tuple[float, str], ...]:
    """Standstill modes ``(frequency [Hz], label)`` of model ``key`` on the basis ``options`` at
    nominal parameters: from :data:`TABLE` where it holds them (and the nominal parameters are
    those it was made with), else computed once per process."""
    table = _stored().get(key, {}) if stored else {}
    entry = table.get("bases", {}).get(_options_key(options))
    if entry is not None and table.get("nominal") == _nominal_digest(key):
        return tuple((float(f), str(lab)) for f, lab in entry)
    return _computed(key, _options_key(options))


def tabulated_bases(key: str) -> list[dict[str, Any]]:
    """The bases :data:`TABLE` holds for a model: its default and :data:`LIGHT`, each with every
    :data:`LADDER` step, and :data:`REFERENCE`, for each beam theory (with the model's other basis
    options at their defaults), and for the direct drive each shaft reading."""
    from ddgsa.models import get as get_model

    default = basis_of(get_model(key, fidelity="kloss" if key == "hss_rig" else "flexible"))
    assert default is not None
    defaults = [default]
    if key == "direct_drive":                   # each shaft reading (issue 47), the default's first
        from ddgsa.models.seed_readings import SHAFT

        defaults += [{**default, "shaft": s} for s in SHAFT if s != default["shaft"]]
    out: list[dict[str, Any]] = []
    for start in defaults:
        for beam in ("euler_bernoulli", "timoshenko"):
            for base in (start, {**start, **LIGHT[key]}):
                for step in [{}, *(s for s, _ in LADDER[key]), REFERENCE[key]]:
                    basis = {**base, "beam": beam, **step}
                    if basis not in out:
                        out.append(basis)
    return out


def tabulate(path: Path = TABLE, keys: tuple[str, ...] = tuple(REFERENCE)) -> dict[str, Any]:
    """Compute the modes of every :func:`tabulated_bases` basis of the models ``keys`` and write them to
    ``path`` (JSON; the other models' entries already there are kept)."""
    table = json.loads(path.read_text()) if path.exists() else {}
    table.update({key: {"nominal": _nominal_digest(key),
                        "bases": {_options_key(b): [[round(f, 6), lab] for f, lab in _computed(key, _options_key(b))]
                                  for b in tabulated_bases(key)}}
                  for key in keys})
    path.write_text(json.dumps(table, indent=1) + "\n")
    _stored.cache_clear()
    return table


def worst_error(modes: tuple[tuple[float, str], ...], reference: tuple[tuple[float, str], ...],
                band: float) -> dict[str, Any]:
    """The largest relative distance between a mode below ``band`` [Hz] of either set and the
    nearest mode of the other: ``{"error", "frequency_hz", "reference_hz", "label"}``."""
    f = np.array([m[0] for m in modes])
    r = np.array([m[0] for m in reference])
    worst: dict[str, Any] = {"error": 0.0, "frequency_hz": None, "reference_hz": None, "label": ""}
    for j, fr in enumerate(r):                                 # every reference mode: is it there?
        if fr < band:
            near = f[np.argmin(np.abs(f - fr))]
            if abs(near - fr) / fr > worst["error"]:
                worst = {"error": float(abs(near - fr) / fr), "frequency_hz": float(near), "reference_hz": float(fr),
                         "label": reference[j][1]}
    for i, fi in enumerate(f):                                 # every mode of the basis: is it real?
        if fi < band:
            near = r[np.argmin(np.abs(r - fi))]
            if abs(fi - near) / near > worst["error"]:
                worst = {"error": float(abs(fi - near) / near), "frequency_hz": float(fi), "reference_hz": float(near),
                         "label": modes[i][1]}
    return worst


def mode_convergence(model: Any, table: Any) -> dict[str, Any] | None:
    """How far each mode of ``table`` (the model's :meth:`modes` at nominal parameters, standstill) is
    from the nearest mode of the converged basis (:data:`REFERENCE`, the same beam theory), and below
    which frequency every mode of either basis has a partner within :data:`TOLERANCE` (``None`` for a
    model without a basis).

    Returns ``{"basis", "reference", "errors" (one per row of ``table``), "below_hz"}``: ``below_hz`` is
    the lowest frequency [Hz] of a mode of either basis without such a partner (infinite if none).
    """
    key, basis = model_key(model), basis_of(model)
    if key is None or basis is None:
        return None
    reference = {**basis, **REFERENCE[key]}
    ref = np.array([f for f, _ in frequencies(key, reference)])
    own = np.asarray(table["frequency_hz"], dtype=float)
    near = ref[np.argmin(np.abs(ref[None, :] - own[:, None]), axis=1)]
    errors = np.abs(own - near) / near
    missing = np.abs(ref - own[np.argmin(np.abs(own[None, :] - ref[:, None]), axis=1)]) / ref
    unpaired = [*own[errors > TOLERANCE], *ref[missing > TOLERANCE]]
    return {"basis": basis, "reference": reference, "errors": errors,
            "below_hz": float(min(unpaired)) if unpaired else float("inf")}


def basis_report(model: Any, scene: Any) -> dict[str, Any] | None:
    """The model's basis and its convergence in the scene's band, or ``None`` without a basis.

    Returns ``{"basis", "band_hz", "error", "frequency_hz", "reference_hz", "label", "converged",
    "advice"}``: ``error`` is the worst relative frequency error below the band against
    :data:`REFERENCE` (:func:`worst_error`), ``advice`` (when not converged) the options of the
    first :data:`LADDER` basis that is, with its cost ("" if none of them is).
    """
    key, basis = model_key(model), basis_of(model)
    if key is None or basis is None:
        return None
    band = band_hz(model, scene)
    own = dict(basis)
    reference = frequencies(key, {**own, **REFERENCE[key]})
    worst = worst_error(frequencies(key, own), reference, band)
    converged = bool(worst["error"] <= TOLERANCE)
    advice = ""
    if not converged:
        for step, cost in LADDER[key]:
            if all(own.get(k) == v for k, v in step.items()):
                continue
            trial = {**own, **step}
            if worst_error(frequencies(key, trial), reference, band)["error"] <= TOLERANCE:
                words = ", ".join(f"{k}: {json.dumps(v)}" for k, v in step.items())
                advice = f"set model options {words}: {cost}"
                break
    return {"basis": basis, "band_hz": band, **worst, "converged": converged, "advice": advice}


def basis_words(report: dict[str, Any]) -> str:
    """One sentence on a :func:`basis_report`: the basis, the band and its worst mode error."""
    basis = ", ".join(f"{k} {json.dumps(v)}" for k, v in report["basis"].items())
    text = (f"shaft basis {basis}: its natural frequencies below {report['band_hz']:.0f} Hz (1.5 x the highest "
            f"frequency an output reads) are within {report['error']:.2%} of a converged basis")
    if report["error"] > 0:
        text += (f" (worst: {report['label']} {report['frequency_hz']:.2f} Hz against "
                 f"{report['reference_hz']:.2f} Hz)")
    if not report["converged"]:
        text += (f", more than {TOLERANCE:.1%}: " + (report["advice"] or "no basis of docs/physics.md's tables "
                                                      "converges it; raise bending_modes"))
    return text
