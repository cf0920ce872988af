"""First-order states (electrical fluxes, controller states) carried by the second-order integrators.

The kernel integrates ``M q_ddot = Q(q, q_dot, t)``. A state ``x`` with ``x_dot = f(x, ...)`` fits
that form exactly as the **velocity** of a unit-mass coordinate ``chi`` (``chi_dot = x``,
``chi_ddot = f``): :class:`FirstOrderStates` is such a body (``M = I``, no forces of its own),
and an element that owns the law ``f`` applies it as a generalised force through the body's
marker, whose ``v`` and ``w`` hold the states (``x[0:3]``, ``x[3:6]``). The coordinates ``chi``
themselves (time integrals of the states) are inert. Every integrator, the linearisation and the
null-space reduction then treat the states like any other coordinates; a modal analysis shows
them as real (non-oscillating) eigenvalues. At most six states per body.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.bodies import Body, Marker

Array = NDArray[np.float64]


class FirstOrderStates(Body):
    """Up to six first-order states as the velocities of unit-mass coordinates.

    Parameters
    ----------
    name : str
    states : sequence of str
        State names (the coordinates are called ``<name>.<state>``; their rates ``d_<name>.<state>``
        in a trajectory frame are the states).
    initial : array_like, optional
        Initial state values (default zeros).

    Examples
    --------
    >>> flux = FirstOrderStates("flux", ["psi_sd", "psi_sq"], initial=[0.5, 0.0])
    >>> flux.initial_state()[1].tolist()
    [0.5, 0.0]
    """

    def __init__(self, name: str, states: Sequence[str], initial: ArrayLike | None = None) -> None:
        if not 1 <= len(states) <= 6:
            raise ModelError(f"body {name!r}: {len(states)} states; a FirstOrderStates body holds 1 to 6")
        self.name = name
        self.coord_names = tuple(states)
        x0 = np.zeros(len(states)) if initial is None else np.asarray(initial, dtype=float).reshape(len(states))
        self.x0 = x0

    def marker(self, position: ArrayLike = (0.0, 0.0, 0.0), name: str | None = None) -> Marker:
        """The body's one marker (its position is ignored)."""
        return Marker(self, np.zeros(3), name or "states", np.zeros((3, 0)), np.zeros((3, 0)))

    def marker_state(self, mk: Marker, q: Array, qd: Array, t: float) -> tuple[Array, Array, Array, Array, Array]:
        n = self.n_coords
        jac = np.zeros((6, n))
        jac[:n, :n] = np.eye(n)
        vw = jac @ qd
        return np.zeros(3), np.eye(3), vw[:3], vw[3:], jac

    def initial_state(self) -> tuple[Array, Array]:
        return np.zeros(self.n_coords), self.x0.copy()

    def terms(self, q: Array, qd: Array, gravity: Array) -> tuple[Array, Array, Array, Array]:
        n = self.n_coords
        return np.eye(n), np.zeros(n), np.zeros((n, n)), np.zeros((n, n))

    def groups(self) -> dict[str, str]:
        return {f"{self.name}.{c}": f"{self.name}_state" for c in self.coord_names}
