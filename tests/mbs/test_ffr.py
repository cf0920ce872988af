"""FFR kernels: invariant form against point sums, rotations, inertia points; FE shaft modes against analytic."""

from __future__ import annotations

import numpy as np
import pytest

import ddgsa.models as models
from ddgsa.mbs.beam import BeamSpec, mesh, shaft_modes
from ddgsa.mbs.ffr import Invariants, body_terms, body_terms_inv, g_bar, inertia_points, rotation


@pytest.mark.parametrize("fidelity", ["flexible", "rigid"])
def test_invariant_form_equals_point_sums(fidelity: str) -> None:
    s = models.get("direct_drive", fidelity=fidelity).assemble().system
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
