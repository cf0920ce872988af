"""Operating state and the ``linear`` fidelity of the indirect drive.

The constrained system is linearised about a steadily spinning operating state under the
scene's mean loads, spinning at the drive's **mean speed** over the record (:func:`linearise`,
the kernel's central differences on its compiled terms; the model takes the loads' mean speed,
:data:`~ddgsa.models.indirect_drive.model.SPEED_PASSES`): the rotor tilt/yaw modes (3.9 / 4.6 Hz at rated) carry the hub's
gyroscopic moment, so their frequencies follow the speed used in the linearisation -- the torque
balance of the mean inputs differs from the record's mean speed by ~0.15 % on 20-60 s records (the
speed mode relaxes in ``J / c_gen``, about 50 s). The torque imbalance at the mean speed is a
constant generalised force. What the linearisation cannot hold is the speed's variation within a
record: docs/indirect_drive.md gives the resulting bias by scene (<= 0.2 % on housing translation
RMS and 1.2 % on bearing damage since the rotor's tilting inertia is the hub's, version 0.4.0; up to
4.5 % and 13 % before).

The linearised system is integrated as a first-order state space in reduced coordinates on the
states that satisfy the **linearised constraints** (:func:`state_space`): ``H dq = 0`` for the holonomic rows and
``C_q dq' + B0 dq = 0`` for the velocity-level ones, with ``B0 = d(C_q qd0)/dq``
(:func:`velocity_curvature`). ``B0`` is zero for the bearings; for the gear mesh (eq. 2.4) it is
the change of the pitch-point velocity when a gear centre moves in the spinning gear's field,
which a reduction on the null space of ``C_q`` alone misses (the tooth force's response to a
hub-force pulse was 4.6 % off without it, 0.16 % with it). Inputs enter through a constant
matrix ``G`` (hub force and moment through the hub marker's Jacobian, the set speed through the
torque law) and are integrated exactly for their C1 cubic between samples
(:func:`ddgsa.mbs.linear.lti_response`); the multipliers (bearing and tooth forces) are those that
keep the constraints' derivatives zero. The states satisfy the linearised constraints to
round-off, so the nonlinear constraint residual of the record (``position_drift``,
``gear_drift``) is the linearisation's second-order error: it scales with the square of the
fluctuations (tested).

The linearisation is time-invariant because the spin angles are cyclic: the LSS carries its
bending in non-rotating coordinates and every spinning body (rotor, blades, wheel, HSS) is rigid and
axisymmetric with its markers on its axis (:mod:`.assembly`); linearised a quarter of a
second later, the eigenvalues agree to 1e-8.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import null_space

from ddgsa.mbs.assembly import System
from ddgsa.mbs.compiled import Packed, constraint_values, evaluate, pack
from ddgsa.mbs.linear import input_window, lti_response, modal_output_matrix, modal_step
from ddgsa.mbs.derivatives import central_jacobian
from ddgsa.mbs.modal import ConstrainedLinearisation, linearise_system
from ddgsa.models.indirect_drive.assembly import Assembly

Array = NDArray[np.float64]


#: relative central-difference step of the linearisation (:func:`ddgsa.mbs.modal.linearise_system`,
#: compiled): the step of a coordinate near zero is
#: 1e-3 x this, 1e-6 m (the kernel's default gives 1e-9 m, where round-off of the ~1e6 N constant
#: forces leaves ~1 N/m in K; responses agree to 1e-9 between 1e-4 and 1e-2)
LINEARISATION_STEP = 1e-3
#: relative central-difference step of :func:`velocity_curvature` (the residual is smooth and of
#: order the pitch velocity, ~1 m/s: 1e-6 m steps keep round-off near 1e-10 instead of 1e-7)
CURVATURE_STEP = 1e-3
#: relative singular-value cut-off of the reduced stiffness: the spin directions have none, and
#: central differences leave them ~1e-13 of the largest
RCOND = 1e-9


def operating_state(system: System, q: Array, qd: Array, free_rate: int, iterations: int = 30,
                    tol: float = 1e-12, start: ConstrainedLinearisation | None = None,
                    packed: Packed | None = None) -> tuple[Array, Array, ConstrainedLinearisation]:
    """Quasi-static state at spin: ``N^T Q(q, qd) = 0`` on the null space ``N`` of ``C_q``.

    Modified Newton: the stiffness of one linearisation at the start, projected on the current
    null space, against the current residual ``N^T Q`` (least squares: the spin directions carry
    no stiffness; their residual is the torque imbalance, which accelerates the drive and is left
    alone); each step is projected back on the constraints, the velocities by changing only the
    rate of coordinate ``free_rate`` (the pinion's spin: a minimum-norm correction would give the
    housing a roll rate, which a linearised run integrates into a drift of its roll). Stops when
    the step is below ``tol`` [m or rad]; returns the state and the linearisation there.

    ``start``: a linearisation of the same system near ``(q, qd)`` (the first pass of the linear
    fidelity, at a speed 0.1 % away) whose stiffness serves the iterations instead of a new one.
    Every evaluation is the compiled kernel's (``packed``: :func:`~ddgsa.mbs.compiled.pack` of
    ``system``, packed here when not given).

    Raises
    ------
    RuntimeError
        If the iterations do not converge.
    """
    packed = pack(system) if packed is None else packed
    keep = [i for i in range(system.n) if i != free_rate]

    def values(q: Array, qd: Array, t: float) -> tuple[Array, Array, Array, Array]:
        return constraint_values(packed, q, qd, t)

    q, qd = system.consistent_state(q, qd, 0.0, keep=keep, residuals=values)
    k_full = evaluate(packed, q, qd, 0.0)[2] if start is None else start.k_full
    basis, r0 = _null_space_and_force(packed, q, qd)
    k_r = basis.T @ k_full @ basis
    for _ in range(iterations):
        step = basis @ np.linalg.lstsq(k_r, r0, rcond=RCOND)[0]
        q, qd = system.consistent_state(q + step, qd, 0.0, keep=keep, residuals=values)
        if np.max(np.abs(step)) < tol:
            return q, qd, linearise_system(system, q, qd, rel_step=LINEARISATION_STEP, compiled=packed)
        basis, r0 = _null_space_and_force(packed, q, qd)
        k_r = basis.T @ k_full @ basis
    raise RuntimeError(f"operating state: no convergence in {iterations} modified-Newton steps (last step "
                       f"{np.max(np.abs(step)):.3g})")


def _null_space_and_force(packed: Packed, q: Array, qd: Array) -> tuple[Array, Array]:
    """``N`` (the null space of ``C_q``, the rows of ``numpy.linalg.svd``'s ``V^T`` past the Jacobian's
    rank: a Newton step on it does not depend on which basis) and ``N^T Q`` at ``(q, qd)``."""
    _, f, *_, jac, _ = evaluate(packed, q, qd, 0.0)
    _, sv, vt = np.linalg.svd(jac)
    basis = vt[np.sum(sv > sv[0] * max(jac.shape) * np.finfo(float).eps):].T
    return basis, basis.T @ f


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
class StateSpace:
    """The linearised constrained system as ``y' = A y + B du + c`` in reduced coordinates.

    The state ``y = [p, v]`` maps to coordinates and rates that satisfy the linearised constraints
    (:func:`state_space`): ``dq = positions @ y``, ``dq' = rates @ y``; the multipliers are
    ``lambda = lambda0 + multipliers @ [y, du, 1]``; ``g`` is the input matrix (:func:`input_matrix`).
    """

    a: Array
    b: Array
    c: Array
    positions: Array
    rates: Array
    multipliers: Array
    g: Array
    lin: ConstrainedLinearisation


def velocity_curvature(system: System, q: Array, qd: Array, packed: Packed | None = None) -> Array:
    """``B0 = d(C_q(q) qd0)/dq`` (n_c, n) at the operating state by central differences [1/s].

    Zero for the holonomic rows of a system whose constraints do not depend on the spin angles;
    for the gear's velocity constraint it is the change of the pitch-point velocity when a gear
    centre moves in the housing while the gears spin (``w x dr``), which the null space of ``C_q``
    alone misses. ``packed``: the system packed already (:func:`~ddgsa.mbs.compiled.pack`).
    """
    packed = pack(system) if packed is None else packed
    return central_jacobian(lambda x: evaluate(packed, x, qd, 0.0)[7], [np.asarray(q, dtype=float)], 0, 1e-3,
                            rel_step=CURVATURE_STEP)


def state_space(asm: Assembly, lin: ConstrainedLinearisation, packed: Packed | None = None) -> StateSpace:
    """First-order linearisation of ``asm`` about ``lin``'s operating state with its constraints linearised.

    ``M dq'' + C dq' + K dq + C_q^T dlambda = G du + M qdd0`` (the full matrices of ``lin``, with
    the geometric stiffness of the operating multipliers) on the states that satisfy the
    linearised constraints, parametrised without ``M^-1`` (the placeholder 1 kg bodies make the
    full mass matrix span 1e7): positions ``dq = N_h p`` on the null space of the holonomic rows
    ``H``; rates ``dq' = N v - C_q^+ B0 dq`` on the velocity-level rows
    ``C_q dq' + B0 dq = 0`` (:func:`velocity_curvature`), ``N`` the null space of ``C_q``.
    Then ``p' = N_h^T dq'`` and, projected on ``N`` (no multipliers),
    ``N^T M N v' = N^T (G du + M qdd0 - K dq - C dq' + M C_q^+ B0 dq')``.
    """
    s = asm.system
    packed = pack(s) if packed is None else packed
    n, nh = s.n, s.n_holonomic
    q0, qd0 = lin.q0, lin.qd0
    cq = evaluate(packed, q0, qd0, 0.0)[6]
    # the operating trajectory q0 + t qd0 is cyclic: nothing depends on a uniform advance of the spin
    # angles, K qd0 = B0 qd0 = 0 exactly; central differences leave round-off there, which the
    # perturbation of the spin angles (growing with the speed's, ~30 rad of the pinion's) multiplies
    spin = qd0 / np.linalg.norm(qd0)
    along = np.eye(n) - np.outer(spin, spin)
    k_full = lin.k_full @ along
    curvature = (velocity_curvature(s, q0, qd0, packed) if lin.curvature is None else lin.curvature) @ along
    n_h, n_v = null_space(cq[:nh]), lin.basis
    cq_pinv = np.linalg.pinv(cq)                                      # pinv(C_q^T) is its transpose
    np_, nv = n_h.shape[1], n_v.shape[1]
    positions = np.hstack([n_h, np.zeros((n, nv))])
    rates = np.hstack([-cq_pinv @ curvature @ n_h, n_v])
    m, c = lin.m_full, lin.c_full
    m_r = n_v.T @ m @ n_v
    g = input_matrix(asm, q0, qd0, asm.c_hss, asm.ratio)
    force = np.hstack([-k_full @ positions - (c - m @ cq_pinv @ curvature) @ rates, g, (m @ lin.qdd0)[:, None]])
    accel = np.linalg.solve(m_r, n_v.T @ force)                          # v' = accel [y, du, 1]
    a = np.vstack([n_h.T @ rates, accel[:, :np_ + nv]])
    # multipliers: C_q^T dlambda = force - M dq'', dq'' = N v' - C_q^+ B0 dq'
    ddq = n_v @ accel - np.hstack([cq_pinv @ curvature @ rates, np.zeros((n, 8))])
    mult = cq_pinv.T @ (force - m @ ddq)
    return StateSpace(a, np.vstack([np.zeros((np_, 7)), accel[:, np_ + nv:-1]]),
                      np.concatenate([np.zeros(np_), accel[:, -1]]), positions, rates, mult, g, lin)


def reduced_response(ss: StateSpace, u: Array, dt: float, spin_scale: float = 1.0,
                     out: Array | None = None, window: Array | None = None) -> Array:
    """States ``y`` (n_t, n_y) of ``ss`` over a record of inputs ``u`` (n_t, 7) (or ``y @ out``, out (n_y, k)).

    ``u`` columns: hub ``Fx, Fy, Fz`` [N], ``Mx, My, Mz`` [N m], LSS set speed [rad/s], sampled
    every ``dt`` [s], about their record mean (the loads the system was built with). Starts from
    the quasi-static deflection under ``u[0]``, every body spinning at ``spin_scale`` times its
    operating speed (the drive's speed mode relaxes in ``J / c_gen``, about 50 s: start it at the
    scene's initial speed, not the mean), projected on the linearised constraints (:func:`state_space`).
    Exact for the inputs' C1 cubic between samples, stepped at the sample interval in modal
    coordinates (:func:`ddgsa.mbs.linear.modal_step`: one complex multiply per mode and step, only
    the columns of ``out`` formed); by the dense recurrence (:func:`ddgsa.mbs.linear.lti_response`)
    where the eigenvectors are too ill-conditioned for that. ``window``: :func:`~ddgsa.mbs.linear.input_window`
    of ``[u - mean, 1]`` where formed already (one record, several systems).
    """
    lin = ss.lin
    du = u - u.mean(axis=0)
    qd0, basis = lin.qd0, lin.basis
    dq0 = basis @ np.linalg.lstsq(lin.k, basis.T @ ss.g @ du[0] + lin.r0, rcond=RCOND)[0]
    np_ = ss.positions.shape[1] - basis.shape[1]
    p0 = ss.positions[:, :np_].T @ dq0
    v0 = basis.T @ ((spin_scale - 1.0) * qd0 - ss.rates[:, :np_] @ p0)
    y0 = np.concatenate([p0, v0])
    out = np.eye(ss.a.shape[0]) if out is None else out
    bw = np.column_stack([ss.b, ss.c])
    w = np.column_stack([du, np.ones(len(u))])
    step = modal_step(ss.a, bw, dt)
    if step is None:
        return lti_response(ss.a, bw, w, dt, y0, c_out=out.T)
    return step.outputs(input_window(w) if window is None else window, y0, modal_output_matrix(step.vec, step.lam, out.T))


@dataclass(frozen=True)
class LinearResponse:
    """Coordinates, rates and multipliers of the linearised system over a record."""

    q: Array
    qd: Array
    lam: Array
    lin: ConstrainedLinearisation


def linear_response(ss: StateSpace, u: Array, dt: float, spin_scale: float = 1.0,
                    window: Array | None = None) -> LinearResponse:
    """Coordinates, rates and multipliers over a record of inputs ``u`` (n_t, 7) (:func:`reduced_response`).

    ``ss`` is the state space of the system built with the constant loads ``u0 = u.mean(0)``,
    linearised at its operating state (:func:`operating_state`); every state of the record
    satisfies the linearised constraints to round-off.
    """
    y = reduced_response(ss, u, dt, spin_scale, window=window)
    lin = ss.lin
    du = u - u.mean(axis=0)
    times = dt * np.arange(len(u))
    q = lin.q0 + np.outer(times, lin.qd0) + y @ ss.positions.T
    qd = lin.qd0 + y @ ss.rates.T
    lam = lin.lam0 + np.column_stack([y, du, np.ones(len(u))]) @ ss.multipliers.T
    return LinearResponse(q, qd, lam, lin)
