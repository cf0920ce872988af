"""How converged a flexible shaft's modal basis is in a scene's band of interest (issue 26).

A model that keeps a few modes of a finite-element shaft declares its :class:`BasisRule` (the class
attribute ``basis_rule``: the rig's in :mod:`ddgsa.models.hss_rig.model`, the direct drive's in
:mod:`ddgsa.models.direct_drive`; docs/physics.md). :func:`basis_report` says which basis a model uses and
how far its modes below the scene's **band of interest** -- 1.5 x the highest frequency an output reads,
the rule's ``band_hz`` -- are from a converged basis (the rule's ``reference``, the same beam theory),
and, above :data:`TOLERANCE`, the smallest basis of the rule's ``ladder`` that would converge them.

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

from ddgsa.models.base import MODELS, BasisRule

TOLERANCE = 0.005
"""Relative frequency error below which a basis counts as converged (the issue's 0.5 %)."""



TABLE = Path(__file__).parents[1] / "data" / "basis_modes.json"
"""Stored standstill modes at nominal parameters of the bases of each rule's ladder and reference
(and the defaults), both beam theories, so that a study on them costs no modal analysis;
:func:`tabulate` writes it, ``tests/models/test_basis.py`` checks it against fresh ones (slow)."""


def rule(model: Any) -> BasisRule | None:
    """The basis rule a model (an instance, a class or a registered name) declares, or ``None``."""
    if isinstance(model, str):
        model = MODELS.lookup(model)
    return getattr(model, "basis_rule", None)


def _model(key: str, **options: Any) -> Any:
    """Model ``key`` built with ``options`` (:func:`ddgsa.models.get`; imported here, when the models are all
    registered, since the models' package imports the modules that declare the rules)."""
    from ddgsa.models import get

    return get(key, **options)


def model_key(model: Any) -> str | None:
    """The registered name of a model that declares a basis rule, else ``None``."""
    return model.name if rule(model) is not None else None


def basis_of(model: Any) -> dict[str, Any] | None:
    """The model's shaft basis as model options, or ``None`` for a model (or fidelity) without one."""
    r = rule(model)
    return None if r is None else r.options(model)


def band_hz(model: Any, scene: Any) -> float:
    """The scene's band of interest [Hz] (the model's rule: :data:`~ddgsa.models.base.BAND_FACTOR` x the highest frequency
    its outputs read)."""
    r = rule(model)
    assert r is not None
    return r.band_hz(model, scene)


def _options_key(options: dict[str, Any]) -> str:
    return json.dumps(options, sort_keys=True)


def _nominal_digest(key: str) -> str:
    """A digest of the model's nominal parameters: the stored table holds only while they do."""
    import hashlib

    r = rule(key)
    assert r is not None
    nominal = r.nominal()
    return hashlib.sha256(json.dumps(nominal, sort_keys=True).encode()).hexdigest()[:16]


@functools.lru_cache(maxsize=1)
def _stored() -> dict[str, Any]:
    return json.loads(TABLE.read_text()) if TABLE.exists() else {}


@functools.lru_cache(maxsize=32)
def _computed(key: str, options: str) -> tuple[tuple[float, str], ...]:
    """Standstill natural frequencies [Hz] and labels at nominal parameters for one basis (cached)."""
    r = rule(key)
    assert r is not None
    modes = _model(key, fidelity=r.fidelity, **json.loads(options)).modes()
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
    """The bases :data:`TABLE` holds for a model: each of its rule's starts (its default basis) and the
    rule's light basis, each with every ladder step, and the reference, for each beam theory (with the
    model's other basis options at their defaults)."""
    r = rule(key)
    assert r is not None
    default = r.options(_model(key, fidelity=r.fidelity))
    assert default is not None
    out: list[dict[str, Any]] = []
    for start in r.starts(default):
        for beam in ("euler_bernoulli", "timoshenko"):
            for base in (start, {**start, **r.light}):
                for step in [{}, *(s for s, _ in r.ladder), r.reference]:
                    basis = {**base, "beam": beam, **step}
                    if basis not in out:
                        out.append(basis)
    return out


def tabulate(path: Path = TABLE, keys: tuple[str, ...] | None = None) -> dict[str, Any]:
    """Compute the modes of every :func:`tabulated_bases` basis of the models ``keys`` (default: every
    registered model that declares a basis rule) and write them to ``path`` (JSON; the other models'
    entries already there are kept)."""
    if keys is None:
        keys = tuple(name for name in MODELS if rule(name) is not None)
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
    from the nearest mode of the converged basis (the rule's ``reference``, the same beam theory), and below
    which frequency every mode of either basis has a partner within :data:`TOLERANCE` (``None`` for a
    model without a basis).

    Returns ``{"basis", "reference", "errors" (one per row of ``table``), "below_hz"}``: ``below_hz`` is
    the lowest frequency [Hz] of a mode of either basis without such a partner (infinite if none).
    """
    key, basis = model_key(model), basis_of(model)
    if key is None or basis is None:
        return None
    reference = {**basis, **rule(model).reference}  # type: ignore[union-attr]
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
    the rule's reference (:func:`worst_error`), ``advice`` (when not converged) the options of the
    first basis of its ladder that is, with its cost ("" if none of them is).
    """
    key, basis = model_key(model), basis_of(model)
    if key is None or basis is None:
        return None
    band = band_hz(model, scene)
    own = dict(basis)
    r = rule(model)
    assert r is not None
    reference = frequencies(key, {**own, **r.reference})
    worst = worst_error(frequencies(key, own), reference, band)
    converged = bool(worst["error"] <= TOLERANCE)
    advice = ""
    if not converged:
        for step, cost in r.ladder:
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
