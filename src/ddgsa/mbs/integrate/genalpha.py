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

The same algorithm runs compiled (:mod:`ddgsa.mbs.compiled`) whenever every part of the system
has a compiled form, and in Python otherwise (or with ``compiled=False``); the two agree to
round-off (tested).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.alpha import coefficients, next_aux, predict, primed
from ddgsa.mbs.assembly import System, accelerations
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
    n, nc, nh = system.n, system.n_constraints, system.n_holonomic
    n_steps = int(round((t_end - t0) / dt))
    if n_steps < 1 or abs(n_steps * dt - (t_end - t0)) > 1e-9 * max(1.0, t_end):
        raise ModelError(f"t_end - t0 = {t_end - t0} s is not a positive multiple of dt = {dt} s")
    am, af, gamma, beta = coefficients(rho_inf)
    if output_every < 1 or n_steps % output_every:
        raise ModelError(f"output_every = {output_every} must divide the {n_steps} steps")
    packed = None
    if compiled or compiled is None:
        from ddgsa.mbs.compiled import gen_alpha, pack
        try:
            packed = pack(system)
        except ModelError:
            if compiled:
                raise
    if packed is not None:
        q, qd, lam, y, pdrift, vdrift, status, total = gen_alpha(packed, q0, qd0, t0, dt, n_steps, output_every,
                                                                 (am, af, gamma, beta), tol, max_iter)
        if status < 0:
            raise ModelError(f"generalised-alpha: Newton did not converge in {max_iter} iterations at "
                             f"t = {t0 - status * dt:.6g} s (step {dt} s); reduce the step or check the model")
        t_out = t0 + dt * output_every * np.arange(q.shape[0])
        return Trajectory(t_out, q, qd, lam, y, pdrift, vdrift, system.coord_names, system.element_names,
                          system.multiplier_names,
                          {"method": "generalised-alpha (compiled)", "rho_inf": rho_inf, "dt": dt, "steps": n_steps,
                           "newton_max": int(status), "newton_mean": total / n_steps})
    h = dt
    bp, gp = primed(am, af, gamma, beta)
    q, qd = np.array(q0, dtype=float), np.array(qd0, dtype=float)
    acc, lam = accelerations(system, q, qd, t0)
    aux = acc.copy()
    keep = list(range(0, n_steps + 1, output_every))
    n_out = len(keep)
    t_out = t0 + dt * np.asarray(keep, dtype=float)
    q_out, qd_out, lam_out = np.empty((n_out, n)), np.empty((n_out, n)), np.empty((n_out, nc))
    y_out = np.empty((n_out, len(system.elements), 6))
    pdrift, vdrift = np.zeros(n_out), np.zeros(n_out)

    def record(slot: int, t: float) -> None:
        states = system.marker_states(q, qd, t)
        tm = system.terms(q, qd, t, states)
        q_out[slot], qd_out[slot], lam_out[slot] = q, qd, lam
        if tm.outputs:
            y_out[slot] = np.array(tm.outputs)
        if nh:
            pdrift[slot] = np.max(np.abs(system.holonomic_residual(q, qd, t, states)[0]))
        if nc:
            vdrift[slot] = np.max(np.abs(system.velocity_residual(q, qd, t, states)[0]))

    record(0, t0)
    iters = []
    slot = 1
    big = np.zeros((n + nc, n + nc))
    for step in range(1, n_steps + 1):
        t = t0 + step * h
        acc_new, q, qd = predict(q, qd, acc, aux, h, am, af, gamma, beta)
        for it in range(max_iter):
            states = system.marker_states(q, qd, t)
            tm = system.terms(q, qd, t, states)
            res = tm.m @ acc_new - tm.q
            if nc:
                v, b = system.velocity_residual(q, qd, t, states)
                cval = np.empty(nc)
                if nh:
                    cval[:nh] = system.holonomic_residual(q, qd, t, states)[0] / (bp * h * h)
                cval[nh:] = v[nh:] / (gp * h)
                res = res + b.T @ lam
                big[:n, n:] = b.T
                big[n:, :n] = b
            big[:n, :n] = tm.m + gp * h * tm.c + bp * h * h * tm.k
            rhs = -np.concatenate([res, cval]) if nc else -res
            delta = np.linalg.solve(big, rhs)
            acc_new += delta[:n]
            q += bp * h * h * delta[:n]
            qd += gp * h * delta[:n]
            if nc:
                lam = lam + delta[n:]
            small = np.max(np.abs(bp * h * h * delta[:n])) < tol
            if small and (not nc or np.max(np.abs(cval)) * bp * h * h < tol):
                break
        else:
            raise ModelError(f"generalised-alpha: Newton did not converge in {max_iter} iterations at t = {t:.6g} s "
                             f"(step {dt} s); reduce the step or check the model")
        if not np.all(np.isfinite(q)):
            raise ModelError(f"generalised-alpha: the state is not finite at t = {t:.6g} s")
        iters.append(it + 1)
        aux = next_aux(acc, aux, acc_new, am, af)
        acc = acc_new
        if step % output_every == 0:
            record(slot, t)
            slot += 1
    return Trajectory(t_out, q_out, qd_out, lam_out, y_out, pdrift, vdrift, system.coord_names,
                      system.element_names, system.multiplier_names,
                      {"method": "generalised-alpha (Python)", "rho_inf": rho_inf, "dt": dt, "steps": n_steps,
                       "newton_max": int(max(iters)), "newton_mean": float(np.mean(iters))})
