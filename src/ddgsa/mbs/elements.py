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

import math
from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.bodies import Marker, MarkerState
from ddgsa.mbs.derivatives import central_step
from ddgsa.mbs.ffr import cross, mm, mv, rotation_vector, skew
from ddgsa.mbs.machines import N_CONSTANTS as N_MACHINE
from ddgsa.mbs.machines import air_gap_pull, dq_wrench, induction_slope, induction_torque
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

    def compiled(self) -> "CompiledForm | None":
        """The element's compiled form (:func:`element_wrench` runs it in the packed system), or None:
        the element runs in Python only (the packed system refuses it; :class:`ddgsa.mbs.compiled.HybridTerms`
        evaluates it in Python beside the compiled parts)."""
        return None


@dataclass(frozen=True)
class CompiledForm:
    """What the packed system (:func:`ddgsa.mbs.compiled.pack`) stores of an element or constraint.

    ``kind`` selects the compiled kernel (:func:`element_wrench`,
    :func:`ddgsa.mbs.constraints.constraint_rows`), ``parameters`` are its flat numbers, and
    ``series`` an input whose value at ``t`` the kernel reads (None: no input).
    """

    kind: int
    parameters: Array
    series: Series | None = None


#: the kinds of compiled element (:func:`element_wrench`)
CONNECTOR, TORQUE, LOAD, POWER_TORQUE, ECCENTRIC, MACHINE_TORQUE, AIR_GAP, DQ_MACHINE = 0, 1, 2, 3, 4, 5, 6, 7


def stacked(states: list[MarkerState]) -> tuple[Array, Array, Array, Array]:
    """Positions (n, 3), orientations (n, 3, 3), velocities (n, 3) and angular velocities (n, 3) of
    ``states``: the arrays the compiled element and constraint kernels read (the packed system
    passes its own arrays of every marker)."""
    return (np.array([s.r for s in states], dtype=float), np.array([s.a for s in states], dtype=float),
            np.array([s.v for s in states], dtype=float), np.array([s.w for s in states], dtype=float))


class _Connector(Element):
    """A linear 6-DOF connector ``F = K (d + offset) + C d_dot`` in the global frame or marker i's frame.

    ``offset`` (6,) [m, rad], global frame, zero unless a subclass sets it: a fixed pre-deflection
    (a coupling's misalignment, :class:`ddgsa.models.hss_rig.elements.MisalignedCoupling`).
    """

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
        self.offset: Array = np.zeros(6)

    def bind(self, states: list[MarkerState]) -> None:
        si, sj = states
        self.rest_r = si.a.T @ (sj.r - si.r) if self.frame == "i" else sj.r - si.r
        self.rest_a = si.a.T @ sj.a

    def _deflection(self, states: list[MarkerState]) -> tuple[Array, Array, Array]:
        """``(d + offset, d_dot, rest)``: the deflection and its rate (6,) [m, rad], [m/s, rad/s] and
        the points' rest offset (3,) [m], global frame (:func:`connector_deflection`)."""
        return connector_deflection(*stacked(states), 0, 1, self.frame == "i", self.free_spin, self.rest_r,
                                    self.rest_a, self.offset)

    def wrench(self, t: float, states: list[MarkerState]) -> tuple[Array, Array, Array]:
        d, dd, rest = self._deflection(states)
        r = np.array([states[0].r, states[1].r], dtype=float)
        ai = np.ascontiguousarray(states[0].a, dtype=float)
        return connector_force(r, ai, self.frame == "i", rest, d, dd, self.k6, self.c6, True)[:3]

    def compiled(self) -> CompiledForm | None:
        """``[frame_i, free_spin, rest_r (3), rest_a (9), offset (6), k6 (36), c6 (36)]`` for
        :func:`connector_wrench`; None for a subclass with a law of its own (its ``wrench`` or
        ``_deflection`` overridden: Python only)."""
        own = type(self)
        if own.wrench is not _Connector.wrench or own._deflection is not _Connector._deflection:
            return None
        flags = [float(self.frame == "i"), float(self.free_spin)]
        return CompiledForm(CONNECTOR, np.concatenate([flags, self.rest_r, self.rest_a.ravel(), self.offset,
                                                       self.k6.ravel(), self.c6.ravel()]))

    def potential_energy(self, states: list[MarkerState]) -> float:
        d = self._deflection(states)[0]
        k, _ = connector_matrices(np.ascontiguousarray(states[0].a, dtype=float), self.k6, self.c6, self.frame == "i")
        return float(0.5 * d @ k @ d)


@njit(cache=True)
def connector_deflection(r, a, v, w, i, j, frame_i, free_spin, rest_r, rest_a, offset):  # pragma: no cover
    """``(d, d_dot, rest)`` of a connector between markers ``i`` and ``j`` of the arrays ``r, a, v, w``.

    ``d = [r_j - r_i - rest, theta] + offset`` (6,) [m, rad] with ``rest`` (3,) [m] the rest offset
    of the points (turning with marker i when ``frame_i``), ``theta`` the rotation vector of the
    relative rotation since the rest pose ``rest_a`` or, with ``free_spin``, the tilt ``a_i x a_j``
    of the two x axes; ``d_dot`` its rate, without the spin about marker i's x axis when
    ``free_spin``; both in the global frame.

    Compiled, and the one implementation: the element (:class:`_Connector`) calls it from Python
    and the packed system (:mod:`ddgsa.mbs.compiled`) from its compiled assembly.
    """
    ai, aj = a[i], a[j]
    rest = mv(ai, rest_r) if frame_i else rest_r.copy()
    d = np.zeros(6)
    dd = np.zeros(6)
    wxr = cross(w[i], rest) if frame_i else np.zeros(3)
    for k in range(3):
        d[k] = r[j, k] - r[i, k] - rest[k]
        dd[k] = v[j, k] - v[i, k] - wxr[k]
    dw = w[j] - w[i]
    if free_spin:
        axis = ai[:, 0].copy()
        th = cross(axis, mm(aj, rest_a.T)[:, 0].copy())
        proj = axis[0] * dw[0] + axis[1] * dw[1] + axis[2] * dw[2]
        dw = dw - axis * proj
    else:
        th = rotation_vector(mm(mm(aj, rest_a.T), ai.T))
    for k in range(3):
        d[3 + k] = th[k]
        dd[3 + k] = dw[k]
    for k in range(6):
        d[k] += offset[k]
    return d, dd, rest


@njit(cache=True)
def connector_matrices(ai, k6, c6, frame_i):  # pragma: no cover (compiled)
    """Stiffness and damping (6, 6) in the global frame: ``k6, c6`` as given, or turned by marker i's
    orientation ``ai`` (``blockdiag(A_i, A_i) k6 blockdiag(A_i, A_i)^T``) when ``frame_i``."""
    if not frame_i:
        return k6.copy(), c6.copy()
    big = np.zeros((6, 6))
    big[:3, :3] = ai
    big[3:, 3:] = ai
    return mm(mm(big, k6), big.T), mm(mm(big, c6), big.T)


@njit(cache=True)
def connector_force(r, ai, frame_i, rest, d, dd, k6, c6, tangents):  # pragma: no cover (compiled)
    """``(W (2, 6), K (12, 12), C (12, 12), F (6,))`` of a connector ``F = K d + C d_dot`` between
    the points ``r[0]`` (marker i, orientation ``ai``) and ``r[1]`` (marker j) with the deflection
    ``d``, its rate ``dd`` and the points' rest offset ``rest`` (:func:`connector_deflection`):
    ``+F`` on marker i, ``-F`` and the couple ``(r_j - r_i) x F`` on marker j, and the tangents
    (:func:`connector_tangent`; (0, 0) without ``tangents``: they are 70 % of a connector's evaluation, which
    a residual alone, e.g. a step of a central difference, does not need).

    Compiled, and the one implementation: the element (:class:`_Connector`) calls it from Python
    and the packed system (:mod:`ddgsa.mbs.compiled`, through :func:`connector_wrench`) from its
    compiled assembly.
    """
    kg, cg = connector_matrices(ai, k6, c6, frame_i)
    fv = mv(kg, d) + mv(cg, dd)
    arm = r[1] - r[0]
    wr = np.zeros((2, 6))
    mom = cross(arm, fv[:3].copy())
    for k in range(3):
        wr[0, k] = fv[k]
        wr[0, 3 + k] = fv[3 + k]
        wr[1, k] = -fv[k]
        wr[1, 3 + k] = -fv[3 + k] + mom[k]
    if not tangents:
        return wr, np.zeros((0, 0)), np.zeros((0, 0)), fv
    turning = rest if frame_i else np.zeros(3)    # a global-frame rest offset does not turn with marker i
    return wr, connector_tangent(kg, turning, arm, fv[:3].copy()), connector_tangent(cg, turning, arm,
                                                                                     np.zeros(3)), fv


@njit(cache=True)
def connector_wrench(r, a, v, w, i, j, frame_i, free_spin, rest_r, rest_a, offset, k6, c6,
                     tangents):  # pragma: no cover (compiled)
    """:func:`connector_force` of :func:`connector_deflection` for markers ``i`` and ``j`` of the arrays
    ``r, a, v, w`` (the packed system's connector)."""
    d, dd, rest = connector_deflection(r, a, v, w, i, j, frame_i, free_spin, rest_r, rest_a, offset)
    pts = np.empty((2, 3))
    pts[0] = r[i]
    pts[1] = r[j]
    return connector_force(pts, a[i].copy(), frame_i, rest, d, dd, k6, c6, tangents)


@njit(cache=True)
def _pair(k: Array) -> Array:  # pragma: no cover (compiled)
    """Tangent of a two-marker connector over ``[x_i, x_j]``: ``[[K, -K], [-K, K]]``."""
    out = np.zeros((12, 12))
    out[:6, :6] = k
    out[:6, 6:] = -k
    out[6:, :6] = -k
    out[6:, 6:] = k
    return out


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
    #: ``(T_L, n, w_rated)`` of a power law (:meth:`power`), which the compiled path can run
    power_form: tuple[float, float, float] | None = None
    #: the constants of an induction machine's steady torque (:meth:`machine`), which the compiled path can run
    machine_form: Array | None = None

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
        law = cls(marker, lambda t, w: linear_torque(float(torque0), float(damping), float(ws(t)), w), reaction,
                  lambda t, w: -float(damping), name)
        law.linear_form = (float(torque0), float(damping), set_speed)
        return law

    @classmethod
    def power(cls, marker: Marker, torque: float, exponent: float, rated_speed: float,
              reaction: Marker | None = None, name: str = "torque") -> "TorqueLaw":
        """``T = -T_L (|w| / w_rated)^n sign(w)`` (a fan or pump load; ``n = 0``: ``-T_L tanh(w / 1 rad/s)``,
        a load smooth through rest) [N m, -, rad/s]: :func:`power_torque`; also runs on the compiled path."""
        form = (float(torque), float(exponent), float(rated_speed))
        law = cls(marker, lambda t, w: power_torque(form, float(w)), reaction, name=name)
        law.power_form = form
        return law

    @classmethod
    def machine(cls, marker: Marker, constants: ArrayLike, reaction: Marker | None = None,
                name: str = "motor") -> "TorqueLaw":
        """An induction machine's steady air-gap torque at the time and the spin speed
        (:func:`ddgsa.mbs.machines.induction_torque`; ``constants`` in the layout of
        :mod:`ddgsa.mbs.machines`); also runs on the compiled path."""
        form = np.asarray(constants, dtype=float).copy()
        if form.shape != (N_MACHINE,):
            raise ModelError(f"torque law {name!r}: a machine needs {N_MACHINE} constants, got shape {form.shape}")
        law = cls(marker, lambda t, w: induction_torque(form, float(t), float(w)), reaction, name=name)
        law.machine_form = form
        return law

    def compiled(self) -> CompiledForm | None:
        """``[torque0, damping, set_speed]`` of the :meth:`linear` form (the set speed a series input
        when it is a :class:`Series`), ``[T_L, n, w_rated]`` of the :meth:`power` form, the machine's
        constants of the :meth:`machine` form; None for a Python law."""
        if self.machine_form is not None:
            return CompiledForm(MACHINE_TORQUE, self.machine_form.copy())
        if self.power_form is not None:
            return CompiledForm(POWER_TORQUE, np.array(self.power_form))
        if self.linear_form is None:
            return None
        torque0, damping, ws = self.linear_form
        series = ws if isinstance(ws, Series) else None
        return CompiledForm(TORQUE, np.array([torque0, damping, 0.0 if series is not None else float(ws)]), series)

    def wrench(self, t: float, states: list[MarkerState]) -> tuple[Array, None, Array]:
        _, a, _, w = stacked(states)
        reaction = 1 if len(states) > 1 else -1
        speed = float(spin_speed(a, w, 0, reaction))
        torque = float(self.law(t, speed))
        if self.machine_form is not None:
            slope = float(induction_slope(self.machine_form, t, speed))
        elif self.power_form is not None:
            slope = float(power_slope(self.power_form, speed))
        elif self.slope is not None:
            slope = float(self.slope(t, speed))
        else:
            h = central_step(speed, 1.0, 1e-6)
            slope = (float(self.law(t, speed + h)) - float(self.law(t, speed - h))) / (2 * h)
        wr, c = axial_torque_wrench(a, 0, reaction, torque, slope)
        return wr, None, c


@njit(cache=True)
def spin_speed(a, w, i, j):  # pragma: no cover (compiled)
    """Spin rate [rad/s] of marker ``i`` about its x axis, relative to marker ``j`` (none when ``j < 0``),
    from the orientations ``a`` and angular velocities ``w`` of the markers.

    Compiled, and the one implementation: :class:`TorqueLaw` calls it from Python and the packed
    system (:mod:`ddgsa.mbs.compiled`) from its compiled assembly."""
    axis = a[i][:, 0].copy()
    wrel = w[i].copy()
    if j >= 0:
        wrel -= w[j]
    return axis[0] * wrel[0] + axis[1] * wrel[1] + axis[2] * wrel[2]


@njit(cache=True)
def power_torque(law, speed):  # pragma: no cover (compiled)
    """``T = -T_L (|w| / w_rated)^n sign(w)`` [N m] at ``speed`` [rad/s] for ``law = (T_L, n, w_rated)``
    (:meth:`TorqueLaw.power`); ``-T_L tanh(w / 1 rad/s)`` for ``n = 0``."""
    t_l, n, rated = law
    if n > 0:
        return -t_l * math.copysign(abs(speed / rated) ** n, speed)
    return -t_l * math.tanh(speed / 1.0)


@njit(cache=True)
def power_slope(law, speed):  # pragma: no cover (compiled)
    """``dT/dw`` [N m s/rad] of :func:`power_torque` by the central difference :meth:`TorqueLaw.wrench`
    takes of a law without a slope (step ``1e-6 max(1, |w|)``: the power law's own slope is infinite at
    rest for ``n < 1``)."""
    h = central_step(speed, 1.0, 1e-6)
    return (power_torque(law, speed + h) - power_torque(law, speed - h)) / (2 * h)


@njit(cache=True)
def eccentric_force(a, w, i, mass, radius):  # pragma: no cover (compiled)
    """``(1, 6)`` wrench of :class:`EccentricMass`: ``-m_u w x (w x r)`` [N] at marker ``i`` with
    ``r = radius`` times its frame's y axis, for the markers' orientations ``a`` and angular velocities ``w``."""
    r = a[i][:, 1] * radius
    wi = w[i]
    wr = wi[0] * r[0] + wi[1] * r[1] + wi[2] * r[2]
    ww = wi[0] * wi[0] + wi[1] * wi[1] + wi[2] * wi[2]
    out = np.zeros((1, 6))
    for k in range(3):
        out[0, k] = -mass * (wi[k] * wr - r[k] * ww)
    return out


@njit(cache=True)
def linear_torque(torque0, damping, set_speed, speed):  # pragma: no cover (compiled)
    """``T = torque0 + damping (set_speed - speed)`` [N m] (:meth:`TorqueLaw.linear`, seed 000 eq. 25)."""
    return torque0 + damping * (set_speed - speed)


@njit(cache=True)
def axial_torque_wrench(a, i, j, torque, slope):  # pragma: no cover (compiled)
    """``(W (n, 6), C (6 n, 6 n))`` of a torque [N m] about marker ``i``'s x axis, reversed on marker
    ``j`` (n = 2; n = 1 when ``j < 0``), with ``slope = dT/d speed`` [N m s/rad] giving the damping
    tangent ``C = -dW/dx_dot``.

    Compiled, and the one implementation: :class:`TorqueLaw` calls it from Python and the packed
    system (:mod:`ddgsa.mbs.compiled`) from its compiled assembly."""
    axis = a[i][:, 0].copy()
    n = 1 if j < 0 else 2
    wr = np.zeros((n, 6))
    c6 = np.zeros((6, 6))
    for r in range(3):
        wr[0, 3 + r] = torque * axis[r]
        for c in range(3):
            c6[3 + r, 3 + c] = -slope * axis[r] * axis[c]
    if n == 1:
        return wr, c6
    for r in range(3):
        wr[1, 3 + r] = -wr[0, 3 + r]
    return wr, _pair(c6)


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

    def compiled(self) -> CompiledForm:
        """No parameters: the force and moment are the series input."""
        return CompiledForm(LOAD, np.zeros(0), self.series)

    def wrench(self, t: float, states: list[MarkerState]) -> tuple[Array, None, None]:
        return self.series(t).reshape(1, 6), None, None


class EccentricMass(Element):
    """Centrifugal force of an eccentric point mass on a turning section: an unbalance.

    ``F = -m_u w x (w x r)`` [N] on the section's marker, ``r`` the mass's offset ``e`` along the
    marker frame's y axis (which points at the mass at ``t = 0``), ``w`` the section's angular
    velocity (:func:`eccentric_force`). The tangential term ``m_u e dw/dt`` (start-up, coast-down)
    is left out, and with it the force's tangents: ``dw/dt / w^2`` is below 1 % above 100 rpm for a
    rig's accelerations (docs/hss_rig.md).

    Parameters
    ----------
    marker : Marker
        The section (a disk centre).
    mass : float
        Eccentric mass ``m_u`` [kg].
    radius : float
        Its radius ``e`` [m].
    """

    def __init__(self, marker: Marker, mass: float, radius: float, name: str = "unbalance") -> None:
        self.markers = (marker,)
        self.mass, self.radius, self.name = float(mass), float(radius), name

    def compiled(self) -> CompiledForm:
        """``[m_u, e]``."""
        return CompiledForm(ECCENTRIC, np.array([self.mass, self.radius]))

    def wrench(self, t: float, states: list[MarkerState]) -> tuple[Array, None, None]:
        _, a, _, w = stacked(states)
        return eccentric_force(a, w, 0, self.mass, self.radius), None, None


@njit(cache=True)
def element_wrench(kind, r, a, v, w, i, j, par, inputs, t, tangents):  # pragma: no cover (compiled)
    """``(W (n_m, 6), K, C)`` of a compiled element between markers ``i`` and ``j`` (``j < 0``: one
    marker) of the arrays ``r, a, v, w``, from its :class:`CompiledForm`: ``kind``, ``par`` (its
    parameters), ``inputs`` (its series' value at ``t``, empty without one) and the time ``t`` [s] (a
    machine's supply). ``K`` or ``C``
    are (0, 0) where the element has none; without ``tangents`` they may be (0, 0) (the connectors skip
    theirs). The packed system's one dispatch on the element kinds:
    a new compiled element adds its kind and a branch here, and :meth:`Element.compiled`.
    """
    none = np.zeros((0, 0))
    if kind == CONNECTOR:
        wr, kr, cr, _ = connector_wrench(r, a, v, w, i, j, par[0] == 1.0, par[1] == 1.0, par[2:5].copy(),
                                         par[5:14].copy().reshape(3, 3), par[14:20].copy(),
                                         par[20:56].copy().reshape(6, 6), par[56:92].copy().reshape(6, 6), tangents)
        return wr, kr, cr
    if kind == TORQUE:
        ws = inputs[0] if inputs.size else par[2]
        torque = linear_torque(par[0], par[1], ws, spin_speed(a, w, i, j))
        wr, cr = axial_torque_wrench(a, i, j, torque, -par[1])
        return wr, none, cr
    if kind == POWER_TORQUE:
        law = (par[0], par[1], par[2])
        speed = spin_speed(a, w, i, j)
        wr, cr = axial_torque_wrench(a, i, j, power_torque(law, speed), power_slope(law, speed))
        return wr, none, cr
    if kind == ECCENTRIC:
        return eccentric_force(a, w, i, par[0], par[1]), none, none
    if kind == MACHINE_TORQUE:
        speed = spin_speed(a, w, i, j)
        wr, cr = axial_torque_wrench(a, i, j, induction_torque(par, t, speed), induction_slope(par, t, speed))
        return wr, none, cr
    if kind == AIR_GAP:
        e = radial_displacement(r, a, i, j, par[0:2].copy())
        force, slope = air_gap_pull(par[2:], e[0], e[1])
        wr, kr = radial_wrench(r, a, i, j, force, slope)
        return wr, kr, none
    if kind == DQ_MACHINE:
        wr, cr = dq_wrench(par, t, a, w, v, i, j)
        return wr, none, cr
    return inputs.copy().reshape(1, 6), none, none


@njit(cache=True)
def radial_displacement(r, a, i, j, rest):  # pragma: no cover (compiled)
    """``e = P A_j^T (r_i - r_j) - rest`` (2,) [m]: marker i's displacement in marker j's y, z axes."""
    e = np.zeros(2)
    for k in range(2):
        e[k] = (a[j][0, k + 1] * (r[i][0] - r[j][0]) + a[j][1, k + 1] * (r[i][1] - r[j][1])
                + a[j][2, k + 1] * (r[i][2] - r[j][2])) - rest[k]
    return e


@njit(cache=True)
def radial_wrench(r, a, i, j, force, slope):  # pragma: no cover (compiled)
    """``(W (2, 6), K (12, 12))`` of :class:`RadialForce`: ``F = A_j P^T force`` on marker ``i``, ``-F`` and the
    pair's couple ``(r_j - r_i) x F`` on marker ``j``, and the tangent ``-A_j P^T slope P A_j^T`` of the
    translations (exact for coincident markers whose frame j does not turn)."""
    axes = a[j][:, 1:3].copy()
    f = np.zeros(3)
    k = np.zeros((6, 6))
    for m in range(3):
        f[m] = axes[m, 0] * force[0] + axes[m, 1] * force[1]
    for m in range(3):
        for n in range(3):
            acc = 0.0
            for p in range(2):
                for q in range(2):
                    acc += axes[m, p] * slope[p, q] * axes[n, q]
            k[m, n] = -acc
    w = np.zeros((2, 6))
    w[0, :3] = f
    w[1, :3] = -f
    w[1, 3:] = cross(r[j] - r[i], f)
    return w, _pair(k)


@dataclass(frozen=True)
class AirGapPull:
    """The magnetic pull of a surface-PM air gap (:func:`ddgsa.mbs.machines.air_gap_pull`, compiled) as
    the law of a :class:`RadialForce`, which then packs (its constants are the element's parameters).

    Parameters
    ----------
    constants : (7,) ``[g, h_m / mu_r, k_C, B_r, alpha_p, R L beta, N]`` (see the function;
        :attr:`ddgsa.models.electromagnetic.PMGenerator.constants` builds them)
    """

    constants: Array

    def __call__(self, e: Array) -> tuple[Array, Array]:
        """``(F (2,) [N], dF/de (2, 2) [N/m])`` at the eccentricity ``e`` (2,) [m]."""
        return air_gap_pull(self.constants, float(e[0]), float(e[1]))


class RadialForce(Element):
    """A force in the plane normal to marker j's x axis, a given law of the radial displacement.

    The displacement ``e = P A_j^T (r_i - r_j) - e_0`` (``P`` picks marker j's y and z axes,
    ``e_0`` its rest value) sets ``F = law(e)`` (2,) [N] on marker ``i`` along those axes and
    ``-F`` on marker ``j``; with ``dF/de`` (2, 2) [N/m] from the law, the tangent is exact for
    coincident markers whose frame j does not turn (a rotor centre in a stator). The geometry is
    compiled (:func:`radial_displacement`, :func:`radial_wrench`); an :class:`AirGapPull` law (the
    magnetic pull of an air gap) is compiled too and the element packs, any other law runs in Python.

    Parameters
    ----------
    marker_i, marker_j : Marker
    law : callable
        ``law(e) -> (F (2,), dF/de (2, 2))`` with ``e`` (2,) [m], e.g. :class:`AirGapPull`.
    name : str

    Examples
    --------
    >>> from ddgsa.mbs import Ground, RigidBody
    >>> pull = RadialForce(RigidBody("rotor", 1.0, (1.0, 1.0, 1.0)).marker(), Ground().marker(),
    ...                    lambda e: (-1e6 * e, -1e6 * np.eye(2)))
    >>> pull.markers[1].body.name, pull.compiled() is None
    ('ground', True)
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
        r, a, _, _ = stacked(states)
        return radial_displacement(r, a, 0, 1, self.rest)

    def compiled(self) -> CompiledForm | None:
        """``[rest (2), air gap constants (7)]`` for an :class:`AirGapPull` law; None (Python only) for another law."""
        if not isinstance(self.law, AirGapPull):
            return None
        return CompiledForm(AIR_GAP, np.concatenate([self.rest, self.law.constants]))

    def wrench(self, t: float, states: list[MarkerState]) -> tuple[Array, Array, None]:
        r, a, _, _ = stacked(states)
        force, slope = (np.asarray(x, dtype=float) for x in self.law(radial_displacement(r, a, 0, 1, self.rest)))
        w, k = radial_wrench(r, a, 0, 1, force.reshape(2), slope.reshape(2, 2))
        return w, k, None
