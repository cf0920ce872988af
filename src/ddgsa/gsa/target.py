"""Target sensitivity: indices of the part of an output beyond a stated limit.

A designer often cares less about what drives an output's whole spread than about what drives
it past a limit (bearing damage above its design value, a deflection above a clearance). Two
transforms of an output ``y`` [its unit] with a limit ``t`` [the same unit] turn that question
into an output every method analyses (Spagnol, Da Veiga et al. 2019 call such indices
target sensitivity indices):

* ``indicator``: :math:`1\\{y > t\\}` (or :math:`1\\{y < t\\}` with ``below``) [-]; its Sobol
  indices share the variance :math:`p(1 - p)` of exceeding, :math:`p` the exceedance probability;
* ``excess``: :math:`\\max(y - t, 0)` (or :math:`\\max(t - y, 0)`) [unit of y], which also weighs
  how far past the limit a point lies.

Non-finite values stay non-finite (failed runs are refused, never imputed). A limit outside
the output's range gives a constant transform, whose indices are undefined (``zero_variance``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.errors import MethodError

TargetKind = Literal["indicator", "excess"]


@dataclass(frozen=True)
class Target:
    """One target transform of an output.

    Parameters
    ----------
    output : str
        The output transformed.
    limit : float
        The limit [output unit].
    above : bool
        True: the part above ``limit`` counts; False: the part below.
    kind : {"indicator", "excess"}
        Exceedance indicator [-] or excess over the limit [output unit].
    name : str
        Name of the transformed output (default ``<output>_exceeds`` / ``<output>_excess``,
        ``_below`` / ``_shortfall`` for ``above=False``).
    """

    output: str
    limit: float
    above: bool = True
    kind: TargetKind = "indicator"
    name: str = ""

    def __post_init__(self) -> None:
        if self.kind not in ("indicator", "excess"):
            raise MethodError(f"target of {self.output!r}: kind must be 'indicator' or 'excess', got {self.kind!r}")
        if not np.isfinite(self.limit):
            raise MethodError(f"target of {self.output!r}: the limit must be a finite number, got {self.limit!r}")
        if not self.name:
            suffix = {("indicator", True): "exceeds", ("indicator", False): "below",
                      ("excess", True): "excess", ("excess", False): "shortfall"}[(self.kind, self.above)]
            object.__setattr__(self, "name", f"{self.output}_{suffix}")

    def apply(self, y: NDArray[np.float64]) -> NDArray[np.float64]:
        """The transformed values (same shape as ``y``); NaN stays NaN."""
        y = np.asarray(y, dtype=float)
        gap = y - self.limit if self.above else self.limit - y
        with np.errstate(invalid="ignore"):
            out = (gap > 0).astype(float) if self.kind == "indicator" else np.maximum(gap, 0.0)
        return np.where(np.isfinite(y), out, np.nan)

    @property
    def description(self) -> str:
        """One line saying what the transformed output is."""
        sign = ">" if self.above else "<"
        if self.kind == "indicator":
            return f"1 where {self.output} {sign} {self.limit:g}, else 0 (target sensitivity)"
        return f"{'excess' if self.above else 'shortfall'} of {self.output} beyond {self.limit:g}, 0 within"


def with_targets(values: NDArray[np.float64], outputs: list[str],
                 targets: list[Target]) -> tuple[NDArray[np.float64], list[str]]:
    """``values`` (n, len(outputs)) with one more column per target, and the extended output names."""
    cols = [values]
    for t in targets:
        if t.output not in outputs:
            raise MethodError(f"target {t.name!r}: output {t.output!r} is not among {', '.join(outputs)}")
        cols.append(t.apply(values[:, outputs.index(t.output)])[:, None])
    return np.hstack(cols), [*outputs, *(t.name for t in targets)]


def target_function(f: Callable[[NDArray[np.float64]], Any], limit: float, above: bool = True,
                    kind: TargetKind = "indicator", output: str | None = None) -> Callable[[NDArray[np.float64]],
                                                                                         NDArray[np.float64]]:
    """``f`` with its output (or the column ``output`` of a DataFrame) replaced by a target transform.

    Examples
    --------
    >>> import numpy as np, ddgsa
    >>> space = ddgsa.ParameterSpace.from_dict({"a": {"low": 0, "high": 1}, "b": {"low": 0, "high": 1}})
    >>> g = target_function(lambda x: x[:, 0] + x[:, 1], limit=1.0)      # 1{a + b > 1}
    >>> res = ddgsa.sobol(g, space, method="saltelli", n=4096)
    >>> res.indices["S1"].round(1).tolist(), res.indices["ST"].round(1).tolist()   # exact: 1/3, 2/3
    ([0.3, 0.3], [0.7, 0.7])
    """
    def wrapped(x: NDArray[np.float64]) -> NDArray[np.float64]:
        y = f(x)
        if isinstance(y, pd.DataFrame):
            name = output if output is not None else str(y.columns[0])
            y = y[name]
        return Target(str(output or "y"), float(limit), above, kind).apply(np.asarray(y, dtype=float))
    return wrapped
