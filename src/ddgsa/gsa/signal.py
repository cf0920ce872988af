"""Sobol indices of a signal: an output that is a vector on a fixed grid (spectrum, order track, time series).

Each bin ``k`` of the grid is an output of its own: the method's indices ``S_{i,k}``, ``S_{T,i,k}``
with their error bounds, and its estimate of the bin's variance ``V_k`` (M-DRM: the surrogate's,
exact from the quadrature; PCE: the sum of the squared coefficients; Saltelli, FAST, RBD-FAST:
the sample variance of the design, whose every row is a draw from the inputs). The **generalised**
indices over the signal (Gamboa, Janon, Klein & Lagnoux 2014, *Electron. J. Statist.* 8, "Sensitivity
analysis for multidimensional and functional outputs") weight the bins by their variance:

.. math::

    S_i = \\frac{\\sum_k V_k S_{i,k}}{\\sum_k V_k}, \\qquad
    S_{T,i} = \\frac{\\sum_k V_k S_{T,i,k}}{\\sum_k V_k},

the share of the signal's total variance (the trace of its covariance) that input *i* explains
alone, or with its interactions. A bin that holds no variance adds nothing, however its own
indices come out. The generalised bound is the same weighted mean of the bins' bounds (the error of
the weights themselves is not included: each bin's variance is one method's estimate).

Bins whose indices are not defined (constant bins, failed evaluations) drop out of the sums; the
result says what share of the variance the sums cover (``variance_covered``). A generalised row is
``trusted`` when every bin holding at least ``_MATERIAL`` of the signal's variance is.

The generalised rows are ranked as a method's rows are (``rank_confirmed``, ``rank``:
:func:`~ddgsa.gsa.result.rank_structure`), with the same weighted mean of the bins' calibrated ST
error bounds (column ``ST_error``; each bin's ``ST_error`` is the bound the method's trust and rank
rules use) as the error, void (no claim) where a material bin's bounds are voided by a rule other
than an error estimate (column ``bounded`` of the bins: sign change, failed runs...).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.errors import MethodError
from ddgsa.gsa.base import Design, get_method
from ddgsa.gsa.result import SobolResult, index_error_rule, rank_structure, trusted_mask
from ddgsa.gsa.space import ParameterSpace

_MATERIAL = 1e-3
"""A bin holding at least this share of the signal's variance must be trusted for the generalised row to be."""


@dataclass(frozen=True)
class SignalAxis:
    """The grid of a signal: what its bins are.

    Attributes
    ----------
    name : str
        What the axis measures, e.g. ``"frequency"``, ``"order"``, ``"time"``.
    unit : str
        Its unit, e.g. ``"Hz"``, ``"-"``, ``"s"``.
    values : ndarray, shape (n_bins,)
        The bin centres [unit].
    """

    name: str
    unit: str
    values: NDArray[np.float64]

    @property
    def label(self) -> str:
        """``name [unit]`` for axis labels."""
        return f"{self.name} [{self.unit}]" if self.unit else self.name

    def __len__(self) -> int:
        return int(np.asarray(self.values).size)


@dataclass
class SignalResult:
    """Per-bin and generalised indices of one signal from one method.

    Attributes
    ----------
    signal : str
        The signal's name.
    axis : SignalAxis
    bins : pandas.DataFrame
        One row per (bin, parameter): ``signal, bin, axis, parameter, S1, S1_conf, ST, ST_conf, variance,
        trusted, ST_error, bounded`` (``axis`` the bin's value on the grid, ``variance`` the bin's variance
        [signal unit^2], ``ST_error`` the method's calibrated ST bound [-], ``bounded`` whether no rule
        other than an error estimate voids the bin's bounds).
    generalised : pandas.DataFrame
        One row per parameter: ``signal, parameter, S1, S1_conf, ST, ST_conf, ST_error, variance_covered,
        trusted, rank_confirmed, rank``.
    result : SobolResult
        The method's own result over the bins (outputs ``signal[k]``), with its diagnostics.
    """

    signal: str
    axis: SignalAxis
    bins: pd.DataFrame
    generalised: pd.DataFrame
    result: SobolResult

    @property
    def method(self) -> str:
        """The method's registry name."""
        return self.result.method

    @property
    def n_evals(self) -> int:
        """Model evaluations spent (one evaluation gives every bin)."""
        return self.result.n_evals

    def pivot(self, quantity: str = "ST") -> pd.DataFrame:
        """``quantity`` as a (bin value x parameter) table."""
        return self.bins.pivot(index="axis", columns="parameter", values=quantity)


def bin_names(signal: str, n_bins: int) -> list[str]:
    """The per-bin output names ``signal[0] ... signal[n-1]``."""
    return [f"{signal}[{k}]" for k in range(n_bins)]


def signal_indices(method: str, space: ParameterSpace, design: Design, values: NDArray[np.float64],
                   axis: SignalAxis, signal: str = "signal") -> SignalResult:
    """Per-bin and generalised indices of a signal from a method's design and the values there.

    Parameters
    ----------
    method : str
        A registered method (``mdrm``, ``saltelli``, ``pce``, ``fast``, ``rbd_fast``).
    design : Design
        That method's design.
    values : ndarray, shape (n_points, n_bins)
        The signal at each design point, row ``j`` at ``design.points[j]``; non-finite values mark
        failed evaluations (their bins are refused, never imputed).
    axis : SignalAxis
        The grid, ``len(axis) == n_bins``.
    signal : str
        The signal's name.
    """
    y = np.asarray(values, dtype=float)
    if y.ndim != 2 or y.shape[1] != len(axis):
        raise MethodError(f"signal {signal!r}: values of shape {y.shape} do not match its grid of {len(axis)} "
                          f"bins ({axis.name}); expected ({design.n_points}, {len(axis)})")
    names = bin_names(signal, y.shape[1])
    res = get_method(method).analyze(space, design, y, outputs=names)
    return from_result(res, axis, signal)


def from_result(res: SobolResult, axis: SignalAxis, signal: str) -> SignalResult:
    """Per-bin table and generalised indices from a method's result over the bins of ``signal``."""
    d = len(res.indices) // len(axis)
    t = res.indices
    variance = np.asarray(res.extras.get("variance", np.full(len(axis), np.nan)), dtype=float)
    bins = pd.DataFrame({"signal": signal, "bin": np.repeat(np.arange(len(axis)), d),
                         "axis": np.repeat(np.asarray(axis.values, dtype=float), d),
                         "parameter": t["parameter"].to_numpy(),
                         **{q: t[q].to_numpy(float) for q in ("S1", "S1_conf", "ST", "ST_conf")},
                         "variance": np.repeat(variance, d), "trusted": t["trusted"].to_numpy(bool),
                         "ST_error": np.asarray(res.extras.get("rank_error", t["ST_conf"]), dtype=float),
                         "bounded": trusted_mask(t, [g for g in res.diagnostics if not index_error_rule(g.name)])})
    return SignalResult(signal, axis, bins, generalised(bins, res.options.get("tolerance", 0.02)), res)


def generalised(bins: pd.DataFrame, tolerance: float = 0.02) -> pd.DataFrame:
    """Variance-weighted (generalised) indices per parameter from a per-bin table, ranked (see the module
    docstring; ``tolerance`` [-] is the rank rule's margin and floor; a table without ``ST_error`` and
    ``bounded`` columns takes ``ST_conf`` and ``trusted`` for them)."""
    rows = []
    for (sig, par), g in bins.groupby(["signal", "parameter"], sort=False):
        v = g["variance"].to_numpy(float)
        total = np.nansum(np.where(v > 0, v, 0.0))
        ok = np.isfinite(v) & np.isfinite(g["S1"].to_numpy(float)) & np.isfinite(g["ST"].to_numpy(float))
        row: dict[str, Any] = {"signal": sig, "parameter": par}
        used = v[ok].sum() if ok.any() else 0.0
        w = np.where(ok, v, 0.0) / used if used > 0 else np.zeros_like(v)
        for q in ("S1", "ST"):
            row[q] = float(w @ np.nan_to_num(g[q].to_numpy(float))) if used > 0 else np.nan
            row[f"{q}_conf"] = _weighted_bound(w, g[f"{q}_conf"].to_numpy(float)) if used > 0 else np.nan
        row["ST_error"] = _weighted_bound(w, g.get("ST_error", g["ST_conf"]).to_numpy(float)) if used > 0 else np.nan
        row["variance_covered"] = float(used / total) if total > 0 else np.nan
        material = np.where(np.isfinite(v), v, np.inf) >= _MATERIAL * total
        row["trusted"] = bool(used > 0 and g["trusted"].to_numpy(bool)[material].all()
                              and row["variance_covered"] >= 1.0 - _MATERIAL)
        row["bounded"] = bool(g.get("bounded", g["trusted"]).to_numpy(bool)[material].all())
        rows.append(row)
    out = pd.DataFrame(rows, columns=["signal", "parameter", "S1", "S1_conf", "ST", "ST_conf", "ST_error",
                                      "variance_covered", "trusted", "bounded"])
    err = np.where(out["bounded"].to_numpy(bool), out["ST_error"].to_numpy(float), np.nan)
    codes, ranks = rank_structure(out.rename(columns={"signal": "output"}), err, [], tolerance)
    out["rank_confirmed"] = codes > 0
    out["rank"] = ranks
    return out.drop(columns="bounded")


def _weighted_bound(w: NDArray[np.float64], bound: NDArray[np.float64]) -> float:
    """The weighted mean of the bins' bounds over the bins of positive weight (inf where one has none)."""
    live = w > 0
    return float(w[live] @ np.where(np.isfinite(bound[live]), bound[live], np.inf))


def sobol_signal(f: Callable[[NDArray[np.float64]], NDArray[np.float64]], space: ParameterSpace,
                 axis: SignalAxis | Sequence[float], method: str = "mdrm", *, signal: str = "signal",
                 **options: Any) -> SignalResult:
    """Per-bin and generalised Sobol indices of a vectorised signal-valued function.

    Parameters
    ----------
    f : callable
        ``f(x)`` with ``x`` of shape ``(n_points, n_params)`` returning ``(n_points, n_bins)``.
    space : ParameterSpace
    axis : SignalAxis or sequence of float
        The grid (a bare sequence becomes an axis named ``bin`` without unit).
    method : str
        ``mdrm``, ``saltelli``, ``pce``, ``fast`` or ``rbd_fast``.
    signal : str
        The signal's name in the tables.
    **options
        The method's options.

    Examples
    --------
    >>> import numpy as np, ddgsa
    >>> space = ddgsa.ParameterSpace.from_dict({"a": {"dist": "uniform", "low": 1, "high": 2},
    ...                                         "b": {"dist": "uniform", "low": 1, "high": 2}})
    >>> t = np.linspace(0.0, 1.0, 5)
    >>> res = ddgsa.sobol_signal(lambda x: x[:, :1] * (1 + t) + x[:, 1:] * (1 - t), space, t, "pce", order=1)
    >>> res.generalised[["parameter", "S1"]].round(4).to_numpy().tolist()   # 11.875 / 13.75 and 1.875 / 13.75
    [['a', 0.8636], ['b', 0.1364]]
    """
    ax = axis if isinstance(axis, SignalAxis) else SignalAxis("bin", "", np.asarray(axis, dtype=float))
    design = get_method(method).design(space, **options)
    return signal_indices(method, space, design, np.asarray(f(design.points), dtype=float), ax, signal)
