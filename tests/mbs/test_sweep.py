"""The speed sweep's compiled run (:func:`ddgsa.mbs.sweep.integrate`) against closed forms, on toy
models with compiled inputs of their own (not the rig's).

Marked slow: the loop compiled for these inputs costs ~12 s from a cold cache; the default run
checks the sweep through the rig's transients against the nonlinear ``kloss`` rig
(``tests/models/test_hss_rig_transient.py``)."""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit

from ddgsa.mbs.sweep import Inputs, SweepModel, integrate

M, C, K, F = 2.0, 0.3, 50.0, 4.0          # kg, N s/m, N/m, N
pytestmark = pytest.mark.slow


@njit(cache=True)
def constant_force(t, z, zd, data, f):  # pragma: no cover (compiled)
    """Adds ``data[0]`` [N] on the first coordinate."""
    f[0] += data[0]


def toy(m: list, c0: list, c1: list, k0: list, spin: list) -> SweepModel:
    """A sweep model without softening, circulatory stiffness or static load (``lin`` unused here)."""
    n = len(m)
    zero, zeros = np.zeros((n, n)), np.zeros(n)
    return SweepModel(np.array(m, float), np.array(c0, float), np.array(c1, float), np.array(k0, float), zero,
                      zero, zeros, zeros, zeros, np.array(spin, float), zeros, None)


@pytest.mark.parametrize("incremental", [False, True])
def test_a_still_oscillator_gives_the_closed_form_step_response_to_second_order(incremental: bool) -> None:
    """``M x'' + C x' + K x = F`` from rest, the force a compiled input: the error against
    ``F/K (1 - e^{-zeta w t}(cos w_d t + zeta w / w_d sin w_d t))`` falls 4x per halved step (the kernel's loop
    and the incremental one)."""
    model = toy([[M]], [[C]], [[0.0]], [[K]], [0.0])
    wn, zeta = np.sqrt(K / M), C / (2 * np.sqrt(K * M))
    wd = wn * np.sqrt(1 - zeta**2)
    errors = []
    for h in (4e-3, 2e-3):
        t, z, zd = integrate(model, 1.0, h, np.zeros(1), np.zeros(1), Inputs(constant_force, (F,)), rho_inf=0.8,
                             incremental=incremental)
        exact = F / K * (1 - np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta * wn / wd * np.sin(wd * t)))
        errors.append(np.max(np.abs(z[:, 0] - exact)))
    assert 3.6 < errors[0] / errors[1] < 4.4
    assert errors[1] < 2e-4 * F / K


@pytest.mark.parametrize("incremental", [False, True])
def test_the_spin_dependent_damping_is_read_at_the_steps_spin(incremental: bool) -> None:
    """A rotor coordinate spun up by a constant torque ``F`` (``W = z1'``, inertia ``J``) and a
    coordinate damped by ``C1 W`` only: while ``W = F t / J`` grows, ``x' = v0 exp(-C1 F t^2 / (2 J M))`` (the
    kernel's loop and the incremental one, with its factors kept across steps)."""
    j, c1, v0 = 0.5, 3.0, 1.0
    model = toy([[j, 0.0], [0.0, M]], np.zeros((2, 2)), [[0.0, 0.0], [0.0, c1]], np.zeros((2, 2)), [1.0, 0.0])
    t, z, zd = integrate(model, 0.5, 1e-3, np.zeros(2), np.array([0.0, v0]), Inputs(constant_force, (F,)),
                         reuse=3 if incremental else 0, incremental=incremental)
    np.testing.assert_allclose(zd[:, 0], F * t / j, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(zd[:, 1], v0 * np.exp(-c1 * F * t**2 / (2 * j * M)), rtol=2e-4)
