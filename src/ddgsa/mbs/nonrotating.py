"""Linearisation of a spinning, unconstrained system in non-rotating bending coordinates, and its exact run.

An FFR shaft's elastic coordinates turn with it. The kernel's constrained linearisation
(:func:`ddgsa.mbs.modal.linearise_system`) holds them at one spin angle, which is exact for the
shaft alone but freezes the inertia coupling between its turning bending coordinates and its
non-turning rigid translation: on flexible supports the forced response is off by a few per cent
near a critical speed, and a static sag becomes a false once-per-revolution whirl. Here each
pair of bending coordinates with equal shapes (``bending_y_k``, ``bending_z_k``) is written in
non-rotating coordinates ``xi``: ``q_pair = R(-phi) xi`` with the body's spin angle ``phi`` (the
same transformation :mod:`ddgsa.mbs.linear` uses for the direct drive), so an axisymmetric shaft
on non-rotating supports gives time-invariant equations
``M z'' + C z' + K z = T(t)^T dQ(t) + r0`` (gyroscopic and Coriolis terms in ``C``, centrifugal in
``K``), built by central differences of the system's nonlinear residual through the map
``q(z, t)``, projected with ``T = dq/dz`` taken at the perturbed state: the operating point (a
static sag at speed) is not an equilibrium, and the Galerkin term ``(dT/dz)^T r`` of its residual
``r`` belongs in the spin rows (frozen at the operating point, it put a false once-per-revolution
torque into the test rig's steady runs: 1.2e-4 N m, now 7.7e-6, the nonlinear rig's 2.6-3.6e-6). Inputs (the listed
time-varying elements) are projected with ``T(t)`` at every sample; the run is exact for their C1
cubic interpolant (:func:`ddgsa.mbs.linear.lti_response`), from the periodic steady state of one
revolution (the cyclic spin angles excluded: nothing depends on them, they drift with any
residual torque). Systems with constraints are refused.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import LinAlgWarning, expm, lu_factor, lu_solve, null_space

from ddgsa.errors import ModelError
from ddgsa.mbs.assembly import System
from ddgsa.mbs.bodies import FlexibleBody, MarkerState, mode_number
from ddgsa.mbs.campbell import orbit_average, orbit_pairs
from ddgsa.mbs.compiled import HybridTerms, _markers, _residuals, body_rate_slopes, stepped_residuals
from ddgsa.mbs.elements import EccentricMass, Element
from ddgsa.mbs.ffr import g_bar
from ddgsa.mbs.linear import lti_response
from ddgsa.mbs.derivatives import central_difference, central_jacobian

Array = NDArray[np.float64]
RIGID_RCOND = 1e-12
"""Relative singular value below which a direction of the stiffness matrix counts as rigid."""


@dataclass(frozen=True)
class SpinLinearisation:
    """``M z'' + C z' + K z = T(t)^T dQ + r0`` about a steadily spinning state (see the module).

    Attributes
    ----------
    m, c, k : (n, n); ``r0`` : (n,)
    q0, qd0 : the operating state at ``t0`` (coordinates and rates)
    pairs : list of ``(i_y, i_z, i_spin)`` system indices of each bending pair and its body's spin
    xi0 : (n_pairs, 2) the pairs' operating values in non-rotating coordinates
    """

    m: Array
    c: Array
    k: Array
    r0: Array
    q0: Array
    qd0: Array
    t0: float
    pairs: list[tuple[int, int, int]]
    xi0: Array

    def _rot(self, phi: float) -> Array:
        c, s = np.cos(phi), np.sin(phi)
        return np.array([[c, s], [-s, c]])                 # R(-phi)

    def state(self, z: Array, zd: Array, zdd: Array, t: float) -> tuple[Array, Array, Array]:
        """``(q, qd, qdd)`` of the system for non-rotating perturbations ``z`` at time ``t``."""
        dt = t - self.t0
        q = self.q0 + self.qd0 * dt + z
        qd = self.qd0 + zd
        qdd = zdd.copy()
        jm = np.array([[0.0, -1.0], [1.0, 0.0]])
        for k, (iy, iz, isp) in enumerate(self.pairs):
            phi, w, wd = q[isp], qd[isp], qdd[isp]
            r = self._rot(phi)
            xi = self.xi0[k] + z[[iy, iz]]
            xid, xidd = zd[[iy, iz]], zdd[[iy, iz]]
            # d/dt R(-phi) = -w J R(-phi)
            q[[iy, iz]] = r @ xi
            qd[[iy, iz]] = r @ xid - w * jm @ r @ xi
            qdd[[iy, iz]] = r @ xidd - 2 * w * jm @ r @ xid - wd * jm @ r @ xi + w * w * jm @ jm @ r @ xi
        return q, qd, qdd

    def projection(self, t: float, z: Array | None = None) -> Array:
        """``T = dq/dz`` (n, n) at time ``t`` [s] and perturbation ``z`` (default: on the operating trajectory);
        dimensionless but for the bending rows' spin column [m/rad, or the bending coordinates' unit per rad]."""
        tmat = np.eye(self.q0.size)
        for k, (iy, iz, isp) in enumerate(self.pairs):
            phi = self.q0[isp] + self.qd0[isp] * (t - self.t0)
            xi = self.xi0[k]
            if z is not None:
                phi, xi = phi + z[isp], xi + z[[iy, iz]]
            r = self._rot(phi)
            tmat[np.ix_([iy, iz], [iy, iz])] = r
            tmat[[iy, iz], isp] = -np.array([[0.0, -1.0], [1.0, 0.0]]) @ r @ xi
        return tmat


def generalised_force(n: int, t: float, elements: Sequence[Element], states: Sequence[MarkerState]) -> Array:
    """Generalised force (n,) of the listed elements alone at time ``t`` [s] from the ``states`` of their
    markers, in the elements' order (one evaluation of the markers for all elements)."""
    f = np.zeros(n)
    start = 0
    for el in elements:
        own = states[start:start + len(el.markers)]
        start += len(el.markers)
        w = el.wrench(t, own)[0]
        for s, wi in zip(own, w):
            f += s.jac.T @ wi
    return f


def bending_pairs(system: System) -> list[tuple[int, int, int]]:
    """``(i_y, i_z, i_spin)`` for every (bending_y_k, bending_z_k) pair of the system's flexible bodies."""
    out = []
    for b in system.bodies:
        if isinstance(b, FlexibleBody) and b.n_elastic:
            for k in sorted(mode_number(f) for f in b.fields if f.startswith("bending_y_")):
                fy, fz = f"bending_y_{k}", f"bending_z_{k}"
                if fz in b.fields:
                    out.append((system.index(f"{b.name}.{fy}"), system.index(f"{b.name}.{fz}"),
                                system.index(f"{b.name}.rx")))
    return out


def _residual(system: System, lin: SpinLinearisation, z: Array, zd: Array, zdd: Array) -> Array:
    q, qd, qdd = lin.state(z, zd, zdd, lin.t0)
    tm = system.terms(q, qd, lin.t0)
    return lin.projection(lin.t0, z).T @ (tm.m @ qdd - tm.q)


def spin_stiffness(system: System, q0: Array, qd0: Array) -> Array:
    """The flexible bodies' :meth:`~ddgsa.mbs.bodies.FlexibleBody.spin_stiffness` at ``(q0, qd0)`` on the
    system's coordinates (n, n): nonzero on elastic coordinates only. It is invariant under a body's spin
    (an axisymmetric body's y/z pairs share shapes), so it holds in the non-rotating coordinates too."""
    out = np.zeros((system.n, system.n))
    for b in system.bodies:
        if isinstance(b, FlexibleBody) and b.n_elastic:
            first = system.index(f"{b.name}.x")
            ang = q0[first + 3:first + 6]
            w = g_bar(np.asarray(ang, dtype=float)) @ qd0[first + 3:first + 6]
            idx = [system.index(f"{b.name}.{f}") for f in b.fields]
            out[np.ix_(idx, idx)] += b.spin_stiffness(w)
    return out


#: scale of the central-difference steps over the coordinates [m, rad] (step ``rel_step * max(scale, |x|)``)
POSITION_SCALE = 1e-3
#: the same over the rates [m/s, rad/s]: 1, not the coordinates' 1e-3. The residual's rate terms are
#: quadratic (gyroscopic) or smooth (torque laws), so a central difference has no truncation error to
#: speak of at a 1e-6 step, while a 1e-9 step left round-off of 3e-5 relative on the rig's motor-torque
#: ripple (a 4-ulp nudge of the parameters moved it by 5.6e-5; now 8.6e-7; tests/mbs)
VELOCITY_SCALE = 1.0


def linearise(system: System, q0: Array, qd0: Array, t0: float = 0.0, rel_step: float = 1e-6,
              spin_stiffening: bool = False, static: bool = False, compiled: bool = True,
              residual_only: bool = False, tangent_columns: Sequence[int] = (),
              damping_tangents: bool = False) -> SpinLinearisation:
    """Linearise ``system`` about ``(q0, qd0)`` (steady spin) in non-rotating bending coordinates.

    ``spin_stiffening`` adds :func:`spin_stiffness`, the centrifugal stiffness of the rigid inertias'
    second-order motion that the FFR bodies' first-order kinematics leave out (a disk's tilt then
    gets the rigid disk's ``(J_p - J_d) w^2``; tested against the closed-form whirl of a disk). The
    nonlinear bodies do not carry it (their time-domain runs and the linear fidelities built on
    this linearisation are without it unless asked): see docs/physics.md for its size.

    ``K`` and ``C`` are central differences of the projected residual; ``M = T^T M(q0) T`` is exact
    (the residual is linear in the accelerations, and ``d q'' / d z'' = T``). ``static=True`` leaves
    ``C`` at zero (a caller that needs the static part ``K z = r0`` only: half the residual calls).
    A system whose terms are compiled (:func:`ddgsa.mbs.compiled.compile_terms`) takes the
    differences of its packed part straight from the compiled kernel, all steps' states at once, and
    calls its Python elements only where a step moves their markers (:func:`_hybrid_jacobian`: the
    same differences to round-off, 3-4x faster); any other system, or ``compiled=False``, takes them
    through ``system.terms``. ``residual_only=True`` leaves ``K`` and ``C`` at zero too: the map and
    ``r0`` only, one evaluation of the terms (a chord iteration with a tangent it already has).

    ``tangent_columns`` (system indices) take their columns of ``K`` and ``C`` from the terms' own
    tangents instead (``T^T K_t T``, ``T^T C_t T``: the elements' stiffness and damping mapped through
    their markers' Jacobians and the flexible bodies' structural matrices), without a residual call:
    exact only for coordinates on which neither a body's inertia or gravity terms nor the elements'
    Jacobians depend (a body's translations: the caller's claim, to be checked against the central
    differences, as ``tests/models/test_hss_rig_block.py`` does for the test rig, whose steady block path
    takes 21 of its 42 columns this way: :func:`ddgsa.models.hss_rig.rig.tangent_columns`).
    ``damping_tangents`` forms the whole of ``C`` without a residual call, exactly, for a system whose elements
    give their velocity slopes as tangents (linear dampers, torque laws; a turning eccentric mass does not and is
    refused): the residual's rates enter through the
    elements (``C_t``), the bodies' own forces, gravity plus a quadratic form of the rates
    (:func:`~ddgsa.mbs.compiled.body_rate_slopes`: ``G``, each body differenced alone, exact at any step), and
    the map, whose rates and accelerations are linear and quadratic in ``z'`` (``dq'/dz' = T``; ``dq''/dz'`` the
    Coriolis and spin terms of :func:`spin_map`, differenced exactly the same way):
    ``C = T^T (M dq''/dz' + (C_t - G) T)``. At rest ``G`` and the map's rate terms vanish (``T^T C_t T``).
    It needs the compiled terms (:class:`~ddgsa.mbs.compiled.HybridTerms`) for a spinning state; checked
    against the central differences in ``tests/mbs/test_nonrotating.py`` and on the test rig (whose speed sweep
    and steady block take it at rest and at speed) in ``tests/models/test_hss_rig_sweep_block.py``.
    """
    spinning = bool(np.any(qd0))
    if damping_tangents and spinning and not isinstance(system.fast_terms, HybridTerms):
        raise ModelError("linearise: damping_tangents at speed takes the compiled terms (HybridTerms); this system "
                         "has none")
    slopeless = [e.name for e in system.elements if isinstance(e, EccentricMass) and e.mass * e.radius != 0.0]
    if damping_tangents and spinning and slopeless:     # its force, m e w^2, has a rate slope it gives no tangent of
        raise ModelError(f"linearise: damping_tangents at speed leaves out the rate slope of {', '.join(slopeless)} "
                         "(an eccentric mass's force goes with the spin squared and has no damping tangent): "
                         "take its C from differences, or the mass as an input")
    if system.n_constraints:
        raise ModelError("the non-rotating linearisation takes unconstrained systems only "
                         f"({system.n_constraints} constraint equations given)")
    pairs = bending_pairs(system)
    xi0 = np.zeros((len(pairs), 2))
    for k, (iy, iz, isp) in enumerate(pairs):
        c, s = np.cos(q0[isp]), np.sin(q0[isp])
        xi0[k] = np.array([[c, -s], [s, c]]) @ q0[[iy, iz]]     # R(phi) q_pair
    n = system.n
    base = SpinLinearisation(np.eye(n), np.zeros((n, n)), np.zeros((n, n)), np.zeros(n), np.asarray(q0, float),
                             np.asarray(qd0, float), t0, pairs, xi0)
    zero = np.zeros(n)

    cols = np.setdiff1d(np.arange(n), np.asarray(tangent_columns, dtype=np.int64))
    if residual_only or not cols.size:              # no column differenced: no residual call
        k, c = np.zeros((n, n)), np.zeros((n, n))
    elif compiled and isinstance(system.fast_terms, HybridTerms):
        k = _hybrid_jacobian(system.fast_terms, base, 0, POSITION_SCALE, rel_step, cols)
        c = np.zeros((n, n)) if static or damping_tangents else _hybrid_jacobian(
            system.fast_terms, base, 1, VELOCITY_SCALE, rel_step, cols)
    elif len(tangent_columns):
        raise ModelError("tangent_columns take the compiled terms (HybridTerms); this system has none")
    else:
        def res(z: Array, zd: Array, zdd: Array) -> Array:
            return _residual(system, base, z, zd, zdd)

        args = [zero, zero, zero]
        k = central_jacobian(res, args, 0, POSITION_SCALE, rel_step)
        c = np.zeros((n, n)) if static or damping_tangents else central_jacobian(res, args, 1, VELOCITY_SCALE,
                                                                                 rel_step)
    q, qd, qdd = base.state(zero, zero, zero, t0)
    tm = system.terms(q, qd, t0)
    proj = base.projection(t0, zero)
    m = proj.T @ tm.m @ proj
    if len(tangent_columns) and not residual_only:
        tc = np.asarray(tangent_columns, dtype=np.int64)
        k[:, tc] = (proj.T @ tm.k @ proj)[:, tc]
        if not static and not damping_tangents:
            c[:, tc] = (proj.T @ tm.c @ proj)[:, tc]
    if damping_tangents and not static and not residual_only:
        c = proj.T @ tm.c @ proj
        if spinning:
            def rates(x: Array) -> Array:
                """``q''`` of the map (2p, n) at the stepped rates ``x`` (no position or acceleration step)."""
                return spin_map(base, np.zeros_like(x), x)[2]

            qdd_slope = central_difference(rates, zero, 1.0, 1.0)        # quadratic in z': exact at a unit step
            g = body_rate_slopes(system.fast_terms.packed, q, qd)
            c += proj.T @ (tm.m @ qdd_slope - g @ proj)
    if spin_stiffening:
        k = k + spin_stiffness(system, base.q0, base.qd0)
    return SpinLinearisation(m, c, k, proj.T @ (tm.q - tm.m @ qdd), base.q0, base.qd0, t0, pairs, xi0)


def spin_map(lin: SpinLinearisation, z: Array, zd: Array) -> tuple[Array, ...]:
    """:meth:`SpinLinearisation.state` at ``t0`` with ``zdd = 0`` for a batch of perturbations ``z``, ``zd``
    (m, n) at once: ``(q, qd, qdd)`` (m, n) and ``T(z)``'s pair entries, per pair ``cos phi``, ``sin phi``
    (m, n_pairs) of ``R(-phi) = [[c, s], [-s, c]]`` and the spin column ``-J R(-phi) xi = (r_z, -r_y)``
    (m, n_pairs, 2)."""
    q = lin.q0 + z
    qd = lin.qd0 + zd
    qdd = np.zeros_like(z)
    npair = len(lin.pairs)
    cos, sin, spin_col = np.zeros((z.shape[0], npair)), np.zeros((z.shape[0], npair)), np.zeros((z.shape[0], npair, 2))
    for k, (iy, iz, isp) in enumerate(lin.pairs):
        phi, w = q[:, isp], qd[:, isp]
        c, s = np.cos(phi), np.sin(phi)
        xy, xz = lin.xi0[k, 0] + z[:, iy], lin.xi0[k, 1] + z[:, iz]
        ry, rz = c * xy + s * xz, -s * xy + c * xz              # R(-phi) xi
        vy, vz = c * zd[:, iy] + s * zd[:, iz], -s * zd[:, iy] + c * zd[:, iz]      # R(-phi) xi'
        q[:, iy], q[:, iz] = ry, rz
        # d/dt R(-phi) xi = R(-phi) xi' - w J R(-phi) xi; the second rate adds -2 w J R xi' + w^2 J J R xi
        qd[:, iy], qd[:, iz] = vy + w * rz, vz - w * ry
        qdd[:, iy], qdd[:, iz] = 2 * w * vz - w * w * ry, -2 * w * vy - w * w * rz
        cos[:, k], sin[:, k] = c, s
        spin_col[:, k, 0], spin_col[:, k, 1] = rz, -ry
    return q, qd, qdd, cos, sin, spin_col


def _project(lin: SpinLinearisation, cos: Array, sin: Array, spin_col: Array, v: Array) -> Array:
    """``T^T v`` (m, n) for a batch of ``v`` (m, n) with ``T`` given by :func:`spin_map`'s pair entries."""
    out = v.copy()
    for k, (iy, iz, isp) in enumerate(lin.pairs):
        c, s = cos[:, k], sin[:, k]
        out[:, iy] = c * v[:, iy] - s * v[:, iz]
        out[:, iz] = s * v[:, iy] + c * v[:, iz]
        out[:, isp] += spin_col[:, k, 0] * v[:, iy] + spin_col[:, k, 1] * v[:, iz]
    return out


def _hybrid_jacobian(terms: HybridTerms, lin: SpinLinearisation, which: int, scale: float,
                     rel_step: float, columns: NDArray[np.int64]) -> Array:
    """Central differences (:func:`~ddgsa.mbs.derivatives.central_difference`, step ``rel_step * scale``) of
    the projected residual over the entries ``columns`` of ``z`` (``which`` 0) or ``z'`` (1) at zero, as of
    :func:`_residual` (the other columns zero): the steps' states at once (:func:`spin_map`; a step moves the
    coordinates of one body, the stepped one's and, for a spin, its bending pairs'), the packed part by the
    compiled kernel in one call, each step's residual the operating point's plus the change of the stepped
    body's own terms and of the elements on its markers
    (:func:`~ddgsa.mbs.compiled.stepped_residuals`: the same differences to round-off), each Python element
    (:attr:`HybridTerms.python`) once at the operating state and again for the steps of its markers' bodies'
    coordinates only (a step of another body's coordinate, turned within that body, leaves its markers and
    so its force as they were)."""
    n = lin.q0.size
    rows = sorted({r for rs in terms.marker_rows for r in rs})
    arrays = terms.packed.arrays
    t0 = float(lin.t0)
    zero = np.zeros((1, n))
    at0 = spin_map(lin, zero, zero)[:3]
    q, qd = at0[0][0], at0[1][0]
    r0 = _residuals(*at0, np.zeros(0), t0, arrays, False, np.full(1, -1))[0]      # the packed part at the operating point
    *base, lohi = _markers(q, qd, t0, arrays)
    span = {r: range(lohi[r, 0], lohi[r, 1]) for r in rows}         # the coordinates that move marker r

    def batch(steps: Array) -> Array:
        """The projected residual at each stepped row (row ``j`` steps coordinate ``columns[j % p]``)."""
        nil = np.zeros_like(steps)
        q, qd, qdd, cos, sin, spin_col = spin_map(lin, *((steps, nil) if which == 0 else (nil, steps)))
        stepped_coord = np.tile(columns, 2)
        res = stepped_residuals(terms.packed, *(np.vstack([x, x0]) for x, x0 in zip((q, qd, qdd), at0)), t0, r0,
                                stepped_coord)                          # the packed part, one compiled call
        moved = {j: _markers(q[j], qd[j], t0, arrays)[:5] for j, col in enumerate(stepped_coord)
                 if any(col in span[r] for r in rows)}
        for (_, el), el_rows in zip(terms.python, terms.marker_rows):
            f0 = _element_force(el, t0, [MarkerState(*(arr[r] for arr in base)) for r in el_rows])
            cols = set().union(*(span[r] for r in el_rows))
            for j, col in enumerate(stepped_coord):
                if col in cols:
                    res[j] -= _element_force(el, t0, [MarkerState(*(arr[r] for arr in moved[j])) for r in el_rows])
                else:
                    res[j] -= f0
        return _project(lin, cos, sin, spin_col, res)

    return central_difference(batch, np.zeros(n), scale, rel_step, columns)


def _element_force(el: Element, t: float, states: list[MarkerState]) -> Array:
    """Generalised force (n,) of one element at its markers' ``states``."""
    w = el.wrench(t, states)[0]
    return np.vstack([s.jac for s in states]).T @ w.ravel()


def projected_inputs(system: System, lin: SpinLinearisation, times: Array, elements: Sequence[Element],
                     relative: bool | Sequence[bool] = True) -> Array:
    """``T(t)^T (Q_sel(t) - Q_sel(t0))`` of the listed elements along the operating trajectory (n_t, n): the
    inputs of the linearisation (its ``r0`` holds them at ``t0``). ``relative=False``: ``T(t)^T Q_sel(t)``,
    for elements on the system's markers that are not among its parts (loads the linearisation left out, so
    its ``r0`` holds none of them); one flag per element: the sum of both kinds, one evaluation of the
    markers for all."""
    flags = np.broadcast_to(np.asarray(relative, dtype=bool), (len(elements),))
    times = np.concatenate([[lin.t0], np.asarray(times, dtype=float)])
    zero = np.zeros((times.size, lin.q0.size))
    q, qd = full_states(lin, times, zero, zero)
    markers = [mk for el in elements for mk in el.markers]
    if isinstance(system.fast_terms, HybridTerms) and all(system.fast_terms.has(mk) for mk in markers):
        states = system.fast_terms.states_along(markers, q, qd, times)     # those markers alone, compiled
    else:
        states = [system.states_of(markers, q[i], qd[i], t) for i, t in enumerate(times)]
    f = np.array([generalised_force(system.n, t, elements, st) for t, st in zip(times, states)])
    if not flags.all():       # the first row (t0) subtracted below: the relative elements' force alone
        ends = np.cumsum([len(el.markers) for el in elements])
        own = [st for e, flag in enumerate(flags) if flag
               for st in states[0][ends[e] - len(elements[e].markers):ends[e]]]
        f[0] = generalised_force(system.n, times[0], [el for el, flag in zip(elements, flags) if flag], own)
    out = f.copy()
    for k, (iy, iz, isp) in enumerate(lin.pairs):
        phi = q[:, isp]
        c, s = np.cos(phi), np.sin(phi)
        xy, xz = lin.xi0[k]
        ry, rz = c * xy + s * xz, -s * xy + c * xz              # R(-phi) xi
        # T^T: the pair's rows turned back by R(-phi)^T, the spin row gains (-J R(-phi) xi) . f_pair
        out[:, iy], out[:, iz] = c * f[:, iy] - s * f[:, iz], s * f[:, iy] + c * f[:, iz]
        out[:, isp] += rz * f[:, iy] - ry * f[:, iz]
    return out[1:] - out[0]


def simulate(system: System, lin: SpinLinearisation, t_end: float, dt: float, elements: Sequence[Element],
             period: float) -> tuple[Array, Array, Array]:
    """Exact response to the listed elements from the periodic state of one ``period`` [s]; every ``dt`` [s].

    Returns ``(t, q, qd)`` of the full system.
    """
    n = lin.m.shape[0]
    minv = np.linalg.inv(lin.m)
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-minv @ lin.k, -minv @ lin.c]])
    bw = np.vstack([np.zeros((n, n + 1)), minv @ np.column_stack([np.eye(n), lin.r0])])
    k = max(8, int(np.ceil(period / dt)))
    h = period / k
    tp = lin.t0 + h * np.arange(k + 1)
    xt = lti_response(a, bw, np.column_stack([projected_inputs(system, lin, tp, elements), np.ones(k + 1)]), h,
                      np.zeros(2 * n))[-1]
    # rigid directions of the positions (null space of K: the common spin angle) drift freely; the
    # rest of the state repeats after one period
    rigid = null_space(lin.k, rcond=RIGID_RCOND)
    w = null_space(rigid.T) if rigid.size else np.eye(n)
    e = np.block([[w, np.zeros((n, n))], [np.zeros((n, w.shape[1])), np.eye(n)]])
    y = np.linalg.lstsq(e.T @ (np.eye(2 * n) - expm(a * period)) @ e, e.T @ xt, rcond=None)[0]
    x0 = e @ y
    n_out = int(round((t_end - lin.t0) / dt)) + 1
    times = lin.t0 + dt * np.arange(n_out)
    x = lti_response(a, bw, np.column_stack([projected_inputs(system, lin, times, elements), np.ones(n_out)]), dt, x0)
    return (times, *full_states(lin, times, x[:, :n], x[:, n:]))


def periodic(system: System, lin: SpinLinearisation, t_end: float, dt: float, elements: Sequence[Element],
             period: float, samples: int = 64) -> tuple[Array, Array, Array]:
    """The periodic steady state when every listed input repeats with ``period`` [s], every ``dt`` [s].

    The inputs are sampled at ``samples`` points of one period and solved harmonic by harmonic,
    ``(K - (j W)^2 M + i j W C) Z_j = F_j`` with ``W = 2 pi / period`` (the static part ``j = 0``
    by least squares: the rigid spin direction carries no steady displacement), then summed at the
    record times. Exact for inputs band-limited below ``samples / 2`` harmonics (an unbalance is
    one harmonic in non-rotating coordinates); :func:`simulate` from the same periodic state gives
    the same record for such inputs (the check of this path), at the cost of the whole record's
    inputs and two matrix exponentials. Inputs that do not repeat with ``period`` (a defect
    impulse train at a non-integer order, a supply ripple at twice the line frequency) need
    :func:`simulate`. The solve and the sum are those of a block of points (:func:`harmonic_response`,
    :func:`synthesis`) for one point.

    Returns ``(t, q, qd)`` of the full system.
    """
    if samples < 8 or samples % 2:
        raise ModelError(f"periodic response: samples must be an even number >= 8, got {samples}")
    tp = lin.t0 + period * np.arange(samples) / samples
    w = 2 * np.pi / period
    f_hat = input_harmonics(projected_inputs(system, lin, tp, elements) + lin.r0)
    z0, z_hat = harmonic_response(lin.m[None], lin.c[None], lin.k[None], f_hat[None], w)
    n_out = int(round((t_end - lin.t0) / dt)) + 1
    times = lin.t0 + dt * np.arange(n_out)
    z, zd = synthesis(times - lin.t0, w, z_hat)
    return (times, *full_states(lin, times, z0[0] + z[0], zd[0]))


def input_harmonics(forces: Array) -> Array:
    """Complex harmonics ``F_j`` (..., samples/2, n) of inputs ``forces`` (..., samples, n) sampled at
    ``samples`` equal steps of one period (``F(t) = F_0 + 2 Re sum_j F_j e^{i j W t}``); the Nyquist
    term is left out (band limit)."""
    samples = forces.shape[-2]
    return (np.fft.rfft(forces, axis=-2) / samples)[..., : samples // 2, :]


def harmonic_response(m: Array, c: Array, k: Array, f_hat: Array, w: float) -> tuple[Array, NDArray[np.complex128]]:
    """The periodic steady state of a block of ``P`` linear systems, harmonic by harmonic.

    ``(K - (j W)^2 M + i j W C) Z_j = F_j`` for every point and harmonic ``j >= 1`` in one stacked
    solve (``np.linalg.solve`` over (P, J) matrices), the static part ``K Z_0 = F_0`` by least
    squares per point (the rigid spin direction carries no steady displacement).

    Parameters
    ----------
    m, c, k : (P, n, n)
        Mass [kg, kg m^2], damping [N s/m] and stiffness [N/m] matrices of each point (any consistent units).
    f_hat : (P, J + 1, n) complex
        Harmonics of the inputs (:func:`input_harmonics`), ``f_hat[:, 0]`` the static part.
    w : float
        The fundamental ``W`` [rad/s].

    Returns
    -------
    z0 : (P, n)
        Static parts.
    z_hat : (P, J, n) complex
        Harmonics ``Z_j``, ``j = 1..J``.
    """
    j = np.arange(1, f_hat.shape[1])[None, :, None, None] * w
    dynamic = k[:, None] - j**2 * m[:, None] + 1j * j * c[:, None]
    z_hat = np.linalg.solve(dynamic, f_hat[:, 1:, :, None])[..., 0]
    z0 = np.array([np.linalg.lstsq(kp, fp.real, rcond=RIGID_RCOND)[0] for kp, fp in zip(k, f_hat[:, 0])])
    return z0, z_hat


def synthesis(times: Array, w: float, z_hat: NDArray[np.complex128]) -> tuple[Array, Array]:
    """The periodic parts ``z = 2 Re sum_j Z_j e^{i j W t}`` and their rates at ``times`` [s] (from the
    phase origin) of harmonics ``z_hat`` (..., J, n): ``(z, zd)`` each (..., n_t, n).

    In real arithmetic, positions and rates in one product: ``2 Re(e^{i j W t} Z) = 2 (cos Re Z - sin Im Z)``,
    the rates' amplitudes ``i j W Z``."""
    harmonics = np.arange(1, z_hat.shape[-2] + 1)
    jw = (harmonics * w)[:, None]
    phase = np.outer(times, harmonics * w)                                            # (n_t, J)
    basis = np.hstack([np.cos(phase), np.sin(phase)])                                 # (n_t, 2J)
    amp = np.concatenate([np.concatenate([z_hat.real, -jw * z_hat.imag], axis=-1),
                          np.concatenate([-z_hat.imag, -jw * z_hat.real], axis=-1)], axis=-2)   # (..., 2J, 2n)
    both = 2 * (basis @ amp)
    n = z_hat.shape[-1]
    return both[..., :n], both[..., n:]


GROWTH = 0.01
"""Largest growth over the record, ``exp(Re(lambda) horizon) - 1`` [-], of a mode of a linearisation that
counts as stable: the rigid spin direction's zero eigenvalue comes out of the finite differences as a few
1e-5 1/s either side (the test rig), which no record sees."""
ON_MODE = 1e-6
"""Smallest relative distance ``|lambda - i j W| / (j W)`` of an eigenvalue from a harmonic the block
accepts: closer, the order lies on an undamped mode and its response is not finite."""


def first_order_eigenvalues(m: Array, c: Array, k: Array) -> NDArray[np.complex128]:
    """Eigenvalues [1/s] (P, 2n) of the first-order systems ``x' = A x`` of a block of ``P`` linearisations
    ``m, c, k`` (P, n, n), ``A = [[0, I], [-M^-1 K, -M^-1 C]]``: one stacked eigenvalue call."""
    return np.linalg.eigvals(_state_matrices(m, c, k))


def _state_matrices(m: Array, c: Array, k: Array) -> Array:
    """The first-order systems' matrices ``A`` (..., 2n, 2n) of ``m, c, k`` (..., n, n)."""
    n = m.shape[-1]
    a = np.zeros(m.shape[:-2] + (2 * n, 2 * n))
    a[..., :n, n:] = np.eye(n)
    a[..., n:, :n], a[..., n:, n:] = -np.linalg.solve(m, k), -np.linalg.solve(m, c)
    return a


def harmonic_validity(m: Array, c: Array, k: Array, w: float, harmonics: int, horizon: float,
                      eigenvalues: NDArray[np.complex128] | None = None) -> list[str | None]:
    """Why the periodic response of each of a block of ``P`` linearisations (``m, c, k`` (P, n, n)) does not
    hold, or None where it does: an unstable linearisation (a mode of the first-order system that grows by
    more than :data:`GROWTH` over ``horizon`` [s], the record), or a harmonic ``j W`` (``j = 1..harmonics``,
    ``w`` [rad/s]) on an undamped mode (:data:`ON_MODE`). ``eigenvalues`` (P, 2n): those of the block's
    first-order systems where the caller has them (:func:`first_order_eigenvalues`), else one stacked
    eigenvalue call here."""
    lam = first_order_eigenvalues(m, c, k) if eigenvalues is None else eigenvalues            # (P, 2n)
    out: list[str | None] = []
    for row in lam:
        worst = row[np.argmax(row.real)]
        if worst.real * horizon > np.log1p(GROWTH):
            out.append(f"unstable linearisation: eigenvalue {worst.real:.4g} {worst.imag:+.4g}i 1/s grows by "
                       f"more than {GROWTH:.0%} over the {horizon:g} s record")
            continue
        jw = w * np.arange(1, harmonics + 1)
        gap = np.abs(row[None, :] - 1j * jw[:, None]) / jw[:, None]
        j, e = np.unravel_index(np.argmin(gap), gap.shape)
        out.append(None if gap[j, e] > ON_MODE else
                   f"order {j + 1} on an undamped mode at {abs(row[e].imag) / (2 * np.pi):.6g} Hz "
                   f"(damping {-row[e].real:.3g} 1/s): no finite periodic response")
    return out


def full_states(lin: SpinLinearisation, times: Array, z: Array, zd: Array) -> tuple[Array, Array]:
    """``(q, qd)`` of the full system along ``times`` for non-rotating perturbations ``z``, ``zd`` (n_t, n):
    :meth:`SpinLinearisation.state` for a whole record at once, each bending pair turned by its
    body's actual spin angle."""
    q = lin.q0 + np.outer(np.asarray(times, dtype=float) - lin.t0, lin.qd0) + z
    qd = lin.qd0 + zd
    for k, (iy, iz, isp) in enumerate(lin.pairs):
        phi, w = q[:, isp], qd[:, isp]
        c, s = np.cos(phi), np.sin(phi)
        xy, xz = lin.xi0[k, 0] + z[:, iy], lin.xi0[k, 1] + z[:, iz]
        ry, rz = c * xy + s * xz, -s * xy + c * xz              # R(-phi) xi
        q[:, iy], q[:, iz] = ry, rz
        # d/dt R(-phi) xi = R(-phi) xi' - w J R(-phi) xi, J = [[0, -1], [1, 0]]
        qd[:, iy] = c * zd[:, iy] + s * zd[:, iz] + w * rz
        qd[:, iz] = -s * zd[:, iy] + c * zd[:, iz] - w * ry
    return q, qd



def whirl_index(system: System, lin: SpinLinearisation, shape: NDArray[np.complex128]) -> tuple[float, float]:
    """Energy-weighted orbit direction about +x of a mode ``shape`` in non-rotating coordinates, and
    the lateral share of its kinetic energy.

    As :func:`ddgsa.mbs.campbell.whirl_index`, with the bending pairs (non-rotating here, so their
    orbit is seen from the frame) among the orbits: each pair ``(Y, Z)`` orbits with direction
    ``2 Im(Y conj(Z)) / (|Y|^2 + |Z|^2)`` (+1: circular, counter-clockwise about +x, forward for a
    positive spin).
    """
    energy = np.abs(shape) ** 2 * np.abs(np.diag(lin.m))
    return orbit_average(shape, energy, [(iy, iz) for iy, iz, _ in lin.pairs] + orbit_pairs(system))


LATERAL_SHARE = 0.5
"""Least share of a mode's kinetic energy in the lateral and bending pairs for it to count as lateral
(:func:`lateral_frequencies`)."""


def lateral_frequencies(system: System, lin: SpinLinearisation, count: int,
                        eigenvalues: NDArray[np.complex128] | None = None) -> Array:
    """The ``count`` lowest damped natural frequencies [rad/s] of the lateral modes of ``lin``: modes of
    the first-order system (one per conjugate pair, positive imaginary part) whose kinetic energy lies
    mostly in the bodies' lateral and bending pairs (:func:`whirl_index`, share above
    :data:`LATERAL_SHARE`), lowest first; NaN where fewer are found. Seen from the frame at the
    linearisation's spin (a Campbell diagram's frequencies at that speed).

    ``eigenvalues`` (2n,): the first-order system's, where the caller has them
    (:func:`first_order_eigenvalues`); the shapes of the candidates, lowest first, then come from
    :func:`_inverse_iteration` (one complex factorisation each, two solves) instead of a full eigen
    decomposition with its vectors, which costs 1.7x the eigenvalues alone on the test rig's 84 states
    (``tests/models/test_hss_rig_block.py`` checks the block path's features, found this way, against the
    per-point path's, found by the full decomposition)."""
    n = lin.m.shape[0]
    a = _state_matrices(lin.m, lin.c, lin.k)
    if eigenvalues is None:
        lam, vec = np.linalg.eig(a)
    else:
        lam, vec = np.asarray(eigenvalues), None
    out = np.full(count, np.nan)
    found = 0
    for e in np.argsort(np.abs(lam.imag)):
        if lam[e].imag <= 0.0 or found == count:
            continue
        shape = vec[:n, e] if vec is not None else _inverse_iteration(a, lam[e])[:n]
        if whirl_index(system, lin, shape)[1] > LATERAL_SHARE:
            out[found] = lam[e].imag
            found += 1
    return out


def _inverse_iteration(a: Array, lam: complex) -> NDArray[np.complex128]:
    """The eigenvector (2n,) of ``a`` (2n, 2n) at its computed eigenvalue ``lam``: two steps of inverse
    iteration shifted to ``lam`` (the shift's round-off, ``eps |A|``, leaves a neighbour ``d`` apart at
    ``eps |A| / d`` of the shape per step) from a fixed generic start; a shift with an exactly zero pivot
    is moved by ``1e-12 |A|``."""
    n2 = a.shape[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", LinAlgWarning)          # a zero pivot: shifted again below
        lu = lu_factor(a - lam * np.eye(n2), check_finite=False)
    if not np.all(np.diagonal(lu[0])):
        lu = lu_factor(a - (lam + 1e-12 * np.abs(a).max()) * np.eye(n2), check_finite=False)
    v = np.random.default_rng(0).standard_normal(n2).astype(complex)
    for _ in range(2):
        v = lu_solve(lu, v, check_finite=False)
        v /= np.abs(v).max()
    return v
