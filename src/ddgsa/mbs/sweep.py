"""Speed sweeps (run-up, coast-down) of a spinning system that is linear about its static sag.

A rotor on non-rotating supports, written in the non-rotating bending coordinates ``z`` of
:mod:`ddgsa.mbs.nonrotating`, has matrices that do not depend on the spin angle when it is
axisymmetric, and depend on the spin ``W`` only through the gyroscopic term (linear in ``W``),
the internal damping of its turning bending coordinates (a skew-symmetric circulatory stiffness,
linear in ``W``) and the spin softening an FFR shaft's bending coordinates keep (symmetric,
quadratic in ``W``). A run-up or coast-down is then the linear parameter-varying system

``M z'' + (C_0 + W C_1) z' + (K_0 + W K_1 + W^2 K_2) z = r_0 - (W K_1 + W^2 K_2) s + W^2 r_2 + f(t, z, z')``,

with ``s`` the static displacement of the operating positions from the unloaded ones (the sag the
spin-dependent forces act on), ``r_2`` the part of the static force second order in the sag (a
torque on the spin rows from the sag's centrifugal force on the bent shape: the linear
extrapolation ``-(W K_1 + W^2 K_2) s`` gives half of it) and ``f`` the few nonlinear inputs the
caller names (torque laws of a spin speed, a turning unbalance). :func:`sweep_model` builds it from two linearisations of the
system without those inputs, at rest and at a reference spin ``W_1``: ``C_1`` from their
difference, ``K_1`` and ``K_2`` from the skew and symmetric parts of the stiffness difference
(for the test rig this split reproduces a third linearisation at ``W_1 / 2`` to 1e-6 of the change,
a quadratic fit only to 3e-2). The spin coordinates (``.rx`` of the rotating bodies) are the total
angles, not perturbations about ``W_1 t``: their equations are linear in angle differences, and
the matrices are made blind to the common (cyclic) angle. :func:`integrate` runs it with the
kernel's generalised-alpha (:mod:`ddgsa.mbs.alpha`'s one loop, compiled for the sweep and the
caller's compiled :class:`Inputs`) on small dense matrices: the iteration matrix
``M + gamma' h C(W) + beta' h^2 K(W)`` at the step's spin (modified Newton: factorised once a step),
the inputs iterated to the kernel's tolerance. :func:`full_state` maps the
record back to the system's coordinates with the actual spin angles (for sensors), and
:func:`steady_orbit` gives the periodic state a coast-down starts from.

What it leaves out (the caller's model must allow it): the dependence of the matrices on the
spin angle (an anisotropic rotor or support turning with it: the caller carries it in ``f`` as
a turning input, as the test rig does with its coupling; :func:`steady_orbit` takes its
harmonics), geometric nonlinearity about the sag, and any state dependence of the inputs other
than what ``f`` computes.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import cached_property, lru_cache

import numpy as np
from numba import njit
from numpy.typing import NDArray
from scipy.linalg import eigh
from scipy.optimize import NoConvergence, newton_krylov

from ddgsa.errors import ModelError
from ddgsa.mbs.assembly import System
from ddgsa.mbs.bodies import Marker
from ddgsa.mbs.alpha import _advance, _predict, bind, coefficients, specialise, stamp, steps
from ddgsa.mbs.nonrotating import RIGID_RCOND, SpinLinearisation, full_states
from ddgsa.mbs.nonrotating import first_order_eigenvalues
from ddgsa.mbs.nonrotating import lateral_frequencies as _lateral_at

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Inputs:
    """The nonlinear inputs ``f(t, z, z')`` of a sweep: a compiled function and what it reads.

    Attributes
    ----------
    add : numba dispatcher
        ``add(t, z, zd, data, f)``: adds the generalised forces [N, N m] at time ``t`` [s] and state
        ``(z, z')`` to ``f`` (n,) in place (an ``njit`` function; the sweep's loop is compiled for it).
    data : tuple
        What ``add`` reads: arrays and floats (a numba-typable tuple).
    """

    add: Callable
    data: tuple


@dataclass(frozen=True)
class SweepModel:
    """``M z'' + (C_0 + W C_1) z' + (K_0 + W K_1 + W^2 K_2) z = r_0 - (W K_1 + W^2 K_2) s + W^2 r_2 + f``
    (see the module).

    Attributes
    ----------
    m, c0, c1 : (n, n)
        Mass [kg, kg m^2], damping at rest and its gyroscopic slope per unit spin (SI per coordinate).
    k0, k1, k2 : (n, n)
        Stiffness at rest, its circulatory part per unit spin and its softening per unit spin squared.
    r0, r1, r2 : (n,)
        The static generalised force ``r(W) = r_0 + W r_1 + W^2 r_2`` [N, N m; per rad/s; per (rad/s)^2]:
        at the operating positions at rest, and its slope and curvature with the spin -- the
        extrapolation through the sag ``s``, ``r_1 = -K_1 s``, and ``r_2`` the reference
        linearisation's static force less that extrapolation (``-K_2 s`` included), so ``r(W_1)`` is exact.
    spin : (n,)
        Row giving the spin ``W = spin @ z'`` [rad/s] the matrices are evaluated at.
    rates : (n,)
        Rates of a rigid spin at unit speed (1 on every rotating body's angle) [-].
    lin : SpinLinearisation
        The linearisation at rest (operating positions, bending pairs) for :func:`full_state`.
    basis : (n_system, n), optional
        A reduced model's basis (:func:`reduce`): the system's non-rotating coordinates are ``basis @ z``
        (None: ``z`` are those coordinates).
    """

    m: Array
    c0: Array
    c1: Array
    k0: Array
    k1: Array
    k2: Array
    r0: Array
    r1: Array
    r2: Array
    spin: Array
    rates: Array
    lin: SpinLinearisation
    basis: Array | None = None

    @cached_property
    def arrays(self) -> tuple[Array, ...]:
        """``(M, C_0, C_1, K_0, K_1, K_2, r_0, r_1, r_2, spin, transposes of (C_0, C_1, K_0, K_1, K_2))``: what
        the compiled sweep reads (the transposes for its column-by-column products)."""
        tr = tuple(np.ascontiguousarray(a.T) for a in (self.c0, self.c1, self.k0, self.k1, self.k2))
        return (self.m, self.c0, self.c1, self.k0, self.k1, self.k2, self.r0, self.r1, self.r2, self.spin, tr)

    def at_spin(self, w: float) -> tuple[Array, Array, Array]:
        """``(K(w), C(w), r(w))``: stiffness, damping and gyroscopic matrix, static generalised force at
        spin ``w`` [rad/s] (the compiled :func:`_at_spin` the sweep's steps evaluate)."""
        n = self.m.shape[0]
        k, c, r = np.empty((n, n)), np.empty((n, n)), np.empty(n)
        _at_spin(self.arrays, float(w), k, c, r)
        return k, c, r


def sweep_model(rest: SpinLinearisation, spinning: SpinLinearisation, spin_index: int, sag: Array) -> SweepModel:
    """The sweep model from linearisations at rest and at a reference spin (same positions).

    Parameters
    ----------
    rest, spinning : SpinLinearisation
        :func:`ddgsa.mbs.nonrotating.linearise` of the system without the sweep's inputs about the
        same positions ``q0``, with zero rates and with the reference spin on every rotating body.
    spin_index : int
        System index of the coordinate whose rate is the spin ``W`` (``spinning.qd0[spin_index]``
        is the reference spin ``W_1``, > 0).
    sag : (n,)
        ``q0`` less the unloaded positions [m, rad] (no spin angles in it).
    """
    w1 = float(spinning.qd0[spin_index])
    if not w1 > 0.0:
        raise ModelError(f"sweep model: the reference spin must be positive, got {w1} rad/s")
    if np.any(rest.qd0) or not np.allclose(rest.q0, spinning.q0, rtol=0.0, atol=1e-12):
        raise ModelError("sweep model: the two linearisations must share their positions, the first at rest")
    row = np.zeros(rest.q0.size)
    row[spin_index] = 1.0
    rates = spinning.qd0 / w1
    # the common spin angle is cyclic and the spin a parameter: no force may depend on the angle
    # (central-difference noise along it would grow with the hundreds of radians a sweep turns), and
    # the spinning damping's column along the spin rate is the speed derivative of the static
    # spin-dependent force, not a damping (times the spin itself it would add that force twice)
    free = np.eye(rates.size) - np.outer(rates, rates) / (rates @ rates)
    dk = spinning.k - rest.k
    k1, k2 = (dk - dk.T) @ free / (2 * w1), (dk + dk.T) @ free / (2 * w1**2)
    sag = np.asarray(sag, dtype=float)
    r1 = -k1 @ sag
    r2 = (spinning.r0 - rest.r0 - w1 * r1) / w1**2
    return SweepModel(rest.m, rest.c @ free, (spinning.c - rest.c) @ free / w1, rest.k @ free, k1, k2, rest.r0,
                      r1, r2, row, rates, rest)


def reduce(model: SweepModel, band_hz: float) -> SweepModel:
    """The sweep model on the basis of its modes up to ``band_hz`` [Hz] (issue 46: a modal model reduced to
    the scene's band).

    The basis is the rigid spin (:attr:`SweepModel.rates`) and the undamped modes of the symmetric part of
    ``(K_0, M)`` at rest below ``band_hz``, made mass-orthonormal to it: every matrix projected
    (``basis.T @ A @ basis``), every force row (``basis.T @ r``). The spin-dependent terms (gyroscopic,
    circulatory, softening) couple the kept modes among themselves; what lies above the band responds
    quasi-statically and is dropped, so the band must hold every frequency the caller's records read (the
    test rig's accelerometers read their housings' resonances up to the record's Nyquist frequency: a band
    below them moves their RMS by 20 %, ``tests/models/test_hss_rig_sweep_block.py``). The caller maps its
    input rows onto the basis (``row @ basis``); :func:`full_state` maps the record back.
    """
    if model.basis is not None:
        raise ModelError("sweep reduce: the model is reduced already")
    if not band_hz > 0.0:
        raise ModelError(f"sweep reduce: the band must be positive, got {band_hz} Hz")
    m = model.m
    w2, shapes = eigh(0.5 * (model.k0 + model.k0.T), m)
    rigid = model.rates / np.sqrt(model.rates @ m @ model.rates)
    shapes = shapes - np.outer(rigid, rigid @ m @ shapes)        # mass-orthogonal to the spin
    # the spin's own mode is left with nothing (the others are mass-orthogonal to it already)
    own = np.einsum("ij,ik,kj->j", shapes, m, shapes) > 0.5
    shapes = shapes[:, own & (w2 < (2 * np.pi * band_hz) ** 2)]
    basis = np.column_stack([rigid, shapes])
    bt = basis.T

    def mat(a: Array) -> Array:
        return np.ascontiguousarray(bt @ a @ basis)

    rates = np.zeros(basis.shape[1])
    rates[0] = np.sqrt(model.rates @ m @ model.rates)             # the spin's rates are the first column times this
    return SweepModel(mat(m), mat(model.c0), mat(model.c1), mat(model.k0), mat(model.k1), mat(model.k2),
                      bt @ model.r0, bt @ model.r1, bt @ model.r2, model.spin @ basis, rates, model.lin, basis)


def lateral_frequencies(system: System, model: SweepModel, spin: float, count: int) -> Array:
    """The ``count`` lowest lateral natural frequencies [rad/s] of the unreduced sweep ``model`` of ``system`` at the
    spin ``spin`` [rad/s]: :func:`ddgsa.mbs.nonrotating.lateral_frequencies` of its matrices there (``M``,
    ``C_0 + W C_1``, ``K_0 + W K_1 + W^2 K_2``), seen from the frame; at the reference spin they are the spinning
    linearisation's own (``tests/mbs/test_sweep.py``). The eigenvalues alone, the few lowest modes' shapes by
    inverse iteration (``eigenvalues`` of :func:`~ddgsa.mbs.nonrotating.lateral_frequencies`: 1.7x cheaper than a
    decomposition with its vectors, as the steady block's)."""
    if model.basis is not None:
        raise ValueError("sweep.lateral_frequencies takes the unreduced model (its coordinates are the system's)")
    k, c, _ = model.at_spin(spin)
    return _lateral_at(system, replace(model.lin, m=model.m, c=c, k=k), count, first_order_eigenvalues(model.m, c, k))


def marker_rows(system: System, lin: SpinLinearisation, marker: Marker) -> Array:
    """``d (v, w) / d z'`` (6, n) of ``marker`` at the operating point: translational and angular
    velocity rows [m/s, rad/s per unit rate]; their transposes map a force and moment on the
    marker to generalised forces in ``z``."""
    return system.marker_state(marker, lin.q0, np.zeros_like(lin.q0), lin.t0).jac @ lin.projection(lin.t0)


def integrate(model: SweepModel, t_end: float, dt: float, z0: Array, zd0: Array, inputs: Inputs,
              output_every: int = 1, rho_inf: float = 0.8, tol: float = 1e-10,
              max_iter: int = 20, reuse: int = 0, extrapolate: bool = False,
              incremental: bool = False) -> tuple[Array, Array, Array]:
    """Generalised-alpha run of the sweep model from ``(z0, zd0)`` at ``t = 0`` to ``t_end`` [s].

    The kernel's loop (:mod:`ddgsa.mbs.alpha`) compiled for this sweep and its ``inputs``: the
    matrices at the step's spin written in place, the inputs added, modified Newton.

    Parameters
    ----------
    inputs : Inputs
        The nonlinear generalised forces (torque laws, unbalance) as a compiled function.
    output_every : int
        Keep every ``output_every``-th step.
    rho_inf, tol, max_iter
        As :func:`ddgsa.mbs.integrate.genalpha.simulate` (the iteration stops when the position
        correction is below ``tol``; the inputs' slopes are left out of the iteration matrix, so
        they must be small against ``M / (gamma' h)``: torque laws of a speed are).
    reuse : int
        0: the iteration matrix factorised once a step (modified Newton); ``k > 0``: its factors kept across
        steps while a step converges in at most ``k`` iterations (:mod:`ddgsa.mbs.alpha`'s ``reuse``: the
        sweep's matrices change with the spin only; the states are the same to ``tol``).
    extrapolate : bool
        Predict each step's acceleration by linear extrapolation from the last two (:mod:`ddgsa.mbs.alpha`'s
        predictor option) instead of the last one: the same states to ``tol``, about a fifth fewer iterations
        on the test rig's sweeps.
    incremental : bool
        Run :func:`_incremental_loop` instead of the kernel's loop: the same generalised-alpha iterates, the
        residual's linear part carried along the Newton corrections (three products a correction with matrices
        fixed for the step size, instead of the six of a fresh evaluation) and the iteration matrix formed from
        those matrices; the states agree with the kernel's loop to ``tol``.

    Returns
    -------
    ``(t, z, zd)`` at the kept steps.
    """
    n_steps = steps(t_end, dt, output_every, "sweep")
    kind, loop = _compiled(inputs.add)
    ctx = (model.arrays, inputs.data)
    z, zd = np.array(z0, dtype=float), np.array(zd0, dtype=float)
    n = z.size
    m, f, kt, ct = np.zeros((n, n)), np.zeros(n), np.zeros((n, n)), np.zeros((n, n))
    kind(z, zd, 0.0, 0, ctx, m, f, kt, ct, np.zeros(0), np.zeros(0), np.zeros((0, n)), np.zeros(0))
    acc = np.linalg.solve(m, f)
    if incremental:
        z_out, zd_out, status, _ = _compiled_incremental(inputs.add)(
            model.arrays, inputs.data, z, zd, acc, float(dt), n_steps, output_every, *coefficients(rho_inf), tol,
            max_iter, reuse, extrapolate)
    else:
        z_out, zd_out, _, _, _, status, _ = loop(ctx, z, zd, acc, np.zeros(0), 0.0, float(dt), n_steps, output_every,
                                                 *coefficients(rho_inf), tol, max_iter, 0, 0, extrapolate, False, True,
                                                 reuse)
    if status < 0:
        raise ModelError(f"sweep: the iteration did not converge in {max_iter} iterations at t = {-status * dt:.6g} s "
                         f"(step {dt} s), or the state is not finite; reduce the step")
    return dt * output_every * np.arange(n_steps // output_every + 1), z_out, zd_out


@njit(cache=True)
def _at_spin(arrays, w, k, c, r):  # pragma: no cover (compiled)
    """``K(w) = K_0 + w K_1 + w^2 K_2``, ``C(w) = C_0 + w C_1`` and ``r(w) = r_0 + w r_1 + w^2 r_2``
    written into ``k``, ``c``, ``r`` (see :class:`SweepModel`; ``arrays`` is :attr:`SweepModel.arrays`)."""
    c0, c1, k0, k1, k2, r0, r1, r2 = arrays[1], arrays[2], arrays[3], arrays[4], arrays[5], arrays[6], arrays[7], arrays[8]
    w2 = w * w
    for i in range(r.size):
        r[i] = r0[i] + w * r1[i] + w2 * r2[i]
        for j in range(r.size):
            k[i, j] = k0[i, j] + w * k1[i, j] + w2 * k2[i, j]
            c[i, j] = c0[i, j] + w * c1[i, j]


@njit(cache=True, inline="always")
def _linear_terms(z, zd, arrays, m, f, kt, ct):  # pragma: no cover (compiled)
    """``M``, ``K(W)``, ``C(W)`` and ``f = r(W) - C(W) z' - K(W) z`` at ``W = spin @ z'`` (:func:`_at_spin`);
    with empty ``kt``, ``ct`` (the loop's kept factors: :mod:`ddgsa.mbs.alpha`'s ``reuse``) ``f`` alone, column by
    column through the parts' transposes (independent updates: half the time of the row sums that form ``K(W)``,
    ``C(W)``), ``M`` left as the last full evaluation wrote it (it is constant)."""
    mm, spin = arrays[0], arrays[9]
    n = z.size
    w = 0.0
    for i in range(n):
        w += spin[i] * zd[i]
    if kt.size == 0:
        r0, r1, r2 = arrays[6], arrays[7], arrays[8]
        c0, c1, k0, k1, k2 = arrays[10]            # transposed: row j is column j
        w2 = w * w
        for i in range(n):                         # M stands as the last full evaluation wrote it
            f[i] = r0[i] + w * r1[i] + w2 * r2[i]
        for j in range(n):                         # column by column: independent updates of f (vectorised)
            a, b, c = zd[j], w * zd[j], z[j]
            d, e = w * c, w2 * c
            for i in range(n):
                f[i] -= c0[j, i] * a + c1[j, i] * b + k0[j, i] * c + k1[j, i] * d + k2[j, i] * e
        return
    _at_spin(arrays, w, kt, ct, f)
    for i in range(n):
        acc = f[i]
        for j in range(n):
            m[i, j] = mm[i, j]
            acc -= ct[i, j] * zd[j] + kt[i, j] * z[j]
        f[i] = acc


_inputs: Callable | None = None
"""The sweep's inputs, bound in each copy of :func:`_kind` by :func:`_compiled`."""


def _kind(z, zd, t, step, ctx, m, f, kt, ct, y, ch, jac, vel):  # pragma: no cover (compiled per inputs)
    """The sweep as a kind of :mod:`ddgsa.mbs.alpha`'s loop: :func:`_linear_terms` plus the inputs."""
    _linear_terms(z, zd, ctx[0], m, f, kt, ct)
    _inputs(t, z, zd, ctx[1], f)


@lru_cache(maxsize=None)
def _compiled(add: Callable) -> tuple[Callable, Callable]:
    """The kind and the loop compiled (and cached) for the inputs function ``add``."""
    # the stamp covers the kernel's files and the inputs' package (the physics the inputs call)
    folders = (os.path.dirname(__file__), os.path.dirname(add.py_func.__code__.co_filename))
    tag = f"sweep_{getattr(add, '__name__', 'inputs')}_{stamp(add, folders=folders)}"
    kind = njit(cache=True, inline="always")(bind(add, tag, _kind, name="_inputs"))
    return kind, specialise(kind, tag)


def _incremental_loop(arrays, data, z0, zd0, acc0, h, n_steps, output_every, am, af, gamma, beta, tol, max_iter,
                      reuse, extrapolate):  # pragma: no cover (compiled per inputs)
    """The kernel's generalised-alpha loop (:func:`ddgsa.mbs.alpha._loop` with modified Newton, its ``reuse`` of
    the factors and its predictor) for the sweep model alone, its residual's linear part carried along the step.

    At a step's predictor ``p = M a + C_0 z' + K_0 z``, ``v = C_1 z' + K_1 z`` and ``u = K_2 z`` are formed once
    (rows of ``[M C_0 K_0]``, ``[C_1 K_1]``, ``K_2`` against ``[a; z'; z]``); the residual is
    ``p + W v + W^2 u - r(W) - f(t, z, z')`` with ``W = spin @ z'``, and a correction ``d`` of the acceleration
    (``z += beta' h^2 d``, ``z' += gamma' h d``) moves them by the rows of ``[S_0; S_1; S_2] d`` with
    ``S_0 = M + gamma' h C_0 + beta' h^2 K_0``, ``S_1 = gamma' h C_1 + beta' h^2 K_1``, ``S_2 = beta' h^2 K_2``
    (fixed for the step size: three products a correction instead of six). The iteration matrix
    ``M + gamma' h C(W) + beta' h^2 K(W)`` is ``S_0 + W S_1 + W^2 S_2``, kept as its inverse (a product a
    correction; modified Newton converges on the residual, so the inverse's round-off moves no converged state).
    Every product is a row's dot product, which :func:`_compiled_incremental` lets the compiler reorder (its
    ``fastmath`` flags: no NaN or infinity assumption, so the finiteness checks hold). The iterates are the kernel
    loop's up to round-off. ``arrays`` is :attr:`SweepModel.arrays`, ``data`` the inputs'; ``_inputs`` is bound
    by :func:`_compiled_incremental`. Returns ``(z, z', status, total)`` at the kept steps as the kernel's loop
    (``status`` the worst Newton count, or ``-step`` at the step that failed)."""
    m, c0, c1, k0, k1, k2 = arrays[0], arrays[1], arrays[2], arrays[3], arrays[4], arrays[5]
    r0, r1, r2, spin = arrays[6], arrays[7], arrays[8], arrays[9]
    n = z0.size
    bp = beta * (1.0 - af) / (1.0 - am)
    gp = gamma * (1.0 - af) / (1.0 - am)
    bh2, gh = bp * h * h, gp * h
    s0 = m + gh * c0 + bh2 * k0
    s1 = gh * c1 + bh2 * k1
    s2 = bh2 * k2
    state_rows = np.ascontiguousarray(np.hstack((m, c0, k0)))       # p = state_rows @ [a; z'; z]
    spin_rows = np.ascontiguousarray(np.hstack((c1, k1)))           # v = spin_rows @ [z'; z]
    soft_rows = np.ascontiguousarray(k2)                            # u = soft_rows @ z
    moves = np.ascontiguousarray(np.vstack((s0, s1, s2)))           # [p; v; u] += moves @ d
    x, y = np.zeros(3 * n), np.zeros(3 * n)                         # [a; z'; z] and [p; v; u]
    z, zd, acc = z0.copy(), zd0.copy(), acc0.copy()
    aux, acc_prev, acc_new = acc.copy(), acc.copy(), acc.copy()
    g, rhs, delta = np.zeros(n), np.zeros(n), np.zeros(n)
    big, inverse = np.zeros((n, n)), np.zeros((n, n))
    n_out = n_steps // output_every + 1
    z_out, zd_out = np.zeros((n_out, n)), np.zeros((n_out, n))
    z_out[0], zd_out[0] = z, zd
    slot, worst, total = 1, 0, 0
    stale = True
    for step in range(1, n_steps + 1):
        t = step * h
        _predict(z, zd, acc, aux, acc_prev, acc_new, h, am, af, gamma, beta, extrapolate)
        x[:n] = acc_new
        x[n:2 * n] = zd
        x[2 * n:] = z
        for i in range(n):
            acc_i = 0.0
            for j in range(3 * n):
                acc_i += state_rows[i, j] * x[j]
            y[i] = acc_i
            acc_i = 0.0
            for j in range(2 * n):
                acc_i += spin_rows[i, j] * x[n + j]
            y[n + i] = acc_i
            acc_i = 0.0
            for j in range(n):
                acc_i += soft_rows[i, j] * x[2 * n + j]
            y[2 * n + i] = acc_i
        converged = False
        it = 0
        for it in range(max_iter):
            w = 0.0
            for i in range(n):
                w += spin[i] * zd[i]
            w2 = w * w
            g[:] = 0.0
            _inputs(t, z, zd, data, g)
            for i in range(n):
                rhs[i] = r0[i] + w * r1[i] + w2 * r2[i] + g[i] - y[i] - w * y[n + i] - w2 * y[2 * n + i]
            if (it == 0 and stale) or (reuse > 0 and it == 2 * reuse):
                for i in range(n):
                    for j in range(n):
                        big[i, j] = s0[i, j] + w * s1[i, j] + w2 * s2[i, j]
                inverse[:, :] = np.linalg.inv(big)
            largest = 0.0
            for i in range(n):
                acc_i = 0.0
                for j in range(n):
                    acc_i += inverse[i, j] * rhs[j]
                delta[i] = acc_i
            for i in range(n):
                acc_new[i] += delta[i]
                z[i] += bh2 * delta[i]
                zd[i] += gh * delta[i]
                largest = max(largest, abs(bh2 * delta[i]))
            if largest < tol:
                converged = True
                break
            for r in range(3 * n):
                acc_i = 0.0
                for j in range(n):
                    acc_i += moves[r, j] * delta[j]
                y[r] += acc_i
        if not converged or not np.all(np.isfinite(z)):
            return z_out[:slot], zd_out[:slot], -step, total
        total += it + 1
        worst = max(worst, it + 1)
        stale = reuse == 0 or it + 1 > reuse
        _advance(acc, aux, acc_prev, acc_new, am, af)
        if step % output_every == 0:
            z_out[slot], zd_out[slot] = z, zd
            slot += 1
    return z_out, zd_out, worst, total


REORDER = frozenset({"reassoc", "contract", "nsz", "arcp"})
"""The ``fastmath`` flags of :func:`_incremental_loop`: sums reordered (its dot products vectorised: 1.7x on the
rig's start-up), no assumption that values are finite."""


@lru_cache(maxsize=None)
def _compiled_incremental(add: Callable) -> Callable:
    """:func:`_incremental_loop` compiled (and cached) for the inputs function ``add``."""
    folders = (os.path.dirname(__file__), os.path.dirname(add.py_func.__code__.co_filename))
    tag = f"{getattr(add, '__name__', 'inputs')}_{stamp(_incremental_loop, add, folders=folders)}"
    return njit(cache=True, fastmath=set(REORDER))(bind(add, tag, _incremental_loop, name="_inputs"))


def full_state(model: SweepModel, z: Array, zd: Array) -> tuple[Array, Array]:
    """``(q, qd)`` (n_t, n) of the system for records ``z``, ``zd`` (n_t, n), with each bending pair
    turned by its body's actual spin angle ``q0 + z`` (not the reference trajectory's):
    :func:`ddgsa.mbs.nonrotating.full_states` of the linearisation at rest (no reference spin); a reduced
    model's records mapped back through its basis first."""
    if model.basis is not None:
        z, zd = z @ model.basis.T, zd @ model.basis.T
    return full_states(model.lin, np.zeros(z.shape[0]) + model.lin.t0, z, zd)


def steady_orbit(model: SweepModel, w: float, static: Array, once: NDArray[np.complex128], tangent: Array,
                 gauge: Array, turning: Callable[[Array], Array] | None = None, samples: int = 16,
                 rtol: float = 1e-9, max_iter: int = 30) -> tuple[Array, Array]:
    """State ``(z, z')`` at ``t = 0`` of the periodic response at constant spin ``w`` [rad/s].

    ``z(t) = z_s + w t rates + Re(sum_j Z_j exp(i j w t))`` with ``K z_s = r + static + F_0``
    (least squares: the rigid spin direction carries no static load, ``gauge @ z_s = 0``) and
    ``(K - (j w)^2 M + i j w (C(w) + tangent)) Z_j = F_j`` (plus ``once`` at ``j = 1``), ``F_j``
    the harmonics of ``turning(z(t))`` over one revolution (``samples`` points, harmonics below
    ``samples / 2``), iterated to a fixed point (the turning input's dependence on the state, a
    parametric stiffness, must be small against the rig's: the iteration stops when the orbit
    changes by less than ``rtol`` of its size).

    Parameters
    ----------
    static : (n,)
        Constant inputs at the operating point (the torques that wind the shafts up) [SI].
    once : (n,) complex
        Once-per-revolution input amplitude (``Re(once exp(i w t))``, an unbalance) [SI].
    tangent : (n, n)
        ``-d f / d z'`` of the inputs at the operating point (a torque law's slope damps the spin).
    gauge : (n,)
        Row fixing the free common angle: ``gauge @ z_s = 0`` (e.g. the angle the unbalance turns with).
    turning : callable, optional
        ``turning(z) -> f`` (m, n): an input that repeats with the revolution on the orbit (a turning
        anisotropy acting on the state), evaluated at the orbit's ``m`` samples ``z`` (m, n) at once, their spin
        angle included.
    """
    k, c, r = model.at_spin(w)
    # one SVD for the rigid directions and the least-squares flexibility (scipy's null_space and numpy's pinv
    # cut at the same relative singular value)
    u, sv, vh = np.linalg.svd(k)
    kept = int(np.sum(sv > RIGID_RCOND * sv.max(initial=0.0)))
    rigid = vh[kept:].T
    flexibility = vh[:kept].T @ (u[:, :kept].T / sv[:kept, None])
    n_h = samples // 2
    damping = c + tangent
    ops = np.array([k - (j * w) ** 2 * model.m + 1j * j * w * damping for j in range(1, n_h)])
    inverses = np.linalg.inv(ops)                  # once: the fixed point below responds to many inputs
    g = gauge @ rigid
    # the gauge's minimum-norm correction along the rigid directions (the least-squares solution of one row)
    along = rigid @ g / (g @ g) if rigid.size and g @ g > 0.0 else np.zeros((k.shape[0]))
    tau = 2 * np.pi / w * np.arange(samples) / samples
    phase = np.exp(1j * w * np.outer(tau, np.arange(1, n_h)))               # (samples, n_h - 1)
    shape = (n_h, k.shape[0])

    def respond(f_hat: NDArray[np.complex128]) -> tuple[Array, NDArray[np.complex128]]:
        """The static part and harmonic amplitudes ``(z_s, Z_j)`` for turning-input harmonics ``f_hat``."""
        zs = flexibility @ (r + static + f_hat[0].real)            # the least-squares static part
        zs = zs - along * (gauge @ zs)
        rhs = f_hat[1:].astype(complex)
        rhs[0] += once
        return zs, np.einsum("jab,jb->ja", inverses, rhs)                  # (n_h - 1, n)

    def harmonics(zs: Array, amps: NDArray[np.complex128]) -> NDArray[np.complex128]:
        """The turning input's harmonics over the orbit ``(z_s, Z_j)``."""
        assert turning is not None
        orbit = zs + (phase @ amps).real + np.outer(w * tau, model.rates)
        f_hat = np.fft.fft(turning(orbit), axis=0)[:n_h] / samples
        f_hat[1:] *= 2.0                                                       # Re(F_j exp(i j w t)) form
        return f_hat

    zs, amps = respond(np.zeros(shape, dtype=complex))
    last, first = None, None
    for _ in range(max_iter if turning is not None else 0):
        f_hat = harmonics(zs, amps)
        first = f_hat if first is None else first
        zs, amps = respond(f_hat)
        state = np.concatenate([zs, amps.ravel().view(float)])
        if last is not None and np.linalg.norm(state - last) <= rtol * np.linalg.norm(state):
            break
        last = state
    else:
        if turning is not None:
            # Near a resonance the parametric coupling of the turning input is no longer small against
            # the rig's dynamic stiffness and the plain iteration diverges: solve the fixed point
            # f = harmonics(respond(f)) by Newton-Krylov from the first iterate (the map is affine in f
            # up to the spin angle's small effect, so one or two Newton steps do).
            def residual(x: Array) -> Array:
                f = x.view(complex).reshape(shape)
                return (harmonics(*respond(f)) - f).ravel().view(float)

            x0 = np.array(first).ravel().view(float)                             # the first iterate
            scale = max(float(np.abs(x0).max()), np.finfo(float).tiny)
            try:
                x = newton_krylov(residual, x0.copy(), f_tol=rtol * scale, maxiter=max_iter)
            except (NoConvergence, ValueError, np.linalg.LinAlgError) as exc:
                raise ModelError(f"steady orbit: the turning input's harmonics did not settle in {max_iter} "
                                 f"iterations, nor by Newton-Krylov ({exc})") from None
            zs, amps = respond(x.view(complex).reshape(shape))
    z = zs + amps.sum(axis=0).real
    zd = (1j * w * np.arange(1, n_h)[:, None] * amps).sum(axis=0).real + w * model.rates
    return z, zd
