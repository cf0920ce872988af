"""Global sensitivity analysis methods, independent of any turbine model.

Every method is split into ``design`` (the points it needs) and ``analyze`` (indices
from the values there), so the runner can pool and cache evaluations;
:func:`sobol` chains the two for a Python function.
"""

from __future__ import annotations

from collections.abc import Mapping, Callable, Sequence
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.gsa import hsic, mdrm, pce, salib, shapley  # noqa: F401  (register the methods)
from ddgsa.gsa.auto import run_auto
from ddgsa.gsa.base import METHODS, Design, GsaMethod, evaluate, get_method, register
from ddgsa.gsa.result import Diagnostic, SobolResult
from ddgsa.errors import MethodError
from ddgsa.gsa.space import ParameterSpace

__all__ = ["METHODS", "Design", "Diagnostic", "GsaMethod", "SobolResult", "get_method", "register",
           "sobol"]

VectorisedFunction = Callable[[NDArray[np.float64]], "NDArray[np.float64] | pd.DataFrame | pd.Series"]
"""A function of points (n_points, n_params) returning (n_points,), (n_points, n_outputs) or a DataFrame."""


def sobol(f: VectorisedFunction, space: ParameterSpace | Mapping[str, Any], method: str = "mdrm", *,
          outputs: Sequence[str] | None = None, timeout: float | None = None, **options: Any) -> SobolResult:
    """Sobol indices of a vectorised function.

    Parameters
    ----------
    f : callable
        ``f(x)`` with ``x`` of shape ``(n_points, n_params)`` (columns in ``space.names``
        order) returning ``(n_points,)``, ``(n_points, n_outputs)`` or a DataFrame whose
        columns name the outputs. Non-finite values are treated as failed evaluations.
    space : ParameterSpace or dict
        The uncertain inputs: a space, or the dict of distributions :meth:`ParameterSpace.from_dict`
        takes (``{"k": {"nominal": 1e10, "spread": 0.2}}``).
    method : str
        A registered method: ``mdrm``, ``saltelli``, ``fast``, ``rbd_fast``, ``pce``; or ``auto``
        (M-DRM, escalating to PCE and Saltelli within ``budget`` runs while diagnostics fire:
        :mod:`ddgsa.gsa.auto`).
    outputs : sequence of str, optional
        Names of the outputs (default: DataFrame columns, ``y`` or ``y0, y1, ...``).
    timeout : float, optional
        Seconds one evaluation may take [s]. When given, each point is evaluated alone in a child
        process (POSIX; the function need not be picklable) and one that runs longer, raises or
        dies is a failed evaluation: NaN in its row (the outputs it touches are refused, never
        imputed), its point and reason in ``extras["failures"]`` and the ``failed_evaluations``
        diagnostic. None (default): ``f`` is called on the whole design in this process.
    **options
        Method options (e.g. ``points=5`` for M-DRM, ``n=1024, seed=0`` for Saltelli).

    Returns
    -------
    SobolResult

    Examples
    --------
    >>> import ddgsa
    >>> from ddgsa.gsa.testfunctions import sobol_g
    >>> g = sobol_g([1.0, 2.0, 5.0])
    >>> res = ddgsa.sobol(g.f, g.space, method="mdrm", points=6)
    >>> res.n_evals   # 3 x 6 + 1 plus a 32-point check sample
    51
    >>> bool(abs(res.indices["S1"].to_numpy() - g.S1).max() < 0.05)
    True
    """
    if isinstance(space, Mapping):
        space = ParameterSpace.from_dict(space)
    elif not isinstance(space, ParameterSpace):
        raise MethodError(f"space: expected a ddgsa.ParameterSpace or a dict of distributions "
                          f"(ParameterSpace.from_dict), got {type(space).__name__}")
    if method == "auto" and space.dependent:
        raise MethodError("method 'auto' escalates through methods that assume independent inputs, and the "
                          "space is correlated; use method 'shapley'")
    if timeout is None:
        return _sobol(f, space, method, outputs, options)
    from ddgsa.gsa.timed import TimedFunction

    timed = TimedFunction(f, timeout)
    try:
        return timed.annotate(_sobol(timed, space, method, outputs, options))
    finally:
        timed.close()


def _sobol(f: VectorisedFunction, space: ParameterSpace, method: str, outputs: Sequence[str] | None,
           options: dict[str, Any]) -> SobolResult:
    if method == "auto":
        return run_auto(f, space, list(outputs) if outputs is not None else None, **options)
    m = get_method(method)
    design, y, names = evaluate(m, space, f, options, outputs)
    return m.analyze(space, design, y, outputs=names)
