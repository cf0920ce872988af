"""The hybrid terms (compiled parts plus Python elements) against the Python System.terms."""

from __future__ import annotations

import numpy as np

from ddgsa.mbs import Bushing6, Ground, RigidBody, SpringDamper3, System, TorqueLaw
from ddgsa.mbs.compiled import compile_terms
from ddgsa.mbs.elements import Bushing6 as PlainBushing


class _OffsetBushing(PlainBushing):
    """A bushing with a fixed pre-deflection (as the rig's misaligned coupling): it packs."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.offset = np.array([0.0, 1e-3, 0.0, 0.0, 0.0, 2e-3])


def _system() -> System:
    ground = Ground()
    a = RigidBody("a", mass=3.0, inertia=(0.2, 0.1, 0.15), angle_rates=(40.0, 0.0, 0.0))
    b = RigidBody("b", mass=2.0, inertia=(0.1, 0.05, 0.07), position=(0.5, 0.0, 0.0), angle_rates=(40.0, 0.0, 0.0))
    k6 = np.diag([1e5, 2e5, 3e5, 0.0, 1e3, 2e3])
    return System([a, b], [
        Bushing6(a.marker(), ground.marker(), k6, 0.01 * k6, free_spin=True, name="support"),
        _OffsetBushing(a.marker((0.25, 0.0, 0.0)), b.marker((-0.25, 0.0, 0.0)), np.diag([1e5] * 3 + [50.0, 1e3, 1e3]),
                       np.diag([10.0] * 6), frame="i", name="coupling"),
        SpringDamper3(b.marker((0.1, 0.0, 0.0)), ground.marker((0.6, 0.0, 0.0)), (1e5, 1e5, 1e5), (5.0, 5.0, 5.0)),
        TorqueLaw(b.marker(), lambda t, w: -0.3 * w * abs(w) + 2.0 * np.sin(t), name="drag")],
        gravity=(0.0, 0.0, -9.81))


def test_hybrid_terms_equal_the_python_terms_and_positions():
    system = _system()
    rng = np.random.default_rng(1)
    q = system.q0 + 1e-3 * rng.standard_normal(system.n)
    qd = system.qd0 + 0.1 * rng.standard_normal(system.n)
    ref = system.terms(q, qd, 0.7)
    assert compile_terms(system)
    assert [el.name for _, el in system.fast_terms.python] == ["drag"]     # the Python torque law: no compiled form
    fast = system.terms(q, qd, 0.7)
    for a, b in ((ref.m, fast.m), (ref.q, fast.q), (ref.k, fast.k), (ref.c, fast.c)):
        assert np.allclose(a, b, rtol=1e-12, atol=1e-12 * np.max(np.abs(a)))
    for a, b in zip(ref.outputs, fast.outputs):
        assert np.allclose(a, b, rtol=1e-12, atol=1e-9)
    qs = system.q0 + 1e-3 * rng.standard_normal((5, system.n))
    times = np.linspace(0.0, 1.0, 5)
    marker = system.elements[2].markers[0]
    expected = np.array([system.marker_state(marker, qi, qd, ti).r for qi, ti in zip(qs, times)])
    assert np.allclose(system.positions(marker, qs, np.tile(qd, (5, 1)), times), expected, rtol=0, atol=1e-14)
    for fast, ref_state in zip(system.states_of([marker], qs[1], qd, 0.3), [system.marker_state(marker, qs[1], qd, 0.3)]):
        for a, b in ((fast.r, ref_state.r), (fast.a, ref_state.a), (fast.v, ref_state.v), (fast.w, ref_state.w),
                     (fast.jac, ref_state.jac)):
            assert np.allclose(a, b, rtol=0, atol=1e-12)
