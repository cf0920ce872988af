"""A system of bodies, force elements and constraints: the equations of seed 001 eq. 2.5.

``M(q) q_ddot + C_q^T lambda = Q(q, q_dot, t)``, with holonomic constraints ``C(q, t) = 0`` and
velocity-level ones ``B(q) q_dot + b(t) = 0``. :class:`System` numbers the bodies' coordinates,
evaluates every marker once per call, and assembles mass matrix, forces, tangents and
constraint Jacobians for the integrators (:mod:`ddgsa.mbs.integrate`) and the modal analysis
(:mod:`ddgsa.mbs.modal`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.bodies import Body, Marker, MarkerState
from ddgsa.mbs.constraints import Constraint
from ddgsa.mbs.elements import Element
from ddgsa.mbs.scatter import add_wrench, constraint_rows_over

Array = NDArray[np.float64]


@dataclass
class Terms:
    """The assembled equations at one state.

    Attributes
    ----------
    m : (n, n) mass matrix; ``q`` : (n,) generalised forces (inertia, gravity, elastic, elements);
    k, c : (n, n) tangent stiffness ``-dQ/dq`` and damping ``-dQ/dq_dot`` (element and elastic
    parts; gyroscopic and geometric terms are left to the Newton iterations);
    outputs : one (6,) wrench per element (:meth:`~ddgsa.mbs.elements.Element.output`).
    """

    m: Array
    q: Array
    k: Array
    c: Array
    outputs: list[Array]


class System:
    """Bodies, force elements and constraints assembled into one set of equations.

    Parameters
    ----------
    bodies : sequence of Body
        Bodies that own coordinates (ground and prescribed bodies need not be listed).
    elements : sequence of Element
    constraints : sequence of Constraint
    gravity : (3,)
        Gravity acceleration, global frame [m/s^2].

    Attributes
    ----------
    coord_names : tuple of str
        ``"<body>.<coordinate>"`` for every coordinate, in system order.
    q0, qd0 : ndarray
        Initial state from the bodies' poses (see :meth:`consistent_state`).
    """

    def __init__(self, bodies: Sequence[Body], elements: Sequence[Element] = (),
                 constraints: Sequence[Constraint] = (), gravity: ArrayLike = (0.0, 0.0, 0.0)) -> None:
        names = [b.name for b in bodies]
        if len(set(names)) != len(names):
            raise ModelError(f"body names must be unique; got {names}")
        self.bodies = list(bodies)
        self.elements = list(elements)
        self.constraints = list(constraints)
        self.gravity = np.asarray(gravity, dtype=float).reshape(3)
        self.slices: dict[int, slice] = {}
        start = 0
        for b in self.bodies:
            self.slices[id(b)] = slice(start, start + b.n_coords)
            start += b.n_coords
        self.n = start
        self.coord_names = tuple(f"{b.name}.{c}" for b in self.bodies for c in b.coord_names)
        for part in [*self.elements, *self.constraints]:
            for mk in part.markers:
                if mk.body.n_coords and id(mk.body) not in self.slices:
                    raise ModelError(f"{type(part).__name__} {part.name!r} uses body {mk.body.name!r}, which is not "
                                     f"in the system's bodies {names}")
        self.markers: list[Marker] = list({id(mk): mk for p in [*self.elements, *self.constraints]
                                           for mk in p.markers}.values())
        self._index = {id(mk): i for i, mk in enumerate(self.markers)}
        by_body: dict[int, list[int]] = {}
        for i, mk in enumerate(self.markers):
            by_body.setdefault(id(mk.body), []).append(i)
        self._groups = [(self.markers[idx[0]].body, idx) for idx in by_body.values()]
        self.holonomic = [c for c in self.constraints if c.holonomic]
        self.nonholonomic = [c for c in self.constraints if not c.holonomic]
        self.n_holonomic = sum(c.n_eq for c in self.holonomic)
        self.n_constraints = sum(c.n_eq for c in self.constraints)
        q0 = [b.initial_state()[0] for b in self.bodies]
        qd0 = [b.initial_state()[1] for b in self.bodies]
        self.fast_terms: Any = None
        """:meth:`terms` evaluated another way (:func:`ddgsa.mbs.compiled.compile_terms`), or None."""
        self.q0 = np.concatenate(q0) if q0 else np.zeros(0)
        self.qd0 = np.concatenate(qd0) if qd0 else np.zeros(0)
        states = self.marker_states(self.q0, self.qd0, 0.0)
        for part in [*self.elements, *self.constraints]:
            part.bind(self._states_of(part, states))

    # -- kinematics -------------------------------------------------------------------------------
    def marker_states(self, q: Array, qd: Array, t: float) -> list[MarkerState]:
        """States of all markers used by elements and constraints, with Jacobians over all coordinates."""
        out: list[MarkerState] = [None] * len(self.markers)  # type: ignore[list-item]
        for body, idx in self._groups:
            sl = self.slices.get(id(body), slice(0, 0))
            for i, (r, a, v, w, jb) in zip(idx, body.marker_states([self.markers[i] for i in idx], q[sl], qd[sl], t)):
                jac = np.zeros((6, self.n))
                jac[:, sl] = jb
                out[i] = MarkerState(r, a, v, w, jac)
        return out

    def marker_state(self, mk: Marker, q: Array, qd: Array, t: float) -> MarkerState:
        """State of any marker (also one no element uses)."""
        sl = self.slices.get(id(mk.body), slice(0, 0))
        r, a, v, w, jb = mk.body.marker_state(mk, q[sl], qd[sl], t)
        jac = np.zeros((6, self.n))
        jac[:, sl] = jb
        return MarkerState(r, a, v, w, jac)

    def states_of(self, markers: Sequence[Marker], q: Array, qd: Array, t: float) -> list[MarkerState]:
        """States of ``markers`` at ``(q, qd, t)`` (compiled where :func:`ddgsa.mbs.compiled.compile_terms`
        packed the system and every marker is one of its parts')."""
        if self.fast_terms is not None and all(id(mk) in self._index for mk in markers):
            return self.fast_terms.states(list(markers), q, qd, t)
        return [self.marker_state(mk, q, qd, t) for mk in markers]

    def positions(self, mk: Marker, q: Array, qd: Array, times: Array) -> Array:
        """Global position (n_t, 3) [m] of marker ``mk`` along a record ``q, qd`` (n_t, n) at ``times``
        (compiled where :func:`ddgsa.mbs.compiled.compile_terms` packed the system and the marker is one
        of its parts')."""
        if self.fast_terms is not None and id(mk) in self._index:
            return self.fast_terms.positions(mk, q, qd, times)
        return np.array([self.marker_state(mk, qi, qdi, ti).r for ti, qi, qdi in zip(times, q, qd)])

    def _states_of(self, part: Element | Constraint, states: list[MarkerState]) -> list[MarkerState]:
        return [states[self._index[id(mk)]] for mk in part.markers]

    # -- equations --------------------------------------------------------------------------------
    def terms(self, q: Array, qd: Array, t: float, states: list[MarkerState] | None = None) -> Terms:
        """Mass matrix, forces and tangents at ``(q, qd, t)``."""
        if states is None and self.fast_terms is not None:
            return self.fast_terms(q, qd, t)
        n = self.n
        m, f, kt, ct = np.zeros((n, n)), np.zeros(n), np.zeros((n, n)), np.zeros((n, n))
        for b in self.bodies:
            sl = self.slices[id(b)]
            mb, fb, kb, cb = b.terms(q[sl], qd[sl], self.gravity)
            m[sl, sl], f[sl], kt[sl, sl], ct[sl, sl] = mb, fb, kb, cb
        states = self.marker_states(q, qd, t) if states is None else states
        outputs = []
        for el in self.elements:
            st = self._states_of(el, states)
            w, k_el, c_el = el.wrench(t, st)
            add_wrench(f, kt, ct, st, w, k_el, c_el)
            outputs.append(w[0])
        return Terms(m, f, kt, ct, outputs)

    def holonomic_residual(self, q: Array, qd: Array, t: float,
                           states: list[MarkerState] | None = None) -> tuple[Array, Array]:
        """``(C (n_h,), C_q (n_h, n))`` of the holonomic constraints."""
        states = self.marker_states(q, qd, t) if states is None else states
        vals, jacs = [np.zeros(0)], [np.zeros((0, self.n))]
        for c in self.holonomic:
            st = self._states_of(c, states)
            v, jx = c.position(t, st)
            vals.append(v)
            jacs.append(constraint_rows_over(jx, st))
        return np.concatenate(vals), np.vstack(jacs)

    def velocity_residual(self, q: Array, qd: Array, t: float,
                          states: list[MarkerState] | None = None) -> tuple[Array, Array]:
        """Velocity-level values and Jacobians of all constraints (holonomic first), ``(n_c,), (n_c, n)``."""
        states = self.marker_states(q, qd, t) if states is None else states
        vals, jacs = [np.zeros(0)], [np.zeros((0, self.n))]
        for c in [*self.holonomic, *self.nonholonomic]:
            st = self._states_of(c, states)
            v, jx = c.velocity(t, st)
            vals.append(v)
            jacs.append(constraint_rows_over(jx, st))
        return np.concatenate(vals), np.vstack(jacs)

    def constraint_jacobian(self, q: Array, qd: Array, t: float) -> Array:
        """Jacobian of all constraints over the coordinates (holonomic rows first) (n_c, n)."""
        return self.velocity_residual(q, qd, t)[1]

    def energy(self, q: Array, qd: Array, t: float = 0.0) -> float:
        """Kinetic + gravity + elastic + element potential energy [J]."""
        m = self.terms(q, qd, t).m
        e = 0.5 * qd @ m @ qd
        for b in self.bodies:
            e += b.potential_energy(q[self.slices[id(b)]], self.gravity)
        states = self.marker_states(q, qd, t)
        for el in self.elements:
            e += el.potential_energy(self._states_of(el, states))
        return float(e)

    def consistent_state(self, q: Array | None = None, qd: Array | None = None, t: float = 0.0,
                         keep: Sequence[int] = (), tol: float = 1e-12, max_iter: int = 50,
                         residuals: Callable[[Array, Array, float], tuple[Array, Array, Array, Array]] | None = None
                         ) -> tuple[Array, Array]:
        """Nearest state that satisfies the constraints (least-squares corrections).

        Positions are corrected by Gauss-Newton on ``C(q) = 0`` with minimum-norm steps; velocities
        are projected on ``B q_dot + b = 0`` with the coordinates in ``keep`` (e.g. a driving spin
        rate) held at their given values. ``residuals(q, qd, t) -> (C, C_q, V, B)`` evaluates the
        constraints another way (the compiled kernel's, :func:`ddgsa.mbs.compiled.constraint_values`;
        the same values to round-off); default :meth:`holonomic_residual` and :meth:`velocity_residual`.
        """
        q = (self.q0 if q is None else np.asarray(q, dtype=float)).copy()
        qd = (self.qd0 if qd is None else np.asarray(qd, dtype=float)).copy()
        for _ in range(max_iter):
            c, cq = self.holonomic_residual(q, qd, t) if residuals is None else residuals(q, qd, t)[:2]
            if c.size == 0 or np.max(np.abs(c)) < tol:
                break
            q -= np.linalg.lstsq(cq, c, rcond=None)[0]
        else:
            raise ModelError(f"the constraints cannot be satisfied near the initial pose (residual "
                             f"{np.max(np.abs(c)):.3g})")
        v, b = self.velocity_residual(q, qd, t) if residuals is None else residuals(q, qd, t)[2:]
        if v.size:
            free = np.setdiff1d(np.arange(self.n), np.asarray(keep, dtype=int))
            dq = np.zeros(self.n)
            dq[free] = np.linalg.lstsq(b[:, free], -v, rcond=None)[0]
            qd = qd + dq
        return q, qd

    @property
    def multiplier_names(self) -> tuple[str, ...]:
        """``"<constraint>.<reaction>"`` for every multiplier, holonomic constraints first."""
        return tuple(f"{c.name}.{r}" for c in [*self.holonomic, *self.nonholonomic] for r in c.reaction)

    @property
    def element_names(self) -> tuple[str, ...]:
        """Names of the elements, in output order."""
        return tuple(el.name for el in self.elements)

    def index(self, name: str) -> int:
        """Position of coordinate ``"<body>.<coordinate>"``."""
        try:
            return self.coord_names.index(name)
        except ValueError:
            raise ModelError(f"unknown coordinate {name!r}; known: {', '.join(self.coord_names)}") from None

    def groups(self) -> dict[str, str]:
        """Coordinate name -> mode label (body and direction)."""
        out: dict[str, str] = {}
        for b in self.bodies:
            out.update(b.groups())
        return out


def accelerations(system: System, q: Array, qd: Array, t: float, stabilisation: float = 0.0,
                  fd_step: float = 1e-6) -> tuple[Array, Array]:
    """Accelerations and multipliers of the index-1 form of eq. 2.6 (with Baumgarte terms).

    Solves ``[[M, C_q^T], [C_q, 0]] [q_ddot; lambda] = [Q; -g - 2 w V - w^2 C]`` where ``V`` are
    the velocity-level constraint values, ``C`` the holonomic ones (velocity-level constraints
    get ``-w V`` only) and ``g = d/dt(V) at q_ddot = 0`` is taken by a central difference along
    ``(q_dot, 1)`` in ``(q, t)`` with step ``fd_step`` [s]. ``stabilisation`` is the Baumgarte
    rate ``w`` [rad/s] (0: the plain index-1 form).
    """
    states = system.marker_states(q, qd, t)
    tm = system.terms(q, qd, t, states)
    nc = system.n_constraints
    if nc == 0:
        return np.linalg.solve(tm.m, tm.q), np.zeros(0)
    v, b = system.velocity_residual(q, qd, t, states)
    h = fd_step
    g = (system.velocity_residual(q + h * qd, qd, t + h)[0] - system.velocity_residual(q - h * qd, qd, t - h)[0]) / (2 * h)
    rhs_c = -g
    if stabilisation > 0:
        nh = system.n_holonomic
        rhs_c[:nh] -= 2 * stabilisation * v[:nh] + stabilisation ** 2 * system.holonomic_residual(q, qd, t, states)[0]
        rhs_c[nh:] -= stabilisation * v[nh:]
    n = system.n
    big = np.zeros((n + nc, n + nc))
    big[:n, :n] = tm.m
    big[:n, n:] = b.T
    big[n:, :n] = b
    sol = np.linalg.solve(big, np.concatenate([tm.q, rhs_c]))
    return sol[:n], sol[n:]


def python_kind(system: System) -> Callable[..., None]:
    """The System run on its own objects as a kind of :mod:`ddgsa.mbs.alpha`'s loops
    (``evaluate(q, qd, t, step, ctx, m, f, kt, ct, y, ch, jac, vel)``: generalised-alpha's and the
    statics'): the equations, the elements' wrenches as outputs, the constraints' residuals and Jacobian."""
    nh, nc = system.n_holonomic, system.n_constraints

    def evaluate(q: Array, qd: Array, t: float, step: int, ctx: None, m: Array, f: Array, kt: Array, ct: Array,
                 y: Array, ch: Array, jac: Array, vel: Array) -> None:
        states = system.marker_states(q, qd, t)
        tm = system.terms(q, qd, t, states)
        m[:], f[:], kt[:], ct[:] = tm.m, tm.q, tm.k, tm.c
        if tm.outputs:
            y[:] = np.ravel(tm.outputs)
        if nh:
            ch[:] = system.holonomic_residual(q, qd, t, states)[0]
        if nc:
            vel[:], jac[:] = system.velocity_residual(q, qd, t, states)

    return evaluate
