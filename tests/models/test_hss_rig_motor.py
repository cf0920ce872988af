"""Induction motor of the test rig: the dq model against the equivalent circuit, Kloss, unbalance."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, minimize_scalar

from ddgsa.errors import ModelError
from ddgsa.models.hss_rig.motor import (LAB_MOTOR, InductionMotor, Supply, breakdown, circuit_torque,
                                        dq_derivatives, kloss_torque, sequence_phasors, steady_torque)

DOL = Supply()


def _locked_speed_run(motor: InductionMotor, speed: float, t_end: float, t_eval: np.ndarray, y0=None):
    """dq fluxes at a held rotor speed, integrated by scipy's Radau (tight tolerances) from ``y0`` (zero flux)."""
    sol = solve_ivp(lambda t, y: dq_derivatives(motor, DOL, t, y, speed)[0], (0.0, t_end),
                    np.zeros(4) if y0 is None else y0,
                    method="Radau", rtol=1e-10, atol=1e-10, t_eval=t_eval)
    assert sol.success
    return np.array([dq_derivatives(motor, DOL, t, y, speed)[1] for t, y in zip(sol.t, sol.y.T)])


@pytest.mark.parametrize("slip", [0.02, 0.05, 0.3, 1.0])
def test_dq_steady_torque_equals_equivalent_circuit(slip):
    """The dq model held at a speed settles to the per-phase equivalent-circuit torque (1e-3)."""
    speed = LAB_MOTOR.synchronous_speed * (1 - slip)
    torque = _locked_speed_run(LAB_MOTOR, speed, 3.0, np.array([3.0]))[-1]
    expected = float(circuit_torque(LAB_MOTOR, slip))
    assert torque == pytest.approx(expected, rel=1e-3)


def test_direct_on_line_start_settles_where_circuit_torque_meets_the_load():
    """Fifth-order start (dq + rotor inertia) against the operating point of the torque-slip curve."""
    inertia, c_load = 0.089, 0.07          # [kg m^2], generator-like load T = c w [N m s/rad]
    m = LAB_MOTOR

    def rhs(t, y):
        d, torque = dq_derivatives(m, DOL, t, y[:4], y[4])
        return np.append(d, (torque - c_load * y[4]) / inertia)

    sol = solve_ivp(rhs, (0.0, 4.0), np.zeros(5), method="Radau", rtol=1e-9, atol=1e-9)
    ws = m.synchronous_speed
    slip = brentq(lambda s: float(circuit_torque(m, s)) - c_load * ws * (1 - s), 1e-6, 0.5)
    assert sol.y[4, -1] == pytest.approx(ws * (1 - slip), rel=1e-6)
    torque_end = dq_derivatives(m, DOL, sol.t[-1], sol.y[:4, -1], sol.y[4, -1])[1]
    assert torque_end == pytest.approx(c_load * ws * (1 - slip), rel=1e-3)
    # the start passes through the breakdown torque region: peak torque above the steady one
    assert np.max([dq_derivatives(m, DOL, t, y[:4], y[4])[1] for t, y in zip(sol.t, sol.y.T)]) > 3 * torque_end


def test_kloss_formula_is_exact_without_stator_resistance_and_breakdown_is_the_maximum():
    slips = np.array([0.01, 0.05, 0.2, 0.6, 1.0])
    m0 = LAB_MOTOR.updated({"stator_resistance": 0.0})
    s_k, t_k = breakdown(m0)
    np.testing.assert_allclose(kloss_torque(slips, s_k, t_k), circuit_torque(m0, slips), rtol=1e-10)
    # with R_s > 0 the Thevenin breakdown is the maximum of the exact curve (numerical maximum)
    s_k, t_k = breakdown(LAB_MOTOR)
    res = minimize_scalar(lambda s: -float(circuit_torque(LAB_MOTOR, s)), bounds=(0.01, 1.0), method="bounded",
                          options={"xatol": 1e-10})
    assert res.x == pytest.approx(s_k, rel=1e-5)
    assert -res.fun == pytest.approx(t_k, rel=1e-9)


def test_supply_unbalance_mean_and_ripple_match_the_sequence_circuits():
    """dq at a held speed with 5 % negative sequence: mean torque = T(s) - T_neg(2 - s) (circuit),
    2f ripple as the closed form of :func:`steady_torque` (1e-3)."""
    m = LAB_MOTOR.updated({"supply_unbalance": 0.05})
    slip = 0.04
    speed = m.synchronous_speed * (1 - slip)
    f = m.supply_frequency
    t = np.linspace(1.0, 1.2, 2001)                      # 10 periods of the 2f ripple
    # start from the balanced steady fluxes (sequence circuit), so only the negative sequence settles
    _, _, psi_s, psi_r = sequence_phasors(m, 2 * math.pi * m.supply_frequency, speed, m.phase_voltage_peak)
    torque = _locked_speed_run(m, speed, 1.2, t, np.array([psi_s.real, psi_s.imag, psi_r.real, psi_r.imag]))
    theta = 2 * math.pi * f * t
    basis = np.column_stack([np.ones_like(t), np.cos(2 * theta), np.sin(2 * theta)])
    c0, cc, cs = np.linalg.lstsq(basis, torque, rcond=None)[0]
    mean_circuit = (float(circuit_torque(m, slip))
                    - float(circuit_torque(m, 2 - slip, voltage=0.05 * m.supply_voltage)))
    closed = steady_torque(m, speed)
    assert c0 == pytest.approx(mean_circuit, rel=1e-3)
    assert closed.mean == pytest.approx(mean_circuit, rel=1e-9)
    assert math.hypot(cc, cs) == pytest.approx(closed.ripple, rel=1e-3)
    assert math.atan2(-cs, cc) == pytest.approx(closed.phase, abs=1e-3)
    assert closed.ripple > 0.05 * closed.mean            # a visible 2f ripple
    assert steady_torque(LAB_MOTOR, speed).ripple == 0.0


def test_frequency_ramp_angle_is_the_integral_of_its_frequency():
    ramp = Supply(ramp_time=2.0, start_frequency=1.0)
    t = np.linspace(0.0, 3.0, 30001)
    states = np.array([ramp.state(LAB_MOTOR, ti) for ti in t])
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (states[1:, 1] + states[:-1, 1]) * np.diff(t))])
    np.testing.assert_allclose(states[:, 0], integral, atol=1e-6)
    assert states[-1, 2] == pytest.approx(LAB_MOTOR.phase_voltage_peak)
    assert states[0, 2] == pytest.approx(0.05 * LAB_MOTOR.phase_voltage_peak)


def test_bad_motor_data_is_refused_with_the_field_named():
    with pytest.raises(ModelError, match="'rotor_resistance' must be > 0, got -1"):
        InductionMotor(rotor_resistance=-1.0)
    with pytest.raises(ModelError, match="'supply_unbalance' must be in"):
        InductionMotor(supply_unbalance=1.5)
    with pytest.raises(ModelError, match="'pole_pairs' must be an integer"):
        InductionMotor(pole_pairs=2.5)


def test_the_rigs_dq_machine_and_its_flux_states_pack() -> None:
    """The rig's ``dq`` fidelity (a :class:`~ddgsa.mbs.first_order.FirstOrderStates` body of four fluxes and
    the dq machine) packs: the packed system's mass matrix, forces and tangents equal the Python objects'
    at a state with nonzero fluxes, spin and flux rates (the compiled generalised-alpha runs it)."""
    from ddgsa import models
    from ddgsa.mbs.compiled import evaluate, pack
    from ddgsa.models.hss_rig.scenes import RigScene

    rig = models.get("hss_rig", fidelity="dq").build(None, RigScene("steady", speed_rpm=1500.0, duration=0.45,
                                                                    sample_rate=2000.0, settle=0.05))[0]
    system = rig.system
    system.fast_terms = None                      # the Python objects' own assembly
    packed = pack(system)
    rng = np.random.default_rng(7)
    q, qd = system.q0 + 1e-5 * rng.standard_normal(system.n), system.qd0 + 1e-2 * rng.standard_normal(system.n)
    python = system.terms(q, qd, 0.031)
    m, f, kt, ct, *_ = evaluate(packed, q, qd, 0.031)
    for mine, theirs in ((m, python.m), (f, python.q), (kt, python.k), (ct, python.c)):
        np.testing.assert_allclose(mine, theirs, rtol=1e-12, atol=1e-12 * np.abs(theirs).max())
