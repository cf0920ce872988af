"""The compiled nonlinear path: a System packed into arrays, evaluated and integrated in numba.

:func:`pack` turns a :class:`~ddgsa.mbs.assembly.System` into flat arrays; the compiled
:func:`_terms` evaluates them by calling the same compiled functions the Python objects call
(the connectors' :func:`~ddgsa.mbs.elements.connector_wrench`, the torque law's
:func:`~ddgsa.mbs.elements.axial_torque_wrench`, the constraints' residuals and Jacobians in
:mod:`ddgsa.mbs.constraints`, the rotation helpers of :mod:`ddgsa.mbs.ffr`, the inputs'
:func:`~ddgsa.mbs.series.interpolate`) and maps their wrenches and Jacobians onto the coordinates,
and :func:`gen_alpha` runs the one generalised-alpha loop (:mod:`ddgsa.mbs.alpha`) compiled on it. What packs:

- bodies: :class:`RigidBody`, :class:`FlexibleBody`; :class:`Ground` and
  :class:`PrescribedBody.translating` (sampled translation);
- elements: :class:`SpringDamper3`, :class:`Bushing6`, :class:`TorsionalSpring` (with a fixed ``offset``),
  :class:`AppliedLoad`, :class:`EccentricMass`, and :class:`TorqueLaw` in its :meth:`~TorqueLaw.linear`,
  :meth:`~TorqueLaw.power` and :meth:`~TorqueLaw.machine` forms;
- constraints: :class:`Spherical`, :class:`TransverseBearing`, :class:`GearContact`,
  :class:`PrescribedSpeed` (constant speed or a :class:`Series`), :class:`Lock`.

Anything else (a Python torque law, a general trajectory, a new element class) raises a
:class:`~ddgsa.errors.ModelError` naming the part; the Python path runs it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit
from numpy.typing import NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.alpha import specialise
from ddgsa.mbs.assembly import System, Terms
from ddgsa.mbs.bodies import FlexibleBody, MarkerState, PrescribedBody
from ddgsa.mbs.constraints import PrescribedSpeed, constraint_rows
from ddgsa.mbs.derivatives import central_difference
from ddgsa.mbs.elements import TorqueLaw, element_wrench
from ddgsa.mbs.first_order import FirstOrderStates
from ddgsa.mbs.ffr import body_terms_into, body_terms_inv, g_bar, mm, mv, rodrigues, rotation
from ddgsa.mbs.ffr import cross as _cross
from ddgsa.mbs.scatter import add_element, add_rows, add_wrench
from ddgsa.mbs.series import Series, interpolate

Array = NDArray[np.float64]



@dataclass(frozen=True)
class Packed:
    """A system as arrays for the compiled kernels (``arrays`` in kernel order)."""

    n: int
    n_holonomic: int
    n_constraints: int
    n_elements: int
    arrays: tuple


class _SeriesTable:
    """Collects :class:`Series` into one flat coefficient array."""

    def __init__(self) -> None:
        self.coef: list[Array] = []
        self.meta: list[tuple[int, int, int, float, float]] = []     # offset, n, k, t0, dt
        self.size = 0

    def add(self, s: Series) -> int:
        flat = np.ascontiguousarray(s.coef).ravel()
        self.meta.append((self.size, s.n, s.coef.shape[2], s.t0, s.dt))
        self.coef.append(flat)
        self.size += flat.size
        return len(self.meta) - 1

    def arrays(self) -> tuple[Array, ...]:
        coef = np.concatenate(self.coef) if self.coef else np.zeros(1)
        meta = np.array(self.meta, dtype=float).reshape(-1, 5)
        return coef, meta[:, 0].astype(np.int64), meta[:, 1].astype(np.int64), meta[:, 2].astype(np.int64), \
            meta[:, 3].copy(), meta[:, 4].copy()


def _no_compiled_form(part: object, what: str) -> str:
    """Why ``part`` does not pack (the refusal :func:`pack` raises)."""
    if isinstance(part, TorqueLaw):
        return f"torque law {part.name!r} is a Python function: no compiled form (use TorqueLaw.linear, .power or .machine)"
    if isinstance(part, PrescribedSpeed):
        return f"prescribed speed {part.name!r} is a Python function: no compiled form (give a constant or a Series)"
    return f"{what} {part.name!r} ({type(part).__name__}) has no compiled form"


def pack(system: System, elements: list | None = None) -> Packed:
    """Arrays of ``system`` for the compiled kernels; raises :class:`ModelError` for parts it cannot run.

    ``elements``: the elements to pack (default: all of the system's); :class:`HybridTerms` packs
    those with a compiled form and evaluates the rest in Python."""
    n = system.n
    nb = len(system.bodies)
    series = _SeriesTable()
    # bodies
    b_off, b_nf, b_mass = np.zeros(nb, np.int64), np.zeros(nb, np.int64), np.zeros(nb)
    b_first0, b_k0 = np.zeros((nb, 3)), np.zeros((nb, 3, 3))
    o1, o2 = np.zeros(nb, np.int64), np.zeros(nb, np.int64)
    flat: dict[str, list[Array]] = {k: [] for k in ("ssum", "k1", "e", "f4", "h0", "h1", "kff", "cff")}
    c1 = c2 = 0
    for b_i, b in enumerate(system.bodies):
        if isinstance(b, FirstOrderStates):       # unit-mass coordinates whose rates are the states: b_nf = -n
            b_off[b_i], b_nf[b_i] = system.slices[id(b)].start, -b.n_coords
            o1[b_i], o2[b_i] = c1, c2
            continue
        if not isinstance(b, FlexibleBody):
            raise ModelError(f"body {b.name!r} ({type(b).__name__}) has no compiled form")
        inv = b.invariants
        nf = b.n_elastic
        b_off[b_i], b_nf[b_i], b_mass[b_i] = system.slices[id(b)].start, nf, inv.mass
        b_first0[b_i], b_k0[b_i] = inv.first0, inv.k0
        o1[b_i], o2[b_i] = c1, c2
        c1, c2 = c1 + nf, c2 + nf * nf
        for key, arr in (("ssum", inv.s_sum), ("k1", inv.k1), ("e", inv.e), ("f4", inv.f), ("h0", inv.h0),
                         ("h1", inv.h1), ("kff", b.kff), ("cff", b.cff)):
            flat[key].append(np.ascontiguousarray(arr, dtype=float).ravel())
    fl = {k: (np.concatenate(v) if v and sum(a.size for a in v) else np.zeros(1)) for k, v in flat.items()}
    body_index = {id(b): i for i, b in enumerate(system.bodies)}
    # prescribed bodies and markers
    prescribed: list[PrescribedBody] = []
    nm = len(system.markers)
    mk_body, mk_u0 = np.zeros(nm, np.int64), np.zeros((nm, 3))
    mk_so = np.zeros(nm, np.int64)
    mk_s, mk_sr = [], []
    off = 0
    for m_i, mk in enumerate(system.markers):
        body = mk.body
        if id(body) in body_index:
            mk_body[m_i] = body_index[id(body)]
        else:
            if not isinstance(body, PrescribedBody) or (body.fixed_pose is None and body.series is None):
                raise ModelError(f"body {body.name!r} moves along a Python trajectory: no compiled form (use Ground "
                                 "or PrescribedBody.translating)")
            if body not in prescribed:
                prescribed.append(body)
            mk_body[m_i] = -1 - prescribed.index(body)
        mk_u0[m_i] = mk.position
        mk_so[m_i] = off
        mk_s.append(np.ascontiguousarray(mk.shapes, dtype=float).ravel())
        mk_sr.append(np.ascontiguousarray(mk.rotation_shapes, dtype=float).ravel())
        off += mk.shapes.size
    mk_s_a = np.concatenate(mk_s) if off else np.zeros(1)
    mk_sr_a = np.concatenate(mk_sr) if off else np.zeros(1)
    npb = max(len(prescribed), 1)
    pb_r0, pb_a0, pb_ser = np.zeros((npb, 3)), np.tile(np.eye(3), (npb, 1, 1)), -np.ones(npb, np.int64)
    for p_i, body in enumerate(prescribed):
        if body.fixed_pose is not None:
            pb_r0[p_i], pb_a0[p_i] = body.fixed_pose
        else:
            pb_ser[p_i] = series.add(body.series)
    midx = {id(mk): i for i, mk in enumerate(system.markers)}
    # elements and constraints (holonomic first): their compiled forms, parameters in one flat array each
    chosen = system.elements if elements is None else list(elements)
    cons = [*system.holonomic, *system.nonholonomic]
    parts = []
    for part in [*chosen, *cons]:
        form = part.compiled()
        if form is None:
            raise ModelError(_no_compiled_form(part, "element" if part in chosen else "constraint"))
        parts.append(form)
    nel, ncs = len(chosen), len(cons)
    kind, marker = np.zeros(nel + ncs, np.int64), -np.ones((nel + ncs, 3), np.int64)
    ser, offsets = -np.ones(nel + ncs, np.int64), np.zeros(nel + ncs + 1, np.int64)
    for p_i, (part, form) in enumerate(zip([*chosen, *cons], parts)):
        kind[p_i] = form.kind
        for k, mk in enumerate(part.markers):
            marker[p_i, k] = midx[id(mk)]
        if form.series is not None:
            ser[p_i] = series.add(form.series)
        offsets[p_i + 1] = offsets[p_i] + form.parameters.size
    par = np.concatenate([np.zeros(1), *(form.parameters for form in parts)])[1:].copy()
    cs_row = np.cumsum([0] + [c.n_eq for c in cons])[:-1].astype(np.int64) if cons else np.zeros(0, np.int64)
    cs_neq = np.array([c.n_eq for c in cons], dtype=np.int64)
    arrays = (b_off, b_nf, b_mass, b_first0, b_k0, o1, o2, fl["ssum"], fl["k1"], fl["e"], fl["f4"], fl["h0"],
              fl["h1"], fl["kff"], fl["cff"], mk_body, mk_u0, mk_so, mk_s_a, mk_sr_a, pb_r0, pb_a0, pb_ser,
              *series.arrays(), np.int64(nel), kind, marker, ser, offsets, par, cs_row, cs_neq,
              np.int64(system.n_holonomic),
              np.asarray(system.gravity, dtype=float))
    return Packed(n, system.n_holonomic, system.n_constraints, nel, arrays)


# ---------------------------------------------------------------------------------------------------
# compiled kernels


@njit(cache=True)
def _series(coef, s_off, s_n, s_k, s_t0, s_dt, idx, t, deriv):  # pragma: no cover (compiled)
    """Value (or time derivative) of series ``idx`` of the table at ``t`` (:func:`ddgsa.mbs.series.interpolate`)."""
    return interpolate(coef, s_off[idx], s_n[idx], s_k[idx], s_t0[idx], s_dt[idx], t, deriv)


@njit(cache=True)
def _markers(q, qd, t, P):  # pragma: no cover (compiled)
    """Position, orientation, velocity, angular velocity, Jacobian and column range of every marker."""
    return _marker_table(q, qd, t, P, np.ones(P[15].size, np.bool_))


@njit(cache=True)
def _marker_table(q, qd, t, P, keep):  # pragma: no cover (compiled)
    """:func:`_markers` of the markers where ``keep`` (n_markers,) is set; the other rows are left zero."""
    (b_off, b_nf, b_mass, b_first0, b_k0, o1, o2, ssum, k1, e, f4, h0, h1, kff, cff, mk_body, mk_u0, mk_so,
     mk_s, mk_sr, pb_r0, pb_a0, pb_ser, coef, s_off, s_n, s_k, s_t0, s_dt) = P[:29]
    n = q.size
    nm = mk_body.size
    mr, ma = np.zeros((nm, 3)), np.zeros((nm, 3, 3))
    mvel, mw = np.zeros((nm, 3)), np.zeros((nm, 3))
    mj = np.zeros((nm, 6, n))
    lohi = np.zeros((nm, 2), np.int64)
    for m in range(nm):
        if not keep[m]:
            continue
        b = mk_body[m]
        u0 = mk_u0[m]
        if b < 0:
            p = -1 - b
            if pb_ser[p] >= 0:
                r0 = _series(coef, s_off, s_n, s_k, s_t0, s_dt, pb_ser[p], t, False)
                v0 = _series(coef, s_off, s_n, s_k, s_t0, s_dt, pb_ser[p], t, True)
                a = np.eye(3)
            else:
                r0, v0, a = pb_r0[p].copy(), np.zeros(3), pb_a0[p].copy()
            arm = mv(a, u0)
            mr[m] = r0 + arm
            ma[m] = a
            mvel[m] = v0
            continue
        lo, nf = b_off[b], b_nf[b]
        if nf < 0:                               # first-order states: v, w are the rates of its -nf coordinates
            lohi[m, 0], lohi[m, 1] = lo, lo - nf
            ma[m] = np.eye(3)
            for k in range(-nf):
                mj[m, k, lo + k] = 1.0
                if k < 3:
                    mvel[m, k] = qd[lo + k]
                else:
                    mw[m, k - 3] = qd[lo + k]
            continue
        ang = q[lo + 3:lo + 6]
        a = rotation(ang)
        ag = mm(a, g_bar(ang))
        so = mk_so[m]
        s = mk_s[so:so + 3 * nf].reshape(3, nf) if nf > 0 else np.zeros((3, 0))
        sr = mk_sr[so:so + 3 * nf].reshape(3, nf) if nf > 0 else np.zeros((3, 0))
        qf = q[lo + 6:lo + 6 + nf]
        ub = u0.copy()
        for i in range(3):
            for k in range(nf):
                ub[i] += s[i, k] * qf[k]
        u = mv(a, ub)
        hi = lo + 6 + nf
        lohi[m, 0], lohi[m, 1] = lo, hi
        for i in range(3):
            mj[m, i, lo + i] = 1.0
        # -skew(u) @ ag
        for k in range(3):
            c = _cross(ag[:, k], u)
            for i in range(3):
                mj[m, i, lo + 3 + k] = c[i]
                mj[m, 3 + i, lo + 3 + k] = ag[i, k]
        if nf > 0:
            as_ = mm(a, s)
            asr = mm(a, sr)
            for i in range(3):
                for k in range(nf):
                    mj[m, i, lo + 6 + k] = as_[i, k]
                    mj[m, 3 + i, lo + 6 + k] = asr[i, k]
            th = np.zeros(3)
            for i in range(3):
                for k in range(nf):
                    th[i] += sr[i, k] * qf[k]
            ma[m] = mm(a, rodrigues(th))
        else:
            ma[m] = a
        mr[m] = q[lo:lo + 3] + u
        for i in range(3):
            acc_v, acc_w = 0.0, 0.0
            for c in range(lo, hi):
                acc_v += mj[m, i, c] * qd[c]
                acc_w += mj[m, 3 + i, c] * qd[c]
            mvel[m, i], mw[m, i] = acc_v, acc_w
    return mr, ma, mvel, mw, mj, lohi


@njit(cache=True)
def _inputs(coef, s_off, s_n, s_k, s_t0, s_dt, idx, t):  # pragma: no cover (compiled)
    """The value at ``t`` of series ``idx`` of the table, empty for ``idx < 0`` (a part without input)."""
    if idx < 0:
        return np.zeros(0)
    return _series(coef, s_off, s_n, s_k, s_t0, s_dt, idx, t, False)


@njit(cache=True)
def _terms(q, qd, t, P, tangents, constraints, only):  # pragma: no cover (compiled)
    """``M, Q, K_t, C_t, element outputs (n_el, 6), C_h, jac (n_c, n), V`` at ``(q, qd, t)``; without
    ``tangents`` ``K_t`` and ``C_t`` are (0, 0) (their scatter skipped), without ``constraints``
    ``C_h``, ``jac`` and ``V`` are empty. ``only`` (an integer): -1 for the whole system; a body's index for
    the part of the terms that moves with that body's coordinates alone -- its own block and forces and the
    elements with a marker on it (the other elements' outputs zero; no constraints), from the markers of those
    elements alone (:func:`stepped_residuals`).

    This function, with every element law under it, is most of the kernel's first-run compilation,
    and numba links a full copy of it into every compiled function that calls it. So it is called
    directly (no compiled wrappers around it), by few compiled functions, and with run-time flags
    (``np.bool_`` in compiled code, plain ``bool`` from Python): a *literal* ``True`` or ``False``
    would compile it once per value."""
    (b_off, b_nf, b_mass, b_first0, b_k0, o1, o2, ssum, k1, e, f4, h0, h1, kff, cff, mk_body, mk_u0, mk_so,
     mk_s, mk_sr, pb_r0, pb_a0, pb_ser, coef, s_off, s_n, s_k, s_t0, s_dt, nel, kind, marker, ser, offsets, par,
     cs_row, cs_neq, nh, gravity) = P
    n = q.size
    m_mat, f = np.zeros((n, n)), np.zeros(n)
    nt = n if tangents else 0                    # no tangents: (0, 0), nothing to clear
    kt, ct = np.zeros((nt, nt)), np.zeros((nt, nt))
    for b in range(b_off.size):
        if only >= 0 and b != only:
            continue
        lo, nf = b_off[b], b_nf[b]
        if nf < 0:                               # first-order states: unit mass, no force of their own
            for k in range(-nf):
                m_mat[lo + k, lo + k] = 1.0
            continue
        hi = lo + 6 + nf
        a1, a2 = o1[b], o2[b]
        mb, fb = body_terms_inv(q[lo:hi].copy(), qd[lo:hi].copy(), b_mass[b], b_first0[b],
                                ssum[3 * a1:3 * (a1 + nf)].reshape(3, nf), b_k0[b],
                                k1[9 * a1:9 * (a1 + nf)].reshape(3, 3, nf), e[9 * a1:9 * (a1 + nf)].reshape(3, 3, nf),
                                f4[9 * a2:9 * (a2 + nf * nf)].reshape(3, 3, nf, nf),
                                h0[3 * a1:3 * (a1 + nf)].reshape(3, nf), h1[3 * a2:3 * (a2 + nf * nf)].reshape(nf, 3, nf),
                                gravity)
        m_mat[lo:hi, lo:hi] = mb
        f[lo:hi] += fb
        if nf > 0:
            kb = kff[a2:a2 + nf * nf].reshape(nf, nf)
            cb = cff[a2:a2 + nf * nf].reshape(nf, nf)
            f[lo + 6:hi] -= mv(kb, q[lo + 6:hi]) + mv(cb, qd[lo + 6:hi])
            if tangents:
                kt[lo + 6:hi, lo + 6:hi] += kb
                ct[lo + 6:hi, lo + 6:hi] += cb
    on = np.ones(nel, np.bool_)                  # the elements evaluated, and their markers
    keep = np.ones(mk_body.size, np.bool_)
    if only >= 0:
        keep[:] = False
        for el in range(nel):
            i, j = marker[el, 0], marker[el, 1]
            on[el] = (i >= 0 and mk_body[i] == only) or (j >= 0 and mk_body[j] == only)
            if on[el]:
                keep[i] = True
                if j >= 0:
                    keep[j] = True
    mr, ma, mvel, mw, mj, lohi = _marker_table(q, qd, t, P, keep)
    out = np.zeros((nel, 6))
    for el in range(nel):
        if not on[el]:
            continue
        i, j = marker[el, 0], marker[el, 1]
        wr, kr, cr = element_wrench(kind[el], mr, ma, mvel, mw, i, j, par[offsets[el]:offsets[el + 1]],
                                    _inputs(coef, s_off, s_n, s_k, s_t0, s_dt, ser[el], t), t, tangents)
        add_element(f, kt, ct, mj, lohi, i, j, wr, kr, cr, tangents)
        out[el] = wr[0]
    if not constraints or only >= 0:
        return m_mat, f, kt, ct, out, np.zeros(0), np.zeros((0, n)), np.zeros(0)
    ch, jac, vel = _constraint_terms(n, t, P, mr, ma, mvel, mw, mj, lohi)
    return m_mat, f, kt, ct, out, ch, jac, vel


@njit(cache=True)
def _constraint_terms(n, t, P, mr, ma, mvel, mw, mj, lohi):  # pragma: no cover (compiled)
    """``C_h, jac (n_c, n), V`` of the packed constraints from the markers' states (:func:`_markers`)."""
    (b_off, b_nf, b_mass, b_first0, b_k0, o1, o2, ssum, k1, e, f4, h0, h1, kff, cff, mk_body, mk_u0, mk_so,
     mk_s, mk_sr, pb_r0, pb_a0, pb_ser, coef, s_off, s_n, s_k, s_t0, s_dt, nel, kind, marker, ser, offsets, par,
     cs_row, cs_neq, nh, gravity) = P
    ncs = cs_row.size
    nc = 0
    for c in range(ncs):
        nc += cs_neq[c]
    ch = np.zeros(nh)
    jac = np.zeros((nc, n))
    vel = np.zeros(nc)
    for c in range(ncs):
        p, row = nel + c, cs_row[c]
        value, v, jx = constraint_rows(kind[p], mr, ma, mvel, mw, marker[p, 0], marker[p, 1], marker[p, 2],
                                       par[offsets[p]:offsets[p + 1]],
                                       _inputs(coef, s_off, s_n, s_k, s_t0, s_dt, ser[p], t))
        for r in range(v.size):
            vel[row + r] = v[r]
        for r in range(value.size):
            ch[row + r] = value[r]
        for slot in range(jx.shape[1] // 6):
            add_rows(jac, mj, lohi, marker[p, slot], row, jx, slot)
    return ch, jac, vel


@njit(cache=True)
def _constraints(q, qd, t, P):  # pragma: no cover (compiled)
    """``C_h, jac, V`` alone (no body or element terms): the constraint half of :func:`_terms`."""
    mr, ma, mvel, mw, mj, lohi = _markers(q, qd, t, P)
    return _constraint_terms(q.size, t, P, mr, ma, mvel, mw, mj, lohi)


@njit(cache=True)
def _evaluate(q, qd, t, step, P, m, f, kt, ct, y, ch, jac, vel):  # pragma: no cover (compiled)
    """The packed System as a kind of :mod:`ddgsa.mbs.alpha`'s loop: :func:`_terms` written into its arrays."""
    m_mat, fv, ktv, ctv, out, chv, jacv, velv = _terms(q, qd, t, P, np.bool_(True), np.bool_(True), np.int64(-1))
    m[:] = m_mat
    f[:] = fv
    kt[:] = ktv
    ct[:] = ctv
    y[:] = out.ravel()
    ch[:] = chv
    jac[:] = jacv
    vel[:] = velv


_loop = specialise(_evaluate, "packed")


def evaluate(packed: Packed, q: Array, qd: Array, t: float) -> tuple[Array, ...]:
    """``(M, Q, K_t, C_t, outputs, C_h, C_q, V)`` of the packed system at one state."""
    return _terms(np.asarray(q, dtype=float), np.asarray(qd, dtype=float), float(t), packed.arrays, True, True, -1)


def constraint_values(packed: Packed, q: Array, qd: Array, t: float) -> tuple[Array, Array, Array, Array]:
    """``(C, C_q, V, B)`` of the packed system at one state: the holonomic residual and its Jacobian,
    the velocity-level values of all constraints (holonomic first) and their Jacobian, as
    :meth:`System.holonomic_residual <ddgsa.mbs.assembly.System.holonomic_residual>` and
    :meth:`~ddgsa.mbs.assembly.System.velocity_residual` give them (the ``residuals`` of
    :meth:`~ddgsa.mbs.assembly.System.consistent_state`)."""
    ch, jac, vel = _constraints(np.asarray(q, dtype=float), np.asarray(qd, dtype=float), float(t), packed.arrays)
    return ch, jac[:packed.n_holonomic], vel, jac


def accelerations(packed: Packed, q: Array, qd: Array, t: float, fd_step: float = 1e-6) -> tuple[Array, Array]:
    """Index-1 accelerations [m/s^2 or rad/s^2] and multipliers of the packed system at ``(q, qd, t)``, as
    :func:`ddgsa.mbs.assembly.accelerations` without stabilisation; ``fd_step`` [s]: the central difference
    of the velocity-level constraint values along the motion that gives their time derivative.

    Three calls of the compiled :func:`_terms` and one solve, in Python: it runs once per simulation, and a
    compiled copy would be one more entry point that links and optimises the whole element tree on a
    first run (~14 s of CPU on 2 loaded cores, issue 48)."""
    q, qd, t = np.asarray(q, dtype=float), np.asarray(qd, dtype=float), float(t)
    m_mat, f, _, _, _, _, jac, vel = _terms(q, qd, t, packed.arrays, True, True, -1)
    n, nc = q.size, vel.size
    if nc == 0:
        return np.linalg.solve(m_mat, f), np.zeros(0)
    h = float(fd_step)
    vp = _terms(q + h * qd, qd, t + h, packed.arrays, True, True, -1)[7]
    vm = _terms(q - h * qd, qd, t - h, packed.arrays, True, True, -1)[7]
    big = np.zeros((n + nc, n + nc))
    big[:n, :n] = m_mat
    big[:n, n:] = jac.T
    big[n:, :n] = jac
    rhs = np.concatenate((f, -(vp - vm) / (2 * h)))
    sol = np.linalg.solve(big, rhs)
    return sol[:n], sol[n:]


@njit(cache=True)
def _residuals(qs, qds, qdds, lam0, t, P, over_q, only):  # pragma: no cover (compiled)
    """``M(q) qdd - Q(q, qd, t) + C_q(q)^T lam0`` at each row of ``qs``, ``qds``, ``qdds`` (k, n), followed, where
    ``over_q``, by the velocity-level constraint values (k, n + n_v); for steps of the velocities
    (``over_q`` False) the constraints are not assembled: ``C_q`` depends on ``q`` alone, so its term
    drops out of their difference. The tangents are not assembled. ``only`` (k,) int: -1, or the body whose part
    of the residual row ``j`` is (:func:`_terms`' ``only``; without ``over_q``)."""
    k, n = qs.shape
    out = np.empty((k, 0))
    for j in range(k):
        m_mat, f, kt, ct, y, ch, jac, vel = _terms(qs[j], qds[j], t, P, np.bool_(False), over_q, only[j])
        r = np.dot(m_mat, qdds[j]) - f
        if over_q:
            if lam0.size:
                r += np.dot(jac.T, lam0)
            r = np.concatenate((r, vel))
        if j == 0:                                       # the first row sizes the table
            out = np.empty((k, r.size))
        out[j] = r
    return out


@njit(cache=True)
def _body_rate_slopes(q, qd, P):  # pragma: no cover (compiled)
    """:func:`body_rate_slopes` on the packed arrays ``P``."""
    (b_off, b_nf, b_mass, b_first0, b_k0, o1, o2, ssum, k1, e, f4, h0, h1, kff, cff, mk_body, mk_u0, mk_so,
     mk_s, mk_sr, pb_r0, pb_a0, pb_ser, coef, s_off, s_n, s_k, s_t0, s_dt, nel, kind, marker, ser, offsets, par,
     cs_row, cs_neq, nh, gravity) = P
    n = q.size
    out = np.zeros((n, n))
    for b in range(b_off.size):
        lo, nf = b_off[b], b_nf[b]
        if nf < 0:                               # first-order states: no force of their own
            continue
        nb = 6 + nf
        a1, a2 = o1[b], o2[b]
        qb = q[lo:lo + nb].copy()
        m_b = np.empty((nb, nb))
        f_plus, f_minus = np.empty(nb), np.empty(nb)
        for c in range(nb):
            h = max(1.0, abs(qd[lo + c]))
            for sign in range(2):
                qdb = qd[lo:lo + nb].copy()
                qdb[c] += h if sign == 0 else -h
                body_terms_into(qb, qdb, b_mass[b], b_first0[b], ssum[3 * a1:3 * (a1 + nf)].reshape(3, nf), b_k0[b],
                                k1[9 * a1:9 * (a1 + nf)].reshape(3, 3, nf), e[9 * a1:9 * (a1 + nf)].reshape(3, 3, nf),
                                f4[9 * a2:9 * (a2 + nf * nf)].reshape(3, 3, nf, nf),
                                h0[3 * a1:3 * (a1 + nf)].reshape(3, nf), h1[3 * a2:3 * (a2 + nf * nf)].reshape(nf, 3, nf),
                                gravity, m_b, f_plus if sign == 0 else f_minus)
            for r in range(nb):
                out[lo + r, lo + c] = (f_plus[r] - f_minus[r]) / (2.0 * h)
    return out


def body_rate_slopes(packed: Packed, q: Array, qd: Array) -> Array:
    """``dQ_b/dq_dot`` (n, n) [N s/m, N m s/rad, ...]: the slope over the rates of the packed bodies' own
    generalised forces (gravity and the velocity-quadratic inertia terms of :func:`ddgsa.mbs.ffr.body_terms_inv`:
    centrifugal, Coriolis, gyroscopic) at ``(q, qd)``, block-diagonal by body; without the structural damping,
    which is among the tangents (``C_t``).

    Exact: each body's forces are gravity plus a quadratic form of its rates, whose central difference has no
    truncation error at any step, so each column is the difference of two evaluations of that body alone at a
    step of ``max(1, |qd_c|)`` (rate units: no cancellation to speak of). Two body evaluations a coordinate, not
    two evaluations of the whole system (``tests/mbs/test_nonrotating.py`` checks it against the differences of
    the residual)."""
    return _body_rate_slopes(np.asarray(q, dtype=float), np.asarray(qd, dtype=float), packed.arrays)


def stepped_residuals(packed: Packed, qs: Array, qds: Array, qdds: Array, t: float, base: Array,
                      coords: NDArray[np.int64]) -> Array:
    """The residual ``M(q) qdd - Q(q, qd, t)`` (k, n) of a packed system without constraints at states ``qs``,
    ``qds``, ``qdds`` (k + 1, n), each of the first ``k`` stepped from the last (the state of the residual ``base``
    (n,)) within the coordinates of the body that owns its coordinate ``coords[j]`` (a step of the central
    differences of :func:`ddgsa.mbs.nonrotating.linearise`: a coordinate of a body and whatever that turns within
    the body).

    The residual's other parts do not move with those coordinates, so each row is ``base`` plus the change of the
    stepped body's own terms and of the elements with a marker on it, evaluated from those elements' markers
    alone (:func:`_residuals` with ``only``, at the row and once a body at the base state): the same residuals as
    :func:`_residuals` of the whole system but for round-off, at a fraction of a full evaluation where a system
    has several bodies (the test rig: a step of the motor's or the hub's coordinates evaluates one rigid body and
    three of eleven elements, one of the shaft's the shaft and six)."""
    b_off, b_nf = packed.arrays[0], packed.arrays[1]
    owner = np.empty(packed.n, np.int64)
    for b, (lo, nf) in enumerate(zip(b_off, b_nf)):
        owner[lo:lo + (6 + nf if nf >= 0 else -nf)] = b
    qs, qds, qdds = (np.ascontiguousarray(x, dtype=float) for x in (qs, qds, qdds))
    k = qs.shape[0] - 1
    body = owner[np.asarray(coords, dtype=np.int64)]
    bodies, which = np.unique(body, return_inverse=True)
    t, none = float(t), np.zeros(0)
    part = _residuals(qs[:k], qds[:k], qdds[:k], none, t, packed.arrays, False, body)
    at_base = _residuals(*(np.repeat(x[k:], bodies.size, axis=0) for x in (qs, qds, qdds)), none, t, packed.arrays,
                         False, bodies)
    return np.asarray(base, dtype=float) + (part - at_base[which])


def residual_jacobians(packed: Packed, q: Array, qd: Array, qdd: Array, lam: Array, t: float, scale: float,
                       rel_step: float, static: bool = False,
                       columns: NDArray[np.int64] | None = None) -> tuple[Array, Array, Array]:
    """``(K, C, B0)``: the Jacobians of ``M q_ddot - Q + C_q^T lambda`` over ``q`` and ``q_dot`` at ``(q, qd, t)``
    with ``q_ddot, lambda`` held (the stiffness and damping of :func:`ddgsa.mbs.modal.linearise_system`), and
    of the velocity-level constraint values ``V`` over ``q`` (``d(C_q q_dot)/dq``), by central differences
    (:func:`~ddgsa.mbs.derivatives.central_difference`) of residuals evaluated in one compiled call per
    argument (:func:`_residuals`). ``static``: ``C`` is left at zero (half the evaluations). ``columns``: only
    those coordinates are stepped, the other columns are zero (:func:`~ddgsa.mbs.derivatives.central_difference`)."""
    q, qd, qdd, lam = (np.asarray(x, dtype=float) for x in (q, qd, qdd, lam))
    args = (lam, float(t), packed.arrays)

    def tiled(x: Array, v: Array) -> Array:
        return np.tile(v, (len(x), 1))

    def whole(x: Array) -> NDArray[np.int64]:
        return np.full(len(x), -1, np.int64)

    over_q = central_difference(lambda x: _residuals(x, tiled(x, qd), tiled(x, qdd), *args, True, whole(x)), q, scale, rel_step,
                                columns)
    n = q.size
    if static:
        return over_q[:n], np.zeros((n, n)), over_q[n:]
    over_qd = central_difference(lambda x: _residuals(tiled(x, q), x, tiled(x, qdd), *args, False, whole(x)), qd, scale,
                                 rel_step, columns)
    return over_q[:n], over_qd, over_q[n:]


def gen_alpha(packed: Packed, q0: Array, qd0: Array, t0: float, dt: float, n_steps: int, output_every: int,
              coefficients: tuple[float, float, float, float], tol: float, max_iter: int) -> tuple:
    """Run the constrained generalised-alpha on the packed system (:mod:`ddgsa.mbs.alpha`'s loop);
    see :func:`ddgsa.mbs.integrate.genalpha.simulate`. Returns ``(q, qd, lam, y (n_out, n_el, 6),
    drift (n_out, 2), status, total)`` as the loop."""
    am, af, gamma, beta = coefficients
    q0, qd0 = np.asarray(q0, dtype=float), np.asarray(qd0, dtype=float)
    acc0, lam0 = accelerations(packed, q0, qd0, t0)
    q, qd, lam, y, drift, status, total = _loop(packed.arrays, q0, qd0, acc0, lam0, float(t0), float(dt), int(n_steps),
                                                int(output_every), am, af, gamma, beta, float(tol), int(max_iter),
                                                packed.n_holonomic, 6 * packed.n_elements, False, False, False)
    return q, qd, lam, y.reshape(y.shape[0], packed.n_elements, 6), drift, status, total


@njit(cache=True)
def _along(q, qd, times, P, nh):  # pragma: no cover (compiled)
    """Generalised forces, element outputs and constraint drift at each row of ``q, qd`` (times ``times``)."""
    n_t, n = q.shape
    full = np.bool_(True)
    forces = np.zeros((n_t, n))
    outs = np.zeros((n_t, 0, 6))
    pdrift, vdrift = np.zeros(n_t), np.zeros(n_t)
    for i in range(n_t):
        m_mat, f, kt, ct, out, ch, jac, vel = _terms(q[i], qd[i], times[i], P, full, full, np.int64(-1))
        if i == 0:                                       # the first row sizes the outputs' table
            outs = np.zeros((n_t, out.shape[0], 6))
        forces[i] = f
        outs[i] = out
        if nh > 0:
            pdrift[i] = np.max(np.abs(ch))
        if vel.size > 0:
            vdrift[i] = np.max(np.abs(vel))
    return forces, outs, pdrift, vdrift


def along(packed: Packed, q: Array, qd: Array, times: Array) -> tuple[Array, Array, Array, Array]:
    """``(Q (n_t, n), outputs (n_t, n_el, 6), position drift, velocity drift)`` along a trajectory."""
    return _along(np.ascontiguousarray(q, dtype=float), np.ascontiguousarray(qd, dtype=float),
                  np.asarray(times, dtype=float), packed.arrays, packed.n_holonomic)


@njit(cache=True)
def _positions_along(q, qd, times, P, m):  # pragma: no cover (compiled)
    """Position (n_t, 3) of marker ``m`` at each row of ``q, qd`` (times ``times``)."""
    out = np.zeros((q.shape[0], 3))
    for i in range(q.shape[0]):
        out[i] = _markers(q[i], qd[i], times[i], P)[0][m]
    return out


def _some_markers(arrays: tuple, rows: list[int]) -> tuple:
    """Packed ``arrays`` with the markers ``rows`` as their only markers (row ``k``: marker ``rows[k]``): a
    record's kinematics of a few markers without computing every other marker at every sample."""
    mk_body, mk_u0, mk_so, mk_s, mk_sr = arrays[15:20]
    offsets, s_parts, sr_parts, size_sum = [], [], [], 0
    for m in rows:
        b = mk_body[m]
        size = 3 * max(arrays[1][b], 0) if b >= 0 else 0
        offsets.append(size_sum)
        s_parts.append(mk_s[mk_so[m]:mk_so[m] + size])
        sr_parts.append(mk_sr[mk_so[m]:mk_so[m] + size])
        size_sum += size
    shapes = (np.concatenate(s_parts), np.concatenate(sr_parts)) if size_sum else (np.zeros(1), np.zeros(1))
    idx = np.asarray(rows, dtype=np.int64)
    return (*arrays[:15], mk_body[idx].copy(), mk_u0[idx].copy(), np.asarray(offsets, dtype=np.int64), *shapes,
            *arrays[20:])


class HybridTerms:
    """:meth:`System.terms <ddgsa.mbs.assembly.System.terms>` with every part that packs evaluated
    by the compiled kernel and the few elements without a compiled form (Python torque laws, a
    model's own element classes) in Python: the same terms to round-off (tested), for systems
    whose linearisations call the terms hundreds of times (:func:`ddgsa.mbs.nonrotating.linearise`).

    Raises :class:`ModelError` when a body or constraint has no compiled form.
    """

    def __init__(self, system: System) -> None:
        if system.n_constraints:
            raise ModelError("hybrid terms: constrained systems run on System.terms or the compiled kernel")
        self.system = system
        packs = [el.compiled() is not None for el in system.elements]
        self.packed = pack(system, [el for el, k in zip(system.elements, packs) if k])
        self.python = [(i, el) for i, (el, k) in enumerate(zip(system.elements, packs)) if not k]
        self.compiled_rows = [i for i, k in enumerate(packs) if k]
        self._row = {id(mk): i for i, mk in enumerate(system.markers)}
        """The row of each of the system's markers (by identity) in the kernel's marker tables."""
        self.marker_rows = [[self._row[id(mk)] for mk in el.markers] for _, el in self.python]

    def positions(self, marker: object, q: Array, qd: Array, times: Array) -> Array:
        """Global position (n_t, 3) [m] of one of the system's markers along a record ``q, qd`` (n_t, n)."""
        m = self._row[id(marker)]
        return _positions_along(np.ascontiguousarray(q, dtype=float), np.ascontiguousarray(qd, dtype=float),
                                np.asarray(times, dtype=float), _some_markers(self.packed.arrays, [m]), 0)

    def has(self, marker: object) -> bool:
        """Whether ``marker`` is one of the system's markers (so in the kernel's tables)."""
        return id(marker) in self._row

    def states_along(self, markers: list, q: Array, qd: Array, times: Array) -> list[list[MarkerState]]:
        """States of some of the system's ``markers`` at each row of a record ``q, qd`` (n_t, n) and its
        ``times`` [s]: the kernel's marker tables of those markers alone (:func:`_some_markers`)."""
        sub = _some_markers(self.packed.arrays, [self._row[id(m)] for m in markers])
        out = []
        for qi, qdi, t in zip(np.asarray(q, dtype=float), np.asarray(qd, dtype=float), np.asarray(times, dtype=float)):
            mr, ma, mvel, mw, mj, _ = _markers(qi, qdi, float(t), sub)
            out.append([MarkerState(mr[k], ma[k], mvel[k], mw[k], mj[k]) for k in range(len(markers))])
        return out

    def states(self, markers: list, q: Array, qd: Array, t: float) -> list[MarkerState]:
        """States of some of the system's ``markers`` at ``(q, qd, t)``."""
        mr, ma, mvel, mw, mj, _ = _markers(np.asarray(q, dtype=float), np.asarray(qd, dtype=float), float(t),
                                           self.packed.arrays)
        return [MarkerState(mr[r], ma[r], mvel[r], mw[r], mj[r]) for r in (self._row[id(m)] for m in markers)]

    def __call__(self, q: Array, qd: Array, t: float):
        """:class:`~ddgsa.mbs.assembly.Terms` at ``(q, qd, t)``."""
        system = self.system
        q, qd, t = np.asarray(q, dtype=float), np.asarray(qd, dtype=float), float(t)
        m, f, kt, ct, out = _terms(q, qd, t, self.packed.arrays, True, True, -1)[:5]
        outputs: list = [None] * len(system.elements)
        for row, i in enumerate(self.compiled_rows):
            outputs[i] = out[row]
        if self.python:
            mr, ma, mvel, mw, mj, _ = _markers(q, qd, t, self.packed.arrays)
        for (i, el), rows in zip(self.python, self.marker_rows):
            states = [MarkerState(mr[r], ma[r], mvel[r], mw[r], mj[r]) for r in rows]
            w, k_el, c_el = el.wrench(t, states)
            add_wrench(f, kt, ct, states, w, k_el, c_el)
            outputs[i] = w[0]
        return Terms(m, f, kt, ct, outputs)


def compile_terms(system: System) -> bool:
    """Evaluate ``system.terms`` from now on by :class:`HybridTerms` (the same terms to round-off);
    False, and nothing changed, where a body or constraint has no compiled form. Call it once the
    system's elements are final (they are packed now)."""
    try:
        system.fast_terms = HybridTerms(system)
    except ModelError:
        return False
    return True
