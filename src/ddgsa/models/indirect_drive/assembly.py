"""The indirect drive as a multibody system on the shared kernel (:mod:`ddgsa.mbs`).

Bodies (seed 001 §2.2, Fig. 2.2; frame of :mod:`ddgsa.loads.hubloads`, X along the LSS):

- ``lss`` -- the low-speed shaft as a **non-spinning** carrier of its bending and axial motion:
  an FFR shaft (``flexible``: axial and two bending modes per plane, FE shapes on pinned supports
  at the main bearing and the rear gearbox bearing) or a rigid body (``rigid``), with the hub's
  mass and diametral inertia at x = 0; its spin rate is held at zero
  (:class:`~ddgsa.mbs.constraints.PrescribedSpeed`). For an axisymmetric shaft these are the
  non-rotating bending coordinates of the direct drive's linear model (the slender shaft's own
  gyroscopic moments, small, are left out), and they make every spinning body below rigid and
  axisymmetric with its markers on its axis, so the spin angles are cyclic and the linearised
  system is time-invariant.
- ``rotor`` -- the hub's polar inertia (``hub_inertia_x``, the direct drive's), on the LSS flange by
  a revolute joint: :class:`~ddgsa.mbs.constraints.Spherical` at the flange and a
  :class:`~ddgsa.mbs.constraints.TransverseBearing` between a rotor point 1 m along its axis and the
  flange's section axes, which keeps the two axes parallel (:data:`JOINT_LEVER`); it keeps the
  hub's gyroscopic moments when the flange tilts.
- ``blades`` -- the rest of the rotor's polar inertia (``rotor_inertia_x - hub_inertia_x``), turned
  by the drive-train torsion only: a revolute joint to the bedplate at the hub (its axis does not
  tilt: the blades' flap flexibility keeps their diametral and gyroscopic inertia off the shaft,
  as in the direct drive) and a :class:`~ddgsa.mbs.constraints.PrescribedSpeed` tie of zero
  relative spin to the ``rotor`` (``blades_tie``), so hub and blades turn as one in torsion.
- ``wheel`` -- the gear wheel with the LSS's polar inertia, on the LSS at the mesh plane by a
  revolute joint; the NREL equivalent drive-train torsional spring-damper joins it to the rotor
  (:class:`~ddgsa.mbs.elements.TorsionalSpring`: shaft, gearbox and HSS compliance lumped into one
  LSS spring as the NREL model does). Rotor, blades and wheel masses and diametral inertias are
  1 kg / 1 kg m^2 placeholders (the masses are on the LSS and in the housing).
- ``hss`` -- rigid pinion shaft, axis parallel to the LSS at the centre distance above it,
  polar inertia = the generator inertia.
- ``housing`` -- rigid gearbox housing, centre of mass on the LSS axis at the mesh plane, on two
  6-DOF torque-arm bushings to the bedplate (ground).

Constraints: main bearing (spherical, LSS-ground), LSS bearings 1 and 3 (transverse-only,
LSS-housing), HSS bearing 2 (spherical) and 4 (transverse-only) to the housing, gear mesh
(eq. 2.4 along the line of action, :class:`~ddgsa.mbs.gear_mesh.GearMesh`) between wheel and pinion.

Loads: hub force and moment on the rotor (the hub; the aerodynamic torque net of the inertial torque of
the rotor inertia this model does not spin, see :func:`ddgsa.models.indirect_drive.model.scene_inputs`),
gravity (shaft tilted 4 deg), generator torque ``T = (c_gen / N^2) (w_set,HSS - w_HSS)`` on the HSS
with ``w_set,HSS = -N w_set`` (seed 000 eq. 25 referred through the gear; the HSS turns the other way).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.assembly import System
from ddgsa.mbs.beam import BeamSpec, mesh
from ddgsa.mbs.bodies import Body, FlexibleBody, Ground, Marker, RigidBody
from ddgsa.mbs.constraints import PrescribedSpeed, Spherical, TransverseBearing
from ddgsa.mbs.elements import AppliedLoad, Bushing6, TorqueLaw, TorsionalSpring
from ddgsa.mbs.series import Series
from ddgsa.mbs.gear_mesh import GearMesh
from ddgsa.models.constants import tilted_gravity
from ddgsa.models.indirect_drive.closed_form import MeshGeometry, mesh_geometry

Array = NDArray[np.float64]

#: LSS elastic coordinates of the flexible fidelity
FLEXIBLE_FIELDS = ("axial", "bending_y_1", "bending_z_1", "bending_y_2", "bending_z_2")
#: LSS bore radius of the hollow shaft [m] (the polar inertia only)
LSS_BORE = 0.15
#: longest FE element of the LSS mesh [m]
MAX_ELEMENT = 0.25
#: placeholder mass [kg] of the rotor, blades and wheel spin bodies (their diametral inertia: 1 kg m^2)
_SPIN_BODY_MASS = 1.0
#: axial distance of the second point of a revolute joint (its transverse constraint aligns the axes) [m]
JOINT_LEVER = 1.0
#: direction from the LSS axis to the HSS axis (HSS above the LSS)
HSS_OFFSET = (0.0, 0.0, 1.0)


@dataclass
class Assembly:
    """A built indirect drive: the system and what the outputs need.

    Attributes
    ----------
    system : System
    rotor, blades, wheel, lss, hss, housing : Body
    lss_origin : float
        x of the LSS body frame origin [m] (0 for the FFR shaft, its centre of mass if rigid).
    geometry : MeshGeometry
        The stage's pitch point, tangent and line of action (housing frame, origin on the LSS axis).
    housing_origin : ndarray (3,)
        Undeformed position of the housing's reference point (its centre of mass) [m].
    mount_points : ndarray (2, 3)
        Mount positions in the housing frame [m].
    gravity : ndarray (3,)
        [m/s^2]
    spin_inertia : float
        Polar inertia the model spins, referred to the LSS [kg m^2].
    ratio : float
        Gear ratio N [-].
    c_hss : float
        Generator torque constant on the HSS, ``c_gen / N^2`` [N m s/rad].
    """

    system: System
    rotor: Body
    blades: Body
    wheel: Body
    lss: Body
    hss: Body
    housing: Body
    lss_origin: float
    geometry: MeshGeometry
    housing_origin: Array
    mount_points: Array
    gravity: Array
    spin_inertia: float
    ratio: float
    c_hss: float


def check_geometry(p: Mapping[str, float]) -> None:
    """Raise :class:`ModelError` unless the positions along the LSS are ordered as the topology needs
    and the hub's polar inertia is a part of the rotor's."""
    order = ("main_bearing_x", "lss_bearing_1_x", "gear_x", "lss_bearing_3_x", "lss_length")
    vals = [p[k] for k in order]
    if not all(a < b for a, b in zip(vals, vals[1:])):
        raise ModelError("indirect_drive: positions must satisfy main_bearing_x < lss_bearing_1_x < gear_x < "
                         f"lss_bearing_3_x < lss_length; got {dict(zip(order, vals))}")
    if not p["hub_inertia_x"] < p["rotor_inertia_x"]:
        raise ModelError(f"indirect_drive: the hub's polar inertia hub_inertia_x ({p['hub_inertia_x']:.4g} kg m^2) "
                         f"must be below the whole rotor's, rotor_inertia_x ({p['rotor_inertia_x']:.4g} kg m^2)")
    if not p["hss_bearing_2_x"] < p["gear_x"] < p["hss_bearing_4_x"]:
        raise ModelError(f"indirect_drive: the pinion must lie between its bearings: hss_bearing_2_x "
                         f"({p['hss_bearing_2_x']}) < gear_x ({p['gear_x']}) < hss_bearing_4_x ({p['hss_bearing_4_x']})")


def lss_polar_inertia(p: Mapping[str, float]) -> float:
    """Polar inertia of the hollow LSS [kg m^2] (bore :data:`LSS_BORE`, at most 0.8 of the radius)."""
    r_o = p["lss_radius"]
    return p["lss_mass"] * (r_o ** 2 + min(LSS_BORE, 0.8 * r_o) ** 2) / 2.0


def _lss_body(p: Mapping[str, float], fields: tuple[str, ...]) -> tuple[Body, float]:
    """The non-spinning LSS with the hub mass at x = 0: FFR shaft with ``fields`` or rigid (no fields)."""
    length, r_o = p["lss_length"], p["lss_radius"]
    r_i = min(LSS_BORE, 0.8 * r_o)
    polar = lss_polar_inertia(p)
    if fields:
        spec = BeamSpec(nodes=mesh([0.0, p["main_bearing_x"], p["lss_bearing_1_x"], p["gear_x"],
                                    p["lss_bearing_3_x"], length], MAX_ELEMENT),
                        mass=p["lss_mass"], polar_inertia=polar, EI=p["lss_bending_stiffness"],
                        EA=p["lss_axial_stiffness"], GJ=p["drivetrain_torsional_stiffness"] * p["gear_x"],  # no torsion field
                        end_masses=((0.0, p["hub_mass"] - _SPIN_BODY_MASS, 0.0, p["hub_inertia_yz"]),),
                        supports=(p["main_bearing_x"], p["lss_bearing_3_x"]), axial_support=p["main_bearing_x"])
        body = FlexibleBody.shaft("lss", spec, fields, damping_ratio=p["lss_damping_ratio"], rotary_inertia=False)
        return body, 0.0
    m_s, m_h = p["lss_mass"], p["hub_mass"] - _SPIN_BODY_MASS
    x_cm = m_s * length / 2.0 / (m_s + m_h)
    j_d = (m_s * (length ** 2 / 12.0 + (r_o ** 2 + r_i ** 2) / 4.0) + m_s * (length / 2.0 - x_cm) ** 2
           + p["hub_inertia_yz"] + m_h * x_cm ** 2)
    body = RigidBody("lss", m_s + m_h, (polar, j_d, j_d), position=(x_cm, 0.0, 0.0))
    return body, x_cm


def build(p: Mapping[str, float], fields: tuple[str, ...], times: Array, hub_force: Array, hub_moment: Array,
          lss_speed_set: Array, spin: float) -> Assembly:
    """Assemble the system for one parameter set.

    Parameters
    ----------
    p : mapping
        Full parameter set (:data:`~ddgsa.models.indirect_drive.parameters.PARAMETERS` names).
    fields : tuple of str
        LSS elastic coordinates (empty: rigid LSS).
    times : (n_t,) uniformly spaced [s]
    hub_force, hub_moment : (n_t, 3)
        Loads on the rotor at x = 0, global frame [N], [N m].
    lss_speed_set : (n_t,)
        Generator set speed referred to the LSS, ``w_set`` [rad/s].
    spin : float
        Initial LSS spin rate [rad/s] (rotor and wheel turn at ``spin``, the HSS at ``-N spin``).
    """
    check_geometry(p)
    n = p["gear_ratio"]
    geo = mesh_geometry(p["gear_pitch_radius"], n, p["pressure_angle"], HSS_OFFSET)
    gx, off = p["gear_x"], geo.centre_distance * geo.offset_direction
    ground = Ground("bedplate")
    rotor = RigidBody("rotor", _SPIN_BODY_MASS, (p["hub_inertia_x"], 1.0, 1.0), angle_rates=(spin, 0.0, 0.0))
    blades = RigidBody("blades", _SPIN_BODY_MASS, (p["rotor_inertia_x"] - p["hub_inertia_x"], 1.0, 1.0),
                       angle_rates=(spin, 0.0, 0.0))
    lss, x0 = _lss_body(p, fields)
    wheel = RigidBody("wheel", _SPIN_BODY_MASS, (lss_polar_inertia(p), 1.0, 1.0), position=(gx, 0.0, 0.0),
                      angle_rates=(spin, 0.0, 0.0))
    hss = RigidBody("hss", p["hss_mass"], (p["generator_inertia"], p["hss_inertia_yz"], p["hss_inertia_yz"]),
                    position=(gx, *off[1:]), angle_rates=(-n * spin, 0.0, 0.0))
    housing = RigidBody("housing", p["housing_mass"],
                        (p["housing_inertia_x"], p["housing_inertia_y"], p["housing_inertia_z"]), position=(gx, 0.0, 0.0))

    def on_lss(x: float, name: str) -> Marker:
        return lss.marker((x - x0, 0.0, 0.0), name)

    def on_housing(x: float, name: str, offset: NDArray[np.float64] | None = None) -> Marker:
        o = np.zeros(3) if offset is None else offset
        return housing.marker((x - gx + o[0], o[1], o[2]), name)

    flange, seat = on_lss(0.0, "flange"), on_lss(gx, "wheel_seat")
    hub, wheel_centre = rotor.marker((0.0, 0.0, 0.0), "hub"), wheel.marker((0.0, 0.0, 0.0), "centre")
    constraints = [
        Spherical(hub, flange, name="hub_joint"),
        TransverseBearing(rotor.marker((JOINT_LEVER, 0.0, 0.0), "hub_axis"), flange, name="hub_alignment"),
        Spherical(blades.marker((0.0, 0.0, 0.0), "centre"), ground.marker((0.0, 0.0, 0.0)), name="blades_joint"),
        TransverseBearing(blades.marker((JOINT_LEVER, 0.0, 0.0), "axis"), ground.marker((0.0, 0.0, 0.0)),
                          name="blades_alignment"),
        PrescribedSpeed(hub, 0.0, reference=blades.marker((0.0, 0.0, 0.0), "tie"), name="blades_tie"),
        Spherical(wheel_centre, seat, name="wheel_joint"),
        TransverseBearing(wheel.marker((JOINT_LEVER, 0.0, 0.0), "wheel_axis"), seat, name="wheel_alignment"),
        Spherical(on_lss(p["main_bearing_x"], "main"), ground.marker((p["main_bearing_x"], 0.0, 0.0)), name="main"),
        TransverseBearing(on_lss(p["lss_bearing_1_x"], "lss1"), on_housing(p["lss_bearing_1_x"], "lss1"), name="lss1"),
        TransverseBearing(on_lss(p["lss_bearing_3_x"], "lss3"), on_housing(p["lss_bearing_3_x"], "lss3"), name="lss3"),
        Spherical(hss.marker((p["hss_bearing_2_x"] - gx, 0.0, 0.0), "hss2"),
                  on_housing(p["hss_bearing_2_x"], "hss2", off), name="hss2"),
        TransverseBearing(hss.marker((p["hss_bearing_4_x"] - gx, 0.0, 0.0), "hss4"),
                          on_housing(p["hss_bearing_4_x"], "hss4", off), name="hss4"),
        PrescribedSpeed(on_lss(p["main_bearing_x"], "no_spin"), 0.0, name="lss_no_spin"),
        GearMesh(wheel_centre, hss.marker((0.0, 0.0, 0.0), "pinion"), geo.wheel_radius, geo.pinion_radius,
                 on_housing(gx, "mesh"), p["pressure_angle"], name="gear"),
    ]
    mass_h = p["housing_mass"]
    k_t = np.array([p["k_mount_x"], p["k_mount_y"], p["k_mount_z"]])
    c_t = 2.0 * p["mount_damping_ratio"] * np.sqrt(k_t * mass_h / 2.0)
    k6, c6 = np.zeros((6, 6)), np.zeros((6, 6))
    k6[:3, :3], c6[:3, :3] = np.diag(k_t), np.diag(c_t)
    mounts = np.array([[0.0, p["mount_arm"], 0.0], [0.0, -p["mount_arm"], 0.0]])
    c_hss = p["c_gen"] / n ** 2
    w_set = Series(times, -n * np.asarray(lss_speed_set, dtype=float))
    elements = [
        TorsionalSpring(wheel_centre, hub, p["drivetrain_torsional_stiffness"], p["drivetrain_torsional_damping"],
                        name="drivetrain_spring"),
        *(Bushing6(housing.marker(m, f"mount_{s}"), ground.marker(m + np.array([gx, 0.0, 0.0])), k6, c6,
                   name=f"mount_{s}") for m, s in zip(mounts, ("left", "right"))),
        TorqueLaw.linear(hss.marker((0.0, 0.0, 0.0), "generator"), 0.0, c_hss, w_set, name="generator"),
        AppliedLoad(rotor.marker((0.0, 0.0, 0.0), "hub_load"), times, hub_force, hub_moment, name="hub"),
    ]
    gravity = np.array(tilted_gravity())
    system = System([rotor, blades, wheel, lss, hss, housing], elements, constraints, gravity=gravity)
    return Assembly(system, rotor, blades, wheel, lss, hss, housing, x0, geo, np.array([gx, 0.0, 0.0]), mounts, gravity,
                    spin_inertia(p), n, c_hss)


def spin_inertia(p: Mapping[str, float]) -> float:
    """Polar inertia the model spins, referred to the LSS: rotor, LSS and ``N^2`` x generator [kg m^2]."""
    return p["rotor_inertia_x"] + p["gear_ratio"] ** 2 * p["generator_inertia"] + lss_polar_inertia(p)
