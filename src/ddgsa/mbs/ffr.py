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

import math

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
def skew(d: NDArray[np.float64]) -> NDArray[np.float64]:  # pragma: no cover (compiled)
    """Cross-product matrix: ``skew(d) @ x == d x x``."""
    out = np.zeros((3, 3))
    out[0, 1], out[0, 2], out[1, 2] = -d[2], d[1], -d[0]
    out[1, 0], out[2, 0], out[2, 1] = d[2], -d[1], d[0]
    return out


@njit(cache=True)
def rodrigues(v: NDArray[np.float64]) -> NDArray[np.float64]:  # pragma: no cover (compiled)
    """Rotation matrix of the rotation vector ``v`` [rad]."""
    angle = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    k = skew(v)
    kk = mm(k, k)
    if angle < 1e-8:
        return np.eye(3) + k + 0.5 * kk
    return np.eye(3) + math.sin(angle) / angle * k + (1.0 - math.cos(angle)) / angle ** 2 * kk


@njit(cache=True)
def rotation_vector(r: NDArray[np.float64]) -> NDArray[np.float64]:  # pragma: no cover (compiled)
    """Rotation vector [rad] of the rotation matrix ``r`` (angles below pi)."""
    cos = min(1.0, max(-1.0, 0.5 * (r[0, 0] + r[1, 1] + r[2, 2] - 1.0)))
    angle = math.acos(cos)
    out = np.empty(3)
    out[0], out[1], out[2] = r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]
    if angle < 1e-6:
        return 0.5 * out
    return 0.5 * angle / math.sin(angle) * out


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
        # every sum over the points as one matrix product (BLAS): the points' masses times [u0 | S] (N, 3 + 3 n_f)
        # against [u0 | S]; a three-operand einsum loops in C over all indices at once, 10x slower at a
        # shaft's 270 points and 12 fields (most of a new shaft's build)
        nf = ps.shape[2]
        w = np.hstack([pu, ps.reshape(len(pm), 3 * nf)])
        g = (w * pm[:, None]).T @ w                                  # (3 + 3 n_f)^2: sum m w_i w_j
        uu, us = g[:3, :3], g[:3, 3:].reshape(3, 3, nf)             # sum m u0_a u0_b, sum m u0_a S_bk
        ss = g[3:, 3:].reshape(3, nf, 3, nf)                         # sum m S_ak S_bl, as [a, k, b, l]
        self.mass = float(pm.sum())
        self.first0 = pm @ pu
        self.s_sum = np.tensordot(pm, ps, axes=1)
        self.k0 = uu.copy()
        self.k1 = us.copy()
        self.e = us.transpose(1, 0, 2).copy()                       # sum m S_ak u0_b
        self.f = ss.transpose(0, 2, 1, 3).copy()                    # [a, b, k, l]
        self.h0 = np.stack([us[1, 2] - us[2, 1], us[2, 0] - us[0, 2], us[0, 1] - us[1, 0]])
        sl = ss.transpose(1, 0, 2, 3)                                # sum m S_al S_bk, as [l, a, b, k]
        self.h1 = np.stack([sl[:, 1, 2] - sl[:, 2, 1], sl[:, 2, 0] - sl[:, 0, 2], sl[:, 0, 1] - sl[:, 1, 0]],
                           axis=1)                               # (n_f, 3, n_f)

    def args(self) -> tuple:
        """The invariants in kernel order."""
        return (self.mass, self.first0, self.s_sum, self.k0, self.k1, self.e, self.f, self.h0, self.h1)


@njit(cache=True)
def body_terms_inv(q, qd, mass, first0, s_sum, k0, k1, e, f4, h0, h1, gravity):  # pragma: no cover
    """Mass matrix and quadratic-velocity plus gravity forces from :class:`Invariants`.

    Equal to :func:`body_terms` on the same points (tested), at a cost independent of the
    number of points. Allocates its outputs; :func:`body_terms_into` writes into given arrays.
    """
    n = 6 + s_sum.shape[1]
    m = np.empty((n, n))
    out = np.empty(n)
    body_terms_into(q, qd, mass, first0, s_sum, k0, k1, e, f4, h0, h1, gravity, m, out)
    return m, out


@njit(cache=True)
def body_terms_into(q, qd, mass, first0, s_sum, k0, k1, e, f4, h0, h1, gravity, m, out):  # pragma: no cover
    """:func:`body_terms_inv` written into ``m`` (n, n) and ``out`` (n,), in scalar loops.

    The integrators call this once per Newton iteration, so it allocates only three small
    arrays (the ``f4`` contractions and the rotation) and keeps 3-vectors in scalars: whole-array
    expressions of 3-vectors cost an allocation each, more than their arithmetic.

    Terms (seed 000 App. 6.7 in the invariant form of :class:`Invariants`): with
    ``c = first0 + s_sum q_f`` (first moment), ``theta = sum m u u^T`` and
    ``psi = sum m u (S q_f_dot)^T`` (quadratic in ``q_f``), ``hq = h0 + sum_l q_f,l h1[l]``,

    - ``M_RR = m I``, ``M_Ra = A (g_k x c)`` (column k), ``M_aa = G^T (tr(theta) I - theta) G``,
      ``M_Rf = A s_sum``, ``M_af = G^T hq``, ``M_ff = sum_a f4[a, a]``;
    - ``Q_R = A (m g_b - alpha x c - w x (w x c) - 2 w x (s_sum q_f_dot))``,
    - ``Q_a = G^T (c x g_b - (tr(theta) alpha - theta alpha + (theta w) x w + 2 (tr(psi) w - psi^T w)))``,
    - ``Q_f = s_sum^T g_b - sum_ab ((alpha~ + w~ w~)_ab (e_ab + f4_ab q_f) + 2 w~_ab f4_ab q_f_dot)``,

    with ``g_b = A^T gravity``, ``w = G angles_dot`` and ``alpha = G_dot angles_dot``.
    """
    nf = s_sum.shape[1]
    cf, sf = np.cos(q[3]), np.sin(q[3])
    ct, st = np.cos(q[4]), np.sin(q[4])
    fd, td, pd = qd[3], qd[4], qd[5]
    a = rotation(q[3:6])
    g00, g02, g11, g12, g21, g22 = 1.0, -st, cf, ct * sf, -sf, ct * cf        # G_bar (others zero)
    w0, w1, w2 = fd + g02 * pd, g11 * td + g12 * pd, g21 * td + g22 * pd
    al0 = -ct * td * pd                                                    # G_bar_dot angles_dot
    al1 = -sf * fd * td + (-st * td * sf + ct * cf * fd) * pd
    al2 = -cf * fd * td + (-st * td * cf - ct * sf * fd) * pd
    gb0 = a[0, 0] * gravity[0] + a[1, 0] * gravity[1] + a[2, 0] * gravity[2]
    gb1 = a[0, 1] * gravity[0] + a[1, 1] * gravity[1] + a[2, 1] * gravity[2]
    gb2 = a[0, 2] * gravity[0] + a[1, 2] * gravity[1] + a[2, 2] * gravity[2]
    c0, c1, c2 = first0[0], first0[1], first0[2]
    sd0, sd1, sd2 = 0.0, 0.0, 0.0                                          # s_sum q_f_dot
    for k in range(nf):
        qk, qdk = q[6 + k], qd[6 + k]
        c0 += s_sum[0, k] * qk
        c1 += s_sum[1, k] * qk
        c2 += s_sum[2, k] * qk
        sd0 += s_sum[0, k] * qdk
        sd1 += s_sum[1, k] * qdk
        sd2 += s_sum[2, k] * qdk
    # theta (3x3), psi (3x3) and the f4 contractions fq = f4 q_f, fqd = f4 q_f_dot
    fq = np.empty((3, 3, nf))
    fqd = np.empty((3, 3, nf))
    th = np.empty((3, 3))
    ps = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            t_ij, p_ij = k0[i, j], 0.0
            for k in range(nf):
                qk = q[6 + k]
                t_ij += (k1[i, j, k] + k1[j, i, k]) * qk
                p_ij += k1[i, j, k] * qd[6 + k]
                acc, accd = 0.0, 0.0
                for l in range(nf):
                    x = f4[i, j, k, l]
                    acc += x * q[6 + l]
                    accd += x * qd[6 + l]
                fq[i, j, k] = acc
                fqd[i, j, k] = accd
                t_ij += qk * acc
                p_ij += qk * accd
            th[i, j] = t_ij
            ps[i, j] = p_ij
    tr = th[0, 0] + th[1, 1] + th[2, 2]
    trp = ps[0, 0] + ps[1, 1] + ps[2, 2]
    n = 6 + nf
    for i in range(n):
        for j in range(n):
            m[i, j] = 0.0
    for i in range(3):
        m[i, i] = mass
    # M_Ra: column k is A (g_k x c) with g_k column k of G_bar
    for k in range(3):
        gk0 = g00 if k == 0 else (g02 if k == 2 else 0.0)
        gk1 = 0.0 if k == 0 else (g11 if k == 1 else g12)
        gk2 = 0.0 if k == 0 else (g21 if k == 1 else g22)
        x0, x1, x2 = gk1 * c2 - gk2 * c1, gk2 * c0 - gk0 * c2, gk0 * c1 - gk1 * c0
        for i in range(3):
            v = a[i, 0] * x0 + a[i, 1] * x1 + a[i, 2] * x2
            m[i, 3 + k] = v
            m[3 + k, i] = v
    # M_aa = G^T (tr I - theta) G, G = [[1, 0, g02], [0, g11, g12], [0, g21, g22]]
    j00, j01, j02 = tr - th[0, 0], -th[0, 1], -th[0, 2]
    j10, j11, j12 = -th[1, 0], tr - th[1, 1], -th[1, 2]
    j20, j21, j22 = -th[2, 0], -th[2, 1], tr - th[2, 2]
    # (tr I - theta) G, columns 0..2
    b00, b10, b20 = j00, j10, j20
    b01, b11, b21 = j01 * g11 + j02 * g21, j11 * g11 + j12 * g21, j21 * g11 + j22 * g21
    b02 = j00 * g02 + j01 * g12 + j02 * g22
    b12 = j10 * g02 + j11 * g12 + j12 * g22
    b22 = j20 * g02 + j21 * g12 + j22 * g22
    m[3, 3], m[3, 4], m[3, 5] = b00, b01, b02
    m[4, 3] = g11 * b10 + g21 * b20
    m[4, 4] = g11 * b11 + g21 * b21
    m[4, 5] = g11 * b12 + g21 * b22
    m[5, 3] = g02 * b00 + g12 * b10 + g22 * b20
    m[5, 4] = g02 * b01 + g12 * b11 + g22 * b21
    m[5, 5] = g02 * b02 + g12 * b12 + g22 * b22
    # forces on the reference point: A (m g_b - alpha x c - w x (w x c) - 2 w x sd)
    wc0, wc1, wc2 = w1 * c2 - w2 * c1, w2 * c0 - w0 * c2, w0 * c1 - w1 * c0
    fr0 = mass * gb0 - ((al1 * c2 - al2 * c1) + (w1 * wc2 - w2 * wc1) + 2.0 * (w1 * sd2 - w2 * sd1))
    fr1 = mass * gb1 - ((al2 * c0 - al0 * c2) + (w2 * wc0 - w0 * wc2) + 2.0 * (w2 * sd0 - w0 * sd2))
    fr2 = mass * gb2 - ((al0 * c1 - al1 * c0) + (w0 * wc1 - w1 * wc0) + 2.0 * (w0 * sd1 - w1 * sd0))
    for i in range(3):
        out[i] = a[i, 0] * fr0 + a[i, 1] * fr1 + a[i, 2] * fr2
    # torque: c x g_b - (tr alpha - theta alpha + (theta w) x w + 2 (tr(psi) w - psi^T w))
    ta0 = th[0, 0] * al0 + th[0, 1] * al1 + th[0, 2] * al2
    ta1 = th[1, 0] * al0 + th[1, 1] * al1 + th[1, 2] * al2
    ta2 = th[2, 0] * al0 + th[2, 1] * al1 + th[2, 2] * al2
    tw0 = th[0, 0] * w0 + th[0, 1] * w1 + th[0, 2] * w2
    tw1 = th[1, 0] * w0 + th[1, 1] * w1 + th[1, 2] * w2
    tw2 = th[2, 0] * w0 + th[2, 1] * w1 + th[2, 2] * w2
    pw0 = ps[0, 0] * w0 + ps[1, 0] * w1 + ps[2, 0] * w2
    pw1 = ps[0, 1] * w0 + ps[1, 1] * w1 + ps[2, 1] * w2
    pw2 = ps[0, 2] * w0 + ps[1, 2] * w1 + ps[2, 2] * w2
    ft0 = (c1 * gb2 - c2 * gb1) - (tr * al0 - ta0 + (tw1 * w2 - tw2 * w1) + 2.0 * (trp * w0 - pw0))
    ft1 = (c2 * gb0 - c0 * gb2) - (tr * al1 - ta1 + (tw2 * w0 - tw0 * w2) + 2.0 * (trp * w1 - pw1))
    ft2 = (c0 * gb1 - c1 * gb0) - (tr * al2 - ta2 + (tw0 * w1 - tw1 * w0) + 2.0 * (trp * w2 - pw2))
    out[3] = ft0
    out[4] = g11 * ft1 + g21 * ft2
    out[5] = g02 * ft0 + g12 * ft1 + g22 * ft2
    if nf == 0:
        return
    # skew(alpha) + skew(w) skew(w) = alpha~ + w w^T - |w|^2 I, and skew(w)
    ww = w0 * w0 + w1 * w1 + w2 * w2
    cq = np.empty((3, 3))           # coefficient of (e + fq)
    cw = np.empty((3, 3))           # coefficient of fqd (2 w~)
    cq[0, 0], cq[1, 1], cq[2, 2] = w0 * w0 - ww, w1 * w1 - ww, w2 * w2 - ww
    cq[0, 1], cq[1, 0] = -al2 + w0 * w1, al2 + w1 * w0
    cq[0, 2], cq[2, 0] = al1 + w0 * w2, -al1 + w2 * w0
    cq[1, 2], cq[2, 1] = -al0 + w1 * w2, al0 + w2 * w1
    cw[0, 0], cw[1, 1], cw[2, 2] = 0.0, 0.0, 0.0
    cw[0, 1], cw[1, 0] = -2.0 * w2, 2.0 * w2
    cw[0, 2], cw[2, 0] = 2.0 * w1, -2.0 * w1
    cw[1, 2], cw[2, 1] = -2.0 * w0, 2.0 * w0
    for k in range(nf):
        # M_Rf = A s_sum, M_af = G^T hq with hq = h0 + sum_l q_f,l h1[l]
        s0, s1, s2 = s_sum[0, k], s_sum[1, k], s_sum[2, k]
        h_0, h_1, h_2 = h0[0, k], h0[1, k], h0[2, k]
        for l in range(nf):
            ql = q[6 + l]
            h_0 += ql * h1[l, 0, k]
            h_1 += ql * h1[l, 1, k]
            h_2 += ql * h1[l, 2, k]
        for i in range(3):
            v = a[i, 0] * s0 + a[i, 1] * s1 + a[i, 2] * s2
            m[i, 6 + k] = v
            m[6 + k, i] = v
        va = (h_0, g11 * h_1 + g21 * h_2, g02 * h_0 + g12 * h_1 + g22 * h_2)
        for i in range(3):
            m[3 + i, 6 + k] = va[i]
            m[6 + k, 3 + i] = va[i]
        for l in range(nf):
            m[6 + k, 6 + l] = f4[0, 0, k, l] + f4[1, 1, k, l] + f4[2, 2, k, l]
        acc = s0 * gb0 + s1 * gb1 + s2 * gb2
        for i in range(3):
            for j in range(3):
                acc -= cq[i, j] * (e[i, j, k] + fq[i, j, k]) + cw[i, j] * fqd[i, j, k]
        out[6 + k] = acc
