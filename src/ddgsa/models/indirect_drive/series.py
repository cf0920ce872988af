"""Time series of the indirect drive from its coordinates and multipliers (every fidelity alike).

Sign conventions: bearing forces are the forces on the **outer ring** (housing or bedplate),
global frame [N] -- the multiplier of :class:`~ddgsa.mbs.constraints.Spherical` /
:class:`~ddgsa.mbs.constraints.TransverseBearing` on their housing-side marker; ``gear_force`` is
the normal tooth force on the pinion along the line of action [N]; mount forces are the forces
the torque-arm bushings apply to the housing [N]; ``housing_torque`` their torque about the
LSS axis (X through the origin) [N m].
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd
from numba import njit
from numpy.typing import NDArray

from ddgsa.mbs.ffr import g_bar, rotation
from ddgsa.models.indirect_drive.assembly import Assembly
from ddgsa.models.indirect_drive.outputs import axial_torque, point_displacement, rotation_vectors
from ddgsa.models.indirect_drive.parameters import BEARINGS

Array = NDArray[np.float64]
X_AXIS = np.array([1.0, 0.0, 0.0])
#: bearings on the housing whose multipliers are radial forces along the housing's y, z axes
TRANSVERSE = ("lss1", "lss3", "hss4")


def bryant(angles: Array) -> Array:
    """Rotation matrices (n_t, 3, 3) of Bryant angles (n_t, 3) ``[phi, theta, psi]``: ``R_Z R_Y R_X``
    (the kernel's :func:`ddgsa.mbs.ffr.rotation` at each sample, compiled)."""
    return _rotations(np.ascontiguousarray(angles, dtype=float))


@njit(cache=True)
def _rotations(angles):  # pragma: no cover (compiled)
    """:func:`ddgsa.mbs.ffr.rotation` of each row of ``angles`` (n_t, 3)."""
    out = np.empty((angles.shape[0], 3, 3))
    for i in range(angles.shape[0]):
        out[i] = rotation(angles[i])
    return out


def mount_forces(asm: Assembly, k: Array, c: Array, q_h: Array, qd_h: Array,
                 a: Array | None = None) -> tuple[Array, Array]:
    """Mount forces on the housing (n_t, 2, 3) [N] and mount positions (n_t, 2, 3) [m].

    The bushings' law in the global frame (:class:`~ddgsa.mbs.elements.Bushing6` with diagonal
    translational ``k``, ``c`` [N/m], [N s/m] and no rotational stiffness): ``F = -K u - C u_dot``
    with ``u`` the mount point's displacement from its rest position. ``a``: the housing's rotation
    matrices (n_t, 3, 3) where known (:func:`bryant` of its angles).
    """
    a = bryant(q_h[:, 3:6]) if a is None else a
    arm = np.tensordot(a, asm.mount_points, axes=([2], [1])).transpose(0, 2, 1)      # (n_t, 2, 3): A r_m
    w = _angular_velocity(q_h[:, 3:6], qd_h[:, 3:6], a)
    return _bushing_forces(np.ascontiguousarray(q_h[:, :3], dtype=float), np.ascontiguousarray(qd_h[:, :3], dtype=float),
                           np.ascontiguousarray(arm), w, asm.housing_origin + asm.mount_points,
                           np.asarray(k, dtype=float), np.asarray(c, dtype=float))


@njit(cache=True)
def _bushing_forces(x, v, arm, w, rest, k, c):  # pragma: no cover (compiled)
    """Mount forces and positions (n_t, m, 3) of :func:`mount_forces`, sample by sample (the numpy
    expressions it replaced, term by term: the same numbers, half the time): positions ``x + arm``,
    velocities ``v + w x arm``, forces ``-(pos - rest) k - vel c``."""
    n, m = arm.shape[0], arm.shape[1]
    f, pts = np.empty((n, m, 3)), np.empty((n, m, 3))
    for t in range(n):
        for j in range(m):
            a0, a1, a2 = arm[t, j, 0], arm[t, j, 1], arm[t, j, 2]
            vel = (v[t, 0] + (w[t, 1] * a2 - w[t, 2] * a1), v[t, 1] + (w[t, 2] * a0 - w[t, 0] * a2),
                   v[t, 2] + (w[t, 0] * a1 - w[t, 1] * a0))
            for i in range(3):
                pts[t, j, i] = x[t, i] + arm[t, j, i]
                f[t, j, i] = -(pts[t, j, i] - rest[j, i]) * k[i] - vel[i] * c[i]
    return f, pts


def _angular_velocity(ang: Array, rate: Array, a: Array | None = None) -> Array:
    """Global angular velocity (n_t, 3) of Bryant angles and rates (n_t, 3): ``A G_bar angles_dot`` (the
    kernel's :func:`ddgsa.mbs.ffr.g_bar` at each sample, compiled); ``a``: the rotation matrices
    (n_t, 3, 3) of ``ang`` where known (:func:`bryant`)."""
    ang = np.ascontiguousarray(ang, dtype=float)
    a = bryant(ang) if a is None else np.ascontiguousarray(a, dtype=float)
    return _angular_velocities(ang, np.ascontiguousarray(rate, dtype=float), a)


@njit(cache=True)
def _angular_velocities(ang, rate, a):  # pragma: no cover (compiled)
    out = np.empty_like(ang)
    wb = np.empty(3)
    for i in range(ang.shape[0]):
        g = g_bar(ang[i])
        for r in range(3):
            wb[r] = g[r, 0] * rate[i, 0] + g[r, 1] * rate[i, 1] + g[r, 2] * rate[i, 2]
        for r in range(3):
            out[i, r] = a[i, r, 0] * wb[0] + a[i, r, 1] * wb[1] + a[i, r, 2] * wb[2]
    return out


def spin_ratio(q_w: Array, qd_w: Array, q_p: Array, qd_p: Array, q_h: Array, qd_h: Array) -> Array:
    """Pinion over wheel spin relative to the housing, about the housing's gear axis (n_t,) [-].

    ``((w_p - w_h) . e) / ((w_w - w_h) . e)`` from the bodies' angular velocities (not their
    Bryant rates) and the housing's x axis ``e``. The gear constraint (eq. 2.4) makes the two
    pitch-point velocities equal along the line of action; this ratio is ``-N`` exactly when
    both gear centres are fixed in the housing (rigid LSS: its two gearbox bearings hold the
    wheel centre), and differs by the wheel centre's velocity in the housing over the pitch
    velocity when the LSS bends between those bearings (flexible).
    """
    a_h = bryant(q_h[:, 3:6])
    e = a_h[:, :, 0]
    w_h = _angular_velocity(q_h[:, 3:6], qd_h[:, 3:6], a_h)
    rel_w = np.einsum("ti,ti->t", _angular_velocity(q_w[:, 3:6], qd_w[:, 3:6]) - w_h, e)
    rel_p = np.einsum("ti,ti->t", _angular_velocity(q_p[:, 3:6], qd_p[:, 3:6]) - w_h, e)
    return rel_p / rel_w


def housing_series(asm: Assembly, p: Mapping[str, float], q_h: Array, qd_h: Array,
                   housing_point: Array) -> tuple[dict[str, Array], Array]:
    """The housing's columns of :func:`time_series` (point displacement and rotation vector, mount
    forces and their torque) from its coordinates and rates (n_t, 6), and its rotation matrices (n_t, 3, 3)."""
    a_h = bryant(q_h[:, 3:6])
    cols: dict[str, Array] = {}
    disp = point_displacement(q_h[:, :3], a_h, housing_point, asm.housing_origin, np.eye(3))
    ang = rotation_vectors(a_h)
    for i, ax in enumerate("xyz"):
        cols[f"housing_d{ax}"] = disp[:, i]
    for i, ax in enumerate("xyz"):
        cols[f"housing_r{ax}"] = ang[:, i]
    k_m = np.array([p["k_mount_x"], p["k_mount_y"], p["k_mount_z"]])
    c_m = 2.0 * p["mount_damping_ratio"] * np.sqrt(k_m * p["housing_mass"] / 2.0)
    fm, pts = mount_forces(asm, k_m, c_m, q_h, qd_h, a_h)
    for m, side in enumerate(("left", "right")):
        for i, ax in enumerate("xyz"):
            cols[f"mount_{side}_F{ax}"] = fm[:, m, i]
    cols["housing_torque"] = axial_torque(fm, np.zeros_like(fm), pts, np.zeros(3), X_AXIS)
    return cols, a_h


def force_series(names: tuple[str, ...], lam: Array, a_h: Array) -> dict[str, Array]:
    """``gear_force`` and the bearing force columns ``{b}_F{x,y,z}`` of :func:`time_series` from the
    multipliers (n_t, len(names)) named ``names`` and the housing's rotation matrices (n_t, 3, 3)."""
    col = {n: i for i, n in enumerate(names)}
    cols = {"gear_force": lam[:, col["gear.normal_force_on_j"]]}
    for b in BEARINGS:
        if b in TRANSVERSE:
            f = (a_h[:, :, 1] * lam[:, [col[f"{b}.force_on_j_n1"]]] + a_h[:, :, 2] * lam[:, [col[f"{b}.force_on_j_n2"]]])
        else:
            f = lam[:, [col[f"{b}.force_on_j_{ax}"] for ax in "xyz"]]
        for i, ax in enumerate("xyz"):
            cols[f"{b}_F{ax}"] = f[:, i]
    return cols


#: multipliers :func:`force_series` reads
FORCE_MULTIPLIERS = ("gear.normal_force_on_j",
                     *(f"{b}.force_on_j_{r}" for b in BEARINGS for r in (("n1", "n2") if b in TRANSVERSE else "xyz")))


def time_series(asm: Assembly, p: Mapping[str, float], times: Array, q: Array, qd: Array, lam: Array,
                loads: Mapping[str, Array], housing_point: Array, drift: tuple[Array, Array]) -> pd.DataFrame:
    """The model's time series (see :meth:`IndirectDrive.simulate` for the columns)."""
    s = asm.system
    sl = {b.name: s.slices[id(b)] for b in (asm.rotor, asm.wheel, asm.lss, asm.hss, asm.housing)}
    q_h, qd_h = q[:, sl["housing"]], qd[:, sl["housing"]]
    housing, a_h = housing_series(asm, p, q_h, qd_h, housing_point)
    cols = {k: v for k, v in housing.items() if not k.startswith("mount_") and k != "housing_torque"}
    w_lss, w_hss, w_h = qd[:, sl["wheel"]][:, 3], qd[:, sl["hss"]][:, 3], qd_h[:, 3]
    cols["lss_speed"], cols["hss_speed"], cols["housing_roll_rate"] = w_lss, w_hss, w_h
    cols["rotor_twist"] = q[:, sl["rotor"]][:, 3] - q[:, sl["wheel"]][:, 3]
    cols["spin_ratio"] = spin_ratio(q[:, sl["wheel"]], qd[:, sl["wheel"]], q[:, sl["hss"]], qd[:, sl["hss"]], q_h, qd_h)
    cols.update(force_series(s.multiplier_names, lam, a_h))
    cols.update({k: v for k, v in housing.items() if k not in cols})          # mount forces, then their torque
    n = p["gear_ratio"]
    cols["gen_torque"] = p["c_gen"] / n ** 2 * (-n * loads["w_set"] - w_hss)
    for name in ("Fx", "Fy", "Fz", "Mx", "My", "Mz"):
        cols[name] = loads[name]
    cols["position_drift"], cols["gear_drift"] = drift
    return pd.DataFrame(cols, index=pd.Index(times, name="time"))
