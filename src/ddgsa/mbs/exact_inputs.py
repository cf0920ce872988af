"""Exact-discretisation runs whose inputs come from a chosen set of elements (a faster ``exact.simulate``).

:func:`ddgsa.mbs.integrate.exact.simulate` evaluates the whole system's generalised forces at
every output sample along the operating trajectory ``q_op(t) = q0 + qd0 (t - t0)`` -- general,
and one full nonlinear evaluation per sample. Most elements of a steadily spinning rotor give
the same force all along that trajectory (isotropic bearings, supports, springs on the axis);
only a few change with time or with the spin angle (applied loads, torque ripple, an eccentric
mass, a coupling with a turning anisotropy). :func:`simulate` evaluates only the bodies' own
terms (inertia, gravity seen by turning elastic coordinates) and the elements the caller lists,
and integrates the same linearised system with the same exact discretisation
(:func:`ddgsa.mbs.integrate.exact.state_matrices`, :func:`ddgsa.mbs.linear.lti_response`).
The caller is responsible for the claim that the unlisted elements are invariant along
``q_op(t)``; :func:`check_invariant` measures it at a few samples.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import expm

from ddgsa.errors import ModelError
from ddgsa.mbs.assembly import System
from ddgsa.mbs.elements import Element
from ddgsa.mbs.integrate.exact import state_matrices
from ddgsa.mbs.linear import lti_response
from ddgsa.mbs.modal import ConstrainedLinearisation

Array = NDArray[np.float64]


def generalised_force(system: System, q: Array, qd: Array, t: float, elements: Sequence[Element]) -> Array:
    """Generalised force (n,) of the listed elements alone at ``(q, qd, t)``."""
    f = np.zeros(system.n)
    for el in elements:
        states = [system.marker_state(mk, q, qd, t) for mk in el.markers]
        w = el.wrench(t, states)[0]
        for s, wi in zip(states, w):
            f += s.jac.T @ wi
    return f


def _forces(system: System, q: Array, qd: Array, t: float, elements: Sequence[Element]) -> Array:
    """Bodies' terms plus the listed elements' generalised forces at ``(q, qd, t)``."""
    f = generalised_force(system, q, qd, t, elements)
    for b in system.bodies:
        sl = system.slices[id(b)]
        f[sl] += b.terms(q[sl], qd[sl], system.gravity)[1]
    return f


def inputs(system: System, lin: ConstrainedLinearisation, times: Array, elements: Sequence[Element]) -> Array:
    """``N^T (Q_sel(q_op(t), qd0, t) - Q_sel(q0, qd0, t0))`` at ``times`` (n_t, n_z)."""
    ref = _forces(system, lin.q0, lin.qd0, lin.t0, elements)
    out = np.empty((times.size, lin.basis.shape[1]))
    for i, t in enumerate(times):
        q = lin.q0 + (t - lin.t0) * lin.qd0
        out[i] = lin.basis.T @ (_forces(system, q, lin.qd0, t, elements) - ref)
    return out


def check_invariant(system: System, lin: ConstrainedLinearisation, elements: Sequence[Element], times: Array) -> float:
    """Largest change of the *unlisted* elements' generalised forces along ``q_op(t)`` at ``times`` [N or N m]."""
    rest = [e for e in system.elements if all(e is not x for x in elements)]

    def q_rest(t: float) -> Array:
        q = lin.q0 + (t - lin.t0) * lin.qd0
        return _forces(system, q, lin.qd0, t, rest) - _forces(system, q, lin.qd0, t, [])

    ref = q_rest(lin.t0)
    return float(max(np.max(np.abs(q_rest(t) - ref)) for t in times))


def simulate(system: System, lin: ConstrainedLinearisation, t_end: float, dt: float,
             elements: Sequence[Element], start: str | float = "static") -> tuple[Array, Array, Array]:
    """Exact response of the linearised system to the listed elements, output every ``dt`` [s].

    Parameters
    ----------
    start : 'static', 'operating' or float
        Initial state: the quasi-static deflection under the first inputs, the operating state
        itself, or -- a period ``T`` [s] -- the state from which the response to the inputs over
        ``[t0, t0 + T]`` is periodic (``x0 = (I - e^{A T})^+ x_T(0)``, least squares for the rigid
        directions): the steady state of a rotor under inputs that repeat every revolution, with
        no start-up transient to wait for.

    Returns
    -------
    t : (n_t,) times [s]; ``q``, ``qd`` : (n_t, n) coordinates and velocities.
    """
    if not (start in ("static", "operating") or (isinstance(start, float) and start > 0)):
        raise ModelError(f"start {start!r} not allowed; use 'static', 'operating' or a period > 0 [s]")
    n_out = int(round((t_end - lin.t0) / dt)) + 1
    times = lin.t0 + dt * np.arange(n_out)
    dq = inputs(system, lin, times, elements)
    a, bw = state_matrices(lin)
    nz = lin.m.shape[0]
    x0 = np.zeros(2 * nz)
    if start == "static":
        x0[:nz] = np.linalg.lstsq(lin.k, dq[0] + lin.r0, rcond=None)[0]
    elif isinstance(start, float):
        k = max(8, int(np.ceil(start / dt)))
        h = start / k
        tp = lin.t0 + h * np.arange(k + 1)
        xt = lti_response(a, bw, np.column_stack([inputs(system, lin, tp, elements), np.ones(k + 1)]), h, x0)[-1]
        x0 = np.linalg.lstsq(np.eye(2 * nz) - expm(a * start), xt, rcond=None)[0]
    x = lti_response(a, bw, np.column_stack([dq, np.ones(n_out)]), dt, x0)
    q = lin.q0 + np.outer(times - lin.t0, lin.qd0) + x[:, :nz] @ lin.basis.T
    qd = lin.qd0 + x[:, nz:] @ lin.basis.T
    return times, q, qd
