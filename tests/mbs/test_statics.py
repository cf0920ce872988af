"""The kernel's one statics (:mod:`ddgsa.mbs.statics`): held coordinates against a closed form, and
the same Newton loop run compiled on the single-body kernel against Python on the System's objects."""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa import models
from ddgsa.errors import ModelError
from ddgsa.mbs import AppliedLoad, Bushing6, Ground, RigidBody, System
from ddgsa.mbs.statics import static_equilibrium
from ddgsa.mbs.system import static_state


def _free_spin_body(spin0: float) -> System:
    """A body on a diagonal bushing that carries no torque about x (a free spin), under a wrench
    without a torque about x, its spin angle started at ``spin0`` [rad]."""
    k6 = np.diag([2e6, 3e6, 4e6, 0.0, 5e5, 6e5])
    body = RigidBody("body", 5.0, (0.2, 0.3, 0.4), angles=(spin0, 0.0, 0.0))
    wrench = np.array([300.0, -200.0, 500.0, 0.0, 20.0, -15.0])
    load = AppliedLoad(body.marker(), [0.0, 1.0], force=[wrench[:3]] * 2, moment=[wrench[3:]] * 2)
    return System([body], [Bushing6(body.marker(), Ground().marker(), k6, free_spin=True), load])


def test_held_spin_angle_keeps_its_value_and_the_rest_deflects_by_the_closed_form() -> None:
    """Held at its start (0.3 rad): translations F / k (linear springs), tilts M / k to first order
    in the tilt (~4e-5 rad); without ``hold`` the free spin leaves the tangent singular."""
    sys_ = _free_spin_body(0.3)
    for analytic in (False, True):
        q, _ = static_equilibrium(sys_, hold=(3,), analytic=analytic)
        assert q[3] == 0.3
        np.testing.assert_allclose(q[:3], [300.0 / 2e6, -200.0 / 3e6, 500.0 / 4e6], rtol=1e-9)
        np.testing.assert_allclose(q[4:6], [20.0 / 5e5, -15.0 / 6e5], rtol=1e-4)
    with pytest.raises(ModelError, match="singular"):
        static_equilibrium(sys_, analytic=True)


def test_compiled_single_body_statics_equals_the_python_statics_of_the_same_system() -> None:
    """The direct drive under gravity: the loop compiled on the single-body kernel (its own numba
    physics, :func:`ddgsa.mbs.system.static_state`) and run as Python on the System's element
    objects (:func:`static_equilibrium`, central-difference tangent) find the same state."""
    asm = models.get("direct_drive").build()
    zero = np.zeros(3)
    compiled = static_state(asm.system, zero, zero)
    python, _ = static_equilibrium(asm.kernel, np.zeros(asm.kernel.n), hold=(3,), tol=1e-12)
    assert np.abs(compiled).max() > 1e-4                       # the shaft sags under its weight
    np.testing.assert_allclose(python, compiled, rtol=0, atol=1e-9 * np.abs(compiled).max())
