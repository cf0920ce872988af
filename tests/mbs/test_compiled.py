"""The compiled kernel evaluates and integrates exactly what the Python objects do."""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa.errors import ModelError
from ddgsa.mbs import (AppliedLoad, Bushing6, EccentricMass, FlexibleBody, GearContact, Ground, PrescribedBody,
                       PrescribedSpeed, RigidBody, Spherical, SpringDamper3, System, TorqueLaw, TorsionalSpring,
                       TransverseBearing, genalpha)
from ddgsa.mbs.beam import BeamSpec, mesh
from ddgsa.mbs.compiled import evaluate, pack
from ddgsa.mbs.series import Series
from ddgsa.models.hss_rig.motor import LAB_MOTOR, Supply, machine_constants


def every_part() -> System:
    """A flexible shaft in a housing on a moving base, geared to a disc; one of every packable part
    (an unbalance, a fan law and a ramped induction machine among the elements)."""
    times = np.linspace(0.0, 1.0, 11)
    base = PrescribedBody.translating("base", times, np.column_stack([0 * times, 1e-3 * np.sin(6 * times),
                                                                      1e-3 * times]))
    spec = BeamSpec(nodes=mesh([0.0, 0.5, 1.5, 2.0], 0.25), mass=300.0, polar_inertia=5.0, EI=2e7, EA=1e9, GJ=1e7,
                    end_masses=((2.0, 100.0, 4.0, 2.0),), supports=(0.5, 1.5), axial_support=0.5)
    shaft = FlexibleBody.shaft("shaft", spec, fields=("torsion", "bending_y_1", "bending_z_1"), damping_ratio=0.02,
                               position=(0.0, 0.0, 0.4), angle_rates=(3.0, 0.0, 0.0))
    housing = RigidBody("housing", 400.0, (30.0, 40.0, 40.0))
    disc = RigidBody("disc", 50.0, (2.0, 1.5, 1.5), position=(2.0, 0.0, 0.0), angle_rates=(3.0, 0.0, 0.0))
    pinion = RigidBody("pinion", 10.0, (0.1, 0.2, 0.2), position=(2.0, 0.0, 0.3), angle_rates=(-6.0, 0, 0))
    rng = np.random.default_rng(1)
    a = rng.normal(size=(6, 6))
    k6 = a @ a.T * 1e6 + 1e7 * np.eye(6)
    els = [Bushing6(housing.marker(), base.marker(), k6, 1e-3 * k6, name="mounts"),
           Bushing6(shaft.marker((2.0, 0, 0)), disc.marker(), k6 * 10, k6 * 1e-2, frame="i", name="coupling"),
           SpringDamper3(disc.marker((0.2, 0, 0)), housing.marker((2.2, 0, 0)), (1e6, 2e6, 3e6), (10, 20, 30),
                         frame="i", name="seal"),
           TorsionalSpring(pinion.marker(), housing.marker((2.0, 0, 0.3)), 5e3, 10.0, name="twist"),
           TorqueLaw.linear(pinion.marker(), 20.0, 3.0, Series(times, -6 + times), reaction=housing.marker(),
                            name="generator"),
           AppliedLoad(shaft.marker((0.0, 0.1, 0.0)), times, force=rng.normal(size=(11, 3)) * 1e3,
                       moment=rng.normal(size=(11, 3)) * 1e2, name="hub"),
           EccentricMass(disc.marker(), 0.5, 0.2, name="unbalance"),
           TorqueLaw.power(disc.marker(), 40.0, 2.0, 3.0, reaction=housing.marker((2.0, 0, 0)), name="fan"),
           TorqueLaw.machine(pinion.marker(), machine_constants(LAB_MOTOR, Supply(ramp_time=0.5, start_frequency=1.0)),
                             reaction=housing.marker((2.0, 0, 0.3)), name="machine")]
    cons = [Spherical(shaft.marker((0.5, 0, 0)), housing.marker((0.5, 0, 0.4))),
            TransverseBearing(shaft.marker((1.5, 0, 0)), housing.marker((1.5, 0, 0.4))),
            Spherical(disc.marker((-0.1, 0, 0)), housing.marker((1.9, 0, 0))),
            TransverseBearing(disc.marker((0.1, 0, 0)), housing.marker((2.1, 0, 0))),
            Spherical(pinion.marker((-0.1, 0, 0)), housing.marker((1.9, 0, 0.3))),
            TransverseBearing(pinion.marker((0.1, 0, 0)), housing.marker((2.1, 0, 0.3))),
            GearContact(disc.marker(), pinion.marker(), 0.2, 0.1, housing=housing.marker((2.0, 0, 0))),
            PrescribedSpeed(shaft.marker(), Series(times, 3.0 + 0.5 * times), name="motor")]
    return System([shaft, housing, disc, pinion], els, cons, gravity=(0, 0, -9.81))


def test_compiled_evaluation_equals_python() -> None:
    sys_ = every_part()
    packed = pack(sys_)
    rng = np.random.default_rng(7)
    for t in (0.0, 0.37, 0.95):
        q = sys_.q0 + rng.normal(size=sys_.n) * 1e-2
        qd = sys_.qd0 + rng.normal(size=sys_.n)
        m, f, k, c, out, ch, jac, vel = evaluate(packed, q, qd, t)
        tm = sys_.terms(q, qd, t)
        v, b = sys_.velocity_residual(q, qd, t)
        for got, want in ((m, tm.m), (f, tm.q), (k, tm.k), (c, tm.c), (out, np.array(tm.outputs)),
                          (ch, sys_.holonomic_residual(q, qd, t)[0]), (jac, b), (vel, v)):
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * max(1.0, np.abs(want).max()))


def test_compiled_generalised_alpha_equals_python() -> None:
    sys_ = every_part()
    fast = genalpha.simulate(sys_, 0.05, 1e-3, compiled=True)
    slow = genalpha.simulate(sys_, 0.05, 1e-3, compiled=False)
    assert fast.info["method"].endswith("(compiled)") and slow.info["method"].endswith("(Python)")
    np.testing.assert_allclose(fast.q, slow.q, rtol=0, atol=1e-10)
    np.testing.assert_allclose(fast.outputs, slow.outputs, rtol=0, atol=1e-8 * np.abs(slow.outputs).max())
    np.testing.assert_allclose(fast.lam, slow.lam, rtol=0, atol=1e-7 * np.abs(slow.lam).max())
    assert fast.max_drift < 1e-9
    motor = sys_.constraints[-1].markers[0]              # spin of the driven section (rigid spin + twist rate)
    st = sys_.marker_state(motor, fast.q[-1], fast.qd[-1], fast.t[-1])
    # the prescribed speed holds (its C1 interpolant, which near the first sample is not the straight line)
    assert st.a[:, 0] @ st.w == pytest.approx(float(sys_.constraints[-1].speed(fast.t[-1])), rel=1e-9)


def test_python_only_parts_are_named() -> None:
    body = RigidBody("b", 1.0, (1, 1, 1))
    sys_ = System([body], [TorqueLaw(body.marker(), lambda t, w: 1.0, name="custom")])
    with pytest.raises(ModelError, match="torque law 'custom' is a Python function"):
        pack(sys_)
    with pytest.raises(ModelError, match="torque law 'custom'"):
        genalpha.simulate(sys_, 0.01, 1e-3, compiled=True)
    assert genalpha.simulate(sys_, 0.01, 1e-3).info["method"].endswith("(Python)")
    base = PrescribedBody("shaker", lambda t: (np.zeros(3), np.eye(3), np.zeros(3), np.zeros(3)))
    with pytest.raises(ModelError, match="Python trajectory"):
        pack(System([body], [SpringDamper3(body.marker(), base.marker(), (1, 1, 1))]))
    assert Ground().fixed_pose is not None


def test_compiled_linearisation_and_consistent_state_equal_python() -> None:
    """``linearise_system(compiled=...)`` (compiled central differences, accelerations and the constraint
    values' curvature ``d(C_q qd)/dq``) gives the Python path's matrices, and ``consistent_state`` with the
    compiled constraint values the Python state (1e-9 of each matrix's scale; 1e-12 for the state)."""
    from ddgsa.mbs.compiled import constraint_values
    from ddgsa.mbs.derivatives import central_jacobian
    from ddgsa.mbs.modal import linearise_system

    sys_ = every_part()
    packed = pack(sys_)
    rng = np.random.default_rng(3)
    q, qd = sys_.q0 + rng.normal(size=sys_.n) * 1e-3, sys_.qd0 + rng.normal(size=sys_.n) * 0.1
    want = sys_.consistent_state(q, qd, 0.2, keep=[0])
    got = sys_.consistent_state(q, qd, 0.2, keep=[0], residuals=lambda *a: constraint_values(packed, *a))
    for g, w in zip(got, want):
        np.testing.assert_allclose(g, w, rtol=0, atol=1e-12 * np.abs(w).max())
    q, qd = want
    slow = linearise_system(sys_, q, qd, 0.2, rel_step=1e-4)
    fast = linearise_system(sys_, q, qd, 0.2, rel_step=1e-4, compiled=packed)
    for name in ("m_full", "c_full", "k_full", "qdd0", "lam0"):
        g, w = getattr(fast, name), getattr(slow, name)
        np.testing.assert_allclose(g, w, rtol=0, atol=1e-9 * np.abs(w).max(), err_msg=name)
    # the null-space basis of C_q is not unique: its projector and the projected force are
    np.testing.assert_allclose(fast.basis @ fast.basis.T, slow.basis @ slow.basis.T, rtol=0, atol=1e-12)
    np.testing.assert_allclose(fast.basis @ fast.r0, slow.basis @ slow.r0, rtol=0, atol=1e-9 * np.abs(slow.r0).max())
    curvature = central_jacobian(lambda x: sys_.velocity_residual(x, qd, 0.2)[0], [q], 0, 1e-3, rel_step=1e-4)
    assert slow.curvature is None
    np.testing.assert_allclose(fast.curvature, curvature, rtol=0, atol=1e-9 * np.abs(curvature).max())


def test_residual_rows_are_the_assemblys_mass_and_force() -> None:
    """:func:`ddgsa.mbs.compiled._residuals` (what the central differences assemble, one compiled call for all
    steps) is ``M qdd - Q`` of the assembly (:func:`_terms`) at each row's own state and acceleration, on a
    constrained system at moved, moving states (velocity steps: without the constraints' term), to
    round-off (1e-13 of the largest term: the two products sum in different orders)."""
    from ddgsa.mbs.compiled import _residuals, _terms

    system = every_part()
    packed = pack(system)
    rows = np.arange(3)[:, None]
    q = system.q0 + 1e-3 * np.sin(np.arange(system.n) + rows)
    qd = 0.1 * np.cos(np.arange(system.n) + rows)
    qdd = np.cos(2.0 * np.arange(system.n) + rows)
    res = _residuals(q, qd, qdd, np.zeros(0), 0.3, packed.arrays, False, np.full(3, -1))
    for j in range(3):
        m, f = _terms(q[j], qd[j], 0.3, packed.arrays, True, True, -1)[:2]
        ref = m @ qdd[j] - f
        np.testing.assert_allclose(res[j], ref, rtol=0, atol=1e-13 * max(np.abs(m @ qdd[j]).max(), np.abs(f).max()))


def test_the_assembly_is_compiled_once_whatever_its_callers_pass() -> None:
    """Guard on first-run compilation time (not on numbers). :func:`ddgsa.mbs.compiled._terms`, with
    every element law under it, is linked whole into each compiled caller and compiled once per
    argument *type*; a literal ``True`` / ``False`` / ``0`` passed by compiled code is a type of its own
    and compiles it (~25 s) again. So no compiled function of the kernel may pass a literal to it or to
    the packed kind (read from the source: a warm on-disk cache hides the extra copies from
    ``signatures``); and the single-body kernel's arrays must all be writeable and C-contiguous (the
    direct drive's read-only shaft matrices compiled its kernel twice)."""
    import ast
    import inspect

    from ddgsa.mbs import alpha, compiled
    from ddgsa.models.direct_drive import DirectDrive

    literal_calls = []
    for module in (compiled, alpha):
        for fn in ast.walk(ast.parse(inspect.getsource(module))):
            if not isinstance(fn, ast.FunctionDef) or not any("njit" in ast.unparse(d) for d in fn.decorator_list):
                continue
            for call in ast.walk(fn):
                if isinstance(call, ast.Call) and ast.unparse(call.func) in ("_terms", "_evaluate") and \
                        any(isinstance(a, ast.Constant) for a in call.args):
                    literal_calls.append(f"{module.__name__}.{fn.name}: {ast.unparse(call)}")
    assert not literal_calls, literal_calls
    arrays = DirectDrive().build().system.args()
    loose = [i for i, a in enumerate(arrays) if isinstance(a, np.ndarray)
             and not (a.flags.writeable and a.flags.c_contiguous)]
    assert not loose, f"single-body arrays {loose} are read-only or not C-contiguous"


def test_stepped_residuals_are_the_full_residuals() -> None:
    """:func:`ddgsa.mbs.compiled.stepped_residuals` (a step's residual as the operating point's plus the change of
    the stepped body's terms and of the elements on its markers) against the full residual of every row
    (:func:`_residuals`: every body and element evaluated), on four bodies, a prescribed base and one of every
    packable element, each row moving every coordinate, rate and acceleration of one body at a moving state:
    within 1e-12 of the largest term. A row whose step leaves its named body is wrong by the other body's change
    (the contract the caller keeps: checked to fail)."""
    from ddgsa.mbs.compiled import _residuals, stepped_residuals

    system = every_part()
    packed = pack(system)
    n, t = system.n, 0.3
    rng = np.random.default_rng(5)
    q0 = system.q0 + 1e-3 * rng.normal(size=n)
    qd0, qdd0 = system.qd0 + 0.1 * rng.normal(size=n), rng.normal(size=n)
    base = _residuals(q0[None], qd0[None], qdd0[None], np.zeros(0), t, packed.arrays, False, np.full(1, -1))[0]
    coords = np.arange(n)
    qs, qds, qdds = (np.tile(x, (n + 1, 1)) for x in (q0, qd0, qdd0))
    for c in coords:
        body = next(sl for sl in system.slices.values() if sl.start <= c < sl.stop)
        span = np.arange(body.start, body.stop)
        qs[c, span] += 1e-3 * rng.normal(size=span.size)
        qds[c, span] += 0.1 * rng.normal(size=span.size)
        qdds[c, span] += rng.normal(size=span.size)
    got = stepped_residuals(packed, qs, qds, qdds, t, base, coords)
    want = _residuals(qs[:n], qds[:n], qdds[:n], np.zeros(0), t, packed.arrays, False, np.full(n, -1))
    assert np.abs(got - want).max() <= 1e-12 * np.abs(want).max()
    wrong = stepped_residuals(packed, qs, qds, qdds, t, base, np.roll(coords, 9))
    assert np.abs(wrong - want).max() > 1e-6 * np.abs(want).max()
