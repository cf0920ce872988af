"""Closed-form and hand-assembled answers for the rig, independent of the multibody kernel (test oracles).

* Torsion: the rig as a chain of discs on massless torsional springs (motor rotor -- motor shaft
  -- coupling hub -- coupling -- coupling hub -- high-speed shaft -- disk). Free-free chains have
  a zero (rigid) mode and ``n - 1`` elastic ones; two and three discs in closed form
  (Den Hartog, *Mechanical Vibrations*, §5.4), longer chains from the hand-assembled tridiagonal
  stiffness and diagonal inertia matrices.
* Bending: the Jeffcott (Laval) rotor -- a disc of mass ``m`` on a massless shaft, simply
  supported on two elastic supports (Genta, *Dynamics of Rotating Systems*, §4.2; Childs,
  *Turbomachinery Rotordynamics*, §2). A disc at ``a`` from support 1 and ``b = L - a`` from
  support 2 sees the stiffness ``1 / (a^2 b^2 / (3 E I L) + (b/L)^2 / k_1 + (a/L)^2 / k_2)``
  (beam deflection under a point load plus the rigid motion on the two supports). The
  unbalance ``U = m_u e`` turning at ``W`` makes the synchronous whirl
  ``r = U W^2 / sqrt((k - M W^2)^2 + (c W)^2)``, lagging the unbalance by
  ``atan2(c W, k - M W^2)``. Exact for a disc without tilt (mid-span disc on equal supports);
  gyroscopic moments do not enter.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import eigh


def two_disc_frequency(j1: float, j2: float, k: float) -> float:
    """Elastic natural frequency [Hz] of two discs ``j1, j2`` [kg m^2] on a spring ``k`` [N m/rad]."""
    return math.sqrt(k * (j1 + j2) / (j1 * j2)) / (2 * math.pi)


def three_disc_frequencies(j1: float, j2: float, j3: float, k1: float, k2: float) -> tuple[float, float]:
    """The two elastic natural frequencies [Hz] of a free-free three-disc chain ``j1 -k1- j2 -k2- j3``.

    Roots in ``w^2`` of ``j1 j2 j3 w^4 - (k1 j3 (j1 + j2) + k2 j1 (j2 + j3)) w^2 + k1 k2 (j1 + j2 + j3) = 0``.
    """
    a = j1 * j2 * j3
    b = k1 * j3 * (j1 + j2) + k2 * j1 * (j2 + j3)
    c = k1 * k2 * (j1 + j2 + j3)
    disc = math.sqrt(b * b - 4 * a * c)
    w2 = sorted(((b - disc) / (2 * a), (b + disc) / (2 * a)))
    return math.sqrt(w2[0]) / (2 * math.pi), math.sqrt(w2[1]) / (2 * math.pi)


def chain_frequencies(inertias: ArrayLike, stiffnesses: ArrayLike) -> NDArray[np.float64]:
    """Elastic natural frequencies [Hz] of a free-free chain of discs (rigid mode dropped).

    Parameters
    ----------
    inertias : array_like, shape (n,)
        Disc inertias [kg m^2].
    stiffnesses : array_like, shape (n - 1,)
        Torsional stiffnesses between consecutive discs [N m/rad].
    """
    j = np.asarray(inertias, float)
    k = np.asarray(stiffnesses, float)
    kk = np.zeros((j.size, j.size))
    for i, ki in enumerate(k):
        kk[i:i + 2, i:i + 2] += ki * np.array([[1.0, -1.0], [-1.0, 1.0]])
    w2 = eigh(kk, np.diag(j), eigvals_only=True)
    return np.sqrt(np.clip(np.sort(w2)[1:], 0.0, None)) / (2 * math.pi)


def series(*stiffnesses: float) -> float:
    """Stiffness of springs in series ``1 / sum(1 / k_i)``."""
    return 1.0 / sum(1.0 / k for k in stiffnesses)


def jeffcott_stiffness(bending_stiffness: float, span: float, disc_position: float, k_support_1: float,
                       k_support_2: float) -> float:
    """Lateral stiffness [N/m] at a disc at ``disc_position`` [m] from support 1 of a simply supported shaft.

    Parameters
    ----------
    bending_stiffness : float
        ``E I`` [N m^2].
    span : float
        Distance between the supports ``L`` [m].
    k_support_1, k_support_2 : float
        Lateral stiffness of each support (bearing in series with its housing support) [N/m].
    """
    a, b, L = disc_position, span - disc_position, span
    return 1.0 / (a * a * b * b / (3 * bending_stiffness * L) + (b / L) ** 2 / k_support_1 + (a / L) ** 2 / k_support_2)


def jeffcott_critical_speed(stiffness: float, mass: float) -> float:
    """Critical speed ``sqrt(k / m)`` [rad/s] of the Jeffcott rotor (undamped)."""
    return math.sqrt(stiffness / mass)


def jeffcott_unbalance_response(speed: ArrayLike, stiffness: float, mass: float, damping: float,
                                unbalance: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Synchronous whirl amplitude [m] and its lag behind the unbalance [rad] at ``speed`` [rad/s].

    Parameters
    ----------
    stiffness : float
        Lateral stiffness ``k`` at the disc [N/m].
    mass : float
        Disc mass ``M`` [kg] (including the unbalance mass).
    damping : float
        Lateral damping ``c`` at the disc [N s/m].
    unbalance : float
        ``U = m_u e`` [kg m].
    """
    w = np.asarray(speed, float)
    re = stiffness - mass * w * w
    im = damping * w
    return unbalance * w * w / np.hypot(re, im), np.arctan2(im, re)
