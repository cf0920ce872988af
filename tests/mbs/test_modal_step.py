"""The blocked modal recurrence (:meth:`ddgsa.mbs.linear.ModalStep.outputs`, stepped in blocks of
:data:`ddgsa.mbs.linear.STEP_BLOCK` samples) against the exact discretisation of the same LTI
system by :func:`ddgsa.mbs.linear.lti_response`, across block boundaries and with the constant
input added in the recurrence instead of as a window channel."""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa.mbs.linear import STEP_BLOCK, input_window, lti_response, modal_output_matrix, modal_step


def _system() -> tuple[np.ndarray, np.ndarray]:
    """Two damped oscillators (1.6 and 7 Hz, 2 % and 5 %) driven by two inputs."""
    a = np.zeros((4, 4))
    a[0, 2] = a[1, 3] = 1.0
    for i, (f, z) in enumerate(((1.6, 0.02), (7.0, 0.05))):
        w = 2 * np.pi * f
        a[2 + i, i], a[2 + i, 2 + i] = -w * w, -2 * z * w
    a[2, 1], a[3, 0] = 3.0, 2.0                                   # coupled: no diagonal shortcut
    bw = np.array([[0.0, 0.0], [0.0, 0.0], [1.0, 0.3], [0.0, 1.0]])
    return a, bw


@pytest.mark.parametrize("n_t", [2, 3, STEP_BLOCK, STEP_BLOCK + 1, STEP_BLOCK + 2, 2 * STEP_BLOCK + 1])
@pytest.mark.parametrize("with_constant", [False, True])
def test_blocked_modal_outputs_equal_the_exact_discretisation(n_t: int, with_constant: bool) -> None:
    a, bw = _system()
    dt = 0.01
    rng = np.random.default_rng(n_t)
    w = rng.normal(size=(n_t, 2))
    const = np.array([0.7, -0.4]) if with_constant else np.zeros(2)
    x0 = np.array([1e-3, -2e-3, 0.05, 0.01])
    c_out = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 1.0]])
    ref = lti_response(a, bw, w + const, dt, x0, c_out=c_out)
    step = modal_step(a, bw, dt)
    assert step is not None
    out = modal_output_matrix(step.vec, step.lam, c_out)
    got = step.outputs(input_window(w), x0, out, constant=const if with_constant else None)
    assert got.shape == ref.shape == (n_t, 3)
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-11 * np.abs(ref).max())
