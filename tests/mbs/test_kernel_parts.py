"""Kernel parts against closed forms: elements, prescribed motion, flexible bodies, the exact path."""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa.errors import ModelError
from ddgsa.mbs import (AppliedLoad, Bushing6, FlexibleBody, Ground, PrescribedBody, PrescribedSpeed, RigidBody,
                       Spherical, SpringDamper3, System, TorqueLaw, TorsionalSpring, TransverseBearing, exact,
                       genalpha)
from ddgsa.mbs.statics import static_equilibrium
from ddgsa.mbs.beam import BeamSpec, mesh
from ddgsa.mbs.series import Series, sub_sampled

K, M = 4.0e4, 10.0                      # spring [N/m] and mass [kg]: w_n = 63.2 rad/s
W_N = np.sqrt(K / M)


def oscillator(load: float = 0.0, base: PrescribedBody | None = None) -> tuple[System, RigidBody]:
    mass = RigidBody("mass", M, (1.0, 1.0, 1.0))
    anchor = (base or Ground()).marker()
    els = [SpringDamper3(mass.marker(), anchor, (K, K, K), name="spring")]
    if load:
        els.append(AppliedLoad(mass.marker(), [0.0, 1.0], force=[[0.0, 0.0, load]] * 2, name="load"))
    return System([mass], els), mass


def test_step_load_exact_and_generalised_alpha_against_closed_form() -> None:
    """Undamped oscillator under a step force: z(t) = F/k (1 - cos w t)."""
    f = 100.0
    sys_, _ = oscillator(load=f)
    t_end = 0.5
    exact_run = exact.simulate(sys_, t_end, 1e-3, start="operating")
    ga_run = genalpha.simulate(sys_, t_end, 2.5e-4, rho_inf=1.0, output_every=4)
    z_true = f / K * (1 - np.cos(W_N * exact_run.t))
    iz = sys_.index("mass.z")
    np.testing.assert_allclose(exact_run.q[:, iz], z_true, atol=1e-9 * f / K)
    np.testing.assert_allclose(ga_run.q[:, iz], z_true, atol=2e-3 * f / K)      # O((w h)^2) phase error
    spring_fz = exact_run.element("spring")[:, 2]                              # force on the mass
    np.testing.assert_allclose(spring_fz, -K * z_true, atol=1e-6 * f)


def test_prescribed_base_motion() -> None:
    """Base starting at constant speed v0: x(t) = v0 t - v0 / w sin(w t) (generalised-alpha, 0.1 ms)."""
    v0 = 0.01
    times = np.linspace(0.0, 0.4, 401)
    base = PrescribedBody.translating("base", times, np.column_stack([v0 * times, 0 * times, 0 * times]))
    sys_, _ = oscillator(base=base)
    run = genalpha.simulate(sys_, 0.4, 1e-4, rho_inf=1.0, output_every=10)
    x_true = v0 * run.t - v0 / W_N * np.sin(W_N * run.t)
    np.testing.assert_allclose(run.q[:, sys_.index("mass.x")], x_true, atol=1e-3 * v0 / W_N)


def test_bushing_full_matrix_statics() -> None:
    """A body on a coupled 6 x 6 bushing under a wrench deflects by K^-1 w (force at the bushing point)."""
    rng = np.random.default_rng(3)
    a = rng.normal(size=(6, 6))
    k6 = a @ a.T + 6 * np.eye(6)
    k6[:3] *= 1e6
    k6[:, :3] *= 1e3                                       # mixed units, still symmetric positive definite
    k6 = 0.5 * (k6 + k6.T)
    body = RigidBody("body", 5.0, (0.2, 0.3, 0.4))
    wrench = np.array([300.0, -200.0, 500.0, 0.02, -0.01, 0.015])    # rotations ~1e-4 rad: linear range
    times = [0.0, 1.0]
    sys_ = System([body], [Bushing6(body.marker(), Ground().marker(), k6, name="bushing"),
                           AppliedLoad(body.marker(), times, force=[wrench[:3]] * 2, moment=[wrench[3:]] * 2)])
    q, _ = static_equilibrium(sys_)
    linear = np.linalg.solve(k6, wrench)
    # small rotations (Bryant angles = rotation vector to first order): agreement to second order in them
    np.testing.assert_allclose(q[:6], linear, rtol=0, atol=1e-3 * np.abs(linear[3:]).max())
    np.testing.assert_allclose(q[:3], linear[:3], rtol=1e-3)


def test_simply_supported_flexible_shaft_static_deflection() -> None:
    """Central load on a pinned-pinned FE shaft with bending modes 1, 2, 3: the modal truncation of
    P L^3 / 48 EI, i.e. (2 / pi^4)(1 + 1/81) / (1/48) = 0.99744 of it."""
    length, ei, load = 4.0, 2e8, 1e4
    spec = BeamSpec(nodes=mesh([0.0, length], 0.05), mass=400.0, polar_inertia=2.0, EI=ei, EA=1e10, GJ=1e8,
                    end_masses=(), supports=(0.0, length), axial_support=0.0)
    shaft = FlexibleBody.shaft("shaft", spec, fields=("bending_z_1", "bending_z_2", "bending_z_3"))
    ground = Ground()
    mid = shaft.marker((length / 2, 0, 0))
    sys_ = System([shaft], [AppliedLoad(mid, [0.0, 1.0], force=[[0.0, 0.0, -load]] * 2),
                            TorsionalSpring(shaft.marker(), ground.marker(), 1e6)],
                  [Spherical(shaft.marker(), ground.marker()),
                   TransverseBearing(shaft.marker((length, 0, 0)), ground.marker((length, 0, 0)))])
    q, _ = static_equilibrium(sys_)
    deflection = sys_.marker_state(mid, q, np.zeros(sys_.n), 0.0).r[2]
    truncated = 2 / np.pi ** 4 * (1 + 1 / 81) * load * length ** 3 / ei
    assert -deflection == pytest.approx(truncated, rel=1e-3)
    assert -deflection / (load * length ** 3 / (48 * ei)) == pytest.approx(0.99744, abs=1e-3)


def test_motor_drives_load_through_shaft() -> None:
    """Prescribed motor speed, torsional shaft, generator torque -c w: steady twist c W / k; the motor's
    multiplier is minus its driving torque c W."""
    speed, k, c = 10.0, 1e4, 100.0
    motor = RigidBody("motor", 1.0, (0.5, 0.3, 0.3))
    load = RigidBody("load", 1.0, (1.0, 0.5, 0.5), position=(1.0, 0, 0))
    ground = Ground()
    cons = [PrescribedSpeed(motor.marker(), speed, name="motor")]
    for body in (motor, load):
        cons += [Spherical(body.marker((-0.1, 0, 0)), ground.marker(body.pose.position + (-0.1, 0, 0))),
                 TransverseBearing(body.marker((0.1, 0, 0)), ground.marker(body.pose.position + (0.1, 0, 0)))]
    els = [TorsionalSpring(motor.marker(), load.marker(), k, name="shaft"),
           TorqueLaw(load.marker(), lambda t, w: -c * w, reaction=ground.marker((1.0, 0, 0)), name="generator")]
    sys_ = System([motor, load], els, cons)
    q0, qd0 = sys_.consistent_state(qd=np.where(np.isin(sys_.coord_names, ["motor.rx", "load.rx"]), speed, 0.0))
    run = genalpha.simulate(sys_, 1.0, 1e-3, q0=q0, qd0=qd0)
    twist = run.q[-1, sys_.index("motor.rx")] - run.q[-1, sys_.index("load.rx")]
    assert twist == pytest.approx(c * speed / k, rel=1e-4)
    assert run.qd[-1, sys_.index("load.rx")] == pytest.approx(speed, rel=1e-6)
    assert run.lam[-1, sys_.multiplier_names.index("motor.torque")] == pytest.approx(-c * speed, rel=1e-4)
    np.testing.assert_allclose(run.element("generator")[-1, 3:], [-c * speed, 0, 0], rtol=1e-4, atol=1e-6)


def test_series_interpolation_and_errors() -> None:
    s = Series(np.arange(5.0), np.arange(5.0) ** 2)
    assert float(s(2.0)) == pytest.approx(4.0) and float(s.derivative(2.0)) == pytest.approx(4.0)
    with pytest.raises(ModelError, match="uniformly spaced"):
        Series([0.0, 1.0, 3.0], [0.0, 1.0, 2.0])


def test_sub_sampled_is_the_series_on_the_sub_step_grid() -> None:
    """The vectorised sub-step values against the compiled scalar path (:class:`Series`), and a
    quadratic against its closed form away from the end intervals (Catmull-Rom's central-difference
    slopes are exact for a quadratic there; the ends repeat their sample)."""
    rng = np.random.default_rng(7)
    w = rng.normal(size=(9, 3))
    s = Series(0.05 * np.arange(9), w)
    fine = sub_sampled(w, 4)
    assert fine.shape == (33, 3)
    np.testing.assert_allclose(fine, [s(0.05 * i / 4) for i in range(33)], rtol=0, atol=1e-13)
    t = np.arange(9.0)
    quad = sub_sampled(t ** 2, 5)[:, 0]
    tf = np.arange(41) / 5
    np.testing.assert_allclose(quad[5:-5], tf[5:-5] ** 2, rtol=0, atol=1e-12)


def test_bad_inputs_name_the_part() -> None:
    with pytest.raises(ModelError, match="not physical"):
        RigidBody("bad", -1.0, (1, 1, 1))
    shaft = FlexibleBody.shaft("shaft", BeamSpec(nodes=mesh([0.0, 2.0], 0.5), mass=10.0, polar_inertia=1.0, EI=1e6,
                                                EA=1e8, GJ=1e6, end_masses=(), supports=(0.0, 2.0),
                                                axial_support=0.0))
    with pytest.raises(ModelError, match="not a shaft node"):
        shaft.marker((0.3, 0, 0))
    with pytest.raises(ModelError, match="unknown elastic field"):
        FlexibleBody.shaft("s", BeamSpec(nodes=(0.0, 1.0), mass=1.0, polar_inertia=1.0, EI=1.0, EA=1.0, GJ=1.0,
                                         end_masses=(), supports=(0.0, 1.0), axial_support=0.0), fields=("twist",))
    other = RigidBody("other", 1.0, (1, 1, 1))
    with pytest.raises(ModelError, match="not in the system's bodies"):
        System([RigidBody("a", 1.0, (1, 1, 1))], [SpringDamper3(other.marker(), Ground().marker(), (1, 1, 1))])
    with pytest.raises(ModelError, match="unknown coordinate"):
        System([other]).index("other.spin")


def test_kernel_imports_neither_loads_nor_models() -> None:
    """Layering: no module of ddgsa.mbs imports ddgsa.loads or ddgsa.models (the package's own
    ``__init__`` imports ``loads``, so this reads the import statements)."""
    import ast
    from pathlib import Path

    import ddgsa.mbs

    root = Path(ddgsa.mbs.__file__).parent
    found = []
    for path in root.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                     else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            found += [f"{path.name}: {n}" for n in names if n.startswith(("ddgsa.loads", "ddgsa.models"))]
    assert len(list(root.rglob("*.py"))) > 10 and found == []
