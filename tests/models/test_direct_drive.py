"""Direct-drive model: statics, free rotation, modes against an independent FE model, step size,
reference integrator, rigid against flexible, seed Table 1."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy.linalg import eigh

import ddgsa.models as models
from ddgsa import ModelError, Scene
from ddgsa.mbs.beam import BeamSpec, mesh, shaft_modes
from ddgsa.mbs.ffr import rotation
from ddgsa.mbs.system import evaluate_terms, integrate
from ddgsa.models.direct_drive import PARAMETERS

NOM = {p.name: p.nominal for p in PARAMETERS}
TURBULENT_60S = Scene(wind_speed=11.0, turbulence_intensity=0.12, duration=60.0, seed=1)


def test_registry_and_parameters() -> None:
    m = models.get("direct_drive")
    assert m.outputs[:4] == ("rms_deflection_hub", "rms_deflection_gen", "damage_front", "damage_rear")
    assert m.nominal["k_front_y"] == 3e9 and m.nominal["c_gen"] == 828.26e3
    with pytest.raises(ModelError, match="unknown model 'drect'; known: analytic, direct_drive"):
        models.get("drect")
    with pytest.raises(ModelError, match="unknown fidelity 'soft'"):
        models.get("direct_drive", fidelity="soft")
    with pytest.raises(ModelError, match="unknown parameter 'k_front'; did you mean 'k_front_z' or 'k_front_y' or 'k_front_x'"):
        m.resolve({"k_front": 1.0})
    with pytest.raises(ModelError, match="parameter 'k_front_y' = -1 N/m leaves its allowed range"):
        m.resolve({"k_front_y": -1.0})


@pytest.mark.parametrize("fidelity", ["flexible", "rigid"])
def test_static_reactions_balance_gravity_and_hub_loads(fidelity: str) -> None:
    model = models.get("direct_drive", fidelity=fidelity)
    asm = model.build()
    s = asm.system
    force, moment = np.array([6e5, 3e4, -2e4]), np.array([4e6, 2.5e6, -1.2e6])
    q = model.static(asm, force, moment)
    _, _, _, _, fs, _ = evaluate_terms(s, q, np.zeros_like(q), force, moment, 0.0, torque0=-moment[0])
    a = rotation(q[3:6])
    pts = q[:3] + (s.pu + np.einsum("jak,k->ja", s.ps, q[6:])) @ a.T        # mass points, global
    weight = s.pm.sum() * s.gravity
    hub = q[:3] + a @ (s.ld_u0 + s.ld_s @ q[6:])
    bearings = q[:3] + (s.sp_u0 + np.einsum("jak,k->ja", s.sp_s, q[6:])) @ a.T
    np.testing.assert_allclose(fs.sum(axis=0), force + weight, rtol=1e-6)
    generator = -moment[0] * a[:, 0]          # the generator torque acts about the (tilted) shaft axis
    applied = np.cross(hub, force) + moment + np.cross(pts, s.pm[:, None] * s.gravity).sum(axis=0) + generator
    reaction = np.cross(bearings, fs).sum(axis=0)
    # y and z: the spin equation (x) is not solved in statics -- the spin angle is held, so a
    # small moment about the shaft axis goes to that constraint
    np.testing.assert_allclose(reaction[1:], applied[1:], rtol=1e-6)


SEED_BASIS = {"beam": "euler_bernoulli", "bending_modes": 2}
TABLE2 = {"shaft": "table2"}
"""The shaft the recorded numbers below were made on (seed 000 Table 2's, the default until issue 47)."""
"""Seed 000's shaft basis (the default until issue 26): tests of its two-mode example hold it."""


def test_free_rotation_conserves_energy_and_spin() -> None:
    """Seed 000's basis at a 1 ms step (the default's 534-717 Hz modes at that step drift by 8e-5: the
    trapezoidal rule's error in the fast modes of a nonlinear system, 2e-6 at 0.25 ms)."""
    model = models.get("direct_drive", **SEED_BASIS)
    params = {**NOM, "bearing_damping_ratio": 0.0, "shaft_damping_ratio": 0.0}
    s = dataclasses.replace(model.build(params).system, gravity=np.zeros(3))
    n, spin = s.n_dof, 1.25
    q0, qd0 = np.zeros(n), np.zeros(n)
    qd0[3] = spin
    steps = 10_000
    zeros = np.zeros((steps + 1, 3))
    w_set = np.full(steps + 1, spin)
    pure = integrate(s, q0, qd0, 1e-3, 1, zeros, zeros, w_set, rho_inf=1.0)
    assert np.abs(pure["qd"][:, 3] - spin).max() < 1e-12
    # perturbed: lateral and elastic motion, no dissipation (the torque law sees no slip
    # only to first order, so its constant is made negligible)
    s = dataclasses.replace(s, c_torque=0.0)
    q0[6:] = 1e-4
    qd0[1], qd0[4] = 1e-3, 1e-3

    def energy(q: np.ndarray, qd: np.ndarray) -> float:
        m, *_ = evaluate_terms(s, q, qd, np.zeros(3), np.zeros(3), 0.0)
        _, _, _, _, fs, _ = evaluate_terms(s, q, np.zeros_like(qd), np.zeros(3), np.zeros(3), 0.0)
        k = np.where(s.sp_k > 0, s.sp_k, np.inf)
        return 0.5 * qd @ m @ qd + 0.5 * q[6:] @ s.kff @ q[6:] + 0.5 * np.sum(fs ** 2 / k)

    res = integrate(s, q0, qd0, 1e-3, 1, zeros, zeros, w_set, rho_inf=1.0)
    e = np.array([energy(res["q"][i], res["qd"][i]) for i in range(0, steps + 1, 500)])
    assert np.abs(e - e[0]).max() / e[0] < 1e-6


def _fe_plane(k_front: float, k_rear: float, p: dict) -> np.ndarray:
    """Independent FE model of one bending plane: fine Hermite mesh, end masses and rotary
    inertias, bearings as translational springs (no FFR, no mode reduction)."""
    spec = BeamSpec(nodes=mesh([0.0, p["front_bearing_x"], p["rear_bearing_x"], p["shaft_length"]], 0.05),
                    mass=p["shaft_mass"], polar_inertia=1.0, EI=p["shaft_bending_stiffness"], EA=1.0, GJ=1.0,
                    end_masses=((0.0, p["hub_mass"], 0.0, p["hub_inertia_yz"]),
                                (p["shaft_length"], p["generator_mass"], 0.0, p["generator_inertia_yz"])),
                    supports=(), axial_support=0.0)
    from ddgsa.mbs.beam import bending_matrices

    k, m = bending_matrices(spec)
    for x, kb in ((p["front_bearing_x"], k_front), (p["rear_bearing_x"], k_rear)):
        i = 2 * spec.node_index(x)
        k[i, i] += kb
    w2 = eigh(k, m, eigvals_only=True)
    return np.sqrt(w2[:4]) / (2 * np.pi)


def test_modes_agree_with_independent_fe_within_2_percent() -> None:
    """Lowest two modes per bending plane and the torsion mode within 2 % of a fine FE model (Euler-Bernoulli,
    as the seed's basis; the default's Timoshenko modes are held to ROSS in test_direct_drive_oracles.py)."""
    modes = models.get("direct_drive", **SEED_BASIS, **TABLE2).modes()
    for plane, (kf, kr) in (("y", (NOM["k_front_y"], NOM["k_rear_y"])), ("z", (NOM["k_front_z"], NOM["k_rear_z"]))):
        fe = _fe_plane(kf, kr, NOM)
        ours = np.sort(modes[modes[f"share_bearing_{plane}"] + modes[f"share_bending_{plane}_1"]
                             + modes[f"share_bending_{plane}_2"] > 0.5]["frequency_hz"].to_numpy())
        # the two lowest modes of each plane (rotor rocking 3.25 Hz, second bending 19-21 Hz)
        np.testing.assert_allclose(ours[:2], fe[:2], rtol=0.02)
        # the third (bearing mode with a bent shaft) is 23 % (y) high: the seed's pinned-support
        # shapes cannot bend the shaft at the bearings (seed 000 §2.5 says so) -- a known limit
        assert ours[2] > fe[2]
    # torsion: two discs (hub, generator) on the massless shaft the FFR model assumes
    tor = modes.loc[modes["label"] == "torsion_1", "frequency_hz"].iloc[0]
    two_disc = np.sqrt(NOM["shaft_torsional_stiffness"] / NOM["shaft_length"]
                       * (1 / NOM["hub_inertia_x"] + 1 / NOM["generator_inertia_x"])) / (2 * np.pi)
    assert tor == pytest.approx(two_disc, rel=0.02)


def test_fe_frequencies_for_seed_table_1() -> None:
    """Seed 000 Table 1 lists 6.08 / 29.54 Hz bending, 127.8 Hz axial, 37.8 Hz torsion for its
    shaft. With Table 2's values (L = 6, bearings at 1 and 5 m, 40 t and 30 t point masses,
    m_ms = 1 t, EI = 1e9) an Euler-Bernoulli FE model gives 17.4 / 27.4 Hz bending: Table 1's
    first mode would need rho A = 1481 kg/m (from its own beta_1 = 0.2156 and
    omega = beta^2 sqrt(EI / rho A)), a 8.9 t shaft, so Table 1 and Table 2 do not describe the
    same shaft; the second mode (end masses near nodes) agrees within 8 %. The axial and torsion
    values depend on EA, GJ and inertias Table 2 does not give."""
    spec = BeamSpec(nodes=mesh([0, 1, 5, 6], 0.25), mass=1000.0, polar_inertia=450.0, EI=1e9, EA=2.24e10,
                    GJ=7.69e8, end_masses=((0, 40000, 1.96e6, 0.0), (6, 30000, 7.5e3, 0.0)), supports=(1, 5),
                    axial_support=1)
    md = shaft_modes(spec)
    np.testing.assert_allclose(md.freq_bending, [17.44, 27.35], rtol=2e-3)
    assert md.freq_bending[1] == pytest.approx(29.54, rel=0.08)


@pytest.mark.parametrize("fidelity, h", [("flexible", 0.005), ("rigid", 0.01)])
def test_halving_the_step_changes_objectives_below_half_a_percent(fidelity: str, h: float) -> None:
    coarse = models.get("direct_drive", fidelity=fidelity, time_step=h).evaluate(None, TURBULENT_60S)
    fine = models.get("direct_drive", fidelity=fidelity, time_step=h / 2).evaluate(None, TURBULENT_60S)
    nonzero = fine.columns[(fine.abs() > 0).all()]
    rel = ((coarse[nonzero] - fine[nonzero]) / fine[nonzero]).abs().max(axis=None)
    assert rel < 5e-3, rel


def _radau_errors(*steps: float) -> list[float]:
    """The largest relative objective error of the flexible fidelity at each time step [s] against Radau
    (rtol 1e-6) on the same equations, 8 s at 11 m/s, I 0.12."""
    scene = Scene(wind_speed=11.0, turbulence_intensity=0.12, duration=8.0, seed=1)
    ref = models.get("direct_drive", integrator="Radau").evaluate(None, scene)
    nonzero = ref.columns[(ref.abs() > 0).all()]
    out = []
    for h in steps:
        fast = models.get("direct_drive", time_step=h).evaluate(None, scene)
        out.append(float(((fast[nonzero] - ref[nonzero]) / ref[nonzero]).abs().max(axis=None)))
    return out


@pytest.mark.slow                  # ~15-25 s (Radau on the 5-mode basis); the default run keeps the step-halving test
def test_generalised_alpha_converges_to_solve_ivp_radau() -> None:
    """Generalised-alpha against Radau (rtol 1e-6) on the same equations: second order (the error at 2.5 ms
    below 0.3 of the 5 ms one) and within 1 % at 2.5 ms. Measured on Table 1's shaft (the default since issue
    47): 2.09 % at 5 ms (the bearing's mean radial force, then the generator-end deflection 1.8 %), 0.57 % at
    2.5 ms, 0.11 % at 1.25 ms (0.66 / 0.17 / 0.03 % on Table 2's shaft before)."""
    coarse, fine = _radau_errors(0.005, 0.0025)
    assert fine < 1e-2 and fine < 0.3 * coarse, (coarse, fine)


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="the default 5 ms step reads 2.1 % from Radau on Table 1's shaft (the "
                   "default since issue 47), over the speed bench's 1 % flexible_error target; the default step "
                   "is to be chosen again (2.5 ms: 0.57 %, twice the run time): docs/physics.md")
def test_the_default_step_is_within_one_percent_of_radau() -> None:
    """The speed bench's ``flexible_error`` target, 1 %, at the default step (5 ms)."""
    assert _radau_errors(0.005)[0] < 1e-2


def test_flexible_takes_one_newton_iteration_a_step() -> None:
    """What the flexible fidelity's cost rests on (one kernel evaluation and one solve a step):
    with the extrapolating predictor the first correction is below the 1e-6 m tolerance almost
    every step (measured 1.002 on average, worst 2, on the 600 s bench scene)."""
    sim = models.get("direct_drive", fidelity="flexible").simulate(TURBULENT_60S)
    assert 1.0 <= sim.attrs["mean_newton_iterations"] < 1.05, sim.attrs["mean_newton_iterations"]
    assert sim.attrs["max_newton_iterations"] <= 3


def test_rigid_and_flexible_damage_indices() -> None:
    """Measured (60 s, I_ref 0.12): rigid/flexible damage 0.97/0.92 at 6 m/s, 0.90/0.82 at
    11 m/s, 0.78/0.77 at 18 m/s. Static reactions of two bearings do not depend on shaft
    flexibility, but the flexible shaft's rotor-rocking mode (3.25 Hz, 1 % damping) adds dynamic
    bearing load that the rigid model lacks, more so at high wind (seed 000 found near-equal
    damage). Tolerance: the rigid model is within -30 % / +5 % of the flexible one."""
    flex = models.get("direct_drive").evaluate(None, TURBULENT_60S)
    rigid = models.get("direct_drive", fidelity="rigid").evaluate(None, TURBULENT_60S)
    for col in ("damage_front", "damage_rear"):
        ratio = rigid[col].iloc[0] / flex[col].iloc[0]
        assert 0.7 < ratio < 1.05, (col, ratio)
    # deflection at the shaft ends is shaft bending: the rigid model sees only bearing compliance
    assert rigid["rms_deflection_hub"].iloc[0] < 0.2 * flex["rms_deflection_hub"].iloc[0]


def test_failed_points_are_reported_not_imputed() -> None:
    model = models.get("direct_drive")
    out = model.evaluate({"front_bearing_x": 5.5}, Scene(duration=5.0, turbulence_intensity=0.0))
    assert out.isna().all(axis=None)
    assert "bearing positions must satisfy" in out.attrs["failures"][0]


@pytest.mark.parametrize("wind", [6.0, 18.0])
def test_linear_fidelity_agrees_with_flexible(wind: float) -> None:
    """The flexible model linearised about the scene's mean operating point (gyroscopic terms at
    the mean speed, bending in non-rotating coordinates). Measured on 60 s scenes: within
    0.13 % at 6 and 18 m/s, 0.53 % at 11 m/s (largest rotor-speed swings). Stated band: 1 %."""
    scene = Scene(wind_speed=wind, turbulence_intensity=0.12, duration=60.0, seed=1)
    lin = models.get("direct_drive", fidelity="linear").evaluate(None, scene)
    flex = models.get("direct_drive", fidelity="flexible").evaluate(None, scene)
    nonzero = flex.columns[(flex.abs() > 0).all()]
    rel = ((lin[nonzero] - flex[nonzero]) / flex[nonzero]).abs().max(axis=None)
    assert rel < 0.01, rel


def test_linear_batch_path_matches_its_time_series_and_the_dense_recurrence(monkeypatch: pytest.MonkeyPatch) -> None:
    """The linear fidelity's batch path (modal drive from the scene's shared input windows, objectives
    from arrays) against the same model's time-series frame (:meth:`simulate` then
    :func:`objectives`) and against the dense ``x[k+1] = Phi x[k] + ...`` recurrence on the
    per-point inputs (:func:`lti_response`, forced by a zero condition limit), for points that move
    the inputs' per-point maps (excitation factors, inertias, C_gen, torque factor). Tolerance 1e-9
    relative: round-off of a reordered computation (eigenvector condition ~1e3)."""
    import ddgsa.mbs.linear as linear
    from ddgsa.models.direct_drive import objectives

    scene = Scene(wind_speed=13.0, turbulence_intensity=0.12, duration=60.0, seed=4)
    points = pd.DataFrame([NOM, {**NOM, "thrust_factor": 1.3, "torque_factor": 0.8, "hub_inertia_x": 1.8e6},
                           {**NOM, "c_gen": 1.2e6, "tilt_moment_factor": 0.7, "k_rear_y": 4e9, "rear_bearing_x": 4.6}])
    model = models.get("direct_drive", fidelity="linear")
    batch = model.evaluate(points, scene)
    frames = pd.DataFrame([objectives(model.simulate(scene, p), p, "iso281")
                           for p in points.to_dict("records")])
    monkeypatch.setattr(linear, "MAX_MODAL_CONDITION", 0.0)
    dense = models.get("direct_drive", fidelity="linear").evaluate(points, scene)
    for other in (frames, dense):
        np.testing.assert_allclose(batch.to_numpy(), other[batch.columns].to_numpy(), rtol=1e-9, atol=1e-300)


@pytest.mark.slow
def test_bench_quick_variant_produces_every_target_row() -> None:
    """``ddgsa bench --quick`` (small problems, ~1 min): every target of the speed issue has a row
    with a measured value and a verdict (but the seed studies that only the full bench runs), in the
    table and in the JSON. Timings are judged by the
    bench, never here; the only numbers checked are ones that do not depend on the machine."""
    import json as json_module

    from ddgsa.bench.speed import FULL_ONLY, TARGETS, format_speed, speed

    res = speed(quick=True)
    assert [t["key"] for t in res["targets"]] == [t[0] for t in TARGETS]
    measured = [t for t in res["targets"] if t["key"] not in FULL_ONLY]
    assert all(t["measured"] is not None and t["pass"] in (True, False) for t in measured), res["targets"]
    # the seed studies of the rig and the geared drive run in the full bench only, and say so
    assert all(t["measured"] is None and t["note"] == "not measured" for t in res["targets"] if t["key"] in FULL_ONLY)
    table = format_speed(res)
    assert all(t["target"] in table for t in res["targets"])
    assert json_module.loads(json_module.dumps(res))["targets"] == res["targets"]
    by = {t["key"]: t["measured"] for t in res["targets"]}
    assert by["flexible_error"] < 0.05                      # flexible vs Radau on the same equations
    assert by["loads_generations"] == 1                     # no realisation generated twice
    assert "/" not in res["study"]["study"].split("studies")[0]       # no absolute path of the machine


def test_excitation_factors_scale_the_hub_loads_and_keep_the_speed() -> None:
    scene = Scene(wind_speed=14.0, turbulence_intensity=0.05, duration=20.0, seed=2)
    model = models.get("direct_drive", fidelity="linear")
    base = model.simulate(scene)
    scaled = model.simulate(scene, {"thrust_factor": 1.2, "torque_factor": 1.2, "yaw_moment_factor": 0.5})
    np.testing.assert_allclose(scaled["Fx"], 1.2 * base["Fx"], rtol=1e-12)
    np.testing.assert_allclose(scaled["Mz"], 0.5 * base["Mz"], rtol=1e-12)
    # the torque factor scales aerodynamic and generator torque together: the mean speed moves by
    # 0.3 % (scaling the aerodynamic torque alone would add 0.2 M_x / C_gen = 0.95 rad/s, +75 %)
    assert abs(scaled["rotor_speed"].mean() / base["rotor_speed"].mean() - 1) < 0.01
    # and the thrust reaches the front (axial) bearing
    assert scaled["front_Fx"].mean() == pytest.approx(base["front_Fx"].mean() + 0.2 * base["Fx"].mean(), rel=1e-3)


REGRESSION = Path(__file__).parents[2] / "benchmarks" / "results" / "regression_600s.json"


def _regression(fidelity: str) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Recorded and recomputed objectives of ``fidelity`` on the 600 s bench scene."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("regression", REGRESSION.parents[1] / "regression.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    recorded = pd.DataFrame(json.loads(REGRESSION.read_text())["objectives"][fidelity])
    return recorded, module.compute(fidelity)


def test_linear_fidelity_keeps_its_recorded_600s_objectives() -> None:
    """Regression guard for ports of the model (recorded by ``benchmarks/regression.py``; the
    recorded linear figures are within 3e-8 of the dense-recurrence implementation they replaced,
    the difference being its linearised end displacements). Tolerance 1e-6 relative: round-off of
    a reordered computation passes, a change of physics or discretisation does not; another BLAS
    kernel (OpenBLAS's Nehalem against Haswell, numba's generic target) moved them by 2.7e-8 (issue 48)."""
    recorded, now = _regression("linear")
    np.testing.assert_allclose(now[recorded.columns].to_numpy(), recorded.to_numpy(), rtol=1e-6, atol=0.0)


@pytest.mark.slow
@pytest.mark.parametrize("fidelity", ["flexible", "rigid"])
def test_integrated_fidelities_keep_their_recorded_600s_objectives(fidelity: str) -> None:
    """As above for the generalised-alpha fidelities (tolerance 1e-5: the Newton loop stops at a
    1e-6 m correction, so a reordered computation may converge to a neighbouring iterate; the
    extrapolating predictor moved the recorded figures by <= 8e-6 (flexible), 5e-7 (rigid))."""
    recorded, now = _regression(fidelity)
    np.testing.assert_allclose(now[recorded.columns].to_numpy(), recorded.to_numpy(), rtol=1e-5, atol=0.0)


def _standstill_linearisation() -> tuple:
    from ddgsa.mbs.linear import linearise_spinning, state_matrices

    model = models.get("direct_drive", fidelity="linear")
    asm = model.build()
    q0 = model.static(asm, np.zeros(3), np.zeros(3))
    pairs = [(model.fields.index(f"bending_y_{k}"), model.fields.index(f"bending_z_{k}"))
             for k in range(1, 6)]
    lin, _ = linearise_spinning(asm.system, np.delete(q0, 3), 0.0, np.zeros(7), pairs)
    return model, state_matrices(lin)


def test_spinning_linearisation_at_standstill_has_the_modal_analysis_frequencies() -> None:
    """The compiled linearisation (non-rotating coordinates, spin rate as a state) against the
    model's modal analysis (its own central differences of the mass matrix and forces in body
    coordinates): at standstill both describe the same 17 oscillating modes, 3.2-717 Hz, within
    1e-5 relative below 150 Hz and 5e-5 above (finite-difference round-off grows with the stiffness) --
    except torsion: the modal analysis drops the spin rate with the spin angle, the linearisation keeps it
    as a state tied to the generator's torque law (C_gen), which moves the 43 %-damped torsion mode by
    0.14 % (tolerance 0.3 %)."""
    model, (a, _) = _standstill_linearisation()
    lam = np.linalg.eigvals(a)
    freq = np.sort(np.abs(lam[lam.imag > 1e-6]) / (2 * np.pi))
    modes = model.modes()
    torsion = (modes["label"] == "torsion_1").to_numpy()
    expected = modes["frequency_hz"].to_numpy()
    assert freq.size == expected.size == 17
    low = expected < 150.0
    np.testing.assert_allclose(freq[~torsion & low], expected[~torsion & low], rtol=1e-5)
    np.testing.assert_allclose(freq[~low], expected[~low], rtol=5e-5)
    np.testing.assert_allclose(freq[torsion], modes["frequency_hz"].to_numpy()[torsion], rtol=3e-3)


def test_modal_and_dense_lti_recurrences_agree(monkeypatch: pytest.MonkeyPatch) -> None:
    """:func:`lti_response` in modal coordinates (conjugate pairs once) against the dense
    ``x[k+1] = Phi x[k] + drive`` path it falls back to, on the direct drive's 35-state system
    with random inputs, on the load grid and on a 3x finer output grid. Tolerance: 1e-8 of each
    state's peak (eigenvector condition number ~1e3 times 1e-16 round-off, summed over 400 steps)."""
    import ddgsa.mbs.linear as linear

    _, (a, bw) = _standstill_linearisation()
    rng = np.random.default_rng(3)
    w = np.column_stack([np.cumsum(rng.standard_normal((400, 7)), axis=0) * [1e4, 1e4, 1e4, 1e5, 1e5, 1e5, 1e-3],
                         np.ones(400)])
    x0 = rng.standard_normal(a.shape[0]) * 1e-5
    for n_sub in (1, 3):
        modal = linear.lti_response(a, bw, w, 0.05, x0, n_sub=n_sub)
        monkeypatch.setattr(linear, "MAX_MODAL_CONDITION", 0.0)
        dense = linear.lti_response(a, bw, w, 0.05, x0, n_sub=n_sub)
        monkeypatch.undo()
        assert modal.shape == dense.shape == ((len(w) - 1) * n_sub + 1, a.shape[0])
        assert np.all(np.abs(modal - dense) <= 1e-8 * np.abs(dense).max(axis=0)), np.abs(modal - dense).max()


def test_modal_step_gains_are_the_integrals_of_the_cubic_input() -> None:
    """:func:`ddgsa.mbs.linear._cubic_integrals` (closed form for ``|x| >= 1``, series below)
    against adaptive quadrature on both sides of the switch, and the modal step's taps against the
    matrix-exponential gains projected on the modes (the dense path's), on the direct drive's
    system. Tolerances: 1e-13 relative (quadrature round-off), 1e-12 of the largest tap."""
    from scipy.integrate import quad

    import ddgsa.mbs.linear as linear

    for x in (0.0, 1e-3, -0.02 + 0.3j, -0.999, 1.0, -1.2 + 3.0j, -5.0 + 60.0j):
        got = linear._cubic_integrals(np.array([x]))[:, 0]
        for j in range(4):
            part = [quad(lambda s, f=f: f(np.exp(x * (1 - s)) * s ** j), 0.0, 1.0, epsabs=1e-14, epsrel=2e-14)[0]
                    for f in (np.real, np.imag)]
            assert abs(got[j] - complex(*part)) <= 1e-13 * abs(complex(*part)), (x, j)
    _, (a, bw) = _standstill_linearisation()
    step = linear.modal_step(a, bw, 0.05)
    _, gains = linear.discretise_cubic(a, bw, 0.05)
    dense = linear._window_gains(gains, 0, 1) @ np.hstack([step.vinv.real.T, step.vinv.imag.T])
    assert np.abs(step.taps - dense).max() <= 1e-12 * np.abs(dense).max()


def test_modal_basis_refuses_defective_and_keeps_normal_matrices() -> None:
    """The modal path's guard (1-norm condition of the eigenvectors): a Jordan block (defective,
    eigenvectors parallel) is refused, a damped oscillator (condition ~1) keeps one mode of its
    pair with the exact eigenvalue ``-zeta w + i w sqrt(1 - zeta^2)`` (1e-12)."""
    import ddgsa.mbs.linear as linear

    assert linear.modal_basis(np.array([[-1.0, 1.0], [0.0, -1.0]])) is None
    w, zeta = 2.0, 0.05
    lam, vec, vinv = linear.modal_basis(np.array([[0.0, 1.0], [-w * w, -2.0 * zeta * w]]))
    assert lam.shape == (1,)
    assert abs(lam[0] - complex(-zeta * w, w * np.sqrt(1 - zeta ** 2))) <= 1e-12
    assert np.allclose(vinv @ vec, 1.0, atol=1e-12)


def test_end_jacobian_closed_form_matches_central_differences_of_the_end_positions() -> None:
    """The linear fidelity's shaft-end Jacobian (closed form) against central differences of
    :func:`shaft_ends` (the flexible path's end positions) at rotations of 1e-4 and 1e-2 rad.
    Tolerance 1e-7 of the largest entry (~6 m/rad): the differences' round-off at a 1e-6 step.
    Scaling the first bending shape at the hub (entry 1) by 1 + 1e-6 moves its column by 1e-6: it fails."""
    from ddgsa.models.direct_drive import _end_jacobian, shaft_ends

    model = models.get("direct_drive", fidelity="flexible")
    asm = model.build()
    rng = np.random.default_rng(3)
    for scale in (1e-4, 1e-2):
        p0 = rng.normal(size=len(model.coordinate_names) - 1) * scale
        ends, jac = _end_jacobian(asm, p0)
        q = np.insert(p0, 3, 0.0)[None, :]
        np.testing.assert_allclose(ends, shaft_ends(q, asm)[0], rtol=0, atol=1e-14)
        h = 1e-6
        fd = np.empty_like(jac)
        for i in range(p0.size):
            up, down = p0.copy(), p0.copy()
            up[i] += h
            down[i] -= h
            fd[:, i] = (shaft_ends(np.insert(up, 3, 0.0)[None, :], asm)[0]
                        - shaft_ends(np.insert(down, 3, 0.0)[None, :], asm)[0]) / (2 * h)
        assert np.abs(jac - fd).max() <= 1e-7 * np.abs(fd).max(), np.abs(jac - fd).max()
