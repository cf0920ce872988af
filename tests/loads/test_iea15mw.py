"""The IEA 15 MW reference rotor (issue 47): its BEM blade and its controller against the turbine's
published numbers (Gaertner et al. 2020, NREL/TP-5000-75698) and against ROSCO's Cp/Ct table
(CCBlade, an independent BEM of the same blade, with the rotor's precone and tilt)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from ddgsa.loads import IEA15MW, Scene, generate
from ddgsa.loads.bem import IEA15MW_BLADE, simulate_bem
from ddgsa.loads.hubloads import grid_points
from ddgsa.loads.rotor import IEA_GENERATOR_EFFICIENCY
from ddgsa.models.constants import GRAVITY

NO_TILT = replace(IEA15MW, tilt_deg=0.0)
Q_AREA = 0.5 * NO_TILT.air_density * NO_TILT.area
ROTOR_ASSEMBLY_MASS = 274.9e3
"""Blades and hub [kg] (seed 003 §2.1, from the same report)."""


def coefficients(v: float, tsr: float, pitch_deg: float) -> tuple[float, float]:
    """Power and thrust coefficients of the BEM rotor (no tower, no tilt) in uniform wind ``v`` [m/s]."""
    pts, _ = grid_points(NO_TILT)
    inflow = np.zeros((3, 40, pts.shape[0]))
    inflow[0] = v
    omega = tsr * v / NO_TILT.rotor_radius
    out = simulate_bem(NO_TILT, inflow, 0.05, {"rotor_speed": omega, "pitch": np.deg2rad(pitch_deg)},
                       blade=replace(IEA15MW_BLADE, tower_shadow=False), fixed=True)[-1]
    return out[3] * omega / (Q_AREA * v ** 3), out[0] / (Q_AREA * v ** 2)


def test_rotor_names_and_blades() -> None:
    assert IEA15MW_BLADE.elements["r"].size == 16
    assert IEA15MW_BLADE.elements["r"][-1] + 0.5 * IEA15MW_BLADE.elements["dr"][-1] < IEA15MW.rotor_radius


def test_peak_power_coefficient_against_the_report() -> None:
    """Report Table 1: aerodynamic Cp,max 0.489 at the design tip-speed ratio 9, fine pitch (its
    BEM with precone and prebend, which this rotor lacks). Measured: 0.494 (+1.0 %)."""
    cp, _ = coefficients(8.0, 9.0, 0.0)
    assert cp == pytest.approx(0.489, rel=0.02)
    assert coefficients(8.0, 8.0, 0.0)[0] < cp > coefficients(8.0, 10.0, 0.0)[0]


@pytest.mark.parametrize("tsr, pitch_deg", [(9.0, 0.0), (7.0, 0.0), (11.0, 0.0), (6.0, 5.0), (5.0, 10.0),
                                            (4.0, 15.0)])
def test_coefficients_against_the_rosco_table(tsr: float, pitch_deg: float) -> None:
    """ROSCO's table (CCBlade with the 4 deg precone and 6 deg tilt). Measured: Ct +1.0 ... +4.1 %,
    Cp +2.2 ... +7.8 % (higher here: no precone, no tilt; the same sign as the NREL 5-MW rotor's)."""
    cp, ct = coefficients(10.0, tsr, pitch_deg)
    tab = IEA15MW.table
    ct_tab = float(tab.lookup(tab.ct, tsr, np.deg2rad(pitch_deg)))
    cp_tab = float(tab.lookup(tab.cp, tsr, np.deg2rad(pitch_deg)))
    assert 1.0 <= ct / ct_tab < 1.05
    assert 1.0 <= cp / cp_tab < 1.09


def test_rated_wind_speed_and_thrust_against_the_report() -> None:
    """Report: rated wind speed 10.59 m/s; rated thrust about 2.8 MN, which the report's steady curves
    give along the shaft including the rotor's weight times sin(tilt) (forums.nrel.gov/t/3440; the
    repository's later WISDEM table has 2.45 MN aerodynamic). Measured: 10.587 m/s from the table;
    BEM aerodynamic thrust 2.54 MN at rated (7.56 rpm, pitch 0), + 0.28 MN of weight = 2.82 MN."""
    v = IEA15MW.rated_wind_speed
    assert v == pytest.approx(10.59, rel=0.01)
    _, ct = coefficients(v, IEA15MW.rated_speed * IEA15MW.rotor_radius / v, 0.0)
    aero = ct * Q_AREA * v ** 2
    assert aero == pytest.approx(2.45e6, rel=0.05)
    weight = ROTOR_ASSEMBLY_MASS * GRAVITY * np.sin(np.deg2rad(IEA15MW.tilt_deg))
    assert aero + weight == pytest.approx(2.8e6, rel=0.03)


@pytest.mark.parametrize("fidelity", ["table", "bem"])
def test_controlled_rotor_holds_rated_speed_and_power(fidelity: str) -> None:
    """Above rated (14 m/s, steady) the controller settles at the report's 7.56 rpm rated speed
    (7.55 in its text) and 15 MW electrical: the PI pitch loop and the torque law, closed on the
    table or the BEM rotor. Measured: 7.560 rpm, 15.00 MW, pitch 9.9 / 10.2 deg."""
    loads = generate(Scene(wind_speed=14.0, turbulence_intensity=0.0, shear_exponent=0.0, duration=60.0,
                           loads_fidelity=fidelity), IEA15MW)
    end = loads.iloc[-200:]
    assert float(end["rotor_speed"].mean()) * 30 / np.pi == pytest.approx(7.55, rel=0.005)
    assert float(end["power"].mean()) * IEA_GENERATOR_EFFICIENCY == pytest.approx(15e6, rel=0.01)
    assert 8.0 < np.rad2deg(float(end["pitch"].mean())) < 12.0
    assert float(end["rotor_speed"].std()) < 1e-3 * IEA15MW.rated_speed
