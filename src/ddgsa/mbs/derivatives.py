"""Central differences: the one numerical derivative of the kernel (statics' tangent, every
linearisation, the constraints' curvature).

:func:`central_difference` chooses the steps and takes the differences; a caller gives it the
function to difference as a *batch*: all ``2 n`` stepped arguments at once, so a compiled
residual evaluates them in one call (:func:`ddgsa.mbs.compiled.residual_jacobians`, the
non-rotating linearisation, the single-body kernel's spinning linearisation) and a Python one in
a loop (:func:`central_jacobian`). Compiled loops that difference one entry at a time take their
step from :func:`central_step`.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numba import njit
from numpy.typing import NDArray

Batch = Callable[[NDArray[np.float64]], NDArray[np.float64]]


@njit(cache=True)
def central_step(x, scale, rel_step):  # pragma: no cover (compiled)
    """The step [units of ``x``] of a central difference at ``x``: ``rel_step * max(scale, |x|)``; compiled
    loops that difference one entry at a time call it (the statics' tangent, the torque laws' slopes)."""
    return rel_step * max(scale, abs(x))


def central_steps(x0: NDArray[np.float64], scale: float, rel_step: float) -> NDArray[np.float64]:
    """:func:`central_step` of each entry."""
    return rel_step * np.maximum(scale, np.abs(np.asarray(x0, dtype=float)))


def stepped(x0: NDArray[np.float64], h: NDArray[np.float64],
            columns: NDArray[np.int64] | None = None) -> NDArray[np.float64]:
    """The ``2 p`` stepped arguments (2p, n) of :func:`central_difference` for the ``p`` entries ``columns``
    (default all ``n``): row ``i < p`` is ``x0 + h_c e_c`` with ``c = columns[i]``, row ``p + i`` is
    ``x0 - h_c e_c`` (so row ``j`` steps entry ``columns[j % p]``)."""
    x0 = np.asarray(x0, dtype=float)
    cols = np.arange(x0.size) if columns is None else np.asarray(columns, dtype=np.int64)
    d = np.zeros((cols.size, x0.size))
    d[np.arange(cols.size), cols] = np.asarray(h, dtype=float)[cols]
    return np.vstack([x0 + d, x0 - d])


def central_difference(batch: Batch, x0: NDArray[np.float64], scale: float,
                       rel_step: float = 1e-6, columns: NDArray[np.int64] | None = None) -> NDArray[np.float64]:
    """Central-difference Jacobian (m, n) of a function given as a batch.

    Parameters
    ----------
    batch : callable
        ``batch(X) -> F``: ``X`` (2p, n) the :func:`stepped` arguments, ``F`` (2p, m) the function at
        each row.
    x0 : (n,) the point
    scale, rel_step : the step of entry ``i`` is ``rel_step * max(scale, |x0_i|)`` (:func:`central_steps`)
    columns : (p,) int, optional
        The entries to difference (default all): the Jacobian's other columns are returned as zero, and
        ``batch`` evaluates ``2 p`` arguments instead of ``2 n``.

    Returns
    -------
    ndarray (m, n)
        ``(f(x0 + h_i e_i) - f(x0 - h_i e_i)) / (2 h_i)`` in column ``i``.
    """
    h = central_steps(x0, scale, rel_step)
    n = h.size
    cols = np.arange(n) if columns is None else np.asarray(columns, dtype=np.int64)
    p = cols.size
    f = np.asarray(batch(stepped(x0, h, cols)), dtype=float).reshape(2 * p, -1)
    jac = np.zeros((f.shape[1], n))
    jac[:, cols] = ((f[:p] - f[p:]) / (2.0 * h[cols])[:, None]).T
    return jac


def central_jacobian(fun: Callable[..., NDArray[np.float64]], args: list[NDArray[np.float64]], which: int,
                     scale: float, rel_step: float = 1e-6) -> NDArray[np.float64]:
    """Central-difference Jacobian of ``fun(*args)`` with respect to ``args[which]`` (a Python
    function, called once per stepped argument; :func:`central_difference`)."""
    def batch(x: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.array([fun(*(xi.copy() if k == which else a for k, a in enumerate(args))) for xi in x])

    return central_difference(batch, np.asarray(args[which], dtype=float), scale, rel_step)
