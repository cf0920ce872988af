"""The hss_rig model on the kernel against closed forms: torsion chain, Jeffcott rotor, unbalance, faults."""

from __future__ import annotations

import math

import numpy as np
import pytest

import ddgsa.models as models
from ddgsa.errors import ModelError, SceneError
from ddgsa.models.hss_rig.closed_form import (chain_frequencies, jeffcott_critical_speed, jeffcott_stiffness,
                                              jeffcott_unbalance_response, series)
from ddgsa.models.hss_rig.drive import drive_for
from ddgsa.models.hss_rig.motor import steady_torque
from ddgsa.models.hss_rig.scenes import RigScene

# a short steady record: the linear path starts in the periodic steady state, so little settling is needed
STEADY = RigScene("steady", speed_rpm=1500.0, duration=0.6, sample_rate=2000.0, settle=0.1)
# the Jeffcott rotor inside the rig: near-massless shafts (5 g against the 15 kg disk), no coupling
# stiffness, a 10 g hub (lighter parts push real modes under the kernel's rigid-mode cut, 1e-7 of the
# largest eigenvalue)
JEFFCOTT = {"shaft_density": 1.0, "coupling_radial_stiffness": 0.0, "coupling_angular_stiffness": 0.0,
            "coupling_hub_mass": 0.01, "coupling_hub_inertia": 1e-5}


@pytest.fixture(scope="module")
def linear():
    return models.get("hss_rig", fidelity="linear")


def test_torsional_frequencies_equal_the_disc_chain(linear):
    """Massless shafts: motor rotor -- motor shaft -- hub -- coupling -- hub -- shaft -- disk (1e-3)."""
    p = {**linear.nominal, "shaft_density": 1.0, "coupling_torsional_damping": 0.0, "load_torque": 0.0}
    md = linear.modes({k: p[k] for k in ("shaft_density", "coupling_torsional_damping", "load_torque")})
    torsional = md[md["label"].str.contains("spin|torsion") & ~md["label"].str.startswith("housing")]
    g = p["shaft_shear_modulus"]
    x_disk = p["hss_overhang"] + p["disk_position"] * p["hss_span"]
    chain = chain_frequencies(
        [p["motor_inertia"], p["coupling_hub_inertia"], p["coupling_hub_inertia"], p["disk_polar_inertia"]],
        [g * math.pi * p["motor_shaft_diameter"] ** 4 / 32 / p["motor_shaft_length"],
         p["coupling_torsional_stiffness"], g * math.pi * p["hss_diameter"] ** 4 / 32 / x_disk])
    np.testing.assert_allclose(np.sort(torsional["frequency_hz"].to_numpy())[:3], chain, rtol=1e-3)


def test_first_lateral_mode_is_the_jeffcott_critical_speed(linear):
    """Disk on a massless shaft, bearings in series with the housing supports (1e-3; the issue asks 2 %)."""
    md = linear.modes({**JEFFCOTT, "disk_damping": 0.0, "coupling_asymmetry": 0.0})
    p = linear.nominal
    k = _jeffcott_k(p)
    lateral = md[md["label"].str.contains("bending|lateral")]["frequency_hz"].min()
    assert lateral == pytest.approx(jeffcott_critical_speed(k, p["disk_mass"]) / (2 * math.pi), rel=1e-3)


def test_modes_at_speed_keep_the_jeffcott_mode_and_split_the_tilt_mode(linear):
    """At 150 rad/s the mid-span disk's bending mode stays at the Jeffcott frequency (1e-3, no
    gyroscopic coupling); the disk-tilt mode splits into a backward whirl below and a forward one above
    the standstill frequency, within 1e-3 of ``Id w^2 -+ Ip W w - k_tilt = 0`` (1.2-1.6 % low before the
    modes carried the spin stiffening that the FFR disk's first-order rotation shapes miss, docs/physics.md)."""
    point = {**JEFFCOTT, "disk_damping": 0.0, "coupling_asymmetry": 0.0}
    p = {**linear.nominal, **point}
    still = linear.modes(point)
    spin = 150.0
    turning = linear.modes(point, rotor_speed=spin)
    bending = turning[turning["label"].str.contains("bending_._1")]["frequency_hz"].to_numpy()
    jeff = jeffcott_critical_speed(_jeffcott_k(p), p["disk_mass"]) / (2 * math.pi)
    np.testing.assert_allclose(bending, jeff, rtol=1e-3)
    ei = p["shaft_youngs_modulus"] * math.pi * p["hss_diameter"] ** 4 / 64
    ks = series(p["bearing_stiffness"], p["support_stiffness"])
    k_tilt = 1.0 / (p["hss_span"] / (12 * ei) + 2 / (p["hss_span"] ** 2 * ks))
    i_d, i_p = p["disk_diametral_inertia"], p["disk_polar_inertia"]
    root = math.sqrt((i_p * spin) ** 2 + 4 * i_d * k_tilt)
    backward, forward = ((root - i_p * spin) / (2 * i_d) / (2 * math.pi), (root + i_p * spin) / (2 * i_d) / (2 * math.pi))
    tilt_still = still[still["label"].str.contains("bending_._2")]["frequency_hz"].min()
    assert tilt_still == pytest.approx(math.sqrt(k_tilt / i_d) / (2 * math.pi), rel=1e-3)
    tilt = np.sort(turning[turning["label"].str.contains("bending_._2")]["frequency_hz"].to_numpy())
    assert tilt[0] == pytest.approx(backward, rel=1e-3) and tilt[-1] == pytest.approx(forward, rel=1e-3)
    assert tilt[0] < tilt_still < tilt[-1]


def _jeffcott_k(p):
    ei = p["shaft_youngs_modulus"] * math.pi * p["hss_diameter"] ** 4 / 64
    ks = series(p["bearing_stiffness"], p["support_stiffness"])
    return jeffcott_stiffness(ei, p["hss_span"], p["disk_position"] * p["hss_span"], ks, ks)


@pytest.mark.parametrize("speed_rpm", [900.0, 1100.0, 1500.0])
def test_unbalance_response_amplitude_and_phase_match_jeffcott(linear, speed_rpm):
    """1x whirl at the disk below, near (critical 1080 rpm) and above the critical speed at the
    ``linear`` fidelity: amplitude within 1e-3 (the issue asks 2 %) and lag within 0.01 rad."""
    scene = RigScene("steady", speed_rpm=speed_rpm, duration=0.8, sample_rate=2000.0, settle=0.1)
    point = {**JEFFCOTT, "coupling_asymmetry": 0.0, "eccentric_mass": 0.02}
    s = linear.simulate(scene, point)
    s = s[s.index >= scene.settle]
    w = float(s["speed"].mean())
    p = {**linear.nominal, **point}
    amp, lag = jeffcott_unbalance_response(w, _jeffcott_k(p), p["disk_mass"], p["disk_damping"],
                                           p["eccentric_mass"] * p["eccentric_radius"])
    ang = s["angle"].to_numpy()
    y = s["disk_y"].to_numpy() - s["disk_y"].mean()
    cc, cs = np.linalg.lstsq(np.column_stack([np.cos(ang), np.sin(ang)]), y, rcond=None)[0]
    assert math.hypot(cc, cs) == pytest.approx(float(amp), rel=1e-3)
    assert math.atan2(cs, cc) == pytest.approx(float(lag), abs=0.01)


def test_unbalance_response_scales_with_the_eccentric_mass(linear):
    """Doubling m_u doubles the 1x amplitude at the disk and the housings (1e-3); without it the
    gravity sag of the turning shaft makes no 1x at all (< 1e-3 of the 10 g response)."""
    zero = linear.evaluate({"eccentric_mass": 0.0}, STEADY)
    one = linear.evaluate({"eccentric_mass": 0.01}, STEADY)
    two = linear.evaluate({"eccentric_mass": 0.02}, STEADY)
    assert zero["order1x_disk_z"][0] < 1e-3 * one["order1x_disk_z"][0]
    for out in ("order1x_disk_y", "order1x_disk_z", "order1x_housing_1_y", "order1x_housing_2_z"):
        assert two[out][0] == pytest.approx(2 * one[out][0], rel=1e-3), out


def test_faults_show_in_their_indicators(linear):
    """Each fault moves its own indicator well above the healthy rig's (factors stated per fault)."""
    healthy = linear.evaluate(None, STEADY).iloc[0]
    defect = linear.evaluate({"defect_amplitude": 200.0}, STEADY).iloc[0]
    assert defect["bpfo_housing_2_z"] > 1e6 * healthy["bpfo_housing_2_z"]
    loose = linear.evaluate({"housing_looseness": 0.9}, STEADY).iloc[0]
    assert loose["order1x_housing_2_z"] > 3 * healthy["order1x_housing_2_z"]
    supply = linear.evaluate({"supply_unbalance": 0.02}, STEADY).iloc[0]
    drive = drive_for({**linear.nominal, "supply_unbalance": 0.02}, STEADY)
    ripple = steady_torque(drive.motor, 2 * math.pi * supply["mean_speed_rpm"] / 60).ripple
    assert supply["torque_2f"] == pytest.approx(ripple, rel=1e-3)
    assert healthy["torque_2f"] < 1e-6 * ripple


def test_wrong_scenes_are_refused(linear):
    with pytest.raises(SceneError, match="needs a rig scene"):
        linear.simulate(3.0)
    with pytest.raises(ModelError, match="would alias"):
        linear.evaluate(None, RigScene("steady", duration=1.0, sample_rate=400.0))
    with pytest.raises(ModelError, match="misalignment in steady scenes only"):
        linear.simulate(RigScene("startup", duration=0.5, sample_rate=2000.0), {"misalignment_parallel": 1e-4})
    with pytest.raises(ModelError, match="unknown fidelity 'fast'"):
        models.get("hss_rig", fidelity="fast")
