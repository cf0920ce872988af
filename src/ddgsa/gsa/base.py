"""What every GSA method is: a ``design`` (points to evaluate) and an ``analyze`` (indices).

Splitting the two lets the runner pool the designs of several methods, cache
evaluations on disk and resume; :func:`ddgsa.sobol` simply chains them.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.errors import MethodError, unknown_name_message, with_hint
from ddgsa.registry import Registry
from ddgsa.gsa.groups import GroupIndices, group_frame
from ddgsa.gsa.result import Diagnostic, SobolResult
from ddgsa.gsa.trust import DEFAULT_TOLERANCE
from ddgsa.gsa.space import ParameterSpace

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
            first = sorted(unknown, key=str)[0]
            raise MethodError(f"method {self.name!r}: " + unknown_name_message("option", first, sorted(self.defaults))
                              + (f" (also unknown: {', '.join(map(repr, sorted(unknown, key=str)[1:]))})"
                                 if len(unknown) > 1 else ""))
        return {**self.defaults, **options}

    def design(self, space: ParameterSpace, **options: Any) -> Design:
        """The points this method needs on ``space`` with ``options``."""
        opts = self.resolve_options(options)
        self.check_space(space)
        self.check_options(space, opts)
        return self._design(space, opts)

    sobol_sizes: ClassVar[tuple[str, ...]] = ()
    """Options that set a number of scrambled Sobol' points (best a power of two: ``validate`` hints
    at another size, naming the field)."""

    dependent_inputs: ClassVar[bool] = False
    """Whether the method is valid for correlated inputs (only ``shapley`` is)."""

    def followup(self, space: ParameterSpace, design: Design,
                 values: NDArray[np.float64] | pd.DataFrame | pd.Series,
                 outputs: Sequence[str] | None = None) -> Design | None:
        """A second round of points, decided from the first round's ``values`` (None: the method has
        none, the default). The returned design holds ``design``'s points first, then the new ones;
        :meth:`analyze` takes it with the values of all of them. Callers: :func:`ddgsa.sobol`, a
        study's ``kind: gsa`` (:mod:`ddgsa.execute.kinds.gsa`)."""
        return None

    def check_space(self, space: ParameterSpace) -> None:
        """Refuse a correlated space when the method assumes independent inputs, saying what to use."""
        if space.dependent and not self.dependent_inputs:
            pairs = ", ".join(f"{a}-{b} {rho:g}" for a, b, rho in space.correlation)
            raise MethodError(f"method {self.name!r} assumes independent inputs, and the space correlates "
                              f"{pairs}; use method 'shapley' (Shapley effects with full first-order and "
                              "independent total indices, ddgsa.gsa.shapley), or drop 'correlation'")

    def n_points(self, space: ParameterSpace, **options: Any) -> int:
        """How many points :meth:`design` would return, without building it (options checked):
        a study's run size is estimated from it before any large design is allocated."""
        opts = self.resolve_options(options)
        self.check_space(space)
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
            Model outputs, row ``k`` at ``design.points[k]``, in any units: each output is
            standardised (:func:`standardise`) before the method sees it, so the indices and
            flags do not depend on its scale. Non-finite values mark failed evaluations: an
            output with any is refused (NaN indices, diagnostic ``nonfinite_values``,
            untrusted), never imputed; a constant one has undefined indices (``zero_variance``).
        outputs : sequence of str, optional
            Output names (DataFrame columns are used when given a DataFrame).
        """
        y, names = as_value_matrix(values, design.n_points, outputs)
        finite = np.isfinite(y).all(axis=0)
        with np.errstate(invalid="ignore"):
            constant = finite & (np.nanmax(y, axis=0) == np.nanmin(y, axis=0)) if len(y) else finite
        n_out, d = len(names), space.dim
        S1, ST = np.full((n_out, d), np.nan), np.full((n_out, d), np.nan)
        S1c, STc = np.full((n_out, d), np.nan), np.full((n_out, d), np.nan)
        st_err = np.full((n_out, d), np.nan)
        pair_err = np.full((n_out, d, d), np.nan)
        diags: list[Diagnostic] = []
        extras: dict[str, Any] = {}
        variance = np.where(constant, 0.0, np.nan)
        n_groups = len(space.groups)
        groups = GroupIndices(*(np.full((n_out, n_groups), np.nan) for _ in range(4)))
        columns: dict[str, NDArray[np.float64]] = {}
        for j in np.flatnonzero(~finite):
            bad = int((~np.isfinite(y[:, j])).sum())
            diags.append(Diagnostic(
                "nonfinite_values",
                f"output {names[j]!r}: {bad} of {design.n_points} evaluations failed or are not finite; "
                "its indices are not computed (failures are never imputed)",
                "untrusted", output=names[j], value=float(bad)))
        for j in np.flatnonzero(constant):
            diags.append(Diagnostic("zero_variance", f"output {names[j]!r} is constant ({y[0, j]:.6g}) at all "
                                    f"{design.n_points} points; its Sobol indices are undefined", "untrusted",
                                    output=names[j], value=float(y[0, j])))
        usable = finite & ~constant
        if usable.any():
            cols = np.flatnonzero(usable)
            shift, scale = standardise(y[:, cols], centre=self.centre)
            part = self._analyze(space, design, (y[:, cols] - shift) / scale, [names[j] for j in cols])
            S1[cols], ST[cols] = part.S1, part.ST
            S1c[cols], STc[cols] = part.S1_conf, part.ST_conf
            st_err[cols] = part.extras.get("ST_error", part.ST_conf)
            if "ST_diff_error" in part.extras:
                pair_err[cols] = part.extras["ST_diff_error"]
            diags += part.diagnostics
            if "variance" in part.extras:
                variance[cols] = part.extras["variance"] * scale ** 2
            extras = self.unscale_extras({k: v for k, v in part.extras.items() if k not in ("variance", "ST_diff_error")},
                                         shift, scale)
            if part.groups is not None:
                for name in ("S_closed", "ST", "S_closed_conf", "ST_conf"):
                    getattr(groups, name)[cols] = getattr(part.groups, name)
            for name, values in part.columns.items():
                columns.setdefault(name, np.full((n_out, d), np.nan))[cols] = values
        extras["variance"] = variance
        diags += undefined_index_diagnostics(names, space.names, S1, ST, diags, self.gives_st)
        res = SobolResult.from_arrays(outputs=names, parameters=space.names, S1=S1, ST=ST,
                                      S1_conf=S1c, ST_conf=STc, n_evals=design.n_points,
                                      method=self.name, options=design.options,
                                      diagnostics=diags, extras=extras, ST_error=st_err,
                                      ST_diff_error=pair_err if np.isfinite(pair_err).any() else None)
        for name, values in columns.items():
            res.indices[name] = values.ravel()
        if self.rank_by != "ST":
            bound = next(c for c in (f"{self.rank_by}_error", f"{self.rank_by}_conf") if c in res.indices)
            res.extras.update(rank_by=self.rank_by, rank_error=res.indices[bound].to_numpy(float))
            res.extras.pop("rank_diff_error", None)          # it bounds differences of ST, not of this column
            res = res.rerank()
        res.groups = group_frame(names, space.groups, groups if self.gives_groups else None, diags,
                                 res.options.get("tolerance", DEFAULT_TOLERANCE))
        return res

    rank_by: ClassVar[str] = "ST"
    """The column the rows are ranked by (:func:`~ddgsa.gsa.result.rank_structure`), its ``_error`` column (else
    ``_conf``) the error bound where it is not ``ST``: Shapley effects rank by ``Sh``, the share that sums to one
    under dependence."""

    gives_sobol: ClassVar[bool] = True
    """Whether the method estimates Sobol indices at all (HSIC screening does not: its rows carry other measures)."""
    gives_groups: ClassVar[bool] = False
    """Whether ``_analyze`` returns group indices (``PartialIndices.groups``) for a space with groups."""

    centre: ClassVar[bool] = True
    """Whether ``_analyze`` may see centred outputs (M-DRM may not: its surrogate is a product)."""
    gives_st: ClassVar[bool] = True
    """Whether the method estimates ``ST`` (RBD-FAST does not)."""

    def unscale_extras(self, extras: dict[str, Any], shift: NDArray[np.float64],
                       scale: NDArray[np.float64]) -> dict[str, Any]:
        """``extras`` of the standardised outputs in the outputs' own units (override where any has units)."""
        return extras

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
    """Method-specific numbers; ``variance`` (n_outputs,), the method's estimate of each output's
    variance in the standardised units, becomes ``SobolResult.extras["variance"]`` in the output's own
    units (NaN where the method gives none; 0 for a constant output): the weights of the generalised
    indices of a signal (:mod:`ddgsa.gsa.signal`)."""
    groups: GroupIndices | None = None
    """Closed and total indices (n_outputs, n_groups) of the space's groups, where the method gives them."""
    columns: dict[str, NDArray[np.float64]] = field(default_factory=dict)
    """Further per-row quantities (n_outputs, n_params) added as columns of the table (e.g. ``Sh``)."""


def standardise(y: NDArray[np.float64], centre: bool = True) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Shift and scale (each (n_outputs,)) that make every column of ``y`` order one.

    With ``centre`` the columns are centred on their mean and scaled by their standard deviation;
    without, only scaled by their largest magnitude (the sign and the ratios between values are
    kept). Sobol indices are invariant under both maps, and estimators that difference or fit
    values (sparse PCE's least-angle path, Saltelli's products) then see the same numbers for an
    output in N m and in MN m, or a damage rate of 1e-9 1/s: the scale-free estimators of the
    module docstring. Non-constant finite columns give positive, finite scales.
    """
    if centre:
        shift = y.mean(axis=0)
        scale = y.std(axis=0)
    else:
        shift = np.zeros(y.shape[1])
        scale = np.abs(y).max(axis=0)
    return shift, np.where(scale > 0, scale, 1.0)


def undefined_index_diagnostics(outputs: Sequence[str], parameters: Sequence[str], S1: NDArray[np.float64],
                                ST: NDArray[np.float64], diagnostics: list[Diagnostic],
                                gives_st: bool = True) -> list[Diagnostic]:
    """An ``undefined_index`` diagnostic for each row whose index is NaN with no ``untrusted``
    diagnostic explaining it (no NaN is ever shown without a reason)."""
    explained = {(d.output, d.parameter) for d in diagnostics if d.severity == "untrusted"}
    out = []
    missing = ~np.isfinite(S1) | (~np.isfinite(ST) if gives_st else False)
    for j, i in zip(*np.nonzero(missing)):
        o, p = outputs[j], parameters[i]
        if {(None, None), (o, None), (None, p), (o, p)} & explained:
            continue
        out.append(Diagnostic("undefined_index", f"output {o!r}: {p}: the estimator gave no finite index "
                              "(0/0: no variance in its fit or sample)", "untrusted", output=o, parameter=p))
    return out


def evaluate(method: "GsaMethod", space: ParameterSpace, f: Callable[[NDArray[np.float64]], Any],
             options: Mapping[str, Any], outputs: Sequence[str] | None = None
             ) -> tuple[Design, NDArray[np.float64], list[str]]:
    """``method``'s design on ``space`` with ``options``, evaluated by the vectorised ``f``, and its second
    round (:meth:`GsaMethod.followup`) where it asks for one: the design run, the values (n, k) and
    their output names."""
    design = method.design(space, **options)
    y, names = as_value_matrix(f(design.points), design.n_points, outputs)
    more = method.followup(space, design, y, names)
    if more is not None:
        extra, _ = as_value_matrix(f(more.points[design.n_points:]), more.n_points - design.n_points, names)
        design, y = more, np.vstack([y, extra])
    return design, y, names


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
        raise MethodError(with_hint(f"method {method!r}: option {key!r} must be one of {', '.join(allowed)}; "
                                    f"got {value!r}", value, allowed))
    return str(value)


def check_fraction(method: str, key: str, value: Any, low: float = 0.0, high: float = 1.0) -> float:
    """A float option in ``(low, high)`` or a :class:`MethodError` naming it."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)) \
            or not low < float(value) < high:
        raise MethodError(f"method {method!r}: option {key!r} must be a number in ({low}, {high}), got {value!r}")
    return float(value)


def sobol_rows(indices: pd.DataFrame) -> pd.DataFrame:
    """The rows of methods that estimate Sobol indices (screening rows, HSIC's, are judged by their p-values,
    not by trust: they make no problem and take no place in the ranking)."""
    if not len(indices):
        return indices
    screening = [m for m in indices["method"].unique() if m in METHODS and not METHODS.lookup(m).gives_sobol]
    return indices[~indices["method"].isin(screening)]
