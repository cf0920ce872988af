"""``solve_ivp`` on the index-1 form of the constrained equations: the reference path.

At every right-hand side the accelerations and multipliers come from eq. 2.6,
``[[M, C_q^T], [C_q, 0]] [q_ddot; lambda] = [Q; -g - 2 w V - w^2 C]``
(:func:`~ddgsa.mbs.assembly.accelerations`), with **Baumgarte stabilisation** at rate ``w``
(default 10 rad/s, well below the fastest mode the step control resolves) pulling the
position- and velocity-level constraint values ``C``, ``V`` back to zero; the constraint drift
that remains is measured and returned. An implicit scipy method (Radau by default) with tight
tolerances; slow, for tests and benchmarks. :func:`ddgsa.mbs.ivp.first_order` is the one ``solve_ivp`` call of the
package: :func:`simulate` gives it the System's accelerations, the single-body kernel
(:func:`ddgsa.mbs.system.integrate_reference`, the direct drive's reference) its compiled ones.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ddgsa.mbs.assembly import System, accelerations
from ddgsa.mbs.integrate.trajectory import Trajectory
from ddgsa.mbs.ivp import first_order

Array = NDArray[np.float64]


def simulate(system: System, t_end: float, dt: float, q0: Array | None = None, qd0: Array | None = None,
             t0: float = 0.0, method: str = "Radau", rtol: float = 1e-8, atol: float = 1e-10,
             stabilisation: float = 10.0) -> Trajectory:
    """Integrate from ``t0`` to ``t_end`` and report the state every ``dt`` [s].

    Parameters
    ----------
    method : str
        A ``solve_ivp`` method (Radau, BDF, LSODA, DOP853...).
    rtol, atol : float
        ``solve_ivp`` tolerances.
    stabilisation : float
        Baumgarte rate [rad/s] (0: plain index-1 form).
    """
    if q0 is None or qd0 is None:
        q0, qd0 = system.consistent_state(q0, qd0, t0)
    n_out = int(round((t_end - t0) / dt)) + 1
    times = t0 + dt * np.arange(n_out)
    q, qd, nfev = first_order(lambda t, q, qd: accelerations(system, q, qd, t, stabilisation)[0], q0, qd0, times,
                              method, rtol, atol)
    nc, nh = system.n_constraints, system.n_holonomic
    lam = np.zeros((n_out, nc))
    outputs = np.zeros((n_out, len(system.elements), 6))
    pdrift, vdrift = np.zeros(n_out), np.zeros(n_out)
    for i, t in enumerate(times):
        states = system.marker_states(q[i], qd[i], t)
        tm = system.terms(q[i], qd[i], t, states)
        if tm.outputs:
            outputs[i] = np.array(tm.outputs)
        if nc:
            lam[i] = accelerations(system, q[i], qd[i], t, stabilisation)[1]
            vdrift[i] = np.max(np.abs(system.velocity_residual(q[i], qd[i], t, states)[0]))
        if nh:
            pdrift[i] = np.max(np.abs(system.holonomic_residual(q[i], qd[i], t, states)[0]))
    return Trajectory(times, q, qd, lam, outputs, pdrift, vdrift, system.coord_names, system.element_names,
                      system.multiplier_names, {"method": f"solve_ivp {method}", "rtol": rtol, "atol": atol,
                                                "stabilisation": stabilisation, "nfev": nfev})

