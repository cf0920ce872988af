"""A vectorised function evaluated point by point under a per-evaluation timeout (``sobol(..., timeout=)``).

Each point (a row of the design) is evaluated alone in a child process forked from this one
(:class:`ddgsa.runner.TimedCalls`: the function need not be picklable, and the child keeps what
it builds between points). A point that runs past the timeout, raises, kills its process or
returns something other than one row is a failed evaluation: its row is NaN (so the method
refuses the outputs it touches, never imputes them) and :attr:`TimedFunction.failures` records
the point and the reason, which :meth:`TimedFunction.annotate` adds to the result.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.errors import MethodError
from ddgsa.gsa.result import Diagnostic, SobolResult

SHOWN_FAILURES = 5
"""Failed points quoted in the ``failed_evaluations`` diagnostic (all are in ``extras["failures"]``)."""


class TimedFunction:
    """``f`` called one point at a time, each call stopped after ``timeout`` seconds.

    Parameters
    ----------
    f : callable
        ``f(x)`` with ``x`` of shape ``(1, n_params)``, returning one row: shape ``(1,)`` or
        ``(1, n_outputs)``, a one-row DataFrame or a Series.
    timeout : float
        Seconds one evaluation may take [s], > 0.
    """

    def __init__(self, f: Callable[[NDArray[np.float64]], Any], timeout: float) -> None:
        from ddgsa.runner import TimedCalls, failure_reason

        self._reason = failure_reason
        if isinstance(timeout, bool) or not isinstance(timeout, (int, float)) or not timeout > 0:
            raise MethodError(f"timeout must be a positive number of seconds, got {timeout!r}")
        self._calls = TimedCalls(f, float(timeout))
        self.failures: list[dict[str, Any]] = []
        """One entry per failed point: ``row`` (in its call), ``point`` and ``error`` (the reason)."""
        self.n_calls = 0

    def __call__(self, x: NDArray[np.float64]) -> NDArray[np.float64] | pd.DataFrame:
        """Values at the rows of ``x``: a DataFrame when ``f`` returns DataFrames or named Series,
        else a matrix ``(n_points, n_outputs)``; failed points are NaN rows."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        rows: list[NDArray[np.float64] | None] = []
        columns: list[str] | None = None
        for k in range(len(x)):
            try:
                row, names = _one_row(self._calls(x[k:k + 1]))
                columns = columns or names
            except Exception as exc:  # noqa: BLE001 -- a failed point is data: NaN and its reason
                row = None
                self.failures.append({"row": k, "call": self.n_calls, "point": x[k].tolist(),
                                      "error": self._reason(exc)})
            rows.append(row)
        self.n_calls += 1
        widths = {len(r) for r in rows if r is not None}
        if not widths:
            raise MethodError(f"every one of the {len(x)} evaluations failed; the first: {self.failures[-len(x)]['error']}")
        if len(widths) > 1:
            raise MethodError(f"the function returned rows of {sorted(widths)} values for different points")
        values = np.full((len(x), widths.pop()), np.nan)
        for k, row in enumerate(rows):
            if row is not None:
                values[k] = row
        return pd.DataFrame(values, columns=columns) if columns else values

    def annotate(self, result: SobolResult) -> SobolResult:
        """Add the failed points to ``result``: ``extras["failures"]`` and a ``failed_evaluations``
        diagnostic quoting the first :data:`SHOWN_FAILURES` reasons."""
        if not self.failures:
            return result
        shown = "; ".join(f"point {f['point']}: {f['error']}" for f in self.failures[:SHOWN_FAILURES])
        more = f" (and {len(self.failures) - SHOWN_FAILURES} more)" if len(self.failures) > SHOWN_FAILURES else ""
        result.diagnostics.append(Diagnostic(
            "failed_evaluations", f"{len(self.failures)} of {result.n_evals} evaluations failed: {shown}{more}",
            "warning", value=float(len(self.failures))))
        result.extras["failures"] = list(self.failures)
        return result

    def close(self) -> None:
        """Stop the child process."""
        self._calls.close()


def _one_row(value: Any) -> tuple[NDArray[np.float64], list[str] | None]:
    """The one row of values ``f`` returned for one point, and its column names (None: unnamed)."""
    names = None
    if isinstance(value, pd.DataFrame):
        names, arr = [str(c) for c in value.columns], value.to_numpy(dtype=float)
    elif isinstance(value, pd.Series):
        names = [str(value.name)] if value.name is not None else None
        arr = value.to_numpy(dtype=float)[:, None]
    else:
        arr = np.asarray(value, dtype=float)
        arr = arr[:, None] if arr.ndim == 1 else arr
    if arr.ndim != 2 or arr.shape[0] != 1:
        raise MethodError(f"expected one row of values for one point, got shape {np.shape(value)}")
    return arr[0], names
