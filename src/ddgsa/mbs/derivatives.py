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


def stepped(x0: NDArray[np.float64], h: NDArray[np.float64]) -> NDArray[np.float64]:
    """The ``2 n`` stepped arguments (2n, n) of :func:`central_difference`: row ``i < n`` is
    ``x0 + h_i e_i``, row ``n + i`` is ``x0 - h_i e_i`` (so row ``j`` steps entry ``j % n``)."""
    x0 = np.asarray(x0, dtype=float)
    return np.vstack([x0 + np.diag(h), x0 - np.diag(h)])


def central_difference(batch: Batch, x0: NDArray[np.float64], scale: float,
                       rel_step: float = 1e-6) -> NDArray[np.float64]:
    """Central-difference Jacobian (m, n) of a function given as a batch.

    Parameters
    ----------
    batch : callable
        ``batch(X) -> F``: ``X`` (2n, n) the :func:`stepped` arguments, ``F`` (2n, m) the function at
        each row.
    x0 : (n,) the point
    scale, rel_step : the step of entry ``i`` is ``rel_step * max(scale, |x0_i|)`` (:func:`central_steps`)

    Returns
    -------
    ndarray (m, n)
        ``(f(x0 + h_i e_i) - f(x0 - h_i e_i)) / (2 h_i)`` in column ``i``.
    """
    h = central_steps(x0, scale, rel_step)
    n = h.size
    f = np.asarray(batch(stepped(x0, h)), dtype=float).reshape(2 * n, -1)
    return ((f[:n] - f[n:]) / (2.0 * h)[:, None]).T


def central_jacobian(fun: Callable[..., NDArray[np.float64]], args: list[NDArray[np.float64]], which: int,
                     scale: float, rel_step: float = 1e-6) -> NDArray[np.float64]:
    """Central-difference Jacobian of ``fun(*args)`` with respect to ``args[which]`` (a Python
    function, called once per stepped argument; :func:`central_difference`)."""
    def batch(x: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.array([fun(*(xi.copy() if k == which else a for k, a in enumerate(args))) for xi in x])

    return central_difference(batch, np.asarray(args[which], dtype=float), scale, rel_step)
