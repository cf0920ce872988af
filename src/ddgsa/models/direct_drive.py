"""Direct-drive drive train (seed 000, Asadi & Johansson 2020): FFR main shaft on two bearings.

The main shaft is one floating-frame-of-reference body (:mod:`ddgsa.mbs.ffr`) from the hub
(x = 0) to the generator rotor (x = L), with the rotor hub and the generator rotor as rigid
end inertias and the two main bearings as 3-direction spring-dampers to the bedplate. Loads:
aerodynamic hub force and moment (:func:`ddgsa.loads.generate`, scaled by the excitation
factors), gravity of every mass (shaft tilted 4 deg, hub end up), and the generator torque
``T = C_gen (w_set - w)`` at x = L (seed 000 eq. 25) with the set speed
``w_set = w_loads - T_ctrl / C_gen`` so that the torque equals the controller's demand when
the shaft turns at the loads model's speed (the law then adds ``C_gen`` of speed damping).

Fidelities: ``flexible`` -- 6 rigid + 12 elastic coordinates (1 axial, 1 torsion, 5 bending per
plane, :data:`DEFAULT_BENDING_MODES`; drop the axial or all but the first bending mode with
``axial=False`` / ``second_bending=False``), shapes from FE eigenmodes of the shaft with its end
inertias on pinned bearings, Timoshenko elements (seed 000 §2.5 has Euler-Bernoulli with two modes
per plane: ``beam: euler_bernoulli, bending_modes: 2``; docs/physics.md says what they move);
``linear`` -- the flexible model linearised about the scene's mean operating point;
``rigid`` -- the same body without elastic coordinates.

Parameter choices (seed 000 Table 2 is not self-consistent; each value is a parameter):

- The shaft and end inertias are a named reading, option ``shaft`` (issue 47,
  :mod:`ddgsa.models.seed_readings`). ``table1`` (the default): the shaft whose FE modes seed 000's
  Table 1 prints, **solid** steel of radius 0.3258 m (E = 200 GPa, rho = 7850 kg/m^3): 15.7 t,
  EI = 1.77e9, GJ = 1.36e9 N m^2, EA = 6.67e10 N, with the hub and generator rotor as thin discs
  of radii R1 = 7 m, R2 = 0.5 m (J_x = m R^2 / 2: 9.8e5 and 3 750 kg m^2, diametral half of that).
  It reproduces Table 1's first bending and torsion frequencies (6.08, 37.84 Hz on its rigid
  supports; 5.94 / 6.02 and 37.84 Hz in the model on its bearings). ``table2``: Table 2's
  EI = 1e9 N m^2 at ``shaft_radius`` 0.3258 m, so the shaft is taken **hollow**, bore radius
  0.2686 m (E = 210 GPa), 5.03 t (``shaft_mass``), not Table 2's 1 t; GJ = EI / (1 + nu) =
  7.69e8 N m^2 (nu = 0.3), EA = 2.24e10 N; its first bending mode is 3.21 Hz, 46 % below Table 1.
  The declared nominal values below are ``table2``'s; :func:`shaft_parameters` gives each reading's.
- Hub body (``table2``): Table 2's hub mass m1 = 40 t with its equivalent radius R1 = 7 m read as
  radius of gyration, J_x = m1 R1^2 = 1.96e6 kg m^2, diametral half (the extracted "0.095 kg m^2" is
  garbled). As in seed 000, where the hub loads came from a full turbine simulation, the blades
  are not bodies of this model: their inertia is in the loads model (NREL 5-MW rotor,
  3.87e7 kg m^2), and the hub torque this model receives is the aerodynamic torque net of the
  blades' inertial torque, ``M_x - (J_rotor,loads - J_hub - J_gen) d(w_loads)/dt``, so the shaft
  turns at the loads model's speed. (A rigid 126 m rotor's diametral inertia, 1.9e7 kg m^2, on
  this soft shaft would put a rotor-rocking mode at 0.74 Hz, at 3P; the blades' flap
  flexibility decouples most of that inertia from the shaft.) Generator rotor (``table2``): Table 2's
  R2 = 0.5 m read the same way, J = m2 R2^2 = 7.5e3 kg m^2, diametral half.
- Bearing damping: Table 2's ratio 0.01 as ``C_i = 2 zeta sqrt(K_i m / 2)`` per direction
  (m the total mass); shaft damping Rayleigh (seed 000 eq. 43-44) with ratio 0.01. These are the
  physical readings; the seed's printed ones (eq. 44a's ``delta = 2 zeta (w1 + w2)``, Table 2's
  zeta in seconds) and two readings of the deflection objective are options
  (:mod:`ddgsa.models.seed_readings`, ``docs/seed000_readings.md``).
- Dynamic load ratings ``bearing_C_front/rear`` 1e7 N (spherical roller main bearings of this
  size: 5e6-2e7 N); damage indices are usually reported scaled by their maximum (seed 000 §4).
- The shaft's own rotary inertia (~450 kg m^2 polar, 0.02 % of the hub's) is in the body with
  Timoshenko elements (the default); with ``beam="euler_bernoulli"`` and at fidelity ``rigid`` its
  mass is lumped on the axis (the FE torsion shape includes it).

Equivalent bearing load: seed 000 eq. (29) writes ``P = 2.5 Fr + 3.7 Fa``; the catalogue rule
for spherical roller bearings (ISO 281) has two branches, ``P = Fr + 2.5 Fa`` if
``Fa/Fr <= 0.27`` else ``0.67 Fr + 3.7 Fa`` -- the seed's line merges them and overstates P 2.5x
for radial loads. Default ``equivalent_load="iso281"``; ``"seed"`` reproduces eq. (29).
Damage rate (Palmgren-Miner with ``L10 = (C/P)^(10/3)`` million revolutions):
``d = mean_t[(w/2 pi)(P/C)^(10/3)] / 1e6`` [1/s].
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.errors import ModelError
from ddgsa.loads import EXCITATION_FACTORS, NREL5MW, generate_columns
from ddgsa.loads.scene import Scene
from ddgsa.mbs.assembly import System
from ddgsa.mbs.beam import BEAMS, BeamSpec, mesh, shear_coefficient
from ddgsa.mbs.bodies import MAX_BENDING_MODES, FlexibleBody, Ground, bending_fields
from ddgsa.mbs.elements import AppliedLoad, SpringDamper3, TorqueLaw
from ddgsa.mbs.modal import kind_jacobians, modal_analysis
from ddgsa.mbs.linear import (initial_state, input_window, linearise_spinning, lti_response,
                              modal_output_matrix, modal_step, state_matrices)
from ddgsa.mbs.sampling import NYQUIST, check_interval, sampling_row
from ddgsa.mbs.system import (SystemArrays, integrate, integrate_reference, kind, kind_context,
                              single_body_arrays, static_state)
from ddgsa.models.base import (BAND_FACTOR, BasisRule, Model, ModelOption, ModelOutput, ModelParameter, SignalOutput,
                               controller_row, register_model)
from ddgsa.models.constants import HUB_INERTIA_X, HUB_INERTIA_YZ, HUB_MASS, tilted_gravity
from ddgsa.models.seed_readings import (BEARING_DAMPING, BENDING_RAYLEIGH, DEFLECTION, DEFLECTION_REFERENCE, SHAFT,
                                        bearing_damping, bending_damping, table1_shaft)
from ddgsa.models.objectives import damage_rate
from ddgsa.models.signals import band_rms_spectrum

_E_STEEL = 210e9
_NU_STEEL = 0.3
_BORE = 0.2686
_MAX_ELEMENT = 0.25

PARAMETERS = (
    ModelParameter("shaft_length", 6.0, "m", "main shaft length L (hub at x = 0, generator at x = L)", 2.0, 20.0),
    ModelParameter("front_bearing_x", 1.0, "m", "front bearing position L1 from the hub", 0.05, 19.0),
    ModelParameter("rear_bearing_x", 5.0, "m", "rear bearing position L2 from the hub", 0.1, 19.9),
    ModelParameter("hub_mass", HUB_MASS, "kg", "rotor hub (with blades) mass m1", 1.0, 1e6),
    ModelParameter("generator_mass", 30000.0, "kg", "generator rotor mass m2", 1.0, 1e6),
    ModelParameter("shaft_mass", 5030.0, "kg", "main shaft mass", 1.0, 1e5),
    ModelParameter("shaft_radius", 0.3258, "m", "main shaft outer radius (enters its polar inertia only)",
                   0.01, 2.0),
    ModelParameter("shaft_bending_stiffness", 1.0e9, "N m^2", "main shaft bending stiffness EI", 1e6, 1e12),
    ModelParameter("shaft_torsional_stiffness", 7.69e8, "N m^2", "main shaft torsional stiffness GJ", 1e6, 1e12),
    ModelParameter("shaft_axial_stiffness", 2.24e10, "N", "main shaft axial stiffness EA", 1e7, 1e13),
    ModelParameter("hub_inertia_x", HUB_INERTIA_X, "kg m^2",
                   "rotor hub polar inertia about the shaft (m1 R1^2 / 2, disc: table1; m1 R1^2: table2)", 1.0, 1e10),
    ModelParameter("hub_inertia_yz", HUB_INERTIA_YZ, "kg m^2", "rotor hub diametral inertia", 1.0, 1e10),
    ModelParameter("generator_inertia_x", 7.5e3, "kg m^2", "generator rotor polar inertia", 1.0, 1e9),
    ModelParameter("generator_inertia_yz", 3.75e3, "kg m^2", "generator rotor diametral inertia", 1.0, 1e9),
    ModelParameter("k_front_x", 1e10, "N/m", "front bearing stiffness, axial", 0.0, 1e12),
    ModelParameter("k_front_y", 3e9, "N/m", "front bearing stiffness, lateral", 1e6, 1e12),
    ModelParameter("k_front_z", 1e10, "N/m", "front bearing stiffness, vertical", 1e6, 1e12),
    ModelParameter("k_rear_x", 0.0, "N/m", "rear bearing stiffness, axial", 0.0, 1e12),
    ModelParameter("k_rear_y", 3e9, "N/m", "rear bearing stiffness, lateral", 1e6, 1e12),
    ModelParameter("k_rear_z", 1e10, "N/m", "rear bearing stiffness, vertical", 1e6, 1e12),
    ModelParameter("bearing_damping_ratio", 0.01, "-", "bearing damping ratio zeta", 0.0, 1.0),
    ModelParameter("shaft_damping_ratio", 0.01, "-", "shaft modal damping ratio (Rayleigh)", 0.0, 1.0),
    ModelParameter("c_gen", 828.26e3, "N m s/rad", "generator torque constant C_gen (seed eq. 25)", 1e3, 1e9),
    ModelParameter("bearing_C_front", 1.0e7, "N", "front bearing dynamic load rating C", 1e5, 1e9),
    ModelParameter("bearing_C_rear", 1.0e7, "N", "rear bearing dynamic load rating C", 1e5, 1e9),
    *(ModelParameter(name, 1.0, "-", f"multiplier on the hub load {col}", 0.0, 10.0)
      for name, col in EXCITATION_FACTORS.items()),
)
OUTPUTS = (
    ModelOutput("rms_deflection_hub", "m", "RMS radial deflection of the shaft axis at the hub about its "
                "quasi-static position (seed 000 §3.2.1)", 0.0, 0.05),
    ModelOutput("rms_deflection_gen", "m", "RMS radial deflection of the shaft axis at the generator rotor about "
                "its quasi-static position", 0.0, 0.05),
    ModelOutput("damage_front", "1/s", "front bearing damage rate: fraction of its L10 rating life used per second "
                "(Palmgren-Miner, L10 = (C/P)^(10/3) million revolutions; 1.6e-9 uses it up in 20 years)", 0.0, 1e-6),
    ModelOutput("damage_rear", "1/s", "rear bearing damage rate: fraction of its L10 rating life used per second",
                0.0, 1e-6),
    ModelOutput("front_Fr_mean", "N", "time-mean radial force on the front bearing", 0.0, 1e7),
    ModelOutput("rear_Fr_mean", "N", "time-mean radial force on the rear bearing", 0.0, 1e7),
    ModelOutput("front_Fa_mean", "N", "time-mean axial force magnitude on the front bearing", 0.0, 1e7),
    ModelOutput("rear_Fa_mean", "N", "time-mean axial force magnitude on the rear bearing", 0.0, 1e7),
)
DEFAULT_SHAFT = "table1"
"""The shaft reading of a model built without ``shaft`` (:data:`~ddgsa.models.seed_readings.SHAFT`): Table 1's,
which reproduces 15 of the 22 numbers seed 000 prints about its shaft, its modes and its deflection, Table 2's 4
(``docs/seed000_readings.md``, "The shaft")."""
SHAFT_BORE = {"table1": 0.0, "table2": _BORE}
"""Bore radius [m] of each shaft reading's section (its polar inertia and Timoshenko shear stiffness)."""


def shaft_parameters(shaft: str) -> tuple[ModelParameter, ...]:
    """:data:`PARAMETERS` with the nominal values of the shaft reading ``shaft`` (``table2``: as declared;
    ``table1``: :func:`~ddgsa.models.seed_readings.table1_shaft` of the declared radius, length and end masses)."""
    if shaft == "table2":
        return PARAMETERS
    nominal = {p.name: p.nominal for p in PARAMETERS}
    solid = table1_shaft(nominal["shaft_radius"], nominal["shaft_length"], nominal["hub_mass"],
                         nominal["generator_mass"])
    return tuple(dataclasses.replace(p, nominal=solid.get(p.name, p.nominal)) for p in PARAMETERS)


SPECTRUM_BAND_HZ = 0.05
"""Width of the signal outputs' frequency bands [Hz] (the records need >= 2 / 0.05 = 40 s)."""
SPECTRUM_EDGES_HZ = SPECTRUM_BAND_HZ * np.arange(51)
"""Band edges of the signal outputs, 0 to 2.5 Hz [Hz]: 1P, 3P, 6P and 9P at rated speed (0.2 Hz)."""
SIGNALS = (
    SignalOutput("front_Fz_spectrum", "N", "RMS of the front bearing's vertical force in 0.05 Hz bands (Hann "
                 "periodogram, mean removed; squares add to its variance)", "frequency", "Hz"),
    SignalOutput("front_Fy_spectrum", "N", "RMS of the front bearing's lateral force in 0.05 Hz bands",
                 "frequency", "Hz"),
    SignalOutput("rear_Fz_spectrum", "N", "RMS of the rear bearing's vertical force in 0.05 Hz bands",
                 "frequency", "Hz"),
    SignalOutput("hub_dz_spectrum", "m", "RMS of the hub end's vertical displacement in 0.05 Hz bands",
                 "frequency", "Hz"),
)
"""Components, not the radial magnitude: the front bearing's force vector passes through zero in turbulence
(its mean is a tenth of its spread at 11 m/s), where the magnitude's spectrum is not smooth in the parameters."""
DEFAULT_BENDING_MODES = 5
"""Bending modes per plane of the default shaft (Timoshenko elements): the smallest basis whose natural
frequencies below 150 Hz are within 0.5 % of a converged one (docs/physics.md). 150 Hz is the band of
interest (:mod:`ddgsa.models.basis`: 1.5 x the load interval's Nyquist frequency) of the finest load
interval the flexible fidelity takes, its 5 ms step, so the default is converged in every such scene on
either shaft reading (table1: 0.064 %, table2: 0.03 %); the table2 shaft's lateral modes below 150 Hz are
within 0.1 % of ROSS (``tests/models/test_direct_drive_oracles.py``), the table1 shaft's first bending and
torsion modes within 0.42 % of an exact continuous-shaft solution (``tests/models/test_direct_drive_shaft.py``)."""
RIGID_NAMES = ("R_x", "R_y", "R_z", "phi", "theta", "psi")
MODE_GROUPS = {"R_x": "bearing_axial", "R_y": "bearing_y", "psi": "bearing_y", "R_z": "bearing_z",
               "theta": "bearing_z", "phi": "spin", "axial": "axial_1", "torsion": "torsion_1",
               **{f: f for f in bending_fields(MAX_BENDING_MODES)}}


@dataclass(frozen=True)
class Assembly:
    """A built system with what the outputs need: ``system`` the compiled kernel's arrays of
    ``kernel``, the :class:`~ddgsa.mbs.assembly.System` of the kernel's parts it was packed from."""

    system: SystemArrays
    fields: tuple[str, ...]
    hub_s: NDArray[np.float64]
    gen_s: NDArray[np.float64]
    length: float
    kernel: System


def bearing_order_problem(p: Mapping[str, float]) -> str:
    """Why the bearing positions of ``p`` are invalid ("" when 0 < front < rear < shaft length)."""
    length, l1, l2 = p["shaft_length"], p["front_bearing_x"], p["rear_bearing_x"]
    if 0.0 < l1 < l2 < length:
        return ""
    return (f"bearing positions must satisfy 0 < front_bearing_x ({l1:g}) < rear_bearing_x ({l2:g}) "
            f"< shaft_length ({length:g}) [m]")


def build(p: Mapping[str, float], fields: tuple[str, ...],
          damping: tuple[str, str] = ("physical", "modal"), beam: str = "euler_bernoulli",
          shaft: str = DEFAULT_SHAFT) -> Assembly:
    """Build the system for one parameter set and the retained elastic fields.

    ``damping``: the readings of seed 000's bending Rayleigh law and bearing damping
    (:mod:`ddgsa.models.seed_readings`: ``bending_rayleigh``, ``bearing_damping``). ``beam``: the
    shaft's FE bending elements (:data:`ddgsa.mbs.beam.BEAMS`); ``timoshenko`` takes the shear
    stiffness ``kappa G A`` of the section (Cowper's ``kappa``, ``G = GJ / J``, Poisson's
    ratio from ``EI / I`` and ``G``) and gives the shaft its rotary inertia. ``shaft``: the shaft
    reading whose section (bore :data:`SHAFT_BORE`, 0 for the solid ``table1``) ``p``'s shaft has.

    Written on the kernel's parts (:mod:`ddgsa.mbs`): the shaft is a
    :meth:`~ddgsa.mbs.bodies.FlexibleBody.shaft` on its FE modes with the hub and generator as end
    inertias, the bearings are :class:`~ddgsa.mbs.elements.SpringDamper3` elements to the
    bedplate, the hub loads an :class:`~ddgsa.mbs.elements.AppliedLoad` point and the generator a
    :meth:`~ddgsa.mbs.elements.TorqueLaw.linear`; :func:`~ddgsa.mbs.system.single_body_arrays`
    packs that System for the compiled single-body integrators, which take the scene's loads,
    set speed and bedplate motion as inputs.
    """
    length, l1, l2 = p["shaft_length"], p["front_bearing_x"], p["rear_bearing_x"]
    problem = bearing_order_problem(p)
    if problem:
        raise ModelError(problem)
    r_o, bore = p["shaft_radius"], SHAFT_BORE[shaft]
    spec = BeamSpec(nodes=mesh([0.0, l1, l2, length], _MAX_ELEMENT), mass=p["shaft_mass"],
                    shear_stiffness=_shear_stiffness(p, bore) if beam == "timoshenko" else None,
                    polar_inertia=p["shaft_mass"] * (r_o ** 2 + min(bore, 0.8 * r_o) ** 2) / 2.0,
                    EI=p["shaft_bending_stiffness"], EA=p["shaft_axial_stiffness"],
                    GJ=p["shaft_torsional_stiffness"],
                    end_masses=((0.0, p["hub_mass"], p["hub_inertia_x"], p["hub_inertia_yz"]),
                                (length, p["generator_mass"], p["generator_inertia_x"], p["generator_inertia_yz"])),
                    supports=(l1, l2), axial_support=l1)
    shaft = _shaft(spec, fields, p["shaft_damping_ratio"], damping[0], beam == "timoshenko")
    bedplate = Ground("bedplate")                           # its motion is an input of the integrators
    k_sp = np.array([[p["k_front_x"], p["k_front_y"], p["k_front_z"]], [p["k_rear_x"], p["k_rear_y"], p["k_rear_z"]]])
    c_sp = bearing_damping(k_sp, shaft.mass, p["bearing_damping_ratio"], damping[1])
    bearings = [SpringDamper3(shaft.marker((x, 0.0, 0.0)), bedplate.marker((x, 0.0, 0.0)), k, c, name=name)
                for x, k, c, name in ((l1, k_sp[0], c_sp[0], "front"), (l2, k_sp[1], c_sp[1], "rear"))]
    hub = AppliedLoad(shaft.marker(), [0.0, 1.0], name="hub")                  # the scene's loads act here
    generator = TorqueLaw.linear(shaft.marker((length, 0.0, 0.0)), damping=p["c_gen"], name="generator")
    system = System([shaft], [*bearings, hub, generator], gravity=tilted_gravity())
    return Assembly(single_body_arrays(system), fields, hub.markers[0].shapes.copy(),
                    generator.markers[0].shapes.copy(), length, system)


_CHANNELS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz", "rotor_acceleration", "rotor_speed", "gen_torque", "one")
_ROTOR_ACC, _ROTOR_SPEED, _GEN_TORQUE, _ONE = 6, 7, 8, 9


@dataclass(frozen=True)
class SceneInputs:
    """The load channels of a scene that every parameter point's inputs are linear in.

    ``channels`` (n_t, 10): hub force ``Fx, Fy, Fz`` [N] and moment ``Mx, My, Mz`` [N m] (aerodynamic),
    the loads model's rotor acceleration [rad/s^2] and speed [rad/s], its controller torque [N m] and
    a column of ones; ``mean`` their time means; ``window`` the four-sample windows around each
    interval (:func:`ddgsa.mbs.linear.input_window`) of all but the column of ones (a constant
    input's drive is the same every step: :meth:`ddgsa.mbs.linear.ModalStep.outputs`), which the
    linear fidelity's modal drive multiplies.
    """

    scene: Scene
    channels: NDArray[np.float64]
    mean: NDArray[np.float64]
    window: NDArray[np.float64]

    @classmethod
    def of(cls, scene: Scene) -> SceneInputs:
        """The channels of ``scene``'s loads (:func:`ddgsa.loads.generate`)."""
        raw = generate_columns(scene, ["Fx", "Fy", "Fz", "Mx", "My", "Mz", "rotor_speed", "gen_torque"])
        channels = np.column_stack([raw[:, :6], np.gradient(raw[:, 6], scene.dt), raw[:, 6], raw[:, 7],
                                    np.ones(len(raw))])
        return cls(scene, channels, channels.mean(axis=0), input_window(channels[:, :_ONE]))


def input_map(p: Mapping[str, float]) -> NDArray[np.float64]:
    """``(10, 7)``: the model's inputs ``[F (3), M (3), w_set]`` = ``channels @ input_map(p)``
    (:class:`SceneInputs`) at parameters ``p``.

    Hub loads scaled by the excitation factors; ``M_x`` net of the blades' inertial torque
    ``(J_rotor,loads - J_hub - J_gen) d(w_loads)/dt`` (module notes); the generator's set speed
    ``w_set = w_loads - torque_factor T_ctrl / C_gen``: ``torque_factor`` scales the torque through
    the shaft, aerodynamic and generator alike, so the rotor keeps its speed (scaling ``M_x`` alone
    would spin the shaft up by ``dM_x / C_gen``).
    """
    m = np.zeros((len(_CHANNELS), 7))
    for i, name in enumerate(EXCITATION_FACTORS):                   # Fx, Fy, Fz, Mx, My, Mz order
        m[i, i] = p[name]
    m[_ROTOR_ACC, 3] = -(NREL5MW.rotor_inertia - p["hub_inertia_x"] - p["generator_inertia_x"])
    m[_ROTOR_SPEED, 6] = 1.0
    m[_GEN_TORQUE, 6] = -p["torque_factor"] / p["c_gen"]
    return m


def _shear_stiffness(p: Mapping[str, float], bore: float) -> float:
    """``kappa G A`` [N] of the shaft (outer radius ``shaft_radius``, bore radius ``bore`` [m], at most 0.8 of it)."""
    r_o = p["shaft_radius"]
    r_i = min(bore, 0.8 * r_o)
    area, j = np.pi * (r_o ** 2 - r_i ** 2), np.pi * (r_o ** 4 - r_i ** 4) / 2
    g = p["shaft_torsional_stiffness"] / j
    poisson = p["shaft_bending_stiffness"] / (j / 2) / (2 * g) - 1.0
    return shear_coefficient(poisson, r_i / r_o) * g * area


@functools.lru_cache(maxsize=16)
def _shaft(spec: BeamSpec, fields: tuple[str, ...], damping_ratio: float, rayleigh: str,
           rotary_inertia: bool = False) -> FlexibleBody:
    """The FE shaft body of ``spec`` (its modes are ~60 % of a linear point's set-up). Kept for the
    last specs seen: points that differ only in bearing stiffnesses, damping, C_gen, ratings or
    excitation (half of an M-DRM design, all of paper C's excitation study) share it; the body is
    never modified by the systems built on it, so sharing it is exact. ``rayleigh``: the bending
    Rayleigh reading (:func:`ddgsa.models.seed_readings.rayleigh_coefficients`)."""
    body = FlexibleBody.shaft("shaft", spec, fields=fields, damping_ratio=damping_ratio,
                              rotary_inertia=rotary_inertia)   # neglected but with Timoshenko elements (module notes)
    if rayleigh != "physical" and any(f.startswith("bending") for f in fields):
        pm, _, ps = body.points
        w1, w2 = 2.0 * np.pi * body.modes.freq_bending[:2]
        body.cff = bending_damping(fields, np.einsum("j,jai,jak->ik", pm, ps, ps), body.kff, body.cff,
                                   w1, w2, damping_ratio, rayleigh)
    return body


@functools.lru_cache(maxsize=256)
def assembled(params: tuple[tuple[str, float], ...], fields: tuple[str, ...],
              damping: tuple[str, str] = ("physical", "modal"), beam: str = "euler_bernoulli",
              shaft: str = DEFAULT_SHAFT) -> Assembly:
    """:func:`build` kept per exact parameter point (~30 % of a linear point's cost).

    A study evaluates every point in each scene and realisation (paper C: 60 times), and a
    worker's batches hold the same points, so all but its first batch reuse the systems. The
    system depends on the parameters only (loads are inputs) and nothing modifies it, so
    sharing it is exact. 256 systems of ~30 kB: more than a batch's points.
    """
    return build(dict(params), fields, damping, beam, shaft)


def _dd_basis(model: "DirectDrive") -> dict[str, Any] | None:
    """The direct drive's shaft basis as model options (``None`` at the rigid fidelity)."""
    if not model.fields:
        return None
    return {"bending_modes": sum(f.startswith("bending_y") for f in model.fields), "beam": model.beam,
            "axial": "axial" in model.fields, "shaft": model.shaft}


BASIS_RULE = BasisRule(
    reference={"bending_modes": 10},
    ladder=(({"bending_modes": 3}, "about the time of the default 5 (Timoshenko; 2 Euler-Bernoulli modes "
                                   "cost 0.7-0.85x)"),
            ({"bending_modes": 5}, "the default; with Timoshenko elements +15 to +40 % per linear run "
                                   "against 2 Euler-Bernoulli modes"),
            ({"bending_modes": 6}, "+10 % time per linear run against the default 5")),
    light={"bending_modes": 2}, fidelity="flexible", options=_dd_basis,
    band_hz=lambda model, scene: BAND_FACTOR * 0.5 / float(scene.dt),
    nominal=lambda: {s: {p.name: p.nominal for p in shaft_parameters(s)} for s in SHAFT},
    starts=lambda default: [default, *({**default, "shaft": s} for s in SHAFT if s != default["shaft"])])
"""The direct drive's shaft basis rule (:mod:`ddgsa.models.basis`): its outputs read its loads, whose band is
the load interval's Nyquist frequency ``1 / (2 dt)``; reference 10 modes per plane; the ladder's costs are CPU
per point of a 64-point batch of 600 s at the ``linear`` fidelity as ``ddgsa bench`` times it (load 11-12;
docs/physics.md "Cost of more modes"): the default 5 modes are converged below 284 Hz, 6 below 466 Hz. The
stored table holds each shaft reading (issue 47), the default's first; light: the seed's 2 modes."""


@register_model("direct_drive")
class DirectDrive(Model):
    """Direct-drive main shaft on two bearings (see the module docstring).

    Parameters
    ----------
    fidelity : {"flexible", "rigid"}
    axial, second_bending : bool
        Keep the axial mode / the second bending mode per plane (flexible only).
    bending_modes : int, optional
        Bending modes per plane (flexible and linear; 1 .. :data:`~ddgsa.mbs.bodies.MAX_BENDING_MODES`);
        default :data:`DEFAULT_BENDING_MODES` (5), or 1 with ``second_bending=False`` (docs/physics.md:
        convergence with the count).
    beam : {"timoshenko", "euler_bernoulli"}
        The shaft's FE bending elements (the shapes' basis); ``timoshenko`` (default) has shear and the
        shaft's rotary inertia (the second bending pair ~7 % below Euler-Bernoulli's, docs/physics.md).
    time_step : float, optional
        Integration step [s]; default 0.005 (flexible) or 0.01 (rigid), where halving it changes
        the objective functions by < 0.5 % (tested). The scene's ``dt`` must be a multiple. The
        ``linear`` fidelity integrates exactly between load samples and does not use it.
    rho_inf : float
        Generalised-alpha high-frequency spectral radius (default 0.8).
    integrator : {"gen_alpha", "Radau", "BDF"}
        The fixed-step generalised-alpha integrator, or scipy ``solve_ivp`` on the same
        equations (the reference path, ``rtol`` 1e-6; slow).
    equivalent_load : {"iso281", "seed"}
        Bearing equivalent-load rule for the damage indices.
    bending_rayleigh : {"physical", "printed"}
        Shaft bending Rayleigh law: ``delta = 2 zeta / (w1 + w2)`` or seed eq. (44a) as printed,
        ``2 zeta (w1 + w2)`` (:mod:`ddgsa.models.seed_readings`; ``docs/seed000_readings.md``).
    bearing_damping : {"modal", "stiffness_proportional"}
        Bearing dampers ``2 zeta sqrt(K m / 2)`` (zeta a ratio) or ``zeta K`` (Table 2's zeta in s).
    deflection : {"total", "frame", "elastic"}
        What the deflection objectives (and ``simulate``'s ``hub_d*``, ``gen_d*`` columns) measure:
        the shaft-end point's whole displacement, its floating frame's part (rigid-body motion)
        or its elastic part.
    deflection_reference : {"static", "mean"}
        Seed eq. (28)'s reference: the static equilibrium under the scene's mean loads (shaft not
        turning) or the record's time mean (the turning shaft's steady state; the two differ where
        the shaft's damping turns with it, as under the printed Rayleigh law).
    shaft : {"table1", "table2"}, optional
        The shaft reading (:mod:`ddgsa.models.seed_readings`): ``table1``, the solid steel shaft and
        thin-disc end inertias whose modes seed 000's Table 1 prints, or ``table2``, Table 2's
        EI = 1e9 N m^2 (a hollow 5 t shaft) with R1, R2 as radii of gyration. It sets the nominal
        values of the shaft's mass, EI, GJ, EA and the end inertias (:func:`shaft_parameters`) and
        the section's bore; default :data:`DEFAULT_SHAFT` (``docs/seed000_readings.md`` says why).
    """

    parameters = shaft_parameters(DEFAULT_SHAFT)
    basis_rule = BASIS_RULE
    outputs = OUTPUTS
    signal_outputs = SIGNALS
    fidelities = ("flexible", "rigid", "linear")
    options_note: ClassVar[str] = ("option shaft: table1 (solid steel shaft and disc end inertias of seed 000 Table 1) "
                                   "| table2 (Table 2's EI, hollow shaft) sets the nominal shaft mass, EI, GJ, EA "
                                   "and end inertias")
    options = (ModelOption("axial", "bool", "axial elastic coordinate"),
               ModelOption("second_bending", "bool", "second bending mode per plane"),
               ModelOption("bending_modes", "integer", "bending modes per plane (default 5; 1 without second_bending)",
                           1, MAX_BENDING_MODES, optional=True),
               ModelOption("beam", "choice", "shaft FE bending elements (default timoshenko)", choices=BEAMS),
               ModelOption("time_step", "number", "integration step (default 0.01 rigid, else 0.005)", 0.0, 0.1, "s",
                           low_open=True, optional=True),
               ModelOption("rho_inf", "number", "generalised-alpha spectral radius at infinity", 0.0, 1.0),
               ModelOption("equivalent_load", "choice", "bearing equivalent-load rule", choices=("iso281", "seed")),
               ModelOption("integrator", "choice", "time integrator (linear: its exact discretisation only)",
                           choices=("gen_alpha", "Radau", "BDF")),
               ModelOption("bending_rayleigh", "choice", "shaft bending damping: seed eq. 44a physical or as printed",
                           choices=BENDING_RAYLEIGH),
               ModelOption("bearing_damping", "choice", "bearing damping: modal 2 zeta sqrt(k m) or Table 2's C = zeta K",
                           choices=BEARING_DAMPING),
               ModelOption("deflection", "choice", "what the deflection outputs measure", choices=DEFLECTION),
               ModelOption("deflection_reference", "choice", "the deflection's quasi-static reference",
                           choices=DEFLECTION_REFERENCE),
               ModelOption("shaft", "choice", "shaft and end inertias: seed 000 Table 1's solid shaft or Table 2's EI",
                           choices=SHAFT, optional=True))

    def unused_parameters(self) -> dict[str, str]:
        """The shaft's elasticity, damping and radius at fidelity ``rigid`` (no elastic coordinates;
        the radius enters only the shaft's polar inertia, which the rigid body lumps)."""
        if self.fidelity != "rigid":
            return {}
        why = "has no effect at fidelity rigid (the shaft has no elastic coordinates{})"
        return {"shaft_bending_stiffness": why.format(""), "shaft_torsional_stiffness": why.format(""),
                "shaft_axial_stiffness": why.format(""), "shaft_damping_ratio": why.format(""),
                "shaft_radius": why.format("; the radius enters only the elastic shaft's polar inertia")}

    def point_problems(self, params: Mapping[str, float]) -> list[str]:
        """Why ``params`` (missing ones nominal) lie outside the valid region: crossing bearings."""
        problem = bearing_order_problem({**self.nominal, **params})
        return [problem] if problem else []

    def __init__(self, fidelity: str = "flexible", axial: bool = True, second_bending: bool = True,
                 bending_modes: int | None = None, beam: str = "timoshenko", time_step: float | None = None,
                 rho_inf: float = 0.8, equivalent_load: str = "iso281",
                 integrator: str = "gen_alpha", bending_rayleigh: str = "physical",
                 bearing_damping: str = "modal", deflection: str = "total",
                 deflection_reference: str = "static", shaft: str | None = None) -> None:
        self.check_options({"fidelity": fidelity, "axial": axial, "second_bending": second_bending,
                            "bending_modes": bending_modes, "beam": beam, "time_step": time_step, "rho_inf": rho_inf,
                            "equivalent_load": equivalent_load, "integrator": integrator,
                            "bending_rayleigh": bending_rayleigh, "bearing_damping": bearing_damping,
                            "deflection": deflection, "deflection_reference": deflection_reference, "shaft": shaft})
        self.shaft = DEFAULT_SHAFT if shaft is None else shaft
        self.parameters = shaft_parameters(self.shaft)
        if time_step is None:
            time_step = 0.01 if fidelity == "rigid" else 0.005
        self.integrator = integrator
        self.damping = (bending_rayleigh, bearing_damping)
        self.deflection = deflection
        # the rigid body has no bending shapes; it keeps the shaft's mass on the axis (module notes)
        self.beam = "euler_bernoulli" if fidelity == "rigid" else beam
        if bending_modes is None:
            bending_modes = DEFAULT_BENDING_MODES if second_bending else 1
        self.reference = deflection_reference
        self.fidelity = fidelity
        self._inputs: SceneInputs | None = None
        self.time_step = float(time_step)
        self.rho_inf = float(rho_inf)
        self.rule = equivalent_load
        if fidelity == "rigid":
            self.fields: tuple[str, ...] = ()
        else:
            self.fields = ("axial", "torsion")[0 if axial else 1:] + bending_fields(bending_modes, "by_plane")

    @property
    def coordinate_names(self) -> tuple[str, ...]:
        """Names of the generalised coordinates."""
        return RIGID_NAMES + self.fields

    def build(self, params: Mapping[str, float] | None = None) -> Assembly:
        """The system for ``params`` (missing -> nominal): the single-body kernel's arrays and the
        :class:`~ddgsa.mbs.assembly.System` they were packed from (:class:`Assembly`)."""
        return build(self.resolve(params).iloc[0].to_dict(), self.fields, self.damping, self.beam, self.shaft)

    def static(self, asm: Assembly, force: NDArray[np.float64], moment: NDArray[np.float64],
               q_guess: NDArray[np.float64] | None = None, tol: float = 1e-12) -> NDArray[np.float64]:
        """Static equilibrium under constant hub loads and gravity (spin angle held at 0).

        The generator holds the aerodynamic torque (``T0 = -M_x``). Newton iterations with the
        tangent stiffness (:func:`~ddgsa.mbs.system.static_state`); converged when the coordinate
        update is below ``tol`` (m or rad).
        """
        return static_state(asm.system, force, moment, torque0=-float(moment[0]), q_guess=q_guess, tol=tol)

    def simulate(self, scene: Scene, params: Mapping[str, float] | None = None) -> pd.DataFrame:
        """Time series of the scene: coordinates, rotor speed, end-point displacements, bearing forces, loads.

        Columns: the coordinates (``R_x`` ... ``psi`` [m, rad] and elastic coordinates),
        ``rotor_speed`` [rad/s], ``hub_dx, hub_dy, hub_dz`` and ``gen_dx, gen_dy, gen_dz`` (shaft-end
        displacements [m] of the ``deflection`` reading), ``front_Fx ... rear_Fz`` (forces on the
        bearings, shaft frame [N]),
        ``gen_torque`` [N m] and the hub loads ``Fx ... Mz`` applied (``Mx`` net of the blades'
        inertial torque). ``attrs`` carries the deflection objectives' reference
        (``static_hub``, ``static_gen``: the shaft-end displacements of the static solution for the
        mean loads, or the record's mean under ``deflection_reference="mean"``) and integrator statistics.
        """
        return self._simulate(scene, self.resolve(params).iloc[0].to_dict(), states=True)

    def _simulate(self, scene: Scene, p: Mapping[str, float], states: bool) -> pd.DataFrame:
        """:meth:`simulate` for resolved parameters ``p``; ``states=False`` lets the linear fidelity
        skip the coordinate columns (the objective functions do not read them)."""
        asm = build(p, self.fields, self.damping, self.beam, self.shaft)
        inputs = self._scene_inputs(scene)
        to_u = input_map(p)
        u = inputs.channels @ to_u
        forces, moments, w_set = u[:, 0:3], u[:, 3:6], u[:, 6]
        n_sub = max(1, int(round(scene.dt / self.time_step)))
        if abs(n_sub * self.time_step - scene.dt) > 1e-9 * scene.dt:
            raise ModelError(f"time_step {self.time_step} s must divide the scene's dt {scene.dt} s")
        # the quasi-static state under the mean loads: the reference of the deflection objectives
        # and the linear fidelity's operating point
        u0 = inputs.mean @ to_u
        q_st = self.static(asm, u0[0:3], u0[3:6])
        reference = deflection_ends(q_st[None, :], asm, self.deflection)[0]
        blocks: list[NDArray[np.float64]] = []
        names: list[str] = []
        if self.fidelity == "linear":
            res = self._linear_response(asm, q_st, to_u, inputs, scene.dt, states)
            ends, bearings = res["deflections"] + res["static_ends"], res["spring_forces"]
        else:
            q0 = self.static(asm, forces[0], moments[0], q_guess=q_st)      # start at rest under the first loads
            qd0 = np.zeros_like(q0)
            qd0[3] = inputs.channels[0, _ROTOR_SPEED]
            if self.integrator == "gen_alpha":
                self._check_step()
                res = integrate(asm.system, q0, qd0, scene.dt, n_sub, forces, moments, w_set, rho_inf=self.rho_inf)
            else:
                res = integrate_reference(asm.system, q0, qd0, np.arange(len(u)) * scene.dt, forces, moments,
                                          w_set, method=self.integrator)
            if res["failed_at"] >= 0:
                raise RuntimeError(f"integrator diverged at t = {res['failed_at'] * scene.dt:.3f} s "
                                   f"(step {self.time_step} s)")
            ends = deflection_ends(res["q"], asm, self.deflection)
            bearings = [res["spring_forces"][:, b, :] for b in range(2)]
        if "q" in res:
            blocks.append(res["q"])
            names += list(self.coordinate_names)
        blocks += [res["speed"][:, None] if "speed" in res else res["qd"][:, 3:4], ends]
        names += ["rotor_speed", "hub_dx", "hub_dy", "hub_dz", "gen_dx", "gen_dy", "gen_dz"]
        for b, name in enumerate(("front", "rear")):
            blocks.append(bearings[b])
            names += [f"{name}_Fx", f"{name}_Fy", f"{name}_Fz"]
        blocks += [res["torque"][:, None], forces, moments]
        names += ["gen_torque", "Fx", "Fy", "Fz", "Mx", "My", "Mz"]
        index = pd.Index(np.arange(len(u)) * scene.dt, name="time")
        out = pd.DataFrame(np.hstack(blocks), index=index, columns=names)   # one block: no per-column inserts
        if self.reference == "mean":
            reference = ends.mean(axis=0)
        out.attrs.update(static_hub=reference[:3], static_gen=reference[3:],
                         max_newton_iterations=res.get("max_iterations", 0),
                         mean_newton_iterations=res.get("mean_iterations", 0.0), fidelity=self.fidelity,
                         fields=self.fields)
        return out

    def _scene_inputs(self, scene: Scene) -> SceneInputs:
        """:class:`SceneInputs` of ``scene``, kept for the last scene seen (a batch of points shares them)."""
        cached = self._inputs
        if cached is None or cached.scene != scene:
            cached = self._inputs = SceneInputs.of(scene)
        return cached

    @functools.cached_property
    def nominal_modes(self) -> pd.DataFrame:
        """:meth:`modes` at the nominal parameters, standstill (computed once per instance)."""
        return self.modes()

    def sampling_checks(self, scene: Scene) -> list[dict[str, Any]]:
        """Integration step against the lowest mode (generalised-alpha fidelities) and the scene's
        load/controller interval against the highest."""
        modes = self.nominal_modes
        low, top = modes.loc[modes["frequency_hz"].idxmin()], modes.loc[modes["frequency_hz"].idxmax()]
        rows = []
        if self.fidelity != "linear":
            rows.append(sampling_row("integration step", self.time_step, low["frequency_hz"], low["label"],
                                     "the mode's period and damping are approximated (below 2 steps a period "
                                     "it is damped out); rigid objectives moved < 0.2 % from 10 to 2.5 ms"))
        return rows + [controller_row(scene.dt, top["frequency_hz"], top["label"])]

    def _check_step(self) -> None:
        """Aliasing guard (:mod:`ddgsa.mbs.sampling`): warn when the step does not resolve the lowest mode."""
        check_interval(self.time_step, float(self.nominal_modes["frequency_hz"].min()),
                       "direct_drive integration step", refuse=False, warn_below=NYQUIST)

    def _linear_response(self, asm: Assembly, q_st: NDArray[np.float64], to_u: NDArray[np.float64],
                         inputs: SceneInputs, dt: float, states: bool) -> dict[str, Any]:
        """The flexible model linearised about the scene's mean operating point, integrated exactly.

        Operating point: ``q_st``, the static state under the mean hub loads; spin at the mean set speed
        plus the slip of the mean torque; bending in non-rotating coordinates
        (:mod:`ddgsa.mbs.linear`). Valid while rotations stay small (they are ~1e-4 rad) and the
        rotor speed stays near its mean (gyroscopic terms are frozen at the mean speed). Every
        output is linear in the state: the bearing forces and the shaft-end displacements are
        linearised about the operating point too (the end points' rotation terms are of order
        ``L theta^2 ~ 1e-7 m``, 1e-5 of the deflections), so the response is one modal pass
        that forms only the rows asked for (``states``: also the coordinates and velocities).

        The inputs ``u = channels @ to_u`` (``to_u = input_map(p)``, built by the caller) are linear
        in the scene's load channels, so the modal drive of every point is one product with the
        channels' sample windows, which a batch of points of one scene shares (:class:`SceneInputs`).
        """
        u0 = inputs.mean @ to_u
        spin = float(u0[6] + u0[3] / asm.system.c_torque)            # torque balance: T = -M_x
        pairs = [(self.fields.index(f"bending_y_{k}"), self.fields.index(f"bending_z_{k}"))
                 for k in range(1, MAX_BENDING_MODES + 1) if f"bending_y_{k}" in self.fields]
        lin, springs = linearise_spinning(asm.system, np.delete(q_st, 3), spin, u0, pairs)
        npos, nvel = lin.k.shape[1], lin.m.shape[0]
        ends0, d_ends = deflection_jacobian(asm, lin.p0, self.deflection)
        # outputs C x with x = [dp, dv] (+ the operating speed and spring forces, + D du): speed, end
        # deflections about the operating point, spring forces
        c_out = np.zeros((1 + 6 + springs.y0.size, npos + nvel))
        c_out[0, npos + 3] = 1.0
        c_out[1:7, :npos] = d_ends
        c_out[7:, :npos], c_out[7:, npos:] = springs.d_p, springs.d_v
        if states:
            c_out = np.vstack([c_out, np.eye(npos + nvel)])
        # LTI inputs w = [u - u0, 1] = channels @ to_w
        to_w = np.zeros((to_u.shape[0], to_u.shape[1] + 1))
        to_w[:, :-1] = to_u
        to_w[_ONE, :-1] -= u0
        to_w[_ONE, -1] = 1.0
        a, bw = state_matrices(lin)
        x0 = initial_state(lin, inputs.channels[0] @ to_w)
        step = modal_step(a, bw, dt)
        if step is None:                                  # eigenvectors too ill-conditioned: dense recurrence
            y = lti_response(a, bw, inputs.channels @ to_w, dt, x0, c_out=c_out)
        else:
            y = step.outputs(inputs.window, x0, modal_output_matrix(step.vec, step.lam, c_out),
                             channel_map=to_w[:_ONE], constant=to_w[_ONE])
        # y holds C x: the end displacements' part is their deflection about the operating point
        # (the objectives' reference); speed and spring forces get their operating values
        # and the forces' feed-through (none for springs between body points and the bedplate)
        deflections = y[:, 1:7]
        y[:, 0] += spin
        y[:, 7:7 + springs.y0.size] += springs.y0
        if springs.d_u.any():
            y[:, 7:7 + springs.y0.size] += inputs.channels @ (to_w[:, :-1] @ springs.d_u.T)
        speed = y[:, 0]
        res = {"speed": speed, "deflections": deflections,
               "spring_forces": [y[:, 7 + 3 * b:10 + 3 * b] for b in range(2)], "static_ends": ends0,
               "max_iterations": 0}
        if states:
            res["torque"] = asm.system.c_torque * (inputs.channels @ to_u[:, 6] - speed)
            first = 7 + springs.y0.size
            pos = lin.p0 + y[:, first:first + npos]
            res["q"] = np.insert(pos, 3, 0.0, axis=1)                     # axis points do not see the spin angle
        return res

    def _linear_series(self, p: dict[str, float], scene: Scene) -> tuple[NDArray[np.float64], ...]:
        """The linear fidelity's records straight from the response arrays (no time-series frame):
        shaft-end deflections (n_t, 6) about the objectives' reference, speed, front and rear forces."""
        asm = assembled(tuple(p.items()), self.fields, self.damping, self.beam, self.shaft)
        inputs = self._scene_inputs(scene)
        to_u = input_map(p)
        u0 = inputs.mean @ to_u
        q_st = self.static(asm, u0[0:3], u0[3:6])
        res = self._linear_response(asm, q_st, to_u, inputs, scene.dt, states=False)
        ends = res["deflections"]            # about the operating point, which is the static state
        if self.reference == "mean":
            ends = ends - ends.mean(axis=0)
        return ends, res["speed"], *res["spring_forces"]

    def _series(self, p: dict[str, float], scene: Scene) -> tuple[NDArray[np.float64], ...]:
        """Shaft-end deflections (n_t, 6) about the reference, speed (n_t,), front and rear forces (n_t, 3)."""
        if self.fidelity == "linear":
            return self._linear_series(p, scene)
        sim = self._simulate(scene, p, states=False)
        ends = sim[["hub_dx", "hub_dy", "hub_dz", "gen_dx", "gen_dy", "gen_dz"]].to_numpy()
        ends = ends - np.concatenate([sim.attrs["static_hub"], sim.attrs["static_gen"]])
        front, rear = (sim[[f"{b}_F{c}" for c in "xyz"]].to_numpy() for b in ("front", "rear"))
        return ends, sim["rotor_speed"].to_numpy(), front, rear

    def _evaluate_one(self, params: dict[str, float], scene: Scene) -> dict[str, float]:
        if self.fidelity == "linear":
            ends, speed, front, rear = self._linear_series(params, scene)
            return objective_values(ends[:, 0:3], ends[:, 3:6], speed, front, rear, params, self.rule)
        sim = self._simulate(scene, params, states=False)
        return objectives(sim, params, self.rule)

    def signal_axis(self, name: str, scene: Any) -> NDArray[np.float64]:
        """Band centres [Hz] of the spectra (:data:`SPECTRUM_EDGES_HZ`); refuses a scene too short
        (under 40 s) or too coarse (``dt`` > 0.2 s) for them."""
        self.signal_output(name)
        if scene.duration < 2.0 / SPECTRUM_BAND_HZ or scene.dt > 0.5 / SPECTRUM_EDGES_HZ[-1]:
            raise ModelError(f"model 'direct_drive': signal {name!r} needs scenes of duration >= "
                             f"{2.0 / SPECTRUM_BAND_HZ:g} s and dt <= {0.5 / SPECTRUM_EDGES_HZ[-1]:g} s (bands of "
                             f"{SPECTRUM_BAND_HZ} Hz up to {SPECTRUM_EDGES_HZ[-1]:g} Hz); got duration "
                             f"{scene.duration:g} s, dt {scene.dt:g} s")
        return 0.5 * (SPECTRUM_EDGES_HZ[1:] + SPECTRUM_EDGES_HZ[:-1])

    def _evaluate_signals_one(self, params: dict[str, float], scene: Any,
                              signals: tuple[str, ...]) -> tuple[dict[str, float], dict[str, NDArray[np.float64]]]:
        """The outputs and the band spectra of one run (one simulation serves both)."""
        ends, speed, front, rear = self._series(params, scene)
        scalars = objective_values(ends[:, 0:3], ends[:, 3:6], speed, front, rear, params, self.rule)
        records = {"front_Fz_spectrum": front[:, 2], "front_Fy_spectrum": front[:, 1], "rear_Fz_spectrum": rear[:, 2],
                   "hub_dz_spectrum": ends[:, 2]}
        return scalars, {s: band_rms_spectrum(records[s], scene.dt, SPECTRUM_EDGES_HZ) for s in signals}

    def modes(self, params: Mapping[str, float] | None = None, rotor_speed: float = 0.0) -> pd.DataFrame:
        """Natural frequencies [Hz], damping ratios and labels about the static state under gravity.

        Linearised by the kernel's linearisation (:func:`ddgsa.mbs.modal.kind_jacobians` on the
        single-body kernel) with the spin angle held (cyclic) and the rotor turning at ``rotor_speed``
        [rad/s] (0: standstill; the bearings are anisotropic, so a spinning linearisation is a snapshot
        at spin angle 0).
        """
        asm = self.build(params)
        zero = np.zeros(3)
        q0 = self.static(asm, zero, zero)
        qd0 = np.zeros_like(q0)
        qd0[3] = rotor_speed
        keep = [i for i in range(q0.size) if i != 3]
        sizes = (3 * asm.system.sp_k.shape[0] + 1, 0, 0)
        m, c, k = kind_jacobians(kind, kind_context(asm.system, zero, zero, rotor_speed), sizes, q0, qd0, 0.0,
                                 np.zeros_like(q0), np.zeros(0), keep=keep, scales=(1.0, 1e-3))
        names = [self.coordinate_names[i] for i in keep]
        return modal_analysis(m, c, k, names, {n: MODE_GROUPS[n] for n in names})


def _rotations(q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Body rotation matrices (n_t, 3, 3) of the angles ``q[:, 3:6]`` (phi, theta, psi)."""
    phi, theta, psi = q[:, 3], q[:, 4], q[:, 5]
    cf, sf, ct, st, cp, sp = np.cos(phi), np.sin(phi), np.cos(theta), np.sin(theta), np.cos(psi), np.sin(psi)
    return np.stack([np.stack([cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf], -1),
                     np.stack([sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf], -1),
                     np.stack([-st, ct * sf, ct * cf], -1)], 1)


def end_positions(q: NDArray[np.float64], s_mat: NDArray[np.float64], x0: float,
                  rotations: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """Global positions (n_t, 3) of the shaft-axis point at ``x0`` with shapes ``s_mat`` (3, n_f);
    ``rotations`` :func:`_rotations` of ``q`` where the caller has them (both shaft ends share them)."""
    u = np.array([x0, 0.0, 0.0])[None, :] + q[:, 6:] @ s_mat.T                 # body frame (n_t, 3)
    a = _rotations(q) if rotations is None else rotations
    return q[:, :3] + np.einsum("tij,tj->ti", a, u)


def shaft_ends(q: NDArray[np.float64], asm: Assembly) -> NDArray[np.float64]:
    """Displacements (n_t, 6) [m] of the hub end and the generator end (from ``x = L``) at coordinates ``q``."""
    a = _rotations(q)
    out = np.hstack([end_positions(q, asm.hub_s, 0.0, a), end_positions(q, asm.gen_s, asm.length, a)])
    out[:, 3] -= asm.length
    return out


def frame_points(asm: Assembly) -> Assembly:
    """``asm`` with the end points' elastic shapes zeroed: its shaft ends are the floating frame's points."""
    return dataclasses.replace(asm, hub_s=np.zeros_like(asm.hub_s), gen_s=np.zeros_like(asm.gen_s))


def deflection_ends(q: NDArray[np.float64], asm: Assembly, reading: str) -> NDArray[np.float64]:
    """Shaft-end displacements (n_t, 6) [m] at coordinates ``q`` as the deflection ``reading`` takes
    them (:mod:`ddgsa.models.seed_readings`): :func:`shaft_ends` (``total``), its floating frame's
    part (``frame``) or the difference, the elastic part ``A S q_f`` (``elastic``)."""
    if reading == "total":
        return shaft_ends(q, asm)
    frame = shaft_ends(q, frame_points(asm))
    return frame if reading == "frame" else shaft_ends(q, asm) - frame


def deflection_jacobian(asm: Assembly, p0: NDArray[np.float64],
                        reading: str) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """:func:`_end_jacobian` of the deflection ``reading`` (as :func:`deflection_ends`)."""
    if reading == "total":
        return _end_jacobian(asm, p0)
    frame = _end_jacobian(frame_points(asm), p0)
    if reading == "frame":
        return frame
    total = _end_jacobian(asm, p0)
    return total[0] - frame[0], total[1] - frame[1]


def _end_jacobian(asm: Assembly, p0: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Shaft-end displacements ``[hub (3), gen (3)]`` [m] at positions ``p0`` (no spin angle: ``[R,
    theta, psi, q_f]``) and their Jacobian (6, n_p), in closed form.

    An end at ``x0`` with shapes ``S`` sits at ``R + A(0, theta, psi) (x0 e_x + S q_f)`` (``A`` of
    :func:`_rotations` at spin angle 0), so its derivatives are ``I`` along ``R``, ``dA/dtheta u`` and
    ``dA/dpsi u`` along the tilts and ``A S`` along the elastic coordinates.
    """
    theta, psi, qf = p0[3], p0[4], p0[5:]
    ct, st, cp, sp = math.cos(theta), math.sin(theta), math.cos(psi), math.sin(psi)
    a = np.array([[cp * ct, -sp, cp * st], [sp * ct, cp, sp * st], [-st, 0.0, ct]])
    a_theta = np.array([[-cp * st, 0.0, cp * ct], [-sp * st, 0.0, sp * ct], [-ct, 0.0, -st]])
    a_psi = np.array([[-sp * ct, -cp, -sp * st], [cp * ct, -sp, cp * st], [0.0, 0.0, 0.0]])
    ends = np.empty(6)
    jac = np.zeros((6, p0.size))
    for rows, x0, shapes in ((slice(0, 3), 0.0, asm.hub_s), (slice(3, 6), asm.length, asm.gen_s)):
        u = shapes @ qf
        u[0] += x0
        ends[rows] = p0[0:3] + a @ u
        jac[rows, 0:3] = np.eye(3)
        jac[rows, 3] = a_theta @ u
        jac[rows, 4] = a_psi @ u
        jac[rows, 5:] = a @ shapes
    ends[3] -= asm.length
    return ends, jac


def objectives(sim: pd.DataFrame, params: Mapping[str, float], rule: str) -> dict[str, float]:
    """Objective functions of a simulation (seed 000 §3.2.1 plus force statistics); the shaft-end
    displacement columns and their static values (``attrs``) are those of the model's deflection reading."""
    hub = sim[["hub_dx", "hub_dy", "hub_dz"]].to_numpy()
    gen = sim[["gen_dx", "gen_dy", "gen_dz"]].to_numpy()
    front, rear = (sim[[f"{b}_F{c}" for c in "xyz"]].to_numpy() for b in ("front", "rear"))
    return objective_values(hub - sim.attrs["static_hub"], gen - sim.attrs["static_gen"], sim["rotor_speed"].to_numpy(),
                            front, rear, params, rule)


def objective_values(hub: NDArray[np.float64], gen: NDArray[np.float64], speed: NDArray[np.float64],
                     front: NDArray[np.float64], rear: NDArray[np.float64], params: Mapping[str, float],
                     rule: str) -> dict[str, float]:
    """The outputs from time series: ``hub``, ``gen`` (n_t, 3) shaft-end deflections about the
    quasi-static state [m], ``speed`` (n_t,) [rad/s], ``front``, ``rear`` (n_t, 3) forces on the
    bearings [N]; ``rule`` the equivalent-load rule."""
    n = len(speed)
    out = {"rms_deflection_hub": float(np.sqrt(np.einsum("ij,ij->", hub, hub) / n)),
           "rms_deflection_gen": float(np.sqrt(np.einsum("ij,ij->", gen, gen) / n))}
    for name, f, rating in (("front", front, params["bearing_C_front"]), ("rear", rear, params["bearing_C_rear"])):
        fr = np.sqrt(f[:, 1] ** 2 + f[:, 2] ** 2)          # no overflow at bearing loads (np.hypot is 5x slower)
        fa = np.abs(f[:, 0])
        out[f"damage_{name}"] = damage_rate(fr, fa, speed, rating, rule)
        out[f"{name}_Fr_mean"] = float(fr.mean())
        out[f"{name}_Fa_mean"] = float(fa.mean())
    return {k: out[k] for k in OUTPUTS}
