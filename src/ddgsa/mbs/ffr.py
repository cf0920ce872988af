"""Floating-frame-of-reference (FFR) body with lumped mass points, in compiled kernels.

Generalised coordinates of a body: ``q = [R (3), angles (3), q_f (n_f)]``. The rotation is
``A = R_Z(psi) R_Y(theta) R_X(phi)`` with angles ``(phi, theta, psi)``: the spin ``phi`` about
the body x axis (the shaft axis) acts first, so tilting or yawing of the shaft axis
(``theta``, ``psi``) does not oscillate with the spin (singular only at ``theta = +-90 deg``).
Body components of the angular velocity are ``w_bar = G_bar(angles) angles_dot``.

The body is a set of mass points ``j`` with mass ``m_j``, undeformed body-frame position
``u0_j`` and shape matrix ``S_j`` (3 x n_f): ``u_j = u0_j + S_j q_f`` (seed 000 eq. 2; the
lumped form of App. 6.1, ``M ~ sum_j m_j ...``). With ``L_j = A [A^T, -u~_j G_bar, S_j]``
(``r_dot_j = L_j q_dot``) the mass matrix is ``sum m_j L_j^T L_j`` and the quadratic velocity
vector ``-sum m_j L_j^T gamma_j`` with the body-frame velocity-quadratic acceleration
``gamma_j = (G_bar_dot angles_dot) x u_j + w x (w x u_j) + 2 w x (S_j q_f_dot)`` (centrifugal,
gyroscopic and Coriolis terms, App. 6.7). Rigid inertias (rotor hub, generator rotor) are
represented exactly by six points on their principal axes plus one at the centre
(:func:`inertia_points`).
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import NDArray


@njit(cache=True)
def rotation(ang: NDArray[np.float64]) -> NDArray[np.float64]:  # pragma: no cover (compiled)
    """Rotation matrix ``A = R_Z(psi) R_Y(theta) R_X(phi)`` (body -> global)."""
    cf, sf = np.cos(ang[0]), np.sin(ang[0])
    ct, st = np.cos(ang[1]), np.sin(ang[1])
    cp, sp = np.cos(ang[2]), np.sin(ang[2])
    a = np.empty((3, 3))
    a[0, 0] = cp * ct
    a[0, 1] = cp * st * sf - sp * cf
    a[0, 2] = cp * st * cf + sp * sf
    a[1, 0] = sp * ct
    a[1, 1] = sp * st * sf + cp * cf
    a[1, 2] = sp * st * cf - cp * sf
    a[2, 0] = -st
    a[2, 1] = ct * sf
    a[2, 2] = ct * cf
    return a


@njit(cache=True)
def g_bar(ang: NDArray[np.float64]) -> NDArray[np.float64]:  # pragma: no cover (compiled)
    """``G_bar``: body angular velocity = ``G_bar @ angles_dot``."""
    cf, sf = np.cos(ang[0]), np.sin(ang[0])
    ct, st = np.cos(ang[1]), np.sin(ang[1])
    g = np.zeros((3, 3))
    g[0, 0] = 1.0
    g[0, 2] = -st
    g[1, 1] = cf
    g[1, 2] = ct * sf
    g[2, 1] = -sf
    g[2, 2] = ct * cf
    return g


@njit(cache=True)
def g_bar_dot_rate(ang: NDArray[np.float64], rate: NDArray[np.float64]) -> NDArray[np.float64]:  # pragma: no cover
    """``d(G_bar)/dt @ angles_dot``: the velocity part of the body angular acceleration."""
    cf, sf = np.cos(ang[0]), np.sin(ang[0])
    ct, st = np.cos(ang[1]), np.sin(ang[1])
    fd, td, pd = rate[0], rate[1], rate[2]
    out = np.empty(3)
    out[0] = -ct * td * pd
    out[1] = -sf * fd * td + (-st * td * sf + ct * cf * fd) * pd
    out[2] = -cf * fd * td + (-st * td * cf - ct * sf * fd) * pd
    return out


@njit(cache=True)
def cross(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:  # pragma: no cover
    """Cross product of 3-vectors."""
    out = np.empty(3)
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]
    return out


@njit(cache=True)
def mm(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:  # pragma: no cover (compiled)
    """Small matrix product by loops (numba's ``@`` calls BLAS, slow for 3x3 and 12x12)."""
    out = np.zeros((a.shape[0], b.shape[1]))
    for i in range(a.shape[0]):
        for k in range(a.shape[1]):
            aik = a[i, k]
            for j in range(b.shape[1]):
                out[i, j] += aik * b[k, j]
    return out


@njit(cache=True)
def mv(a: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:  # pragma: no cover (compiled)
    """Small matrix-vector product by loops."""
    out = np.zeros(a.shape[0])
    for i in range(a.shape[0]):
        acc = 0.0
        for k in range(a.shape[1]):
            acc += a[i, k] * v[k]
        out[i] = acc
    return out


@njit(cache=True)
def dot(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:  # pragma: no cover (compiled)
    """Dot product by a loop."""
    acc = 0.0
    for i in range(a.size):
        acc += a[i] * b[i]
    return acc


@njit(cache=True)
def l_bar(a: NDArray[np.float64], g: NDArray[np.float64], u: NDArray[np.float64],
          s: NDArray[np.float64]) -> NDArray[np.float64]:  # pragma: no cover (compiled)
    """Body-frame velocity map ``[A^T, -u~ G_bar, S]`` (3 x n) of a point at body position ``u``."""
    nf = s.shape[1]
    out = np.empty((3, 6 + nf))
    out[:, 0:3] = a.T
    for k in range(3):   # column k of -u~ G_bar is g_k x u
        gk = g[:, k]
        out[0, 3 + k] = gk[1] * u[2] - gk[2] * u[1]
        out[1, 3 + k] = gk[2] * u[0] - gk[0] * u[2]
        out[2, 3 + k] = gk[0] * u[1] - gk[1] * u[0]
    out[:, 6:] = s
    return out


@njit(cache=True)
def body_terms(q: NDArray[np.float64], qd: NDArray[np.float64], pm: NDArray[np.float64],
               pu: NDArray[np.float64], ps: NDArray[np.float64],
               gravity: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:  # pragma: no cover
    """Mass matrix and quadratic-velocity plus gravity forces of an FFR body of mass points."""
    nf = ps.shape[2]
    n = 6 + nf
    a = rotation(q[3:6])
    g = g_bar(q[3:6])
    w = g @ qd[3:6]
    alpha_v = g_bar_dot_rate(q[3:6], qd[3:6])
    qf, qfd = q[6:], qd[6:]
    g_body = a.T @ gravity
    m = np.zeros((n, n))
    f = np.zeros(n)
    for j in range(pm.size):
        s = ps[j]
        u = pu[j] + s @ qf
        lb = l_bar(a, g, u, s)
        m += pm[j] * (lb.T @ lb)
        gam = cross(alpha_v, u) + cross(w, cross(w, u)) + 2.0 * cross(w, s @ qfd)
        f += pm[j] * (lb.T @ (g_body - gam))
    return m, f


def inertia_points(mass: float, j_axial: float,
                   j_diametral: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Seven mass points reproducing a rigid body's mass and axisymmetric inertia exactly.

    Parameters
    ----------
    mass : float [kg]
    j_axial, j_diametral : float
        Moments of inertia about the body x axis and about a transverse axis through the
        centre [kg m^2]; ``j_axial <= 2 j_diametral`` (a physical body).

    Returns
    -------
    masses : ndarray (7,)
    offsets : ndarray (7, 3)
        Offsets from the centre of mass [m] (the centre point first).
    """
    second = np.array([j_diametral - 0.5 * j_axial, 0.5 * j_axial, 0.5 * j_axial])   # sum m x^2, y^2, z^2
    if mass <= 0 or np.any(second < -1e-9 * max(j_axial, 1.0)):
        raise ValueError(f"inertia (m={mass}, Jx={j_axial}, Jd={j_diametral}) is not physical")
    second = np.maximum(second, 0.0)
    arm = 1.2 * np.sqrt(max(second.sum(), 1e-30) / mass)
    pair = second / arm ** 2                      # mass of each +- pair
    offsets = [np.zeros(3)]
    masses = [mass - pair.sum()]
    for k in range(3):
        for sign in (1.0, -1.0):
            e = np.zeros(3)
            e[k] = sign * arm
            offsets.append(e)
            masses.append(pair[k] / 2.0)
    return np.array(masses), np.array(offsets)


class Invariants:
    """Inertia invariants of a body of mass points (the "integrated" FFR form; computed once).

    With ``u_j = u0_j + S_j q_f`` every sum over points that the mass matrix and the
    quadratic velocity vector need is a polynomial of degree <= 2 in ``q_f`` with these
    coefficients (Shabana's inertia shape integrals, lumped):

    ``mass = sum m``, ``first0 = sum m u0`` (3), ``s_sum = sum m S`` (3, n_f),
    ``k0 = sum m u0 u0^T`` (3, 3), ``k1[a,b,:] = sum m u0_a S_b`` (3, 3, n_f),
    ``e[a,b,:] = sum m S_a u0_b`` (3, 3, n_f), ``f[a,b] = sum m S_a^T S_b`` (3, 3, n_f, n_f),
    ``h0[:,k] = sum m u0 x S[:,k]`` (3, n_f), ``h1[l][:,k] = sum m S[:,l] x S[:,k]`` (n_f, 3, n_f),
    where ``S_a`` is row ``a`` of ``S``.
    """

    def __init__(self, pm: NDArray[np.float64], pu: NDArray[np.float64], ps: NDArray[np.float64]) -> None:
        self.mass = float(pm.sum())
        self.first0 = np.einsum("j,ja->a", pm, pu)
        self.s_sum = np.einsum("j,jak->ak", pm, ps)
        self.k0 = np.einsum("j,ja,jb->ab", pm, pu, pu)
        self.k1 = np.einsum("j,ja,jbk->abk", pm, pu, ps)
        self.e = np.einsum("j,jak,jb->abk", pm, ps, pu)
        self.f = np.einsum("j,jak,jbl->abkl", pm, ps, ps)
        self.h0 = np.einsum("j,ja,jbk->abk", pm, pu, ps)      # sum m u0_a S_bk, crossed below
        self.h0 = np.stack([self.h0[1, 2] - self.h0[2, 1], self.h0[2, 0] - self.h0[0, 2],
                            self.h0[0, 1] - self.h0[1, 0]])
        ss = np.einsum("j,jal,jbk->labk", pm, ps, ps)           # sum m S_al S_bk
        self.h1 = np.stack([ss[:, 1, 2] - ss[:, 2, 1], ss[:, 2, 0] - ss[:, 0, 2], ss[:, 0, 1] - ss[:, 1, 0]],
                           axis=1)                               # (n_f, 3, n_f)

    def args(self) -> tuple:
        """The invariants in kernel order."""
        return (self.mass, self.first0, self.s_sum, self.k0, self.k1, self.e, self.f, self.h0, self.h1)


@njit(cache=True)
def body_terms_inv(q, qd, mass, first0, s_sum, k0, k1, e, f4, h0, h1, gravity):  # pragma: no cover
    """Mass matrix and quadratic-velocity plus gravity forces from :class:`Invariants`.

    Equal to :func:`body_terms` on the same points (tested), at a cost independent of the
    number of points.
    """
    nf = s_sum.shape[1]
    n = 6 + nf
    a = rotation(q[3:6])
    g = g_bar(q[3:6])
    w = mv(g, qd[3:6])
    al = g_bar_dot_rate(q[3:6], qd[3:6])
    qf = q[6:]
    qfd = qd[6:]
    gb = mv(a.T, gravity)
    c = first0 + mv(s_sum, qf)
    theta = k0.copy()
    psi = np.zeros((3, 3))
    fq = np.zeros((3, 3, nf))          # f[a,b] @ qf
    fqd = np.zeros((3, 3, nf))         # f[a,b] @ qfd
    for i in range(3):                 # loops, not calls: this runs in every Newton iteration
        for j in range(3):
            th, ps_ = 0.0, 0.0
            for k in range(nf):
                th += (k1[i, j, k] + k1[j, i, k]) * qf[k]
                ps_ += k1[i, j, k] * qfd[k]
                acc, accd = 0.0, 0.0
                for l in range(nf):
                    acc += f4[i, j, k, l] * qf[l]
                    accd += f4[i, j, k, l] * qfd[l]
                fq[i, j, k], fqd[i, j, k] = acc, accd
                th += qf[k] * acc
                ps_ += qf[k] * accd
            theta[i, j] += th
            psi[i, j] = ps_
    hq = h0.copy()
    for l in range(nf):
        hq += qf[l] * h1[l]
    m = np.zeros((n, n))
    ct = np.zeros((3, 3))
    ct[0, 1], ct[0, 2], ct[1, 2] = -c[2], c[1], -c[0]
    ct[1, 0], ct[2, 0], ct[2, 1] = c[2], -c[1], c[0]
    for i in range(3):
        m[i, i] = mass
    m[0:3, 3:6] = mm(mm(a, -ct), g)
    m[3:6, 0:3] = m[0:3, 3:6].T
    tr = theta[0, 0] + theta[1, 1] + theta[2, 2]
    inert = -theta.copy()
    for i in range(3):
        inert[i, i] += tr
    m[3:6, 3:6] = mm(mm(g.T, inert), g)
    if nf > 0:
        m[0:3, 6:] = mm(a, s_sum)
        m[6:, 0:3] = m[0:3, 6:].T
        m[3:6, 6:] = mm(g.T, hq)
        m[6:, 3:6] = m[3:6, 6:].T
        mff = f4[0, 0] + f4[1, 1] + f4[2, 2]
        m[6:, 6:] = mff
    out = np.zeros(n)
    wsq = cross(w, cross(w, c))
    fr = mass * gb - (cross(al, c) + wsq + 2.0 * cross(w, mv(s_sum, qfd)))
    out[0:3] = mv(a, fr)
    trp = psi[0, 0] + psi[1, 1] + psi[2, 2]
    ft = cross(c, gb) - (tr * al - mv(theta, al) + cross(mv(theta, w), w) + 2.0 * (trp * w - mv(psi.T, w)))
    out[3:6] = mv(g.T, ft)
    if nf > 0:
        wt = np.zeros((3, 3))          # skew(w)
        wt[0, 1], wt[0, 2], wt[1, 2] = -w[2], w[1], -w[0]
        wt[1, 0], wt[2, 0], wt[2, 1] = w[2], -w[1], w[0]
        at = np.zeros((3, 3))          # skew(alpha_v)
        at[0, 1], at[0, 2], at[1, 2] = -al[2], al[1], -al[0]
        at[1, 0], at[2, 0], at[2, 1] = al[2], -al[1], al[0]
        ww = mm(wt, wt)
        ff = mv(s_sum.T, gb)
        for i in range(3):
            for j in range(3):
                ff -= (at[i, j] + ww[i, j]) * (e[i, j] + fq[i, j]) + 2.0 * wt[i, j] * fqd[i, j]
        out[6:] = ff
    return m, out
