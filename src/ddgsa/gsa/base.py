"""What every GSA method is: a ``design`` (points to evaluate) and an ``analyze`` (indices).

Splitting the two lets the runner pool the designs of several methods, cache
evaluations on disk and resume; :func:`ddgsa.sobol` simply chains them.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.errors import MethodError
from ddgsa.registry import Registry
from ddgsa.gsa.result import Diagnostic, SobolResult
from ddgsa.space import ParameterSpace

METHODS: Registry[type["GsaMethod"]] = Registry("GSA method", MethodError)
register = METHODS.register


def get_method(name: str) -> "GsaMethod":
    """An instance of the registered method ``name``.

    Raises
    ------
    MethodError
        If no method of that name exists; the message lists the known ones.
    """
    return METHODS.lookup(name)()


@dataclass(frozen=True)
class Design:
    """The points a method needs, with what its ``analyze`` needs to read them back.

    Attributes
    ----------
    method : str
        Registry name of the method that made it.
    points : ndarray, shape (n_points, n_params)
        Parameter values in the space's column order [SI units].
    options : dict
        Resolved options (defaults filled in).
    meta : dict
        Method-specific layout (quadrature nodes, unit-cube sample...).
    """

    method: str
    points: NDArray[np.float64]
    options: dict[str, Any]
    meta: dict[str, Any] = field(default_factory=dict)

    @property
    def n_points(self) -> int:
        """Number of model evaluations the design asks for."""
        return int(self.points.shape[0])


class GsaMethod(ABC):
    """Base class of GSA methods.

    Subclasses declare ``defaults`` (every option with its default) and implement
    :meth:`_design` and :meth:`_analyze`. Option names are checked here; values are
    checked by each method.
    """

    name: ClassVar[str] = ""
    defaults: ClassVar[dict[str, Any]] = {}

    def resolve_options(self, options: Mapping[str, Any]) -> dict[str, Any]:
        """Defaults updated with ``options``; unknown option names are refused."""
        unknown = set(options) - set(self.defaults)
        if unknown:
            raise MethodError(f"method {self.name!r}: unknown option(s) {sorted(unknown)}; "
                              f"allowed: {', '.join(sorted(self.defaults))}")
        return {**self.defaults, **options}

    def design(self, space: ParameterSpace, **options: Any) -> Design:
        """The points this method needs on ``space`` with ``options``."""
        opts = self.resolve_options(options)
        self.check_options(space, opts)
        return self._design(space, opts)

    def n_points(self, space: ParameterSpace, **options: Any) -> int:
        """How many points :meth:`design` would return, without building it (options checked):
        a study's run size is estimated from it before any large design is allocated."""
        opts = self.resolve_options(options)
        self.check_options(space, opts)
        return self._n_points(space, opts)

    def _n_points(self, space: ParameterSpace, opts: dict[str, Any]) -> int:
        """The design's size from checked options (default: build it; methods override with the count)."""
        return self._design(space, opts).n_points

    def analyze(self, space: ParameterSpace, design: Design,
                values: NDArray[np.float64] | pd.DataFrame | pd.Series,
                outputs: Sequence[str] | None = None) -> SobolResult:
        """Indices from the model ``values`` at ``design.points``.

        Parameters
        ----------
        values : array (n_points,) or (n_points, n_outputs), or DataFrame
            Model outputs, row ``k`` at ``design.points[k]``. Non-finite values mark
            failed evaluations: an output with any is refused (NaN indices, diagnostic
            ``nonfinite_values``, untrusted), never imputed.
        outputs : sequence of str, optional
            Output names (DataFrame columns are used when given a DataFrame).
        """
        y, names = as_value_matrix(values, design.n_points, outputs)
        finite = np.isfinite(y).all(axis=0)
        n_out, d = len(names), space.dim
        S1, ST = np.full((n_out, d), np.nan), np.full((n_out, d), np.nan)
        S1c, STc = np.full((n_out, d), np.nan), np.full((n_out, d), np.nan)
        diags: list[Diagnostic] = []
        extras: dict[str, Any] = {}
        for j in np.flatnonzero(~finite):
            bad = int((~np.isfinite(y[:, j])).sum())
            diags.append(Diagnostic(
                "nonfinite_values",
                f"output {names[j]!r}: {bad} of {design.n_points} evaluations failed or are not finite; "
                "its indices are not computed (failures are never imputed)",
                "untrusted", output=names[j], value=float(bad)))
        if finite.any():
            cols = np.flatnonzero(finite)
            part = self._analyze(space, design, y[:, cols], [names[j] for j in cols])
            S1[cols], ST[cols] = part.S1, part.ST
            S1c[cols], STc[cols] = part.S1_conf, part.ST_conf
            diags += part.diagnostics
            extras = part.extras
        return SobolResult.from_arrays(outputs=names, parameters=space.names, S1=S1, ST=ST,
                                       S1_conf=S1c, ST_conf=STc, n_evals=design.n_points,
                                       method=self.name, options=design.options,
                                       diagnostics=diags, extras=extras)

    def check_options(self, space: ParameterSpace, opts: dict[str, Any]) -> None:
        """Raise :class:`MethodError` for invalid option values (override to add checks)."""

    @abstractmethod
    def _design(self, space: ParameterSpace, opts: dict[str, Any]) -> Design:
        """Make the design (options already resolved and checked)."""

    @abstractmethod
    def _analyze(self, space: ParameterSpace, design: Design, y: NDArray[np.float64],
                 outputs: list[str]) -> "PartialIndices":
        """Indices for finite outputs ``y`` (n_points, n_outputs)."""


@dataclass
class PartialIndices:
    """Arrays (n_outputs, n_params) a method returns for its finite outputs."""

    S1: NDArray[np.float64]
    ST: NDArray[np.float64]
    S1_conf: NDArray[np.float64] | float = np.nan
    ST_conf: NDArray[np.float64] | float = np.nan
    diagnostics: list[Diagnostic] = field(default_factory=list)
    extras: dict[str, Any] = field(default_factory=dict)


def as_value_matrix(values: NDArray[np.float64] | pd.DataFrame | pd.Series, n_points: int,
                    outputs: Sequence[str] | None = None) -> tuple[NDArray[np.float64], list[str]]:
    """Model values as a float matrix (n_points, n_outputs) and the output names."""
    if isinstance(values, pd.DataFrame):
        names = [str(c) for c in values.columns]
        y = values.to_numpy(dtype=float)
    elif isinstance(values, pd.Series):
        names = [str(values.name or "y")]
        y = values.to_numpy(dtype=float)[:, None]
    else:
        y = np.asarray(values, dtype=float)
        if y.ndim == 1:
            y = y[:, None]
        names = ["y"] if y.shape[1] == 1 else [f"y{k}" for k in range(y.shape[1])]
    if outputs is not None:
        names = [str(o) for o in outputs]
    if y.ndim != 2 or y.shape[0] != n_points:
        raise MethodError(f"expected {n_points} model values (one per design point), got shape {y.shape}")
    if len(names) != y.shape[1]:
        raise MethodError(f"{len(names)} output names for {y.shape[1]} output columns")
    return y, names


def check_int(method: str, key: str, value: Any, low: int, high: int | None = None) -> int:
    """An integer option in ``[low, high]`` or a :class:`MethodError` naming it."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise MethodError(f"method {method!r}: option {key!r} must be an integer, got {value!r}")
    if value < low or (high is not None and value > high):
        rng = f">= {low}" if high is None else f"in [{low}, {high}]"
        raise MethodError(f"method {method!r}: option {key!r} must be {rng}, got {value}")
    return int(value)


def check_choice(method: str, key: str, value: Any, allowed: Sequence[str]) -> str:
    """A string option among ``allowed`` or a :class:`MethodError` naming it."""
    if value not in allowed:
        raise MethodError(f"method {method!r}: option {key!r} must be one of {', '.join(allowed)}; got {value!r}")
    return str(value)


def check_fraction(method: str, key: str, value: Any, low: float = 0.0, high: float = 1.0) -> float:
    """A float option in ``(low, high)`` or a :class:`MethodError` naming it."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)) \
            or not low < float(value) < high:
        raise MethodError(f"method {method!r}: option {key!r} must be a number in ({low}, {high}), got {value!r}")
    return float(value)
