"""Linearisation of a spinning system about its operating point, and exact discretisation.

The body's bending coordinates live in the rotating body frame, where an axisymmetric shaft
on anisotropic (but non-rotating) bearings has time-periodic equations. Written in
**non-rotating** bending coordinates ``xi`` (``q_f = R(-phi) xi`` for each y/z pair of equal
shapes) the equations are time-invariant; the spin angle is cyclic and only its rate enters.
:func:`linearise_spinning` builds, by central differences of the full nonlinear residual,

``M dv_dot + C dv + K dp = B du + r0``

with positions ``p = [R, theta, psi, xi]`` (no spin angle), velocities
``v = [R_dot, phi_dot, theta_dot, psi_dot, xi_dot]`` and inputs ``u = [F (3), M (3), w_set]``:
gyroscopic and Coriolis terms at the operating spin are in ``C``, centrifugal softening in
``K``; the spring-damper forces are linearised in the same pass (:class:`LinearOutputs`).
:func:`lti_response` integrates the first-order form exactly for inputs cubic between
samples (the integrators' C1 interpolation; one matrix exponential).

Cost: the linearisation is one compiled call (``2 n + 6`` pairs of residual evaluations for
``n`` velocities; the acceleration Jacobian is the mass matrix);
the response is stepped at the load interval in **modal coordinates** ``x = V z`` of the
state matrix, where the recurrence is one complex multiply per mode and step (a conjugate
pair counted once) and only the requested outputs ``C x`` are formed; the dense
``x[k+1] = Phi x[k] + ...`` recurrence is kept for eigenvector bases too ill-conditioned to
trust (:data:`MAX_MODAL_CONDITION`). :func:`modal_step` gives the same step with each mode's
cubic-input gains in closed form (no matrix exponential) and takes the inputs as windows of
channels shared by many systems (a batch of parameter points of one scene), so that the drive of
every point is one product with the same window; it runs block by block (:data:`STEP_BLOCK`
samples), so the drive, the modal states and the outputs of a block never leave the core's cache.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol
from math import comb

import numpy as np
from numba import njit
from numpy.lib.stride_tricks import sliding_window_view
from numpy.typing import NDArray
from scipy.linalg import expm

from ddgsa.mbs.derivatives import central_difference
from ddgsa.mbs.series import CATMULL_ROM, _padded
from ddgsa.mbs.system import SystemArrays, terms

MAX_MODAL_CONDITION = 1e8
"""Condition number (1-norm) of the eigenvector matrix above which :func:`lti_response` steps the dense
recurrence instead of modal coordinates (modal round-off grows with it: 1e8 keeps ~1e-8 of 1e-16)."""


@dataclass(frozen=True)
class LinearSystem:
    """``M dv_dot + C dv + K dp = B du + r0`` about ``(p0, v0, u0)``."""

    m: NDArray[np.float64]
    c: NDArray[np.float64]
    k: NDArray[np.float64]
    b: NDArray[np.float64]
    r0: NDArray[np.float64]
    p0: NDArray[np.float64]
    v0: NDArray[np.float64]
    u0: NDArray[np.float64]

    @property
    def velocity_map(self) -> NDArray[np.float64]:
        """``T`` of ``dp_dot = T dv``: positions skip the spin angle, velocities include its rate."""
        nq, npos = self.k.shape
        t = np.zeros((npos, nq))
        t[:3, :3] = np.eye(3)
        t[3:, 4:] = np.eye(npos - 3)
        return t


@dataclass(frozen=True)
class LinearOutputs:
    """Spring-damper forces (n_s x 3, flattened, global frame [N]) linearised about the same point:
    ``y = y0 + d_p dp + d_v dv + d_u du``."""

    y0: NDArray[np.float64]
    d_p: NDArray[np.float64]
    d_v: NDArray[np.float64]
    d_u: NDArray[np.float64]


@njit(cache=True)
def _rot_pairs(xi, iy, iz):  # pragma: no cover (compiled)
    """``J xi``: the 90-degree rotation applied to each (y, z) pair, zero elsewhere."""
    out = np.zeros_like(xi)
    for k in range(iy.size):
        out[iy[k]] = -xi[iz[k]]
        out[iz[k]] = xi[iy[k]]
    return out


@njit(cache=True)
def _residual_and_springs(p, v, a, u, iy, iz, sys):  # pragma: no cover (compiled)
    """``M q_ddot - Q``, the spring forces and ``M`` at a non-rotating state (spin angle 0).

    Body coordinates from the non-rotating ones: ``q_f = xi``, ``q_f_dot = xi_dot - w J xi``,
    ``q_f_ddot = xi_ddot - 2 w J xi_dot - w_dot J xi + w^2 J J xi``.
    """
    n = v.size
    q, qd, qdd = np.zeros(n), np.zeros(n), np.zeros(n)
    q[0:3] = p[0:3]
    q[4:6] = p[3:5]
    q[6:] = p[5:]
    qd[:6] = v[:6]
    qdd[:6] = a[:6]
    w, wd = v[3], a[3]
    jxi = _rot_pairs(p[5:], iy, iz)
    jjxi = _rot_pairs(jxi, iy, iz)
    jxid = _rot_pairs(v[6:], iy, iz)
    qd[6:] = v[6:] - w * jxi
    qdd[6:] = a[6:] - 2.0 * w * jxid - wd * jxi + w * w * jjxi
    zero = np.zeros(3)
    m, f, _, _, fs, _ = terms(q, qd, u[0:3], u[3:6], u[6], 0.0, zero, zero, *sys)
    return m @ qdd - f, fs.ravel().copy(), m


@njit(cache=True)
def _residuals_and_springs(ps, vs, us, a0, iy, iz, sys):  # pragma: no cover (compiled)
    """:func:`_residual_and_springs` at each row of ``ps``, ``vs``, ``us`` (k, .) with the accelerations
    ``a0``: the residuals and the spring forces side by side (k, n + n_springs)."""
    out = np.empty((0, 0))
    for j in range(ps.shape[0]):
        r, fs, _ = _residual_and_springs(ps[j], vs[j], a0, us[j], iy, iz, sys)
        if j == 0:                                   # the first row's sizes set the table's
            out = np.empty((ps.shape[0], r.size + fs.size))
        out[j, :r.size] = r
        out[j, r.size:] = fs
    return out


def linearise_spinning(sys: SystemArrays, p0: NDArray[np.float64], spin: float, u0: NDArray[np.float64],
                       pairs: list[tuple[int, int]],
                       rel_step: float = 1e-6) -> tuple[LinearSystem, LinearOutputs]:
    """Central-difference linearisation about ``(p0, spin, u0)`` (see the module).

    Parameters
    ----------
    p0 : positions without the spin angle [m, rad]
    spin : operating spin rate [rad/s]
    u0 : inputs ``[F (3) [N], M (3) [N m], w_set [rad/s]]``
    pairs : elastic-coordinate indices ``(y, z)`` of equal bending shapes
    rel_step : relative finite-difference step

    Returns
    -------
    LinearSystem, LinearOutputs
        The equations of motion and the spring-damper forces, linearised.
    """
    n = p0.size + 1
    v0 = np.zeros(n)
    v0[3] = spin
    a0 = np.zeros(n)
    u0 = np.asarray(u0, dtype=float)
    iy = np.array([i for i, _ in pairs], dtype=np.int64)
    iz = np.array([j for _, j in pairs], dtype=np.int64)
    args = sys.args()
    r_base, y0, m = _residual_and_springs(p0, v0, a0, u0, iy, iz, args)
    base = (p0, v0, u0)

    def over(which: int, scale: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The residual's and the spring forces' Jacobians over ``p``, ``v`` or ``u`` (``which`` 0, 1, 2)."""
        def batch(x: NDArray[np.float64]) -> NDArray[np.float64]:
            rows = [x if k == which else np.tile(b, (len(x), 1)) for k, b in enumerate(base)]
            return _residuals_and_springs(*rows, a0, iy, iz, args)

        jac = central_difference(batch, base[which], scale, rel_step)
        return jac[:n], jac[n:]

    jac = {0: over(0, 1e-3), 1: over(1, 1e-3), 3: over(2, 1.0)}
    # the residual is linear in the accelerations: d/da = M d(q_ddot)/da, exactly, where the spin
    # acceleration (a[3]) enters the body's elastic accelerations as -J xi
    m_a = m.copy()
    m_a[:, 3] -= m[:, 6:] @ _rot_pairs(p0[5:], iy, iz)
    lin = LinearSystem(m=m_a, c=jac[1][0], k=jac[0][0], b=-jac[3][0], r0=-r_base, p0=p0, v0=v0, u0=u0)
    return lin, LinearOutputs(y0=y0, d_p=jac[0][1], d_v=jac[1][1], d_u=jac[3][1])


class SecondOrder(Protocol):
    """A linearisation ``M v_dot + C v + K p = B u + r0``, ``p_dot = T v`` (what :func:`state_matrices` reads)."""

    m: NDArray[np.float64]
    c: NDArray[np.float64]
    k: NDArray[np.float64]
    r0: NDArray[np.float64]

    @property
    def b(self) -> NDArray[np.float64]: ...

    @property
    def velocity_map(self) -> NDArray[np.float64]: ...


def state_matrices(lin: SecondOrder) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """First-order form ``x_dot = A x + B_w w`` with ``x = [p, v]`` and ``w = [u, 1]``: the one
    first-order form of every linearisation (:class:`LinearSystem` of the single-body kernel,
    :class:`~ddgsa.mbs.modal.ConstrainedLinearisation` of any System)."""
    npos = lin.k.shape[1]
    minv = np.linalg.inv(lin.m)
    a = np.block([[np.zeros((npos, npos)), lin.velocity_map], [-minv @ lin.k, -minv @ lin.c]])
    bw = np.vstack([np.zeros((npos, lin.b.shape[1] + 1)), minv @ np.column_stack([lin.b, lin.r0])])
    return a, bw


def discretise_cubic(a: NDArray[np.float64], bw: NDArray[np.float64],
                     dt: float) -> tuple[NDArray[np.float64], list[NDArray[np.float64]]]:
    """Exact step for inputs cubic in time: ``x[k+1] = Phi x[k] + sum_j G_j c_j`` with
    ``w(t_k + s dt) = sum_j c_j s^j``, ``G_j = dt int_0^1 e^(A dt (1-s)) B s^j ds``.

    One matrix exponential of the chain ``[[A dt, B dt, 0..], [0, 0, I, ..], ...]``: its block
    (0, j+1) is ``dt int e^(A dt (1-s)) B s^j / j! ds`` (Van Loan).
    """
    ns, ni = a.shape[0], bw.shape[1]
    size = ns + 4 * ni
    big = np.zeros((size, size))
    big[:ns, :ns] = a * dt
    big[:ns, ns:ns + ni] = bw * dt
    for j in range(3):
        big[ns + j * ni:ns + (j + 1) * ni, ns + (j + 1) * ni:ns + (j + 2) * ni] = np.eye(ni)
    e = expm(big)
    factorial = (1.0, 1.0, 2.0, 6.0)
    return e[:ns, :ns], [factorial[j] * e[:ns, ns + j * ni:ns + (j + 1) * ni] for j in range(4)]


def initial_state(lin: LinearSystem, w0: NDArray[np.float64]) -> NDArray[np.float64]:
    """``x0 = [dp0, 0]``: the quasi-static state ``K dp0 = B du0 + r0`` for the first input sample
    ``w0 = [du0, 1]``."""
    dp0 = np.linalg.lstsq(lin.k, lin.b @ w0[:-1] + lin.r0, rcond=None)[0]
    return np.concatenate([dp0, np.zeros(lin.m.shape[0])])


def _window_gains(gains: list[NDArray[np.float64]], m: int, n_sub: int) -> NDArray[np.float64]:
    """``H`` (4 k, ns): the drive of sub-interval ``m`` of interval k is ``window_k @ H`` with
    ``window_k[4 c + l] = w[k - 1 + l, c]`` (the four samples around the interval, channel-major).

    ``w(k + (m + s)/n)`` as a cubic in s has coefficients ``d_i = sum_{j>=i} c_j C(j, i) m^(j-i) / n^j``
    and ``c_j = sum_l CATMULL_ROM[j, l] w[k - 1 + l]``, so the drive ``sum_i G_i d_i`` is a
    four-tap filter of the samples: one product with a (n_t - 1, 4 k) window view, no table of
    cubic coefficients."""
    per_c = [sum(comb(j, i) * m ** (j - i) / n_sub ** j * gains[i].T for i in range(j + 1)) for j in range(4)]
    taps = [sum(CATMULL_ROM[j, l] * per_c[j] for j in range(4)) for l in range(4)]          # (k, ns) each
    return np.stack(taps, axis=1).reshape(-1, taps[0].shape[1])


def _drive(w: NDArray[np.float64], gains: list[NDArray[np.float64]], n_sub: int,
           basis: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """Drive rows ((n_t - 1) n_sub + 1, .) of the recurrence, the last one zero; ``basis`` maps the
    state drive to other coordinates (``drive @ basis``)."""
    n = w.shape[0] - 1
    window = input_window(w)
    h0 = _window_gains(gains, 0, n_sub)
    width = h0.shape[1] if basis is None else basis.shape[1]
    drive = np.zeros((n * n_sub + 1, width))
    for m in range(n_sub):
        h = h0 if m == 0 else _window_gains(gains, m, n_sub)
        drive[m:n * n_sub:n_sub] = window @ (h if basis is None else h @ basis)
    return drive


def lti_response(a: NDArray[np.float64], bw: NDArray[np.float64], w: NDArray[np.float64], dt: float,
                 x0: NDArray[np.float64], n_sub: int = 1,
                 c_out: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """States (or outputs ``c_out x``) of ``x_dot = A x + B_w w(t)`` for samples ``w`` (n_t, k) at
    spacing ``dt`` [s], exactly.

    ``w`` between samples is the C1 cubic (Catmull-Rom) interpolant; the states come back at
    ``n_sub`` points per sample interval (``(n_t - 1) n_sub + 1`` rows), each sub-interval's
    cubic re-expanded exactly, so a fine output grid costs no interpolation error. Stepped in
    modal coordinates when the eigenvectors of ``A`` are well conditioned (see the module).
    """
    phi, gains = discretise_cubic(a, bw, dt / n_sub)
    c_out = np.eye(a.shape[0]) if c_out is None else np.asarray(c_out, dtype=float)
    basis = modal_basis(a)
    if basis is None:
        return _recurrence(phi, _drive(w, gains, n_sub), x0) @ c_out.T
    lam, vec, vinv = basis
    drive = _drive(w, gains, n_sub, np.hstack([vinv.real.T, vinv.imag.T]))     # [Re | Im] of the modal drive
    z = _modal_recurrence(np.exp(lam * dt / n_sub), drive, vinv @ x0)          # [Re | Im] of z
    return z @ modal_output_matrix(vec, lam, c_out)


def modal_basis(a: NDArray[np.float64]) -> tuple[NDArray[np.complex128], NDArray[np.complex128],
                                                  NDArray[np.complex128]] | None:
    """Eigenvalues, eigenvectors (ns, m) and the matching rows of the inverse (m, ns) of ``A``,
    one mode of each conjugate pair and every real one; None when the eigenvector matrix is too
    ill-conditioned to step in modal coordinates (:data:`MAX_MODAL_CONDITION`)."""
    lam, vec = np.linalg.eig(a)
    try:
        inv = np.linalg.inv(vec)
    except np.linalg.LinAlgError:
        return None
    # 1-norm condition from the inverse the modal step needs anyway (an SVD for the 2-norm one
    # cost as much as the eigen-decomposition); the two are within a factor ns of each other
    if np.linalg.norm(vec, 1) * np.linalg.norm(inv, 1) > MAX_MODAL_CONDITION:
        return None
    keep = lam.imag >= 0.0
    return lam[keep], vec[:, keep], inv[keep]


def modal_output_matrix(vec: NDArray[np.complex128], lam: NDArray[np.complex128],
                        c_out: NDArray[np.float64]) -> NDArray[np.float64]:
    """``(2 m, n_out)``: outputs ``c_out x`` from ``[Re z | Im z]`` (``x = sum_real v z +
    sum_pairs 2 Re(v z)``)."""
    cm = (c_out @ vec) * np.where(lam.imag > 0.0, 2.0, 1.0)
    return np.vstack([cm.real.T, -cm.imag.T])


@dataclass(frozen=True)
class ModalStep:
    """The exact one-sample step of ``x_dot = A x + B_w w(t)`` in modal coordinates, for inputs
    given as windows of their four samples around each interval (:func:`input_window`).

    ``z[k+1] = mu z[k] + window[k] @ taps`` (``z`` as ``[Re | Im]``), ``x = V z``.

    Attributes
    ----------
    mu : (m,) complex
        ``exp(lambda dt)`` of the kept modes.
    taps : (4 k, 2 m)
        Drive of ``[Re z | Im z]`` from the input window (channel-major, :func:`_window_gains`).
    vec, vinv : (ns, m), (m, ns) complex
        Kept eigenvectors and the matching rows of the inverse.
    lam : (m,) complex
        Kept eigenvalues [1/s].
    """

    mu: NDArray[np.complex128]
    taps: NDArray[np.float64]
    vec: NDArray[np.complex128]
    vinv: NDArray[np.complex128]
    lam: NDArray[np.complex128]

    def outputs(self, window: NDArray[np.float64], x0: NDArray[np.float64], out: NDArray[np.float64],
                channel_map: NDArray[np.float64] | None = None,
                constant: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
        """Outputs (n_t, n_out) from the input ``window`` (n_t - 1, 4 k) (:func:`input_window`), the
        initial state ``x0`` and the output matrix ``out`` (2 m, n_out) of :func:`modal_output_matrix`.

        With ``channel_map`` (k_c, k) the window is that of channels ``c`` (n_t, k_c) with inputs
        ``w = c @ channel_map (+ constant)``: the taps are mapped instead of the samples, so inputs
        that are linear in channels shared by many systems need one window for all. ``constant``
        (k,): a part of the inputs that does not change in time, whose drive is the same every step
        (added in the recurrence, not a channel of the window).
        """
        taps = self.taps
        k = taps.shape[0] // 4
        if channel_map is not None:
            taps = np.einsum("dc,clm->dlm", channel_map, taps.reshape(k, 4, -1)).reshape(-1, taps.shape[1])
        steady = np.zeros(taps.shape[1]) if constant is None else constant @ self.taps.reshape(k, 4, -1).sum(axis=1)
        # column-major (n_t, n_out): each output's series contiguous
        return _modal_outputs(np.ascontiguousarray(window), np.ascontiguousarray(taps), self.mu, self.vinv @ x0,
                              steady, np.ascontiguousarray(out.T), STEP_BLOCK)


def modal_step(a: NDArray[np.float64], bw: NDArray[np.float64], dt: float) -> ModalStep | None:
    """:class:`ModalStep` of ``x_dot = A x + B_w w`` for the sample interval ``dt`` [s] (inputs the C1
    cubic of their samples, as :func:`lti_response`); None where :func:`modal_basis` refuses."""
    basis = modal_basis(a)
    if basis is None:
        return None
    lam, vec, vinv = basis
    # per mode the cubic's gains are scalars: g_j = dt int_0^1 e^(lam dt (1-s)) s^j ds (no matrix exponential)
    per_tap = dt * CATMULL_ROM.T @ _cubic_integrals(lam * dt)                # (4 taps, m)
    modal_b = (vinv @ bw).T                                                  # (k, m)
    taps = (modal_b[:, None, :] * per_tap[None, :, :]).reshape(-1, lam.size)  # rows 4 c + l, channel-major
    return ModalStep(np.exp(lam * dt), np.hstack([taps.real, taps.imag]), vec, vinv, lam)


def _cubic_integrals(x: NDArray[np.complex128]) -> NDArray[np.complex128]:
    """``I_j(x) = int_0^1 e^(x (1-s)) s^j ds`` for j = 0..3, shape (4, len(x)).

    ``|x| >= 1``: ``I_0 = (e^x - 1)/x``, ``I_j = (j I_(j-1) - 1)/x`` (by parts; round-off grows
    by at most ``j/|x|`` a step); ``|x| < 1``: the series ``sum_n x^n j! / (j + n + 1)!`` (20 terms:
    the last is below 1e-18 of the first). Compiled: a point's dozen modes cost ~40 numpy calls
    otherwise (~0.1 ms, 3 % of a linear point)."""
    x = np.asarray(x, dtype=np.complex128).ravel()
    return _cubic_integrals_compiled(x, np.expm1(x))


@njit(cache=True)
def _cubic_integrals_compiled(x, em1):  # pragma: no cover (compiled)
    """:func:`_cubic_integrals` with ``em1 = expm1(x)`` (numpy's, accurate near 0)."""
    out = np.empty((4, x.size), dtype=np.complex128)
    for r in range(x.size):
        xr = x[r]
        if abs(xr) >= 1.0:
            out[0, r] = em1[r] / xr
            for j in range(1, 4):
                out[j, r] = (j * out[j - 1, r] - 1.0) / xr
        else:
            for j in range(4):
                term = 1.0 / (j + 1.0) + 0.0j
                total = term
                for n in range(20):
                    term = term * (xr / (j + n + 2.0))
                    total += term
                out[j, r] = total
    return out


def input_window(w: NDArray[np.float64]) -> NDArray[np.float64]:
    """``(n_t - 1, 4 k)``: the four samples around each interval of ``w`` (n_t, k), channel-major
    (end samples repeated), the rows :attr:`ModalStep.taps` multiplies."""
    n = w.shape[0] - 1
    return sliding_window_view(_padded(w), 4, axis=0)[:n].reshape(n, -1)


@njit(cache=True)
def _modal_recurrence(mu, drive, z0):  # pragma: no cover (compiled)
    """``z[k+1] = mu z[k] + drive[k]`` per mode from ``z0``; ``drive`` and the result hold the real
    parts in the first half of the columns and the imaginary parts in the second."""
    n, m = drive.shape[0], mu.size
    out = np.empty((n, 2 * m))
    zr, zi = z0.real.copy(), z0.imag.copy()
    mr, mi = mu.real.copy(), mu.imag.copy()
    for i in range(n):
        for r in range(m):
            out[i, r] = zr[r]
            out[i, m + r] = zi[r]
            re = mr[r] * zr[r] - mi[r] * zi[r] + drive[i, r]
            zi[r] = mr[r] * zi[r] + mi[r] * zr[r] + drive[i, m + r]
            zr[r] = re
    return out


STEP_BLOCK = 512
"""Steps per block of :meth:`ModalStep.outputs`: a block's window rows, drive and modal states
(~0.3 MB) stay in the core's cache between the drive product, the recurrence and the output
product (one pass of each over the whole record streamed ~10 MB through memory: 25 % slower)."""


@njit(cache=True)
def _modal_outputs(window, taps, mu, z0, steady, out_t, block):  # pragma: no cover (compiled)
    """:meth:`ModalStep.outputs` block by block: ``drive = window @ taps`` (BLAS), ``z[k+1] = mu z[k] +
    drive[k] + steady``, ``y = out_t @ z`` (BLAS). ``z`` as ``[Re | Im]``; returns (n_t, n_out),
    column-major."""
    n = window.shape[0] + 1
    m2 = taps.shape[1]
    m = m2 // 2
    y = np.empty((out_t.shape[0], n))
    z = np.empty(m2)
    z[:m] = z0.real
    z[m:] = z0.imag
    mr, mi = mu.real.copy(), mu.imag.copy()
    drive = np.empty((block, m2))
    zb = np.empty((block, m2))
    for start in range(0, n, block):
        stop = min(start + block, n)
        driven = min(stop, n - 1) - start               # the last sample has no interval after it
        if driven > 0:
            drive[:driven] = np.dot(window[start:start + driven], taps)
        for i in range(stop - start):
            for r in range(m2):
                zb[i, r] = z[r]
            if i < driven:
                for r in range(m):
                    re = mr[r] * z[r] - mi[r] * z[m + r] + (drive[i, r] + steady[r])
                    z[m + r] = mr[r] * z[m + r] + mi[r] * z[r] + (drive[i, m + r] + steady[m + r])
                    z[r] = re
        y[:, start:stop] = np.dot(out_t, zb[:stop - start].T)
    return y.T


@njit(cache=True)
def _recurrence(phi, drive, x0):  # pragma: no cover (compiled)
    """``x[k+1] = Phi x[k] + drive[k]`` from ``x0``."""
    n, m = drive.shape
    out = np.empty((n, m))
    x = x0.copy()
    for i in range(n):
        out[i] = x
        nxt = drive[i].copy()
        for r in range(m):
            acc = 0.0
            for c in range(m):
                acc += phi[r, c] * x[c]
            nxt[r] += acc
        x = nxt
    return out
