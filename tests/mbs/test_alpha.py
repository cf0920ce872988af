"""The one generalised-alpha loop (:mod:`ddgsa.mbs.alpha`) against closed forms."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from ddgsa.errors import ModelError
from ddgsa.mbs.alpha import coefficients, lu_factor, lu_solve, python_loop, steps

M, C, K, F = 2.0, 0.3, 50.0, 4.0          # kg, N s/m, N/m, N


def oscillator(t: float, step: int, ctx: None, m: np.ndarray, f: np.ndarray, kt: np.ndarray, ct: np.ndarray,
               x: np.ndarray, xd: np.ndarray) -> None:
    m[:], kt[:], ct[:] = M, K, C
    f[:] = F - C * xd - K * x


def kind(x, xd, t, step, ctx, m, f, kt, ct, y, ch, jac, vel):  # noqa: ANN001, ANN202 (the loop's signature)
    oscillator(t, step, ctx, m, f, kt, ct, x, xd)
    y[0] = K * x[0]                        # the spring force as an output


def exact(t: np.ndarray) -> np.ndarray:
    """``M x'' + C x' + K x = F`` from rest at ``x = 0``: the step response [m]."""
    wn, zeta = np.sqrt(K / M), C / (2 * np.sqrt(K * M))
    wd = wn * np.sqrt(1 - zeta**2)
    return F / K * (1 - np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta * wn / wd * np.sin(wd * t)))


def run(h: float, extrapolate: bool, symmetric: bool, modified: bool, rho_inf: float = 0.8) -> tuple:
    n_steps = steps(1.0, h, 1, "test")
    acc0 = np.array([F / M])
    return python_loop(kind)(None, np.zeros(1), np.zeros(1), acc0, np.zeros(0), 0.0, h, n_steps, 1,
                             *coefficients(rho_inf), 1e-12, 5, 0, 1, extrapolate, symmetric, modified)


@pytest.mark.parametrize("extrapolate, symmetric, modified", list(itertools.product((False, True), repeat=3)))
def test_every_option_is_second_order_on_the_oscillator(extrapolate: bool, symmetric: bool, modified: bool) -> None:
    """Predictor, solver and modified Newton change the iterations, not the answer: the error
    against the exact step response falls 4x per halved step (second order) for each."""
    errors = []
    for h in (4e-3, 2e-3):
        x, xd, lam, y, drift, status, total = run(h, extrapolate, symmetric, modified)
        t = h * np.arange(x.shape[0])
        errors.append(np.max(np.abs(x[:, 0] - exact(t))))
        np.testing.assert_allclose(y[:, 0], K * x[:, 0], rtol=1e-14)
        assert status >= 1 and lam.shape == (x.shape[0], 0) and not drift.any()
    assert 3.6 < errors[0] / errors[1] < 4.4
    assert errors[1] < 2e-4 * F / K


def test_options_agree_to_the_newton_tolerance() -> None:
    """On a linear system every option converges to the same discrete solution."""
    base = run(2e-3, False, False, False)[0]
    for opts in itertools.product((False, True), repeat=3):
        np.testing.assert_allclose(run(2e-3, *opts)[0], base, rtol=0, atol=1e-11)


def test_extrapolated_predictor_saves_iterations() -> None:
    """On smooth motion the extrapolated acceleration is within the tolerance more often."""
    plain, extra = run(2e-3, False, True, False), run(2e-3, True, True, False)
    assert extra[6] < plain[6]


def test_a_failed_step_is_reported_with_the_outputs_before_it() -> None:
    def diverging(x, xd, t, step, ctx, m, f, kt, ct, y, ch, jac, vel):  # noqa: ANN001, ANN202
        m[:], kt[:], ct[:] = M, K, C
        f[:] = F - C * xd - K * x + (np.nan if t > 0.0105 else 0.0)     # the model fails from step 11
    x, *_, status, _ = python_loop(diverging)(None, np.zeros(1), np.zeros(1), np.array([F / M]), np.zeros(0), 0.0,
                                              1e-3, 50, 1, *coefficients(0.8), 1e-12, 3, 0, 0, False, False, False)
    assert status == -11 and x.shape[0] == 11


def test_steps_refuses_a_span_the_step_does_not_divide() -> None:
    with pytest.raises(ModelError, match="not a positive multiple"):
        steps(1.0, 0.3, 1, "test")
    with pytest.raises(ModelError, match="output_every = 3 must divide the 10 steps"):
        steps(1.0, 0.1, 3, "test")


def test_lu_factors_solve_as_lapack_does_with_pivoting() -> None:
    """:func:`lu_factor` / :func:`lu_solve` (modified Newton's kept factors) against LAPACK's solve, on a
    random system, on one whose first pivot is zero (so rows must swap) and on a gyroscopic-like
    non-symmetric matrix; a singular matrix gives non-finite values, which the loop reports."""
    rng = np.random.default_rng(3)
    cases = [rng.normal(size=(9, 9)), np.array([[0.0, 2.0, 1.0], [1.0, 1.0, 0.0], [3.0, 0.0, 1.0]])]
    spd = rng.normal(size=(6, 6))
    cases.append(spd @ spd.T + 6 * np.eye(6) + 40.0 * (np.triu(np.ones((6, 6)), 1) - np.tril(np.ones((6, 6)), -1)))
    for a in cases:
        b = rng.normal(size=a.shape[0])
        lu, piv = np.zeros_like(a), np.zeros(a.shape[0], dtype=np.int64)
        lu_factor(a, lu, piv)
        np.testing.assert_allclose(lu_solve(lu, piv, b), np.linalg.solve(a, b), rtol=1e-12, atol=1e-12)
    lu, piv = np.zeros((2, 2)), np.zeros(2, dtype=np.int64)
    lu_factor(np.array([[1.0, 2.0], [2.0, 4.0]]), lu, piv)
    assert not np.all(np.isfinite(lu_solve(lu, piv, np.array([1.0, 1.0]))))
