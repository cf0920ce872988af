"""``solve_ivp`` on a second-order system in first-order form: the reference integrator's one call.

:func:`ddgsa.mbs.integrate.reference.simulate` gives it a System's accelerations (index-1 form),
:func:`ddgsa.mbs.system.integrate_reference` the single-body kernel's compiled ones (the direct drive's
reference).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray
from scipy.integrate import solve_ivp

from ddgsa.errors import ModelError

Array = NDArray[np.float64]


def first_order(acceleration: Callable[[float, Array, Array], Array], q0: Array, qd0: Array, times: Array,
                method: str = "Radau", rtol: float = 1e-8, atol: float = 1e-10) -> tuple[Array, Array, int]:
    """``solve_ivp`` on ``y = (q, q_dot)``, ``y' = (q_dot, acceleration(t, q, q_dot))``, reported at ``times`` [s].

    Returns ``(q, qd)`` (n_t, n) and the number of right-hand-side evaluations; a
    :class:`ModelError` when the solver fails.
    """
    q0, qd0 = np.asarray(q0, dtype=float), np.asarray(qd0, dtype=float)
    n = q0.size

    def rhs(t: float, y: Array) -> Array:
        return np.concatenate([y[n:], acceleration(t, y[:n], y[n:])])

    sol = solve_ivp(rhs, (times[0], times[-1]), np.concatenate([q0, qd0]), method=method, t_eval=times, rtol=rtol,
                    atol=atol)
    if not sol.success:
        raise ModelError(f"solve_ivp ({method}) failed: {sol.message}")
    return sol.y[:n].T, sol.y[n:].T, int(sol.nfev)
