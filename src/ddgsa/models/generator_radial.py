"""Radial generator degree of freedom of a direct-drive turbine with magnetic pull (seed 003).

The rotating assembly (rotor assembly + generator rotor, mass ``m_rot``) sits on a rigid shaft
whose tilt and axial motion are constrained (seed 003 Fig. 5); two main bearings act as radial
springs ``c_B`` each, and the magnetic pull of the air gap (:mod:`ddgsa.models.electromagnetic`)
acts in parallel as a negative stiffness on the eccentricity, the rotor's displacement relative
to the stator. Configurations (``config``):

``one_mass``
    The seed's §2.1 estimate: one horizontal DOF on a rigid support,
    ``f = sqrt(2 c_B / m_rot) / 2 pi`` (34.5 Hz for 10 GN/m and 426.7 t).
``substructure``
    The drive-train substructure of seed Fig. 4(b): both radial directions (y horizontal,
    z up), gravity sag, hub forces, the pull acting on the eccentricity vector. Linearised
    about the sagged state the pull is slightly anisotropic.
``tower_side_to_side``, ``tower_torsion``
    The substructure coupled to the tower through the reduced 2-DOF-2-mass model of seed
    Eq. 2: a tower mass ``m_1`` on a linearised tower spring ``c_i,lin`` (Table 3:
    3.48e6 N/m side-to-side, 2.55e9 N/m torsion, with ``m_1 + m_2`` = 2 446 t) carries the
    stator; the rotor's horizontal DOF couples to it through the bearings.
``tower_bending_torsion``
    The one-step reading of seed 003 §3.1 ("the coupled system mode in the full
    electro-mechanical model couples the bending and torsion mode"): both tower paths of
    Table 3 carry the stator at once. A tower-top body translates side-to-side (``m_1`` on
    ``c_SS,lin`` = 3.48e6 N/m) and yaws (tower torsion, ``c_tor,lin`` = 2.55e9 N/m and an
    apparent mass ``J / l^2`` at the generator, both taken at the lever ``l`` from the tower
    axis to the generator centre); the stator sits at ``l``, so its lateral motion is
    ``x_1 = y + l gamma`` (seed Eq. 2's ``x_1 = gamma l``). The seed gives no ``l``: the body
    is built at :data:`TORSION_LEVER` with ``J = m_tor l^2`` and ``c_tor = c_tor,lin l^2``, so
    the modes do not depend on it. Reading ``table3`` (the default): the torsion path's apparent
    mass is Table 3's ``m_1`` as well (Table 3 derives both stiffnesses from the one
    ``m_1 + m_2`` = 2 446 t). The seed prints ``c_tor,lin = c_tor / l``, dimensionally a
    stiffness per radian, not per metre; Eq. 2 uses it as N/m with ``x_1`` in m, which is how it
    is read here (either way the linear stiffness at the generator is Table 3's 2.55e9 N/m).

Each configuration runs with or without the magnetic forces (``magnetic``). Damping is not
given in the seed: a bearing damping ratio (of the one-mass mode) and a tower damping ratio
are parameters (2 % and 1 %).

Assembly on the multibody kernel (:mod:`ddgsa.mbs`): the rotating assembly is a
:class:`~ddgsa.mbs.RigidBody` whose axial motion and rotations are held by a
:class:`~ddgsa.mbs.Lock` to the ground (``one_mass`` locks its vertical motion too); the two
bearings are :class:`~ddgsa.mbs.SpringDamper3` elements to the stator (the ground, or the tower
mass: a rigid body locked except for its side-to-side motion, and in ``tower_bending_torsion`` its yaw,
on a tower :class:`~ddgsa.mbs.Bushing6` to the ground; the stator then sits at the lever ``l``);
the pull is a :class:`~ddgsa.mbs.RadialForce` whose law is :func:`pull_vector` and
:func:`pull_jacobian` of :mod:`ddgsa.models.electromagnetic`; the mean hub forces are an
:class:`~ddgsa.mbs.AppliedLoad`, gravity the system's. The static state is
:func:`ddgsa.mbs.statics.static_equilibrium` (Newton, nonlinear pull), the linearisation and
modes those of :mod:`ddgsa.mbs.modal` on the null space of the locks.

Time response: the hub forces ``Fy, Fz`` of the scene act on the rotor, scaled by
``hub_force_factor``. The load generator's rotor is the option ``rotor``: ``iea15mw`` (default,
the IEA 15 MW reference rotor the seed models, :data:`ddgsa.loads.IEA15MW`) or ``nrel5mw`` (the
NREL 5-MW rotor, the loads of this model before issue 47). Where the hub moments ``My, Mz`` go is
the option ``hub_moments``. ``lock`` (default): as in the seed's Fig. 5(b) ("only radial movements
are possible, tilting and axial movements are constraint"), the rotor's tilt lock takes them and the
two bearing springs carry the same radial force. ``bearings``: the rigid rotating assembly is held in
tilt by its two main bearings, so they carry the moments as a couple over their spacing (1.2 m in
the IEA 15 MW layout, :data:`_BEARING_PARAMETERS`): :func:`bearing_loads` splits the springs'
summed force by rotational equilibrium about the centre of mass; the eccentricity, the modes and the
translation are the same as under ``lock`` (the tilt stays rigid: the rocking mode is not modelled;
``hub_force_factor`` scales the hub forces, not the moments).
Bearing radial forces of both readings against the seed's "100 kN to 1 MN" are in docs/models.md
("The 15 MW generator's hub loads and its bearing forces"). The system is linearised about the
static state under gravity and the mean hub forces and integrated exactly for the C1 cubic load input (the state matrices
of :mod:`ddgsa.mbs.integrate.exact`, :func:`ddgsa.mbs.linear.lti_response`; the load fluctuation
enters through the rotor marker's Jacobian) on an output grid of at least
:data:`ddgsa.mbs.sampling.RESOLVED` samples per period of the highest mode. Validity: the pull
is linearised about the static eccentricity; each evaluation measures the nonlinear pull at
the peak eccentricity against the linearised one and fails (recorded, not imputed) when they
differ by more than 1 % of the bearing force.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from ddgsa.errors import ModelError
from ddgsa.loads import ROTORS, generate
from ddgsa.loads.scene import Scene
from ddgsa.mbs import AirGapPull, AppliedLoad, Bushing6, Ground, Lock, RadialForce, RigidBody, SpringDamper3, System
from ddgsa.mbs.statics import static_equilibrium
from ddgsa.mbs.constraints import AXES
from ddgsa.mbs.linear import lti_response, state_matrices
from ddgsa.mbs.modal import ConstrainedLinearisation, linearise_system, modal_analysis
from ddgsa.mbs.series import sub_sampled
from ddgsa.mbs.sampling import RESOLVED, AliasingWarning, check_interval, sampling_row
from ddgsa.models.base import Model, ModelOption, ModelOutput, ModelParameter, controller_row, register_model
from ddgsa.models.constants import GRAVITY
from ddgsa.models.electromagnetic import PMGenerator, pull_jacobian, pull_vector, radial_pull

CONFIGS = ("one_mass", "substructure", "tower_side_to_side", "tower_torsion", "tower_bending_torsion")
TOTAL_MASS_TABLE3 = 2446e3
"""``m_1 + m_2`` of seed 003 Table 3 [kg]."""
TOWER_STIFFNESS = {"tower_side_to_side": 3.48e6, "tower_torsion": 2.55e9}
"""Linearised tower stiffness ``c_i,lin`` of seed 003 Table 3 [N/m]."""
TOWER_LABELS = {"tower_side_to_side": ("tower_side_to_side",), "tower_torsion": ("tower_torsion",),
                "tower_bending_torsion": ("tower_side_to_side", "tower_torsion")}
"""Labels of each tower configuration's tower modes, in ascending frequency at nominal."""
TORSION_LEVER = 1.0
"""Lever ``l`` [m] from the tower axis to the generator centre that ``tower_bending_torsion`` builds its
tower-top body with (seed 003 gives none; the modes do not depend on it, see the module)."""
HUB_MOMENTS = ("bearings", "lock")
"""Readings of where the hub moments go (``hub_moments``, see the module)."""
ROTOR_ASSEMBLY_SHARE = 274.9 / 426.7
"""Share of the rotor assembly (blades and hub, at the hub centre) in the rotating mass (seed 003 §2.1:
274.9 t of 426.7 t; the rest, the generator rotor, sits at the generator centre) [-]."""
LINEARISATION_TOLERANCE = 0.01
"""Largest allowed pull linearisation error at the peak eccentricity, relative to the bearing force."""

_BASE_PARAMETERS = (
    ModelParameter("bearing_stiffness", 10e9, "N/m", "radial stiffness of each of the two main bearings", 1e7, 1e13),
    ModelParameter("rotating_mass", 426.7e3, "kg", "rotor assembly (274.9 t) + generator rotor (151.8 t)", 1e3, 1e8),
    ModelParameter("air_gap", 0.010, "m", "mechanical air gap at zero eccentricity", 1e-3, 0.1),
    ModelParameter("magnet_remanence", 1.28, "T", "remanent flux density B_r of the magnets", 0.1, 2.0),
    ModelParameter("magnet_height", 0.1, "m", "radial magnet height h_m", 1e-3, 0.5),
    ModelParameter("bearing_damping_ratio", 0.02, "-", "damping ratio of the one-mass bearing mode", 0.0, 1.0),
    ModelParameter("hub_force_factor", 1.0, "-", "scale on the scene's radial hub forces Fy, Fz", 0.0, 100.0),
)


_BEARING_PARAMETERS = (
    ModelParameter("front_bearing_x", 4.97, "m",
                   "hub centre to the front main bearing along the shaft (IEA 15 MW: hub radius 3.97 m + 1.0 m)",
                   0.0, 50.0),
    ModelParameter("rear_bearing_x", 6.17, "m",
                   "hub centre to the rear main bearing along the shaft (front + the 1.2 m bearing spacing)",
                   0.0, 50.0),
    ModelParameter("generator_x", 5.57, "m",
                   "hub centre to the generator centre (its rotor's mass and the pull; between the bearings)",
                   0.0, 50.0),
)
"""The drive train's axial layout, read where the hub moments reach the bearings (``hub_moments:
bearings``): IEA-15-240-RWT windIO ``distance_hub_mb`` 1.0 m and ``distance_mb_mb`` 1.2 m from the hub
flange, taken at the hub radius; the generator centred between the bearings (seed 003 Fig. 5)."""


def bearing_loads(total: ArrayLike, hub_force: ArrayLike, hub_moment: ArrayLike, pull: ArrayLike,
                  layout: Mapping[str, float]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Radial forces on the front and rear main bearing [N] of a rigid rotating assembly that translates
    without tilting, the two bearings carrying its moments as a couple (``hub_moments: bearings``).

    The translation gives the bearings' summed force; rotational equilibrium about the assembly's
    centre of mass (where its weight and its inertia act, so neither has a moment there) splits it:
    ``(x_f - x_c) P_f + (x_r - x_c) P_r = Q`` with ``P_f + P_r = total`` and
    ``Q_y = -x_c F_hub,y + (x_g - x_c) F_pull,y + M_z``, ``Q_z = -x_c F_hub,z + (x_g - x_c) F_pull,z - M_y``
    (shaft frame: X from the hub towards the generator, Z up; the hub at ``x = 0``; ``x_c`` the centre of
    mass, :data:`ROTOR_ASSEMBLY_SHARE` of the mass at the hub and the rest at ``x_g``).

    Parameters
    ----------
    total : (n, 2)
        Summed force of the rotor on both bearings, y and z [N].
    hub_force : (n, 2)
        Hub force on the rotor ``(F_y, F_z)`` at the hub centre [N].
    hub_moment : (n, 2)
        Hub moment on the rotor ``(M_y, M_z)`` [N m].
    pull : (n, 2)
        Magnetic pull on the rotor at the generator centre [N].
    layout : mapping
        ``front_bearing_x``, ``rear_bearing_x``, ``generator_x`` [m] from the hub centre.

    Returns
    -------
    front, rear : (n, 2)
        Force of the rotor on each bearing, y and z [N].

    Examples
    --------
    A pure tilt moment of 1.2 MN m over a 1.2 m spacing: +-1 MN vertical.

    >>> front, rear = bearing_loads([[0.0, 0.0]], [[0.0, 0.0]], [[1.2e6, 0.0]], [[0.0, 0.0]],
    ...                             {"front_bearing_x": 5.0, "rear_bearing_x": 6.2, "generator_x": 5.6})
    >>> (front / 1e6).round(6).tolist(), (rear / 1e6).round(6).tolist()
    ([[0.0, 1.0]], [[0.0, -1.0]])
    """
    total, f_hub, m_hub, f_pull = (np.asarray(a, dtype=float).reshape(-1, 2) for a in (total, hub_force, hub_moment,
                                                                                          pull))
    x_f, x_r, x_g = layout["front_bearing_x"], layout["rear_bearing_x"], layout["generator_x"]
    if not x_r > x_f:
        raise ModelError(f"model 'generator_radial': rear_bearing_x ({x_r} m) must lie behind front_bearing_x "
                         f"({x_f} m)")
    x_c = (1.0 - ROTOR_ASSEMBLY_SHARE) * x_g
    q = -x_c * f_hub + (x_g - x_c) * f_pull + np.column_stack([m_hub[:, 1], -m_hub[:, 0]])
    rear = (q - (x_f - x_c) * total) / (x_r - x_f)
    return total - rear, rear


def _tower_parameters(config: str) -> tuple[ModelParameter, ...]:
    both = config == "tower_bending_torsion"
    base = (
        ModelParameter("tower_mass", TOTAL_MASS_TABLE3 - 426.7e3, "kg",
                       "non-rotating mass of tower and tower top m_1 (seed 003 Table 3: m_1 + m_2 = 2 446 t)",
                       1e3, 1e9),
        ModelParameter("tower_stiffness", TOWER_STIFFNESS["tower_side_to_side" if both else config], "N/m",
                       "linearised tower stiffness c_i,lin at the generator (seed 003 Table 3)"
                       + (", side-to-side" if both else ""), 1e3, 1e13),
        ModelParameter("tower_damping_ratio", 0.01, "-", "damping ratio of each tower path on its own", 0.0, 1.0),
    )
    if not both:
        return base
    return base + (
        ModelParameter("tower_torsion_stiffness", TOWER_STIFFNESS["tower_torsion"], "N/m",
                       "tower torsion's linearised stiffness c_tor,lin at the generator (seed 003 Table 3)", 1e3, 1e13),
        ModelParameter("tower_torsion_mass", TOTAL_MASS_TABLE3 - 426.7e3, "kg",
                       "tower torsion's apparent mass at the generator J / l^2 (reading table3: Table 3's m_1)",
                       1e3, 1e9),
    )


def magnetic_pull(eccentricity: ArrayLike, params: Mapping[str, float] | None = None) -> NDArray[np.float64]:
    """Net radial magnetic force [N] towards the smallest gap at radial ``eccentricity`` [m].

    ``params`` overrides the generator data by name: the model parameters ``air_gap``,
    ``magnet_remanence``, ``magnet_height`` and the other :class:`PMGenerator` fields
    (``pole_arc_ratio``, ``carter_factor``, ``sectors``...). Defaults: IEA 15 MW (seed 003 Table 2).

    Examples
    --------
    >>> round(float(magnetic_pull(1e-3)) / 1e3)      # kN at 1 mm
    283
    """
    return radial_pull(eccentricity, PMGenerator().updated(params))


@dataclass(frozen=True)
class Operating:
    """The assembled system linearised about its static state, and the maps the model reads.

    Attributes
    ----------
    system : System
    lin : ConstrainedLinearisation
        ``M z'' + C z' + K z = N^T dQ`` on the free coordinates ``q = q0 + N z``.
    static_ecc : (n_dir,) static eccentricity [m] (y[, z])
    ecc_map : (n_dir, n_z) eccentricity per unit ``z`` [m]
    load_map : (n_z, n_dir) generalised force per unit hub force (Fy[, Fz]), ``hub_force_factor`` included
    tower_row : (n_z,) or None, tower displacement per unit ``z`` (tower configurations)
    """

    system: System
    lin: ConstrainedLinearisation
    static_ecc: NDArray[np.float64]
    ecc_map: NDArray[np.float64]
    load_map: NDArray[np.float64]
    tower_row: NDArray[np.float64] | None


OUTPUTS = (
    ModelOutput("bearing_frequency_hz", "Hz", "natural frequency of the bearing radial mode (bearing_radial)",
                1.0, 200.0),
    ModelOutput("tower_frequency_hz", "Hz", "natural frequency of the (lowest) tower mode (tower configurations only)",
                0.05, 20.0),
    ModelOutput("static_eccentricity_m", "m", "static radial eccentricity of the generator rotor in the air gap",
                0.0, 0.02),
    ModelOutput("peak_eccentricity_m", "m", "largest radial eccentricity of the generator rotor over the scene",
                0.0, 0.02),
    ModelOutput("rms_dynamic_eccentricity_m", "m", "RMS of the eccentricity about its static value", 0.0, 0.02),
    ModelOutput("peak_bearing_force_n", "N", "largest radial force on a main bearing, static plus dynamic", 0.0, 1e8),
    ModelOutput("peak_dynamic_bearing_force_n", "N",
                "largest change of a main bearing's radial force from its mean over the scene (the wind's part)",
                0.0, 1e8),
)


@register_model("generator_radial")
class GeneratorRadial(Model):
    """Radial generator DOF with magnetic pull, alone or coupled to a tower mode (see the module).

    Parameters
    ----------
    config : str
        ``one_mass``, ``substructure``, ``tower_side_to_side``, ``tower_torsion`` or
        ``tower_bending_torsion`` (the one-step reading: both tower paths at once).
    magnetic : bool
        Include the magnetic pull (negative stiffness).
    fidelity : str
        Only ``linearised`` (about the static state; see the module for its validity check).
    output_step : float, optional
        Output interval [s]; must divide the scene's ``dt``. Default: the largest such interval
        with at least 10 samples per period of the highest mode. Below 2 samples per period it is
        refused (the output would alias), below 10 warned (peaks under-resolved).
    generator : mapping, optional
        Overrides of further :class:`PMGenerator` fields (``pole_arc_ratio``, ``carter_factor``,
        ``sectors``, ``air_gap_radius``, ``core_length``, ``relative_permeability``).
    rotor : str
        Reference rotor of the hub loads (:data:`ddgsa.loads.ROTORS`): ``iea15mw`` (the seed's
        turbine, default) or ``nrel5mw`` (the reading before issue 47).
    hub_moments : str
        ``lock`` (default, the seed's Fig. 5: tilt constrained, the lock takes the hub moments, both
        bearings carry the same radial force) or ``bearings`` (the rigid assembly's tilt held by the
        two main bearings: the moments reach them as a couple, :func:`bearing_loads`; adds the layout
        parameters ``front_bearing_x``, ``rear_bearing_x``, ``generator_x``).

    Outputs
    -------
    ``bearing_frequency_hz`` (the ``bearing_radial`` mode), ``tower_frequency_hz`` (tower
    configurations), ``static_eccentricity_m``, ``peak_eccentricity_m`` and
    ``rms_dynamic_eccentricity_m`` (|e - e_static|) [m], ``peak_bearing_force_n`` (the front or
    rear bearing, dynamic + static) and ``peak_dynamic_bearing_force_n`` (its largest change from
    the record's mean: the wind's part) [N].
    """

    fidelities: ClassVar[tuple[str, ...]] = ("linearised",)
    options = (ModelOption("config", "choice", "configuration", choices=CONFIGS),
               ModelOption("magnetic", "bool", "magnetic pull on"),
               ModelOption("output_step", "number", "output interval", 0.0, math.inf, "s", low_open=True,
                           optional=True),
               ModelOption("generator", "mapping", "generator air-gap fields to change", optional=True),
               ModelOption("rotor", "choice", "reference rotor of the hub loads", choices=tuple(ROTORS)),
               ModelOption("hub_moments", "choice", "where the hub moments go", choices=HUB_MOMENTS))
    options_note: ClassVar[str] = ("options: config one_mass | substructure (default) | tower_side_to_side | "
                                   "tower_torsion | tower_bending_torsion, magnetic true | false, output_step [s], "
                                   "generator {field: value}, rotor iea15mw (default) | nrel5mw, hub_moments "
                                   "lock (default) | bearings; tower_* configs add tower_mass [kg], tower_stiffness "
                                   "[N/m], tower_damping_ratio [-] and the output tower_frequency_hz; "
                                   "tower_bending_torsion adds tower_torsion_stiffness [N/m], tower_torsion_mass [kg]; "
                                   "hub_moments bearings adds front_bearing_x, rear_bearing_x, generator_x [m]")

    def __init__(self, config: str = "substructure", magnetic: bool = True, fidelity: str = "linearised",
                 output_step: float | None = None, generator: Mapping[str, float] | None = None,
                 rotor: str = "iea15mw", hub_moments: str = "lock") -> None:
        self.check_options({"fidelity": fidelity, "config": config, "magnetic": magnetic, "output_step": output_step,
                            "generator": generator, "rotor": rotor, "hub_moments": hub_moments})
        self.config, self.magnetic, self.fidelity = config, magnetic, fidelity
        self.rotor, self.hub_moments = rotor, hub_moments
        self.output_step = output_step
        self.generator = PMGenerator().updated(dict(generator or {}))
        bad = set(generator or {}) - set(PMGenerator.__dataclass_fields__)
        if bad:
            raise ModelError(f"model 'generator_radial': unknown generator field(s) {sorted(bad)}; "
                             f"known: {', '.join(PMGenerator.__dataclass_fields__)}")
        self.tower = config.startswith("tower_")
        self.tower_labels = TOWER_LABELS.get(config, ())
        self.parameters = (_BASE_PARAMETERS + (_tower_parameters(config) if self.tower else ())
                           + (_BEARING_PARAMETERS if hub_moments == "bearings" else ()))
        tower_coords = ("tower_y", "tower_rz")[: len(self.tower_labels)]
        self.coordinates = tower_coords + (("rotor_y",) if config == "one_mass" else ("rotor_y", "rotor_z"))
        self.outputs = tuple(o for o in OUTPUTS if self.tower or o != "tower_frequency_hz")

    # -- physics -------------------------------------------------------------------------
    def _gen(self, p: Mapping[str, float]) -> PMGenerator:
        return self.generator.updated({k: p[k] for k in ("air_gap", "magnet_remanence", "magnet_height")})

    def _pull(self, ecc: NDArray[np.float64], gen: PMGenerator) -> NDArray[np.float64]:
        """Pull on the rotor in the model's eccentricity directions [N]."""
        f = pull_vector(ecc[0], ecc[1] if ecc.size > 1 else 0.0, gen)
        return f[: ecc.size]

    def _pull_stiffness(self, ecc: NDArray[np.float64], gen: PMGenerator) -> NDArray[np.float64]:
        """``d pull / d ecc`` [N/m] in the model's eccentricity directions."""
        j = pull_jacobian(float(ecc[0]), float(ecc[1]) if ecc.size > 1 else 0.0, gen)
        return j[: ecc.size, : ecc.size]

    def _law(self, gen: PMGenerator) -> Any:
        """The pull of the air gap as the law of a :class:`~ddgsa.mbs.RadialForce` (force, tangent): the
        kernel's compiled air gap (:class:`~ddgsa.mbs.AirGapPull`), so the element packs."""
        return AirGapPull(gen.constants)

    def build(self, params: Mapping[str, float] | None = None,
               mean_hub_force: NDArray[np.float64] | None = None) -> tuple[System, RigidBody, Any]:
        """The configuration assembled from kernel parts, the mean hub forces ``(Fy, Fz)`` [N] applied.

        Returns the system, the rotor body and the stator marker (ground or tower).
        """
        return self._build(self.resolve(params).iloc[0].to_dict(), mean_hub_force)

    def _build(self, p: Mapping[str, float],
                  mean_hub_force: NDArray[np.float64] | None) -> tuple[System, RigidBody, Any]:
        free = ("y",) if self.config == "one_mass" else ("y", "z")
        both = self.config == "tower_bending_torsion"
        lever = TORSION_LEVER if both else 0.0
        rotor = RigidBody("rotor", p["rotating_mass"], (1.0, 1.0, 1.0), position=(lever, 0.0, 0.0))  # rotations locked
        ground = Ground()
        bodies, elements = [rotor], []
        constraints = [Lock(rotor.marker(), axes=tuple(a for a in AXES if a not in free), name="rotor_guide")]
        stator = ground.marker()
        if self.tower:
            bodies.append(tower := self._tower_body(p, lever))
            constraints.append(Lock(tower.marker(), axes=("x", "z", "rx", "ry") + (() if both else ("rz",)),
                                    name="tower_guide"))
            k6, c6 = self._tower_bushing(p, lever)
            elements.append(Bushing6(tower.marker(), ground.marker(), k6, c6, name="tower"))
            stator = tower.marker((lever, 0.0, 0.0))
        c_b = p["bearing_stiffness"]
        d_b = p["bearing_damping_ratio"] * math.sqrt(2 * c_b * p["rotating_mass"])   # one bearing: half of 2 zeta sqrt(2 c_B m)
        for name in ("bearing_front", "bearing_rear"):
            elements.append(SpringDamper3(rotor.marker(), stator, (0.0, c_b, c_b), (0.0, d_b, d_b), name=name))
        if self.magnetic:
            elements.append(RadialForce(rotor.marker(), stator, self._law(self._gen(p)), name="magnetic_pull"))
        f_hub = np.zeros(2) if mean_hub_force is None else np.asarray(mean_hub_force, dtype=float)[:2]
        force = np.array([0.0, *(f_hub * p["hub_force_factor"])])
        elements.append(AppliedLoad(rotor.marker(), [0.0, 1.0], force=[force, force], name="hub_mean"))
        gravity = (0.0, 0.0, 0.0 if self.config == "one_mass" else -GRAVITY)
        return System(bodies, elements, constraints, gravity=gravity), rotor, stator

    def _tower_body(self, p: Mapping[str, float], lever: float) -> RigidBody:
        """Tower-top body: mass ``m_1`` [kg]; yaw inertia ``m_tor l^2`` [kg m^2] where it yaws."""
        j_z = p["tower_torsion_mass"] * lever ** 2 if "tower_torsion_mass" in p else 1.0
        return RigidBody("tower", p["tower_mass"], (1.0, 1.0, j_z))

    def _tower_bushing(self, p: Mapping[str, float], lever: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """6 x 6 stiffness and damping of the tower at its top: side-to-side [N/m] and, in
        ``tower_bending_torsion``, yaw ``c_tor,lin l^2`` [N m/rad]; each path damped at
        ``tower_damping_ratio`` of its 2-DOF mode with the rotor rigidly attached."""
        k6, c6 = np.zeros((6, 6)), np.zeros((6, 6))
        m_rot, zeta = p["rotating_mass"], p["tower_damping_ratio"]
        k6[1, 1] = p["tower_stiffness"]
        c6[1, 1] = zeta * 2 * math.sqrt(k6[1, 1] * (p["tower_mass"] + m_rot))
        if "tower_torsion_stiffness" in p:
            c_lin = p["tower_torsion_stiffness"]
            k6[5, 5] = c_lin * lever ** 2
            c6[5, 5] = zeta * 2 * math.sqrt(c_lin * (p["tower_torsion_mass"] + m_rot)) * lever ** 2
        return k6, c6

    def operating(self, params: Mapping[str, float] | None = None,
                  mean_hub_force: NDArray[np.float64] | None = None) -> Operating:
        """Static state under gravity (not in ``one_mass``) and the mean hub forces, and the linearisation there.

        Raises
        ------
        RuntimeError
            When the pull exceeds the bearings (no equilibrium inside the gap: the rotor would
            close the gap, or the centred rotor is unstable).
        """
        return self._operating(self.resolve(params).iloc[0].to_dict(), mean_hub_force)

    def _operating(self, p: Mapping[str, float], mean_hub_force: NDArray[np.float64] | None) -> Operating:
        system, rotor, stator = self._build(p, mean_hub_force)
        try:
            q0, _ = static_equilibrium(system, tol=1e-15, analytic=True)
        except (ValueError, ModelError) as exc:
            raise RuntimeError(f"no static equilibrium inside the air gap against the magnetic pull ({exc})") from None
        zero = np.zeros(system.n)
        lin = linearise_system(system, q0, zero, 0.0, analytic=True)    # at rest, exact element tangents
        if np.linalg.eigvalsh(0.5 * (lin.k + lin.k.T)).min() <= 0:
            raise RuntimeError("magnetic pull stiffness exceeds the bearings': no stable centred rotor")
        n_dir = 1 if self.config == "one_mass" else 2
        js_r, js_s = system.marker_state(rotor.marker(), q0, zero, 0.0), system.marker_state(stator, q0, zero, 0.0)
        rows = slice(1, 1 + n_dir)                                    # y[, z]
        ecc_map = (js_r.jac[rows] - js_s.jac[rows]) @ lin.basis
        tower_row = lin.basis[system.index("tower.y")] if self.tower else None
        return Operating(system, lin, (js_r.r - js_s.r)[rows], ecc_map,
                         lin.basis.T @ js_r.jac[rows].T * p["hub_force_factor"], tower_row)

    # -- Model interface -----------------------------------------------------------------
    def modes(self, params: Mapping[str, float] | None = None, rotor_speed: float = 0.0) -> pd.DataFrame:
        """Natural frequencies [Hz], damping ratios and labels about the static state under gravity
        (at standstill: a nonzero ``rotor_speed`` is refused).

        Labels: ``bearing_radial`` (horizontal rotor mode; with a tower, the out-of-phase coupled
        mode), ``bearing_radial_vertical`` and the tower configuration's name for the tower mode.
        """
        self.standstill_only(rotor_speed)
        op = self.operating(params)
        names = {"rotor_y": "bearing_radial", "rotor_z": "bearing_radial_vertical",
                 **dict(zip(("tower_y", "tower_rz"), self.tower_labels))}
        groups = {c.replace("_", "."): names[c] for c in self.coordinates}
        lin = op.lin
        out = modal_analysis(lin.m, lin.c, lin.k, op.system.coord_names, groups, lin.basis, lin.m_full)
        # a degenerate pair (isotropic bearings, no pull) in coordinate order: horizontal first
        rank = out["label"].map({g: i for i, g in enumerate(groups.values())}).fillna(len(groups))
        bucket = np.round(np.log(out["frequency_hz"].to_numpy()) * 1e9)
        out = out.iloc[np.lexsort((rank.to_numpy(), bucket))].reset_index(drop=True)
        if self.tower:      # horizontal modes: the lower (in-phase) ones are the tower's, whatever their energy split
            horizontal = out.index[out["share_bearing_radial_vertical"] < 0.5]     # ascending frequency
            out.loc[horizontal, "label"] = [*self.tower_labels, "bearing_radial"]
        return out

    def output_interval(self, scene: Scene, highest_hz: float) -> tuple[float, int]:
        """Output interval [s] and sub-steps per scene sample; checked by the aliasing guard."""
        if self.output_step is None:
            n_sub = max(1, math.ceil(scene.dt * RESOLVED * highest_hz))
        else:
            n_sub = max(1, int(round(scene.dt / self.output_step)))
            if abs(n_sub * self.output_step - scene.dt) > 1e-9 * scene.dt:
                raise ModelError(f"model 'generator_radial': output_step {self.output_step} s must divide "
                                 f"the scene's dt {scene.dt} s")
        h = scene.dt / n_sub
        check_interval(h, highest_hz, "generator_radial output interval", refuse=True)
        return h, n_sub

    def sampling_checks(self, scene: Scene) -> list[dict[str, Any]]:
        """Output interval and the scene's load/controller interval against the highest mode."""
        modes = self.modes()
        top = modes.loc[modes["frequency_hz"].idxmax()]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", AliasingWarning)
            h, _ = self.output_interval(scene, float(top["frequency_hz"]))
        return [sampling_row("generator_radial output interval", h, top["frequency_hz"], top["label"],
                             "sampled peaks under-resolved"),
                controller_row(scene.dt, top["frequency_hz"], top["label"])]

    def simulate(self, scene: Scene, params: Mapping[str, float] | None = None) -> pd.DataFrame:
        """Time series on the output grid: eccentricity ``ecc_y[, ecc_z]`` [m], its magnitude
        ``eccentricity`` [m], each bearing's spring force ``bearing_Fy[, bearing_Fz]`` [N] (half the
        radial load), the force on the front and the rear bearing ``front_Fy, rear_Fy[, front_Fz,
        rear_Fz]`` [N] (with ``hub_moments: bearings`` the spring force plus the hub moments' couple,
        :func:`bearing_loads`; with ``lock`` the spring force, the lock taking the moments) and
        ``tower_y`` [m] in tower configurations. ``attrs``: ``static_eccentricity`` [m],
        ``output_step`` [s], ``linearisation_error`` (pull at the peak, relative to the bearing force).
        """
        p = self.resolve(params).iloc[0].to_dict()
        loads = generate(scene, ROTORS[self.rotor])
        hub = loads[["Fy", "Fz"]].to_numpy()
        op = self._operating(p, hub.mean(axis=0))
        lin, n_dir = op.lin, op.ecc_map.shape[0]
        highest_hz = float(np.sqrt(np.linalg.eigvals(np.linalg.solve(lin.m, lin.k)).real.max()) / (2 * np.pi))
        h, n_sub = self.output_interval(scene, highest_hz)
        nz = lin.m.shape[0]
        a, bw = state_matrices(lin)                 # inputs [N^T dQ, 1]; dQ = J_rotor^T dF_hub, N^T Q_0 = 0 at rest
        w = hub[:, :n_dir] - hub[:, :n_dir].mean(axis=0)
        x0 = np.concatenate([np.linalg.solve(lin.k, op.load_map @ w[0]), np.zeros(nz)])
        x = lti_response(a, bw[:, :nz] @ op.load_map, w, scene.dt, x0, n_sub)
        ecc = op.static_ecc + x[:, :nz] @ op.ecc_map.T
        ecc_rate = x[:, nz:] @ op.ecc_map.T
        bearing = op.system.elements[op.system.element_names.index("bearing_front")]
        force = bearing.k6[1, 1] * ecc + bearing.c6[1, 1] * ecc_rate
        time = loads.index[0] + h * np.arange(len(x))
        out = pd.DataFrame(ecc, index=pd.Index(time, name="time"), columns=["ecc_y", "ecc_z"][:n_dir])
        out["eccentricity"] = np.linalg.norm(ecc, axis=1)
        out[["bearing_Fy", "bearing_Fz"][:n_dir]] = force
        front, rear = force, force
        if self.hub_moments == "bearings":
            front, rear = self._couple(p, op.static_ecc, ecc, force, loads, n_sub)
        for name, f in (("front", front), ("rear", rear)):
            out[[f"{name}_Fy", f"{name}_Fz"][:n_dir]] = f
        if op.tower_row is not None:
            out["tower_y"] = lin.q0[op.system.index("tower.y")] + x[:, :nz] @ op.tower_row
        out.attrs.update(static_eccentricity=op.static_ecc, output_step=h,
                         linearisation_error=self._linearisation_error(p, op.static_ecc, ecc))
        return out

    def _couple(self, p: Mapping[str, float], static_ecc: NDArray[np.float64], ecc: NDArray[np.float64],
                force: NDArray[np.float64], loads: pd.DataFrame,
                n_sub: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Front and rear bearing forces [N] on the output grid (:func:`bearing_loads`): the two springs'
        force, the hub loads (their C1 cubic, as the response integrated them; forces scaled by
        ``hub_force_factor``) and the linearised pull."""
        n_dir = ecc.shape[1]
        hub = sub_sampled(loads[["Fy", "Fz", "My", "Mz"]].to_numpy(), n_sub)
        pull = np.zeros_like(ecc)
        if self.magnetic:
            gen = self._gen(p)
            pull = self._pull(static_ecc, gen) + (ecc - static_ecc) @ self._pull_stiffness(static_ecc, gen).T
        pad = np.zeros((len(ecc), 2 - n_dir))
        front, rear = bearing_loads(np.hstack([2.0 * force, pad]), hub[:, :2] * p["hub_force_factor"], hub[:, 2:],
                                    np.hstack([pull, pad]), p)
        return front[:, :n_dir], rear[:, :n_dir]

    def _linearisation_error(self, p: Mapping[str, float], static_ecc: NDArray[np.float64],
                             ecc: NDArray[np.float64]) -> float:
        """|F_mag(e_peak) - linearised F_mag(e_peak)| over the bearing force there."""
        if not self.magnetic:
            return 0.0
        gen = self._gen(p)
        i = int(np.argmax(np.linalg.norm(ecc - static_ecc, axis=1)))
        de = ecc[i] - static_ecc
        exact = self._pull(ecc[i], gen) - self._pull(static_ecc, gen)
        lin = self._pull_stiffness(static_ecc, gen) @ de
        return float(np.linalg.norm(exact - lin) / (2 * p["bearing_stiffness"] * np.linalg.norm(ecc[i])))

    def _evaluate_one(self, params: dict[str, float], scene: Scene) -> dict[str, float]:
        sim = self.simulate(scene, params)
        err = sim.attrs["linearisation_error"]
        if err > LINEARISATION_TOLERANCE:
            raise ValueError(f"linearised magnetic pull off by {err:.1%} of the bearing force at the peak "
                             f"eccentricity (validity band {LINEARISATION_TOLERANCE:.0%})")
        modes = self.modes(params)
        freq = dict(zip(modes["label"], modes["frequency_hz"]))
        ecc = sim[["ecc_y", "ecc_z"][: len(sim.attrs["static_eccentricity"])]].to_numpy()
        force = np.hstack([sim[[c for c in sim.columns if c.startswith(side)]].to_numpy()
                           for side in ("front_F", "rear_F")]).reshape(len(sim), 2, -1)
        out: dict[str, Any] = {"bearing_frequency_hz": freq["bearing_radial"]}
        if self.tower:
            out["tower_frequency_hz"] = freq[self.tower_labels[0]]
        out.update(static_eccentricity_m=float(np.linalg.norm(sim.attrs["static_eccentricity"])),
                   peak_eccentricity_m=float(sim["eccentricity"].max()),
                   rms_dynamic_eccentricity_m=float(np.sqrt(np.mean(np.sum(
                       (ecc - sim.attrs["static_eccentricity"]) ** 2, axis=1)))),
                   peak_bearing_force_n=float(np.linalg.norm(force, axis=2).max()),
                   peak_dynamic_bearing_force_n=float(np.linalg.norm(force - force.mean(axis=0), axis=2).max()))
        return out
