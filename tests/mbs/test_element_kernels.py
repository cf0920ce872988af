"""The element and constraint kernels that the Python objects and the packed system share
(:mod:`ddgsa.mbs.elements`, :mod:`ddgsa.mbs.constraints`), against closed forms on both paths."""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa.mbs import Bushing6, EccentricMass, Ground, RigidBody, System, TorqueLaw, genalpha
from ddgsa.errors import ModelError
from ddgsa.mbs.compiled import evaluate, pack
from ddgsa.mbs.statics import static_equilibrium

OFFSET = np.array([2e-4, -1e-4, 3e-4, 0.0, 0.0, 0.0])
K6 = np.diag([1e6, 2e6, 3e6, 1e4, 2e4, 3e4])


def _preloaded(frame: str) -> System:
    """A body on a bushing to the ground with a fixed pre-deflection (the rig coupling's misalignment)."""
    body = RigidBody("b", mass=2.0, inertia=(0.1, 0.2, 0.3), position=(0.5, 0.0, 0.0))
    bushing = Bushing6(Ground().marker((0.5, 0.0, 0.0)), body.marker(), K6, 0.01 * K6, frame=frame)
    bushing.offset = OFFSET.copy()
    return System([body], [bushing], gravity=(0.0, 0.0, 0.0))


@pytest.mark.parametrize("frame", ["global", "i"])
def test_a_preloaded_connector_pushes_by_k_offset_and_rests_at_minus_offset(frame: str) -> None:
    """At the rest pose the connector's force is ``K offset`` (on both paths); in static
    equilibrium the body has moved by ``-offset`` (translations: exact for a linear connector)."""
    system = _preloaded(frame)
    q0, qd0 = system.q0, np.zeros(system.n)
    python = system.terms(q0, qd0, 0.0).outputs[0]
    compiled = evaluate(pack(system), q0, qd0, 0.0)[4][0]
    for out in (python, compiled):
        np.testing.assert_allclose(out, K6 @ OFFSET, rtol=1e-14, atol=0.0)
    q, _ = static_equilibrium(system, q0)
    np.testing.assert_allclose(q[:3] - q0[:3], -OFFSET[:3], rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(q[3:6], 0.0, atol=1e-15)


def test_linear_torque_law_spins_up_as_the_closed_form() -> None:
    """A disc on a frictionless spin bearing driven by ``T = T0 + c (w_set - w)`` from rest spins up as
    ``w(t) = (w_set + T0/c)(1 - exp(-c t / J))``: compiled and Python generalised-alpha both."""
    j_x, torque0, damping, w_set = 0.5, 2.0, 4.0, 3.0
    disc = RigidBody("disc", mass=1.0, inertia=(j_x, 1.0, 1.0))
    law = TorqueLaw.linear(disc.marker(), torque0, damping, w_set, reaction=Ground().marker())
    system = System([disc], [law], gravity=(0.0, 0.0, 0.0))
    t_end = 0.5
    exact = (w_set + torque0 / damping) * (1.0 - np.exp(-damping * t_end / j_x))
    for compiled in (True, False):
        run = genalpha.simulate(system, t_end=t_end, dt=1e-3, compiled=compiled)
        assert run.qd[-1, system.index("disc.rx")] == pytest.approx(exact, rel=2e-6)


def test_power_torque_law_runs_down_as_the_closed_form() -> None:
    """A disc spinning at ``w0`` against ``T = -T_L (w / w_r)^2`` slows as ``w(t) = w0 / (1 + a w0 t)``,
    ``a = T_L / (J w_r^2)``: the compiled form (:meth:`TorqueLaw.power`) and the Python path both."""
    j_x, t_l, w_r, w0 = 0.5, 3.0, 10.0, 20.0
    disc = RigidBody("disc", mass=1.0, inertia=(j_x, 1.0, 1.0), angle_rates=(w0, 0.0, 0.0))
    law = TorqueLaw.power(disc.marker(), t_l, 2.0, w_r, reaction=Ground().marker())
    system = System([disc], [law], gravity=(0.0, 0.0, 0.0))
    assert law.compiled() is not None
    t_end = 0.5
    exact = w0 / (1.0 + t_l / (j_x * w_r**2) * w0 * t_end)
    for compiled in (True, False):
        run = genalpha.simulate(system, t_end=t_end, dt=1e-3, compiled=compiled)
        assert run.qd[-1, system.index("disc.rx")] == pytest.approx(exact, rel=2e-6)


def test_eccentric_mass_pulls_m_e_w2_along_its_turning_axis() -> None:
    """An unbalance ``m_u`` at ``e`` on a disc spinning at ``w`` about x, turned by ``phi``: the force is
    ``m_u e w^2 (0, cos phi, sin phi)`` [N] (outward along the turned y axis), no moment, on both paths."""
    mass, radius, w, phi = 0.01, 0.05, 150.0, 0.7
    disc = RigidBody("disc", mass=1.0, inertia=(0.5, 1.0, 1.0), angles=(phi, 0.0, 0.0), angle_rates=(w, 0.0, 0.0))
    system = System([disc], [EccentricMass(disc.marker(), mass, radius)], gravity=(0.0, 0.0, 0.0))
    q0, qd0 = system.q0, system.qd0
    exact = mass * radius * w**2 * np.array([0.0, np.cos(phi), np.sin(phi), 0.0, 0.0, 0.0])
    python = system.terms(q0, qd0, 0.0).outputs[0]
    compiled = evaluate(pack(system), q0, qd0, 0.0)[4][0]
    for out in (python, compiled):
        np.testing.assert_allclose(np.ravel(out), exact, rtol=1e-12, atol=1e-12)


def test_machine_torque_law_is_the_equivalent_circuits_torque_on_both_paths() -> None:
    """:meth:`TorqueLaw.machine` on a disc at 3 % slip of the lab motor on a balanced direct-on-line
    supply: the torque about the spin axis is the per-phase equivalent circuit's ``3 |I_r|^2 R_r /
    (s w_s)`` (:func:`~ddgsa.models.hss_rig.motor.circuit_torque`, an independent formula), by the
    Python wrench and the packed system alike; with the supply cut (``t > 0``) it is zero."""
    from ddgsa.models.hss_rig.motor import LAB_MOTOR, circuit_torque, machine_constants

    slip = 0.03
    speed = LAB_MOTOR.synchronous_speed * (1.0 - slip)
    disc = RigidBody("rotor", mass=1.0, inertia=(0.089, 1.0, 1.0), angle_rates=(speed, 0.0, 0.0))
    for cut, t, exact in ((False, 0.013, float(circuit_torque(LAB_MOTOR, slip))), (True, 0.013, 0.0)):
        law = TorqueLaw.machine(disc.marker(), machine_constants(LAB_MOTOR, cut=cut))
        system = System([disc], [law], gravity=(0.0, 0.0, 0.0))
        assert law.compiled() is not None
        python = system.terms(system.q0, system.qd0, t).outputs[0]
        compiled = evaluate(pack(system), system.q0, system.qd0, t)[4][0]
        for out in (python, compiled):
            np.testing.assert_allclose(np.ravel(out)[3:], [exact, 0.0, 0.0], rtol=1e-12, atol=1e-12)
    with pytest.raises(ModelError, match="13 constants"):
        TorqueLaw.machine(disc.marker(), np.zeros(4))


def test_dq_machine_tangent_is_the_closed_form_of_its_linear_flux_equations() -> None:
    """The dq machine's flux equations are linear in the fluxes at a fixed speed: ``d psi_s' / d psi_s =
    -R_s L_r / D - j w``, ``d psi_s' / d psi_r = R_s L_m / D``, ``d psi_r' / d psi_s = R_r L_m / D``,
    ``d psi_r' / d psi_r = -R_r L_s / D - j (w - p w_m)`` (``D = L_s L_r - L_m^2``), and
    ``d psi_r' / d w_m = j p psi_r``; the compiled element's damping ``C = -dW/dv`` holds them."""
    from ddgsa.mbs.machines import N_CONSTANTS, dq_wrench, supply_on

    # a 3 kW four-pole motor on a 50 Hz direct-on-line supply (the rig's; layout: ddgsa.mbs.machines)
    c = np.array([0.435, 0.816, 0.0713, 0.0713, 0.0693, 2.0, 0.0, 100 * np.pi, 149.7, 0.0, 0.0, 0.05, 0.0])
    assert c.size == N_CONSTANTS
    rs, rr, ls, lr, lm, p = c[:6]
    d = ls * lr - lm * lm
    t, speed = 0.013, 140.0
    _, w, _ = supply_on(c, t)
    psi = np.array([0.8, -0.3, 0.7, -0.25])
    a = np.stack([np.eye(3), np.eye(3)])
    omega = np.stack([np.array([speed, 0.0, 0.0]), np.array([psi[3], 0.0, 0.0])])
    vel = np.stack([np.zeros(3), psi[:3]])
    _, damping = dq_wrench(c, t, a, omega, vel, 0, 1)

    def block(z: complex) -> np.ndarray:
        """The real 2x2 form of multiplication by ``z``."""
        return np.array([[z.real, -z.imag], [z.imag, z.real]])

    exact = np.block([[block(-rs * lr / d - 1j * w), block(complex(rs * lm / d))],
                      [block(complex(rr * lm / d)), block(-rr * ls / d - 1j * (w - p * speed))]])
    np.testing.assert_allclose(-damping[6:10, 6:10], exact, rtol=1e-6, atol=1e-6 * np.abs(exact).max())
    d_speed = 1j * p * complex(psi[2], psi[3])
    np.testing.assert_allclose(-damping[8:10, 3], [d_speed.real, d_speed.imag], rtol=1e-6)

