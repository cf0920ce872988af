"""Study files: the YAML schema, its validation, and the plan (which model runs a study needs).

A study names a model and fidelity, the uncertain parameters, a grid of scenes with
realisations, the outputs, the GSA methods and how to run them. Everything is validated
before anything runs; every error names the file, the field path and what is allowed.

Minimal example::

    name: quickstart
    model: {name: direct_drive, fidelity: rigid}
    parameters:
      k_front_z: {nominal: 1e10, spread: 0.2}
      c_gen: {dist: normal, mean: 828.26e3, std: 41.4e3}
    scenes: {wind_speed: [11.0], duration: 60, realisations: 2}
    outputs: [damage_front, damage_rear]
    methods:
      - {method: mdrm, points: 4}
      - {method: saltelli, n: 64}

Kinds: ``gsa`` (default: Sobol indices per scene), ``sweep`` (no uncertain parameters:
objective functions over the scene grid and realisations, e.g. seed 000 §4; optionally over a
full-factorial ``grid`` of parameter values and ``model.variants``, lists of option overrides
run one after the other, e.g. seed 003's frequencies per configuration) and ``fault``
(fault detectability: a ``fault`` block names a parameter, its healthy value and faulty levels,
measurement noise per output, the false-alarm rate, POD target and confidence level; see
:mod:`ddgsa.detection`).
"""

from __future__ import annotations

import csv
import dataclasses
import hashlib
import itertools
import json
import re
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Literal, NoReturn

import numpy as np

from pydantic import (BaseModel, ConfigDict, Field, PrivateAttr, ValidationError, ValidationInfo,
                      field_validator, model_validator)
from pydantic_core import InitErrorDetails, PydanticCustomError

from ddgsa.errors import DdgsaError, StudyError, clip, unknown_name_message, with_hint
from ddgsa.gsa.auto import resolve_auto_options
from ddgsa.gsa.base import METHODS, get_method
from ddgsa.gsa.escalate import MAX_BUDGET
from ddgsa.gsa.target import Target
from ddgsa.loads.scene import Scene
from ddgsa.models import MODELS
from ddgsa.models import get as get_model
from ddgsa.gsa.space import ParameterSpace
from ddgsa.models.base import ModelOutput, declared
from ddgsa.units import UnitError, convert, factor, has_unit, parameter_in, scene_hints
from ddgsa.study.limits import (MAX_NAME_CHARS, check_names, check_run_size, load_yaml,  # bounded input, run size
                                read_text, refuse_unordered, scenes_to_check)

_STRICT = ConfigDict(extra="forbid")

_LATER_DEFAULTS: dict[tuple[str, str], Any] = {("scenes", "loads"): {"fidelity": "table",
                                                                     "inclination_convention": "upflow"},
                                               ("fault", "design"): "population",
                                               ("confirm", "time"): None, ("run", "timeout"): None}
"""Study fields added in the third stage, with their defaults: left out of :attr:`Study.digest` at
the default (the scene's rotor aerodynamics and inclination convention, key by key; the fault
study's design; the confirmation's time budget; the run's timeout)."""


_LATER_EMPTY = ("groups", "correlation", "target", "signals")
"""Top-level study fields added in the third stage's second round: left out of :attr:`Study.digest` when empty."""


class StudyWarning(UserWarning):
    """A valid study that will probably not give what its author wants."""


SceneValue = float | list[float]


class AutoSpec(BaseModel):
    """``model.auto:`` -- how ``fidelity: auto`` chooses per scene."""

    model_config = _STRICT
    tolerance: float = Field(0.02, gt=0, description="largest relative output error allowed vs the richest fidelity")
    pilot: int = Field(4, ge=1, le=256, description="space-filling pilot points besides the nominal one")
    seed: int = Field(7, ge=0)


class ModelSpec(BaseModel):
    """``model:`` -- registry name, fidelity (or ``auto``) and model options."""

    model_config = _STRICT
    name: str
    fidelity: str | None = Field(None, description="a fidelity of the model, or auto (default: its richest)")
    options: dict[str, Any] = Field(default_factory=dict)
    auto: AutoSpec = Field(default_factory=AutoSpec)
    variants: list[dict[str, Any]] = Field(
        default_factory=list, description="option overrides, one sweep per entry (kind: sweep only)")


class LoadsSpec(BaseModel):
    """``scenes.loads:`` -- how the wind scenes' hub loads are computed (:mod:`ddgsa.loads`)."""

    model_config = _STRICT
    fidelity: Literal["table", "bem", "auto"] = Field(
        Scene.loads_fidelity, description="rotor aerodynamics: quasi-steady Cp/Ct table, blade-element "
        "momentum, or auto (bem where |inclination_deg| >= ddgsa.loads.scene.AUTO_BEM_INCLINATION_DEG)")
    inclination_convention: Literal["upflow", "downflow_horizontal"] = Field(
        Scene.inclination_convention, description="upflow: positive inclination_deg tilts the flow upwards, "
        "wind_speed along the flow; downflow_horizontal: positive tilts it downwards, wind_speed horizontal")


class ScenesSpec(BaseModel):
    """``scenes:`` -- a grid over the list-valued fields; every grid point has ``realisations`` seeds."""

    model_config = _STRICT
    # defaults are the Scene's own (one source of truth)
    wind_speed: SceneValue = Scene.wind_speed
    turbulence_intensity: SceneValue = Scene.turbulence_intensity
    inclination_deg: SceneValue = Scene.inclination_deg
    shear_exponent: SceneValue = Scene.shear_exponent
    duration: float = Scene.duration
    dt: float = Scene.dt
    realisations: int = Field(1, ge=1, le=1000)
    seed: int = Field(Scene.seed, ge=0)
    aggregate: Literal["mean", "median", "max"] = "mean"
    loads: LoadsSpec = Field(default_factory=LoadsSpec)

    @field_validator("wind_speed", "turbulence_intensity", "inclination_deg", "shear_exponent")
    @classmethod
    def _non_empty(cls, v: SceneValue) -> SceneValue:
        if isinstance(v, list) and not v:
            raise ValueError("an empty list gives an empty scene grid; give at least one value")
        return v

    def grid(self) -> list[dict[str, float]]:
        """The scene grid (without seeds): one dict per combination of the list-valued fields."""
        axes = {k: (v if isinstance(v, list) else [v]) for k, v in
                (("wind_speed", self.wind_speed), ("turbulence_intensity", self.turbulence_intensity),
                 ("inclination_deg", self.inclination_deg), ("shear_exponent", self.shear_exponent))}
        return [dict(zip(axes, combo)) for combo in itertools.product(*axes.values())]

    def scene(self, fields: dict[str, float], realisation: int) -> Scene:
        """The scene of one grid point and realisation (turbulence seed ``seed + realisation``)."""
        return Scene(**fields, duration=self.duration, dt=self.dt, seed=self.seed + realisation,
                     loads_fidelity=self.loads.fidelity, inclination_convention=self.loads.inclination_convention)


WIND_LABEL_FIELDS = ("wind_speed", "turbulence_intensity", "inclination_deg", "shear_exponent")
"""The wind scene's grid fields, which label its scenes in tables and plots."""
_GRID_KEYS = ("realisations", "seed", "aggregate")
"""Keys of ``scenes:`` that are not fields of the model's scene type."""


def _refuse(key: str, value: Any, message: str, where: tuple[str, ...] = ()) -> NoReturn:
    """Raise a validation error at field ``key`` under ``where`` (raised within ``scenes:``, its path then reads
    ``scenes.<key>``; from the study, ``where=("confirm",)``: ``confirm.<key>``)."""
    raise ValidationError.from_exception_data("scenes", [InitErrorDetails(
        type=PydanticCustomError("scene_field", message), loc=(*where, key), input=value)])


class ModelScenesSpec(BaseModel):
    """``scenes:`` of a model with its own scene type (e.g. the test rig's ``RigScene``).

    In the file the scene type's fields stand beside ``realisations``, ``seed`` and ``aggregate``;
    a list-valued field is a grid axis. A mapping-valued field gives one value per value of one axis
    (``duration: {startup: 1.2, steady: 1.2, coastdown: 3.0}`` beside ``kind: [startup, steady,
    coastdown]``: each scene takes its kind's record length); it adds no axis. Every grid point has
    ``realisations`` scenes with seeds ``seed + r``. The scene type (a dataclass whose ``__post_init__``
    validates it) names the fields that label its scenes in ``label_fields``; list-valued fields label
    them too.
    """

    model_config = _STRICT
    scene_type: str = Field(description="the scene type's qualified name (provenance)")
    fields: dict[str, Any] = Field(default_factory=dict, description="the scene fields as given")
    realisations: int = Field(1, ge=1, le=1000)
    seed: int = Field(1, ge=0)
    aggregate: Literal["mean", "median", "max"] = "mean"
    _type: Any = PrivateAttr(None)

    @classmethod
    def for_type(cls, scene_type: type, model: str, data: Any) -> "ModelScenesSpec":
        """Validate the raw ``scenes:`` mapping against ``scene_type`` (the scene type of ``model``).

        Raises
        ------
        ValueError
            For an unknown field (with close names and the allowed ones) or an empty list.
        """
        if data is None:
            data = {}
        if not isinstance(data, dict):
            raise ValueError(f"a mapping of {model!r} scene fields is needed, got {type(data).__name__}")
        allowed = [f.name for f in dataclasses.fields(scene_type) if f.name != "seed"]
        for key, value in data.items():
            if key not in allowed and key not in _GRID_KEYS:
                _refuse(key, value, unknown_name_message(f"{model} scene field", key,
                                                         [*allowed, *_GRID_KEYS]))
            if isinstance(value, list) and not value:
                _refuse(key, value, "an empty list gives an empty scene grid; give at least one value")
        for key, value in data.items():
            if isinstance(value, dict) and key not in _GRID_KEYS:
                if key in getattr(scene_type, "label_fields", ()):
                    _refuse(key, value, f"{key!r} labels the scenes and cannot take one value per value of "
                                        "another field; give it as a list (one scene per value)")
                _keyed_axis(key, value, data)
        grid = {k: v for k, v in data.items() if k in _GRID_KEYS}
        spec = cls(scene_type=f"{scene_type.__module__}.{scene_type.__qualname__}",
                   fields={k: v for k, v in data.items() if k not in _GRID_KEYS}, **grid)
        spec._type = scene_type
        return spec

    @property
    def label_fields(self) -> list[str]:
        """The fields that label a scene: the type's ``label_fields`` and every list-valued one."""
        declared = list(getattr(self._type, "label_fields", ()))
        return declared + [k for k, v in self.fields.items() if isinstance(v, list) and k not in declared]

    def grid(self) -> list[dict[str, Any]]:
        """The scene grid (without seeds): the label fields of every combination of the list-valued fields."""
        defaults = {f.name: f.default for f in dataclasses.fields(self._type)}
        labels = self.label_fields
        axes = {k: (v if isinstance(v, list) else [v]) for k, v in
                ((k, self.fields.get(k, defaults[k])) for k in labels)}
        return [dict(zip(axes, combo)) for combo in itertools.product(*axes.values())]

    def scene(self, fields: dict[str, Any], realisation: int) -> Any:
        """The scene of one grid point and realisation (seed ``seed + realisation``); a mapping-valued
        field takes the value of the grid point's value on its axis."""
        scalars = {k: v for k, v in self.fields.items() if not isinstance(v, (list, dict))}
        keyed = {k: v[fields[_keyed_axis(k, v, self.fields)]] for k, v in self.fields.items() if isinstance(v, dict)}
        return self._type(**{**scalars, **keyed, **fields}, seed=self.seed + realisation)


def _keyed_axis(key: str, value: dict[Any, Any], fields: dict[str, Any], where: tuple[str, ...] = ()) -> str:
    """The grid axis (a list-valued field of ``fields``) whose values are exactly the keys of the
    mapping-valued scene field ``key``.

    Raises
    ------
    pydantic.ValidationError
        At ``scenes.<key>`` (``confirm.budget``: ``where=("confirm",)``) where no axis or more than one has
        those values, a key is true or false, or a value is itself a list or mapping.
    """
    def refuse(message: str) -> NoReturn:
        _refuse(key, value, message, where)

    if not value:
        refuse("an empty mapping gives no value; give one value per value of a list-valued field")
    if any(isinstance(k, bool) for k in value):
        refuse("a mapping's keys are values of a list-valued scene field, not true or false")
    matches = []
    for axis, values in fields.items():
        if not isinstance(values, list) or axis in _GRID_KEYS:
            continue
        try:
            if set(value) == set(values) and len(values) == len(set(values)):
                matches.append(axis)
        except TypeError:                                  # a value that is not one value: refused elsewhere
            continue
    if len(matches) > 1:
        refuse(f"its keys are the values of {' and of '.join(matches)}: say which by giving the fields different "
               "values")
    if matches:
        bad = [v for v in value.values() if isinstance(v, (list, dict))]
        if bad:
            refuse(f"a mapping gives one value per {matches[0]}: {bad[0]!r} is not one value")
        return matches[0]
    axes = {k: v for k, v in fields.items() if isinstance(v, list) and k not in _GRID_KEYS}
    listed = "; ".join(f"{k}: {', '.join(map(str, v))}" for k, v in axes.items()) or "none"
    refuse(f"a mapping gives one value per value of a list-valued scene field, keyed by all of its values, each once "
           f"(the lists here: {listed}); got keys {', '.join(map(str, value))}")


class MethodSpec(BaseModel):
    """One entry of ``methods:`` -- ``method`` plus that method's options."""

    model_config = ConfigDict(extra="allow")
    method: str

    @property
    def options(self) -> dict[str, Any]:
        """The method's options (every key but ``method``)."""
        return dict(self.model_extra or {})


class ConfirmSpec(BaseModel):
    """``confirm:`` -- add runs per scene until every output is confirmed or the budget is spent
    (:mod:`ddgsa.gsa.escalate`)."""

    model_config = _STRICT
    budget: int | dict[Any, int] | None = Field(
        None, description="most new points per scene (each run in every realisation), or a mapping with one such "
                          "budget per value of a list-valued scene field, e.g. {startup: 16384, steady: 62000}")
    time: float | None = Field(None, gt=0.0, le=30 * 86400.0,
                               description="most wall time the escalation may spend, e.g. '10 min' [s]: it runs the "
                                           "stages that fit, cheapest first, then stops and says what the rest "
                                           "would cost")
    seed: int = Field(0, ge=0, description="seed of the added points")

    @field_validator("budget", mode="before")
    @classmethod
    def _budget(cls, value: Any) -> Any:
        """Every budget a whole number of points in [0, MAX_BUDGET] (not true or false)."""
        if value is None:
            return value
        for v in (value.values() if isinstance(value, dict) else [value]):
            if isinstance(v, bool) or not isinstance(v, (int, float)) or v != int(v) or not 0 <= v <= MAX_BUDGET:
                raise ValueError(f"a budget is a whole number of points from 0 to {MAX_BUDGET}, got {v!r}"
                                 + (" in the mapping" if isinstance(value, dict) else ""))
        return value

    @field_validator("time", mode="before")
    @classmethod
    def _time(cls, value: Any) -> Any:
        """``time: 10 min`` (any time unit; a plain number is seconds)."""
        if value is None or isinstance(value, bool):
            return value
        try:
            return convert(value, "s")
        except UnitError as exc:
            raise ValueError(f"{exc} (a wall time such as '10 min', '1.5 h' or seconds)") from None

    @model_validator(mode="after")
    def _some_limit(self) -> "ConfirmSpec":
        if self.budget is None and self.time is None:
            raise ValueError("a 'confirm' block needs 'budget' (most new points per scene), 'time' (most wall time, "
                             "e.g. '10 min') or both")
        return self


class RankingSpec(BaseModel):
    """``ranking:`` -- how a ranking by ST is confirmed (:func:`ddgsa.gsa.result.rank_structure`): two
    parameters whose ST difference is surely within ``tie_margin`` are a confirmed tie; parameters whose ST
    is surely below ``negligible`` form the negligible group. Both default to the methods' trust tolerance."""

    model_config = _STRICT
    tie_margin: float | None = Field(None, gt=0.0, lt=1.0, description="largest ST difference still a tie [-]")
    negligible: float | None = Field(None, gt=0.0, lt=1.0, description="ST below which a parameter is negligible [-]")

    @property
    def pair(self) -> tuple[float | None, float | None]:
        """(tie margin, negligible floor); None: the tolerance."""
        return self.tie_margin, self.negligible


class FaultRange(BaseModel):
    """``fault.faulty: {start, stop, num}`` -- evenly spaced fault levels, both ends included."""

    model_config = _STRICT
    start: float
    stop: float
    num: int = Field(ge=2, le=100)

    def levels(self) -> list[float]:
        """The levels, from ``start`` to ``stop``."""
        return [float(v) for v in np.linspace(self.start, self.stop, self.num)]


class NoiseSpec(BaseModel):
    """``fault.noise.<output>:`` -- measurement noise, standard deviation ``sqrt(absolute^2 + (relative y)^2)``."""

    model_config = _STRICT
    absolute: float = Field(0.0, ge=0, description="additive noise standard deviation [output unit]")
    relative: float = Field(0.0, ge=0, description="noise standard deviation as a fraction of the value [-]")


class FaultSpec(BaseModel):
    """``fault:`` -- a fault parameter, its healthy value and faulty levels, and how detection is judged."""

    model_config = _STRICT
    parameter: str
    healthy: float
    faulty: list[float] | FaultRange = Field(description="faulty levels: a list, or {start, stop, num}")
    unit: str | None = Field(None, exclude=True, description="unit of healthy and faulty (default: the parameter's "
                                                             "SI unit; converted on validation)")
    samples: int = Field(64, ge=8, le=4096, description="points over the other uncertainties per fault level")
    design: Literal["population", "paired"] = Field(
        "population", description="population: a monitoring system's healthy and faulty fleets (measurements "
                                  "compared only where they share no point or wind record); paired: each turbine "
                                  "against its own healthy baseline in another wind record")
    noise: dict[str, NoiseSpec] = Field(default_factory=dict, description="measurement noise per output")
    combine: list[str] | None = Field(None, min_length=2, description="outputs of the combined detector "
                                                                      "(default: every output with healthy spread)")
    false_alarm: float = Field(0.05, gt=0, lt=0.5, description="stated false-alarm rate")
    pod_target: float = Field(0.9, gt=0, le=1, description="probability of detection the lower bound must reach")
    confidence: float = Field(0.95, gt=0.5, lt=1, description="two-sided confidence level of the intervals")
    bootstrap: int = Field(1000, ge=100, le=100_000, description="bootstrap replicates")
    seed: int | None = Field(None, ge=0, description="seed of the fault samples, noise and bootstrap "
                                                     "(default: scenes.seed)")

    @model_validator(mode="before")
    @classmethod
    def _no_threshold(cls, data: Any) -> Any:
        if isinstance(data, dict) and "threshold" in data:
            raise ValueError("'threshold' (an effect-size verdict) is gone: detection is judged by the probability "
                             "of detection at a false-alarm rate; use false_alarm (default 0.05) and pod_target "
                             "(default 0.9)")
        return data

    @field_validator("faulty", mode="before")
    @classmethod
    def _levels_given(cls, v: Any) -> Any:
        if isinstance(v, dict):          # one clear message instead of one per union member
            try:
                return FaultRange.model_validate(v)
            except ValidationError as exc:
                problems = "; ".join(f"{'.'.join(map(str, e['loc'])) or 'range'}: " + (
                    "unknown field" if e["type"] == "extra_forbidden"
                    else bound_message(e)) for e in exc.errors())
                raise ValueError(f"a range of levels is {{start, stop, num >= 2}} ({problems})") from None
        if isinstance(v, list) and not v:
            raise ValueError("give at least one faulty level")
        return v

    @property
    def levels(self) -> list[float]:
        """The faulty levels."""
        return self.faulty.levels() if isinstance(self.faulty, FaultRange) else list(self.faulty)


class TargetSpec(BaseModel):
    """One entry of ``target:`` -- an output transformed to its part beyond a limit (:mod:`ddgsa.gsa.target`)."""

    model_config = _STRICT
    output: str = Field(description="the output transformed (one of the study's outputs)")
    above: float | None = Field(None, description="limit whose exceedance counts [the output's unit in the study]")
    below: float | None = Field(None, description="limit whose undershoot counts (instead of above)")
    kind: Literal["indicator", "excess"] = Field("indicator", description="indicator 1{y > limit} [-] or excess "
                                                                          "max(y - limit, 0) [output unit]")
    name: str | None = Field(None, pattern=r"^[A-Za-z_][A-Za-z0-9_]*$",
                             description="name of the transformed output (default <output>_exceeds, _excess, ...)")

    @model_validator(mode="after")
    def _one_limit(self) -> "TargetSpec":
        if (self.above is None) == (self.below is None):
            raise ValueError("give exactly one limit: 'above' or 'below'")
        return self

    def target(self) -> Target:
        """The transform."""
        above = self.above is not None
        return Target(self.output, float(self.above if above else self.below),  # type: ignore[arg-type]
                      above, self.kind, self.name or "")


class RunSpec(BaseModel):
    """``run:`` -- parallel options (overridden by the CLI's ``--jobs`` / ``--backend``)."""

    model_config = _STRICT
    jobs: int = Field(1, ge=1, le=512)
    batch_size: int = Field(4, ge=1, le=10_000)
    backend: Literal["loky", "dask"] = "loky"
    address: str | None = None
    timeout: float | None = Field(None, gt=0, le=1e6, description=(
        "seconds one model evaluation may take: one that runs longer is stopped and stored as failed "
        "('timed out'); each point then runs alone in a child process of its worker (POSIX)"))


class StudySpec(BaseModel):
    """A whole study file."""

    model_config = _STRICT
    name: str = Field(pattern=r"^[A-Za-z0-9_.-]+$", max_length=MAX_NAME_CHARS)
    description: str = ""
    kind: Literal["gsa", "sweep", "fault"] = "gsa"
    model: ModelSpec
    parameters: dict[str, dict[str, Any]] = Field(default_factory=dict)
    groups: dict[str, list[str]] = Field(
        default_factory=dict, description="named disjoint groups of uncertain parameters; methods that can "
                                          "(mdrm, saltelli, pce) report their closed and total indices")
    correlation: list[tuple[str, str, float]] = Field(
        default_factory=list, description="Gaussian-copula correlations [parameter, parameter, rho] of the "
                                          "uncertain parameters (positive definite); needs method shapley")
    target: list[TargetSpec] = Field(
        default_factory=list, description="outputs transformed to their part beyond a limit (a mapping or a "
                                          "list); analysed beside the outputs (target sensitivity)")
    fixed: dict[str, float | str | dict[str, Any]] = Field(
        default_factory=dict, description="parameter values held fixed: a number in the model's unit, a quantity "
                                          "('12 kN/m') or {value, unit}")
    grid: dict[str, list[float | str] | dict[str, Any]] = Field(
        default_factory=dict, description="parameter values to sweep, full factorial (kind: sweep only); "
                                          "numbers, quantities or {value: [...], unit}")
    scenes: ScenesSpec | ModelScenesSpec = Field(default_factory=ScenesSpec)
    outputs: list[str] = Field(default_factory=list, description="output names; an entry {name, unit} reports "
                                                                "that output in another unit")
    output_units: dict[str, str] = Field(default_factory=dict, exclude=True,
                                         description="the units of outputs given as {name, unit} (filled from "
                                                     "'outputs'; display only, so not part of the digest)")
    signals: list[str] = Field(default_factory=list, description="signal outputs of the model (vectors on a fixed "
                                                                 "grid: spectra...) to analyse per bin and "
                                                                 "generalised (kind: gsa)")
    methods: list[MethodSpec] = Field(default_factory=list)
    fault: FaultSpec | None = None
    confirm: ConfirmSpec | None = None
    ranking: RankingSpec = Field(default_factory=RankingSpec, exclude=True,
                                 description="tie margin and negligible floor of confirmed rankings (analysis only, "
                                             "so not part of the digest: stored runs are reused)")
    run: RunSpec = Field(default_factory=RunSpec)

    @model_validator(mode="before")
    @classmethod
    def _output_units(cls, data: Any) -> Any:
        """``outputs: [{name: x, unit: mm}]`` -> ``outputs: [x]`` and ``output_units: {x: mm}``."""
        if not isinstance(data, dict) or not isinstance(data.get("outputs"), list):
            return data
        given = data.get("output_units") or {}
        if not isinstance(given, dict):
            raise ValueError(f"output_units: a mapping of output name to unit (better: outputs: [{{name, unit}}]), "
                             f"got {type(given).__name__}")
        names, units = [], dict(given)
        for i, entry in enumerate(data["outputs"]):
            if isinstance(entry, dict):
                if set(entry) != {"name", "unit"}:
                    raise ValueError(f"outputs[{i}]: an output with a unit is {{name, unit}}, got keys {sorted(entry)}")
                names.append(entry["name"])
                units[str(entry["name"])] = str(entry["unit"])
            else:
                names.append(entry)
        return {**data, "outputs": names, "output_units": units}

    @field_validator("target", mode="before")
    @classmethod
    def _one_target(cls, v: Any) -> Any:
        """``target: {output, above}`` is a list of one."""
        return [v] if isinstance(v, dict) else v

    @field_validator("scenes", mode="wrap")
    @classmethod
    def _model_scenes(cls, v: Any, handler: Any, info: ValidationInfo) -> ScenesSpec | ModelScenesSpec:
        """Scenes are the model's: validated against the scene type of the named model (wind by default)."""
        if isinstance(v, (ScenesSpec, ModelScenesSpec)):
            return v
        model = info.data.get("model")
        scene_type = scene_type_of(model.name) if isinstance(model, ModelSpec) else Scene
        v = scene_units(scene_type, v)
        if scene_type is Scene:
            return ScenesSpec.model_validate(v)
        return ModelScenesSpec.for_type(scene_type, model.name, v)

    @model_validator(mode="after")
    def _kind_needs(self) -> "StudySpec":
        if self.kind in ("gsa", "fault") and not self.parameters:
            raise ValueError(f"kind '{self.kind}' needs at least one entry under 'parameters'")
        if self.kind in ("gsa", "fault") and not self.methods:
            raise ValueError(f"kind '{self.kind}' needs at least one entry under 'methods'")
        if self.kind == "fault" and self.fault is None:
            raise ValueError("kind 'fault' needs a 'fault' block (parameter, healthy, faulty)")
        if self.confirm is not None and self.kind != "gsa":
            raise ValueError("a 'confirm' block needs kind: gsa")
        if self.confirm is not None and isinstance(self.confirm.budget, dict):
            _keyed_axis("budget", self.confirm.budget, self.scene_axes(), ("confirm",))
        if self.kind != "fault" and self.fault is not None:
            raise ValueError("a 'fault' block needs kind: fault")
        if self.kind != "sweep" and (self.grid or self.model.variants):
            raise ValueError("'grid' and 'model.variants' need kind: sweep")
        if any(not (values.get("value") if isinstance(values, dict) else values) for values in self.grid.values()):
            raise ValueError("every 'grid' entry needs at least one value")
        if self.model.variants and self.model.fidelity == "auto":
            raise ValueError("'model.variants' cannot be combined with fidelity: auto")
        if self.signals and self.kind != "gsa":
            raise ValueError("'signals' need kind: gsa")
        return self

    def scene_axes(self) -> dict[str, Any]:
        """The fields of ``scenes:`` by name (a list-valued one is a grid axis)."""
        if isinstance(self.scenes, ModelScenesSpec):
            return dict(self.scenes.fields)
        return {k: getattr(self.scenes, k) for k in WIND_LABEL_FIELDS}

    def confirm_budget(self, fields: dict[str, Any]) -> int | None:
        """The ``confirm:`` budget [points] of the grid point whose label fields are ``fields`` (one value of a
        per-value mapping, ``budget: {startup: 16384, steady: 62000}``), None without a budget."""
        budget = None if self.confirm is None else self.confirm.budget
        return int(budget[self.budget_key(fields)]) if isinstance(budget, dict) else budget

    def budget_key(self, fields: dict[str, Any]) -> Any:
        """The key of a per-value ``confirm:`` budget that applies at the grid point with label ``fields`` (None
        where the budget is one number or absent)."""
        budget = None if self.confirm is None else self.confirm.budget
        if not isinstance(budget, dict):
            return None
        return fields[_keyed_axis("budget", budget, self.scene_axes(), ("confirm",))]


def scene_units(scene_type: type, data: Any) -> Any:
    """The raw ``scenes:`` mapping with every value written with a unit converted to the scene
    type's (its ``units``; :mod:`ddgsa.units`).

    Raises
    ------
    ValueError
        At field ``scenes.<key>`` for a unit of another dimension or one that cannot be read.
    """
    if not isinstance(data, dict):
        return data
    units = getattr(scene_type, "units", {})
    out = dict(data)
    for key, value in data.items():
        if isinstance(value, dict) and not has_unit(value) and units.get(key):   # one value per axis value
            if scene_type is Scene:
                _refuse(key, value, "one value per value of a grid axis is for a model's own scene type (the "
                                    "rig's); a wind scene field takes a number, a quantity or a list")
            out[key] = {k: scene_units(scene_type, {key: v})[key] for k, v in value.items()}
        elif units.get(key) and has_unit(value):
            try:
                out[key] = convert(value, units[key])
            except UnitError as exc:
                _refuse(key, value, f"{exc} (field {key!r} is in {units[key]})")
    return out


def scene_type_of(model: str) -> type:
    """The scene type model ``model`` declares (``Model.scene_type``; the wind ``Scene`` for an unknown name)."""
    return getattr(MODELS[model], "scene_type", Scene) if model in MODELS else Scene


@dataclass
class Study:
    """A validated study: the spec, its parameter space, the model, and where it came from."""

    spec: StudySpec
    space: ParameterSpace | None
    path: Path | None
    text: str

    @property
    def name(self) -> str:
        """The study's name."""
        return self.spec.name

    def with_confirm_time(self, value: Any) -> "Study":
        """This study with ``confirm: {time: value}`` (``ddgsa run --confirm-time``): the study's own
        ``confirm`` block keeps its budget and seed.

        Raises
        ------
        StudyError
            For an unreadable time, or a study that is not of kind gsa.
        """
        if self.spec.kind != "gsa":
            raise StudyError(f"{_where(self.path)}: --confirm-time needs a study of kind gsa (this one is "
                             f"{self.spec.kind!r})")
        old = self.spec.confirm.model_dump() if self.spec.confirm is not None else {}
        confirm = ConfirmSpec(**{**old, "time": confirm_time(value)})
        return replace(self, spec=self.spec.model_copy(update={"confirm": confirm}))

    @property
    def digest(self) -> str:
        """SHA-256 of the validated study (canonical JSON), for provenance. Fields added after
        studies were committed (:data:`_LATER_DEFAULTS`) count only when they differ from their
        default, so a study written before them keeps its digest."""
        data = self.spec.model_dump(mode="json")
        for key in _LATER_EMPTY:
            if not data.get(key):
                data.pop(key, None)
        for (part, field), default in _LATER_DEFAULTS.items():
            if not isinstance(data.get(part), dict) or field not in data[part]:
                continue
            if isinstance(default, dict) and isinstance(data[part][field], dict):
                sub = {k: v for k, v in data[part][field].items() if default.get(k, object()) != v}
                if sub:
                    data[part][field] = sub
                else:
                    del data[part][field]
            elif data[part][field] == default:
                del data[part][field]
        if data.get("confirm") is None:                  # added later still: absent keeps the digest
            data.pop("confirm", None)
        return hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()

    def make_model(self) -> Any:
        """The model instance the study runs (its richest fidelity under ``auto``)."""
        fidelity = self.spec.model.fidelity
        cls = MODELS.lookup(self.spec.model.name)
        return get_model(self.spec.model.name, fidelity=cls.fidelities[0] if fidelity == "auto" else fidelity,
                         **self.spec.model.options)

    def variants(self) -> list[tuple[str, "Study"]]:
        """One ``(label, study)`` per entry of ``model.variants`` (options merged); ``[]`` without variants."""
        out = []
        for v in self.spec.model.variants:
            model = self.spec.model.model_copy(update={"options": {**self.spec.model.options, **v}, "variants": []})
            label = ", ".join(f"{k}={val}" for k, val in v.items())
            out.append((label, Study(self.spec.model_copy(update={"model": model}), self.space, self.path, self.text)))
        return out

    @property
    def scene_fields(self) -> list[str]:
        """The fields that label the study's scenes in tables and plots."""
        sc = self.spec.scenes
        return sc.label_fields if isinstance(sc, ModelScenesSpec) else list(WIND_LABEL_FIELDS)

    @property
    def wind(self) -> bool:
        """Whether the study's scenes are wind scenes (``ddgsa.Scene``, whose loads are cached)."""
        return isinstance(self.spec.scenes, ScenesSpec)

    @property
    def outputs(self) -> list[str]:
        """Outputs to analyse (all of the model's when the study lists none)."""
        return self.spec.outputs or list(self.make_model().outputs)

    @property
    def targets(self) -> list[Target]:
        """The study's target transforms (``target:``)."""
        return [t.target() for t in self.spec.target]

    @property
    def analysed_outputs(self) -> list[str]:
        """The outputs and then the target-transformed outputs: the rows of the indices table."""
        return self.outputs + [t.name for t in self.targets]

    def output_factors(self, outputs: list[str]) -> np.ndarray:
        """Per output, the factor from the model's SI unit to the unit the study reports it in (1 by default)."""
        if not self.spec.output_units:
            return np.ones(len(outputs))
        model = self.make_model()
        return np.array([factor(model.output(o).unit, self.spec.output_units[o])
                         if o in self.spec.output_units else 1.0 for o in outputs])

    def output_declarations(self) -> dict[str, ModelOutput]:
        """:meth:`output_declaration` of every analysed output, in the units the study reports them in."""
        model = self.make_model()
        return {o: self.output_declaration(model, o) for o in self.analysed_outputs}

    def output_declaration(self, model: Any, name: str) -> ModelOutput:
        """The declaration of output ``name`` in the unit the study reports it in (range scaled)."""
        for t in self.targets:
            if name == t.name:
                base = self.output_declaration(model, t.output)
                return ModelOutput(name, "-" if t.kind == "indicator" else base.unit, t.description)
        decl = model.output(name) if name in model.outputs else declared(name)
        unit = self.spec.output_units.get(name)
        if unit is None:
            return decl
        f = factor(decl.unit, unit)
        return ModelOutput(name, unit, decl.description, decl.low * f, decl.high * f)


def _where(path: Path | None) -> str:
    return str(path) if path is not None else "<study>"


def load_study(path: str | Path) -> Study:
    """Read and validate a study file.

    Raises
    ------
    StudyError
        Naming the file, the field path and what is allowed.
    """
    p = Path(path)
    data, text = load_yaml(p)
    return validate_study(data, p, text)


def salib_parameters(file: str, path: Path | None = None) -> dict[str, dict[str, Any]]:
    """``parameters: FILE``: the study's parameters from a SALib problem, a JSON or YAML mapping
    (``names``, ``bounds``, ``dists``) or SALib's text parameter file (``name,low,high[,group[,dist]]``
    per line), relative to the study file's folder (:meth:`ParameterSpace.from_salib`)."""
    from SALib.util import read_param_file

    src = (path.parent if path is not None else Path.cwd()) / file
    field = f"{_where(path)}: field 'parameters'"
    if not src.exists():
        raise StudyError(f"{field}: SALib problem file {src} not found (a mapping of parameters, or a file name)")
    yaml = src.suffix in (".json", ".yaml", ".yml")
    try:                                   # bounded and a regular file, as the study file, before it is parsed
        problem = load_yaml(src, "parameters file")[0] if yaml else read_text(src, "parameters file")
    except StudyError as exc:
        raise StudyError(f"{field}: {exc}") from None
    try:
        return ParameterSpace.from_salib(problem if yaml else read_param_file(str(src))).to_dict()
    except (DdgsaError, ValueError, TypeError, KeyError, csv.Error) as exc:
        hint = " (a text problem file has one 'name,low,high[,group[,dist]]' per line)" if src.suffix not in (
            ".json", ".yaml", ".yml") else ""
        raise StudyError(f"{field}: SALib problem file {src}: {exc}{hint}") from None


def validate_study(data: Any, path: Path | None = None, text: str = "") -> Study:
    """Validate a study given as data (see :func:`load_study`)."""
    where = _where(path)
    if not isinstance(data, dict):
        raise StudyError(f"{where}: a study is a mapping of fields (name, model, parameters, ...), "
                         f"got {type(data).__name__}")
    refuse_unordered(data, where)
    if isinstance(data.get("parameters"), str):
        data = {**data, "parameters": salib_parameters(data["parameters"], path)}
    try:
        spec = StudySpec.model_validate(data)
    except ValidationError as exc:
        raise StudyError(_pydantic_message(where, exc)) from None
    check_names(where, spec)
    # model-aware checks
    if spec.model.name not in MODELS:
        raise StudyError(f"{where}: field 'model.name': {unknown_name_message('model', spec.model.name, list(MODELS))}")
    if spec.model.fidelity is None:
        spec.model.fidelity = MODELS.lookup(spec.model.name).fidelities[0]
    try:
        MODELS.lookup(spec.model.name).check_options(spec.model.options)     # each option as declared
    except DdgsaError as exc:
        raise StudyError(f"{where}: field 'model.options': {exc}") from None
    try:
        fidelities = MODELS.lookup(spec.model.name).fidelities
        for fid in (fidelities if spec.model.fidelity == "auto" else [spec.model.fidelity]):
            model = get_model(spec.model.name, fidelity=fid, **spec.model.options)
    except (DdgsaError, TypeError) as exc:
        field = "model.fidelity" if "fidelity" in str(exc) else "model"
        raise StudyError(f"{where}: field '{field}': {exc}") from None
    variants = []
    for i, v in enumerate(spec.model.variants):
        try:
            variants.append(get_model(spec.model.name, fidelity=spec.model.fidelity, **{**spec.model.options, **v}))
        except (DdgsaError, TypeError) as exc:
            raise StudyError(f"{where}: field 'model.variants[{i}]': {exc}") from None
        for j, out in enumerate(spec.outputs):
            if out not in variants[i].outputs:
                raise StudyError(f"{where}: field 'outputs[{j}]': output {out!r} does not exist in "
                                 f"model.variants[{i}]; that variant has: {', '.join(variants[i].outputs)}")
    model = variants[0] if variants else model          # parameter names: the first variant's
    names = [p.name for p in model.parameters]
    for section in ("parameters", "fixed"):
        for key in getattr(spec, section):
            if key not in names:
                raise StudyError(f"{where}: field '{section}.{key}': not a parameter of model "
                                 f"{spec.model.name!r}: {_unknown_parameter(key, names)}")
    _convert_units(where, spec, model)
    for key, values in spec.grid.items():
        if key not in names:
            raise StudyError(f"{where}: field 'grid.{key}': not a parameter of model {spec.model.name!r}: "
                             f"{_unknown_parameter(key, names)}")
        assert isinstance(values, list)
        for v in values:
            if problem := model.parameter(key).range_problem(v):
                raise StudyError(f"{where}: field 'grid.{key}': {problem}")
    for key, value in spec.fixed.items():
        if isinstance(value, (int, float)) and (problem := model.parameter(key).range_problem(value)):
            raise StudyError(f"{where}: field 'fixed.{key}': {problem}")
    overlap = (set(spec.parameters) | set(spec.grid)) & set(spec.fixed)
    if overlap:
        raise StudyError(f"{where}: field 'fixed': {sorted(overlap)} are also uncertain 'parameters' or 'grid' entries")
    for i, out in enumerate(spec.outputs):
        if out not in model.outputs and not spec.model.variants:
            raise StudyError(f"{where}: field 'outputs[{i}]': "
                             + unknown_name_message("output", out, list(model.outputs),
                                                    where=f"ddgsa models {spec.model.name}"))
    declared_signals = [x.name for x in model.signal_outputs]
    for i, sig in enumerate(spec.signals):
        if sig not in declared_signals:
            raise StudyError(f"{where}: field 'signals[{i}]': " + unknown_name_message(
                "signal output", sig, declared_signals, where=f"ddgsa models {spec.model.name}"))
    for key, unit in spec.output_units.items():
        if key not in spec.outputs:
            raise StudyError(with_hint(f"{where}: field 'output_units.{key}': not an output of the study; "
                                       f"known: {', '.join(spec.outputs)}", key, spec.outputs))
        try:
            factor(unit, model.output(key).unit)
        except UnitError as exc:
            raise StudyError(f"{where}: field 'outputs[{spec.outputs.index(key)}].unit': output {key!r}: "
                             f"{exc}") from None
    space = None
    if spec.parameters:
        try:
            space = ParameterSpace.from_dict(spec.parameters)
        except DdgsaError as exc:         # "parameter 'k': ..." names the entry: the field is parameters.k
            named = re.match(r"parameter '([^']+)'", str(exc))
            field = f"parameters.{named[1]}" if named and named[1] in spec.parameters else "parameters"
            raise StudyError(f"{where}: field '{field}': {exc}") from None
        try:
            space = ParameterSpace.from_dict(spec.parameters, groups=spec.groups, correlation=spec.correlation)
        except DdgsaError as exc:       # the message starts with the field: groups.<g> or correlation[k]
            head, _, rest = str(exc).partition(": ")
            raise StudyError(f"{where}: field '{head}': {rest}") from None
        for p in space.parameters:
            written = spec.parameters.get(p.name)           # a unit written beside it: no prefix to advise
            hint = not (isinstance(written, dict) and "unit" in written)
            if problem := model.parameter(p.name).range_problem(p.support, what="support", hint=hint):
                raise StudyError(f"{where}: field 'parameters.{p.name}': {problem}")
    check_run_size(where, spec, space, len(spec.outputs or model.outputs))     # before any design is built
    nominal = {**dict(spec.fixed), **(space.nominal if space is not None else {})}
    for problem in model.point_problems(nominal):
        warnings.warn(f"{where}: the study's nominal point is outside model {spec.model.name!r}'s valid region: "
                      f"{problem}; every evaluation near it will fail", StudyWarning, stacklevel=2)
    for i, m in enumerate(spec.methods):
        first = [x.method for x in spec.methods].index(m.method)
        if first < i:       # results are keyed by method name: a second entry would collide after all runs
            raise StudyError(f"{where}: field 'methods[{i}].method': method {m.method!r} is already given as "
                             f"methods[{first}]; one entry per method (to compare two settings, run two studies)")
        if m.method == "auto":
            if space is not None and space.dependent:
                raise StudyError(f"{where}: field 'methods[{i}]': method 'auto' escalates through methods that "
                                 "assume independent inputs, and 'correlation' couples them; use method 'shapley'")
            try:
                resolve_auto_options(space, m.options) if space is not None else None
            except DdgsaError as exc:
                raise StudyError(f"{where}: field 'methods[{i}]': {exc}") from None
            continue
        if m.method not in METHODS:
            raise StudyError(f"{where}: field 'methods[{i}].method': "
                             + unknown_name_message("GSA method", m.method, [*METHODS, "auto"]))
        try:
            get_method(m.method).design(space, **m.options) if space is not None else None
        except DdgsaError as exc:
            raise StudyError(f"{where}: field 'methods[{i}]': {exc}") from None
    for k, fields in enumerate(scenes_to_check(spec.scenes)):
        try:
            spec.scenes.scene(fields, 0)
        except (DdgsaError, TypeError) as exc:
            values = {key: [v] for key, v in {**getattr(spec.scenes, "fields", {}), **fields}.items()}
            hints = "".join(f" (hint: {h})" for _, h in scene_hints(scene_type_of(spec.model.name), values))
            raise StudyError(f"{where}: field 'scenes' (scene {k}: {scene_text(fields)}): {exc}{hints}") from None
    for i, sig in enumerate(spec.signals):
        for k, fields in enumerate(scenes_to_check(spec.scenes)):
            try:
                model.signal_axis(sig, spec.scenes.scene(fields, 0))
            except DdgsaError as exc:
                raise StudyError(f"{where}: field 'signals[{i}]' (scene {k}: {scene_text(fields)}): {exc}") from None
    if spec.fault is not None:
        _validate_fault(where, spec, model)
    _validate_targets(where, spec, list(spec.outputs or model.outputs))
    return Study(spec=spec, space=space, path=path, text=text)


def _validate_targets(where: str, spec: StudySpec, outputs: list[str]) -> None:
    """Each target names an output of the study, its name is new, and no ``auto`` method runs beside it;
    targets, groups and correlations belong to ``kind: gsa``."""
    names = set(outputs)
    for i, t in enumerate(spec.target):
        if t.output not in outputs:
            raise StudyError(f"{where}: field 'target[{i}].output': " + unknown_name_message("output", t.output, outputs))
        name = t.target().name
        if name in names:
            raise StudyError(f"{where}: field 'target[{i}].name': {name!r} is already an output's name; set 'name'")
        names.add(name)
    for key in ("target", "groups", "correlation"):
        if getattr(spec, key) and spec.kind != "gsa":
            raise StudyError(f"{where}: field '{key}': needs kind: gsa (a {spec.kind} study does not analyse it)")
    if spec.target and any(m.method == "auto" for m in spec.methods):
        raise StudyError(f"{where}: field 'target': method 'auto' analyses the model's outputs only; use fixed "
                         "methods (saltelli, pce, hsic, mdrm) beside a target")


def _convert_units(where: str, spec: StudySpec, model: Any) -> None:
    """Convert, in place, every parameter specification, fixed value, grid value and fault level
    written with a unit to the unit model ``model`` declares (see :mod:`ddgsa.units`).

    Raises
    ------
    StudyError
        Naming the file, the field, the unit given and the dimension expected.
    """
    names = {p.name for p in model.parameters}
    try:
        for key, value in spec.parameters.items():
            if key in names and isinstance(value, dict) and "unit" in value:
                field = f"parameters.{key}.unit"
                spec.parameters[key] = parameter_in(value, model.parameter(key).unit)
        for section in ("fixed", "grid"):
            values = getattr(spec, section)
            for key, value in values.items():
                plain = isinstance(value, (int, float)) or (
                    isinstance(value, list) and all(isinstance(v, (int, float)) for v in value))
                if key in names and not plain:                # plain numbers stay as written (digest)
                    field = f"{section}.{key}"
                    values[key] = convert(value, model.parameter(key).unit)
        fault = spec.fault
        if fault is not None and fault.unit is not None and fault.parameter in names:
            field = "fault.unit"
            unit = model.parameter(fault.parameter).unit
            fault.healthy = convert({"value": fault.healthy, "unit": fault.unit}, unit)
            fault.faulty = convert({"value": fault.levels, "unit": fault.unit}, unit)
            fault.unit = unit
    except UnitError as exc:
        raise StudyError(f"{where}: field '{field}': {exc}") from None


def scene_text(values: Mapping[str, Any]) -> str:
    """``field=value, ...`` of a scene's label fields (numbers by ``:g``, labels such as a rig scene's
    kind as they are), for messages, tables and plot titles."""
    return ", ".join(f"{k}={v:g}" if isinstance(v, (int, float)) and not isinstance(v, bool) else f"{k}={v}"
                     for k, v in values.items())


def _unknown_parameter(name: str, known: list[str]) -> str:
    return unknown_name_message("parameter", name, known, where="ddgsa models")


def _validate_fault(where: str, spec: StudySpec, model: Any) -> None:
    """Model-aware checks of the ``fault`` block."""
    fault = spec.fault
    assert fault is not None
    if fault.parameter not in spec.parameters:
        raise StudyError(f"{where}: field 'fault.parameter': {fault.parameter!r} must also be an "
                         f"uncertain parameter (under 'parameters')")
    for value in [fault.healthy, *fault.levels]:
        if problem := model.parameter(fault.parameter).range_problem(value, what="level"):
            raise StudyError(f"{where}: field 'fault': {problem}")
    if fault.healthy in fault.levels:
        raise StudyError(f"{where}: field 'fault.faulty': contains the healthy value {fault.healthy:g}")
    outputs = spec.outputs or list(model.outputs)
    for key in fault.noise:
        if key not in outputs:
            raise StudyError(with_hint(f"{where}: field 'fault.noise.{key}': not an output of the study; "
                                       f"known: {', '.join(outputs)}", key, outputs))
    for i, key in enumerate(fault.combine or []):
        if key not in outputs:
            raise StudyError(with_hint(f"{where}: field 'fault.combine[{i}]': not an output of the study; "
                                       f"known: {', '.join(outputs)}", key, outputs))
    if fault.design == "paired" and spec.scenes.realisations < 4:
        raise StudyError(f"{where}: field 'fault.design': paired compares each point's record r with its own "
                         "healthy record r - 1; two such changes are independent only on four distinct records: "
                         f"needs scenes.realisations >= 4, got {spec.scenes.realisations}")
    n = fault.samples * spec.scenes.realisations
    if n * fault.false_alarm < 1:
        raise StudyError(f"{where}: field 'fault.samples': {fault.samples} samples x "
                         f"{spec.scenes.realisations} realisations "
                         f"= {n} measurements per level cannot resolve false_alarm = {fault.false_alarm:g}; "
                         f"need >= {int(np.ceil(1 / fault.false_alarm))}")


def _known_fields(loc: tuple[Any, ...]) -> list[str]:
    """The fields of the schema part at ``loc`` (a pydantic error location), for unknown-field messages."""
    node: Any = StudySpec
    for key in loc:
        if isinstance(key, int) or not (isinstance(node, type) and issubclass(node, BaseModel)):
            continue                                 # a list index or a dict key: the same part
        field = node.model_fields.get(str(key))
        if field is None:
            return []
        parts = [a for a in (*getattr(field.annotation, "__args__", ()), field.annotation)
                 if isinstance(a, type) and issubclass(a, BaseModel)]
        if not parts:
            return []
        node = next((a for a in parts if a is not ModelScenesSpec), parts[0])
    if node is StudySpec:
        return [k for k in node.model_fields if k != "output_units"]
    return list(node.model_fields) if isinstance(node, type) and issubclass(node, BaseModel) else []


_BOUNDS = {"greater_than": ("gt", ">"), "greater_than_equal": ("ge", ">="), "less_than": ("lt", "<"),
           "less_than_equal": ("le", "<=")}
"""pydantic's bound errors and the symbol ddgsa's messages use for each."""


def confirm_time(value: Any) -> float:
    """``ddgsa run --confirm-time``'s value as seconds, checked as ``confirm: {time:}`` is (a number of
    seconds or a time with its unit, above 0).

    Raises
    ------
    StudyError
        For an unreadable or non-positive time.
    """
    try:
        return float(ConfirmSpec(time=value).time)  # type: ignore[arg-type]
    except ValidationError as exc:
        err = exc.errors()[0]
        raise StudyError(f"--confirm-time {value!r}: "
                         f"{bound_message(err)}") from None


def bound_message(err: Mapping[str, Any]) -> str:
    """A pydantic error in the words of ddgsa's other messages: a bound as ``must be > 0`` where pydantic
    says "Input should be greater than 0", any other error as pydantic words it.

    >>> bound_message({"type": "less_than", "ctx": {"lt": 1.0}})
    'must be < 1'
    >>> bound_message({"type": "int_type", "msg": "Input should be a valid integer"})
    'Input should be a valid integer'
    """
    if err["type"] not in _BOUNDS:
        return str(err["msg"])
    key, symbol = _BOUNDS[err["type"]]
    return f"must be {symbol} {err['ctx'][key]:g}"


def _pydantic_message(where: str, exc: ValidationError) -> str:
    """One line per problem: file, field path, message and the value given."""
    lines = []
    for err in exc.errors():
        loc = ".".join(f"[{x}]" if isinstance(x, int) else str(x) for x in err["loc"]).replace(".[", "[")
        msg = err["msg"]
        if err["type"] == "extra_forbidden":
            known = _known_fields(err["loc"][:-1])
            msg = unknown_name_message("field", err["loc"][-1], known) if known else "unknown field"
        elif err["type"] == "literal_error":
            allowed = re.findall(r"'([^']*)'", str(err.get("ctx", {}).get("expected", "")))
            msg = unknown_name_message("value", err["input"], allowed)
        elif err["type"] == "missing":
            msg = "required field is missing"
        elif err["type"] in _BOUNDS:
            msg = bound_message(err)
        elif err["type"] == "value_error":
            msg = msg.removeprefix("Value error, ")        # our validators' own words, without pydantic's tag
        given = f" (given: {clip(err['input'])})" if err["type"] not in ("missing", "extra_forbidden", "literal_error") \
            and not isinstance(err.get("input"), dict) else ""
        lines.append(f"{where}: field '{loc or '<top>'}': {msg}{given}")
    return "\n".join(lines)


@dataclass(frozen=True)
class PlannedScene:
    """One grid point of the scene grid with its realisation seeds."""

    index: int
    fields: dict[str, Any]
    scenes: tuple[Any, ...]
    """The realisations' scenes, of the model's scene type."""


def plan_scenes(study: Study) -> list[PlannedScene]:
    """The scene grid with every realisation's :class:`Scene`."""
    sc = study.spec.scenes
    return [PlannedScene(i, f, tuple(sc.scene(f, r) for r in range(sc.realisations)))
            for i, f in enumerate(sc.grid())]
