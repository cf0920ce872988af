"""Kinematic constraints between markers (thesis seed 001 §2.2, eqs. 2.3-2.4).

A constraint reads its markers' states and returns its value and its Jacobian over the markers'
motions ``x = [dr (3), dtheta (3)]`` per marker; the system maps the Jacobian onto the
coordinates (``C_q = sum_m jac_x[:, m] J_m``). Two kinds:

- **holonomic** (position level, ``C(q, t) = 0``): :class:`Spherical` (eq. 2.3),
  :class:`TransverseBearing` (the two projections ``N1, N2`` of eq. 2.3), :class:`Lock` (chosen
  relative translations and rotations of two markers held at their rest values) and
  :class:`PrescribedCoordinate` (one of them held at a value or a function of time). Their
  velocity-level form ``C_q q_dot + C_t`` is ``jac_x @ [v_i, w_i, v_j, w_j] + C_t`` (prescribed
  motion of a marker enters through its rates; ``C_t`` is the explicit time rate of a prescribed
  coordinate).
- **velocity level** (``B(q) q_dot + b(t) = 0``, non-holonomic in form): :class:`GearContact`
  (eq. 2.4), :class:`PrescribedSpeed`.

The Lagrange multipliers ``lambda`` enter the dynamics as ``M q_ddot + C_q^T lambda = Q``
(eq. 2.5): the constraint force on a body is ``-C_q^T lambda``; :meth:`Constraint.reaction`
says what ``lambda`` means for each constraint.
"""

from __future__ import annotations

from abc import ABC
from collections.abc import Callable

import numpy as np
from numba import njit
from numpy.typing import NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.bodies import Ground, Marker, MarkerState
from ddgsa.mbs.elements import CompiledForm, stacked
from ddgsa.mbs.series import Series
from ddgsa.mbs.ffr import cross, mm, mv, rotation_vector, skew

Array = NDArray[np.float64]


def _rates(states: list[MarkerState]) -> Array:
    return np.concatenate([np.concatenate([s.v, s.w]) for s in states])


# ---------------------------------------------------------------------------------------------------
# The constraints' residuals and Jacobians, compiled: each is the one implementation, which the
# constraint calls from Python and the packed system (:mod:`ddgsa.mbs.compiled`) from its compiled
# assembly. Each reads the markers ``i, j (, h)`` of the arrays ``r, a, v, w`` (positions,
# orientations, velocities, angular velocities; :func:`ddgsa.mbs.elements.stacked`) and returns
# ``(C, V, jac)``: the position-level residual (empty for a velocity-level constraint), the
# velocity-level value and the Jacobian over the markers' motions ``[dr, dtheta]`` (n_eq, 6 n_markers).


@njit(cache=True)
def spherical(r, a, v, w, i, j):  # pragma: no cover (compiled)
    """:class:`Spherical`: ``C = r_i - r_j`` (3,), ``V = v_i - v_j``."""
    value, vel, jac = np.zeros(3), np.zeros(3), np.zeros((3, 12))
    for k in range(3):
        value[k] = r[i, k] - r[j, k]
        vel[k] = v[i, k] - v[j, k]
        jac[k, k] = 1.0
        jac[k, 6 + k] = -1.0
    return value, vel, jac


@njit(cache=True)
def transverse_bearing(r, a, v, w, i, j):  # pragma: no cover (compiled)
    """:class:`TransverseBearing`: ``C_k = N_k . (r_i - r_j)`` with ``N_1, N_2`` marker j's y, z axes;
    ``d C_k / d theta_j = N_k x (r_i - r_j)``."""
    d = r[i] - r[j]
    value, vel, jac = np.zeros(2), np.zeros(2), np.zeros((2, 12))
    for row in range(2):
        nv = a[j][:, 1 + row].copy()
        nxd = cross(nv, d)
        value[row] = nv[0] * d[0] + nv[1] * d[1] + nv[2] * d[2]
        acc = 0.0
        for x in range(3):
            acc += nv[x] * (v[i, x] - v[j, x]) + nxd[x] * w[j, x]
            jac[row, x] = nv[x]
            jac[row, 6 + x] = -nv[x]
            jac[row, 9 + x] = nxd[x]
        vel[row] = acc
    return value, vel, jac


@njit(cache=True)
def gear_contact(r, a, v, w, i, j, h, contact, tangent):  # pragma: no cover (compiled)
    """:class:`GearContact` (seed 001 eq. 2.4): ``V = t . (v_i^A - v_j^A)`` at the contact point
    ``A = r_h + A_h contact`` along ``t = A_h tangent`` (housing marker ``h``)."""
    p = r[h] + mv(a[h], contact)
    tan = mv(a[h], tangent)
    ci = cross(p - r[i], tan)
    cj = cross(p - r[j], tan)
    jac = np.zeros((1, 18))
    acc = 0.0
    for x in range(3):
        acc += tan[x] * v[i, x] + ci[x] * w[i, x] - tan[x] * v[j, x] - cj[x] * w[j, x]
        jac[0, x] = tan[x]
        jac[0, 3 + x] = ci[x]
        jac[0, 6 + x] = -tan[x]
        jac[0, 9 + x] = -cj[x]
    return np.zeros(0), np.array([acc]), jac


@njit(cache=True)
def prescribed_speed(r, a, v, w, i, j, speed):  # pragma: no cover (compiled)
    """:class:`PrescribedSpeed`: ``V = a_i^x . (w_i - w_j) - speed`` (``w_j`` left out when ``j < 0``)."""
    axis = a[i][:, 0].copy()
    jac = np.zeros((1, 6 if j < 0 else 12))
    acc = 0.0
    for x in range(3):
        acc += axis[x] * w[i, x]
        if j >= 0:
            acc -= axis[x] * w[j, x]
        jac[0, 3 + x] = axis[x]
        if j >= 0:
            jac[0, 9 + x] = -axis[x]
    return np.zeros(0), np.array([acc - speed]), jac


@njit(cache=True)
def inverse_left_jacobian(phi):  # pragma: no cover (compiled)
    """``J_l(phi)^-1``: maps a small global rotation ``dtheta`` of ``exp(phi)`` to ``d phi`` [-].

    ``exp(dtheta^) exp(phi^) = exp((phi + J_l^-1 dtheta)^)`` to first order (the SO(3) left Jacobian).
    """
    angle = np.sqrt(phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2])
    k = skew(phi)
    kk = mm(k, k)
    if angle < 1e-6:
        coef = 1.0 / 12.0
    else:
        coef = 1.0 / angle ** 2 - (1.0 + np.cos(angle)) / (2.0 * angle * np.sin(angle))
    return np.eye(3) - 0.5 * k + coef * kk


@njit(cache=True)
def relative_coordinates(r, a, v, w, i, j, rest_r, rest_a):  # pragma: no cover (compiled)
    """``(x, x_dot, jac)`` of :class:`Lock` and :class:`PrescribedCoordinate`: the six relative
    coordinates of marker ``i`` seen from marker ``j`` since the rest pose ``rest_r, rest_a``,
    ``x = [A_j^T (r_i - r_j) - rest_r, rotvec(A_j^T A_i rest_a^T)]`` [m, rad], their rates and
    their exact Jacobian (6, 12) over the markers' motions (the rotation through
    :func:`inverse_left_jacobian`)."""
    at = a[j].T.copy()
    arm = r[i] - r[j]
    phi = rotation_vector(mm(mm(at, a[i]), rest_a.T))
    jl = mm(inverse_left_jacobian(phi), at)
    sa = mm(at, skew(arm))
    jac = np.zeros((6, 12))
    for x in range(3):
        for y in range(3):
            jac[x, y] = at[x, y]
            jac[x, 6 + y] = -at[x, y]
            jac[x, 9 + y] = sa[x, y]
            jac[3 + x, 3 + y] = jl[x, y]
            jac[3 + x, 9 + y] = -jl[x, y]
    value = np.zeros(6)
    value[:3] = mv(at, arm) - rest_r
    value[3:] = phi
    rates = np.zeros(12)
    rates[0:3], rates[3:6], rates[6:9], rates[9:12] = v[i], w[i], v[j], w[j]
    return value, mv(jac, rates), jac


#: the kinds of compiled constraint (:func:`constraint_rows`)
SPHERICAL, TRANSVERSE, GEAR, SPEED, LOCK = 0, 1, 2, 3, 4


@njit(cache=True)
def constraint_rows(kind, r, a, v, w, i, j, h, par, inputs):  # pragma: no cover (compiled)
    """``(C, V, jac)`` of a compiled constraint on markers ``i, j, h`` (-1: absent) of the arrays
    ``r, a, v, w``, from its :class:`~ddgsa.mbs.elements.CompiledForm`: ``kind``, ``par`` and
    ``inputs`` (its series' value at ``t``, empty without one). The packed system's one dispatch on
    the constraint kinds: a new compiled constraint adds its kind and a branch here, and its
    ``compiled()``.
    """
    if kind == SPHERICAL:
        return spherical(r, a, v, w, i, j)
    if kind == TRANSVERSE:
        return transverse_bearing(r, a, v, w, i, j)
    if kind == GEAR:
        return gear_contact(r, a, v, w, i, j, h, par[0:3].copy(), par[3:6].copy())
    if kind == LOCK:                   # par: rest_r (3), rest_a (9), then the locked rows
        value, rates, jac = relative_coordinates(r, a, v, w, i, j, par[0:3].copy(), par[3:12].copy().reshape(3, 3))
        rows = par[12:].astype(np.int64)
        return value[rows], rates[rows], jac[rows]
    return prescribed_speed(r, a, v, w, i, j, inputs[0] if inputs.size else par[0])


class Constraint(ABC):
    """``n_eq`` scalar constraint equations on ``markers``."""

    name: str
    markers: tuple[Marker, ...]
    n_eq: int
    holonomic: bool
    #: what the multipliers are (one string per equation), for results tables
    reaction: tuple[str, ...] = ()

    def bind(self, states: list[MarkerState]) -> None:
        """Record what the constraint needs from the initial configuration (called by the system)."""

    def position(self, t: float, states: list[MarkerState]) -> tuple[Array, Array]:
        """``(C, dC/dx)`` of a holonomic constraint."""
        raise NotImplementedError(f"{type(self).__name__} is a velocity-level constraint")

    def velocity(self, t: float, states: list[MarkerState]) -> tuple[Array, Array]:
        """``(C_dot or B q_dot + b, jac_x)``: the velocity-level value and its Jacobian over marker rates."""
        _, jac = self.position(t, states)
        return jac @ _rates(states), jac

    def compiled(self) -> CompiledForm | None:
        """The constraint's compiled form (:func:`constraint_rows` runs it in the packed system), or
        None: Python only (the packed system refuses it)."""
        return None


class _PointPair(Constraint):
    """A holonomic constraint between two points whose residual, velocity-level value and Jacobian
    are one compiled kernel ``kernel(r, a, v, w, 0, 1) -> (C, V, jac)``."""

    holonomic = True
    kernel: Callable
    kind: int

    def compiled(self) -> CompiledForm:
        """No parameters."""
        return CompiledForm(self.kind, np.zeros(0))

    def position(self, t: float, states: list[MarkerState]) -> tuple[Array, Array]:
        value, _, jac = self.kernel(*stacked(states), 0, 1)
        return value, jac

    def velocity(self, t: float, states: list[MarkerState]) -> tuple[Array, Array]:
        return self.kernel(*stacked(states), 0, 1)[1:]


class Spherical(_PointPair):
    """Spherical joint: the two markers coincide, ``r_i - r_j = 0`` (seed 001 eq. 2.3).

    The multipliers are the force [N] the joint exerts on marker ``j`` (global frame); marker
    ``i`` gets the opposite.
    """

    n_eq = 3
    reaction = ("force_on_j_x", "force_on_j_y", "force_on_j_z")
    kernel = staticmethod(spherical)
    kind = SPHERICAL

    def __init__(self, marker_i: Marker, marker_j: Marker, name: str = "spherical") -> None:
        self.markers, self.name = (marker_i, marker_j), name


class TransverseBearing(_PointPair):
    """A bearing free along its axis: ``N_k^T (r_i - r_j) = 0``, k = 1, 2 (seed 001 §2.2).

    ``marker_i`` is on the shaft, ``marker_j`` on the (non-spinning) housing; the bearing axis is
    the x axis of marker j's frame and ``N_1, N_2`` its y and z axes. The multipliers are the
    radial forces on the housing along ``N_1, N_2`` [N].
    """

    n_eq = 2
    reaction = ("force_on_j_n1", "force_on_j_n2")
    kernel = staticmethod(transverse_bearing)
    kind = TRANSVERSE

    def __init__(self, marker_i: Marker, marker_j: Marker, name: str = "bearing") -> None:
        self.markers, self.name = (marker_i, marker_j), name


class GearContact(Constraint):
    """Gear mesh as the velocity constraint of seed 001 eq. 2.4.

    The material points of the two gears at the contact point ``A`` have equal velocity along
    the tangent ``t`` of the pitch circles: ``t . (v_i^A - v_j^A) = 0`` with
    ``v^A = v_centre + w x (r_A - r_centre)``. ``A`` and ``t`` are fixed in the housing's frame
    (taken from the initial configuration), so when the housing moves the mesh moves with it,
    and the reaction torque reaches the housing through the shafts' bearings.

    Parameters
    ----------
    gear_i, gear_j : Marker
        The gear centres on their shafts; the gear axes are the housing marker's x axis.
    radius_i, radius_j : float
        Pitch radii [m]; for an external pair the centre distance must be ``r_i + r_j``, for an
        internal pair (``gear_j`` the ring) ``r_j - r_i``.
    housing : Marker
        A marker of the housing (or of the ground) whose x axis is the gear axis.
    internal : bool

    Notes
    -----
    The multiplier is the tangential mesh force on gear ``j`` along ``t`` [N] (its negative
    acts on gear ``i``). Speeds follow ``w_j / w_i = -r_i / r_j`` (external) or ``+r_i / r_j``
    (internal).
    """

    n_eq = 1
    holonomic = False
    reaction = ("mesh_force_on_j",)

    def __init__(self, gear_i: Marker, gear_j: Marker, radius_i: float, radius_j: float, housing: Marker,
                 internal: bool = False, name: str = "gear") -> None:
        if radius_i <= 0 or radius_j <= 0 or (internal and radius_j <= radius_i):
            raise ModelError(f"gear contact {name!r}: pitch radii ({radius_i}, {radius_j}) m must be > 0"
                             + (" and the ring's larger" if internal else ""))
        self.markers = (gear_i, gear_j, housing)
        self.radius_i, self.radius_j, self.internal, self.name = radius_i, radius_j, internal, name
        self.contact = np.zeros(3)
        self.tangent = np.zeros(3)

    def bind(self, states: list[MarkerState]) -> None:
        si, sj, sh = states
        axis = sh.a[:, 0]
        d = sj.r - si.r
        d_plane = d - axis * (axis @ d)
        dist = float(np.linalg.norm(d_plane))
        want = self.radius_j - self.radius_i if self.internal else self.radius_i + self.radius_j
        if abs(dist - want) > 1e-6 * want:
            raise ModelError(f"gear contact {self.name!r}: centre distance {dist:.6g} m in the gear plane does not "
                             f"match the pitch radii ({want:.6g} m for an {'internal' if self.internal else 'external'}"
                             " pair)")
        e = d_plane / dist
        a_point = si.r + (-1.0 if self.internal else 1.0) * self.radius_i * e
        self.contact = sh.a.T @ (a_point - sh.r)
        self.tangent = sh.a.T @ cross(axis, e)

    def velocity(self, t: float, states: list[MarkerState]) -> tuple[Array, Array]:
        return gear_contact(*stacked(states), 0, 1, 2, self.contact, self.tangent)[1:]

    def compiled(self) -> CompiledForm:
        """``[contact (3), tangent (3)]`` in the housing marker's frame."""
        return CompiledForm(GEAR, np.concatenate([self.contact, self.tangent]))


class PrescribedSpeed(Constraint):
    """Spin rate of a marker about its x axis (relative to ``reference``) equals ``speed(t)`` [rad/s].

    The multiplier is the driving torque the motor applies to the marker, negated [N m].
    """

    n_eq = 1
    holonomic = False
    reaction = ("torque",)

    def __init__(self, marker: Marker, speed: "float | Callable[[float], float]", reference: Marker | None = None,
                 name: str = "speed") -> None:
        self.markers = (marker,) if reference is None else (marker, reference)
        self.speed = speed if callable(speed) else (lambda t, s=float(speed): s)
        #: the constant speed, or None when ``speed`` is a function (a ``Series`` runs compiled)
        self.constant = None if callable(speed) else float(speed)
        self.name = name

    def velocity(self, t: float, states: list[MarkerState]) -> tuple[Array, Array]:
        return prescribed_speed(*stacked(states), 0, 1 if len(states) > 1 else -1, float(self.speed(t)))[1:]

    def compiled(self) -> CompiledForm | None:
        """``[speed]`` of a constant speed, a :class:`Series` as the input; None for a Python function."""
        if self.constant is not None:
            return CompiledForm(SPEED, np.array([self.constant]))
        return CompiledForm(SPEED, np.zeros(1), self.speed) if isinstance(self.speed, Series) else None


AXES = ("x", "y", "z", "rx", "ry", "rz")
"""Relative coordinates a :class:`Lock` or :class:`PrescribedCoordinate` can hold: translations
along and rotations about the x, y, z axes of the reference marker's frame."""


class _RelativeCoordinates(Constraint):
    """Relative coordinates of marker ``i`` seen from marker ``j`` (default: the ground), from the rest pose.

    Translation ``d = A_j^T (r_i - r_j) - d_0`` and rotation ``phi = rotvec(A_j^T A_i (A_j0^T A_i0)^T)``
    (the rotation vector of the relative rotation since the rest pose, in marker j's axes); the
    rest pose is the markers' configuration when the system is built. The Jacobians are exact
    (``phi`` through the inverse left Jacobian of SO(3)), so Newton corrections converge
    quadratically at any angle below pi.
    """

    holonomic = True

    def __init__(self, marker_i: Marker, marker_j: Marker | None, axes: tuple[str, ...], name: str) -> None:
        bad = [a for a in axes if a not in AXES]
        if bad or not axes or len(set(axes)) != len(axes):
            raise ModelError(f"constraint {name!r}: axes {list(axes)} not allowed; choose distinct ones of "
                             f"{', '.join(AXES)}")
        self.markers = (marker_i, Ground().marker() if marker_j is None else marker_j)
        self.rows = np.array([AXES.index(a) for a in axes])
        self.axes, self.name, self.n_eq = tuple(axes), name, len(axes)
        self.rest_r: Array = np.zeros(3)
        self.rest_a: Array = np.eye(3)

    def bind(self, states: list[MarkerState]) -> None:
        si, sj = states
        self.rest_r = sj.a.T @ (si.r - sj.r)
        self.rest_a = sj.a.T @ si.a

    def relative(self, states: list[MarkerState]) -> tuple[Array, Array, Array]:
        """All six relative coordinates ``[d (3) [m], phi (3) [rad]]``, their rates and their Jacobian
        (6, 12) (:func:`relative_coordinates`)."""
        return relative_coordinates(*stacked(states), 0, 1, self.rest_r, self.rest_a)


class Lock(_RelativeCoordinates):
    """A joint that locks chosen relative translations and rotations of two markers.

    ``axes`` are taken from ``x, y, z`` (translations along marker j's axes) and ``rx, ry, rz``
    (rotations about them); the locked coordinates stay at their rest values (the markers'
    relative pose when the system is built). All six lock the markers rigidly together; ``("x",
    "y", "z", "ry", "rz")`` leaves a spin about x free (a rigid shaft on its bearings).

    Parameters
    ----------
    marker_i : Marker
    marker_j : Marker, optional
        The reference marker (default: a ground marker at the origin, global axes).
    axes : sequence of str
    name : str

    Notes
    -----
    The multipliers are the force [N] along, and the moment [N m] about (to first order in the
    relative rotation), each locked axis of marker j's frame that the joint exerts on marker
    ``j``; marker ``i`` gets the opposite.

    Examples
    --------
    >>> from ddgsa.mbs import RigidBody
    >>> lock = Lock(RigidBody("b", 1.0, (1.0, 1.0, 1.0)).marker(), axes=("x", "ry", "rz"))
    >>> lock.n_eq, lock.reaction
    (3, ('force_on_j_x', 'moment_on_j_ry', 'moment_on_j_rz'))
    """

    def __init__(self, marker_i: Marker, marker_j: Marker | None = None,
                 axes: tuple[str, ...] = AXES, name: str = "lock") -> None:
        super().__init__(marker_i, marker_j, tuple(axes), name)
        self.reaction = tuple(("force_on_j_" if a in "xyz" else "moment_on_j_") + a for a in self.axes)

    def position(self, t: float, states: list[MarkerState]) -> tuple[Array, Array]:
        value, _, jac = self.relative(states)
        return value[self.rows], jac[self.rows]

    def velocity(self, t: float, states: list[MarkerState]) -> tuple[Array, Array]:
        _, rates, jac = self.relative(states)
        return rates[self.rows], jac[self.rows]

    def compiled(self) -> CompiledForm:
        """``[rest_r (3), rest_a (9), locked rows]`` for :func:`relative_coordinates`."""
        return CompiledForm(LOCK, np.concatenate([self.rest_r, self.rest_a.ravel(), self.rows.astype(float)]))


class PrescribedCoordinate(_RelativeCoordinates):
    """One relative coordinate of a marker held at a value or a function of time (position level).

    ``C = coordinate - value(t) = 0``, ``C_t = -value'(t)``: the coordinate (``x, y, z`` [m] or
    ``rx, ry, rz`` [rad], see :class:`Lock`) of ``marker`` relative to ``reference`` (default the
    ground), measured from the rest pose, follows ``value``.

    Parameters
    ----------
    marker : Marker
    axis : str
        One of ``x, y, z, rx, ry, rz``.
    value : float or callable
        Constant [m or rad], or ``value(t)``; a callable needs ``rate(t)`` too (a
        :class:`~ddgsa.mbs.series.Series` is both: ``value(t)`` and ``value.derivative(t)``).
    rate : callable, optional
        ``d value / dt`` [m/s or rad/s].
    reference : Marker, optional
    name : str

    Notes
    -----
    The multiplier is the force [N] (moment [N m]) along the axis that the constraint exerts on
    the reference marker; the prescribed marker gets its opposite, so ``-lambda`` is the force
    that drives the marker along the prescribed motion.

    Examples
    --------
    >>> import math
    >>> from ddgsa.mbs import RigidBody
    >>> c = PrescribedCoordinate(RigidBody("b", 1.0, (1.0, 1.0, 1.0)).marker(), "y",
    ...                          math.sin, rate=math.cos)
    >>> c.reaction
    ('force_on_j_y',)
    """

    def __init__(self, marker: Marker, axis: str, value: "float | Callable[[float], float]",
                 rate: Callable[[float], float] | None = None, reference: Marker | None = None,
                 name: str = "prescribed") -> None:
        super().__init__(marker, reference, (axis,), name)
        if callable(value):
            rate = rate if rate is not None else getattr(value, "derivative", None)
            if rate is None:
                raise ModelError(f"constraint {name!r}: a prescribed value(t) needs its rate(t) "
                                 "(or pass a Series, which has both)")
            self.value, self.rate = value, rate
        else:
            self.value, self.rate = (lambda t, s=float(value): s), (lambda t: 0.0)
        self.reaction = (("force_on_j_" if axis in "xyz" else "moment_on_j_") + axis,)

    def position(self, t: float, states: list[MarkerState]) -> tuple[Array, Array]:
        value, _, jac = self.relative(states)
        return value[self.rows] - float(self.value(t)), jac[self.rows]

    def velocity(self, t: float, states: list[MarkerState]) -> tuple[Array, Array]:
        _, rates, jac = self.relative(states)
        return rates[self.rows] - float(self.rate(t)), jac[self.rows]
