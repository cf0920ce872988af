"""Generalised-alpha for constrained multibody systems: the fast nonlinear path.

Chung & Hulbert's method in the form of Arnold & Bruls (2007) for ``M(q) q_ddot + C_q^T lambda =
Q(q, q_dot, t)``: the equilibrium is enforced at ``t_{n+1}`` with the multipliers there;
holonomic constraints at **position level** (index 3, ``C(q_{n+1}) = 0`` to the Newton
tolerance, so they do not drift), velocity-level constraints (gear contact, prescribed speed)
at velocity level (index 2). Both rows are scaled by the Newmark factors (``1/(beta' h^2)``
and ``1/(gamma' h)``, Bottasso, Bauchau & Cardona 2007) so the iteration matrix
``[[M + gamma' h C_t + beta' h^2 K_t, C_q^T], [C_q, 0]]`` stays well conditioned for small
steps. Second-order accurate in positions, unconditionally stable on linear systems, with
high-frequency dissipation set by ``rho_inf`` (1: none; the trapezoidal rule).

The loop is :mod:`ddgsa.mbs.alpha`'s, the one generalised-alpha of the package: compiled on the
packed system (:mod:`ddgsa.mbs.compiled`) whenever every part of it has a compiled form, and run
as Python on the System's own objects otherwise (or with ``compiled=False``); the two agree to
round-off (tested).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.alpha import coefficients, python_loop, steps
from ddgsa.mbs.assembly import System, accelerations, python_kind
from ddgsa.mbs.integrate.trajectory import Trajectory

Array = NDArray[np.float64]


def simulate(system: System, t_end: float, dt: float, q0: Array | None = None, qd0: Array | None = None,
             t0: float = 0.0, rho_inf: float = 0.8, tol: float = 1e-10, max_iter: int = 20,
             output_every: int = 1, compiled: bool | None = None) -> Trajectory:
    """Integrate from ``t0`` to ``t_end`` with fixed step ``dt`` [s].

    Parameters
    ----------
    q0, qd0 : ndarray, optional
        Initial state (default: the system's, made consistent by :meth:`System.consistent_state`).
    rho_inf : float
        Spectral radius at infinite frequency (1: no numerical dissipation).
    tol : float
        Newton stops when the largest coordinate correction is below ``tol`` (m or rad) and the
        scaled constraint residuals are below ``tol`` too.
    output_every : int
        Keep every ``output_every``-th step.
    compiled : bool, optional
        Run the compiled kernel (True: required, raising if a part has no compiled form; None:
        when possible; False: the Python loop).

    Returns
    -------
    Trajectory
        With the constraint drift after every kept step and ``info`` (``newton_max``,
        ``newton_mean``, ``steps``).
    """
    if q0 is None or qd0 is None:
        q0, qd0 = system.consistent_state(q0, qd0, t0)
    n_steps = steps(t_end - t0, dt, output_every, "generalised-alpha")
    am, af, gamma, beta = coefficients(rho_inf)
    packed = None
    if compiled or compiled is None:
        from ddgsa.mbs.compiled import pack
        try:
            packed = pack(system)
        except ModelError:
            if compiled:
                raise
    if packed is not None:
        from ddgsa.mbs.compiled import gen_alpha
        q, qd, lam, y, drift, status, total = gen_alpha(packed, q0, qd0, t0, dt, n_steps, output_every,
                                                        (am, af, gamma, beta), tol, max_iter)
        how = "compiled"
    else:
        q, qd, lam, y, drift, status, total = _python(system, np.array(q0, dtype=float), np.array(qd0, dtype=float),
                                                      t0, dt, n_steps, output_every, (am, af, gamma, beta), tol,
                                                      max_iter)
        how = "Python"
    if status < 0:
        raise ModelError(f"generalised-alpha: Newton did not converge in {max_iter} iterations at "
                         f"t = {t0 - status * dt:.6g} s (step {dt} s); reduce the step or check the model")
    t_out = t0 + dt * output_every * np.arange(q.shape[0])
    return Trajectory(t_out, q, qd, lam, y, drift[:, 0], drift[:, 1], system.coord_names, system.element_names,
                      system.multiplier_names,
                      {"method": f"generalised-alpha ({how})", "rho_inf": rho_inf, "dt": dt, "steps": n_steps,
                       "newton_max": int(status), "newton_mean": total / n_steps})


def _python(system: System, q0: Array, qd0: Array, t0: float, dt: float, n_steps: int, output_every: int,
            coef: tuple[float, float, float, float], tol: float, max_iter: int) -> tuple:
    """The loop run as Python on the System's objects (parts without a compiled form)."""
    nh, nel = system.n_holonomic, len(system.elements)
    acc0, lam0 = accelerations(system, q0, qd0, t0)
    q, qd, lam, y, drift, status, total = python_loop(python_kind(system))(
        None, q0, qd0, acc0, np.asarray(lam0, dtype=float), float(t0), float(dt), n_steps, output_every, *coef, tol,
        max_iter, nh, 6 * nel, False, False, False)
    return q, qd, lam, y.reshape(y.shape[0], nel, 6), drift, status, total
