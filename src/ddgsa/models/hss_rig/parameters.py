"""Declared parameters of the test rig: unit, nominal, allowed range, description and source.

The rig of seed 001 paper A (thesis Fig. 1.4) -- induction motor, motor shaft, flexible shaft
coupling, high-speed shaft on two rolling bearings in housings on elastic supports, disk with
an eccentric mass, brake/generator load -- is rebuilt from first principles: the paper's tables
are not available to us, so every value below is a plausible lab-scale choice with its source
or the reasoning behind it (``SOURCES``). Layout along the shaft axis ``x`` (motor to load)::

    motor rotor --motor shaft-- hub | coupling | hub --overhang-- bearing 1 ====== disk ====== bearing 2
                                                                  (drive end)   (eccentric     (non-drive end)
                                                                                 mass, load)

The faults are parameters whose **healthy value is the nominal**: ``eccentric_mass`` (unbalance
growth above the residual 5 g), ``misalignment_parallel`` and ``misalignment_angular`` (0),
``defect_amplitude`` (0: no outer-race spall), ``housing_looseness`` (0: no support stiffness
lost) and ``supply_unbalance`` (0: balanced supply). :data:`FAULTS` lists them.
"""

from __future__ import annotations

import math

from ddgsa.models.base import ModelParameter
from ddgsa.models.hss_rig.bearing import SKF_6205
from ddgsa.models.hss_rig.motor import LAB_MOTOR

SOURCES: dict[str, str] = {}
"""Parameter name -> where its nominal value comes from."""


def _p(name: str, nominal: float, unit: str, description: str, low: float, high: float,
       source: str) -> ModelParameter:
    SOURCES[name] = source
    return ModelParameter(name, nominal, unit, description, low, high)


_KRAUSE = "Krause, Analysis of Electric Machinery, Table 6.10-1 (3-hp, 4-pole machine)"
_STEEL = "structural steel (EN 10025): E = 210 GPa, nu = 0.3, rho = 7850 kg/m^3"
_JAW = ("order of a size-24 elastomer jaw coupling in manufacturers' catalogues (KTR ROTEX 24: "
        "dynamic torsional stiffness 1e3-1e4 N m/rad, radial 1e6 N/m); assumption")
_ASSUMED = "assumption (lab-scale value, see docs/hss_rig.md)"
_DISK = "steel disk 0.25 m diameter x 0.039 m thick (m = rho pi r^2 h, Ip = m r^2/2, Id = m r^2/4 + m h^2/12)"

MOTOR = (
    _p("stator_resistance", LAB_MOTOR.stator_resistance, "Ohm", "stator resistance R_s per phase", 0.0, 10.0,
       _KRAUSE),
    _p("rotor_resistance", LAB_MOTOR.rotor_resistance, "Ohm", "rotor resistance R_r per phase, referred to the stator",
       0.01, 10.0, _KRAUSE),
    _p("stator_leakage_inductance", LAB_MOTOR.stator_leakage_inductance, "H", "stator leakage inductance L_ls",
       1e-5, 0.1, _KRAUSE + ": X_ls = 0.754 Ohm at 60 Hz"),
    _p("rotor_leakage_inductance", LAB_MOTOR.rotor_leakage_inductance, "H", "rotor leakage inductance L_lr",
       1e-5, 0.1, _KRAUSE + ": X'_lr = 0.754 Ohm at 60 Hz"),
    _p("magnetising_inductance", LAB_MOTOR.magnetising_inductance, "H", "magnetising inductance L_m", 1e-3, 1.0,
       _KRAUSE + ": X_M = 26.13 Ohm at 60 Hz"),
    _p("supply_voltage", LAB_MOTOR.supply_voltage, "V", "line-to-line RMS voltage at the rated 50 Hz", 10.0, 1000.0,
       "Krause's 220 V at 60 Hz moved to 50 Hz at the same V/Hz (assumption)"),
    _p("motor_rotor_mass", 8.0, "kg", "motor rotor mass", 0.1, 200.0,
       "a 3-kW frame-100L rotor (about a third of the 24 kg motor); assumption"),
    _p("motor_bearing_stiffness", 1.0e8, "N/m", "radial stiffness of each of the motor's two bearings", 1e6, 1e10,
       "6206/6306 ball bearings of a frame-100L motor, preloaded; assumption"),
    _p("motor_inertia", 0.089, "kg m^2", "motor rotor polar moment of inertia", 1e-4, 10.0, _KRAUSE + ": J"),
    _p("supply_unbalance", 0.0, "-", "FAULT negative/positive-sequence supply voltage ratio (healthy 0)",
       0.0, 0.2, "IEC 60034-26 voltage unbalance factor; grids keep it below 0.02"),
)

SHAFTS = (
    _p("motor_shaft_diameter", 0.028, "m", "motor shaft diameter", 0.005, 0.1,
       "IEC 60072-1 frame 100L (3 kW, 4 pole): shaft end 28 mm"),
    _p("motor_shaft_length", 0.12, "m", "motor shaft from rotor centre to the coupling hub", 0.01, 1.0, _ASSUMED),
    _p("hss_diameter", 0.025, "m", "high-speed shaft diameter", 0.005, 0.1,
       "bore of the 6205 bearings (25 mm)"),
    _p("hss_span", 1.0, "m", "high-speed shaft: distance between the two bearings", 0.1, 5.0,
       _ASSUMED + "; puts the first lateral critical speed below the 1500 rpm rating, so a start-up passes it"),
    _p("hss_overhang", 0.1, "m", "high-speed shaft from the coupling hub to bearing 1", 0.01, 1.0, _ASSUMED),
    _p("disk_position", 0.5, "-", "disk position as a fraction of the bearing span from bearing 1", 0.05, 0.95,
       _ASSUMED + " (mid-span)"),
    _p("shaft_youngs_modulus", 210e9, "Pa", "Young's modulus of both shafts", 50e9, 400e9, _STEEL),
    _p("shaft_shear_modulus", 210e9 / 2.6, "Pa", "shear modulus of both shafts", 20e9, 160e9, _STEEL + ", G = E/2(1+nu)"),
    _p("shaft_density", 7850.0, "kg/m^3", "density of both shafts", 1e-3, 2e4,
       _STEEL + " (tiny values give the massless shafts of the closed-form checks)"),
)

COUPLING = (
    _p("coupling_torsional_stiffness", 3.0e3, "N m/rad", "coupling torsional stiffness", 10.0, 1e6, _JAW),
    _p("coupling_torsional_damping", 0.5, "N m s/rad", "coupling torsional damping", 0.0, 100.0,
       _JAW + "; about 5 % of critical for the first torsional mode"),
    _p("coupling_radial_stiffness", 1.0e6, "N/m", "coupling radial (lateral) stiffness", 0.0, 1e9, _JAW),
    _p("coupling_angular_stiffness", 100.0, "N m/rad", "coupling angular (bending) stiffness", 0.0, 1e5, _JAW),
    _p("coupling_hub_inertia", 1.2e-3, "kg m^2", "polar inertia of each coupling hub", 1e-6, 0.1,
       "steel hub 65 mm x 40 mm (size-24 jaw coupling); assumption"),
    _p("coupling_hub_mass", 0.6, "kg", "mass of each coupling hub", 1e-3, 10.0, "as coupling_hub_inertia"),
    _p("coupling_asymmetry", 0.2, "-", "two-fold stiffness anisotropy (k1 - k2)/(k1 + k2) of the coupling element",
       0.0, 0.9, _ASSUMED + ": a jaw or pin coupling is not axisymmetric; misalignment through it excites 2x"),
    _p("misalignment_parallel", 0.0, "m", "FAULT parallel offset of the motor axis (healthy 0)", 0.0, 2e-3,
       "fault; catalogues allow about 0.2 mm for a size-24 jaw coupling"),
    _p("misalignment_angular", 0.0, "rad", "FAULT angular misalignment of the motor axis (healthy 0)", 0.0, 0.03,
       "fault; catalogues allow about 1 deg (0.017 rad)"),
)

BEARINGS = (
    _p("bearing_stiffness", 5.0e7, "N/m", "radial stiffness of each rolling bearing", 1e5, 1e10,
       "6205 deep-groove ball bearing at light load (Harris, Rolling Bearing Analysis: 1e7-1e8 N/m); assumption"),
    _p("bearing_damping", 200.0, "N s/m", "radial damping of each rolling bearing", 0.0, 1e5, _ASSUMED),
    _p("housing_mass", 2.0, "kg", "mass of each bearing housing (pillow block and pedestal)", 0.05, 50.0,
       "SY 25 pillow block (0.8 kg) on a steel pedestal; assumption"),
    _p("support_stiffness", 2.0e7, "N/m", "stiffness of each housing support, per direction (y, z)", 1e4, 1e10,
       _ASSUMED + ": bolted pedestal on a stiff frame"),
    _p("support_damping", 500.0, "N s/m", "damping of each housing support, per direction", 0.0, 1e5, _ASSUMED),
    _p("housing_looseness", 0.0, "-",
       "FAULT fraction of the vertical support stiffness of housing 2 lost (healthy 0)", 0.0, 0.95,
       "fault: loose bolts or a cracked pedestal (support stiffness loss)"),
    _p("defect_amplitude", 0.0, "N", "FAULT peak force of the outer-race defect impacts in bearing 2 (healthy 0)",
       0.0, 2000.0, "fault: impulse train at BPFO (Randall & Antoni 2011)"),
    _p("defect_pulse_width", 2e-4, "s", "duration of one defect impact", 1e-5, 5e-3,
       "a ball crossing a 1-2 mm spall at 1500 rpm; assumption"),
)

DISK_AND_LOAD = (
    _p("disk_mass", 15.0, "kg", "disk mass", 0.1, 200.0, _DISK),
    _p("disk_polar_inertia", 0.117, "kg m^2", "disk polar moment of inertia", 1e-5, 20.0, _DISK),
    _p("disk_diametral_inertia", 0.0605, "kg m^2", "disk diametral moment of inertia", 1e-5, 20.0, _DISK),
    _p("disk_damping", 70.0, "N s/m", "non-rotating lateral damping at the disk (air, fixtures), per direction",
       0.0, 1e4, "assumption: about 2 % of critical for the first bending mode, as lab rotor kits measure 1-3 %; "
       "the pinned bending modes get almost nothing from the stiff bearings"),
    _p("eccentric_mass", 0.005, "kg", "eccentric mass on the disk: residual 5 g; more is the FAULT unbalance growth",
       0.0, 0.5, "ISO 21940-11 grade G6.3 allows U = 6.3e-4 kg m for 15 kg at 1500 rpm; 5 g at 0.1 m = 5e-4 kg m"),
    _p("eccentric_radius", 0.1, "m", "radius of the eccentric mass", 0.0, 0.125, "on the disk face; assumption"),
    _p("load_torque", 10.0, "N m", "load (brake/generator) torque at the rated 1500 rpm", 0.0, 50.0,
       "about 85 % of the motor's rated torque (Krause: 11.9 N m); assumption"),
    _p("load_speed_exponent", 1.0, "-", "load law T = load_torque (w / w_rated)^n: 0 brake, 1 generator, 2 fan",
       0.0, 3.0, _ASSUMED + ": a generator on a resistor bank"),
)

PARAMETERS: tuple[ModelParameter, ...] = MOTOR + SHAFTS + COUPLING + BEARINGS + DISK_AND_LOAD

FAULTS: tuple[str, ...] = ("eccentric_mass", "misalignment_parallel", "misalignment_angular", "defect_amplitude",
                           "housing_looseness", "supply_unbalance")
"""Fault parameters; their nominal values are the healthy rig."""

BEARING_GEOMETRY = SKF_6205
"""Both bearings are 6205 (defect frequencies from :mod:`ddgsa.models.hss_rig.bearing`)."""

RATED_SPEED = 2 * math.pi * 1500.0 / 60.0
"""Reference speed of the load law [rad/s] (1500 rpm)."""
