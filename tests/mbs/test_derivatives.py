"""The one central difference (:mod:`ddgsa.mbs.derivatives`) against closed-form Jacobians."""

import numpy as np

from ddgsa.mbs.derivatives import central_difference, central_jacobian, central_step, central_steps, stepped


def _f(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    return np.array([np.sin(x[0]) * x[1], np.exp(x[1]) + x[0] ** 3 * y[0], x[0] * x[1] * y[0]])


def _df_dx(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    return np.array([[np.cos(x[0]) * x[1], np.sin(x[0])],
                     [3 * x[0] ** 2 * y[0], np.exp(x[1])],
                     [x[1] * y[0], x[0] * y[0]]])


def test_central_difference_matches_the_closed_form_to_its_truncation_error() -> None:
    """Second order: the error falls 100x when the step falls 10x, down to ~1e-10 (round-off beyond)."""
    x, y = np.array([0.7, -1.3]), np.array([2.0])
    exact = _df_dx(x, y)
    errors = [np.max(np.abs(central_jacobian(_f, [x, y], 0, 1.0, rel_step=h) - exact)) for h in (1e-2, 1e-3)]
    assert errors[1] < 2e-6
    assert 80 < errors[0] / errors[1] < 120
    assert np.max(np.abs(central_jacobian(_f, [x, y], 0, 1.0) - exact)) < 1e-8


def test_batch_layout_and_steps() -> None:
    """Row ``j`` of the stepped arguments moves entry ``j % n`` by ``+h`` (first half) or ``-h``; the step
    is ``rel_step max(scale, |x|)``, the compiled scalar and the vector forms alike."""
    x0 = np.array([0.0, 5.0, -200.0])
    h = np.array([central_step(v, 10.0, 1e-6) for v in x0])
    np.testing.assert_allclose(h, [1e-5, 1e-5, 2e-4], rtol=1e-15)
    np.testing.assert_array_equal(central_steps(x0, 10.0, 1e-6), h)
    rows = stepped(x0, h)
    n = x0.size
    for j in range(2 * n):
        moved = np.arange(n) == j % n
        np.testing.assert_array_equal(rows[j][~moved], x0[~moved])
        assert rows[j][moved][0] == x0[j % n] + (h[j % n] if j < n else -h[j % n])
    # a linear batch function gives its matrix back, to round-off (eps |f| / h ~ 2e-8 here)
    a = np.arange(6.0).reshape(2, 3)
    np.testing.assert_allclose(central_difference(lambda x: x @ a.T, x0, 10.0), a, rtol=0, atol=1e-7)


def test_a_subset_of_columns_steps_those_entries_alone() -> None:
    """``columns``: the batch gets ``2 p`` rows, row ``j`` stepping entry ``columns[j % p]``; the Jacobian holds
    the closed form's columns there (second order, as the full difference) and zero elsewhere."""
    x, y = np.array([0.7, -1.3]), np.array([2.0])
    seen = []

    def batch(rows: np.ndarray) -> np.ndarray:
        seen.append(rows.copy())
        return np.array([_f(r, y) for r in rows])

    jac = central_difference(batch, x, 1.0, columns=np.array([1]))
    assert seen[0].shape == (2, 2)
    np.testing.assert_array_equal(seen[0][:, 0], x[0])           # entry 0 is never stepped
    np.testing.assert_array_equal(jac[:, 0], 0.0)
    np.testing.assert_allclose(jac[:, 1], _df_dx(x, y)[:, 1], rtol=0, atol=1e-8)
