"""Parameter spaces: named uncertain inputs, their distributions, groups and correlations.

A :class:`ParameterSpace` holds :class:`Parameter` objects, each backed by a
chaospy distribution. All sampling goes through our own uniforms (numpy
``Generator`` or scipy QMC) mapped by the inverse CDF, so no global random
state is touched and a seed fully determines a sample.

Distribution specifications (keys of one parameter's mapping):

============  ==========================================  ==========================
dist          required keys                               shorthand
============  ==========================================  ==========================
uniform       ``low``, ``high``                           ``nominal``, ``spread``
normal        ``mean``, ``std``                           ``nominal``, ``spread``
lognormal     ``mu``, ``sigma`` (of log X) or ``median``,  --
              ``sigma``
truncnormal   ``mean``, ``std``, ``low``, ``high``         ``nominal``, ``spread``,
                                                          ``low``, ``high``
triangular    ``low``, ``mode``, ``high``                  ``nominal``, ``spread``
============  ==========================================  ==========================

``spread`` is a fraction of ``|nominal|``: ``low/high = nominal -/+ spread |nominal|``
for uniform and triangular (mode at nominal), ``std = spread |nominal|`` for
normal and truncated normal. ``dist`` defaults to ``uniform``. Optional keys:
``nominal`` (else the mean), ``unit``, ``description``.

**Groups** (``groups={"front_bearing": ["k_front_y", "k_front_z"]}``) name disjoint sets of
parameters whose closed and total Sobol indices methods report beside the per-parameter ones
(:mod:`ddgsa.gsa.groups`). **Correlation** (``correlation=[("a", "b", 0.5)]``) couples the
inputs by a Gaussian copula: ``z ~ N(0, R)``, ``x_i = F_i^-1(Phi(z_i))``, with ``R`` the
correlation matrix of the normal scores (not of ``x``; the two agree for normal inputs and
differ by under 0.02 for uniform ones), which must be positive definite. Methods that assume
independent inputs refuse a correlated space (:mod:`ddgsa.gsa.shapley` handles it).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, Literal

import chaospy
import numpy as np
import pandas as pd
from numpy.typing import NDArray
from scipy.stats import norm, qmc

from ddgsa.errors import SpaceError, with_hint

DIST_NAMES: tuple[str, ...] = ("uniform", "normal", "lognormal", "truncnormal", "triangular")
_META_KEYS = {"dist", "nominal", "unit", "description"}
_DIST_KEYS: dict[str, tuple[set[str], ...]] = {
    # each entry: alternative sets of keys (besides the meta keys) that define the distribution
    "uniform": ({"low", "high"}, {"spread"}),
    "normal": ({"mean", "std"}, {"spread"}),
    "lognormal": ({"mu", "sigma"}, {"median", "sigma"}),
    "truncnormal": ({"mean", "std", "low", "high"}, {"spread", "low", "high"}),
    "triangular": ({"low", "mode", "high"}, {"spread"}),
}
#: probabilities are clipped to [_U_EPS, 1 - _U_EPS] before the inverse CDF, so
#: unbounded distributions never map a quasi-random 0 or 1 to an infinite value
_U_EPS = 1e-12

SampleRule = Literal["sobol", "random", "lhs", "halton"]


def _as_float(name: str, key: str, value: Any) -> float:
    """Coerce a spec value to float (accepting ``"1e10"`` strings from YAML 1.1 loaders)."""
    if isinstance(value, bool):
        raise SpaceError(f"parameter {name!r}: {key!r} must be a number, got {value!r}")
    try:
        out = float(value)
    except (TypeError, ValueError):
        hint = ""
        if key == "spread" and isinstance(value, str) and value.strip().endswith("%"):
            try:
                hint = f" (a relative spread is a fraction: write {float(value.strip()[:-1]) / 100:g})"
            except ValueError:
                pass
        raise SpaceError(f"parameter {name!r}: {key!r} must be a number, got {value!r}{hint}") from None
    if not math.isfinite(out):
        raise SpaceError(f"parameter {name!r}: {key!r} must be finite, got {value!r}")
    return out


@dataclass(frozen=True)
class Parameter:
    """One uncertain input.

    Parameters
    ----------
    name : str
        Identifier (a valid Python identifier, e.g. ``k_front_y``).
    dist : str
        One of :data:`DIST_NAMES`.
    args : dict of str to float
        Canonical distribution arguments: uniform ``low, high``; normal ``mean, std``;
        lognormal ``mu, sigma`` (of the underlying normal); truncnormal ``mean, std, low,
        high``; triangular ``low, mode, high``.
    nominal : float
        Nominal value [unit]; the distribution mean unless given.
    unit : str
        Unit in SI, e.g. ``"N/m"``.
    description : str
        One line saying what the parameter is.
    """

    name: str
    dist: str
    args: dict[str, float]
    nominal: float
    unit: str = ""
    description: str = ""

    @classmethod
    def from_spec(cls, name: str, spec: Mapping[str, Any]) -> "Parameter":
        """Build a parameter from a specification mapping (see the module docstring).

        Raises
        ------
        SpaceError
            Naming the parameter and the problem: unknown distribution or key,
            missing key, non-numeric value, ``low >= high``, ``std <= 0`` ...
        """
        if not isinstance(name, str) or not name.isidentifier():
            raise SpaceError(f"parameter name {name!r} must be an identifier (letters, digits, _)")
        if not isinstance(spec, Mapping):
            raise SpaceError(f"parameter {name!r}: expected a mapping of dist and its arguments, "
                             f"got {type(spec).__name__} {spec!r}")
        dist = spec.get("dist", "uniform")
        if dist not in _DIST_KEYS:
            raise SpaceError(with_hint(f"parameter {name!r}: unknown dist {dist!r}; allowed: {', '.join(DIST_NAMES)}",
                                       dist, DIST_NAMES))
        given = set(spec) - _META_KEYS
        allowed = set().union(*_DIST_KEYS[dist])
        unknown = given - allowed
        if unknown:
            raise SpaceError(with_hint(f"parameter {name!r}: unknown key(s) {sorted(unknown)} for dist {dist!r}; "
                                       f"allowed: {sorted(allowed | _META_KEYS)}", min(unknown), allowed | _META_KEYS))
        forms = _DIST_KEYS[dist]
        form = next((f for f in forms if f == given), None)
        if form is None:
            wanted = " or ".join("{" + ", ".join(sorted(f)) + "}" for f in forms)
            raise SpaceError(f"parameter {name!r}: dist {dist!r} needs keys {wanted} "
                             f"(with 'spread', also 'nominal'); got {sorted(given)}")
        v = {k: _as_float(name, k, spec[k]) for k in given}
        nominal = _as_float(name, "nominal", spec["nominal"]) if "nominal" in spec else None
        if "spread" in v:
            if nominal is None:
                raise SpaceError(f"parameter {name!r}: 'spread' needs 'nominal'")
            if v["spread"] <= 0:
                raise SpaceError(f"parameter {name!r}: spread must be > 0 (a fraction of |nominal|), "
                                 f"got {v['spread']}")
            if nominal == 0:
                raise SpaceError(f"parameter {name!r}: 'spread' is a fraction of |nominal| and nominal is 0; "
                                 "give the bounds explicitly")
            half = v.pop("spread") * abs(nominal)
            if dist in ("uniform", "triangular"):
                v.update(low=nominal - half, high=nominal + half)
                if dist == "triangular":
                    v["mode"] = nominal
            else:
                v.update(mean=nominal, std=half)
        if "median" in v:
            if v["median"] <= 0:
                raise SpaceError(f"parameter {name!r}: lognormal median must be > 0, got {v['median']}")
            v["mu"] = math.log(v.pop("median"))
        cls._check_args(name, dist, v)
        param = cls(name=name, dist=dist, args=v, nominal=math.nan,
                    unit=str(spec.get("unit", "")), description=str(spec.get("description", "")))
        nominal = param.mean if nominal is None else nominal
        object.__setattr__(param, "nominal", nominal)
        lo, hi = param.support
        if not lo <= nominal <= hi:
            raise SpaceError(f"parameter {name!r}: nominal {nominal} lies outside the support [{lo}, {hi}]")
        return param

    @staticmethod
    def _check_args(name: str, dist: str, v: dict[str, float]) -> None:
        if "low" in v and v["low"] >= v["high"]:
            raise SpaceError(f"parameter {name!r}: low ({v['low']}) must be < high ({v['high']})")
        if v.get("std", 1.0) <= 0:
            raise SpaceError(f"parameter {name!r}: std must be > 0, got {v['std']}")
        if v.get("sigma", 1.0) <= 0:
            raise SpaceError(f"parameter {name!r}: sigma must be > 0, got {v['sigma']}")
        if dist == "triangular" and not v["low"] <= v["mode"] <= v["high"]:
            raise SpaceError(f"parameter {name!r}: mode ({v['mode']}) must lie in [low, high] = "
                             f"[{v['low']}, {v['high']}]")

    @cached_property
    def distribution(self) -> chaospy.Distribution:
        """The chaospy distribution of this parameter."""
        a = self.args
        if self.dist == "uniform":
            return chaospy.Uniform(a["low"], a["high"])
        if self.dist == "normal":
            return chaospy.Normal(a["mean"], a["std"])
        if self.dist == "lognormal":
            return chaospy.LogNormal(a["mu"], a["sigma"])
        if self.dist == "truncnormal":
            return chaospy.TruncNormal(a["low"], a["high"], a["mean"], a["std"])
        return chaospy.Triangle(a["low"], a["mode"], a["high"])

    @property
    def mean(self) -> float:
        """Mean of the distribution [unit]."""
        return float(self.distribution.mom(1))

    @property
    def std(self) -> float:
        """Standard deviation of the distribution [unit]."""
        return float(np.sqrt(self.distribution.mom(2) - self.distribution.mom(1) ** 2))

    @property
    def support(self) -> tuple[float, float]:
        """Lower and upper bound of the support (may be infinite) [unit]."""
        a = self.args
        if self.dist in ("uniform", "triangular", "truncnormal"):
            return a["low"], a["high"]
        if self.dist == "lognormal":
            return 0.0, math.inf
        return -math.inf, math.inf

    def ppf(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """Inverse CDF: map probabilities ``u`` in (0, 1) to parameter values [unit]."""
        u = np.clip(np.asarray(u, dtype=float), _U_EPS, 1.0 - _U_EPS)
        return np.asarray(self.distribution.inv(u), dtype=float).reshape(u.shape)

    def cdf(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """Cumulative distribution function at ``x``."""
        x = np.asarray(x, dtype=float)
        return np.asarray(self.distribution.fwd(x), dtype=float).reshape(x.shape)

    def to_spec(self) -> dict[str, Any]:
        """The canonical specification mapping (round-trips through :meth:`from_spec`)."""
        spec: dict[str, Any] = {"dist": self.dist, **self.args, "nominal": self.nominal}
        if self.unit:
            spec["unit"] = self.unit
        if self.description:
            spec["description"] = self.description
        return spec

    def salib_entry(self) -> tuple[str, list[float]]:
        """SALib ``dists`` name and ``bounds`` entry describing this distribution."""
        a = self.args
        if self.dist == "uniform":
            return "unif", [a["low"], a["high"]]
        if self.dist == "normal":
            return "norm", [a["mean"], a["std"]]
        if self.dist == "lognormal":
            return "lognorm", [a["mu"], a["sigma"]]
        if self.dist == "truncnormal":
            return "truncnorm", [a["low"], a["high"], a["mean"], a["std"]]
        return "triang", [a["low"], a["high"], (a["mode"] - a["low"]) / (a["high"] - a["low"])]


@dataclass(frozen=True)
class ParameterSpace:
    """Named uncertain parameters, with optional groups and Gaussian-copula correlations.

    Examples
    --------
    >>> space = ParameterSpace.from_dict({
    ...     "x1": {"dist": "uniform", "low": -3.14159, "high": 3.14159},
    ...     "k_front": {"dist": "normal", "mean": 1e10, "std": 1e9, "unit": "N/m"},
    ...     "c_gen": {"nominal": 8.28e5, "spread": 0.1},
    ... })
    >>> space.names
    ('x1', 'k_front', 'c_gen')
    >>> space.sample(4, seed=0).shape
    (4, 3)
    """

    parameters: tuple[Parameter, ...]
    groups: dict[str, tuple[str, ...]] = field(default_factory=dict)
    """Named disjoint groups of parameters (closed and total group indices are reported for them)."""
    correlation: tuple[tuple[str, str, float], ...] = ()
    """Gaussian-copula correlations ``(a, b, rho)`` of the normal scores; pairs not listed are 0."""
    _index: dict[str, int] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not self.parameters:
            raise SpaceError("a parameter space needs at least one parameter")
        names = [p.name for p in self.parameters]
        dupes = sorted({n for n in names if names.count(n) > 1})
        if dupes:
            raise SpaceError(f"duplicate parameter name(s): {dupes}")
        object.__setattr__(self, "_index", {n: i for i, n in enumerate(names)})
        object.__setattr__(self, "groups", _check_groups(self.groups, names))
        object.__setattr__(self, "correlation", _check_correlation(self.correlation, names))

    @classmethod
    def from_dict(cls, specs: Mapping[str, Mapping[str, Any]],
                  groups: Mapping[str, Iterable[str]] | None = None,
                  correlation: Iterable[Iterable[Any]] | None = None) -> "ParameterSpace":
        """Build a space from ``{name: spec}`` (see the module docstring for specs).

        Parameters
        ----------
        specs : mapping of str to mapping
            One distribution specification per parameter.
        groups : mapping of str to list of str, optional
            Group name -> its parameters (disjoint, at least one each).
        correlation : list of (str, str, float), optional
            Gaussian-copula correlations of pairs of parameters, each in (-1, 1); the resulting
            matrix must be positive definite.

        Raises
        ------
        SpaceError
            Naming the field (``groups`` / ``correlation``), the entry and what is allowed.
        """
        if not isinstance(specs, Mapping):
            raise SpaceError(f"a parameter space is a mapping of name -> spec, got {type(specs).__name__}")
        return cls(tuple(Parameter.from_spec(n, s) for n, s in specs.items()),
                   groups=dict(groups or {}), correlation=tuple(correlation or ()))  # type: ignore[arg-type]

    @classmethod
    def from_parameters(cls, parameters: Iterable[Parameter]) -> "ParameterSpace":
        """Build a space from :class:`Parameter` objects (duplicate names are refused)."""
        return cls(tuple(parameters))

    def to_dict(self) -> dict[str, dict[str, Any]]:
        """Canonical ``{name: spec}``; ``ParameterSpace.from_dict(space.to_dict()) == space`` for a space
        without groups and correlation (pass those again as ``groups=``, ``correlation=``)."""
        return {p.name: p.to_spec() for p in self.parameters}

    @property
    def dependent(self) -> bool:
        """Whether any pair of inputs is correlated."""
        return any(rho != 0.0 for _, _, rho in self.correlation)

    @cached_property
    def correlation_matrix(self) -> NDArray[np.float64]:
        """Correlation matrix ``R`` (dim, dim) of the normal scores (the identity when independent)."""
        return _correlation_matrix(self.correlation, self.names)

    def group_members(self) -> list[tuple[str, list[int]]]:
        """``(group, column indices)`` of every named group, in the order given."""
        return [(g, [self._index[n] for n in members]) for g, members in self.groups.items()]

    def from_normal(self, z: NDArray[np.float64]) -> NDArray[np.float64]:
        """Map normal scores ``z`` (n, dim) to parameter values: ``x_i = F_i^-1(Phi(z_i))``."""
        return np.column_stack([p.ppf(norm.cdf(z[:, i])) for i, p in enumerate(self.parameters)])

    @property
    def names(self) -> tuple[str, ...]:
        """Parameter names, in order."""
        return tuple(p.name for p in self.parameters)

    @property
    def dim(self) -> int:
        """Number of parameters."""
        return len(self.parameters)

    def __len__(self) -> int:
        return self.dim

    def __getitem__(self, name: str) -> Parameter:
        try:
            return self.parameters[self._index[name]]
        except KeyError:
            raise SpaceError(f"unknown parameter {name!r}; known: {', '.join(self.names)}") from None

    @property
    def nominal(self) -> dict[str, float]:
        """Nominal value of every parameter."""
        return {p.name: p.nominal for p in self.parameters}

    @property
    def means(self) -> NDArray[np.float64]:
        """Mean of every parameter, shape ``(dim,)``."""
        return np.array([p.mean for p in self.parameters])

    @cached_property
    def joint(self) -> chaospy.Distribution:
        """The joint (independent) chaospy distribution."""
        return chaospy.J(*(p.distribution for p in self.parameters))

    def ppf(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """Map unit-hypercube points ``u`` (n, dim) to parameter values (n, dim): each column by
        its inverse CDF, after the Gaussian copula's coupling ``z = L Phi^-1(u)`` (``R = L L^T``)
        when the space is correlated."""
        u = np.atleast_2d(np.asarray(u, dtype=float))
        if u.shape[1] != self.dim:
            raise SpaceError(f"expected points with {self.dim} columns ({', '.join(self.names)}), "
                             f"got shape {u.shape}")
        if self.dependent:
            z = norm.ppf(np.clip(u, _U_EPS, 1.0 - _U_EPS)) @ np.linalg.cholesky(self.correlation_matrix).T
            return self.from_normal(z)
        return np.column_stack([p.ppf(u[:, i]) for i, p in enumerate(self.parameters)])

    def unit_sample(self, n: int, seed: int | np.random.SeedSequence = 0,
                    rule: SampleRule = "sobol") -> NDArray[np.float64]:
        """``n`` points in the open unit hypercube, reproducible for a seed.

        Parameters
        ----------
        n : int
            Number of points (a power of two is best for ``rule="sobol"``).
        seed : int or SeedSequence
            Seed of the scrambling (QMC) or of the generator (random, lhs).
        rule : {"sobol", "halton", "lhs", "random"}
            Scrambled Sobol' or Halton sequence, Latin hypercube, or plain Monte Carlo.
        """
        if not isinstance(n, (int, np.integer)) or n < 1:
            raise SpaceError(f"sample size n must be a positive integer, got {n!r}")
        rng = np.random.default_rng(seed)
        if rule == "sobol":
            with warnings.catch_warnings():   # a study's size is hinted at by ddgsa.study.checks, named by field
                warnings.filterwarnings("ignore", message="The balance properties of Sobol", category=UserWarning)
                u = qmc.Sobol(self.dim, scramble=True, rng=rng).random(n)
        elif rule == "halton":
            u = qmc.Halton(self.dim, scramble=True, rng=rng).random(n)
        elif rule == "lhs":
            u = qmc.LatinHypercube(self.dim, rng=rng).random(n)
        elif rule == "random":
            u = rng.random((n, self.dim))
        else:
            raise SpaceError(f"unknown sampling rule {rule!r}; allowed: sobol, halton, lhs, random")
        return u

    def sample(self, n: int, seed: int | np.random.SeedSequence = 0,
               rule: SampleRule = "sobol") -> NDArray[np.float64]:
        """``n`` points drawn from the joint distribution, shape ``(n, dim)``; see :meth:`unit_sample`."""
        return self.ppf(self.unit_sample(n, seed=seed, rule=rule))

    def frame(self, points: NDArray[np.float64]) -> pd.DataFrame:
        """Points (n, dim) as a DataFrame with one column per parameter."""
        return pd.DataFrame(np.atleast_2d(points), columns=list(self.names))

    def to_salib(self, groups: Mapping[str, str] | None = None) -> dict[str, Any]:
        """The space as a SALib problem dict (``num_vars``, ``names``, ``bounds``, ``dists``, and
        ``groups`` when given), which ``SALib.ProblemSpec(space.to_salib())`` accepts.

        ddgsa's own SALib methods sample the unit hypercube and map it with :meth:`ppf`;
        this export is for users who want to call SALib directly.

        Parameters
        ----------
        groups : mapping of str to str, optional
            Group name of every parameter (SALib's grouped indices).
        """
        entries = [p.salib_entry() for p in self.parameters]
        problem: dict[str, Any] = {"num_vars": self.dim, "names": list(self.names),
                                   "dists": [d for d, _ in entries], "bounds": [b for _, b in entries]}
        if groups is not None:
            missing = [n for n in self.names if n not in groups]
            if missing:
                raise SpaceError(f"groups: no group for parameter(s) {missing}")
            problem["groups"] = [str(groups[n]) for n in self.names]
        return problem

    @classmethod
    def from_salib(cls, problem: Mapping[str, Any]) -> "ParameterSpace":
        """The space of a SALib problem dict or ``ProblemSpec`` (``names``, ``bounds``, ``dists``;
        no ``dists``: all uniform). SALib's ``unif``, ``norm``, ``lognorm`` (of log X), ``truncnorm``
        and ``triang`` (low, high, peak as a fraction of the width) map to ddgsa's distributions;
        ``groups`` are SALib's grouping of the indices and are not part of the space.

        Raises
        ------
        SpaceError
            Naming the entry: missing keys, lengths that disagree, a distribution ddgsa lacks
            (``logunif``, ``weibull``) or invalid bounds.
        """
        if not isinstance(problem, Mapping):
            raise SpaceError(f"a SALib problem is a mapping with names, bounds and dists, got {type(problem).__name__}")
        missing = [k for k in ("names", "bounds") if k not in problem]
        if missing:
            raise SpaceError(f"SALib problem: missing key(s) {missing} (a problem has names, bounds, dists)")
        names, bounds = list(problem["names"]), list(problem["bounds"])
        dists = list(problem.get("dists") or ["unif"] * len(names))
        if not len(names) == len(bounds) == len(dists) or problem.get("num_vars", len(names)) != len(names):
            raise SpaceError(f"SALib problem: names ({len(names)}), bounds ({len(bounds)}), dists ({len(dists)}) "
                             f"and num_vars ({problem.get('num_vars', len(names))}) must agree")
        return cls(tuple(Parameter.from_spec(n, _salib_spec(n, d, b)) for n, d, b in zip(names, dists, bounds)))


def _check_groups(groups: Any, names: list[str]) -> dict[str, tuple[str, ...]]:
    """Validated groups: a mapping of identifier -> non-empty list of known, distinct parameters, disjoint."""
    if not isinstance(groups, Mapping):
        raise SpaceError(f"groups: a mapping of group name -> list of parameters, got {type(groups).__name__}")
    out: dict[str, tuple[str, ...]] = {}
    owner: dict[str, str] = {}
    for g, members in groups.items():
        if not isinstance(g, str) or not g.isidentifier():
            raise SpaceError(f"groups: group name {g!r} must be an identifier (letters, digits, _)")
        if g in names:
            raise SpaceError(f"groups: group name {g!r} is also a parameter's name; choose another")
        if isinstance(members, str) or not isinstance(members, Iterable):
            raise SpaceError(f"groups.{g}: a list of parameter names, got {members!r}")
        members = [str(m) for m in members]
        if not members:
            raise SpaceError(f"groups.{g}: an empty group; give at least one parameter")
        for m in members:
            if m not in names:
                raise SpaceError(f"groups.{g}: {m!r} is not a parameter of the space; known: {', '.join(names)}")
            if m in owner:
                raise SpaceError(f"groups.{g}: {m!r} is already in group {owner[m]!r} (groups must be disjoint)")
            owner[m] = g
        out[g] = tuple(members)
    return out


def _check_correlation(pairs: Any, names: list[str]) -> tuple[tuple[str, str, float], ...]:
    """Validated ``(a, b, rho)`` entries whose correlation matrix is positive definite."""
    if isinstance(pairs, (str, Mapping)) or not isinstance(pairs, Iterable):
        raise SpaceError(f"correlation: a list of [parameter, parameter, rho] entries, got {pairs!r}")
    out: list[tuple[str, str, float]] = []
    seen: set[frozenset[str]] = set()
    for k, entry in enumerate(pairs):
        e = list(entry) if isinstance(entry, Iterable) and not isinstance(entry, (str, Mapping)) else None
        if e is None or len(e) != 3:
            raise SpaceError(f"correlation[{k}]: an entry is [parameter, parameter, rho], got {entry!r}")
        a, b = str(e[0]), str(e[1])
        for n in (a, b):
            if n not in names:
                raise SpaceError(f"correlation[{k}]: {n!r} is not a parameter of the space; known: {', '.join(names)}")
        if a == b:
            raise SpaceError(f"correlation[{k}]: a parameter is not correlated with itself ({a!r}, {a!r})")
        if frozenset((a, b)) in seen:
            raise SpaceError(f"correlation[{k}]: the pair ({a!r}, {b!r}) is given twice")
        seen.add(frozenset((a, b)))
        rho = _as_float(f"{a}-{b}", "rho", e[2])
        if not -1.0 < rho < 1.0:
            raise SpaceError(f"correlation[{k}]: rho of ({a!r}, {b!r}) must lie in (-1, 1), got {rho}")
        out.append((a, b, rho))
    matrix = _correlation_matrix(tuple(out), names)
    low = float(np.linalg.eigvalsh(matrix).min())
    if low <= 1e-10:
        raise SpaceError(f"correlation: the correlation matrix is not positive definite (smallest eigenvalue "
                         f"{low:.3g}); the pairs {[(a, b, r) for a, b, r in out]} contradict each other -- "
                         "lower the magnitudes")
    return tuple(out)


def _correlation_matrix(pairs: tuple[tuple[str, str, float], ...], names: Sequence[str]) -> NDArray[np.float64]:
    """The symmetric matrix with unit diagonal and ``rho`` at every listed pair."""
    index = {n: i for i, n in enumerate(names)}
    matrix = np.eye(len(names))
    for a, b, rho in pairs:
        matrix[index[a], index[b]] = matrix[index[b], index[a]] = rho
    return matrix


_SALIB_ARGS = {"unif": ("uniform", ("low", "high")), "norm": ("normal", ("mean", "std")),
               "lognorm": ("lognormal", ("mu", "sigma")), "truncnorm": ("truncnormal", ("low", "high", "mean", "std"))}


def _salib_spec(name: str, dist: str, bounds: Any) -> dict[str, Any]:
    """ddgsa's specification of one SALib ``(dist, bounds)`` entry (inverse of :meth:`Parameter.salib_entry`)."""
    b = list(bounds) if isinstance(bounds, Iterable) and not isinstance(bounds, str) else [bounds]
    if dist == "triang":
        if len(b) not in (2, 3):
            raise SpaceError(f"SALib problem: parameter {name!r}: triang needs [low, high, peak fraction], got {b}")
        low, high, c = (b if len(b) == 3 else [0.0, *b])
        low, high, c = (_as_float(name, k, v) for k, v in zip(("low", "high", "peak"), (low, high, c)))
        return {"dist": "triangular", "low": low, "high": high, "mode": low + c * (high - low)}
    if dist not in _SALIB_ARGS:
        raise SpaceError(f"SALib problem: parameter {name!r}: dist {dist!r} has no ddgsa counterpart; allowed: "
                         f"{', '.join([*_SALIB_ARGS, 'triang'])}")
    ours, keys = _SALIB_ARGS[dist]
    if len(b) != len(keys):
        raise SpaceError(f"SALib problem: parameter {name!r}: {dist} needs bounds [{', '.join(keys)}], got {b}")
    return {"dist": ours, **dict(zip(keys, b))}
