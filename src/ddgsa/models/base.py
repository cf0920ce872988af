"""What every model is: declared parameters, named outputs, ``evaluate``/``simulate``/``modes``."""

from __future__ import annotations

import dataclasses

import math
import warnings
from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.errors import ModelError, clip, did_you_mean, unknown_name_message, with_hint
from ddgsa.loads.scene import Scene
from ddgsa.mbs.campbell import CampbellDiagram, campbell_from_tables
from ddgsa.mbs.sampling import sampling_row
from ddgsa.registry import Registry
from ddgsa.units import prefix_hint

MODELS: Registry[type["Model"]] = Registry("model", ModelError)
register_model = MODELS.register


BAND_FACTOR = 1.5
"""A scene's band of interest is this times the highest frequency a model's outputs read
(:attr:`BasisRule.band_hz`)."""


@dataclass(frozen=True)
class BasisRule:
    """What a model with a finite-element shaft declares for :func:`ddgsa.models.basis.basis_report`.

    Attributes
    ----------
    reference : dict
        Model options of the converged basis its own is compared with (same beam theory).
    ladder : tuple of (dict, str)
        Bases tried in order for the advice, each with its measured cost in words.
    light : dict
        The cheaper basis studies may keep for speed (tabulated with the ladder's steps from it).
    fidelity : str
        The fidelity whose :meth:`modes` give the basis's standstill frequencies.
    options : callable
        ``options(model)``: the model's basis as model options, ``None`` where a fidelity has none.
    band_hz : callable
        ``band_hz(model, scene)``: the scene's band of interest [Hz].
    nominal : callable
        ``nominal()``: the nominal values the stored table depends on (JSON-serialisable).
    starts : callable
        ``starts(default)``: the bases :func:`tabulated_bases` starts from (the default; the direct drive
        adds each shaft reading).
    """

    reference: dict[str, Any]
    ladder: tuple[tuple[dict[str, Any], str], ...]
    light: dict[str, Any]
    fidelity: str
    options: Callable[[Any], dict[str, Any] | None]
    band_hz: Callable[[Any, Any], float]
    nominal: Callable[[], Any]
    starts: Callable[[dict[str, Any]], list[dict[str, Any]]] = lambda default: [default]


@dataclass(frozen=True)
class ModelParameter:
    """A declared model parameter (OpenMDAO-style ``declare``).

    Attributes
    ----------
    name : str
    nominal : float
        Nominal value [unit].
    unit : str
    description : str
    low, high : float
        Allowed physical range (a study may not sample outside it).
    """

    name: str
    nominal: float
    unit: str
    description: str
    low: float = -math.inf
    high: float = math.inf

    def range_problem(self, values: float | tuple[float, float], what: str = "=", hint: bool = True) -> str:
        """Why ``values`` [unit] leave the allowed range, with a unit hint where a prefix would bring
        them in (:func:`~ddgsa.units.prefix_hint`); empty when inside. The one check of a value
        against its range, for the Python API (:meth:`Model.resolve`) and the study file alike.

        Parameters
        ----------
        values : float or (float, float)
            A value, or an interval such as a distribution's support [unit].
        what : str
            What the values are, e.g. ``"support"``.
        hint : bool
            Advise a unit prefix; off where the user wrote a unit (its numbers are not in this unit).

        Examples
        --------
        >>> ModelParameter("k", 1e10, "N/m", "stiffness", 1e8, 1e12).range_problem(1e7)
        "parameter 'k' = 1e+07 N/m leaves its allowed range [1e+08, 1e+12] N/m (hint: 1e+07 kN/m = 1e+10 N/m is inside it: if the number is in kN/m, write unit: kN/m)"
        """
        given = (values,) if isinstance(values, (int, float, np.floating)) else tuple(values)
        if all(self.low <= float(v) <= self.high for v in given):
            return ""
        text = f"{float(given[0]):g}" if len(given) == 1 else f"[{', '.join(f'{float(v):g}' for v in given)}]"
        unit = "" if self.unit in ("", "-", "1") else f" {self.unit}"
        return (f"parameter {self.name!r} {what} {text}{unit} leaves its allowed range "
                f"[{self.low:g}, {self.high:g}]{unit}" + (prefix_hint(given, self.unit, self.low, self.high) if hint
                                                          else ""))


@dataclass(frozen=True)
class ModelOption:
    """A declared model option (like :class:`ModelParameter`, OpenMDAO's ``options.declare``):
    its kind and allowed values, checked by :meth:`Model.check_options` before a model is built.

    Attributes
    ----------
    name : str
    kind : {"number", "integer", "bool", "choice", "numbers", "mapping"}
        ``numbers``: a list of ``length`` finite numbers; ``mapping``: field -> value (the model
        checks the fields).
    description : str
    low, high : float
        Allowed range of a number [unit]; ``low`` excluded when ``low_open``.
    unit : str
    choices : tuple of str
        The allowed values of a ``choice``.
    optional : bool
        ``None`` (null) allowed: the model's default.
    length : int
        Length of ``numbers``.

    Examples
    --------
    >>> ModelOption("time_step", "number", "integration step", 0.0, 0.1, "s", low_open=True).check("m", float("nan"))
    Traceback (most recent call last):
    ...
    ddgsa.errors.ModelError: model 'm': option 'time_step' must be a finite number in (0, 0.1] s, got nan
    """

    name: str
    kind: str
    description: str
    low: float = -math.inf
    high: float = math.inf
    unit: str = ""
    low_open: bool = False
    choices: tuple[str, ...] = ()
    optional: bool = False
    length: int = 0

    def allowed(self) -> str:
        """What the option allows, in words."""
        if self.kind == "bool":
            return "true or false"
        if self.kind == "choice":
            return f"one of {', '.join(self.choices)}"
        if self.kind == "mapping":
            return "a mapping of field: value"
        rng = f"{'(' if self.low_open else '['}{self.low:g}, {self.high:g}]"
        unit = f" {self.unit}" if self.unit else ""
        what = "an integer" if self.kind == "integer" else "a finite number"
        return f"{self.length} finite numbers in {rng}{unit}" if self.kind == "numbers" else f"{what} in {rng}{unit}"

    def check(self, model: str, value: Any) -> None:
        """Raise :class:`ModelError` naming the model, the option, what it allows and the value given."""
        if value is None and self.optional:
            return
        if self.kind == "bool":
            ok = isinstance(value, bool)
        elif self.kind == "choice":
            ok = isinstance(value, str) and value in self.choices
        elif self.kind == "mapping":
            ok = isinstance(value, Mapping)
        elif self.kind == "numbers":
            ok = isinstance(value, (list, tuple)) and len(value) == self.length and all(map(self._number, value))
        else:
            ok = self._number(value) and (self.kind != "integer" or isinstance(value, int))
        if not ok:
            message = f"model {model!r}: option {self.name!r} must be {self.allowed()}, got {clip(value)}"
            raise ModelError(with_hint(message, value, self.choices) if self.kind == "choice" else message)

    def _number(self, v: Any) -> bool:
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            return False
        return (self.low < v if self.low_open else self.low <= v) and v <= self.high


class ModelOutput(str):
    """A declared model output: its name (it *is* that string, so ``model.outputs`` stays a tuple
    of names) with unit, meaning and plausible range.

    Parameters
    ----------
    name : str
    unit : str
        SI unit, e.g. ``"m"``, ``"1/s"``, ``"Hz"``, ``"-"``.
    description : str
        What the number is, in one line (of what, over what, per what).
    low, high : float
        Plausible range [unit]: values outside are possible but suggest an input or model
        problem; :meth:`Model.evaluate` warns (:class:`ImplausibleOutputWarning`) and reports flag them.
    resolution : float
        Smallest spread of the output the model can tell from its own noise [unit]: a sensor's
        measurement noise, a solver's tolerance. An output whose standard deviation over a study's
        design is at most this (or at most :data:`~ddgsa.gsa.result.CONSTANT_CV` of its mean, the
        numerical floor every output has) has nothing to rank (:func:`~ddgsa.gsa.result.nothing_to_rank`).
        0 for a deterministic output read from a converged solution: only the numerical floor applies.

    Examples
    --------
    >>> out = ModelOutput("rms_deflection_hub", "m", "RMS radial deflection at the hub", 0.0, 0.05)
    >>> out == "rms_deflection_hub", out.unit, out.label, out.resolution
    (True, 'm', 'rms_deflection_hub [m]', 0.0)
    """

    unit: str
    description: str
    low: float
    high: float
    resolution: float

    def __new__(cls, name: str, unit: str = "", description: str = "", low: float = -math.inf,
                high: float = math.inf, resolution: float = 0.0) -> "ModelOutput":
        if not resolution >= 0.0:
            raise ValueError(f"output {name!r}: resolution must be >= 0 [{unit}], got {resolution!r}")
        self = super().__new__(cls, name)
        self.unit, self.description, self.low, self.high = unit, description, float(low), float(high)
        self.resolution = float(resolution)
        return self

    def __getnewargs__(self) -> tuple[str, str, str, float, float, float]:  # type: ignore[override]
        return str(self), self.unit, self.description, self.low, self.high, self.resolution

    @property
    def name(self) -> str:
        """The output's name as a plain string."""
        return str(self)

    @property
    def label(self) -> str:
        """``name [unit]`` for table headers and axis labels."""
        return f"{self} [{self.unit}]" if self.unit else str(self)

    def plausible(self, values: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Which finite ``values`` lie in the plausible range (non-finite ones count as plausible:
        they are failures, reported as such)."""
        v = np.asarray(values, dtype=float)
        return ~np.isfinite(v) | ((v >= self.low) & (v <= self.high))


@dataclass(frozen=True)
class SignalOutput:
    """A declared signal output: a vector on a fixed grid (spectrum, order track, time series).

    Attributes
    ----------
    name : str
    unit : str
        Unit of the values, e.g. ``"N"``.
    description : str
        What the vector is, in one line.
    axis : str
        What its grid measures, e.g. ``"frequency"``.
    axis_unit : str
        The grid's unit, e.g. ``"Hz"``; the grid itself comes from :meth:`Model.signal_axis`.
    """

    name: str
    unit: str
    description: str
    axis: str
    axis_unit: str


class ImplausibleOutputWarning(UserWarning):
    """An output left its declared plausible range (an input or a model problem, most likely)."""


def declared(output: str) -> ModelOutput:
    """``output`` as a :class:`ModelOutput` (an undeclared name gets no unit and no range)."""
    return output if isinstance(output, ModelOutput) else ModelOutput(output)


class Model(ABC):
    """Base class: parameters declared once, evaluated many points at a time.

    Subclasses set ``name`` (by :func:`register_model`), ``parameters`` and ``outputs`` and
    implement :meth:`_evaluate_one`, :meth:`simulate` and :meth:`modes`. A model whose scenes
    are not wind scenes declares its own ``scene_type`` (a validating dataclass with a ``seed``
    field and a ``to_dict()``); studies validate their ``scenes:`` against it.
    """

    name: ClassVar[str] = ""
    scene_type: ClassVar[type] = Scene
    scene_fields_read: ClassVar[tuple[str, ...] | None] = None
    """The scene fields the model's outputs depend on; None: every field of its ``scene_type``. Tables keep
    every label field; the report's chart titles name only these."""
    basis_rule: ClassVar[BasisRule | None] = None
    """How the model's finite-element shaft basis is checked for convergence (:mod:`ddgsa.models.basis`);
    ``None``: no such basis."""
    parameters: tuple[ModelParameter, ...] = ()        # per class, or per instance where options change them
    outputs: tuple[str, ...] = ()                     # names; ModelOutput declarations carry unit and range
    #: vector outputs on a fixed grid (:meth:`signal_axis`), computed only when asked for (``evaluate(signals=)``)
    signal_outputs: ClassVar[tuple[SignalOutput, ...]] = ()
    fidelities: ClassVar[tuple[str, ...]] = ()
    #: the fidelities ``fidelity: auto`` pilots and chooses from, its reference first (default: all)
    pilot_fidelities: ClassVar[tuple[str, ...]] = ()
    #: outputs that measure the numerical method, not the physics (e.g. constraint drift): reported,
    #: but ``fidelity: auto`` does not compare them between fidelities
    numerical_outputs: ClassVar[tuple[str, ...]] = ()
    options_note: ClassVar[str] = ""                   # how options change parameters/outputs (``ddgsa models``)
    #: the options the constructor takes besides ``fidelity`` (None: not declared, not checked)
    options: ClassVar[tuple[ModelOption, ...] | None] = None
    fidelity: str = ""

    @classmethod
    def check_options(cls, given: Mapping[str, Any]) -> None:
        """Check options against the declared :attr:`options` (and ``fidelity`` against
        :attr:`fidelities`) before the model is built.

        Raises
        ------
        ModelError
            For an unknown option (close names listed), a value the declaration does not allow, or an
            ``integrator`` other than ``gen_alpha`` with the ``linear`` fidelity (which has its own exact
            discretisation).
        """
        if given.get("fidelity") is not None and cls.fidelities:
            cls.check_fidelity(given["fidelity"])
        if cls.options is None:
            return
        declared = {o.name: o for o in cls.options}
        for key, value in given.items():
            if key == "fidelity":
                continue
            if key not in declared:
                raise ModelError(f"model {cls.name!r}: " + unknown_name_message("option", key, list(declared)))
            declared[key].check(cls.name, value)
        if given.get("fidelity") == "linear" and given.get("integrator", "gen_alpha") != "gen_alpha":
            raise ModelError(f"model {cls.name!r}: the linear fidelity has its own exact discretisation; "
                             f"integrator {given['integrator']!r} is for the other fidelities")

    @classmethod
    def pilot_pool(cls) -> tuple[str, ...]:
        """The fidelities ``fidelity: auto`` pilots: :attr:`pilot_fidelities`, else all of :attr:`fidelities`."""
        return cls.pilot_fidelities or cls.fidelities

    def fidelity_cost(self, fidelity: str) -> float:
        """Relative cost of one evaluation at ``fidelity`` [-], the deterministic cost model that
        ``fidelity: auto`` ranks by (never measured time, so a choice does not depend on the
        machine or its load).

        The default is the declared order: ``fidelities`` lists the richest and costliest first,
        so the k-th of n costs ``n - k``. A model whose costs are known better overrides this.
        """
        if fidelity not in self.fidelities:
            raise ModelError(unknown_name_message(f"fidelity of model {self.name!r}", fidelity, list(self.fidelities)))
        return float(len(self.fidelities) - self.fidelities.index(fidelity))

    @property
    def nominal(self) -> dict[str, float]:
        """Parameter name -> nominal value (SI units)."""
        return {p.name: p.nominal for p in self.parameters}

    def parameter(self, name: str) -> ModelParameter:
        """The declaration of parameter ``name``."""
        for p in self.parameters:
            if p.name == name:
                return p
        raise ModelError(unknown_name_message(f"parameter of model {self.name!r}", name,
                                              [p.name for p in self.parameters], where="ddgsa models"))

    def parameter_table(self) -> pd.DataFrame:
        """Declared parameters as a table (name, nominal, unit, low, high, description)."""
        return pd.DataFrame([{"name": p.name, "nominal": p.nominal, "unit": p.unit, "low": p.low,
                              "high": p.high, "description": p.description} for p in self.parameters])

    def output(self, name: str) -> ModelOutput:
        """The declaration of output ``name`` (unit, description, plausible range)."""
        for o in self.outputs:
            if o == name:
                return declared(o)
        raise ModelError(unknown_name_message(f"output of model {self.name!r}", name, list(self.outputs)))

    def output_table(self) -> pd.DataFrame:
        """Declared outputs as a table (name, unit, plausible low and high, description)."""
        return pd.DataFrame([{"name": str(o), "unit": o.unit, "plausible_low": o.low, "plausible_high": o.high,
                              "description": o.description} for o in map(declared, self.outputs)])

    def units(self) -> dict[str, str]:
        """The unit of every name a study's tables carry for this model: its scene fields (the scene
        type's ``units``), parameters and outputs, as declared. The one source the report's axes and the
        NetCDF export read (``-`` or an empty string: dimensionless or a word)."""
        return {**getattr(self.scene_type, "units", {}), **{p.name: p.unit for p in self.parameters},
                **{str(o): declared(o).unit for o in self.outputs}}

    def implausible(self, frame: pd.DataFrame) -> list[str]:
        """One message per output column of ``frame`` with values outside its plausible range."""
        msgs = []
        for col in frame.columns:
            if col not in self.outputs:
                continue
            o = self.output(col)
            v = frame[col].to_numpy(float)
            bad = ~o.plausible(v)
            if bad.any():
                worst = v[bad][np.argmax(np.abs(v[bad]))]
                msgs.append(f"model {self.name!r}: {bad.sum()} of {len(v)} values of {o.label} outside the "
                            f"plausible range [{o.low:g}, {o.high:g}] (e.g. {worst:.4g}); check the inputs")
        return msgs

    def unused_parameters(self) -> dict[str, str]:
        """Parameters that have no effect on any output at this fidelity and options, with the reason
        (e.g. ``"has no effect at fidelity rigid: ..."``); studies warn and reports list them by name."""
        return {}

    def point_problems(self, params: Mapping[str, float]) -> list[str]:
        """Why a parameter point (missing names nominal) lies outside the model's valid region,
        beyond each parameter's own range (e.g. bearings that cross); empty when valid."""
        return []

    def resolve(self, points: pd.DataFrame | Mapping[str, Any] | NDArray[np.float64] | None) -> pd.DataFrame:
        """Full parameter table: given columns, nominal values for the missing ones.

        Parameters
        ----------
        points : DataFrame, mapping, 2-D array or None
            A table with one column per given parameter; a mapping of parameter names to scalars
            (one point) or to equal-length arrays or lists (columns); a 2-D array of shape
            (n_points, n_parameters), columns in :attr:`parameters`' declared order; ``None`` for
            the nominal point. Values in each parameter's unit.

        Raises
        ------
        ModelError
            For an unknown parameter name, an array of the wrong shape, columns of unequal length,
            a value that is not a number, or one outside its declared range (the message of
            :meth:`ModelParameter.range_problem`, as a study file gets it).
        """
        frame = self._points_frame(points)
        column = {p.name: j for j, p in enumerate(self.parameters)}
        unknown = [c for c in frame.columns if c not in column]
        if unknown:
            raise ModelError(f"model {self.name!r}: " + unknown_name_message("parameter", unknown[0], list(column),
                                                                            where=f"ddgsa models {self.name}"))
        # one float block, filled column by column (a frame per column cost ~2 ms a batch)
        values = np.tile(np.array([p.nominal for p in self.parameters], dtype=float), (len(frame), 1))
        for name in frame.columns:
            try:
                values[:, column[name]] = frame[name].to_numpy(dtype=float)
            except (TypeError, ValueError):
                raise ModelError(f"model {self.name!r}: parameter {name!r} must be numbers [{self.parameter(name).unit}], "
                                 f"got {clip(frame[name].tolist())}") from None
        low, high = (np.array([getattr(p, b) for p in self.parameters]) for b in ("low", "high"))
        bad = ~((values >= low) & (values <= high))
        if bad.any():
            j = int(np.flatnonzero(bad.any(axis=0))[0])
            raise ModelError(f"model {self.name!r}: " + self.parameters[j].range_problem(float(values[bad[:, j], j][0])))
        return pd.DataFrame(values, columns=list(column))

    def _points_frame(self, points: pd.DataFrame | Mapping[str, Any] | NDArray[np.float64] | None) -> pd.DataFrame:
        """``points`` as a table of given columns (see :meth:`resolve`)."""
        if points is None:
            return pd.DataFrame([{}])
        if isinstance(points, pd.DataFrame):
            return points.reset_index(drop=True)
        if isinstance(points, Mapping):
            if all(np.ndim(v) == 0 for v in points.values()):
                return pd.DataFrame([dict(points)])
            shapes = {str(k): np.shape(v) for k, v in points.items()}
            if len(set(shapes.values())) != 1 or len(next(iter(shapes.values()))) != 1:
                raise ModelError(f"model {self.name!r}: a mapping of points gives every parameter one number, or "
                                 f"every parameter a 1-D column of one length; got shapes {clip(shapes)}")
            return pd.DataFrame({k: list(v) for k, v in points.items()})
        if isinstance(points, np.ndarray):
            names = [p.name for p in self.parameters]
            if points.ndim != 2 or points.shape[1] != len(names):
                raise ModelError(f"model {self.name!r}: an array of points has shape (n_points, {len(names)}), "
                                 f"one column per parameter in the declared order ({', '.join(names)}; "
                                 f"one point: array.reshape(1, -1)); got shape {points.shape}")
            return pd.DataFrame(points, columns=names)
        raise ModelError(f"model {self.name!r}: points are a DataFrame, a mapping of parameter names to numbers "
                         f"or columns, or a 2-D array (n_points, {len(self.parameters)}); got {type(points).__name__}")

    def control_features(self, scene: Any) -> tuple[ModelOutput, ...]:
        """The model's **control features** in ``scene``: quantities each run yields besides its outputs,
        smooth in the parameters where the outputs may not be (the rig's lowest lateral natural frequencies
        against the 1x order, which set its resonant responses), that the confirmation's control variates
        take as inputs (:class:`ddgsa.gsa.control.FeatureSurrogate`). :meth:`evaluate` returns them in
        ``attrs["features"]`` ({name: tuple of one float per point}, NaN where a point failed; tuples, not
        arrays, so that frames concatenate) from the same runs: no extra model run. Default: none
        (``evaluate`` then carries no ``features``)."""
        return ()

    def signal_output(self, name: str) -> SignalOutput:
        """The declaration of signal output ``name``."""
        for s in self.signal_outputs:
            if s.name == name:
                return s
        raise ModelError(unknown_name_message(f"signal output of model {self.name!r}", name,
                                              [s.name for s in self.signal_outputs]))

    def signal_axis(self, name: str, scene: Any) -> NDArray[np.float64]:
        """The grid [axis unit] of signal ``name`` in ``scene`` (the same at every parameter point).

        Raises
        ------
        ModelError
            For an unknown signal, or a scene the signal cannot be computed on (e.g. too short).
        """
        raise ModelError(unknown_name_message(f"signal output of model {self.name!r}", name,
                                              [s.name for s in self.signal_outputs]))

    def _evaluate_signals_one(self, params: dict[str, float], scene: Any,
                              signals: tuple[str, ...]) -> tuple[dict[str, float], dict[str, NDArray[np.float64]]]:
        """Outputs and the asked-for signals (each on :meth:`signal_axis`) for one full parameter set."""
        raise ModelError(f"model {self.name!r} has no signal outputs")

    def as_scene(self, scene: Any) -> Any:
        """``scene`` as the model's :attr:`scene_type`: a mapping of its fields made into one (a misspelt
        field named, with its nearest spelling); anything else as it is, for the model to check.

        Raises
        ------
        ModelError
            For a mapping with an unknown field.
        """
        if not isinstance(scene, Mapping):               # a scene (or what a model without scenes takes)
            return scene
        known = [f.name for f in dataclasses.fields(self.scene_type)]
        bad = [k for k in scene if k not in known]
        if bad:
            raise ModelError(f"model {self.name!r}: scene field {bad[0]!r} is not one of {self.scene_type.__name__}'s "
                             f"({', '.join(known)})" + (f"; {hint}" if (hint := did_you_mean(bad[0], known)) else ""))
        return self.scene_type(**scene)

    def evaluate(self, points: pd.DataFrame | Mapping[str, Any] | None, scene: Scene,
                 signals: tuple[str, ...] = ()) -> pd.DataFrame:
        """Objective functions at each parameter point for ``scene``.

        Returns one row per point and one column per output. A point whose simulation fails
        gets NaN outputs and its reason in ``result.attrs["failures"]`` ({row: reason}); it is
        never imputed. With ``signals`` (names of :attr:`signal_outputs`), ``result.attrs["signals"]``
        maps each to an array (n_points, n_bins) on :meth:`signal_axis` (NaN rows where a point failed).
        Where the model declares :meth:`control_features` for ``scene``, ``result.attrs["features"]``
        holds them ({name: one value per point}).
        The points are resolved (:meth:`resolve`) and handed to :meth:`_evaluate_block` as one block.
        """
        out = self._evaluate_block(self.resolve(points), self.as_scene(scene), tuple(signals))
        for msg in self.implausible(out):
            warnings.warn(msg, ImplausibleOutputWarning, stacklevel=2)
        return out

    def _evaluate_block(self, params: pd.DataFrame, scene: Any, signals: tuple[str, ...] = ()) -> pd.DataFrame:
        """Outputs of a block of resolved points ``params`` (one row per point, every declared
        parameter a column, SI) in ``scene``: the block contract of :meth:`evaluate`.

        Returns one row per point (in order) and one column per output, ``attrs["failures"]``
        ({row: reason}, NaN outputs in that row), with ``signals``, ``attrs["signals"]`` ({name:
        (n_points, n_bins)}) and, with :meth:`control_features`, ``attrs["features"]`` ({name: tuple}). The
        default loops over the points (:meth:`_evaluate_one`, :meth:`_evaluate_signals_one`, whose
        dicts carry the features beside the outputs); a model that computes a block at once overrides it.
        """
        rows, failures = [], {}
        vectors: dict[str, list[NDArray[np.float64]]] = {s: [] for s in signals}
        axes = {s: self.signal_axis(s, scene) for s in signals}
        names = list(params.columns)
        for i, row in enumerate(dict(zip(names, values)) for values in params.to_numpy().tolist()):
            try:
                if signals:
                    scalars, arrays = self._evaluate_signals_one(row, scene, tuple(signals))
                    for s in signals:
                        vectors[s].append(np.asarray(arrays[s], dtype=float).reshape(len(axes[s])))
                    rows.append(scalars)
                else:
                    rows.append(self._evaluate_one(row, scene))
            except (ArithmeticError, RuntimeError, ValueError, np.linalg.LinAlgError) as exc:
                failures[i] = f"{type(exc).__name__}: {exc}"
                rows.append({o: np.nan for o in self.outputs})
                for s in signals:
                    vectors[s] = vectors[s][:i] + [np.full(len(axes[s]), np.nan)]
        out = pd.DataFrame(rows, columns=[str(o) for o in self.outputs])
        out.attrs["failures"] = failures
        features = [str(f) for f in self.control_features(scene)]
        if features:
            out.attrs["features"] = {f: tuple(float(r.get(f, math.nan)) for r in rows) for f in features}
        if signals:
            out.attrs["signals"] = {s: np.vstack(v) if v else np.zeros((0, len(axes[s]))) for s, v in vectors.items()}
        return out

    @abstractmethod
    def _evaluate_one(self, params: dict[str, float], scene: Scene) -> dict[str, float]:
        """Outputs for one full parameter set."""

    @abstractmethod
    def simulate(self, scene: Scene, params: Mapping[str, float] | None = None) -> pd.DataFrame:
        """Time series (indexed by time [s]) of states, bearing forces and loads."""

    def build(self, params: Mapping[str, float] | None = None, **conditions: Any) -> Any:
        """The model's system built from the kernel's parts (:mod:`ddgsa.mbs`) at ``params`` (missing ->
        nominal) and the model's operating ``conditions`` (the rig's scene, the geared drive's rotor
        speed and torque, the generator's mean hub forces): one spelling on every model, each
        documenting what it returns. A model without a multibody system refuses.

        Raises
        ------
        ModelError
            For a model that is not built from the kernel's parts.
        """
        raise ModelError(f"model {self.name!r} is not built from the kernel's parts: nothing to build")

    @abstractmethod
    def modes(self, params: Mapping[str, float] | None = None, rotor_speed: float = 0.0) -> pd.DataFrame:
        """Natural frequencies [Hz], damping ratios and labels at ``params``, the rotor turning at
        ``rotor_speed`` [rad/s] (a model without a rotor speed refuses a nonzero one,
        :meth:`standstill_only`)."""

    def campbell(self, speeds: Any, orders: Any = (1.0,), params: Mapping[str, float] | None = None,
                 max_frequency_hz: float = math.inf) -> CampbellDiagram:
        """Campbell diagram: :meth:`modes` at each rotor speed of ``speeds`` [rad/s], those at or
        below ``max_frequency_hz`` [Hz], with the order lines ``orders``. A model that classifies
        whirl or tracks branches by shape overrides it with the same signature (the rig)."""
        tables = {}
        for w in np.asarray(speeds, dtype=float):
            table = self.modes(params, rotor_speed=float(w))
            tables[float(w)] = table[table["frequency_hz"] <= max_frequency_hz]
        return campbell_from_tables(tables, tuple(float(o) for o in orders), max_frequency_hz)

    @classmethod
    def check_fidelity(cls, fidelity: str) -> None:
        """The one fidelity check of every model: ``fidelity`` must be one of :attr:`fidelities`.

        Raises
        ------
        ModelError
            Naming the model, the fidelity given and the known ones.
        """
        if fidelity not in cls.fidelities:
            raise ModelError(with_hint(f"model {cls.name!r}: unknown fidelity {fidelity!r}; "
                                       f"known: {', '.join(cls.fidelities)}", fidelity, cls.fidelities))

    def standstill_only(self, rotor_speed: float) -> None:
        """Refuse a nonzero ``rotor_speed`` [rad/s] for a model whose modes have no rotor speed.

        Raises
        ------
        ModelError
            When ``rotor_speed`` is not 0.
        """
        if rotor_speed != 0.0:
            raise ModelError(f"model {self.name!r} has no rotor speed to sweep (its modes are at standstill; "
                             f"got rotor_speed = {rotor_speed:g} rad/s): no Campbell diagram")

    def scene_figures(self, scene: Any, params: Mapping[str, float] | None = None) -> list[tuple[Any, str]]:
        """The model's own signal plots of one run at ``params`` as ``(figure, name)`` pairs (a
        study's report draws them at its nominal point; e.g. the rig's order maps); none by default."""
        return []

    def sampling_checks(self, scene: Scene) -> list[dict[str, Any]]:
        """The aliasing guard's table for ``scene`` at nominal parameters
        (:func:`ddgsa.mbs.sampling.sampling_row` rows); none for a model without modes."""
        return []


def controller_row(dt: float, frequency_hz: float, mode: str) -> dict[str, object]:
    """The sampling-table row of a scene's load and controller interval ``dt`` [s] against a
    model's highest mode ``frequency_hz`` [Hz] (``mode``: its label).

    ddgsa computes loads and control beforehand (one-way coupling) and feeds them as a C1 cubic,
    so this interval cannot alias the structure here; it ends the excitation band at ``1/(2 dt)``,
    and the same interval in a two-way co-simulation would alias the mode (seed 003 §3.2).
    """
    return sampling_row("load and controller interval (scene dt)", dt, frequency_hz, mode,
                        f"no load content above {1 / (2 * dt):.3g} Hz: the mode responds quasi-statically "
                        "only; a two-way co-simulation at this interval would alias it (seed 003 §3.2)")
