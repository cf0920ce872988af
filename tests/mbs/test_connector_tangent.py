"""The connector's tangent, one compiled function (:func:`ddgsa.mbs.elements.connector_tangent`) that
the Python element and the packed system both call, against central differences of the forces."""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa.mbs import Bushing6, RigidBody, System
from ddgsa.mbs.compiled import evaluate, pack
from ddgsa.mbs.derivatives import central_jacobian


def _pair() -> System:
    """Two bodies on a coupled 6 x 6 bushing between points off both centres (lever arms)."""
    rng = np.random.default_rng(7)
    a, b = rng.normal(size=(6, 6)), rng.normal(size=(6, 6))
    k6, c6 = a @ a.T + 6 * np.eye(6), b @ b.T + 6 * np.eye(6)
    k6[:3, :3] *= 1e6
    c6[:3, :3] *= 1e3
    one = RigidBody("one", 3.0, (0.1, 0.2, 0.3))
    two = RigidBody("two", 4.0, (0.2, 0.2, 0.1), position=(0.8, 0.1, 0.0))
    return System([one, two], [Bushing6(one.marker((0.5, 0.05, 0.0)), two.marker((-0.3, 0.0, 0.02)), k6, c6)])


@pytest.mark.parametrize("path", ["python", "compiled"])
def test_tangents_are_the_central_differences_of_the_forces(path: str) -> None:
    """At a deflected state (translations ~1e-3 m, rotations ~1e-4 rad, at rest, no gravity) the
    bodies' terms are the bushing's alone, so ``K_t = -dQ/dq`` and ``C_t = -dQ/dq_dot``; the
    difference is of the order of the rotations (the rotation vector's derivative is the identity
    at zero relative rotation only), so 1e-3 of the largest entry."""
    sys_ = _pair()
    rng = np.random.default_rng(1)
    q = sys_.q0 + np.tile(np.r_[1e-3 * np.ones(3), 1e-4 * np.ones(3)], 2) * rng.uniform(-1, 1, sys_.n)
    qd = np.zeros(sys_.n)
    packed = pack(sys_)

    def forces(x: np.ndarray, xd: np.ndarray) -> np.ndarray:
        return sys_.terms(x, xd, 0.0).q if path == "python" else evaluate(packed, x, xd, 0.0)[1]

    kt, ct = (sys_.terms(q, qd, 0.0).k, sys_.terms(q, qd, 0.0).c) if path == "python" else \
        evaluate(packed, q, qd, 0.0)[2:4]
    fd_k = -central_jacobian(forces, [q, qd], 0, 1e-3)
    fd_c = -central_jacobian(forces, [q, qd], 1, 1e-3)
    assert np.abs(forces(q, qd)).max() > 100.0                  # the bushing is loaded: its couples count
    np.testing.assert_allclose(kt, fd_k, rtol=0, atol=1e-3 * np.abs(fd_k).max())
    np.testing.assert_allclose(ct, fd_c, rtol=0, atol=1e-6 * np.abs(fd_c).max())
