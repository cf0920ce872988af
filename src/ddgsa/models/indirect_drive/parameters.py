"""Declared parameters of the indirect drive (thesis paper D), each with its unit, range and source.

Frame: the drive-train frame of :mod:`ddgsa.loads.hubloads` -- X along the low-speed shaft from
the hub (x = 0) towards the gearbox, Z up (perpendicular to the tilted shaft), Y = Z x X. All
positions are x coordinates along the LSS axis [m].

Sources, in order of preference:

- **NREL/TP-500-38060** (Jonkman, Butterfield, Musial & Scott 2009, *Definition of a 5-MW
  reference wind turbine*, Table 5-1): gear ratio 97, generator inertia 534.116 kg m^2 about the
  HSS, equivalent drive-shaft torsional stiffness 867.637 MN m/rad and damping 6.215 MN m s/rad
  (both referred to the LSS). The report gives no bearing positions, shaft sizes, gearbox mass
  or mount stiffnesses.
- The loads model (:data:`ddgsa.loads.NREL5MW`): the rotor's polar inertia.
- Seed 000 Table 2 / the direct drive (:mod:`ddgsa.models.direct_drive`): main-bearing position
  1.0 m from the hub, the hub's mass, polar and diametral inertia (one description of the rotor
  hub for both wind models, :mod:`ddgsa.models.constants`), generator torque constant, bearing
  load ratings -- kept equal so that ``indirect_vs_direct`` compares drive trains, not rotors.
- **Assumptions** (no source gives them; each is a parameter a study can vary):
  LSS and HSS geometry, gearbox bearing positions, housing mass and inertia, mount positions,
  stiffnesses and damping, the pitch radius of the wheel. Stated one by one below.

Assumptions, with the reasoning:

- LSS: hollow steel shaft, outer radius 0.35 m, bore 0.15 m, length 4.2 m (hub flange to the
  LSS end 0.2 m behind the rear gearbox bearing): mass 10.36 t, EI = 2.39e9 N m^2, EA = 6.60e10 N (E = 210 GPa,
  rho = 7850 kg/m^3). Its torsional stiffness is **not** the steel's: the NREL *equivalent*
  drive-train stiffness and damping act between the rotor and the gear wheel, lumping the
  shaft, gearbox and HSS torsional compliance into one LSS spring as the NREL model does.
- Gearbox bearings: LSS bearings at 3.0 m (point 1) and 4.0 m (point 3), HSS bearings at 3.2 m
  (point 2) and 3.8 m (point 4), the mesh plane at 3.5 m (seed 001 Fig. 2.2 topology, sizes
  assumed: a 1.0 m long gearbox behind a 2.0 m main-shaft span).
- Gear stage: one external spur stage (seed 001 §2.2: "1 stage gearbox"), wheel pitch radius
  1.0 m (assumed; first stages of multi-MW gearboxes have pitch diameters of 1.5-2 m), pinion
  pitch radius ``r_w / N`` so the pitch circles roll without slip at the ratio N; pressure
  angle 20 deg (ISO 53 standard basic rack). A single 97:1 stage is the paper's idealisation,
  not a buildable gear: the whole mesh force (4.5 MN at rated torque) passes through one
  1 cm pinion, so HSS bearing forces are those of the stage, not of a real three-stage gearbox.
- HSS: rigid shaft with pinion, 1000 kg, diametral inertia 200 kg m^2 (assumed: a 1.2 m,
  0.15 m radius shaft with coupling half); its polar inertia is the NREL generator inertia (the
  generator rotor is coupled torsionally rigidly; its weight is carried by the generator's own
  bearings on the bedplate and is not in this model).
- Housing: rigid box 2.0 m (x) x 2.5 m x 2.5 m, 40 t (multi-MW gearboxes weigh 30-50 t),
  centre of mass on the LSS axis at the mesh plane; inertias of a homogeneous box:
  J_x = m (2.5^2 + 2.5^2)/12 = 4.17e4, J_y = J_z = m (2.0^2 + 2.5^2)/12 = 3.42e4 kg m^2.
- Mounts (torque arms): two 6-DOF elastomer bushings at (gear_x, +-1.2 m, 0) to the bedplate,
  2e8 N/m vertical, 1e8 N/m axial and lateral per mount (order of magnitude of gearbox torque-arm
  elastomers in flexible-multibody studies of gearbox suspensions, e.g. seed 001 ref. [5]; not a
  quoted value), damping ratio 0.05 (elastomer loss factor ~0.1) as
  ``c = 2 zeta sqrt(k m_housing / 2)``. Torsional mount stiffness about the LSS axis
  ``2 k_z d^2`` = 5.76e8 N m/rad: 7.3 mm vertical motion at the arm under rated torque.
- Bearing load ratings: 1e7 N for all five bearings (the direct drive's main bearings; damage
  indices are compared relative to each other, seed 000 §4).
"""

from __future__ import annotations

import math

from ddgsa.loads import C_GEN_DEFAULT, EXCITATION_FACTORS, NREL5MW
from ddgsa.models.base import ModelParameter
from ddgsa.models.constants import HUB_INERTIA_X, HUB_INERTIA_YZ, HUB_MASS

#: NREL/TP-500-38060 Table 5-1: gearbox ratio [-]
NREL_GEAR_RATIO = 97.0
#: NREL/TP-500-38060 Table 5-1: generator inertia about the high-speed shaft [kg m^2]
NREL_GENERATOR_INERTIA = 534.116
#: NREL/TP-500-38060 Table 5-1: equivalent drive-shaft torsional spring, referred to the LSS [N m/rad]
NREL_TORSIONAL_STIFFNESS = 867.637e6
#: NREL/TP-500-38060 Table 5-1: equivalent drive-shaft torsional damper, referred to the LSS [N m s/rad]
NREL_TORSIONAL_DAMPING = 6.215e6
#: the direct drive's generator rotor polar inertia, part of the loads model's rotor inertia [kg m^2]
_DIRECT_DRIVE_GENERATOR_INERTIA = 7.5e3
#: polar inertia of the rotor (blades and hub) the loads model spins [kg m^2]
ROTOR_INERTIA = NREL5MW.rotor_inertia - _DIRECT_DRIVE_GENERATOR_INERTIA

BEARINGS = ("main", "lss1", "lss3", "hss2", "hss4")
"""Bearing names (seed 001 Fig. 2.2 numbering): the main bearing to the bedplate, the LSS bearings
in the housing (points 1, 3) and the HSS bearings in the housing (points 2, 4)."""

PARAMETERS = (
    # geometry along the LSS axis
    ModelParameter("lss_length", 4.2, "m", "low-speed shaft length, hub flange (x = 0) to its rear end "
                   "(assumed)", 1.0, 20.0),
    ModelParameter("main_bearing_x", 1.0, "m", "main bearing position from the hub (seed 000 Table 2 L1)",
                   0.05, 19.0),
    ModelParameter("lss_bearing_1_x", 3.0, "m", "front LSS bearing in the housing, point 1 (assumed)", 0.1, 19.9),
    ModelParameter("gear_x", 3.5, "m", "gear mesh plane; the housing's centre of mass (assumed)", 0.1, 19.9),
    ModelParameter("lss_bearing_3_x", 4.0, "m", "rear LSS bearing in the housing, point 3 (assumed)", 0.1, 20.0),
    ModelParameter("hss_bearing_2_x", 3.2, "m", "front HSS bearing in the housing, point 2 (assumed)", 0.1, 25.0),
    ModelParameter("hss_bearing_4_x", 3.8, "m", "rear HSS bearing in the housing, point 4 (assumed)", 0.1, 25.0),
    # rotor
    ModelParameter("hub_mass", HUB_MASS, "kg", "rotor mass on the LSS flange (seed 000 Table 2 m1, as the "
                   "direct drive)", 1.0, 1e6),
    ModelParameter("rotor_inertia_x", ROTOR_INERTIA, "kg m^2", "rotor (blades and hub) polar inertia, the "
                   "loads model's NREL 5-MW rotor: the drive-train torsion turns all of it", 1.0, 1e9),
    ModelParameter("hub_inertia_x", HUB_INERTIA_X, "kg m^2", "the part of the rotor's polar inertia that tilts "
                   "with the LSS flange (the hub's, as the direct drive; the blades' flap flexibility "
                   "decouples the rest), so its gyroscopic moment acts on the shaft", 1.0, 1e9),
    ModelParameter("hub_inertia_yz", HUB_INERTIA_YZ, "kg m^2", "rotor diametral inertia carried by the shaft "
                   "(the hub's, as the direct drive)", 1.0, 1e10),
    # low-speed shaft
    ModelParameter("lss_mass", 10360.0, "kg", "LSS mass (hollow steel, r 0.35 / 0.15 m, assumed)", 1.0, 1e5),
    ModelParameter("lss_radius", 0.35, "m", "LSS outer radius (enters its polar inertia only)", 0.01, 2.0),
    ModelParameter("lss_bending_stiffness", 2.39e9, "N m^2", "LSS bending stiffness EI (hollow steel)",
                   1e6, 1e12),
    ModelParameter("lss_axial_stiffness", 6.60e10, "N", "LSS axial stiffness EA (hollow steel)", 1e7, 1e13),
    ModelParameter("drivetrain_torsional_stiffness", NREL_TORSIONAL_STIFFNESS, "N m/rad",
                   "equivalent drive-train torsional stiffness referred to the LSS, hub to mesh "
                   "(NREL/TP-500-38060)", 1e6, 1e12),
    ModelParameter("drivetrain_torsional_damping", NREL_TORSIONAL_DAMPING, "N m s/rad",
                   "equivalent drive-train torsional damping referred to the LSS (NREL/TP-500-38060)", 0.0, 1e10),
    ModelParameter("lss_damping_ratio", 0.01, "-", "LSS bending modal damping ratio (as the direct drive)",
                   0.0, 1.0),
    # gear stage and high-speed side
    ModelParameter("gear_ratio", NREL_GEAR_RATIO, "-", "gear ratio N = HSS speed / LSS speed "
                   "(NREL/TP-500-38060)", 1.0, 300.0),
    ModelParameter("gear_pitch_radius", 1.0, "m", "wheel (LSS) pitch radius r_w; pinion r_w / N (assumed)",
                   0.05, 5.0),
    ModelParameter("pressure_angle", math.radians(20.0), "rad", "gear pressure angle (ISO 53: 20 deg)",
                   0.0, math.radians(35.0)),
    ModelParameter("generator_inertia", NREL_GENERATOR_INERTIA, "kg m^2", "generator inertia about the HSS "
                   "(NREL/TP-500-38060)", 1.0, 1e6),
    ModelParameter("hss_mass", 1000.0, "kg", "HSS with pinion and coupling half (assumed)", 1.0, 1e5),
    ModelParameter("hss_inertia_yz", 200.0, "kg m^2", "HSS diametral inertia (assumed)", 0.01, 1e5),
    ModelParameter("c_gen", C_GEN_DEFAULT, "N m s/rad", "generator torque constant referred to the LSS "
                   "(seed 000 eq. 25); on the HSS it is c_gen / N^2", 1e3, 1e9),
    # housing and its mounts
    ModelParameter("housing_mass", 40000.0, "kg", "gearbox housing with gears (assumed)", 1.0, 1e6),
    ModelParameter("housing_inertia_x", 4.17e4, "kg m^2", "housing inertia about the LSS axis (2.0 x 2.5 x "
                   "2.5 m box)", 1.0, 1e8),
    ModelParameter("housing_inertia_y", 3.42e4, "kg m^2", "housing inertia about the lateral axis", 1.0, 1e8),
    ModelParameter("housing_inertia_z", 3.42e4, "kg m^2", "housing inertia about the vertical axis", 1.0, 1e8),
    ModelParameter("mount_arm", 1.2, "m", "lateral distance of each torque-arm mount from the LSS axis "
                   "(assumed)", 0.1, 5.0),
    ModelParameter("k_mount_x", 1.0e8, "N/m", "mount stiffness per mount, axial (assumed)", 1e5, 1e12),
    ModelParameter("k_mount_y", 1.0e8, "N/m", "mount stiffness per mount, lateral (assumed)", 1e5, 1e12),
    ModelParameter("k_mount_z", 2.0e8, "N/m", "mount stiffness per mount, vertical (assumed)", 1e5, 1e12),
    ModelParameter("mount_damping_ratio", 0.05, "-", "mount damping ratio zeta, c = 2 zeta sqrt(k m_h / 2)",
                   0.0, 1.0),
    # bearing ratings for the damage indices
    *(ModelParameter(f"bearing_C_{b}", 1.0e7, "N", f"{b} bearing dynamic load rating C (as the direct "
                     "drive's main bearings)", 1e5, 1e9) for b in BEARINGS),
    # excitation factors on the hub loads (seed 001 paper C)
    *(ModelParameter(name, 1.0, "-", f"multiplier on the hub load {col}", 0.0, 10.0)
      for name, col in EXCITATION_FACTORS.items()),
)

NOMINAL = {p.name: p.nominal for p in PARAMETERS}
