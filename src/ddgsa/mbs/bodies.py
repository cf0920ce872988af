"""Bodies of the multibody kernel: each owns its coordinates and tells where its points are.

- :class:`RigidBody` -- six coordinates ``[R (3), angles (3)]``, origin at the centre of mass.
- :class:`FlexibleBody` -- a floating-frame-of-reference shaft ``[R, angles, q_f]`` whose elastic
  coordinates scale the FE eigenmodes of :mod:`ddgsa.mbs.beam` (seed 000 §2.5), with the inertia
  invariants of :mod:`ddgsa.mbs.ffr` (computed once) and rigid end inertias from its
  :class:`~ddgsa.mbs.beam.BeamSpec`.
- :class:`Ground` and :class:`PrescribedBody` -- no coordinates; a prescribed body moves along a
  given trajectory (a bedplate, a tower top).

Angles are the Bryant angles of :func:`ddgsa.mbs.ffr.rotation`, ``A = R_Z(psi) R_Y(theta) R_X(phi)``:
the spin ``phi`` about the body x axis acts first, so the x axis is the spin axis of a shaft.

A :class:`Marker` is a point of a body with a section frame. Its state (:class:`MarkerState`) holds
global position, section orientation, velocity, angular velocity and the 6 x n Jacobian
``[v; w] = J q_dot`` of the body's coordinates. Elements and constraints see bodies only through
marker states, so a new element never needs to know what kind of body it is attached to.
"""

from __future__ import annotations

import functools
import math
from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.beam import BeamSpec, ShaftModes, shaft_modes
from ddgsa.mbs.ffr import Invariants, body_terms_inv, cross, g_bar, inertia_points, rodrigues, rotation, skew
from ddgsa.mbs.series import Series

Array = NDArray[np.float64]

MAX_BENDING_MODES = 12
"""Most bending modes per plane a shaft may retain."""
FIELDS = ("axial", "torsion", *(f"bending_{p}_{k}" for k in range(1, MAX_BENDING_MODES + 1) for p in "yz"))


def bending_fields(n: int, order: str = "interleaved") -> tuple[str, ...]:
    """Names of ``n`` bending modes per plane: ``interleaved`` (y_1, z_1, y_2, ...) or ``by_plane`` (y_1, y_2, ..., z_1, ...)."""
    if order == "interleaved":
        return tuple(f"bending_{p}_{k}" for k in range(1, n + 1) for p in "yz")
    return tuple(f"bending_{p}_{k}" for p in "yz" for k in range(1, n + 1))


def mode_number(field_name: str) -> int:
    """The mode number ``k`` of a field ``bending_y_k`` / ``bending_z_k``."""
    return int(field_name.rsplit("_", 1)[1])


@dataclass(frozen=True, eq=False)
class Marker:
    """A point of a body with a section frame (created by ``body.marker``).

    Attributes
    ----------
    body : Body
    position : ndarray (3,)
        Undeformed position in the body frame [m].
    name : str
    shapes, rotation_shapes : ndarray (3, n_f)
        Elastic displacement [m] and section rotation [rad] per unit elastic coordinate
        (empty for rigid bodies).
    """

    body: "Body"
    position: Array
    name: str
    shapes: Array
    rotation_shapes: Array

    def __repr__(self) -> str:
        return f"Marker({self.body.name}.{self.name})"


@dataclass
class MarkerState:
    """Where a marker is and how it moves, in the global frame.

    Attributes
    ----------
    r : (3,) position [m]; ``a`` : (3, 3) section orientation (section -> global);
    v : (3,) velocity [m/s]; ``w`` : (3,) angular velocity [rad/s];
    jac : (6, n) ``[v; w] = jac @ q_dot`` over the system coordinates (zeros for prescribed bodies).
    """

    r: Array
    a: Array
    v: Array
    w: Array
    jac: Array


class Body(ABC):
    """A body: its coordinates, inertia and internal forces, and the kinematics of its markers."""

    name: str
    coord_names: tuple[str, ...] = ()

    @property
    def n_coords(self) -> int:
        """Number of coordinates the body owns."""
        return len(self.coord_names)

    @abstractmethod
    def marker(self, position: ArrayLike = (0.0, 0.0, 0.0), name: str | None = None) -> Marker:
        """A point of the body at ``position`` [m] in the body frame."""

    @abstractmethod
    def marker_state(self, mk: Marker, q: Array, qd: Array, t: float) -> tuple[Array, Array, Array, Array, Array]:
        """``(r, A_section, v, w, J (6, n_coords))`` of a marker at the body's ``q``, ``qd``."""

    def marker_states(self, markers: list[Marker], q: Array, qd: Array,
                      t: float) -> list[tuple[Array, Array, Array, Array, Array]]:
        """:meth:`marker_state` of several markers of this body (bodies may share work between them)."""
        return [self.marker_state(mk, q, qd, t) for mk in markers]

    def initial_state(self) -> tuple[Array, Array]:
        """Initial coordinates and velocities."""
        return np.zeros(self.n_coords), np.zeros(self.n_coords)

    def terms(self, q: Array, qd: Array, gravity: Array) -> tuple[Array, Array, Array, Array]:
        """``(M, Q, K_t, C_t)``: mass matrix, inertia + gravity + internal forces and their tangents."""
        n = self.n_coords
        return np.zeros((n, n)), np.zeros(n), np.zeros((n, n)), np.zeros((n, n))

    def potential_energy(self, q: Array, gravity: Array) -> float:
        """Gravity and elastic potential energy [J]."""
        return 0.0

    def groups(self) -> dict[str, str]:
        """Coordinate name -> mode label (component and direction)."""
        return {}


class PrescribedBody(Body):
    """A body moving along a given trajectory; it owns no coordinates.

    Parameters
    ----------
    name : str
    trajectory : callable
        ``trajectory(t) -> (R, A, v, w)``: origin position [m], orientation (body -> global),
        origin velocity [m/s] and angular velocity [rad/s], global frame.
    """

    #: the sampled translation of :meth:`translating` (a :class:`~ddgsa.mbs.series.Series`), else None
    series = None
    #: fixed pose ``(R, A)`` of a body that does not move (the ground), else None
    fixed_pose: tuple[Array, Array] | None = None

    def __init__(self, name: str, trajectory: Callable[[float], tuple[Array, Array, Array, Array]]) -> None:
        self.name = name
        self.trajectory = trajectory

    @classmethod
    def translating(cls, name: str, times: ArrayLike, displacement: ArrayLike) -> "PrescribedBody":
        """A body translating by sampled ``displacement`` (n_t, 3) [m] at ``times`` [s].

        Between samples the motion is the C1 cubic (Catmull-Rom) the integrators use for every
        input; velocity is its derivative.
        """
        series = Series(times, displacement)
        eye = np.eye(3)
        body = cls(name, lambda t: (series(t), eye, series.derivative(t), np.zeros(3)))
        body.series = series
        return body

    def marker(self, position: ArrayLike = (0.0, 0.0, 0.0), name: str | None = None) -> Marker:
        p = np.asarray(position, dtype=float).reshape(3)
        return Marker(self, p, name or f"p{p.tolist()}", np.zeros((3, 0)), np.zeros((3, 0)))

    def marker_state(self, mk: Marker, q: Array, qd: Array, t: float) -> tuple[Array, Array, Array, Array, Array]:
        return self.marker_states([mk], q, qd, t)[0]

    def marker_states(self, markers: list[Marker], q: Array, qd: Array,
                      t: float) -> list[tuple[Array, Array, Array, Array, Array]]:
        r0, a, v0, w = (np.asarray(x, dtype=float) for x in self.trajectory(t))
        out = []
        for mk in markers:
            arm = a @ mk.position
            out.append((r0 + arm, a, v0 + cross(w, arm), w, np.zeros((6, 0))))
        return out


class Ground(PrescribedBody):
    """The fixed global frame."""

    def __init__(self, name: str = "ground") -> None:
        eye, zero = np.eye(3), np.zeros(3)
        super().__init__(name, lambda t: (zero, eye, zero, zero))
        self.fixed_pose = (zero, eye)


@dataclass
class _Pose:
    position: Array = field(default_factory=lambda: np.zeros(3))
    angles: Array = field(default_factory=lambda: np.zeros(3))
    velocity: Array = field(default_factory=lambda: np.zeros(3))
    angle_rates: Array = field(default_factory=lambda: np.zeros(3))


class FlexibleBody(Body):
    """Floating-frame-of-reference body of mass points (see :mod:`ddgsa.mbs.ffr`).

    Use :meth:`shaft` for an FE shaft, :class:`RigidBody` for a rigid one; the constructor takes
    the lumped points directly.

    Parameters
    ----------
    name : str
    point_masses : (n_p,) [kg]; ``point_positions`` : (n_p, 3) [m]; ``point_shapes`` : (n_p, 3, n_f)
    stiffness, damping : (n_f, n_f)
        Elastic stiffness and damping of the elastic coordinates.
    field_names : sequence of str
        Names of the elastic coordinates (e.g. ``bending_y_1``).
    position, angles, velocity, angle_rates : (3,)
        Initial pose [m, rad] and its rates [m/s, rad/s].
    node_x, node_shapes, node_rotation_shapes : optional
        Stations along the body x axis [m] where markers may sit, with translation and
        section-rotation shapes there (n_nodes, 3, n_f).
    """

    def __init__(self, name: str, point_masses: ArrayLike, point_positions: ArrayLike, point_shapes: ArrayLike,
                 stiffness: ArrayLike | None = None, damping: ArrayLike | None = None,
                 field_names: Sequence[str] = (), *, position: ArrayLike = (0.0, 0.0, 0.0),
                 angles: ArrayLike = (0.0, 0.0, 0.0), velocity: ArrayLike = (0.0, 0.0, 0.0),
                 angle_rates: ArrayLike = (0.0, 0.0, 0.0), node_x: ArrayLike | None = None,
                 node_shapes: ArrayLike | None = None, node_rotation_shapes: ArrayLike | None = None,
                 invariants: Invariants | None = None) -> None:
        self.name = name
        pm = np.asarray(point_masses, dtype=float)
        pu = np.asarray(point_positions, dtype=float).reshape(-1, 3)
        ps = np.asarray(point_shapes, dtype=float).reshape(pu.shape[0], 3, -1)
        nf = ps.shape[2]
        if len(field_names) != nf:
            raise ModelError(f"body {name!r}: {len(field_names)} field names for {nf} elastic coordinates")
        self.fields = tuple(field_names)
        #: the lumped mass points ``(masses, positions, shapes)`` the body was built from
        self.points = (pm, pu, ps)
        self.invariants = invariants if invariants is not None else Invariants(pm, pu, ps)
        self._inv_args = self.invariants.args()
        self.mass = self.invariants.mass
        self.kff = np.zeros((nf, nf)) if stiffness is None else np.asarray(stiffness, dtype=float)
        self.cff = np.zeros((nf, nf)) if damping is None else np.asarray(damping, dtype=float)
        self.pose = _Pose(*(np.asarray(v, dtype=float).reshape(3) for v in (position, angles, velocity, angle_rates)))
        self.coord_names = ("x", "y", "z", "rx", "ry", "rz", *self.fields)
        self.node_x = None if node_x is None else np.asarray(node_x, dtype=float)
        self.node_shapes = None if node_shapes is None else np.asarray(node_shapes, dtype=float)
        self.node_rotation_shapes = None if node_rotation_shapes is None else np.asarray(node_rotation_shapes, float)

    @property
    def n_elastic(self) -> int:
        """Number of elastic coordinates."""
        return len(self.fields)

    @classmethod
    def shaft(cls, name: str, spec: BeamSpec, fields: Sequence[str] = ("torsion", "bending_y_1", "bending_z_1"),
              damping_ratio: float = 0.0, rotary_inertia: bool = True, **pose: ArrayLike) -> "FlexibleBody":
        """An FE shaft along the body x axis (x = 0 .. L) with its end inertias (seed 000 §2.5).

        Parameters
        ----------
        spec : BeamSpec
            Mesh, stiffness, shaft mass and end inertias; ``spec.supports`` and
            ``spec.axial_support`` are the boundary conditions the mode shapes are computed on.
        fields : sequence of str
            Retained elastic coordinates, from ``axial``, ``torsion``, ``bending_y_k``, ``bending_z_k``
            (k = 1 .. :data:`MAX_BENDING_MODES`; y and z share the shapes of the axisymmetric shaft).
        damping_ratio : float
            Modal damping of axial and torsion coordinates; Rayleigh damping through the first
            two bending frequencies for the bending ones (seed 000 eq. 43-44) [-].
        rotary_inertia : bool
            Give each shaft station its slice's polar and diametral inertia (else the shaft mass
            is lumped on the axis, as the direct drive of seed 000 does).
        **pose
            ``position``, ``angles``, ``velocity``, ``angle_rates`` of the body frame.
        """
        bad = [f for f in fields if f not in FIELDS]
        if bad:
            raise ModelError(f"body {name!r}: unknown elastic field(s) {bad}; allowed: {', '.join(FIELDS)}")
        parts = _shaft_parts(spec, tuple(fields), float(damping_ratio), bool(rotary_inertia))
        body = cls(name, parts.pm, parts.pu, parts.ps, parts.k, parts.c, fields, node_x=parts.x,
                   node_shapes=parts.s_tr, node_rotation_shapes=parts.s_rot, invariants=parts.invariants, **pose)
        body.modes = parts.modes
        body.rotating_points = list(parts.rotating)
        return body

    def spin_stiffness(self, w: Array) -> Array:
        """Stiffness (n_f, n_f) of the centrifugal load on the second-order motion of the rigid inertias'
        off-axis points, for body angular velocity ``w`` (3,) [rad/s, body frame] [N/m, N m/rad].

        The FFR kinematics move a point at offset ``d`` from its section by the section rotation
        ``r = R q_f`` to first order only, ``r x d``; to second order it also moves by
        ``1/2 r x (r x d)`` (a rigid rotation keeps its distance), on which the centrifugal force
        ``F = m (|w|^2 u - (w . u) w)`` works: ``1/2 r^T (1/2 (F d^T + d F^T) - (F . d) I) r``. Its
        stiffness ``-R^T (1/2 (F d^T + d F^T) - (F . d) I) R`` completes a disk's gyroscopic
        stiffening: a section tilting about a transverse axis gets ``(J_p / 2) w^2`` (the first-order
        terms give ``(J_p / 2 - J_d) w^2``, the rigid disk's ``(J_p - J_d) w^2`` in all), and the twist
        loses the first-order terms' spurious ``-J_p w^2``. Zero for bodies without rigid inertias.
        """
        nf = self.n_elastic
        out = np.zeros((nf, nf))
        ww = float(w @ w)
        for masses, positions, offsets, rot in getattr(self, "rotating_points", []):
            for m, u, d in zip(masses, positions, offsets):
                if not d.any():
                    continue
                f = m * (ww * u - float(w @ u) * w)
                a = 0.5 * (np.outer(f, d) + np.outer(d, f)) - float(f @ d) * np.eye(3)
                out -= rot.T @ a @ rot
        return out

    def marker(self, position: ArrayLike = (0.0, 0.0, 0.0), name: str | None = None) -> Marker:
        p = np.asarray(position, dtype=float).reshape(3)
        nf = self.n_elastic
        if nf == 0:
            s, sr = np.zeros((3, 0)), np.zeros((3, 0))
        else:
            if self.node_x is None:
                raise ModelError(f"body {self.name!r} has no stations for markers")
            i = int(np.argmin(np.abs(self.node_x - p[0])))
            if abs(self.node_x[i] - p[0]) > 1e-9 * max(1.0, abs(self.node_x[-1])):
                raise ModelError(f"marker at x = {p[0]} m of body {self.name!r} is not a shaft node; nodes: "
                                 f"{np.round(self.node_x, 4).tolist()}")
            off = p - np.array([self.node_x[i], 0.0, 0.0])
            sr = self.node_rotation_shapes[i]
            s = self.node_shapes[i] - skew(off) @ sr
        return Marker(self, p, name or f"p{p.tolist()}", s, sr)

    def initial_state(self) -> tuple[Array, Array]:
        nf = self.n_elastic
        q = np.concatenate([self.pose.position, self.pose.angles, np.zeros(nf)])
        qd = np.concatenate([self.pose.velocity, self.pose.angle_rates, np.zeros(nf)])
        return q, qd

    def marker_state(self, mk: Marker, q: Array, qd: Array, t: float) -> tuple[Array, Array, Array, Array, Array]:
        return self.marker_states([mk], q, qd, t)[0]

    def marker_states(self, markers: list[Marker], q: Array, qd: Array,
                      t: float) -> list[tuple[Array, Array, Array, Array, Array]]:
        a = rotation(q[3:6])
        ag = a @ g_bar(q[3:6])
        qf = q[6:]
        out = []
        for mk in markers:
            u = a @ (mk.position + mk.shapes @ qf) if qf.size else a @ mk.position
            jac = np.zeros((6, self.n_coords))
            jac[0, 0] = jac[1, 1] = jac[2, 2] = 1.0
            jac[0:3, 3:6] = -skew(u) @ ag   # -A u~ G with u in global axes
            jac[3:6, 3:6] = ag
            if qf.size:
                jac[0:3, 6:] = a @ mk.shapes
                jac[3:6, 6:] = a @ mk.rotation_shapes
                a_sec = a @ rodrigues(mk.rotation_shapes @ qf)
            else:
                a_sec = a
            vw = jac @ qd
            out.append((q[0:3] + u, a_sec, vw[:3], vw[3:], jac))
        return out

    def terms(self, q: Array, qd: Array, gravity: Array) -> tuple[Array, Array, Array, Array]:
        m, f = body_terms_inv(np.ascontiguousarray(q), np.ascontiguousarray(qd), *self._inv_args, gravity)  # one layout:
        # numba compiles the body kernel once per layout of its arguments (a strided view is another)
        n = self.n_coords
        kt, ct = np.zeros((n, n)), np.zeros((n, n))
        if self.n_elastic:
            f[6:] -= self.kff @ q[6:] + self.cff @ qd[6:]
            kt[6:, 6:] = self.kff
            ct[6:, 6:] = self.cff
        return m, f, kt, ct

    def potential_energy(self, q: Array, gravity: Array) -> float:
        inv = self.invariants
        c = inv.first0 + inv.s_sum @ q[6:]
        centre = q[0:3] + rotation(q[3:6]) @ c / inv.mass
        return float(-inv.mass * gravity @ centre + 0.5 * q[6:] @ self.kff @ q[6:])

    def groups(self) -> dict[str, str]:
        lab = {"x": "axial", "y": "lateral_y", "z": "lateral_z", "rx": "spin", "ry": "tilt_y", "rz": "tilt_z"}
        out = {f"{self.name}.{c}": f"{self.name}_{lab[c]}" for c in lab}
        for f in self.fields:
            out[f"{self.name}.{f}"] = f"{self.name}_{f}"
        return out


class RigidBody(FlexibleBody):
    """A rigid body: coordinates ``[R, angles]`` of its centre of mass and orientation.

    Parameters
    ----------
    name : str
    mass : float [kg]
    inertia : (3,) or (3, 3)
        Principal moments ``(J_x, J_y, J_z)`` or the inertia tensor about the centre of mass,
        body frame [kg m^2]; ``x`` is the spin axis of a rotor.
    **pose
        ``position``, ``angles``, ``velocity``, ``angle_rates`` (see :class:`FlexibleBody`).

    Examples
    --------
    >>> disc = RigidBody("disc", mass=10.0, inertia=(0.2, 0.1, 0.1), angle_rates=(50.0, 0.0, 0.0))
    >>> disc.coord_names
    ('x', 'y', 'z', 'rx', 'ry', 'rz')
    """

    def __init__(self, name: str, mass: float, inertia: ArrayLike, **pose: ArrayLike) -> None:
        j = np.asarray(inertia, dtype=float)
        j = np.diag(j) if j.shape == (3,) else j.reshape(3, 3)
        if mass <= 0 or not np.allclose(j, j.T) or np.linalg.eigvalsh(j).min() <= 0:
            raise ModelError(f"body {name!r}: mass {mass} kg and inertia {j.tolist()} kg m^2 are not physical "
                             "(mass > 0, symmetric positive-definite inertia)")
        inv = Invariants.__new__(Invariants)
        inv.mass = float(mass)
        inv.first0 = np.zeros(3)
        inv.s_sum = np.zeros((3, 0))
        inv.k0 = 0.5 * np.trace(j) * np.eye(3) - j            # sum m u u^T of the inertia tensor
        inv.k1 = np.zeros((3, 3, 0))
        inv.e = np.zeros((3, 3, 0))
        inv.f = np.zeros((3, 3, 0, 0))
        inv.h0 = np.zeros((3, 0))
        inv.h1 = np.zeros((0, 3, 0))
        super().__init__(name, [mass], np.zeros((1, 3)), np.zeros((1, 3, 0)), invariants=inv, **pose)
        self.inertia = j



@dataclass(frozen=True)
class _ShaftParts:
    """What :meth:`FlexibleBody.shaft` computes from its spec (read-only arrays, shared by the bodies of one spec)."""

    pm: Array
    pu: Array
    ps: Array
    k: Array
    c: Array
    x: Array
    s_tr: Array
    s_rot: Array
    modes: ShaftModes
    rotating: tuple
    invariants: Invariants


@functools.lru_cache(maxsize=8)
def _shaft_parts(spec: BeamSpec, fields: tuple[str, ...], damping_ratio: float, rotary_inertia: bool) -> _ShaftParts:
    """Mode shapes, lumped points, elastic matrices and inertia invariants of an FE shaft (see
    :meth:`FlexibleBody.shaft`), kept for the few latest specs: a model builds the same shaft
    several times for one parameter point (at rest for its sag, spinning for its run), and the
    eigen-solves and invariants are most of a build."""
    n_bend = max([mode_number(f) for f in fields if f.startswith("bending")] + [1])
    modes = shaft_modes(spec, n_axial=1, n_torsion=1, n_bending=max(n_bend, 2))
    s_tr, s_rot = _field_shapes(modes, fields)
    x = spec.x
    trib = np.zeros(x.size)
    le = np.diff(x)
    trib[:-1] += le / 2
    trib[1:] += le / 2
    node_mass = spec.mass / spec.length * trib
    pm, pu, ps = [], [], []
    rotating: list = []
    if rotary_inertia:
        jx_node = spec.polar_inertia / spec.length * trib
        _add_station_inertias(pm, pu, ps, node_mass, jx_node, 0.5 * jx_node + node_mass * trib ** 2 / 12.0, x,
                              s_tr, s_rot, rotating)
    else:
        pm.append(node_mass)
        pu.append(np.column_stack([x, np.zeros_like(x), np.zeros_like(x)]))
        ps.append(s_tr)
    for xe, mass, jx, jd in spec.end_masses:
        i = spec.node_index(xe)
        _add_inertia(pm, pu, ps, mass, jx, jd, x[i], s_tr[i], s_rot[i], rotating)
    pm_a, pu_a, ps_a = np.concatenate(pm), np.vstack(pu), np.concatenate(ps, axis=0)
    m_ff = np.einsum("j,jai,jak->ik", pm_a, ps_a, ps_a)
    k, c = elastic_matrices(fields, modes, m_ff, damping_ratio)
    invariants = Invariants(pm_a, pu_a, ps_a)
    arrays = [pm_a, pu_a, ps_a, k, c, x, s_tr, s_rot]
    for arr in arrays:
        arr.flags.writeable = False
    return _ShaftParts(*arrays, modes, tuple(rotating), invariants)


def _field_shapes(modes: ShaftModes, fields: Sequence[str]) -> tuple[Array, Array]:
    """Translation and section-rotation shapes (n_nodes, 3, n_f) of the retained fields."""
    nf, nn = len(fields), modes.x.size
    s_tr, s_rot = np.zeros((nn, 3, nf)), np.zeros((nn, 3, nf))
    for c, fld in enumerate(fields):
        if fld == "axial":
            s_tr[:, 0, c] = modes.axial[0]
        elif fld == "torsion":
            s_rot[:, 0, c] = modes.torsion[0]
        else:
            k = mode_number(fld) - 1
            if fld.startswith("bending_y"):
                s_tr[:, 1, c], s_rot[:, 2, c] = modes.bending[k], modes.bending_slope[k]
            else:
                s_tr[:, 2, c], s_rot[:, 1, c] = modes.bending[k], -modes.bending_slope[k]
    return s_tr, s_rot


def _add_inertia(pm: list, pu: list, ps: list, mass: float, jx: float, jd: float, x: float,
                 s_tr: Array, s_rot: Array, rotating: list) -> None:
    """Append the seven points of a rigid axisymmetric inertia at station ``x`` (moving with the section),
    and ``(masses, positions, offsets, s_rot)`` to ``rotating`` (for :meth:`FlexibleBody.spin_stiffness`)."""
    if mass <= 0:
        return
    masses, offsets = inertia_points(mass, jx, jd)
    pm.append(masses)
    pu.append(np.array([x, 0.0, 0.0]) + offsets)
    ps.append(np.stack([s_tr - skew(d) @ s_rot for d in offsets]))
    rotating.append((masses, np.array([x, 0.0, 0.0]) + offsets, offsets, s_rot))


def _add_station_inertias(pm: list, pu: list, ps: list, mass: Array, jx: Array, jd: Array, x: Array,
                          s_tr: Array, s_rot: Array, rotating: list) -> None:
    """:func:`_add_inertia` at every station ``i`` at once (the same seven points of
    :func:`~ddgsa.mbs.ffr.inertia_points` in the same order; one pass over arrays instead of a Python loop,
    which was half the set-up of a Timoshenko shaft). ``mass``, ``jx``, ``jd``, ``x`` (n,) [kg, kg m^2, m];
    ``s_tr``, ``s_rot`` (n, 3, n_f) the stations' shapes; every mass positive and ``jd >= jx / 2``."""
    second = np.maximum(np.column_stack([jd - 0.5 * jx, 0.5 * jx, 0.5 * jx]), 0.0)     # sum m x^2, y^2, z^2
    arm = 1.2 * np.sqrt(np.maximum(second.sum(axis=1), 1e-30) / mass)
    half = 0.5 * second / arm[:, None] ** 2                                             # each point of a pair
    masses = np.column_stack([mass - 2.0 * half.sum(axis=1), np.repeat(half, 2, axis=1)])   # (n, 7)
    offsets = np.zeros((x.size, 7, 3))
    for k in range(3):
        offsets[:, 1 + 2 * k, k], offsets[:, 2 + 2 * k, k] = arm, -arm
    rot = np.swapaxes(s_rot, 1, 2)[:, None, :, :]                                       # (n, 1, n_f, 3)
    shapes = s_tr[:, None] - np.swapaxes(np.cross(offsets[:, :, None, :], rot), 2, 3)   # s_tr - d x s_rot
    positions = offsets.copy()
    positions[:, :, 0] += x[:, None]
    pm.append(masses.reshape(-1))
    pu.append(positions.reshape(-1, 3))
    ps.append(shapes.reshape(-1, 3, s_tr.shape[2]))
    rotating.extend(zip(masses, positions, offsets, s_rot))


def elastic_matrices(fields: Sequence[str], modes: ShaftModes, m_ff: Array, zeta: float) -> tuple[Array, Array]:
    """Elastic stiffness (FE generalised stiffness) and damping (seed 000 eq. 43-44) of the fields.

    Axial and torsion coordinates get modal damping ``2 zeta sqrt(k m)``; bending coordinates
    Rayleigh damping ``a0 M + a1 K`` through the first two bending frequencies.
    """
    nf = len(fields)
    k = np.zeros((nf, nf))
    for c, fld in enumerate(fields):
        k[c, c] = (modes.k_axial[0] if fld == "axial" else modes.k_torsion[0] if fld == "torsion"
                   else modes.k_bending[mode_number(fld) - 1])
    c_mat = np.zeros((nf, nf))
    w1, w2 = 2 * np.pi * modes.freq_bending[0], 2 * np.pi * modes.freq_bending[1]
    a0, a1 = 2 * zeta * w1 * w2 / (w1 + w2), 2 * zeta / (w1 + w2)
    for c, fld in enumerate(fields):
        if fld in ("axial", "torsion"):
            c_mat[c, c] = 2 * zeta * math.sqrt(k[c, c] * m_ff[c, c])
    bend = [c for c, f in enumerate(fields) if f.startswith("bending")]
    if bend:
        ix = np.ix_(bend, bend)
        c_mat[ix] = a0 * m_ff[ix] + a1 * k[ix]
    return k, c_mat
