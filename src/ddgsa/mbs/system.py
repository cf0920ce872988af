"""A flexible body on spring-dampers to a prescribed body, driven by point loads and a torque law.

The compiled kernel of systems of one FFR body (:func:`single_body_arrays` packs such a
:class:`ddgsa.mbs.assembly.System`, which is how the direct drive is written): one FFR body (:mod:`ddgsa.mbs.ffr`),
3-direction spring-damper elements between body points and points of a prescribed body
(the bedplate, translating with a given motion), a force and moment time series applied at
one body point (the hub), and a torque law ``T = T0 + c (w_set(t) - w)`` on one section
(the generator, seed 000 eq. 25). Everything is packed into :class:`SystemArrays` so the
compiled kernels see plain arrays.

Integrators:

- :func:`integrate` -- generalised-alpha (Chung & Hulbert 1993, in the Arnold & Bruls 2007
  form for nonlinear second-order systems), fixed step, Newton iterations with the
  iteration matrix ``M + gamma' h C_t + beta' h^2 K_t`` built from the current mass matrix and
  the spring, shaft and torque-law tangents (gyroscopic and geometric-stiffness terms are left
  to the iterations). Second-order accurate, unconditionally stable on linear systems, with
  high-frequency dissipation set by ``rho_inf``.
- :func:`integrate_reference` -- scipy ``solve_ivp`` (Radau or BDF) on the same equations, the
  reference path for tests and benchmarks.

Cost: a step of :func:`integrate` is one evaluation of :func:`terms_into` (the FFR body by
:func:`ddgsa.mbs.ffr.body_terms_into`, then springs, hub load and torque law, all in scalar loops
writing into arrays the integrator keeps) and one 12 x 12 Cholesky solve: ~3 us for the direct
drive (600 s at 5 ms in ~0.4 s of CPU), of which ~0.7 us is numba's reference counting of the
~30 array arguments at the call.

What is specialised here, and why: the springs are :class:`~ddgsa.mbs.elements.SpringDamper3`
along global axes between one body and the bedplate, so their force and tangent are per-axis
scalars summed once into symmetric tangents (no 12 x 12 marker tangent, no allocation); the hub
load is :class:`~ddgsa.mbs.elements.AppliedLoad` mapped onto the one body's coordinates without
a marker Jacobian. The torque law is the elements' own :func:`~ddgsa.mbs.elements.linear_torque`.
Calling the general :func:`~ddgsa.mbs.elements.connector_wrench` per spring would allocate its
6 x 6 and 12 x 12 arrays in every Newton iteration of a ~3 us step.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numba import njit
from numpy.typing import NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.alpha import coefficients, specialise
from ddgsa.mbs.assembly import System
from ddgsa.mbs.bodies import FlexibleBody
from ddgsa.mbs.elements import AppliedLoad, SpringDamper3, TorqueLaw, linear_torque
from ddgsa.mbs.ffr import Invariants, body_terms_into, g_bar, rotation
from ddgsa.mbs.ivp import first_order
from ddgsa.mbs.statics import compiled_statics, solve


@dataclass(frozen=True)
class SystemArrays:
    """All constant arrays of a system (SI units).

    Attributes
    ----------
    pm, pu, ps : mass points of the body: masses (n_p,), positions (n_p, 3), shapes (n_p, 3, n_f)
    gravity : (3,) gravity acceleration in the global frame [m/s^2]
    kff, cff : (n_f, n_f) elastic stiffness and damping of the body
    sp_u0, sp_s : (n_s, 3), (n_s, 3, n_f) body attachment points of the spring-dampers
    sp_k, sp_c : (n_s, 3) stiffness [N/m] and damping [N s/m] along global x, y, z
    sp_ground : (n_s, 3) undisplaced positions of the prescribed-body points [m]
    ld_u0, ld_s, ld_srot : load point (3,), its shapes (3, n_f) and section rotation shapes (3, n_f)
    gn_srot : (3, n_f) section rotation shapes where the torque law acts
    c_torque : torque-law constant c [N m s/rad]
    """

    pm: NDArray[np.float64]
    pu: NDArray[np.float64]
    ps: NDArray[np.float64]
    gravity: NDArray[np.float64]
    kff: NDArray[np.float64]
    cff: NDArray[np.float64]
    sp_u0: NDArray[np.float64]
    sp_s: NDArray[np.float64]
    sp_k: NDArray[np.float64]
    sp_c: NDArray[np.float64]
    sp_ground: NDArray[np.float64]
    ld_u0: NDArray[np.float64]
    ld_s: NDArray[np.float64]
    ld_srot: NDArray[np.float64]
    gn_srot: NDArray[np.float64]
    c_torque: float

    @property
    def n_dof(self) -> int:
        """Number of generalised coordinates (6 + n_f)."""
        return 6 + self.ps.shape[2]

    @cached_property
    def invariants(self) -> Invariants:
        """Inertia invariants of the body (computed once per system)."""
        return Invariants(self.pm, self.pu, self.ps)

    def args(self) -> tuple:
        """The arrays in kernel order (the body enters through its inertia invariants)."""
        return (*self.invariants.args(), self.gravity, self.kff, self.cff, self.sp_u0,
                self.sp_s, self.sp_k, self.sp_c, self.sp_ground, self.ld_u0, self.ld_s, self.ld_srot, self.gn_srot,
                self.c_torque)


@njit(cache=True)
def terms(q, qd, force, moment, w_set, torque0, bp_disp, bp_vel, mass, first0, s_sum, k0, k1, e, f4, h0, h1,
          gravity, kff, cff, sp_u0, sp_s, sp_k, sp_c, sp_ground, ld_u0, ld_s, ld_srot, gn_srot,
          c_torque):  # pragma: no cover
    """Mass matrix, generalised forces, tangent stiffness/damping, spring forces and torque.

    Returns ``(M, Q, K_t, C_t, F_springs (n_s, 3), T)`` where ``F_springs`` are the forces the
    body exerts on the prescribed body (``K l + C l_dot``, global frame) and ``T`` the torque-law
    torque on the body about its x axis. Allocates its outputs; the integrator calls
    :func:`terms_into` on arrays it keeps.
    """
    n = q.size
    m, f, kt, ct = np.empty((n, n)), np.empty(n), np.empty((n, n)), np.empty((n, n))
    fs = np.empty((sp_k.shape[0], 3))
    torque = terms_into(q, qd, force, moment, w_set, torque0, bp_disp, bp_vel, mass, first0, s_sum, k0, k1, e, f4,
                        h0, h1, gravity, kff, cff, sp_u0, sp_s, sp_k, sp_c, sp_ground, ld_u0, ld_s, ld_srot, gn_srot,
                        c_torque, m, f, kt, ct, fs, np.empty((sp_k.shape[0] + 1, 3, n)))
    return m, f, kt, ct, fs, torque


@njit(cache=True)
def terms_into(q, qd, force, moment, w_set, torque0, bp_disp, bp_vel, mass, first0, s_sum, k0, k1, e, f4, h0, h1,
               gravity, kff, cff, sp_u0, sp_s, sp_k, sp_c, sp_ground, ld_u0, ld_s, ld_srot, gn_srot,
               c_torque, m, f, kt, ct, fs, lg):  # pragma: no cover
    """:func:`terms` written into ``m, f, kt, ct`` (n, n), (n,), (n, n), (n, n) and ``fs`` (n_s, 3);
    ``lg`` (n_s + 1, 3, n) is scratch. Returns the torque-law torque [N m].

    Scalar loops, no allocation besides the body kernel's (:func:`ddgsa.mbs.ffr.body_terms_into`):
    this runs once per Newton iteration. The tangents are the symmetric sums
    ``K_t = sum_s L_s^T diag(k_s) L_s + K_ff`` and ``C_t = sum_s L_s^T diag(c_s) L_s + C_ff + c b b^T``
    (springs along global axes, ``L_s`` the velocity map of spring ``s``'s body point, ``b`` the
    map from ``q_dot`` to the generator section's spin rate), each entry summed once and written
    once: accumulating into the arrays spring by spring costs a load and a store per term.
    """
    n = q.size
    nf = n - 6
    ns = sp_k.shape[0]
    body_terms_into(q, qd, mass, first0, s_sum, k0, k1, e, f4, h0, h1, gravity, m, f)
    a = rotation(q[3:6])
    g = g_bar(q[3:6])
    for s in range(ns):
        u0, u1, u2 = sp_u0[s, 0], sp_u0[s, 1], sp_u0[s, 2]
        for k in range(nf):
            u0 += sp_s[s, 0, k] * q[6 + k]
            u1 += sp_s[s, 1, k] * q[6 + k]
            u2 += sp_s[s, 2, k] * q[6 + k]
        _global_map(a, g, u0, u1, u2, sp_s[s], lg[s])
        for d in range(3):
            r = q[d] + a[d, 0] * u0 + a[d, 1] * u1 + a[d, 2] * u2
            v = 0.0
            for i in range(n):
                v += lg[s, d, i] * qd[i]
            fd = sp_k[s, d] * (r - sp_ground[s, d] - bp_disp[d]) + sp_c[s, d] * (v - bp_vel[d])
            fs[s, d] = fd
            for i in range(n):
                f[i] -= lg[s, d, i] * fd
    for i in range(nf):
        acc = 0.0
        for j in range(nf):
            acc += kff[i, j] * q[6 + j] + cff[i, j] * qd[6 + j]
        f[6 + i] -= acc
    # hub force and moment: Q += L^T F, Q_angles += (A G)^T M, Q_f += S_rot^T A^T M
    u0, u1, u2 = ld_u0[0], ld_u0[1], ld_u0[2]
    for k in range(nf):
        u0 += ld_s[0, k] * q[6 + k]
        u1 += ld_s[1, k] * q[6 + k]
        u2 += ld_s[2, k] * q[6 + k]
    ll = lg[ns]
    _global_map(a, g, u0, u1, u2, ld_s, ll)
    for i in range(n):
        f[i] += ll[0, i] * force[0] + ll[1, i] * force[1] + ll[2, i] * force[2]
    mb0 = a[0, 0] * moment[0] + a[1, 0] * moment[1] + a[2, 0] * moment[2]       # A^T M (body frame)
    mb1 = a[0, 1] * moment[0] + a[1, 1] * moment[1] + a[2, 1] * moment[2]
    mb2 = a[0, 2] * moment[0] + a[1, 2] * moment[1] + a[2, 2] * moment[2]
    for k in range(3):                     # (A G)^T M = G^T A^T M
        f[3 + k] += g[0, k] * mb0 + g[1, k] * mb1 + g[2, k] * mb2
    for k in range(nf):
        f[6 + k] += ld_srot[0, k] * mb0 + ld_srot[1, k] * mb1 + ld_srot[2, k] * mb2
    # torque law on the section: b maps q_dot to the section spin rate; (A G)^T A e_x = G^T e_x
    b = ll[0]                              # the load's map is used: its first row holds b
    for i in range(3):
        b[i] = 0.0
    for k in range(3):
        b[3 + k] = g[0, k]
    for k in range(nf):
        b[6 + k] = gn_srot[0, k]           # (A S_rot)^T A e_x = S_rot^T e_x
    rate = 0.0
    for i in range(n):
        rate += b[i] * qd[i]
    torque = linear_torque(torque0, c_torque, w_set, rate)    # the torque law's one implementation
    for i in range(n):
        f[i] += b[i] * torque
    for i in range(n):
        for j in range(i, n):
            acc_k = 0.0
            acc_c = c_torque * b[i] * b[j]
            for s in range(ns):
                for d in range(3):
                    lij = lg[s, d, i] * lg[s, d, j]
                    acc_k += sp_k[s, d] * lij
                    acc_c += sp_c[s, d] * lij
            if i >= 6:
                acc_k += kff[i - 6, j - 6]
                acc_c += cff[i - 6, j - 6]
            kt[i, j] = acc_k
            kt[j, i] = acc_k
            ct[i, j] = acc_c
            ct[j, i] = acc_c
    return torque


@njit(cache=True)
def _global_map(a, g, u0, u1, u2, s, out):  # pragma: no cover (compiled)
    """Write ``L = A [A^T, -u~ G_bar, S]`` (3 x n) of a point at body position ``u`` into ``out``."""
    nf = s.shape[1]
    for i in range(3):
        for j in range(3):
            out[i, j] = 1.0 if i == j else 0.0
    # -u~ G_bar column k = g_k x u, then rotate by A
    for k in range(3):
        c0 = g[1, k] * u2 - g[2, k] * u1
        c1 = g[2, k] * u0 - g[0, k] * u2
        c2 = g[0, k] * u1 - g[1, k] * u0
        for i in range(3):
            out[i, 3 + k] = a[i, 0] * c0 + a[i, 1] * c1 + a[i, 2] * c2
    for k in range(nf):
        for i in range(3):
            out[i, 6 + k] = a[i, 0] * s[0, k] + a[i, 1] * s[1, k] + a[i, 2] * s[2, k]


@njit(cache=True)
def _interp_into(series, k, frac, out):  # pragma: no cover (compiled)
    """Catmull-Rom (C1 cubic) interpolation of a (n_t, m) series between samples k and k+1 at
    fraction ``frac``, written into ``out`` (no allocation per step).

    A C1 input does not kick the stiff bearing modes at every load sample the way linear
    interpolation's slope jumps do, which keeps results independent of the step.
    """
    n = series.shape[0]
    i0, i2, i3 = max(k - 1, 0), min(k + 1, n - 1), min(k + 2, n - 1)
    t = frac
    t2 = t * t
    t3 = t2 * t
    for c in range(series.shape[1]):
        p0, p1, p2, p3 = series[i0, c], series[k, c], series[i2, c], series[i3, c]
        out[c] = 0.5 * ((2.0 * p1) + (-p0 + p2) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2
                        + (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * t3)


@njit(cache=True, inline="always")
def _evaluate(q, qd, t, step, ctx, m, f, kt, ct, y, ch, jac, vel):  # pragma: no cover (compiled)
    """The single-body kernel as a kind of :mod:`ddgsa.mbs.alpha`'s loop: the inputs interpolated
    at step ``step`` (``n_sub`` steps a load sample), :func:`terms_into` written into the loop's
    arrays, the spring forces and the torque as the outputs ``y``."""
    inputs, n_sub, torque0, row, fs, lg, sys = ctx
    _interp_into(inputs, step // n_sub, (step % n_sub) / n_sub, row)
    torque = terms_into(q, qd, row[0:3], row[3:6], row[6], torque0, row[7:10], row[10:13], *sys, m, f, kt, ct, fs, lg)
    ns = fs.shape[0]
    for s in range(ns):
        for d in range(3):
            y[3 * s + d] = fs[s, d]
    y[3 * ns] = torque


_loop = specialise(_evaluate, "single_body")
_static = compiled_statics(_evaluate, "single_body")


def integrate(sys: SystemArrays, q0: NDArray[np.float64], qd0: NDArray[np.float64], dt_load: float,
              n_sub: int, forces: NDArray[np.float64], moments: NDArray[np.float64], w_set: NDArray[np.float64],
              torque0: float = 0.0, bp_disp: NDArray[np.float64] | None = None,
              bp_vel: NDArray[np.float64] | None = None, rho_inf: float = 0.8, tol: float = 1e-6,
              max_iter: int = 25) -> dict[str, NDArray[np.float64] | int]:
    """Generalised-alpha time integration over a load record.

    Parameters
    ----------
    q0, qd0 : initial coordinates and velocities
    dt_load : float
        Sampling interval of the inputs and outputs [s].
    n_sub : int
        Integration steps per load interval (step ``h = dt_load / n_sub``); inputs are
        interpolated by C1 cubics (Catmull-Rom) within an interval.
    forces, moments : (n_t, 3)
        Force [N] and moment [N m] at the load point, global frame.
    w_set : (n_t,)
        Torque-law set speed [rad/s].
    torque0 : float
        Constant torque added to the torque law [N m].
    bp_disp, bp_vel : (n_t, 3), optional
        Prescribed-body translation [m] and velocity [m/s] (zero by default).
    rho_inf : float
        Spectral radius at infinite frequency (1: no numerical dissipation).
    tol : float
        Newton stops when the coordinate correction is below ``tol`` (m or rad). The default
        1e-6 takes one iteration a step with the extrapolating predictor (1.002 on average on the
        600 s bench scene) where 1e-10 took 3 (2.3-2.9x faster); the direct drive's
        objective functions move by <= 1e-5 relative and stay 0.18-0.34 % from
        ``solve_ivp(Radau, rtol 1e-6)`` at 6, 11 and 18 m/s (measured, 60 s scenes).

    Returns
    -------
    dict
        ``q``, ``qd`` (n_t, n), ``spring_forces`` (n_t, n_s, 3), ``torque`` (n_t,) at the load
        samples, ``max_iterations`` (worst Newton count), ``mean_iterations`` (Newton iterations
        per step) and ``failed_at`` (sample index of a divergence, or -1).
    """
    n_t = forces.shape[0]
    zeros = np.zeros((n_t, 3))
    bd = zeros if bp_disp is None else np.ascontiguousarray(bp_disp, dtype=float)
    bv = zeros if bp_vel is None else np.ascontiguousarray(bp_vel, dtype=float)
    inputs = np.column_stack([forces, moments, w_set, bd, bv]).astype(float)     # (n_t, 13)
    q0, qd0 = np.asarray(q0, dtype=float), np.asarray(qd0, dtype=float)
    m, f, *_ = evaluate_terms(sys, q0, qd0, inputs[0, 0:3], inputs[0, 3:6], inputs[0, 6], torque0, inputs[0, 7:10],
                              inputs[0, 10:13])
    n, ns, n_sub = q0.size, sys.sp_k.shape[0], int(n_sub)
    ctx = (inputs, n_sub, float(torque0), np.empty(13), np.empty((ns, 3)), np.empty((ns + 1, 3, n)), sys.args())
    q, qd, _, y, _, status, total = _loop(ctx, q0, qd0, np.linalg.solve(m, f), np.zeros(0), 0.0,
                                          float(dt_load) / n_sub, (n_t - 1) * n_sub, n_sub,
                                          *coefficients(float(rho_inf)), float(tol), int(max_iter), 0, 3 * ns + 1,
                                          True, True, False)
    n_steps = max(1, (n_t - 1) * n_sub)
    return {"q": q, "qd": qd, "spring_forces": y[:, :3 * ns].reshape(-1, ns, 3), "torque": y[:, 3 * ns],
            "max_iterations": max(int(status), 0), "mean_iterations": total / n_steps,
            "failed_at": (-int(status) - 1) // n_sub + 1 if status < 0 else -1}


def evaluate_terms(sys: SystemArrays, q: NDArray[np.float64], qd: NDArray[np.float64],
                   force: NDArray[np.float64], moment: NDArray[np.float64], w_set: float, torque0: float = 0.0,
                   bp_disp: NDArray[np.float64] | None = None, bp_vel: NDArray[np.float64] | None = None) -> tuple:
    """Python entry to :func:`terms` (M, Q, K_t, C_t, spring forces, torque) at one state."""
    z = np.zeros(3)
    return terms(np.asarray(q, float), np.asarray(qd, float), np.asarray(force, float), np.asarray(moment, float),
                 float(w_set), float(torque0), z if bp_disp is None else bp_disp, z if bp_vel is None else bp_vel,
                 *sys.args())


def static_state(sys: SystemArrays, force: NDArray[np.float64], moment: NDArray[np.float64], torque0: float = 0.0,
                 q_guess: NDArray[np.float64] | None = None, tol: float = 1e-12,
                 max_iter: int = 50) -> NDArray[np.float64]:
    """Static equilibrium under a constant ``force`` [N] and ``moment`` [N m] at the load point,
    gravity and the torque law's constant ``torque0`` [N m], with the spin angle (coordinate 3)
    held at its guess (the torque law balances the torque; the angle is cyclic).

    The kernel's statics (:mod:`ddgsa.mbs.statics`) compiled for this kind, with the tangent
    stiffness ``K_t`` of :func:`terms` from ``q_guess`` (zero by default), converged when the largest
    coordinate update is below ``tol`` (m or rad); one compiled call. Raises
    :class:`~ddgsa.errors.ModelError` when ``max_iter`` iterations do not converge.
    """
    n, ns = sys.n_dof, sys.sp_k.shape[0]
    q = np.zeros(n) if q_guess is None else np.asarray(q_guess, dtype=float)
    return solve(_static, kind_context(sys, force, moment, 0.0, torque0), q, 0.0, (3,), tol, max_iter, 0, 0,
                 3 * ns + 1, True)[0]


def kind_context(sys: SystemArrays, force: NDArray[np.float64], moment: NDArray[np.float64], w_set: float = 0.0,
                 torque0: float = 0.0) -> tuple:
    """The single-body kernel's context as a kind (:func:`_evaluate`) under constant inputs: ``force`` [N] and
    ``moment`` [N m] at the load point, the torque law's set speed ``w_set`` [rad/s] and constant ``torque0``
    [N m] (its statics, its linearisation: :func:`ddgsa.mbs.modal.kind_jacobians` with :data:`kind`)."""
    n, ns = sys.n_dof, sys.sp_k.shape[0]
    row = np.zeros(13)
    row[0:3], row[3:6], row[6] = force, moment, w_set
    return (np.stack([row, row]), 1, float(torque0), np.empty(13), np.empty((ns, 3)), np.empty((ns + 1, 3, n)),
            sys.args())


kind = _evaluate
"""The single-body kernel as a kind of :mod:`ddgsa.mbs.alpha`'s loops (with :func:`kind_context`)."""


def integrate_reference(sys: SystemArrays, q0: NDArray[np.float64], qd0: NDArray[np.float64], times: NDArray[np.float64],
                        forces: NDArray[np.float64], moments: NDArray[np.float64], w_set: NDArray[np.float64],
                        torque0: float = 0.0, method: str = "Radau", rtol: float = 1e-6,
                        atol: float = 1e-9) -> dict[str, NDArray[np.float64]]:
    """The same equations by scipy ``solve_ivp`` (:func:`ddgsa.mbs.ivp.first_order`, the
    same C1 cubic load interpolation).

    Returns ``q``, ``qd``, ``spring_forces`` and ``torque`` at ``times`` and the solver's ``nfev``.
    """
    inputs = np.column_stack([forces, moments, w_set])
    dt = times[1] - times[0]
    row = np.empty(inputs.shape[1])

    def acceleration(t: float, q: NDArray[np.float64], qd: NDArray[np.float64]) -> NDArray[np.float64]:
        k = min(int((t - times[0]) / dt), times.size - 2)
        _interp_into(inputs, k, (t - times[k]) / dt, row)
        m, f, *_ = evaluate_terms(sys, q, qd, row[0:3], row[3:6], float(row[6]), torque0)
        return np.linalg.solve(m, f)

    q, qd, nfev = first_order(acceleration, q0, qd0, times, method, rtol, atol)
    at_samples = [evaluate_terms(sys, q[i], qd[i], forces[i], moments[i], w_set[i], torque0)
                  for i in range(times.size)]
    return {"q": q, "qd": qd, "spring_forces": np.stack([t[4] for t in at_samples]),
            "torque": np.array([t[5] for t in at_samples]), "nfev": nfev, "failed_at": -1}


def single_body_arrays(system: System) -> SystemArrays:
    """The arrays of this module's compiled single-body kernel for a :class:`~ddgsa.mbs.assembly.System`
    of that shape (how the direct drive is written on the kernel's parts).

    The System must hold one :class:`~ddgsa.mbs.bodies.FlexibleBody` (FE shaft), global-frame
    :class:`~ddgsa.mbs.elements.SpringDamper3` elements from it to ground or prescribed-body
    markers (the bearings to the bedplate, whose motion the integrators take as an input), one
    :class:`~ddgsa.mbs.elements.AppliedLoad` marker (where the force and moment inputs act) and one
    :class:`~ddgsa.mbs.elements.TorqueLaw.linear` (its damping ``c``; ``torque0`` and the set speed
    are inputs), and no constraints. Anything else raises :class:`~ddgsa.errors.ModelError`.
    """
    if len(system.bodies) != 1 or not isinstance(system.bodies[0], FlexibleBody) or system.constraints:
        raise ModelError("the single-body kernel runs one FlexibleBody on elements, without constraints")
    body = system.bodies[0]
    pm, pu, ps = body.points
    springs = [e for e in system.elements if isinstance(e, SpringDamper3)]
    loads = [e for e in system.elements if isinstance(e, AppliedLoad)]
    laws = [e for e in system.elements if isinstance(e, TorqueLaw)]
    if len(loads) != 1 or len(laws) != 1 or laws[0].linear_form is None or \
            len(springs) + 2 != len(system.elements):
        raise ModelError("the single-body kernel needs SpringDamper3 bearings, one AppliedLoad and one "
                         "TorqueLaw.linear, nothing else")
    for s in springs:
        if s.frame != "global" or s.markers[0].body is not body or s.markers[1].body.n_coords:
            raise ModelError(f"spring {s.name!r}: the single-body kernel needs global-frame springs from the "
                             "body to a ground or prescribed marker")
    load, law = loads[0].markers[0], laws[0].markers[0]
    arrays = SystemArrays(
        pm=pm, pu=pu, ps=ps, gravity=system.gravity.copy(), kff=np.array(body.kff), cff=np.array(body.cff),
        sp_u0=np.array([s.markers[0].position for s in springs]), sp_s=np.stack([s.markers[0].shapes for s in springs]),
        sp_k=np.array([np.diag(s.k6)[:3] for s in springs]), sp_c=np.array([np.diag(s.c6)[:3] for s in springs]),
        sp_ground=np.array([s.markers[1].body.marker_state(s.markers[1], np.zeros(0), np.zeros(0), 0.0)[0]
                            for s in springs]),
        ld_u0=load.position.copy(), ld_s=load.shapes.copy(), ld_srot=load.rotation_shapes.copy(),
        gn_srot=law.rotation_shapes.copy(), c_torque=laws[0].linear_form[1])
    arrays.__dict__["invariants"] = body.invariants      # computed once, by the body (cached property)
    # kff and cff are copied: a body's matrices may be read-only (a shaft's own) or not (scaled), and numba
    # compiles the whole kernel once per read-only flag of each argument
    return arrays
