"""Indirect drive, phase 1: parameters, closed forms against independent solutions, and the output
functions on synthetic signals with known answers."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import eigh
from scipy.spatial.transform import Rotation

from ddgsa.loads import NREL5MW
from ddgsa.models.direct_drive import PARAMETERS as DIRECT_PARAMETERS
from ddgsa.models.indirect_drive.closed_form import (housing_roll, mesh_geometry, mount_torsional_stiffness,
                                                      stage_torques, torsional_frequency)
from ddgsa.models.indirect_drive.outputs import (axial_torque, bearing_outputs, constraint_drift,
                                                  damage_equivalent_load, gear_force_outputs,
                                                  housing_motion_outputs, point_displacement, radial_axial,
                                                  rotated_x_axis, rotation_vectors, signal_statistics)
from ddgsa.models.indirect_drive.parameters import BEARINGS, NOMINAL, PARAMETERS

X = np.array([1.0, 0.0, 0.0])


# ---------------------------------------------------------------- parameters

def test_nrel_defaults_and_declarations() -> None:
    """NREL/TP-500-38060 Table 5-1 values; every parameter has a unit, a description and a range
    holding its nominal; shared values equal the direct drive's."""
    assert NOMINAL["gear_ratio"] == 97.0
    assert NOMINAL["generator_inertia"] == 534.116
    assert NOMINAL["drivetrain_torsional_stiffness"] == 867.637e6
    assert NOMINAL["drivetrain_torsional_damping"] == 6.215e6
    assert NOMINAL["rotor_inertia_x"] == pytest.approx(NREL5MW.rotor_inertia - 7.5e3, rel=1e-12)
    direct = {p.name: p.nominal for p in DIRECT_PARAMETERS}
    assert NOMINAL["main_bearing_x"] == direct["front_bearing_x"]
    assert NOMINAL["hub_mass"] == direct["hub_mass"] and NOMINAL["c_gen"] == direct["c_gen"]
    assert len({p.name for p in PARAMETERS}) == len(PARAMETERS)
    for p in PARAMETERS:
        assert p.unit and p.description and p.low <= p.nominal <= p.high, p.name
    for b in BEARINGS:
        assert f"bearing_C_{b}" in NOMINAL
    # the stated geometry is ordered along the LSS
    order = ["main_bearing_x", "lss_bearing_1_x", "gear_x", "lss_bearing_3_x", "lss_length"]
    assert all(NOMINAL[a] < NOMINAL[b] for a, b in zip(order, order[1:]))
    assert NOMINAL["lss_bearing_1_x"] < NOMINAL["hss_bearing_2_x"] < NOMINAL["gear_x"] < NOMINAL["hss_bearing_4_x"]
    # hollow steel LSS r 0.35 / 0.15 m, 4.2 m: mass and EI from the section (0.2 %)
    area, second = math.pi * (0.35 ** 2 - 0.15 ** 2), math.pi * (0.35 ** 4 - 0.15 ** 4) / 4
    assert NOMINAL["lss_mass"] == pytest.approx(7850 * area * 4.2, rel=2e-3)
    assert NOMINAL["lss_bending_stiffness"] == pytest.approx(210e9 * second, rel=2e-3)
    assert NOMINAL["lss_axial_stiffness"] == pytest.approx(210e9 * area, rel=2e-3)


# ---------------------------------------------------------------- closed forms

def test_torsional_frequency_against_two_inertia_eigenproblem() -> None:
    """The closed form equals the nonzero eigenfrequency of rotor and generator (HSS coordinates)
    joined through the gear by the LSS spring (1e-10)."""
    k, jr, jg, n = 867.637e6, 3.8677e7, 534.116, 97.0
    # coordinates: rotor angle, generator angle (turns -n times the LSS); spring on the LSS twist
    # theta_r - (-theta_g / n): stiffness k [1, 1/n; 1/n, 1/n^2]
    kmat = k * np.array([[1.0, 1.0 / n], [1.0 / n, 1.0 / n ** 2]])
    w2 = eigh(kmat, np.diag([jr, jg]), eigvals_only=True)
    assert abs(w2[0]) < 1e-6 * w2[1]
    assert torsional_frequency(k, jr, jg, n) == pytest.approx(math.sqrt(w2[1]) / (2 * math.pi), rel=1e-10)
    assert torsional_frequency(k, jr, jg, n) == pytest.approx(2.2229, abs=1e-4)


@pytest.mark.parametrize("offset_deg, alpha_deg", [(90.0, 20.0), (30.0, 0.0), (200.0, 25.0)])
def test_stage_torques_against_planar_free_body_statics(offset_deg: float, alpha_deg: float) -> None:
    """Wheel, pinion and housing solved as three planar free bodies (9 equations): generator torque,
    housing torque and tooth force equal the closed form (1e-9)."""
    t_in, n, r_w, alpha = 3.9e6, 97.0, 1.0, math.radians(alpha_deg)
    e = np.array([0.0, math.cos(math.radians(offset_deg)), math.sin(math.radians(offset_deg))])
    g = mesh_geometry(r_w, n, alpha, tuple(e))
    yz = slice(1, 3)
    c_w, c_p, a = np.zeros(3), g.centre_distance * e, g.contact
    loa = g.line_of_action

    def mx(r: np.ndarray, f: np.ndarray) -> float:        # moment about +X of force f at arm r
        return float(np.cross(r, f)[0])

    # unknowns: F, Rw_y, Rw_z, Rp_y, Rp_z, T_gen, Fm_y, Fm_z, T_housing
    rows, rhs = [], []
    for i in range(2):   # wheel forces: R_w - F loa = 0
        rows.append([-loa[yz][i], *(np.eye(2)[i]), 0, 0, 0, 0, 0, 0]); rhs.append(0.0)
    rows.append([mx(a - c_w, -loa), 0, 0, 0, 0, 0, 0, 0, 0]); rhs.append(-t_in)
    for i in range(2):   # pinion forces: R_p + F loa = 0
        rows.append([loa[yz][i], 0, 0, *(np.eye(2)[i]), 0, 0, 0, 0]); rhs.append(0.0)
    rows.append([mx(a - c_p, loa), 0, 0, 0, 0, 1, 0, 0, 0]); rhs.append(0.0)
    for i in range(2):   # housing forces: -R_w - R_p + F_m = 0
        rows.append([0, *(-np.eye(2)[i]), *(-np.eye(2)[i]), 0, *(np.eye(2)[i]), 0]); rhs.append(0.0)
    # housing moment about the LSS axis: bearing reactions at c_w (no arm) and c_p, mounts' torque
    rows.append([0, 0, 0, c_p[2], -c_p[1], 0, 0, 0, 1]); rhs.append(0.0)
    sol = np.linalg.solve(np.array(rows, dtype=float), np.array(rhs))
    ref = stage_torques(t_in, n, r_w, alpha)
    assert sol[0] == pytest.approx(ref.mesh_force, rel=1e-9)
    assert sol[5] == pytest.approx(ref.hss, rel=1e-9)
    assert sol[8] == pytest.approx(ref.housing, rel=1e-9)
    np.testing.assert_allclose(sol[6:8], 0.0, atol=1e-6)           # a pure torque on the mounts
    assert ref.lss + ref.hss + ref.housing == pytest.approx(0.0, abs=1e-6)


def test_mesh_geometry_rolls_without_slip() -> None:
    """The pitch points of wheel (speed w) and pinion (speed -N w) move with the same velocity;
    the line of action is a unit vector at the pressure angle to the tangent."""
    n, w, alpha = 97.0, 1.2, math.radians(20.0)
    e = np.array([0.0, -0.6, 0.8])
    g = mesh_geometry(0.9, n, alpha, tuple(e))
    v_wheel = np.cross(w * X, g.contact)
    v_pinion = np.cross(-n * w * X, g.contact - g.centre_distance * e)
    np.testing.assert_allclose(v_wheel, v_pinion, atol=1e-12)
    np.testing.assert_allclose(v_wheel, w * g.wheel_radius * g.tangent, atol=1e-12)
    assert np.linalg.norm(g.line_of_action) == pytest.approx(1.0, abs=1e-12)
    assert g.line_of_action @ g.tangent == pytest.approx(math.cos(alpha), abs=1e-12)
    assert g.line_of_action @ e == pytest.approx(math.sin(alpha), abs=1e-12)   # towards the pinion axis
    with pytest.raises(ValueError, match="perpendicular to X"):
        mesh_geometry(1.0, 97.0, 0.0, (1.0, 0.0, 0.0))


def test_housing_roll_against_planar_spring_statics() -> None:
    """A rigid housing (y, z, roll) on two mounts at (+-d, 0) with lateral and vertical springs,
    solved as a 3x3 stiffness problem: its roll under a torque equals the closed form (1e-12)."""
    k_y, k_z, d, k_rx, torque = 1e8, 2e8, 1.2, 3e6, -4.2e6
    kmat = np.zeros((3, 3))
    for y in (d, -d):
        # mount displacement (dy, dz) = (v - phi z, w + phi y) at (y, z = 0)
        b = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, y]])
        kmat += b.T @ np.diag([k_y, k_z]) @ b
    kmat[2, 2] += 2 * k_rx
    phi = np.linalg.solve(kmat, np.array([0.0, 0.0, torque]))[2]
    # the closed form takes the torque the mounts apply, i.e. minus the applied one
    assert housing_roll(-torque, k_z, d, k_rx) == pytest.approx(phi, rel=1e-12)
    assert mount_torsional_stiffness(2e8, 1.2) == pytest.approx(5.76e8, rel=1e-12)


# ---------------------------------------------------------------- outputs on synthetic signals

def test_signal_statistics_of_a_sampled_sine() -> None:
    """Over whole periods, uniformly sampled with the peaks on the grid: mean c, RMS A/sqrt(2), p2p 2A (1e-12)."""
    t = np.arange(320) / 40.0                                      # 8 periods of 1 s, 40 samples each
    a, c = 2.5e-3, -1e-3
    x = np.column_stack([c + a * np.sin(2 * np.pi * t), np.full_like(t, 7.0)])
    s = signal_statistics(x)
    np.testing.assert_allclose(s["mean"], [c, 7.0], atol=1e-15)
    np.testing.assert_allclose(s["rms"], [a / math.sqrt(2), 0.0], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(s["p2p"], [2 * a, 0.0], rtol=1e-12)


def test_point_displacement_and_rotation_of_a_rolling_housing() -> None:
    """A housing rolling by phi about X and translating by u: the point (x0, d, h) moves by
    u + (0, d cos - h sin - d, d sin + h cos - h); its rotation vector is (phi, 0, 0)."""
    phi = np.linspace(-0.01, 0.02, 7)
    rot = Rotation.from_rotvec(np.outer(phi, X)).as_matrix()
    u = np.column_stack([np.zeros(7), 1e-3 * np.ones(7), -2e-3 * np.ones(7)])
    ref_pos = np.array([3.5, 0.0, 0.0])
    point = np.array([-1.0, 1.25, 1.25])
    disp = point_displacement(ref_pos + u, rot, point, ref_pos, np.eye(3))
    d, h = point[1], point[2]
    expected = u + np.column_stack([np.zeros(7), d * np.cos(phi) - h * np.sin(phi) - d,
                                    d * np.sin(phi) + h * np.cos(phi) - h])
    np.testing.assert_allclose(disp, expected, atol=1e-15)
    ang = rotation_vectors(rot, np.eye(3))
    np.testing.assert_allclose(ang, np.column_stack([phi, np.zeros(7), np.zeros(7)]), atol=1e-15)
    # relative to a turned reference: a further yaw of 0.03 rad reads as 0.03 about Z
    ref = Rotation.from_rotvec([0.0, 0.1, 0.0]).as_matrix()
    yawed = Rotation.from_rotvec([0.0, 0.0, 0.03]).as_matrix() @ ref
    np.testing.assert_allclose(rotation_vectors(yawed[None], ref)[0], [0.0, 0.0, 0.03], atol=1e-15)
    out = housing_motion_outputs(disp, ang)
    assert len(out) == 18
    assert out["housing_rx_p2p"] == pytest.approx(0.03, rel=1e-12)
    assert out["housing_dy_mean"] == pytest.approx(expected[:, 1].mean(), rel=1e-12)


def test_damage_equivalent_load_closed_forms() -> None:
    """k full cycles of range 2A over T seconds: DEL = 2A (k / (f_ref T))^(1/m); independent of the
    mean; linear in the load scale; with m = 1 the mean range per reference cycle."""
    k, amp, duration, m = 25, 3e5, 100.0, 8.7
    x = np.array([amp, -amp] * k + [amp])
    ref = 2 * amp * (k / duration) ** (1 / m)
    assert damage_equivalent_load(x, duration, m) == pytest.approx(ref, rel=1e-12)
    assert damage_equivalent_load(x + 4e6, duration, m) == pytest.approx(ref, rel=1e-12)
    assert damage_equivalent_load(3 * x, duration, m) == pytest.approx(3 * ref, rel=1e-12)
    # ASTM E1049-85 rainflow example (its Fig. 6): ranges 3, 4, 6, 8, 9 with counts 0.5, 1.5, 0.5, 1, 0.5
    astm = np.array([-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0])
    by_hand = 0.5 * 3 ** 3 + 1.5 * 4 ** 3 + 0.5 * 6 ** 3 + 1.0 * 8 ** 3 + 0.5 * 9 ** 3
    assert damage_equivalent_load(astm, 1.0, exponent=3.0) == pytest.approx(by_hand ** (1 / 3), rel=1e-12)
    assert damage_equivalent_load(np.full(10, 2.0), 1.0) == 0.0
    out = gear_force_outputs(x + 4e6, duration)
    assert out["gear_force_mean"] == pytest.approx(4e6 + amp / (2 * k + 1), rel=1e-12)
    assert out["gear_force_del"] == pytest.approx(ref, rel=1e-12)


def test_rainflow_damage_equals_the_rainflow_package() -> None:
    """The compiled rainflow count (:func:`damage_equivalent_load`) against the ``rainflow`` package
    (ASTM E1049-85, independent code) on 200 random records: white, random-walk and rounded (plateaus of
    repeated values), 0 to 400 samples (1e-12)."""
    rainflow = pytest.importorskip("rainflow")
    rng = np.random.default_rng(0)
    for trial in range(200):
        x = rng.normal(size=int(rng.integers(0, 400)))
        x = np.cumsum(x) if trial % 2 else x
        x = np.round(x, 1) if trial % 3 == 0 else x
        cycles = rainflow.count_cycles(x)
        ranges, counts = np.array(cycles).reshape(-1, 2).T
        want = (np.sum(counts * ranges ** 8.7) / 10.0) ** (1 / 8.7)
        assert damage_equivalent_load(x, 10.0) == pytest.approx(want, rel=1e-12, abs=1e-300), trial


def test_rotation_helpers_against_scipy() -> None:
    """Rotation vectors of rotation matrices and the rotated X axis of rotation vectors against
    ``scipy.spatial.transform.Rotation`` (independent code), angles from 1e-9 to 3 rad (1e-15)."""
    rng = np.random.default_rng(1)
    for scale in (1e-9, 1e-4, 1e-2, 1.0, 3.0):
        v = rng.normal(size=(200, 3))
        v *= rng.uniform(0.0, scale, (200, 1)) / np.linalg.norm(v, axis=1)[:, None]
        r = Rotation.from_rotvec(v).as_matrix()
        np.testing.assert_allclose(rotated_x_axis(v), r[:, :, 0], rtol=0, atol=1e-15)
        np.testing.assert_allclose(rotation_vectors(r, np.eye(3)), v, rtol=0, atol=1e-15 * max(scale, 1e-9))


def test_bearing_outputs_constant_load_closed_form() -> None:
    """A constant force on a tilted shaft axis: radial/axial split by projection and the damage rate
    (w/2pi)(P/C)^(10/3)/1e6 with the ISO 281 equivalent load (1e-12)."""
    tilt = math.radians(4.0)
    axis = np.array([math.cos(tilt), 0.0, -math.sin(tilt)])
    f_axial, f_radial = 2e5, 1.5e6
    normal = np.array([math.sin(tilt), 0.0, math.cos(tilt)])
    force = np.tile(f_axial * axis + f_radial * normal, (50, 1))
    fr, fa = radial_axial(force, axis)
    np.testing.assert_allclose(fr, f_radial, rtol=1e-12)
    np.testing.assert_allclose(fa, f_axial, rtol=1e-12)
    speed, rating = np.full(50, 1.2), 1e7
    out = bearing_outputs("main", force, axis, speed, rating, "iso281")
    p = f_radial + 2.5 * f_axial                         # Fa/Fr = 0.13 <= 0.27: P = Fr + 2.5 Fa
    assert out["damage_main"] == pytest.approx(1.2 / (2 * math.pi) * (p / rating) ** (10 / 3) / 1e6, rel=1e-12)
    assert out["main_Fr_mean"] == pytest.approx(f_radial, rel=1e-12)
    assert out["main_Fa_mean"] == pytest.approx(f_axial, rel=1e-12)


def test_axial_torque_of_two_mounts() -> None:
    """Mounts at (x, +-d, 0) pushing down / up with F: torque about X through the axis -2 F d, plus
    the bushings' own moments; a force along X or through the axis adds nothing."""
    d, f = 1.2, 1.75e6
    pts = np.array([[3.5, d, 0.0], [3.5, -d, 0.0]])
    forces = np.array([[[0.0, 0.0, -f], [0.0, 0.0, f]], [[3e5, 0.0, -f], [0.0, 2e5, f]]])
    moments = np.zeros_like(forces)
    moments[1, 0, 0] = 1e4
    t = axial_torque(forces, moments, pts, np.array([0.0, 0.0, 0.0]), X)
    np.testing.assert_allclose(t, [-2 * f * d, -2 * f * d + 1e4], rtol=1e-12)
    drift = constraint_drift({"holonomic": np.array([[1e-12, -3e-11], [2e-12, 0.0]]), "gear": np.zeros(0)})
    assert drift == {"holonomic_drift": 3e-11, "gear_drift": 0.0}


def test_axial_torque_about_any_axis_is_the_moment_of_the_forces_projected() -> None:
    """About a tilted fixed axis and about a per-sample axis: ``(sum (r - o) x F + M) . e`` (numpy's
    cross product); about X the x component alone, and a rotation vector without a reference is the
    one relative to the identity."""
    rng = np.random.default_rng(7)
    forces, moments = rng.standard_normal((5, 2, 3)) * 1e5, rng.standard_normal((5, 2, 3)) * 1e3
    pts, origin = rng.standard_normal((2, 3)), np.array([0.5, -0.2, 0.1])
    total = (np.cross(pts - origin, forces) + moments).sum(axis=1)
    tilted = np.array([0.0, 0.6, 0.8])
    per_sample = rng.standard_normal((5, 3))
    np.testing.assert_allclose(axial_torque(forces, moments, pts, origin, tilted), total @ tilted, rtol=1e-12)
    np.testing.assert_allclose(axial_torque(forces, moments, pts, origin, per_sample),
                               np.einsum("ti,ti->t", total, per_sample), rtol=1e-12)
    np.testing.assert_allclose(axial_torque(forces, moments, pts, origin, X), total[:, 0], rtol=1e-12)
    rot = np.array([[[np.cos(0.02), -np.sin(0.02), 0.0], [np.sin(0.02), np.cos(0.02), 0.0], [0.0, 0.0, 1.0]]])
    np.testing.assert_allclose(rotation_vectors(rot), [[0.0, 0.0, 0.02]], atol=1e-15)
