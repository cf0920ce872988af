"""Static equilibrium, written once.

One Newton loop, :func:`_newton`, solves ``Q(q, 0, t) = C_q^T lambda`` with the holonomic
constraints ``C(q, t) = 0`` kept exactly and the velocity-level ones (gear contacts) holding for
the displacement from the start, ``B(q) (q - q_start) = 0`` (their integrable linearisation).
Coordinates named in ``hold`` stay at their start values: a cyclic coordinate such as a free spin
angle, whose torque the elements balance without a stiffness, would leave the tangent singular.

The system is evaluated through a kind of :mod:`ddgsa.mbs.alpha`'s loop (``evaluate(q, qd, t, step,
ctx, m, f, kt, ct, y, ch, jac, vel)``), so the statics runs every system the integrator runs: as
Python on any :class:`~ddgsa.mbs.assembly.System` (:func:`static_equilibrium`), compiled for a
compiled kind (:func:`compiled_statics`: the single-body kernel's ``static_state``, the direct drive's).

The tangent is either analytic (``-K_t`` of the kind, without gyroscopic terms or the multipliers'
geometric stiffness; the constraint rows ``C_q``: one evaluation an iteration, the same root) or
central differences of the residual over ``q`` (step ``1e-6 max(1e-3, |q_i|)``, ``2 n`` evaluations
an iteration, quadratic convergence); the multiplier block is exact in both (``-C_q^T``: a
difference step in ``lambda`` is lost in large forces such as the weight a lock carries).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from numba import njit
from numpy.typing import NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.alpha import python_loop, specialise
from ddgsa.mbs.assembly import System, python_kind
from ddgsa.mbs.derivatives import central_step

Array = NDArray[np.float64]

#: relative step and floor [m or rad] of the central-difference tangent
FD_STEP, FD_SCALE = 1e-6, 1e-3

_evaluate: Callable | None = None
"""The kind's evaluation, bound in each copy of :func:`_newton` (:func:`ddgsa.mbs.alpha.specialise`)."""


@njit(cache=True)
def _residual(r, f, ch, jac, lam, q, q_start):  # pragma: no cover (compiled)
    """``[Q - C_q^T lambda; C; B (q - q_start)]`` into ``r`` from the kind's arrays."""
    n, nc, nh = f.size, lam.size, ch.size
    for i in range(n):
        acc = f[i]
        for k in range(nc):
            acc -= jac[k, i] * lam[k]
        r[i] = acc
    for k in range(nh):
        r[n + k] = ch[k]
    for k in range(nh, nc):
        acc = 0.0
        for j in range(n):
            acc += jac[k, j] * (q[j] - q_start[j])
        r[n + k] = acc


def _newton(ctx, q, t, hold, tol, max_iter, nh, nc, n_y, analytic):  # pragma: no cover (compiled per kind)
    """The Newton loop (see the module) on ``q`` in place from its start value; ``hold`` (n,) marks
    the held coordinates. Returns ``(lambda, iterations, residual)``: ``iterations`` -1 when
    ``max_iter`` did not converge (the largest coordinate update stayed at or above ``tol``)."""
    n = q.size
    q_start = q.copy()
    lam = np.zeros(nc)
    qd = np.zeros(n)
    m, f, kt, ct = np.zeros((n, n)), np.zeros(n), np.zeros((n, n)), np.zeros((n, n))
    y, ch, jac, vel = np.zeros(n_y), np.zeros(nh), np.zeros((nc, n)), np.zeros(nc)
    big, r = np.zeros((n + nc, n + nc)), np.zeros(n + nc)
    rp, rm = np.zeros(n + nc), np.zeros(n + nc)
    worst = 0.0
    for it in range(max_iter):
        _evaluate(q, qd, t, 0, ctx, m, f, kt, ct, y, ch, jac, vel)
        _residual(r, f, ch, jac, lam, q, q_start)
        worst = np.max(np.abs(r)) if r.size else 0.0
        big[:, :] = 0.0
        big[:n, n:] = -jac.T
        if analytic:
            big[:n, :n] = -kt
            big[n:, :n] = jac
        else:
            for j in range(n):
                if hold[j]:
                    continue
                x = q[j]
                h = central_step(x, FD_SCALE, FD_STEP)
                q[j] = x + h
                _evaluate(q, qd, t, 0, ctx, m, f, kt, ct, y, ch, jac, vel)
                _residual(rp, f, ch, jac, lam, q, q_start)
                q[j] = x - h
                _evaluate(q, qd, t, 0, ctx, m, f, kt, ct, y, ch, jac, vel)
                _residual(rm, f, ch, jac, lam, q, q_start)
                q[j] = x
                big[:, j] = (rp - rm) / (2 * h)
        for j in range(n):
            if hold[j]:
                big[j, :] = 0.0
                big[:, j] = 0.0
                big[j, j] = 1.0
                r[j] = 0.0
        r[:] = -r
        dx = np.linalg.solve(big, r)
        q += dx[:n]
        lam += dx[n:]
        largest = np.max(np.abs(dx[:n])) if n else 0.0
        if largest < tol:
            return lam, it + 1, worst
    return lam, -1, worst


def compiled_statics(evaluate: Callable, tag: str) -> Callable:
    """:func:`_newton` compiled (and cached) for a compiled kind ``evaluate`` (an ``njit`` function)."""
    return specialise(evaluate, tag, loop=_newton)


def solve(loop: Callable, ctx: object, q: Array, t: float, hold: Sequence[int], tol: float, max_iter: int,
          nh: int, nc: int, n_y: int, analytic: bool) -> tuple[Array, Array]:
    """Run ``loop`` (:func:`_newton` bound to a kind) from ``q``; returns ``(q, lambda)``.

    Raises
    ------
    ModelError
        When the tangent is singular (a rigid-body motion left free by the elements and
        constraints, and not held) or ``max_iter`` iterations do not converge.
    """
    q = np.array(q, dtype=float)
    mask = np.zeros(q.size, dtype=np.bool_)
    mask[np.asarray(hold, dtype=int)] = True
    try:
        lam, iterations, residual = loop(ctx, q, float(t), mask, float(tol), int(max_iter), int(nh), int(nc),
                                         int(n_y), bool(analytic))
    except np.linalg.LinAlgError:
        raise ModelError("static equilibrium: the tangent is singular (a rigid-body motion is left free by "
                         "the elements and constraints)") from None
    if iterations < 0:
        raise ModelError(f"static equilibrium: no convergence in {max_iter} iterations (residual {residual:.3g})")
    return q, lam


def static_equilibrium(system: System, q: Array | None = None, t: float = 0.0, tol: float = 1e-10,
                       max_iter: int = 50, analytic: bool = False, hold: Sequence[int] = ()) -> tuple[Array, Array]:
    """Static equilibrium of any System near ``q`` (default the initial pose): :func:`_newton` run as
    Python on the System's parts (see the module).

    Parameters
    ----------
    q : (n,), optional
        Start [m, rad]; the velocity-level constraints hold for the displacement from it.
    t : float
        Time [s] at which the elements and constraints are evaluated.
    tol : float
        Converged when the largest coordinate update is below ``tol`` [m or rad].
    analytic : bool
        Tangent from the parts' own tangents (one evaluation an iteration) instead of central
        differences (``2 n``); the residual, and so the root, is the same.
    hold : sequence of int
        Coordinates held at their start values (cyclic ones, such as a free spin angle).

    Returns
    -------
    q : (n,) equilibrium coordinates
    lam : (n_c,) multipliers (holonomic first), see each constraint's ``reaction``
    """
    start = system.q0 if q is None else np.asarray(q, dtype=float)
    return solve(python_loop(python_kind(system), loop=_newton), None, start, t, hold, tol,
                 max_iter, system.n_holonomic, system.n_constraints, 6 * len(system.elements), analytic)
