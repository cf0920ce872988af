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
``K``. :func:`simulate_lti` integrates the first-order form exactly for inputs cubic between
samples (the integrators' C1 interpolation; one matrix exponential).
"""

from __future__ import annotations

from dataclasses import dataclass
from math import comb

import numpy as np
from numpy.typing import NDArray
from numba import njit
from scipy.linalg import expm

from ddgsa.mbs.system import SystemArrays, evaluate_terms


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


def _rot_pairs(xi: NDArray[np.float64], pairs: list[tuple[int, int]]) -> NDArray[np.float64]:
    """``J xi``: the 90-degree rotation applied to each (y, z) pair, zero elsewhere."""
    out = np.zeros_like(xi)
    for iy, iz in pairs:
        out[iy], out[iz] = -xi[iz], xi[iy]
    return out


def body_state(p: NDArray[np.float64], v: NDArray[np.float64], a: NDArray[np.float64],
               pairs: list[tuple[int, int]]) -> tuple[NDArray[np.float64], ...]:
    """Body coordinates, velocities and accelerations at spin angle 0 from the non-rotating ones."""
    xi, xid, xidd = p[5:], v[6:], a[6:]
    w, wd = v[3], a[3]
    q = np.concatenate([p[:3], [0.0], p[3:5], xi])
    qd = np.concatenate([v[:6], xid - w * _rot_pairs(xi, pairs)])
    jxi, jxid = _rot_pairs(xi, pairs), _rot_pairs(xid, pairs)
    qdd = np.concatenate([a[:6], xidd - 2 * w * jxid - wd * jxi + w * w * _rot_pairs(jxi, pairs)])
    return q, qd, qdd


def residual(sys: SystemArrays, p: NDArray[np.float64], v: NDArray[np.float64], a: NDArray[np.float64],
             u: NDArray[np.float64], pairs: list[tuple[int, int]]) -> NDArray[np.float64]:
    """``M q_ddot - Q`` of the nonlinear system in non-rotating coordinates (spin angle 0)."""
    q, qd, qdd = body_state(p, v, a, pairs)
    m, f, *_ = evaluate_terms(sys, q, qd, u[0:3], u[3:6], float(u[6]))
    return m @ qdd - f


def linearise_spinning(sys: SystemArrays, p0: NDArray[np.float64], spin: float, u0: NDArray[np.float64],
                       pairs: list[tuple[int, int]], rel_step: float = 1e-6) -> LinearSystem:
    """Central-difference linearisation of :func:`residual` about ``(p0, spin, u0)`` (see the module)."""
    n = p0.size + 1
    v0 = np.zeros(n)
    v0[3] = spin
    a0 = np.zeros(n)
    r0 = -residual(sys, p0, v0, a0, u0, pairs)

    def res(p: NDArray[np.float64], v: NDArray[np.float64], a: NDArray[np.float64],
            u: NDArray[np.float64]) -> NDArray[np.float64]:
        return residual(sys, p, v, a, u, pairs)

    args = [p0, v0, a0, u0]
    k = central_jacobian(res, args, 0, 1e-3, rel_step)
    c = central_jacobian(res, args, 1, 1e-3, rel_step)
    m = central_jacobian(res, args, 2, 1.0, rel_step)
    b = -central_jacobian(res, args, 3, 1.0, rel_step)
    return LinearSystem(m, c, k, b, r0, p0, v0, u0)


def state_matrices(lin: LinearSystem) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """First-order form ``x_dot = A x + B_w w`` with ``x = [dp, dv]`` and ``w = [du, 1]``."""
    nq, npos = lin.k.shape
    minv = np.linalg.inv(lin.m)
    # dp_dot = T dv: positions skip the spin angle, velocities include its rate
    t = np.zeros((npos, nq))
    t[:3, :3] = np.eye(3)
    t[3:, 4:] = np.eye(npos - 3)
    a = np.block([[np.zeros((npos, npos)), t], [-minv @ lin.k, -minv @ lin.c]])
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


def catmull_rom_coefficients(w: NDArray[np.float64]) -> list[NDArray[np.float64]]:
    """Cubic coefficients ``c_0..c_3`` per interval (n_t - 1, k) of the C1 interpolant the integrators use."""
    n = w.shape[0]
    idx = np.arange(n - 1)
    p0, p1 = w[np.maximum(idx - 1, 0)], w[idx]
    p2, p3 = w[idx + 1], w[np.minimum(idx + 2, n - 1)]
    return [p1, 0.5 * (p2 - p0), 0.5 * (2 * p0 - 5 * p1 + 4 * p2 - p3), 0.5 * (-p0 + 3 * p1 - 3 * p2 + p3)]


def simulate_lti(lin: LinearSystem, u: NDArray[np.float64], dt: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Positions and velocities (absolute, ``p0 + dp``, ``v0 + dv``) for input samples ``u`` (n_t, 7).

    Inputs between samples follow the same C1 cubic (Catmull-Rom) the nonlinear integrators
    see, integrated exactly (:func:`discretise_cubic`). Starts from the quasi-static state of
    the first sample (``K dp = B du0 + r0``, ``dv = 0``).
    """
    a, bw = state_matrices(lin)
    npos = lin.k.shape[1]
    w = np.column_stack([u - lin.u0, np.ones(len(u))])
    dp0 = np.linalg.lstsq(lin.k, lin.b @ w[0, :-1] + lin.r0, rcond=None)[0]
    out = lti_response(a, bw, w, dt, np.concatenate([dp0, np.zeros(lin.m.shape[0])]))
    return lin.p0 + out[:, :npos], lin.v0 + out[:, npos:]


def lti_response(a: NDArray[np.float64], bw: NDArray[np.float64], w: NDArray[np.float64], dt: float,
                 x0: NDArray[np.float64], n_sub: int = 1) -> NDArray[np.float64]:
    """States of ``x_dot = A x + B_w w(t)`` for samples ``w`` (n_t, k) at spacing ``dt`` [s], exactly.

    ``w`` between samples is the C1 cubic (Catmull-Rom) interpolant; the states come back at
    ``n_sub`` points per sample interval (``(n_t - 1) n_sub + 1`` rows), each sub-interval's
    cubic re-expanded exactly, so a fine output grid costs no interpolation error.
    """
    phi, gains = discretise_cubic(a, bw, dt / n_sub)
    c = np.hstack(catmull_rom_coefficients(w))                       # (n_t - 1, 4 k)
    ns = a.shape[0]
    drive = np.empty((len(w) - 1, n_sub, ns))
    for m in range(n_sub):
        # w(k + (m + s)/n) as a cubic in s has coefficients d_i = sum_{j>=i} c_j C(j, i) m^(j-i) / n^j,
        # so the drive sum_i G_i d_i is one product with the stacked gains H_m
        h = np.vstack([sum(comb(j, i) * m ** (j - i) / n_sub ** j * gains[i].T for i in range(j + 1))
                       for j in range(4)])                            # (4 k, ns)
        drive[:, m] = c @ h
    drive = np.vstack([drive.reshape(-1, ns), np.zeros((1, ns))])
    return _recurrence(phi, drive, x0)


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


def spring_outputs(sys: SystemArrays, p: NDArray[np.float64], v: NDArray[np.float64], u: NDArray[np.float64],
                   pairs: list[tuple[int, int]]) -> NDArray[np.float64]:
    """Spring-damper forces (n_s x 3, flattened) of the nonlinear system at a non-rotating state."""
    q, qd, _ = body_state(p, v, np.zeros_like(v), pairs)
    return evaluate_terms(sys, q, qd, u[0:3], u[3:6], float(u[6]))[4].ravel()


def central_jacobian(fun, args: list[NDArray[np.float64]], which: int, scale: float,  # noqa: ANN001
                     rel_step: float = 1e-6) -> NDArray[np.float64]:
    """Central-difference Jacobian of ``fun(*args)`` with respect to ``args[which]``.

    The step of entry ``i`` is ``rel_step * max(scale, |x_i|)``.
    """
    x0 = args[which]
    cols = []
    for i in range(x0.size):
        h = rel_step * max(scale, abs(x0[i]))
        plus, minus = [a.copy() for a in args], [a.copy() for a in args]
        plus[which][i] += h
        minus[which][i] -= h
        cols.append((fun(*plus) - fun(*minus)) / (2 * h))
    return np.column_stack(cols)


def linearise_map(fun, lin: LinearSystem, rel_step: float = 1e-6) -> tuple[NDArray[np.float64], ...]:  # noqa: ANN001
    """Value and Jacobians of ``fun(p, v, u)`` at the operating point: ``(y0, dy/dp, dy/dv, dy/du)``."""
    args = [lin.p0, lin.v0, lin.u0]
    return (fun(*args), *(central_jacobian(fun, args, w, s, rel_step) for w, s in ((0, 1e-3), (1, 1e-3), (2, 1.0))))
