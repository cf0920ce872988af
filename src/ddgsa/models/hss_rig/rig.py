"""The rig assembled on the multibody kernel: bodies, elements and sensor markers from a parameter set.

Frame: global ``x`` along the shaft from the motor to the load, ``z`` up (gravity ``-z``), origin
at the coupling. Bodies:

``motor``
    Rigid motor rotor (mass, polar and diametral inertia) at ``x = -motor_shaft_length`` on its
    two bearings, lumped into one 6-DOF bushing to ground with free spin (lateral
    ``motor_bearing_stiffness``, tilt from the two bearings 0.1 m apart).
``hub``
    The motor-side coupling hub (rigid), at ``x = 0``.
``hss``
    The high-speed shaft, an FFR flexible body (:meth:`ddgsa.mbs.FlexibleBody.shaft`) from the
    shaft-side coupling hub (``x = 0``) over bearing 1 (``x = hss_overhang``) and the disk to
    bearing 2, with elastic coordinates ``torsion``, ``axial`` and (by default) five bending modes
    per plane computed on pinned supports at the bearings (:class:`ShaftBasis`); the hub and the disk are its end inertias.
``housing_1``, ``housing_2``
    Rigid bearing housings at the bearings, each on a 6-DOF support bushing to ground
    (``support_stiffness`` per direction; ``housing_looseness`` takes that fraction of housing 2's
    vertical stiffness away).

Elements: the motor shaft as the bushing of a clamped-free Euler-Bernoulli segment (torsion
``G I_p / L``, lateral/tilt the 2 x 2 cantilever stiffness ``EI/L^3 [[12, -+6L], [-+6L, 4L^2]]``):
at 28 mm and 0.12 m its first bending mode is far above the rig's band (> 1 kHz), so its
bending is carried by its stiffness, not by modes -- a stated simplification; the coupling
(:class:`~ddgsa.models.hss_rig.elements.MisalignedCoupling`); the bearings as radial
spring-dampers (bearing 1 also axial: the locating bearing); the eccentric mass; the load
torque law; the motor (a torque law for ``kloss``, :class:`~ddgsa.models.hss_rig.drive.DqMachine`
with its flux states for ``dq``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from ddgsa.mbs import (Bushing6, EccentricMass, FlexibleBody, Ground, Marker, RigidBody, SpringDamper3, System,
                      TorqueLaw)
from ddgsa.mbs.beam import BeamSpec, mesh, shear_coefficient
from ddgsa.mbs.bodies import Body, bending_fields
from ddgsa.mbs.compiled import compile_terms
from ddgsa.mbs.elements import Element, power_torque
from ddgsa.models.constants import tilted_gravity
from ddgsa.models.hss_rig.elements import MisalignedCoupling
from ddgsa.models.hss_rig.parameters import RATED_SPEED

GRAVITY = tilted_gravity(0.0)
"""Gravity [m/s^2], global frame (z up): the rig's shaft is level."""
HOUSING_ROTATIONAL_STIFFNESS = 1e5
"""Rotational stiffness of each housing support [N m/rad] (assumption: the bearings put no moment on it)."""
HOUSING_ROTATIONAL_DAMPING = 3.0
"""Rotational damping of each housing support [N m s/rad] (about 5 % of critical for its 500 Hz rocking)."""
MOTOR_BEARING_SPAN = 0.1
"""Distance between the motor's two bearings [m] (frame 100L; assumption)."""
SHAFT_DAMPING_RATIO = 0.002
"""Modal damping of the high-speed shaft's elastic coordinates [-] (assumption: steel, bolted joints)."""
ELEMENT_LENGTH = 1.0 / 32
"""Largest FE element of the high-speed shaft as a fraction of the bearing span (the default basis)."""


@dataclass(frozen=True)
class ShaftBasis:
    """The high-speed shaft's modal basis (model options ``bending_modes``, ``beam``).

    Attributes
    ----------
    bending_modes : int
        Bending modes per plane (default 5: with 32 elements per span and the axial mode, every mode
        below 600 Hz within 0.34 % of a 10-mode, 64-element basis and below 400 Hz within 0.3 % of
        ROSS; docs/physics.md tabulates the convergence).
    beam : {"euler_bernoulli", "timoshenko"}
        FE bending elements of the shapes (``timoshenko``: shear, with Cowper's solid-section
        ``kappa`` from the shaft's E and G, and the shaft's rotary inertia in the shapes).
    elements_per_span : int
        FE elements per bearing span (default 32, :data:`ELEMENT_LENGTH`): the shaft's mass is lumped
        at the nodes, so the coupling-hub modes on the 0.1 m overhang (one element at 8) need a finer
        mesh to come within 1 % of ROSS (docs/physics.md).
    axial : bool
        Give the shaft an axial elastic mode (its shape on the axial bearing's spring at bearing 1);
        without it the shaft is axially rigid and its axial mode 2.7 % high (default on).
    """

    bending_modes: int = 5
    beam: str = "euler_bernoulli"
    elements_per_span: int = round(1.0 / ELEMENT_LENGTH)
    axial: bool = True


@dataclass
class Rig:
    """The assembled rig and the handles a model needs on it.

    Attributes
    ----------
    system : System
    markers : dict
        Named markers: ``motor``, ``hub``, ``coupling``, ``bearing_1``, ``bearing_2``, ``disk``,
        ``housing_1``, ``housing_2``.
    positions : dict
        Shaft-axis positions [m] (body frame of ``hss``) of ``bearing_1``, ``disk``, ``bearing_2``.
    basis : ShaftBasis
        The shaft's modal basis it was built with.
    """

    system: System
    markers: dict[str, Marker]
    positions: dict[str, float]
    basis: "ShaftBasis"


def cantilever_stiffness(ei: float, length: float) -> np.ndarray:
    """Stiffness of a clamped-free beam at its tip over ``(y, rot_z)`` [N/m, N, N m/rad]: ``EI/L^3 [[12, -6L], [-6L, 4L^2]]``."""
    L = length
    return ei / L**3 * np.array([[12.0, -6 * L], [-6 * L, 4 * L * L]])


def load_law(p: Mapping[str, float]) -> Callable[[float, float], float]:
    """Load torque ``-T_L (|w| / w_rated)^n sign(w)`` [N m] against the spin ``w`` [rad/s]: the kernel's
    :func:`~ddgsa.mbs.elements.power_torque` of :func:`load_constants`."""
    law = load_constants(p)

    def torque(t: float, w: float) -> float:
        return power_torque(law, float(w))

    return torque


def load_constants(p: Mapping[str, float]) -> tuple[float, float, float]:
    """``(T_L, n, w_rated)`` [N m, -, rad/s] of the load law of parameters ``p`` (:meth:`TorqueLaw.power`)."""
    return float(p["load_torque"]), float(p["load_speed_exponent"]), RATED_SPEED


MotorParts = Callable[[Marker], tuple[list[Body], list[Element]]]


def build(p: Mapping[str, float], motor_parts: MotorParts, spin: float = 0.0,
          extra: Callable[[dict[str, Marker]], list[Element]] | None = None, gravity: bool = True,
          basis: ShaftBasis = ShaftBasis()) -> Rig:
    """Assemble the rig for parameters ``p`` (all declared parameters, SI).

    Parameters
    ----------
    motor_parts : callable
        ``motor_parts(motor_marker) -> (bodies, elements)``: the motor's torque element (and the
        flux-state body of ``dq``) -- the fidelity's choice.
    spin : float
        Initial spin speed of every rotating body [rad/s] (the steady operating speed for
        steady scenes, 0 for a start-up).
    extra : callable, optional
        ``extra(markers) -> elements``: further elements on the rig's markers (fault loads).
    gravity : bool
        Include gravity (:data:`GRAVITY`).
    basis : ShaftBasis
        The high-speed shaft's bending modes per plane and element family.
    """
    steel_e, steel_g, rho = p["shaft_youngs_modulus"], p["shaft_shear_modulus"], p["shaft_density"]
    d, span, over = p["hss_diameter"], p["hss_span"], p["hss_overhang"]
    x1, x2 = over, over + span
    xd = over + p["disk_position"] * span
    area, ip = math.pi * d * d / 4, math.pi * d**4 / 32
    length = x2
    spec = BeamSpec(
        nodes=mesh([0.0, x1, xd, x2], span / basis.elements_per_span), mass=rho * area * length,
        polar_inertia=rho * area * length * d * d / 8, EI=steel_e * ip / 2, EA=steel_e * area, GJ=steel_g * ip,
        end_masses=((0.0, p["coupling_hub_mass"], p["coupling_hub_inertia"], p["coupling_hub_inertia"] / 2),
                    (xd, p["disk_mass"], p["disk_polar_inertia"], p["disk_diametral_inertia"])),
        supports=(x1, x2), axial_support=x1, axial_spring=p["bearing_stiffness"] if basis.axial else None,
        shear_stiffness=(shear_coefficient(steel_e / (2 * steel_g) - 1) * steel_g * area
                         if basis.beam == "timoshenko" else None))
    rates = (spin, 0.0, 0.0)
    hss = FlexibleBody.shaft("hss", spec, fields=(("axial",) if basis.axial else ()) + ("torsion", *bending_fields(basis.bending_modes)),
                             damping_ratio=SHAFT_DAMPING_RATIO, angle_rates=rates)
    lm, dm = p["motor_shaft_length"], p["motor_shaft_diameter"]
    m_rotor, j_rotor = p["motor_rotor_mass"], p["motor_inertia"]
    motor = RigidBody("motor", mass=m_rotor, inertia=(j_rotor, j_rotor / 2, j_rotor / 2), position=(-lm, 0.0, 0.0),
                      angle_rates=rates)
    j_hub = p["coupling_hub_inertia"]
    hub = RigidBody("hub", mass=p["coupling_hub_mass"], inertia=(j_hub, j_hub / 2, j_hub / 2), angle_rates=rates)
    housings = [RigidBody(f"housing_{i}", mass=p["housing_mass"], inertia=(0.01, 0.01, 0.01), position=(x, 0.0, 0.0))
                for i, x in ((1, x1), (2, x2))]
    ground = Ground()
    mk = {"motor": motor.marker(), "motor_end": motor.marker((lm, 0.0, 0.0)), "hub": hub.marker(),
          "coupling": hss.marker((0.0, 0.0, 0.0)), "bearing_1": hss.marker((x1, 0.0, 0.0)),
          "disk": hss.marker((xd, 0.0, 0.0)), "bearing_2": hss.marker((x2, 0.0, 0.0)),
          "housing_1": housings[0].marker(), "housing_2": housings[1].marker()}
    elements: list = []
    bodies: list = [motor, hub, hss, *housings]
    # motor bearings: lateral k each, two bearings MOTOR_BEARING_SPAN apart -> tilt k (s/2)^2 * 2
    kmb = p["motor_bearing_stiffness"]
    k_tilt = 2 * kmb * (MOTOR_BEARING_SPAN / 2) ** 2
    elements.append(Bushing6(mk["motor"], ground.marker((-lm, 0.0, 0.0)),
                             np.diag([kmb, 2 * kmb, 2 * kmb, 0.0, k_tilt, k_tilt]),
                             np.diag([0.0, 2 * p["bearing_damping"], 2 * p["bearing_damping"], 0.0, 0.0, 0.0]),
                             free_spin=True, name="motor_bearings"))
    # motor shaft: clamped at the rotor, hub at its free end
    ei_m = steel_e * math.pi * dm**4 / 64
    kc = cantilever_stiffness(ei_m, lm)
    k6 = np.zeros((6, 6))
    k6[0, 0] = steel_e * math.pi * dm * dm / 4 / lm
    k6[3, 3] = steel_g * math.pi * dm**4 / 32 / lm
    k6[np.ix_([1, 5], [1, 5])] = kc
    k6[np.ix_([2, 4], [2, 4])] = kc * np.array([[1.0, -1.0], [-1.0, 1.0]])
    elements.append(Bushing6(mk["motor_end"], mk["hub"], k6, frame="i", name="motor_shaft"))
    kcr, kca = p["coupling_radial_stiffness"], p["coupling_angular_stiffness"]
    elements.append(MisalignedCoupling(
        mk["hub"], mk["coupling"], np.array([kcr, kcr, kcr, p["coupling_torsional_stiffness"], kca, kca]),
        np.array([0.0, 0.0, 0.0, p["coupling_torsional_damping"], 0.0, 0.0]), p["coupling_asymmetry"],
        p["misalignment_parallel"], p["misalignment_angular"]))
    kb, cb = p["bearing_stiffness"], p["bearing_damping"]
    elements.append(SpringDamper3(mk["bearing_1"], mk["housing_1"], (kb, kb, kb), (cb, cb, cb), name="bearing_1"))
    elements.append(SpringDamper3(mk["bearing_2"], mk["housing_2"], (0.0, kb, kb), (0.0, cb, cb), name="bearing_2"))
    ks, cs, kr = p["support_stiffness"], p["support_damping"], HOUSING_ROTATIONAL_STIFFNESS
    for i, x in ((1, x1), (2, x2)):
        kz = ks * (1.0 - p["housing_looseness"]) if i == 2 else ks
        elements.append(Bushing6(mk[f"housing_{i}"], ground.marker((x, 0.0, 0.0)), np.diag([ks, ks, kz, kr, kr, kr]),
                                 np.diag([cs, cs, cs] + [HOUSING_ROTATIONAL_DAMPING] * 3), name=f"support_{i}"))
    cd = p["disk_damping"]
    elements.append(SpringDamper3(mk["disk"], ground.marker((xd, 0.0, 0.0)), (0.0, 0.0, 0.0), (0.0, cd, cd),
                                  name="disk_damper"))
    elements.append(EccentricMass(mk["disk"], p["eccentric_mass"], p["eccentric_radius"]))
    elements.append(TorqueLaw.power(mk["disk"], *load_constants(p), name="load"))
    extra_bodies, motor_elements = motor_parts(mk["motor"])
    bodies += extra_bodies
    elements += motor_elements
    if extra is not None:
        elements += extra(mk)
    system = System(bodies, elements, gravity=GRAVITY if gravity else (0.0, 0.0, 0.0))
    compile_terms(system)           # every part packs (tests/models/test_models_pack.py): terms in compiled code
    return Rig(system, mk, {"bearing_1": x1, "disk": xd, "bearing_2": x2}, basis)


_TANGENT_BODIES = ("housing_1", "housing_2")
"""Bodies whose rotations take the kernel's tangents in the linearisation (:func:`tangent_columns`)."""


def tangent_columns(system: System) -> list[int]:
    """The rig's coordinates whose columns of the linearisation are the kernel's own tangents
    (:func:`ddgsa.mbs.nonrotating.linearise`'s ``tangent_columns``): every body's translation (no inertia or
    gravity term depends on where a body is, nor any marker's Jacobian) and the housings' rotations (they
    do not turn, and their markers and centres of mass sit at their reference points). The rest, 21 of 42
    (the turning bodies' rotations, the shaft's elastic coordinates: gyroscopic, centrifugal and the
    coupling's geometric terms), are central differences. The rig standing still takes the same columns
    (:func:`~ddgsa.mbs.modal.linearise_system`; a misaligned coupling's wrench at rest puts geometric terms
    into the others). ``tests/models/test_hss_rig_block.py`` checks them against central differences.

    The steady block path's linearisations (:mod:`ddgsa.models.hss_rig.steady_block`) take them."""
    names = [f"{b.name}.{c}" for b in system.bodies if isinstance(b, (RigidBody, FlexibleBody))
             for c in b.coord_names if c in ("x", "y", "z")]
    names += [f"{b}.{r}" for b in _TANGENT_BODIES for r in ("rx", "ry", "rz")]
    return [system.index(name) for name in names]
