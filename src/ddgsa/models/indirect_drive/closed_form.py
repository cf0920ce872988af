"""Closed-form answers for the one-stage gear drive: the references the model is tested against.

Geometry of the stage (seed 001 §2.2, Fig. 2.2): the wheel on the LSS and the pinion on the HSS
are an **external** spur pair with parallel axes a distance ``a = r_w + r_p`` apart; the pinion
pitch radius is ``r_p = r_w / N`` so the pitch circles roll without slip at the gear ratio N.
The contact (pitch) point A lies on the line of centres, ``r_w`` from the LSS axis. The tooth
force acts along the line of action, the common tangent of the pitch circles turned by the
pressure angle alpha. An external pair reverses the sense of rotation, so the generator turns
opposite to the rotor and the housing carries the **sum** of input and output torques.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class MeshGeometry:
    """Pitch-point geometry of the stage in the housing frame (X along the LSS axis) [m], [-].

    Attributes
    ----------
    wheel_radius, pinion_radius : float
        Pitch radii r_w and r_p = r_w / N [m].
    centre_distance : float
        Distance between the LSS and HSS axes, r_w + r_p [m].
    offset_direction : ndarray (3,)
        Unit vector from the LSS axis to the HSS axis (perpendicular to X).
    contact : ndarray (3,)
        Pitch point A relative to the LSS axis in the mesh plane [m].
    tangent : ndarray (3,)
        Unit tangent of the pitch circles at A, the direction the wheel's pitch point moves
        when the LSS turns positively about +X.
    line_of_action : ndarray (3,)
        Unit normal of the driven tooth flanks at A, ``cos(alpha) tangent + sin(alpha)
        offset_direction``: the direction of the force the driving wheel applies to the pinion
        (tangential, plus the separating component towards the pinion's own axis).
    """

    wheel_radius: float
    pinion_radius: float
    centre_distance: float
    offset_direction: NDArray[np.float64]
    contact: NDArray[np.float64]
    tangent: NDArray[np.float64]
    line_of_action: NDArray[np.float64]


def mesh_geometry(wheel_radius: float, ratio: float, pressure_angle: float,
                  offset_direction: tuple[float, float, float] = (0.0, 0.0, 1.0)) -> MeshGeometry:
    """The stage's pitch point, tangent and line of action.

    Parameters
    ----------
    wheel_radius : float
        Wheel (LSS) pitch radius r_w [m].
    ratio : float
        Gear ratio N = omega_HSS / omega_LSS in magnitude [-].
    pressure_angle : float
        Pressure angle alpha [rad].
    offset_direction : tuple of float
        Direction from the LSS axis to the HSS axis, perpendicular to X (default: HSS above).

    Examples
    --------
    >>> g = mesh_geometry(1.0, 4.0, 0.0)
    >>> g.pinion_radius, g.centre_distance, g.tangent.tolist()
    (0.25, 1.25, [0.0, -1.0, 0.0])
    """
    e = np.asarray(offset_direction, dtype=float)
    if abs(e[0]) > 1e-12 or not math.isclose(float(np.linalg.norm(e)), 1.0, rel_tol=1e-12):
        raise ValueError(f"offset_direction must be a unit vector perpendicular to X, got {offset_direction}")
    r_p = wheel_radius / ratio
    tangent = np.cross(np.array([1.0, 0.0, 0.0]), e)          # velocity direction of A on the wheel
    loa = math.cos(pressure_angle) * tangent + math.sin(pressure_angle) * e
    return MeshGeometry(wheel_radius, r_p, wheel_radius + r_p, e, wheel_radius * e, tangent, loa)


def torsional_frequency(stiffness: float, rotor_inertia: float, generator_inertia: float, ratio: float) -> float:
    """Drive-train torsional mode of the two-mass model [Hz].

    ``f = sqrt(k (1/J_rotor + 1/(N^2 J_gen))) / 2 pi`` with the generator inertia referred to
    the LSS through the gear ratio (stiffness [N m/rad], inertias [kg m^2], ratio [-]).

    Examples
    --------
    >>> round(torsional_frequency(867.637e6, 3.8677e7, 534.116, 97.0), 4)   # NREL 5-MW, rigid blades
    2.2229
    """
    return math.sqrt(stiffness * (1.0 / rotor_inertia + 1.0 / (ratio ** 2 * generator_inertia))) / (2 * math.pi)


@dataclass(frozen=True)
class StageTorques:
    """Steady torques about +X on the parts of the stage [N m], [N].

    Attributes
    ----------
    lss : float
        Torque applied to the LSS by the rotor.
    hss : float
        Torque the generator applies to the HSS (same sign as ``lss`` for an external pair:
        the HSS turns the other way and the generator opposes its motion).
    housing : float
        Torque the mounts apply to the housing; ``lss + hss + housing = 0``.
    mesh_force : float
        Tooth force along the line of action.
    """

    lss: float
    hss: float
    housing: float
    mesh_force: float


def stage_torques(lss_torque: float, ratio: float, wheel_radius: float, pressure_angle: float) -> StageTorques:
    """Steady torque balance of an ideal (lossless) external stage.

    The mesh transmits ``F cos(alpha) r_w = T_LSS``; the pinion receives ``F cos(alpha) r_p =
    T_LSS / N`` in the same sense about +X, which the generator balances; the housing mounts
    carry the rest: ``T_housing = -(T_LSS + T_LSS / N)``.

    Examples
    --------
    >>> t = stage_torques(97e3, 97.0, 1.0, 0.0)
    >>> t.hss, t.housing, t.mesh_force
    (1000.0, -98000.0, 97000.0)
    """
    hss = lss_torque / ratio
    force = lss_torque / (wheel_radius * math.cos(pressure_angle))
    return StageTorques(lss_torque, hss, -(lss_torque + hss), force)


def mount_torsional_stiffness(k_mount_z: float, arm: float, k_mount_rx: float = 0.0) -> float:
    """Stiffness of two mounts at ``(x, +-arm, 0)`` against housing roll about the LSS axis [N m/rad].

    ``2 k_z d^2 + 2 k_rx``: a roll phi moves each mount vertically by ``+-phi d`` (small angles)
    (``k_mount_z`` [N/m], ``arm`` d [m], ``k_mount_rx`` the bushing's own torsional stiffness [N m/rad]).
    """
    return 2.0 * k_mount_z * arm ** 2 + 2.0 * k_mount_rx


def housing_roll(housing_torque: float, k_mount_z: float, arm: float, k_mount_rx: float = 0.0) -> float:
    """Static housing rotation about the LSS axis under the mount torque ``housing_torque`` [rad].

    The mounts apply ``housing_torque`` to the housing, so the housing has turned by
    ``-housing_torque / k_roll`` (it turns with the reaction it receives from the shafts).
    """
    return -housing_torque / mount_torsional_stiffness(k_mount_z, arm, k_mount_rx)
