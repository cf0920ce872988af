"""Lock, PrescribedCoordinate and RadialForce against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ddgsa.errors import ModelError
from ddgsa.mbs import (AppliedLoad, Ground, Lock, PrescribedCoordinate, RadialForce, RigidBody, SpringDamper3, System,
                       TorsionalSpring, genalpha, modes)
from ddgsa.mbs.assembly import accelerations
from ddgsa.mbs.modal import linearise_system, modal_analysis
from ddgsa.mbs.statics import static_equilibrium
from ddgsa.mbs.ffr import rodrigues, rotation_vector
from ddgsa.mbs.constraints import inverse_left_jacobian

K, M = 4.0e4, 10.0                       # spring [N/m], mass [kg]
AMP, OMEGA = 2e-3, 30.0                  # prescribed y(t) = AMP sin(OMEGA t) [m, rad/s]


def prescribed_mass() -> tuple[System, RigidBody]:
    """A mass on a y spring to ground, y prescribed, the other five coordinates locked to ground."""
    body = RigidBody("mass", M, (1.0, 2.0, 3.0))
    ground = Ground().marker()
    parts = [Lock(body.marker(), axes=("x", "z", "rx", "ry", "rz")),
             PrescribedCoordinate(body.marker(), "y", lambda t: AMP * math.sin(OMEGA * t),
                                  rate=lambda t: AMP * OMEGA * math.cos(OMEGA * t), name="drive")]
    return System([body], [SpringDamper3(body.marker(), ground, (0.0, K, 0.0))], parts), body


def test_prescribed_coordinate_moves_exactly_and_its_multiplier_is_the_force() -> None:
    """y(t) follows AMP sin(OMEGA t) and lambda = -(M y'' + K y), the force needed, to 1e-9 relative."""
    sys_, _ = prescribed_mass()
    iy = sys_.index("mass.y")
    i_drive = sys_.multiplier_names.index("drive.force_on_j_y")
    for t in (0.0, 0.013, 0.1):
        y, yd, ydd = AMP * math.sin(OMEGA * t), AMP * OMEGA * math.cos(OMEGA * t), -AMP * OMEGA ** 2 * math.sin(OMEGA * t)
        q, qd = np.zeros(6), np.zeros(6)
        q[iy], qd[iy] = y, yd
        c, _ = sys_.holonomic_residual(q, qd, t)
        v, _ = sys_.velocity_residual(q, qd, t)
        assert np.abs(c).max() < 1e-15 and np.abs(v).max() < 1e-15
        qdd, lam = accelerations(sys_, q, qd, t, fd_step=1e-5)
        force = M * ydd + K * y                        # what drives the mass along y(t)
        assert qdd[iy] == pytest.approx(ydd, rel=1e-7, abs=1e-9 * AMP * OMEGA ** 2)
        assert -lam[i_drive] == pytest.approx(force, rel=1e-7)      # accelerations' C_tt is a central difference
        qdd_true = np.zeros(6)
        qdd_true[iy] = ydd
        tm = sys_.terms(q, qd, t)
        lam_true = np.linalg.lstsq(sys_.constraint_jacobian(q, qd, t).T, tm.q - tm.m @ qdd_true, rcond=None)[0]
        assert -lam_true[i_drive] == pytest.approx(force, rel=1e-9, abs=1e-12 * K * AMP)
    run = genalpha.simulate(sys_, 0.2, 1e-4, output_every=10)
    np.testing.assert_allclose(run.q[:, iy], AMP * np.sin(OMEGA * run.t), atol=1e-9 * AMP)


def test_prescribed_constant_holds_static_value_and_reaction() -> None:
    """Held at y = 1 mm against the spring: the reaction on the ground is K y (static equilibrium)."""
    body = RigidBody("mass", M, (1.0, 1.0, 1.0))
    sys_ = System([body], [SpringDamper3(body.marker(), Ground().marker(), (K, K, K))],
                  [Lock(body.marker(), axes=("rx", "ry", "rz")), PrescribedCoordinate(body.marker(), "y", 1e-3)])
    q, lam = static_equilibrium(sys_)
    assert q[sys_.index("mass.y")] == pytest.approx(1e-3, rel=1e-12)
    assert -lam[-1] == pytest.approx(K * 1e-3, rel=1e-9)         # the drive pushes the mass out by K y


def test_lock_gives_the_combined_body() -> None:
    """Body 2 locked to body 1 at an offset d: torsion about body 1's x axis sees J1 + J2 + m2 d^2,
    translation along y sees m1 + m2 (1e-9 relative)."""
    m1, m2, j1, j2, d, kt, ky = 5.0, 3.0, 0.4, 0.7, 0.5, 2.0e3, 1.0e5
    b1 = RigidBody("b1", m1, (j1, 1.0, 1.0))
    b2 = RigidBody("b2", m2, (j2, 1.0, 1.0), position=(0.0, d, 0.0))
    ground = Ground().marker()
    lock12 = Lock(b2.marker(), b1.marker((0.0, d, 0.0)), name="weld")
    rot = System([b1, b2], [TorsionalSpring(b1.marker(), ground, kt)],
                 [lock12, Lock(b1.marker(), axes=("x", "y", "z", "ry", "rz"))])
    f_rot = math.sqrt(kt / (j1 + j2 + m2 * d ** 2)) / (2 * math.pi)
    assert modes(rot)["frequency_hz"].to_numpy() == pytest.approx([f_rot], rel=1e-9)
    lin = linearise_system(rot, compiled=True)                    # the locks packed (compiled kernel)
    table = modal_analysis(lin.m, lin.c, lin.k, rot.coord_names, rot.groups(), lin.basis, lin.m_full)
    assert table["frequency_hz"].to_numpy() == pytest.approx([f_rot], rel=1e-9)
    b1b = RigidBody("b1", m1, (j1, 1.0, 1.0))
    b2b = RigidBody("b2", m2, (j2, 1.0, 1.0), position=(0.0, d, 0.0))
    trans = System([b1b, b2b], [SpringDamper3(b1b.marker(), ground, (0.0, ky, 0.0))],
                   [Lock(b2b.marker(), b1b.marker((0.0, d, 0.0))), Lock(b1b.marker(), axes=("x", "z", "rx", "ry", "rz"))])
    f_trans = math.sqrt(ky / (m1 + m2)) / (2 * math.pi)
    assert modes(trans)["frequency_hz"].to_numpy() == pytest.approx([f_trans], rel=1e-9)


def test_rotation_jacobian_is_exact_at_large_angles() -> None:
    """d phi = J_l^-1(phi) d theta for exp(dtheta) exp(phi), phi of 1.2 rad (central differences, 1e-7)."""
    phi = np.array([0.7, -0.5, 0.8])
    r = rodrigues(phi)
    h = 1e-6
    fd = np.column_stack([(rotation_vector(rodrigues(h * e) @ r) - rotation_vector(rodrigues(-h * e) @ r)) / (2 * h)
                          for e in np.eye(3)])
    np.testing.assert_allclose(inverse_left_jacobian(phi), fd, atol=1e-7)


def test_radial_force_negative_stiffness_and_nonlinear_statics() -> None:
    """A linear pull F = k_n e on a rotor on springs k: f = sqrt((k - k_n)/m); a cubic law under a
    load P sits where k e - k_n e - g e^3 = P (1e-9 relative)."""
    kn, g, load = 1.5e4, 2e9, 30.0
    rotor = RigidBody("rotor", M, (1.0, 1.0, 1.0))
    stator = Ground().marker()
    pull = RadialForce(rotor.marker(), stator, lambda e: (kn * e + g * e ** 3, np.diag(kn + 3 * g * e ** 2)))
    locks = Lock(rotor.marker(), axes=("x", "rx", "ry", "rz"))
    sys_ = System([rotor], [SpringDamper3(rotor.marker(), stator, (K, K, K)), pull], [locks])
    freqs = modes(sys_)["frequency_hz"].to_numpy()
    np.testing.assert_allclose(freqs, [math.sqrt((K - kn) / M) / (2 * math.pi)] * 2, rtol=1e-9)
    sys_load = System([rotor], [SpringDamper3(rotor.marker(), stator, (K, K, K)), pull,
                                AppliedLoad(rotor.marker(), [0.0, 1.0], force=[[0.0, 0.0, load]] * 2)], [locks])
    q, _ = static_equilibrium(sys_load)
    e = q[sys_load.index("rotor.z")]
    assert (K - kn) * e - g * e ** 3 == pytest.approx(load, rel=1e-9)
    assert e > load / (K - kn)                        # the cubic pull softens further


def test_bad_axes_and_missing_rate_are_named() -> None:
    body = RigidBody("b", 1.0, (1.0, 1.0, 1.0))
    with pytest.raises(ModelError, match=r"constraint 'j'.*axes \['q'\].*x, y, z, rx, ry, rz"):
        Lock(body.marker(), axes=("q",), name="j")
    with pytest.raises(ModelError, match="needs its rate"):
        PrescribedCoordinate(body.marker(), "y", math.sin)
