"""Timoshenko shaft elements against the closed-form frequencies of a simply supported beam."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ddgsa.mbs.beam import BeamSpec, bending_matrices, mesh, shaft_modes, shear_coefficient

E, G, RHO, LENGTH = 210e9, 80.8e9, 7850.0, 1.0


def _spec(diameter: float, shear: float | None, n_el: int = 80) -> BeamSpec:
    area, ip = math.pi * diameter ** 2 / 4, math.pi * diameter ** 4 / 32
    return BeamSpec(nodes=mesh([0.0, LENGTH], LENGTH / n_el), mass=RHO * area * LENGTH,
                    polar_inertia=RHO * ip * LENGTH, EI=E * ip / 2, EA=E * area, GJ=G * ip, end_masses=(),
                    supports=(0.0, LENGTH), axial_support=0.0, shear_stiffness=shear)


def _simply_supported(diameter: float, kappa_ga: float, rotary: bool, n: int) -> float:
    """Lowest root [Hz] of the Timoshenko equations for w = W sin(k x), psi = Psi cos(k x), k = n pi / L:
    ``det [[kGA k^2 - rhoA w^2, -kGA k], [-kGA k, EI k^2 + kGA - rhoI w^2]] = 0`` (a quadratic in w^2)."""
    area, ip = math.pi * diameter ** 2 / 4, math.pi * diameter ** 4 / 32
    ei, rho_a, rho_i = E * ip / 2, RHO * area, RHO * ip / 2 if rotary else 0.0
    k = n * math.pi / LENGTH
    a, b = kappa_ga * k * k, ei * k * k + kappa_ga
    # (a - rho_a s)(b - rho_i s) - (kGA k)^2 = 0 with s = w^2
    coeffs = [rho_a * rho_i, -(a * rho_i + b * rho_a), a * b - (kappa_ga * k) ** 2]
    roots = np.roots(coeffs) if rho_i else np.array([-coeffs[2] / coeffs[1]])
    return math.sqrt(min(r.real for r in roots if r.real > 0)) / (2 * math.pi)


@pytest.mark.parametrize("diameter", [0.1, 0.25])
def test_timoshenko_frequencies_of_a_simply_supported_beam(diameter):
    """Slenderness L/r 40 and 16: the first three bending frequencies within 5e-4 of the closed form (80
    elements; the interdependent-interpolation element converges as h^2: 1.1e-3 at 40 elements for the thick
    beam's third), and shear plus rotary inertia lower them from the Euler-Bernoulli ones (by more than 10 %
    for the thick beam's third)."""
    kga = shear_coefficient(E / (2 * G) - 1) * G * math.pi * diameter ** 2 / 4
    got = shaft_modes(_spec(diameter, kga), n_bending=3).freq_bending
    want = [_simply_supported(diameter, kga, True, n) for n in (1, 2, 3)]
    np.testing.assert_allclose(got, want, rtol=5e-4)
    euler = shaft_modes(_spec(diameter, None), n_bending=3).freq_bending
    assert np.all(got < euler)
    if diameter > 0.2:
        assert 1 - got[2] / euler[2] > 0.1


def test_euler_bernoulli_limit_when_the_shear_stiffness_grows():
    """kappa G A -> infinity with the rotary inertia left in: the Rayleigh-beam closed form
    ``w^2 = EI k^4 / (rho A + rho I k^2)``; and the element
    stiffness tends to the Hermite one (relative 1e-8), so the frequencies tend to the Euler-Bernoulli
    element's (those without rotary inertia differ by the rotary term alone, checked against its closed form)."""
    d = 0.1
    stiff = 1e12 * E * math.pi * d ** 2 / 4
    got = shaft_modes(_spec(d, stiff), n_bending=3).freq_bending
    ei, rho_a, rho_i = E * math.pi * d ** 4 / 64, RHO * math.pi * d * d / 4, RHO * math.pi * d ** 4 / 64
    rayleigh = [math.sqrt(ei * k ** 4 / (rho_a + rho_i * k * k)) / (2 * math.pi)
                for k in (n * math.pi / LENGTH for n in (1, 2, 3))]
    np.testing.assert_allclose(got, rayleigh, rtol=1e-4)
    euler = shaft_modes(_spec(d, None), n_bending=3).freq_bending
    plain = [(n * math.pi / LENGTH) ** 2 * math.sqrt(E * math.pi * d ** 4 / 64 / (RHO * math.pi * d * d / 4))
             / (2 * math.pi) for n in (1, 2, 3)]
    np.testing.assert_allclose(euler, plain, rtol=1e-4)
    k_t, _ = bending_matrices(_spec(d, stiff))
    k_e, _ = bending_matrices(_spec(d, None))
    np.testing.assert_allclose(k_t, k_e, rtol=1e-7, atol=1e-7 * np.abs(k_e).max())


def test_cowper_shear_coefficients():
    """Cowper's printed values: solid circle 6 (1 + nu) / (7 + 6 nu) = 0.886 at nu = 0.3; thin tube
    (m -> 1) 2 (1 + nu) / (4 + 3 nu) = 0.531."""
    assert shear_coefficient(0.3) == pytest.approx(7.8 / 8.8, rel=1e-12)
    assert shear_coefficient(0.3, 1.0 - 1e-9) == pytest.approx(2.6 / 4.9, rel=1e-6)
