"""FFR kernels: invariant form against point sums, rotations, inertia points; FE shaft modes against analytic."""

from __future__ import annotations

import numpy as np
import pytest

import ddgsa.models as models
from ddgsa.mbs.beam import BeamSpec, mesh, shaft_modes
from ddgsa.mbs.ffr import Invariants, body_terms, body_terms_inv, g_bar, inertia_points, rotation


@pytest.mark.parametrize("fidelity", ["flexible", "rigid"])
def test_invariant_form_equals_point_sums(fidelity: str) -> None:
    s = models.get("direct_drive", fidelity=fidelity).build().system
    inv = Invariants(s.pm, s.pu, s.ps)
    rng = np.random.default_rng(0)
    for _ in range(5):
        q = rng.normal(size=s.n_dof) * 0.05
        q[3] = rng.normal() * 3.0
        qd = rng.normal(size=s.n_dof)
        m1, f1 = body_terms(q, qd, s.pm, s.pu, s.ps, s.gravity)
        m2, f2 = body_terms_inv(q, qd, *inv.args(), s.gravity)
        np.testing.assert_allclose(m2, m1, rtol=0, atol=1e-12 * np.abs(m1).max())
        np.testing.assert_allclose(f2, f1, rtol=0, atol=1e-12 * np.abs(f1).max())
        assert np.allclose(m2, m2.T) and np.linalg.eigvalsh(m2).min() > 0


def test_rotation_and_angular_velocity_map() -> None:
    ang, rate = np.array([2.1, 0.07, -0.04]), np.array([1.3, 0.2, -0.1])
    a = rotation(ang)
    np.testing.assert_allclose(a.T @ a, np.eye(3), atol=1e-14)
    h = 1e-6
    a_dot = (rotation(ang + h * rate) - rotation(ang - h * rate)) / (2 * h)
    w_skew = a.T @ a_dot                                    # body angular velocity, skew form
    w = np.array([w_skew[2, 1], w_skew[0, 2], w_skew[1, 0]])
    np.testing.assert_allclose(g_bar(ang) @ rate, w, atol=1e-8)
    # spin about the body x axis leaves the shaft axis where it is
    np.testing.assert_allclose(rotation(np.array([5.0, 0.1, 0.2]))[:, 0], rotation(np.array([0.0, 0.1, 0.2]))[:, 0])


def test_inertia_points_reproduce_mass_and_inertia() -> None:
    m, off = inertia_points(40000.0, 1.96e6, 0.98e6 + 5e4)
    assert m.sum() == pytest.approx(40000.0) and np.all(m >= 0)
    np.testing.assert_allclose(m @ off, 0.0, atol=1e-9)
    second = np.einsum("j,ja,jb->ab", m, off, off)
    inertia = np.trace(second) * np.eye(3) - second
    np.testing.assert_allclose(inertia, np.diag([1.96e6, 1.03e6, 1.03e6]), rtol=1e-12)
    with pytest.raises(ValueError, match="not physical"):
        inertia_points(1.0, 10.0, 1.0)


def test_fe_bending_and_torsion_against_closed_form() -> None:
    """Pinned-pinned beam without end masses: f_n = (n pi / L)^2 sqrt(EI / rho A) / 2 pi."""
    length, ei, mass = 4.0, 1e9, 4000.0
    spec = BeamSpec(nodes=mesh([0.0, length], 0.1), mass=mass, polar_inertia=1.0, EI=ei, EA=1e10, GJ=7.7e8,
                    end_masses=((0.0, 1e-9, 5e4, 1e-9), (length, 1e-9, 2e4, 1e-9)), supports=(0.0, length),
                    axial_support=0.0)
    md = shaft_modes(spec)
    exact = (np.arange(1, 3) * np.pi / length) ** 2 * np.sqrt(ei / (mass / length)) / (2 * np.pi)
    np.testing.assert_allclose(md.freq_bending, exact, rtol=1e-4)
    # two discs on a (nearly massless) shaft: f = sqrt(GJ/L (1/J1 + 1/J2)) / 2 pi
    two_disc = np.sqrt(7.7e8 / length * (1 / 5e4 + 1 / 2e4)) / (2 * np.pi)
    assert md.freq_torsion[0] == pytest.approx(two_disc, rel=1e-4)


def _kernel_against_parts(fidelity: str, rigid_only: bool) -> None:
    """The single-body kernel (:func:`ddgsa.mbs.system.terms`, scalar loops) against the Python
    System of the kernel's parts it is packed from (element Jacobians and wrenches, matrix algebra)."""
    from dataclasses import replace

    from ddgsa.mbs.assembly import System
    from ddgsa.mbs.elements import AppliedLoad
    from ddgsa.mbs.system import evaluate_terms

    asm = models.get("direct_drive", fidelity=fidelity).build()
    parts = asm.kernel
    bearings, hub, generator = parts.elements[:2], parts.elements[2], parts.elements[3]
    rng = np.random.default_rng(3)
    force, moment = rng.normal(size=3) * 1e5, rng.normal(size=3) * 1e6
    loaded = AppliedLoad(hub.markers[0], [0.0, 1.0], force=[force, force], moment=[moment, moment], name="hub")
    n = asm.system.n_dof
    for _ in range(4):
        q = np.concatenate([rng.normal(size=3) * 1e-3, [rng.uniform(-np.pi, np.pi)], rng.normal(size=2) * 1e-3,
                            np.zeros(n - 6) if rigid_only else rng.normal(size=n - 6) * 1e-3])
        qd = rng.normal(size=n) * 0.1
        qd[3] = 1.2
        if rigid_only:      # the torque law: the kernel takes the section axis as the body axis (exact at q_f = 0)
            want = System(parts.bodies, [*bearings, loaded, generator], gravity=parts.gravity).terms(q, qd, 0.0)
            got = evaluate_terms(asm.system, q, qd, force, moment, 0.0)
        else:
            want = System(parts.bodies, [*bearings, loaded], gravity=parts.gravity).terms(q, qd, 0.0)
            got = evaluate_terms(replace(asm.system, c_torque=0.0), q, qd, force, moment, 0.0)
        for g, w in zip(got[:4], (want.m, want.q, want.k, want.c)):
            np.testing.assert_allclose(g, w, rtol=0, atol=1e-12 * np.abs(w).max())
        np.testing.assert_allclose(got[4], -np.array(want.outputs[:2])[:, :3], rtol=0,
                                   atol=1e-12 * np.abs(got[4]).max())


@pytest.mark.parametrize("rigid_only", [False, True])
def test_single_body_kernel_equals_the_python_system_of_its_parts(rigid_only: bool) -> None:
    _kernel_against_parts("flexible", rigid_only)
