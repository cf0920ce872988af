"""Operating state and the ``linear`` fidelity of the indirect drive.

The constrained system is linearised about its steadily spinning operating state under the
scene's mean loads (:func:`ddgsa.mbs.modal.linearise_system`: null-space reduction ``q = q_op(t)
+ N z``) and integrated exactly for the C1-cubic inputs between load samples
(:func:`ddgsa.mbs.integrate.exact.state_matrices`, :func:`ddgsa.mbs.linear.lti_response`) --
the kernel's exact path. The inputs enter through a constant matrix ``G``: the hub force and
moment through the hub marker's Jacobian and the generator set speed through the torque law,
``dQ(t) = G (u(t) - u0)``, so the whole record is one vectorised product instead of one
nonlinear force evaluation per sample. The multipliers (bearing and tooth forces) follow from
the linearised equations of motion, ``C_q^T dlambda = G du - M N z'' - C N z' - K N z``.

The linearisation is time-invariant because the spin angles are cyclic: the LSS carries its
bending in non-rotating coordinates and every spinning body (rotor, wheel, HSS) is rigid and
axisymmetric with its markers on its axis (:mod:`.assembly`). Its accuracy against
``flexible`` is tested.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import null_space

from ddgsa.mbs.assembly import System
from ddgsa.mbs.integrate.exact import state_matrices
from ddgsa.mbs.linear import lti_response
from ddgsa.mbs.modal import ConstrainedLinearisation, linearise_system
from ddgsa.models.indirect_drive.assembly import Assembly

Array = NDArray[np.float64]


#: relative singular-value cut-off of the reduced stiffness: the spin directions have none, and
#: central differences leave them ~1e-13 of the largest
RCOND = 1e-9


def operating_state(system: System, q: Array, qd: Array, free_rate: int, iterations: int = 30,
                    tol: float = 1e-9) -> tuple[Array, Array, ConstrainedLinearisation]:
    """Quasi-static state at spin: ``N^T Q(q, qd) = 0`` on the null space ``N`` of ``C_q``.

    Modified Newton: the stiffness of one linearisation at the start, projected on the current
    null space, against the current residual ``N^T Q`` (least squares: the spin directions carry
    no stiffness; their residual is the torque imbalance, which accelerates the drive and is left
    alone); each step is projected back on the constraints, the velocities by changing only the
    rate of coordinate ``free_rate`` (the pinion's spin: a minimum-norm correction would give the
    housing a roll rate, which a linearised run integrates into a drift of its roll). Stops when
    the step is below ``tol`` [m or rad]; returns the state and the linearisation there.

    Raises
    ------
    RuntimeError
        If the iterations do not converge.
    """
    keep = [i for i in range(system.n) if i != free_rate]
    q, qd = system.consistent_state(q, qd, 0.0, keep=keep)
    lin = linearise_system(system, q, qd, 0.0)
    basis, k_r, r0 = lin.basis, lin.k, lin.r0
    for _ in range(iterations):
        step = basis @ np.linalg.lstsq(k_r, r0, rcond=RCOND)[0]
        q, qd = system.consistent_state(q + step, qd, 0.0, keep=keep)
        if np.max(np.abs(step)) < tol:
            return q, qd, linearise_system(system, q, qd, 0.0)
        basis = null_space(system.constraint_jacobian(q, qd, 0.0))
        k_r, r0 = basis.T @ lin.k_full @ basis, basis.T @ system.terms(q, qd, 0.0).q
    raise RuntimeError(f"operating state: no convergence in {iterations} modified-Newton steps (last step "
                       f"{np.max(np.abs(step)):.3g})")


def input_matrix(asm: Assembly, q: Array, qd: Array, c_hss: float, ratio: float) -> Array:
    """``G`` (n, 7): generalised forces per unit hub force [N], hub moment [N m] and LSS set speed [rad/s].

    The hub load acts at the rotor marker (global frame); the set speed enters the generator law
    ``T = c_hss (-N w_set - w_HSS)`` about the HSS axis.
    """
    s = asm.system
    hub = next(el for el in s.elements if el.name == "hub").markers[0]
    gen = next(el for el in s.elements if el.name == "generator").markers[0]
    st_hub, st_gen = s.marker_state(hub, q, qd, 0.0), s.marker_state(gen, q, qd, 0.0)
    g = np.zeros((s.n, 7))
    g[:, :6] = st_hub.jac.T
    g[:, 6] = st_gen.jac[3:6].T @ st_gen.a[:, 0] * c_hss * (-ratio)
    return g


@dataclass(frozen=True)
class LinearResponse:
    """Coordinates, rates and multipliers of the linearised system over a record."""

    q: Array
    qd: Array
    lam: Array
    lin: ConstrainedLinearisation


def linear_response(asm: Assembly, lin: ConstrainedLinearisation, u: Array, dt: float,
                    spin_scale: float = 1.0) -> LinearResponse:
    """Exact response of the linearisation ``lin`` of ``asm`` to inputs ``u`` (n_t, 7).

    ``u`` columns: hub ``Fx, Fy, Fz`` [N], ``Mx, My, Mz`` [N m], LSS set speed [rad/s], sampled
    every ``dt`` [s]; ``asm`` must have been built with the constant loads ``u0 = u.mean(0)``
    and ``lin`` taken at its operating state (:func:`operating_state`). Starts from the
    quasi-static deflection under ``u[0]``, every body spinning at ``spin_scale`` times its
    operating speed (the drive's speed mode relaxes in ``J / c_gen``, about 50 s: start it at
    the scene's initial speed, not the mean).
    """
    s = asm.system
    q0, qd0 = lin.q0, lin.qd0
    g = input_matrix(asm, q0, qd0, asm.c_hss, asm.ratio)
    du = u - u.mean(axis=0)
    basis = lin.basis
    forcing = du @ (basis.T @ g).T                                   # (n_t, n_z)
    a, bw = state_matrices(lin)
    nz = lin.m.shape[0]
    x0 = np.zeros(2 * nz)
    x0[:nz] = np.linalg.lstsq(lin.k, forcing[0] + lin.r0, rcond=RCOND)[0]
    x0[nz:] = basis.T @ ((spin_scale - 1.0) * qd0)             # a uniform spin change keeps the constraints
    x = lti_response(a, bw, np.column_stack([forcing, np.ones(len(u))]), dt, x0)
    z, zd = x[:, :nz], x[:, nz:]
    zdd = np.linalg.solve(lin.m, (forcing + lin.r0 - zd @ lin.c.T - z @ lin.k.T).T).T
    times = dt * np.arange(len(u))
    q = q0 + np.outer(times, qd0) + z @ basis.T
    qd = qd0 + zd @ basis.T
    # multipliers: C_q^T dlambda = G du - M N z'' - C_full N z' - K_full N z
    cq = s.constraint_jacobian(q0, qd0, 0.0)
    rhs = du @ g.T - zdd @ (lin.m_full @ basis).T - zd @ (lin.c_full @ basis).T - z @ (lin.k_full @ basis).T
    lam = lin.lam0 + rhs @ np.linalg.pinv(cq.T).T
    return LinearResponse(q, qd, lam, lin)

