"""Objective functions of the indirect drive, as pure functions of time series.

- housing point motion: displacement [m] and rotation [rad] of a point on the gearbox housing
  per global direction -- mean, RMS about the mean and peak-to-peak (what an optical system
  sees, seed 001 paper D);
- gear contact force: mean, RMS about the mean and damage-equivalent load from rainflow counting
  (ASTM E1049, compiled here; the ``rainflow`` package is its test oracle);
- bearing forces split into radial and axial parts about the shaft axis and their damage rates
  by the direct drive's Palmgren-Miner index (:func:`ddgsa.models.objectives.damage_rate`);
- housing reaction torque about the LSS axis from the mount forces and moments;
- constraint drift: the largest constraint residual of a record.

"RMS" in this model is always the RMS of the fluctuation about the record's mean: the mean is
its own output, so the two do not repeat each other.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numba import njit
from numpy.typing import NDArray

from ddgsa.models.objectives import damage_rate

#: Woehler exponent of the gear damage-equivalent load: tooth-root bending of case-carburised
#: steel (ISO 6336-3 S-N curve slope, about 8.7)
GEAR_WOEHLER_EXPONENT = 8.7
#: reference frequency of the damage-equivalent load: N_eq = f_ref x record length [Hz]
DEL_REFERENCE_FREQUENCY = 1.0
STATISTICS = ("mean", "rms", "p2p")
MOTION_CHANNELS = ("dx", "dy", "dz", "rx", "ry", "rz")


def signal_statistics(x: NDArray[np.float64]) -> dict[str, NDArray[np.float64]]:
    """Mean, RMS about the mean and peak-to-peak of each column of ``x`` (n_t,) or (n_t, k).

    Examples
    --------
    >>> s = signal_statistics(np.array([1.0, 3.0, 1.0, 3.0]))
    >>> float(s["mean"]), float(s["rms"]), float(s["p2p"])
    (2.0, 1.0, 2.0)
    """
    mean = x.mean(axis=0)
    return {"mean": mean, "rms": np.sqrt(np.mean((x - mean) ** 2, axis=0)), "p2p": np.ptp(x, axis=0)}


def point_displacement(position: NDArray[np.float64], rotation: NDArray[np.float64], point: NDArray[np.float64],
                       position_ref: NDArray[np.float64], rotation_ref: NDArray[np.float64]) -> NDArray[np.float64]:
    """Displacement (n_t, 3) [m] of a body-fixed point from its reference position, global frame.

    Parameters
    ----------
    position, rotation : ndarray (n_t, 3), (n_t, 3, 3)
        The body's reference point [m] and rotation matrix (body to global) over time.
    point : ndarray (3,)
        The point in body coordinates [m].
    position_ref, rotation_ref : ndarray (3,), (3, 3)
        The body's reference pose (undeformed, unloaded) [m].
    """
    return position + rotation @ point - (position_ref + rotation_ref @ point)


def rotation_vectors(rotation: NDArray[np.float64],
                     rotation_ref: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """Rotation vectors (n_t, 3) [rad] of ``rotation`` (n_t, 3, 3) relative to ``rotation_ref``, global frame.

    The exact logarithm of ``R R_ref^T`` for angles below pi (the kernel's
    :func:`ddgsa.mbs.bodies.rotation_vector`, vectorised, its angle from ``atan2(sin, cos)``: exact
    down to zero); for small angles its components are the rotations about the global X, Y, Z axes.
    ``rotation_ref`` None: the identity, whose product is skipped (``R I`` is ``R`` exactly; the
    stacked product was half of this function's time).
    """
    r = rotation if rotation_ref is None else rotation @ rotation_ref.T
    axis2 = np.stack([r[:, 2, 1] - r[:, 1, 2], r[:, 0, 2] - r[:, 2, 0], r[:, 1, 0] - r[:, 0, 1]], axis=1)  # 2 sin(a) n
    angle = np.arctan2(0.5 * np.linalg.norm(axis2, axis=1), 0.5 * (np.trace(r, axis1=1, axis2=2) - 1.0))
    return (0.5 / np.sinc(angle / np.pi))[:, None] * axis2


def rotated_x_axis(vectors: NDArray[np.float64]) -> NDArray[np.float64]:
    """The first column (n_t, 3) of the rotation matrices of rotation vectors ``v`` (n_t, 3) [rad]: the X
    axis rotated, by Rodrigues' formula (the kernel's :func:`ddgsa.mbs.bodies.rodrigues`, vectorised)
    ``e_x + sin(a)/a (v x e_x) + (1 - cos(a))/a^2 v x (v x e_x)``, the two factors as sinc (exact down to zero)."""
    v = np.asarray(vectors, dtype=float)
    angle = np.linalg.norm(v, axis=1)
    first, second = np.sinc(angle / np.pi), 0.5 * np.sinc(angle / (2.0 * np.pi)) ** 2
    out = second[:, None] * v[:, 0:1] * v                      # v x (v x e_x) = v v_x - a^2 e_x
    out[:, 0] += 1.0 - second * angle ** 2
    out[:, 1] += first * v[:, 2]                                # v x e_x = (0, v_z, -v_y)
    out[:, 2] -= first * v[:, 1]
    return out


def housing_motion_outputs(displacement: NDArray[np.float64], angles: NDArray[np.float64],
                           prefix: str = "housing") -> dict[str, float]:
    """``{prefix}_{dx..rz}_{mean,rms,p2p}`` of a point's displacement [m] and rotation [rad] (n_t, 3) each."""
    stats = signal_statistics(np.hstack([displacement, angles]))
    return {f"{prefix}_{ch}_{s}": float(stats[s][i]) for i, ch in enumerate(MOTION_CHANNELS) for s in STATISTICS}


def damage_equivalent_load(signal: NDArray[np.float64], duration: float, exponent: float = GEAR_WOEHLER_EXPONENT,
                           reference_frequency: float = DEL_REFERENCE_FREQUENCY) -> float:
    """Damage-equivalent load range [unit of ``signal``]: ``(sum n_i S_i^m / N_eq)^(1/m)``.

    Ranges S_i and counts n_i (half cycles count 0.5) by rainflow counting (ASTM E1049-85 section
    5.4.4, compiled: :func:`_rainflow_damage`, the ``rainflow`` package's algorithm, tested equal to it);
    ``N_eq = reference_frequency x duration`` (``duration`` [s], ``reference_frequency`` [Hz]).

    Examples
    --------
    >>> round(damage_equivalent_load(np.array([1.0, -1.0] * 10 + [1.0]), 10.0, exponent=4.0), 12)
    2.0
    """
    total = _rainflow_damage(np.ascontiguousarray(signal, dtype=float), float(exponent))
    return float((total / (reference_frequency * duration)) ** (1.0 / exponent))


@njit(cache=True)
def _rainflow_damage(x, m):  # pragma: no cover (compiled)
    """``sum n_i S_i^m`` over the rainflow cycles of ``x`` (ASTM E1049-85 5.4.4, as ``rainflow.extract_cycles``).

    Reversals: the first and last samples and every sample where the slope changes sign (repeated
    values skipped); then the three-point rule on a stack: a range ``Y`` (the two points before the
    last) not larger than the newest ``X`` is a full cycle, or, holding the start, a half cycle; the
    ranges left at the end are half cycles."""
    n = x.size
    if n < 3:
        return 0.0
    rev = np.empty(n)
    k = 1
    rev[0] = x[0]
    xx, d_last = x[1], x[1] - x[0]
    for i in range(2, n):
        if x[i] == xx:
            continue
        d_next = x[i] - xx
        if d_last * d_next < 0.0:
            rev[k] = xx
            k += 1
        xx, d_last = x[i], d_next
    rev[k] = x[n - 1]
    k += 1
    stack = np.empty(k)
    start, top, total = 0, 0, 0.0
    for j in range(k):
        stack[top] = rev[j]
        top += 1
        while top - start >= 3:
            x1, x2, x3 = stack[top - 3], stack[top - 2], stack[top - 1]
            if abs(x3 - x2) < abs(x2 - x1):
                break
            if top - start == 3:
                total += 0.5 * abs(stack[start] - stack[start + 1]) ** m
                start += 1
            else:
                total += abs(x1 - x2) ** m
                stack[top - 3] = x3
                top -= 2
    for j in range(start, top - 1):
        total += 0.5 * abs(stack[j] - stack[j + 1]) ** m
    return total


def gear_force_outputs(force: NDArray[np.float64], duration: float) -> dict[str, float]:
    """``gear_force_mean``, ``gear_force_rms`` (about the mean) and ``gear_force_del`` [N] of the
    tooth force along the line of action (n_t,) over a record of ``duration`` [s]."""
    stats = signal_statistics(force)
    return {"gear_force_mean": float(stats["mean"]), "gear_force_rms": float(stats["rms"]),
            "gear_force_del": damage_equivalent_load(force, duration)}


def radial_axial(forces: NDArray[np.float64], axis: NDArray[np.float64]) -> tuple[NDArray[np.float64],
                                                                                   NDArray[np.float64]]:
    """Radial and axial magnitudes (n_t,) [N] of bearing forces (n_t, 3) about unit shaft axes (n_t, 3) or (3,)."""
    axial = np.einsum("ti,ti->t", forces, np.broadcast_to(axis, forces.shape))
    radial = np.linalg.norm(forces - axial[:, None] * axis, axis=1)
    return radial, np.abs(axial)


def bearing_outputs(name: str, forces: NDArray[np.float64], axis: NDArray[np.float64], speed: NDArray[np.float64],
                    rating: float, rule: str) -> dict[str, float]:
    """``damage_{name}`` [1/s], ``{name}_Fr_mean`` and ``{name}_Fa_mean`` [N] of one bearing.

    ``forces`` (n_t, 3) [N] in the global frame, ``axis`` the shaft axis, ``speed`` the shaft's
    spin rate relative to the bearing's outer ring (n_t,) [rad/s], ``rating`` C [N], ``rule`` the
    equivalent-load rule of :func:`ddgsa.models.objectives.equivalent_load`.
    """
    fr, fa = radial_axial(forces, axis)
    return {f"damage_{name}": damage_rate(fr, fa, speed, rating, rule), f"{name}_Fr_mean": float(fr.mean()),
            f"{name}_Fa_mean": float(fa.mean())}


def axial_torque(forces: NDArray[np.float64], moments: NDArray[np.float64], points: NDArray[np.float64],
                 origin: NDArray[np.float64], axis: NDArray[np.float64]) -> NDArray[np.float64]:
    """Torque (n_t,) [N m] about ``axis`` (3,) or (n_t, 3) through ``origin`` of forces (n_t, k, 3) [N] at
    points (n_t, k, 3) or (k, 3) [m] and moments (n_t, k, 3) [N m] -- the reaction torque of the mounts.
    About a fixed axis only its nonzero components are formed (about X: the x component alone)."""
    arm = np.broadcast_to(points - origin, forces.shape)
    total = moments.sum(axis=1)
    if axis.ndim == 1:
        out = np.zeros(len(forces))
        for i in np.flatnonzero(axis):                        # (arm x force)_i, summed over the points
            j, k = (i + 1) % 3, (i + 2) % 3
            out += axis[i] * (total[:, i] + (arm[..., j] * forces[..., k] - arm[..., k] * forces[..., j]).sum(axis=1))
        return out
    for i in range(3):
        j, k = (i + 1) % 3, (i + 2) % 3
        total[:, i] += (arm[..., j] * forces[..., k] - arm[..., k] * forces[..., j]).sum(axis=1)
    return np.einsum("ti,ti->t", total, axis)


def constraint_drift(residuals: Mapping[str, NDArray[np.float64]]) -> dict[str, float]:
    """``{name}_drift``: the largest absolute constraint residual of each record (n_t, m) or (n_t,)."""
    return {f"{name}_drift": float(np.max(np.abs(r))) if np.size(r) else 0.0 for name, r in residuals.items()}
