"""Central-difference Jacobians: the one numerical derivative of the kernel (statics' tangent,
every linearisation)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray


def central_jacobian(fun: Callable[..., NDArray[np.float64]], args: list[NDArray[np.float64]], which: int,
                     scale: float, rel_step: float = 1e-6) -> NDArray[np.float64]:
    """Central-difference Jacobian of ``fun(*args)`` with respect to ``args[which]``.

    The step of entry ``i`` is ``rel_step * max(scale, |x_i|)``.
    """
    x0 = args[which]
    cols = []
    for i in range(x0.size):
        h = rel_step * max(scale, abs(x0[i]))
        plus, minus = [a.copy() for a in args], [a.copy() for a in args]
        plus[which][i] += h
        minus[which][i] -= h
        cols.append((fun(*plus) - fun(*minus)) / (2 * h))
    return np.column_stack(cols)
