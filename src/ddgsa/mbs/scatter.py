"""The assembly's mapping, written once (eq. 2.5): a part's wrench, tangents and constraint rows
over its markers' motions mapped onto the generalised coordinates, ``J^T W``, ``J^T K J`` and
``C_x J``, through the markers' Jacobians ``mj`` (n_markers, 6, n) and the coordinate range
``lohi`` (n_markers, 2) each one moves.

Compiled; the packed system's assembly (:func:`ddgsa.mbs.compiled._terms`) calls it with every
marker of the system, :meth:`System.terms <ddgsa.mbs.assembly.System.terms>` and the Python parts
of :class:`~ddgsa.mbs.compiled.HybridTerms` with the markers of one part (:func:`add_wrench`,
:func:`constraint_rows_over`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numba import njit
from numpy.typing import NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.bodies import MarkerState

Array = NDArray[np.float64]
_NONE = np.zeros((0, 0))


@njit(cache=True)
def add_jtw(f, mj, lohi, m, w, sign):  # pragma: no cover (compiled)
    """``f += sign J_m^T w``: a wrench (6,) at marker ``m`` onto the coordinates."""
    for c in range(lohi[m, 0], lohi[m, 1]):
        acc = 0.0
        for k in range(6):
            acc += mj[m, k, c] * w[k]
        f[c] += sign * acc


@njit(cache=True)
def add_jtkj(kt, mj, lohi, a, b, k6, sign):  # pragma: no cover (compiled)
    """``kt += sign J_a^T k6 J_b``."""
    lo_b, hi_b = lohi[b, 0], lohi[b, 1]
    lo_a, hi_a = lohi[a, 0], lohi[a, 1]
    if hi_a == lo_a or hi_b == lo_b:
        return
    tmp = np.zeros((6, hi_b - lo_b))
    for r in range(6):
        for k in range(6):
            kv = k6[r, k]
            if kv != 0.0:
                for c in range(lo_b, hi_b):
                    tmp[r, c - lo_b] += kv * mj[b, k, c]
    for r in range(lo_a, hi_a):
        for k in range(6):
            jv = mj[a, k, r]
            if jv != 0.0:
                for c in range(lo_b, hi_b):
                    kt[r, c] += sign * jv * tmp[k, c - lo_b]


@njit(cache=True)
def add_blocks(kt, mj, lohi, i, j, t12):  # pragma: no cover (compiled)
    """``kt += J^T t12 J`` over the markers ``[i, j]``."""
    add_jtkj(kt, mj, lohi, i, i, t12[0:6, 0:6].copy(), 1.0)
    add_jtkj(kt, mj, lohi, i, j, t12[0:6, 6:12].copy(), 1.0)
    add_jtkj(kt, mj, lohi, j, i, t12[6:12, 0:6].copy(), 1.0)
    add_jtkj(kt, mj, lohi, j, j, t12[6:12, 6:12].copy(), 1.0)


@njit(cache=True)
def add_tangent(kt, mj, lohi, i, j, t):  # pragma: no cover (compiled)
    """``kt += J^T t J`` over the element's markers ``[i]`` (t 6 x 6) or ``[i, j]`` (t 12 x 12)."""
    if t.shape[0] == 6:
        add_jtkj(kt, mj, lohi, i, i, t, 1.0)
    else:
        add_blocks(kt, mj, lohi, i, j, t)


@njit(cache=True)
def add_rows(jac, mj, lohi, m, row, jx, slot):  # pragma: no cover (compiled)
    """``jac[row:row + n_eq] += jx[:, slot] J_m``: a constraint's Jacobian over the motions of its marker
    in ``slot`` (columns ``6 slot`` to ``6 slot + 6`` of ``jx``) mapped onto the coordinates of marker ``m``."""
    for r in range(jx.shape[0]):
        for col in range(lohi[m, 0], lohi[m, 1]):
            for x in range(3):
                jac[row + r, col] += jx[r, 6 * slot + x] * mj[m, x, col] + jx[r, 6 * slot + 3 + x] * mj[m, 3 + x, col]


@njit(cache=True)
def add_element(f, kt, ct, mj, lohi, i, j, wr, kr, cr, tangents):  # pragma: no cover (compiled)
    """An element's wrench ``wr`` (n_m, 6) at its markers ``i`` and ``j`` (``j`` unused for one marker) onto
    ``f``, and its stiffness and damping tangents ``kr``, ``cr`` (6 x 6 or 12 x 12; (0, 0): none) onto
    ``kt``, ``ct`` where ``tangents``."""
    add_jtw(f, mj, lohi, i, wr[0], 1.0)
    if wr.shape[0] > 1:
        add_jtw(f, mj, lohi, j, wr[1], 1.0)
    if tangents and kr.shape[0] > 0:
        add_tangent(kt, mj, lohi, i, j, kr)
    if tangents and cr.shape[0] > 0:
        add_tangent(ct, mj, lohi, i, j, cr)


def _one_part(states: Sequence[MarkerState]) -> tuple[Array, NDArray[np.int64]]:
    """``mj`` and ``lohi`` of one part's markers (dense Jacobians: every coordinate)."""
    mj = np.ascontiguousarray(np.stack([s.jac for s in states]), dtype=float)
    lohi = np.zeros((len(states), 2), np.int64)
    lohi[:, 1] = mj.shape[2]
    return mj, lohi


def add_wrench(f: Array, kt: Array, ct: Array, states: Sequence[MarkerState], w: Array, k_el: Array | None,
               c_el: Array | None) -> None:
    """:func:`add_element` for an element evaluated in Python at its markers' ``states`` (one or two)."""
    if len(states) > 2:
        raise ModelError(f"an element acts on one or two markers, got {len(states)}")
    mj, lohi = _one_part(states)
    add_element(f, kt, ct, mj, lohi, 0, len(states) - 1, np.ascontiguousarray(w, dtype=float).reshape(-1, 6),
                _NONE if k_el is None else np.ascontiguousarray(k_el, dtype=float),
                _NONE if c_el is None else np.ascontiguousarray(c_el, dtype=float), True)


def constraint_rows_over(jx: Array, states: Sequence[MarkerState]) -> Array:
    """A constraint's Jacobian (n_eq, 6 n_markers) over its markers' motions mapped onto the coordinates
    (n_eq, n) (:func:`add_rows`)."""
    mj, lohi = _one_part(states)
    jx = np.ascontiguousarray(jx, dtype=float)
    out = np.zeros((jx.shape[0], mj.shape[2]))
    for slot in range(len(states)):
        add_rows(out, mj, lohi, slot, 0, jx, slot)
    return out
