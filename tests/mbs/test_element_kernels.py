"""The element and constraint kernels that the Python objects and the packed system share
(:mod:`ddgsa.mbs.elements`, :mod:`ddgsa.mbs.constraints`), against closed forms on both paths."""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa.mbs import Bushing6, Ground, RigidBody, System, TorqueLaw, genalpha
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
