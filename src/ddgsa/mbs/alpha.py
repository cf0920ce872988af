"""Generalised-alpha (Chung & Hulbert 1993, in the Arnold & Bruls 2007 form), written once.

One Newton loop, :func:`_loop`, integrates ``M(q) q_ddot + C_q^T lambda = Q(q, q_dot, t)`` with
holonomic constraint rows at position level (index 3) and velocity-level rows at index 2, both
scaled by the Newmark factors ``1/(beta' h^2)`` and ``1/(gamma' h)`` (Bottasso, Bauchau & Cardona
2007), so the iteration matrix ``[[M + gamma' h C_t + beta' h^2 K_t, C_q^T], [C_q, 0]]`` stays
well conditioned for small steps. What differs between the systems it runs is only how the
equations are evaluated: a **kind** is an ``evaluate(q, qd, t, step, ctx, m, f, kt, ct, y, ch, jac,
vel)`` that writes the mass matrix, generalised forces, tangents, outputs, holonomic residuals,
constraint Jacobian and velocity residuals at a state into the arrays it is given. The loop is
compiled once per compiled kind (:func:`specialise`: the packed System of
:mod:`ddgsa.mbs.compiled`, the single-body kernel of :mod:`ddgsa.mbs.system`, the linear speed sweep
of :mod:`ddgsa.mbs.sweep` with its compiled inputs) and run as Python for a Python kind
(:func:`python_loop`: any System in :mod:`ddgsa.mbs.integrate.genalpha`), the Python run calling the
same compiled step helpers. A kind made of parts (the sweep's matrices plus a model's inputs) is a
copy of a template with the part bound to a global name (:func:`bind`), as the loop is bound to its kind.

Options of the loop (the kinds' choices, not separate loops): the predictor (the old acceleration,
or the acceleration extrapolated linearly from the last two steps: about one Newton iteration a
step on smooth forcing), the linear solve (general, or an in-place Cholesky for a symmetric
unconstrained iteration matrix: LAPACK's call overhead dominates at n = 12), and modified Newton
(the iteration matrix of the first iteration kept for the step, factorised once: :func:`lu_factor`).
"""

from __future__ import annotations

import hashlib
import os
import types
from collections.abc import Callable

import numpy as np
from numba import njit
from numpy.typing import NDArray

from ddgsa.errors import ModelError

Array = NDArray[np.float64]


def coefficients(rho_inf: float) -> tuple[float, float, float, float]:
    """``(alpha_m, alpha_f, gamma, beta)`` of generalised-alpha for spectral radius ``rho_inf``."""
    if not 0.0 <= rho_inf <= 1.0:
        raise ModelError(f"rho_inf = {rho_inf} not allowed; 0 <= rho_inf <= 1")
    am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
    af = rho_inf / (rho_inf + 1.0)
    gamma = 0.5 - am + af
    beta = 0.25 * (1.0 - am + af) ** 2
    return am, af, gamma, beta


def steps(t_span: float, dt: float, output_every: int, who: str) -> int:
    """The number of steps of ``dt`` [s] in ``t_span`` [s]; a :class:`ModelError` naming ``who``
    unless it is a positive whole number that ``output_every`` divides."""
    n_steps = int(round(t_span / dt))
    if n_steps < 1 or abs(n_steps * dt - t_span) > 1e-9 * max(1.0, abs(t_span)):
        raise ModelError(f"{who}: the time span {t_span} s is not a positive multiple of dt = {dt} s")
    if output_every < 1 or n_steps % output_every:
        raise ModelError(f"{who}: output_every = {output_every} must divide the {n_steps} steps")
    return n_steps


@njit(cache=True)
def solve_spd(a, b):  # pragma: no cover (compiled)
    """Solve ``a x = b`` for a symmetric positive-definite ``a`` by an in-place Cholesky
    factorisation (reads the lower triangle); falls back to a general solve if a pivot is not positive."""
    n = b.size
    low = np.zeros((n, n))
    for j in range(n):
        d = a[j, j]
        for k in range(j):
            d -= low[j, k] * low[j, k]
        if d <= 0.0:
            return np.linalg.solve(a, b)
        low[j, j] = np.sqrt(d)
        for i in range(j + 1, n):
            acc = a[i, j]
            for k in range(j):
                acc -= low[i, k] * low[j, k]
            low[i, j] = acc / low[j, j]
    y = np.empty(n)
    for i in range(n):
        acc = b[i]
        for k in range(i):
            acc -= low[i, k] * y[k]
        y[i] = acc / low[i, i]
    x = np.empty(n)
    for i in range(n - 1, -1, -1):
        acc = y[i]
        for k in range(i + 1, n):
            acc -= low[k, i] * x[k]
        x[i] = acc / low[i, i]
    return x


@njit(cache=True)
def lu_factor(a, lu, piv):  # pragma: no cover (compiled)
    """LU factorisation with partial pivoting of ``a`` (n, n) into ``lu`` (unit lower and upper
    triangles) and the row swaps ``piv`` (n,): what modified Newton keeps for the step. A zero pivot
    is left in place (:func:`lu_solve` then gives NaN, which the loop reports as a failed step)."""
    n = a.shape[0]
    lu[:, :] = a
    for k in range(n):
        p = k
        big = abs(lu[k, k])
        for i in range(k + 1, n):
            if abs(lu[i, k]) > big:
                p, big = i, abs(lu[i, k])
        piv[k] = p
        if p != k:
            for j in range(n):
                lu[k, j], lu[p, j] = lu[p, j], lu[k, j]
        if lu[k, k] == 0.0:
            continue
        inv = 1.0 / lu[k, k]
        pivot_row = lu[k, k + 1:]
        for i in range(k + 1, n):
            lik = lu[i, k] * inv
            lu[i, k] = lik
            row = lu[i, k + 1:]                            # row views: the update vectorises (2x at n = 42)
            for j in range(row.size):
                row[j] -= lik * pivot_row[j]


@njit(cache=True)
def lu_solve(lu, piv, b):  # pragma: no cover (compiled)
    """``x`` with ``a x = b`` from :func:`lu_factor`'s ``lu`` and ``piv``."""
    n = b.size
    x = b.copy()
    for k in range(n):
        p = piv[k]
        if p != k:
            x[k], x[p] = x[p], x[k]
    for i in range(n):
        acc = x[i]
        for k in range(i):
            acc -= lu[i, k] * x[k]
        x[i] = acc
    for i in range(n - 1, -1, -1):
        acc = x[i]
        for k in range(i + 1, n):
            acc -= lu[i, k] * x[k]
        x[i] = acc / lu[i, i] if lu[i, i] != 0.0 else np.nan
    return x


@njit(cache=True, inline="always")
def _predict(q, qd, acc, aux, acc_prev, acc_new, h, am, af, gamma, beta, extrapolate):  # pragma: no cover
    """The predictor of a step of ``h`` [s], in place: the new acceleration guessed (the old one, or
    extrapolated from the last two), positions and velocities from it."""
    for i in range(q.size):
        acc_new[i] = 2.0 * acc[i] - acc_prev[i] if extrapolate else acc[i]
        aux_new = (af * acc[i] - am * aux[i] + (1.0 - af) * acc_new[i]) / (1.0 - am)
        q[i] = q[i] + h * qd[i] + h * h * ((0.5 - beta) * aux[i] + beta * aux_new)
        qd[i] = qd[i] + h * ((1.0 - gamma) * aux[i] + gamma * aux_new)


@njit(cache=True, inline="always")
def _newton_rows(big, rhs, m, f, kt, ct, jac, lam, ch, vel, acc_new, bp, gp, h, build):  # pragma: no cover
    """Right-hand side (and, when ``build``, the iteration matrix) of one Newton iteration; returns
    the largest constraint residual in position units [m, rad]."""
    n, nc, nh = f.size, vel.size, ch.size
    bh2, gh = bp * h * h, gp * h
    for i in range(n):
        acc_i = 0.0
        for j in range(n):
            acc_i += m[i, j] * acc_new[j]
        r = acc_i - f[i]
        if nc > 0:
            s = 0.0
            for k in range(nc):
                s += jac[k, i] * lam[k]
            r += s
        rhs[i] = -r
    cmax = 0.0
    for r in range(nh):
        rhs[n + r] = -ch[r] / bh2
        cmax = max(cmax, abs(ch[r]))
    for r in range(nh, nc):
        rhs[n + r] = -vel[r] / gh
        cmax = max(cmax, abs(vel[r]) * bp * h / gp)
    if build:
        for i in range(n):
            for j in range(n):
                big[i, j] = m[i, j] + gh * ct[i, j] + bh2 * kt[i, j]
        for k in range(nc):
            for i in range(n):
                big[i, n + k] = jac[k, i]
                big[n + k, i] = jac[k, i]
    return cmax


@njit(cache=True, inline="always")
def _correct(delta, acc_new, q, qd, lam, bh2, gh):  # pragma: no cover (compiled)
    """Apply a Newton correction; returns its largest position change [m, rad]."""
    n = q.size
    largest = 0.0
    for i in range(n):
        acc_new[i] += delta[i]
        q[i] += bh2 * delta[i]
        qd[i] += gh * delta[i]
        largest = max(largest, abs(bh2 * delta[i]))
    for k in range(lam.size):
        lam[k] += delta[n + k]
    return largest


@njit(cache=True, inline="always")
def _advance(acc, aux, acc_prev, acc_new, am, af):  # pragma: no cover (compiled)
    """End of a step: the auxiliary acceleration updated, the accelerations shifted."""
    for i in range(acc.size):
        aux[i] = (af * acc[i] - am * aux[i] + (1.0 - af) * acc_new[i]) / (1.0 - am)
        acc_prev[i] = acc[i]
        acc[i] = acc_new[i]


@njit(cache=True, inline="always")
def _record(slot, q, qd, lam, y, ch, vel, q_out, qd_out, lam_out, y_out, drift):  # pragma: no cover
    """Keep a state, its outputs and its constraint drift (position, velocity) in row ``slot``."""
    q_out[slot], qd_out[slot], lam_out[slot], y_out[slot] = q, qd, lam, y
    if ch.size > 0:
        drift[slot, 0] = np.max(np.abs(ch))
    if vel.size > 0:
        drift[slot, 1] = np.max(np.abs(vel))


_evaluate: Callable | None = None
"""The kind's evaluation, bound in each copy of :func:`_loop` by :func:`bind`."""


def _loop(ctx, q0, qd0, acc0, lam0, t0, h, n_steps, output_every, am, af, gamma, beta, tol, max_iter, nh, n_y,
          extrapolate, symmetric, modified, reuse=0):  # pragma: no cover (compiled per kind)
    """The Newton loop (see the module); ``_evaluate`` is the kind's, bound by :func:`specialise` or
    :func:`python_loop`. ``reuse`` > 0 (with ``modified``): the factors are kept across steps, refreshed at
    a step's first iteration when the last step needed more than ``reuse`` iterations, and within a step
    at its ``2 reuse``-th (the converged states are the same to ``tol``; a slowly varying iteration matrix,
    as a speed sweep's, is then factorised a few times a run instead of once a step). Returns ``(q, qd, lam, y, drift (n_out, 2), status, total)``: ``status``
    the worst Newton count, or ``-step`` at the step that failed (the outputs then end before it),
    ``total`` the Newton iterations of all converged steps."""
    n, nc = q0.size, lam0.size
    q, qd, acc, lam = q0.copy(), qd0.copy(), acc0.copy(), lam0.copy()
    aux, acc_prev, acc_new = acc.copy(), acc.copy(), acc.copy()
    m, f, kt, ct = np.zeros((n, n)), np.zeros(n), np.zeros((n, n)), np.zeros((n, n))
    y, ch, jac, vel = np.zeros(n_y), np.zeros(nh), np.zeros((nc, n)), np.zeros(nc)
    n_out = n_steps // output_every + 1
    q_out, qd_out, lam_out = np.zeros((n_out, n)), np.zeros((n_out, n)), np.zeros((n_out, nc))
    y_out, drift = np.zeros((n_out, n_y)), np.zeros((n_out, 2))
    big, rhs = np.zeros((n + nc, n + nc)), np.zeros(n + nc)
    lu, piv = np.zeros((n + nc, n + nc)), np.zeros(n + nc, dtype=np.int64)
    bp = beta * (1.0 - af) / (1.0 - am)
    gp = gamma * (1.0 - af) / (1.0 - am)
    bh2, gh = bp * h * h, gp * h
    _evaluate(q, qd, t0, np.int64(0), ctx, m, f, kt, ct, y, ch, jac, vel)   # an int64 step, not a literal 0:
    # numba would compile the kind (and link the whole element tree) a second time for the literal
    _record(0, q, qd, lam, y, ch, vel, q_out, qd_out, lam_out, y_out, drift)
    slot, worst, total = 1, 0, 0
    stale = True                                          # no factors yet
    none = np.zeros((0, 0))
    for step in range(1, n_steps + 1):
        t = t0 + step * h
        _predict(q, qd, acc, aux, acc_prev, acc_new, h, am, af, gamma, beta, extrapolate)
        converged = False
        it = 0
        for it in range(max_iter):
            if reuse > 0:
                build = (it == 0 and stale) or it == 2 * reuse
                # the kind skips its tangents where the kept factors stand (empty kt, ct)
                _evaluate(q, qd, t, step, ctx, m, f, kt if build else none, ct if build else none, y, ch, jac, vel)
            else:
                build = it == 0 or not modified
                _evaluate(q, qd, t, step, ctx, m, f, kt, ct, y, ch, jac, vel)
            cmax = _newton_rows(big, rhs, m, f, kt, ct, jac, lam, ch, vel, acc_new, bp, gp, h, build)
            if modified:                                  # the step's factors kept
                if build:
                    lu_factor(big, lu, piv)
                delta = lu_solve(lu, piv, rhs)
            else:
                delta = solve_spd(big, rhs) if symmetric else np.linalg.solve(big, rhs)
            if _correct(delta, acc_new, q, qd, lam, bh2, gh) < tol and cmax < tol:
                converged = True
                break
        if not converged or not np.all(np.isfinite(q)):
            return q_out[:slot], qd_out[:slot], lam_out[:slot], y_out[:slot], drift[:slot], -step, total
        total += it + 1
        worst = max(worst, it + 1)
        stale = it + 1 > reuse
        _advance(acc, aux, acc_prev, acc_new, am, af)
        if step % output_every == 0:
            if n_y > 0 or nc > 0:                         # outputs and drift at the converged state
                _evaluate(q, qd, t, step, ctx, m, f, kt, ct, y, ch, jac, vel)
            _record(slot, q, qd, lam, y, ch, vel, q_out, qd_out, lam_out, y_out, drift)
            slot += 1
    return q_out, qd_out, lam_out, y_out, drift, worst, total


def bind(function: Callable, tag: str, template: Callable, name: str = "_evaluate") -> types.FunctionType:
    """A copy of ``template`` whose global ``name`` is ``function`` (its own name, ``template``'s with
    ``tag``, so that numba caches each copy apart): how a loop gets its kind, and a kind its parts."""
    scope = dict(template.__globals__)
    scope[name] = function
    fn = types.FunctionType(template.__code__, scope, template.__name__, template.__defaults__, template.__closure__)
    fn.__qualname__ = f"{template.__name__}_{tag}"
    fn.__module__ = template.__module__
    return fn


def stamp(*functions: Callable, folders: tuple[str, ...] = ()) -> str:
    """A short hash of the paths, modification times and sizes of the source files of ``functions``
    (plain or ``njit``) and of the ``.py`` files in ``folders``, with the functions' qualified names:
    a tag that changes when any of them is edited.

    numba checks a cached function against its own source file only; a copy made by :func:`bind`
    that calls functions of other files carries this stamp in its name (give the folders of the
    files its callees live in), so that editing one compiles the copy afresh instead of loading a
    stale one.
    """
    files = {getattr(f, "py_func", f).__code__.co_filename for f in functions}
    files |= {os.path.join(d, name) for d in folders for name in os.listdir(d) if name.endswith(".py")}
    names = sorted(f"{getattr(f, '__module__', '')}.{getattr(f, '__qualname__', '')}" for f in functions)
    stamps = "|".join(f"{f}:{os.stat(f).st_mtime_ns}:{os.stat(f).st_size}" for f in sorted(files))
    return hashlib.sha1((stamps + "|" + "|".join(names)).encode()).hexdigest()[:10]


def specialise(evaluate: Callable, tag: str, loop: Callable | None = None) -> Callable:
    """The loop compiled (and cached) for a compiled kind ``evaluate`` (an ``njit`` function);
    ``loop``: another loop over kinds (:func:`ddgsa.mbs.statics._newton`), default :func:`_loop`.
    The copy's name carries the :func:`stamp` of the loop's and the kind's files."""
    loop = _loop if loop is None else loop
    return njit(cache=True)(bind(evaluate, f"{tag}_{stamp(loop, evaluate)}", loop))


def python_loop(evaluate: Callable, loop: Callable | None = None) -> Callable:
    """The loop (default :func:`_loop`) run as Python for a Python kind ``evaluate`` (its step
    helpers stay compiled)."""
    return bind(evaluate, "python", _loop if loop is None else loop)
