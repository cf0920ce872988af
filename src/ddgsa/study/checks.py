"""The model's own checks over a whole study, before anything runs (``ddgsa validate`` and ``ddgsa run``).

:func:`ddgsa.study.spec.load_study` checks the schema, names, ranges and units. What it cannot see
without asking the model is checked here, over everything the study would run:

* **sampling** of every scene: the model's :meth:`~ddgsa.models.base.Model.sampling_checks`
  (e.g. the rig's sensor sample rate against its orders and defect frequencies). A scene the
  model refuses (an aliased record) is an error; a coarse one gives the model's note.
* **the valid region** over the parameters' support: the corners of the support (at most
  :data:`MAX_CORNERS` of them) and a :data:`SAMPLE`-point Sobol' sample, with the study's fixed
  values, through :meth:`~ddgsa.models.base.Model.point_problems` (e.g. the direct drive's
  bearings that must not cross). Every checked point invalid is an error; some invalid is a
  warning that says how many and the first reason (those evaluations fail and are never imputed).
* **parameters without effect** at the study's fidelity
  (:meth:`~ddgsa.models.base.Model.unused_parameters`), warned by name with the reason.
* **the shaft's modal basis** (``hss_rig``, ``direct_drive``): which basis the model uses and how
  far its modes below each scene's band of interest are from a converged basis
  (:func:`ddgsa.models.basis.basis_report`); a note when within 0.5 %, else a warning naming the
  model options that would converge it and their cost.
* **unit hints**: a number that looks written in another unit (a ``speed_rpm`` of 25 that reads
  like Hz; a parameter 1000x its model's nominal value).
"""

from __future__ import annotations

import itertools
import math
import warnings
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from ddgsa.errors import DdgsaError
from ddgsa.mbs.sampling import AliasingWarning
from ddgsa.study.spec import Study, plan_scenes, scene_text
from ddgsa.units import prefixed_unit, scene_hints

SAMPLE = 64
"""Sobol' points of the support checked against the model's valid region."""
MAX_CORNERS = 1024
"""Corners of the support checked (all of them up to 10 parameters)."""
TAIL = 1e-3
"""Probability cut from each tail of an unbounded distribution to give its "corners"."""
SLIP = 100.0
"""A value this many times above or below its model's nominal value gets a unit hint: a warning (shown
under ``-q`` too) where a unit prefix would bring it back to the nominal's order, else a hint."""


@dataclass(frozen=True)
class Finding:
    """One result of a check: an ``error`` refuses the study, a ``warning`` says what will fail,
    a ``hint`` what may be meant (and a ``note`` passes on a model's sampling remark)."""

    level: Literal["error", "warning", "hint", "note"]
    field: str
    message: str

    def __str__(self) -> str:
        return f"field '{self.field}': {self.message}"


def study_findings(study: Study, sample: int = SAMPLE) -> list[Finding]:
    """Every finding of the checks above, errors first."""
    model = study.make_model()
    found = [*_sampling(study, model), *_region(study, model, sample), *_cut_problems(study, model),
             *_unused(study, model), *_basis(study, model), *_unit_hints(study, model),
             *_sobol_sizes(study)]
    order = {"error": 0, "warning": 1, "note": 2, "hint": 3}
    return sorted(found, key=lambda f: order[f.level])


def _sampling(study: Study, model: Any) -> list[Finding]:
    """The model's sampling checks for every scene of the grid (its first realisation)."""
    out: list[Finding] = []
    seen: set[str] = set()
    for ps in plan_scenes(study):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", AliasingWarning)
            try:
                model.sampling_checks(ps.scenes[0])
            except DdgsaError as exc:
                out.append(Finding("error", "scenes", f"scene {ps.index} ({scene_text(ps.fields)}): {exc}; every "
                                                      "evaluation of this scene would fail"))
        for w in caught:
            if issubclass(w.category, AliasingWarning) and str(w.message) not in seen:
                seen.add(str(w.message))
                out.append(Finding("note", "scenes", f"scene {ps.index} ({scene_text(ps.fields)}): {w.message}"))
    return out


def support_points(study: Study, sample: int = SAMPLE) -> list[dict[str, float]]:
    """The checked points: the support's corners (tails cut at :data:`TAIL` where unbounded) and a
    Sobol' sample, each with the study's fixed values."""
    space = study.space
    fixed = {k: float(v) for k, v in study.spec.fixed.items()}
    if space is None:
        return [fixed]
    ends = [(p.ppf(np.array([TAIL]))[0] if not math.isfinite(p.support[0]) else p.support[0],
             p.ppf(np.array([1 - TAIL]))[0] if not math.isfinite(p.support[1]) else p.support[1])
            for p in space.parameters]
    corners = itertools.islice(itertools.product(*ends), MAX_CORNERS)
    points = [dict(zip(space.names, map(float, c))) for c in corners]
    points += [dict(zip(space.names, map(float, row))) for row in space.sample(sample, seed=0)]
    return [{**fixed, **p} for p in points]


def _cut_problems(study: Study, model: Any) -> list[Finding]:
    """M-DRM's cut point outside the valid region: every cut line runs through it, so all but the
    cut parameter's own line would fail and the method's indices are refused; an error, not a warning."""
    from ddgsa.gsa.base import get_method

    space, out = study.space, []
    if space is None:
        return out
    fixed = {k: float(v) for k, v in study.spec.fixed.items()}
    for i, m in enumerate(study.spec.methods):
        if m.method != "mdrm":
            continue
        cut = get_method("mdrm").design(space, **m.options).points[0]          # the design's first point
        point = {**fixed, **dict(zip(space.names, map(float, cut)))}
        problems = model.point_problems(point)
        if problems:
            at = ", ".join(f"{k}={point[k]:.4g}" for k in space.names)
            out.append(Finding("error", f"methods[{i}]", f"M-DRM's cut point ({at}; the inputs' means unless "
                               f"`cut:` says otherwise) lies outside the valid region of model "
                               f"{study.spec.model.name!r}: {problems[0]}; every cut line runs through it, so its "
                               "evaluations would fail: move the inputs' means (or `cut:`) into the valid region"))
    return out


def _region(study: Study, model: Any, sample: int) -> list[Finding]:
    points = support_points(study, sample)
    bad = [(p, problems) for p in points if (problems := model.point_problems(p))]
    if not bad or study.space is None:
        return []
    point, problems = bad[0]
    at = ", ".join(f"{k}={point[k]:.4g}" for k in study.space.names)
    text = (f"{len(bad)} of {len(points)} checked points of the parameters' support (its corners and a {sample}-point "
            f"sample) lie outside the valid region of model {study.spec.model.name!r}; first at {at}: {problems[0]}")
    if len(bad) == len(points):
        return [Finding("error", "parameters", text + "; every evaluation would fail")]
    return [Finding("warning", "parameters", text + "; evaluations there will fail (never imputed) and the methods "
                                                    "that need them will be refused: narrow the support")]


def _sobol_sizes(study: Study) -> list[Finding]:
    """A method option that sets a number of Sobol' points other than a power of two (scipy's own
    warning is silenced where ddgsa draws them): the sequence's balance is lost, so its integration
    error falls more slowly; a hint naming the field and the two nearest powers of two."""
    from ddgsa.gsa.base import get_method

    out: list[Finding] = []
    for i, m in enumerate(study.spec.methods):
        try:
            keys = get_method(m.method).sobol_sizes
        except DdgsaError:
            continue
        for key in keys:
            n = m.options.get(key)
            if isinstance(n, int) and not isinstance(n, bool) and n > 2 and n & (n - 1):
                low = 1 << (n.bit_length() - 1)
                out.append(Finding("hint", f"methods[{i}].{key}",
                                   f"{n} Sobol' points are not a power of two, which loses the sequence's "
                                   f"balance (its error falls more slowly with n); use {low} or {2 * low}"))
    return out


def _unused(study: Study, model: Any) -> list[Finding]:
    """Uncertain parameters the model ignores at the study's fidelity (their indices are 0 by construction)."""
    unused = model.unused_parameters()
    return [Finding("warning", f"parameters.{name}", f"{unused[name]}: its indices are 0 by construction and "
                                                    "its evaluations are spent for nothing")
            for name in study.spec.parameters if name in unused]


def study_basis(study: Study, model: Any | None = None) -> list[dict[str, Any]]:
    """:func:`~ddgsa.models.basis.basis_report` for each scene of the grid (its first realisation),
    ``{"scene", **report}``; empty for a model without a shaft basis. A report that fails says so
    (``"error"`` holds the reason) instead of raising."""
    from ddgsa.models.basis import basis_of, basis_report, model_key

    model = model if model is not None else study.make_model()
    if model_key(model) is None or basis_of(model) is None:
        return []
    out: list[dict[str, Any]] = []
    for ps in plan_scenes(study):
        try:
            report = basis_report(model, ps.scenes[0])
        except (DdgsaError, ArithmeticError, RuntimeError, ValueError, np.linalg.LinAlgError) as exc:
            out.append({"scene": ps.index, "error": f"not checked: {type(exc).__name__}: {exc}"})
            continue
        if report is not None:
            out.append({"scene": ps.index, **report})
    return out


def basis_messages(rows: list[dict[str, Any]]) -> list[tuple[bool, str]]:
    """``(converged, sentence)`` for :func:`study_basis` rows, scenes with the same sentence joined."""
    from ddgsa.models.basis import basis_words

    texts: dict[str, tuple[bool, list[int]]] = {}
    for r in rows:
        text = r["error"] if isinstance(r.get("error"), str) else basis_words(r)
        ok = bool(r.get("converged", True))
        texts.setdefault(text, (ok, []))[1].append(r["scene"])
    return [(ok, f"scene{'s' * (len(sc) > 1)} {', '.join(map(str, sc))}: {text}") for text, (ok, sc) in texts.items()]


def _basis(study: Study, model: Any) -> list[Finding]:
    return [Finding("note" if ok else "warning", "model.options", text)
            for ok, text in basis_messages(study_basis(study, model))]


def _unit_hints(study: Study, model: Any) -> list[Finding]:
    out = [Finding("hint", f"scenes.{k}", h) for k, h in scene_hints(type(plan_scenes(study)[0].scenes[0]),
                                                                      _scene_values(study))]
    values = {**{k: float(v) for k, v in study.spec.fixed.items()},
              **(study.space.nominal if study.space is not None else {})}
    section = {k: "fixed" for k in study.spec.fixed} | {k: "parameters" for k in study.spec.parameters}
    for name, value in values.items():
        decl = model.parameter(name)
        if decl.nominal > 0 and value > 0:
            ratio = value / decl.nominal
            if ratio >= SLIP or ratio <= 1 / SLIP:
                scale = 10.0 ** min(6, max(-6, 3 * round(-math.log10(ratio) / 3)))
                unit = prefixed_unit(decl.unit, scale) if scale != 1.0 else None
                example = f" (e.g. unit: {unit} if the number is in {unit})" if unit else ""
                out.append(Finding("warning" if unit else "hint", f"{section[name]}.{name}",
                                   f"{value:.4g} {decl.unit} is {max(ratio, 1 / ratio):,.0f}x "
                                   f"{'above' if ratio > 1 else 'below'} the model's nominal {decl.nominal:.4g} "
                                   f"{decl.unit}; numbers are in {decl.unit} unless a unit is written{example}"))
    return out


def _scene_values(study: Study) -> dict[str, list[Any]]:
    out: dict[str, list[Any]] = {}
    for ps in plan_scenes(study):
        for key, value in ps.scenes[0].to_dict().items():
            out.setdefault(key, []).append(value)
    return out


def evaluation_plan(study: Study) -> str:
    """What the study will evaluate, per method and in total, with every sample a method adds of
    its own (e.g. M-DRM's check sample, option ``check``, default 32) named; methods share equal
    points, which run once. A sweep: its grid points (the full factorial, one point without a grid) x
    variants x scenes x realisations. Empty for a study without methods or with ``method: auto``."""
    from ddgsa.gsa.base import get_method

    sc = study.spec.scenes
    n_scenes = len(sc.grid())
    times = (f" x {n_scenes} scene{'s' * (n_scenes != 1)} x {sc.realisations} "
             f"realisation{'s' * (sc.realisations != 1)}")
    if study.spec.kind == "sweep":
        points = math.prod(len(v) for v in study.spec.grid.values())
        variants = len(study.spec.model.variants)
        runs = points * max(variants, 1) * n_scenes * sc.realisations
        return (f"evaluations: {points} grid point{'s' * (points != 1)}"
                + (f" x {variants} variant{'s' * (variants != 1)}" if variants else "") + f"{times} = {runs} model runs")
    space = study.space
    if space is None or not study.spec.methods or any(m.method == "auto" for m in study.spec.methods):
        return ""
    parts, blocks = [], []
    for m in study.spec.methods:
        design = get_method(m.method).design(space, **m.options)
        blocks.append(design.points)
        check = design.options.get("check")
        inert = f"; up to {check} more for its inert check" if check and design.options.get("inert_check") else ""
        extra = f" (including its {check}-point check sample; set by the method's `check:` option{inert})" if check else ""
        parts.append(f"{m.method} {len(design.points)}{extra}")
    distinct = len(np.unique(np.vstack(blocks), axis=0))
    runs = distinct * n_scenes * sc.realisations
    return (f"evaluations per scene and realisation: {', '.join(parts)}; {distinct} distinct points (equal points "
            f"run once){times} = {runs} model runs")
