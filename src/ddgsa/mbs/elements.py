"""Force elements between markers of any two bodies (or one marker and a time law).

An element is one small class: it reads the states of its markers and returns the wrench
(force [N], moment [N m], global frame) on each marker and, for the Newton iterations, its
tangent stiffness and damping ``K = -d wrench / d x``, ``C = -d wrench / d x_dot`` over the
markers' motions ``x = [dr (3), dtheta (3)]`` per marker. The system maps them onto the
coordinates with the marker Jacobians (``Q += J^T w``, ``K_t += J^T K J``), the way ROSS
elements give ``M, C, K, G`` and the rotor assembles them.

Two-marker connectors act on the deflection ``d = x_j - x_i`` from the rest configuration (the
markers' relative pose when the system is built): the wrench on marker ``i`` is ``+F`` and on
``j`` is ``-F`` (plus the couple of ``F`` about the two points), with ``F = K d + C d_dot``;
:meth:`Element.output` reports ``F`` (the force the element exerts on marker ``i``).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable

import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.bodies import Marker, MarkerState
from ddgsa.mbs.ffr import cross, mm, rotation_vector, skew
from ddgsa.mbs.series import Series

Array = NDArray[np.float64]


class Element(ABC):
    """A force element acting on ``markers``."""

    name: str
    markers: tuple[Marker, ...]
    #: whether the element's wrench depends on time explicitly (an input of the linearised system)
    time_varying: bool = False

    def bind(self, states: list[MarkerState]) -> None:
        """Record the rest configuration from the markers' initial states (called by the system)."""

    @abstractmethod
    def wrench(self, t: float, states: list[MarkerState]) -> tuple[Array, Array | None, Array | None]:
        """``(W (n_markers, 6), K, C)``: wrenches on the markers and tangents (6 n_m square, or None)."""

    def potential_energy(self, states: list[MarkerState]) -> float:
        """Energy stored in the element [J] (0 for non-conservative elements)."""
        return 0.0

    def output(self, t: float, states: list[MarkerState]) -> Array:
        """What the element reports per time step: the wrench on its first marker (6,) [N, N m]."""
        return self.wrench(t, states)[0][0]


class _Connector(Element):
    """A linear 6-DOF connector ``F = K d + C d_dot`` in the global frame or marker i's frame."""

    def __init__(self, marker_i: Marker, marker_j: Marker, k6: Array, c6: Array, frame: str, free_spin: bool,
                 name: str) -> None:
        if frame not in ("global", "i"):
            raise ModelError(f"element {name!r}: frame {frame!r} not allowed; use 'global' or 'i'")
        self.markers = (marker_i, marker_j)
        self.k6, self.c6 = np.array(k6, dtype=float), np.array(c6, dtype=float)
        if free_spin:                      # no stiffness or damping about the free spin axis
            for mat in (self.k6, self.c6):
                mat[3, :] = mat[:, 3] = 0.0
        self.frame, self.free_spin, self.name = frame, free_spin, name
        self.rest_r: Array = np.zeros(3)
        self.rest_a: Array = np.eye(3)

    def bind(self, states: list[MarkerState]) -> None:
        si, sj = states
        self.rest_r = si.a.T @ (sj.r - si.r) if self.frame == "i" else sj.r - si.r
        self.rest_a = si.a.T @ sj.a

    def _deflection(self, states: list[MarkerState]) -> tuple[Array, Array, Array]:
        si, sj = states
        rest = si.a @ self.rest_r if self.frame == "i" else self.rest_r
        dr = sj.r - si.r - rest
        dw = sj.w - si.w
        if self.free_spin:
            axis = si.a[:, 0]
            dth = cross(axis, (sj.a @ self.rest_a.T)[:, 0])
            dw = dw - axis * (axis @ dw)
        else:
            dth = rotation_vector(sj.a @ self.rest_a.T @ si.a.T)
        dv = sj.v - si.v - cross(si.w, rest) if self.frame == "i" else sj.v - si.v   # d/dt of dr
        rot = si.a if self.frame == "i" else np.eye(3)
        big = np.zeros((6, 6))
        big[:3, :3] = big[3:, 3:] = rot
        return np.concatenate([dr, dth]), np.concatenate([dv, dw]), big

    @property
    def packable(self) -> bool:
        """Whether the compiled kernel computes this connector (:mod:`ddgsa.mbs.compiled`): the
        plain deflection of this class, not one a subclass adds to."""
        return type(self)._deflection is _Connector._deflection

    def _matrices(self, big: Array) -> tuple[Array, Array]:
        return big @ self.k6 @ big.T, big @ self.c6 @ big.T

    def wrench(self, t: float, states: list[MarkerState]) -> tuple[Array, Array, Array]:
        d, dd, big = self._deflection(states)
        k, c = self._matrices(big)
        f = k @ d + c @ dd
        arm = states[1].r - states[0].r
        w = np.zeros((2, 6))
        w[0] = f
        w[1, :3] = -f[:3]
        w[1, 3:] = -f[3:] + cross(arm, f[:3])
        rest = states[0].a @ self.rest_r if self.frame == "i" else np.zeros(3)
        return w, connector_tangent(k, rest, arm, f[:3]), connector_tangent(c, rest, arm, np.zeros(3))

    def potential_energy(self, states: list[MarkerState]) -> float:
        d, _, big = self._deflection(states)
        k, _ = self._matrices(big)
        return float(0.5 * d @ k @ d)


def _pair(k: Array) -> Array:
    """Tangent of a two-marker connector over ``[x_i, x_j]``: ``[[K, -K], [-K, K]]``."""
    return np.block([[k, -k], [-k, k]])


@njit(cache=True)
def connector_tangent(k: Array, rest: Array, arm: Array, force: Array) -> Array:  # pragma: no cover (compiled)
    """``-dW/dx`` (12 x 12) of a connector ``F = K d`` between markers ``i`` and ``j``.

    ``d = [r_j - r_i - rest, theta_j - theta_i]`` where ``rest`` [m] turns with marker i (a
    lever arm when the points do not coincide, frame ``i``), so ``dd/dtheta_i`` has ``skew(rest)``;
    marker j also gets the couple ``arm x F`` of the force about the two points, whose
    variation with the points adds ``-skew(F) (dr_j - dr_i)`` (``force`` the current force).
    Variations of the frame's rotation of ``K`` itself are left to the Newton iterations.

    Compiled, and the one implementation: the element's :meth:`_Connector.wrench` calls it from
    Python and the packed system (:mod:`ddgsa.mbs.compiled`) from its compiled assembly.
    """
    dmat = np.zeros((6, 12))
    sr = skew(rest)
    for r in range(3):
        dmat[r, r] = -1.0
        dmat[r, 6 + r] = 1.0
        dmat[3 + r, 3 + r] = -1.0
        dmat[3 + r, 9 + r] = 1.0
        for c in range(3):
            dmat[r, 3 + c] = sr[r, c]
    g = mm(k, dmat)
    dw = np.zeros((12, 12))
    dw[0:6] = g
    dw[6:9] = -g[:3]
    dw[9:12] = -g[3:] + mm(skew(arm), g[:3])
    sf = skew(force)
    dw[9:12, 0:3] += sf
    dw[9:12, 6:9] -= sf
    return -dw


class SpringDamper3(_Connector):
    """Three-direction spring-damper between two points (translations only; today's bearing element).

    Parameters
    ----------
    marker_i, marker_j : Marker
    stiffness, damping : (3,)
        Along the x, y, z axes of ``frame`` [N/m], [N s/m].
    frame : {'global', 'i'}
        Axes of the stiffness: the global frame, or marker i's section frame.
    """

    def __init__(self, marker_i: Marker, marker_j: Marker, stiffness: ArrayLike, damping: ArrayLike = (0, 0, 0),
                 frame: str = "global", name: str = "spring") -> None:
        k6, c6 = np.zeros((6, 6)), np.zeros((6, 6))
        k6[:3, :3] = np.diag(np.asarray(stiffness, dtype=float).reshape(3))
        c6[:3, :3] = np.diag(np.asarray(damping, dtype=float).reshape(3))
        super().__init__(marker_i, marker_j, k6, c6, frame, True, name)


class Bushing6(_Connector):
    """Six-DOF bushing with full 6 x 6 stiffness and damping (couplings, mounts, torque arms).

    The deflection is ``[dr, dtheta]``: relative translation and the rotation vector of the
    relative rotation (small angles), in the axes of ``frame``.

    Parameters
    ----------
    marker_i, marker_j : Marker
    stiffness, damping : (6, 6)
        [N/m, N/rad, N m/m, N m/rad] and the damping counterparts.
    frame : {'global', 'i'}
    free_spin : bool
        Leave the relative rotation about marker i's x axis free (a bearing or a shaft seen from
        a non-spinning support): the rotational deflection is then the tilt ``a_i x a_j`` of the
        two x axes only, so the bushing carries no torque about the spin axis.
    """

    def __init__(self, marker_i: Marker, marker_j: Marker, stiffness: ArrayLike, damping: ArrayLike | None = None,
                 frame: str = "global", free_spin: bool = False, name: str = "bushing") -> None:
        k6 = np.asarray(stiffness, dtype=float)
        c6 = np.zeros((6, 6)) if damping is None else np.asarray(damping, dtype=float)
        if k6.shape != (6, 6) or c6.shape != (6, 6):
            raise ModelError(f"element {name!r}: stiffness and damping must be 6 x 6, got {k6.shape}, {c6.shape}")
        super().__init__(marker_i, marker_j, k6, c6, frame, free_spin, name)


class TorsionalSpring(_Connector):
    """Torsional spring-damper about marker i's x axis between two sections [N m/rad], [N m s/rad]."""

    def __init__(self, marker_i: Marker, marker_j: Marker, stiffness: float, damping: float = 0.0,
                 name: str = "torsion_spring") -> None:
        k6, c6 = np.zeros((6, 6)), np.zeros((6, 6))
        k6[3, 3], c6[3, 3] = stiffness, damping
        super().__init__(marker_i, marker_j, k6, c6, "i", False, name)


class TorqueLaw(Element):
    """A torque about a marker's x axis from a law of time and speed (generator, motor).

    ``T = law(t, speed)`` [N m] acts on ``marker`` about its x axis and, reversed, on ``reaction``
    (the stator on its housing) if given; ``speed`` is the marker's spin rate relative to the
    reaction marker [rad/s].

    Parameters
    ----------
    marker : Marker
    law : callable
        ``law(t, speed) -> torque``.
    reaction : Marker, optional
    dtorque_dspeed : callable, optional
        ``d law / d speed`` [N m s/rad] for the Newton tangent (central differences otherwise).
    """

    time_varying = True
    #: ``(torque0, c, set_speed)`` of a linear law (:meth:`linear`), which the compiled path can run
    linear_form: tuple[float, float, "float | Series"] | None = None

    def __init__(self, marker: Marker, law: Callable[[float, float], float], reaction: Marker | None = None,
                 dtorque_dspeed: Callable[[float, float], float] | None = None, name: str = "torque") -> None:
        self.markers = (marker,) if reaction is None else (marker, reaction)
        self.law, self.slope, self.name = law, dtorque_dspeed, name

    @classmethod
    def linear(cls, marker: Marker, torque0: float = 0.0, damping: float = 0.0, set_speed: "float | Series" = 0.0,
               reaction: Marker | None = None, name: str = "torque") -> "TorqueLaw":
        """``T = torque0 + damping (set_speed(t) - speed)`` (a generator, seed 000 eq. 25) [N m, N m s/rad].

        ``set_speed`` is a constant [rad/s] or a :class:`Series`; this form also runs on the compiled
        path (:mod:`ddgsa.mbs.compiled`).
        """
        ws = set_speed if isinstance(set_speed, Series) else (lambda t, c=float(set_speed): c)
        law = cls(marker, lambda t, w: torque0 + damping * (float(ws(t)) - w), reaction,
                  lambda t, w: -damping, name)
        law.linear_form = (float(torque0), float(damping), set_speed)
        return law

    def wrench(self, t: float, states: list[MarkerState]) -> tuple[Array, Array, Array | None]:
        axis = states[0].a[:, 0]
        w_rel = states[0].w - (states[1].w if len(states) > 1 else 0.0)
        speed = float(axis @ w_rel)
        torque = float(self.law(t, speed))
        if self.slope is not None:
            slope = float(self.slope(t, speed))
        else:
            h = 1e-6 * max(1.0, abs(speed))
            slope = (float(self.law(t, speed + h)) - float(self.law(t, speed - h))) / (2 * h)
        n = len(states)
        w = np.zeros((n, 6))
        w[0, 3:] = torque * axis
        c = np.zeros((6 * n, 6 * n))
        c[3:6, 3:6] = -slope * np.outer(axis, axis)
        if n > 1:
            w[1, 3:] = -torque * axis
            c = _pair(c[:6, :6])
        return w, None, c


class AppliedLoad(Element):
    """Force and moment at a marker from time series (global frame): hub loads, unbalance.

    Parameters
    ----------
    marker : Marker
    times : (n_t,) uniformly spaced [s]
    force, moment : (n_t, 3), optional
        [N], [N m]; the C1 cubic interpolant of :class:`Series` between samples.
    """

    time_varying = True

    def __init__(self, marker: Marker, times: ArrayLike, force: ArrayLike | None = None,
                 moment: ArrayLike | None = None, name: str = "load") -> None:
        t = np.asarray(times, dtype=float)
        zeros = np.zeros((t.size, 3))
        f = zeros if force is None else np.asarray(force, dtype=float).reshape(t.size, 3)
        m = zeros if moment is None else np.asarray(moment, dtype=float).reshape(t.size, 3)
        self.series = Series(t, np.hstack([f, m]))
        self.markers = (marker,)
        self.name = name

    def wrench(self, t: float, states: list[MarkerState]) -> tuple[Array, None, None]:
        return self.series(t).reshape(1, 6), None, None


class RadialForce(Element):
    """A force in the plane normal to marker j's x axis, a given law of the radial displacement.

    The displacement ``e = P A_j^T (r_i - r_j) - e_0`` (``P`` picks marker j's y and z axes,
    ``e_0`` its rest value) sets ``F = law(e)`` (2,) [N] on marker ``i`` along those axes and
    ``-F`` on marker ``j``; with ``dF/de`` (2, 2) [N/m] from the law, the tangent is exact for
    coincident markers whose frame j does not turn (a rotor centre in a stator, the magnetic pull
    of an air gap: the law lives with the model, e.g. :mod:`ddgsa.models.electromagnetic`).

    Parameters
    ----------
    marker_i, marker_j : Marker
    law : callable
        ``law(e) -> (F (2,), dF/de (2, 2))`` with ``e`` (2,) [m].
    name : str

    Examples
    --------
    >>> from ddgsa.mbs import Ground, RigidBody
    >>> pull = RadialForce(RigidBody("rotor", 1.0, (1.0, 1.0, 1.0)).marker(), Ground().marker(),
    ...                    lambda e: (-1e6 * e, -1e6 * np.eye(2)))
    >>> pull.markers[1].body.name
    'ground'
    """

    def __init__(self, marker_i: Marker, marker_j: Marker,
                 law: Callable[[Array], tuple[ArrayLike, ArrayLike]], name: str = "radial_force") -> None:
        self.markers, self.law, self.name = (marker_i, marker_j), law, name
        self.rest: Array = np.zeros(2)

    def bind(self, states: list[MarkerState]) -> None:
        si, sj = states
        self.rest = sj.a[:, 1:3].T @ (si.r - sj.r)

    def displacement(self, states: list[MarkerState]) -> Array:
        """The radial displacement ``e`` (2,) [m] of marker i from its rest position, marker j's y, z axes."""
        si, sj = states
        return sj.a[:, 1:3].T @ (si.r - sj.r) - self.rest

    def wrench(self, t: float, states: list[MarkerState]) -> tuple[Array, Array, None]:
        si, sj = states
        axes = sj.a[:, 1:3]                                        # (3, 2): marker j's y and z axes
        force, slope = (np.asarray(x, dtype=float) for x in self.law(self.displacement(states)))
        f = axes @ force.reshape(2)
        w = np.zeros((2, 6))
        w[0, :3], w[1, :3] = f, -f
        w[1, 3:] = cross(sj.r - si.r, f)                           # the pair's couple, kept by marker j
        k = np.zeros((6, 6))
        k[:3, :3] = -axes @ slope.reshape(2, 2) @ axes.T
        return w, _pair(k), None
