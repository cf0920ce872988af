"""Linearisation and modal analysis of second-order systems ``M q_ddot = Q(q, q_dot)``.

For a constrained :class:`~ddgsa.mbs.assembly.System`, :func:`linearise_system` linearises
``M q_ddot + C_q^T lambda = Q`` about an operating state and reduces it on the null space ``N``
of the constraint Jacobian (``q = q_op + N z``): holonomic and velocity-level rows alike (the
gear constraint's linearisation is integrable), with the geometric stiffness of the operating
multipliers ``d(C_q^T lambda_0)/dq`` kept (a pendulum's restoring stiffness comes from it).
:func:`modes` labels the modes of that reduced system by body and direction.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray
from scipy.linalg import eig, null_space

from ddgsa.errors import ModelError
from ddgsa.mbs.assembly import System, accelerations, python_kind
from ddgsa.mbs.compiled import Packed, evaluate, pack, residual_jacobians
from ddgsa.mbs.compiled import accelerations as compiled_accelerations
from ddgsa.mbs.derivatives import central_difference

def kind_jacobians(kind: Callable[..., None], ctx: object, sizes: tuple[int, int, int],
                   q0: NDArray[np.float64], qd0: NDArray[np.float64], t0: float, qdd0: NDArray[np.float64],
                   lam0: NDArray[np.float64], keep: Sequence[int] | None = None, scales: tuple[float, float] = (1e-3, 1e-3),
                   rel_step: float = 1e-6, static: bool = False) -> tuple[NDArray[np.float64], ...]:
    """``(M, C, K)`` of ``M(q) q_ddot - Q(q, q_dot, t0) + C_q(q)^T lambda_0`` at ``(q0, qd0)`` on the kept coordinates.

    The system is any ``kind`` of :mod:`ddgsa.mbs.alpha`'s loop (``kind(q, qd, t, step, ctx, m, f, kt, ct,
    y, ch, jac, vel)``: a System's own objects, :func:`~ddgsa.mbs.assembly.python_kind`; the single-body
    kernel, :func:`ddgsa.mbs.system.kind_context`), so one linearisation serves them all. ``K`` and
    ``C`` are central differences (:func:`~ddgsa.mbs.derivatives.central_difference`, steps
    ``rel_step max(scale, |x_i|)`` with ``scales`` for the positions and the velocities) with
    ``q_ddot = qdd0`` and ``lambda = lam0`` held; ``M`` is exact (the residual is linear in the
    accelerations). The other coordinates are held (e.g. a cyclic spin angle). ``static=True``
    leaves ``C`` at zero (half the evaluations).

    Parameters
    ----------
    sizes : ``(n_y, n_h, n_c)`` the kind's output, holonomic and constraint counts
    """
    n = q0.size
    n_y, n_h, n_c = sizes
    idx = np.arange(n) if keep is None else np.asarray(keep)
    m, f, kt, ct = np.zeros((n, n)), np.zeros(n), np.zeros((n, n)), np.zeros((n, n))
    y, ch, jac, vel = np.zeros(n_y), np.zeros(n_h), np.zeros((n_c, n)), np.zeros(n_c)
    kind(q0, qd0, t0, 0, ctx, m, f, kt, ct, y, ch, jac, vel)
    m0 = m[np.ix_(idx, idx)].copy()

    def batch(x: NDArray[np.float64], over_q: bool) -> NDArray[np.float64]:
        """The residual on the kept coordinates at each row of ``x`` (kept positions or velocities)."""
        out = np.empty((len(x), idx.size))
        for j, xj in enumerate(x):
            q, qd = q0.copy(), qd0.copy()
            (q if over_q else qd)[idx] = xj
            kind(q, qd, t0, 0, ctx, m, f, kt, ct, y, ch, jac, vel)
            r = m @ qdd0 - f
            if lam0.size:
                r = r + jac.T @ lam0
            out[j] = r[idx]
        return out

    k = central_difference(lambda x: batch(x, True), q0[idx], scales[0], rel_step)
    c = np.zeros_like(k) if static else central_difference(lambda x: batch(x, False), qd0[idx], scales[1], rel_step)
    return m0, c, k


def damped_eigen(m: NDArray[np.float64], c: NDArray[np.float64],
                 k: NDArray[np.float64]) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Oscillating eigenpairs of ``M q'' + C q' + K q = 0``, ascending ``|lambda|``.

    Returns the eigenvalues with positive imaginary part and their displacement shapes (n, n_modes);
    rigid-body eigenvalues (``|lambda|`` below 1e-7 of the largest, finite-difference noise on a
    zero eigenvalue) are left out.
    """
    n = m.shape[0]
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(m, k), -np.linalg.solve(m, c)]])
    lam, vec = eig(a)
    top = max(1.0, np.abs(lam).max())
    sel = (lam.imag > 1e-9 * top) & (np.abs(lam) > 1e-7 * top)
    lam, vec = lam[sel], vec[:n, sel]
    order = np.argsort(np.abs(lam))
    return lam[order], vec[:, order]


REPEATED_RTOL = 1e-9
"""Eigenvalues within this relative distance are one repeated eigenvalue (:func:`localised`)."""


def localised(lam: NDArray[np.complex128], vec: NDArray[np.complex128]) -> NDArray[np.complex128]:
    """``vec`` with the shapes of each repeated eigenvalue (``lam`` within :data:`REPEATED_RTOL`)
    replaced by the basis of the same subspace that is localised on coordinates: each shape is 1 on
    one coordinate (chosen by column-pivoted QR of the subspace) and 0 on the others chosen. A
    repeated eigenvalue's shapes are otherwise an arbitrary mix (e.g. six identical housing modes
    each spread over both housings), and their labels with them."""
    from scipy.linalg import qr

    out = vec.copy()
    j = 0
    while j < lam.size:
        k = j + 1
        while k < lam.size and abs(lam[k] - lam[j]) <= REPEATED_RTOL * abs(lam[j]):
            k += 1
        if k - j > 1:
            v = vec[:, j:k]
            _, _, piv = qr(v.conj().T, pivoting=True, mode="economic")
            rows = np.sort(piv[: k - j])
            out[:, j:k] = v @ np.linalg.solve(v[rows, :], np.eye(k - j))
        j = k
    return out


def modal_analysis(m: NDArray[np.float64], c: NDArray[np.float64], k: NDArray[np.float64],
                   names: Sequence[str], groups: dict[str, str], basis: NDArray[np.float64] | None = None,
                   m_full: NDArray[np.float64] | None = None) -> pd.DataFrame:
    """Damped modes of ``M q'' + C q' + K q = 0`` with labels from their kinetic-energy shares.

    Parameters
    ----------
    names : sequence of str
        Coordinate names (same order as the matrices, or as the rows of ``basis``).
    groups : dict
        Coordinate name -> mode label; a mode is labelled by the group holding the largest
        share of its kinetic energy (a suffix ``_2``, ``_3`` ... tells repeated labels apart).
    basis, m_full : ndarray, optional
        For reduced matrices (``q = basis z``): the basis (n, n_z) and the full mass matrix;
        energy shares are then taken over the full coordinates.

    Returns
    -------
    DataFrame
        One row per oscillating mode, ascending frequency: ``frequency_hz``, ``damping_ratio``,
        ``label`` and the energy share of each group (``share_<label>``).
    """
    lam, vec = damped_eigen(m, c, k)
    if basis is not None:
        vec, m = basis @ vec, m_full
    vec = localised(lam, vec)
    labels_all = sorted(set(groups.values()))
    rows = []
    seen: dict[str, int] = {}
    for j in range(lam.size):
        v = vec[:, j]
        energy = np.real(np.conj(v) * (m @ v))
        energy = np.abs(energy) / np.abs(energy).sum()
        shares = {g: float(sum(e for e, nm in zip(energy, names) if groups.get(nm) == g)) for g in labels_all}
        label = max(shares, key=shares.get)
        seen[label] = seen.get(label, 0) + 1
        rows.append({"frequency_hz": float(abs(lam[j]) / (2 * np.pi)),
                     "damping_ratio": float(-lam[j].real / abs(lam[j])),
                     "label": label if seen[label] == 1 else f"{label}_{seen[label]}",
                     **{f"share_{g}": s for g, s in shares.items()}})
    return pd.DataFrame(rows)


@dataclass(frozen=True)
class ConstrainedLinearisation:
    """``M z'' + C z' + K z = N^T (Q(t) - Q_0) + r0`` about an operating state, ``q = q0 + qd0 (t - t0) + N z``.

    Attributes
    ----------
    m, c, k : (n_z, n_z) reduced mass, damping (with gyroscopic terms) and stiffness
    basis : (n, n_z) null space ``N`` of the constraint Jacobian at ``q0`` (orthonormal columns)
    m_full, c_full, k_full : (n, n) the unreduced matrices
    q0, qd0, t0 : the operating state; ``qdd0``, ``lam0`` its accelerations and multipliers
    r0 : (n_z,) ``N^T Q_0``, the unbalanced generalised force at the operating state
    curvature : (n_c, n) or None
        ``d(C_q(q) qd0)/dq``, the velocity-level constraint values' Jacobian over the coordinates at the
        operating velocities, where the compiled linearisation took it from the same evaluations
    """

    m: NDArray[np.float64]
    c: NDArray[np.float64]
    k: NDArray[np.float64]
    basis: NDArray[np.float64]
    m_full: NDArray[np.float64]
    c_full: NDArray[np.float64]
    k_full: NDArray[np.float64]
    q0: NDArray[np.float64]
    qd0: NDArray[np.float64]
    t0: float
    qdd0: NDArray[np.float64]
    lam0: NDArray[np.float64]
    r0: NDArray[np.float64]
    curvature: NDArray[np.float64] | None = None

    @property
    def b(self) -> NDArray[np.float64]:
        """The input matrix: the input is ``N^T dQ`` itself (identity)."""
        return np.eye(self.m.shape[0])

    @property
    def velocity_map(self) -> NDArray[np.float64]:
        """``T`` of ``z_dot = T v``: identity (the velocities are the rates of ``z``)."""
        return np.eye(self.m.shape[0])


def linearise_system(system: System, q0: NDArray[np.float64] | None = None, qd0: NDArray[np.float64] | None = None,
                     t0: float = 0.0, rel_step: float = 1e-6, analytic: bool = False,
                     compiled: bool | Packed = False, static: bool = False,
                     tangent_columns: Sequence[int] = ()) -> ConstrainedLinearisation:
    """Linearise a constrained system about ``(q0, qd0, t0)`` and reduce it on the null space of ``C_q``.

    The full matrices are central differences of the residual ``M(q) q_ddot - Q(q, q_dot, t0) +
    C_q(q)^T lambda_0`` (:func:`kind_jacobians` on the System's own objects, the kernel's one
    linearisation); ``q0, qd0`` default to the system's (consistent) initial state.
    ``analytic=True`` takes ``K`` and ``C`` from the parts' own tangents
    (:meth:`~ddgsa.mbs.assembly.System.terms`): exact for a system at rest whose elements give exact
    tangents and whose multipliers add no geometric stiffness (no spin, no gyroscopic terms); one
    evaluation instead of ``4 n``. ``compiled=True`` takes every residual from the packed system
    (the same terms to round-off, about 13x faster; every part must pack), the accelerations too,
    all stepped residuals of an argument in one compiled call
    (:func:`ddgsa.mbs.compiled.residual_jacobians`: the same differences); a
    :class:`~ddgsa.mbs.compiled.Packed` of ``system`` is taken as packed already (a caller that
    linearises one system often). ``static=True`` (unconstrained systems) leaves ``C`` at zero and
    takes ``K`` alone (half the residual calls: a caller that needs the static part ``K z = r0``
    only, such as a gravity sag). ``tangent_columns`` (compiled, unconstrained systems) take those columns
    of ``K`` and ``C`` from the parts' own tangents as ``analytic`` does and difference the others only
    (the caller's claim that no inertia, gravity or geometric term depends on those coordinates; as
    :func:`ddgsa.mbs.nonrotating.linearise`'s); all ``n`` of them take no residual call at all (a system at
    rest whose elements carry no load there, as the test rig's gravity sag in
    :mod:`ddgsa.models.hss_rig.steady_block`).
    """
    if q0 is None or qd0 is None:
        q0, qd0 = system.consistent_state(q0, qd0, t0)
    q0, qd0 = np.asarray(q0, dtype=float), np.asarray(qd0, dtype=float)
    if compiled is not False:
        packed = compiled if isinstance(compiled, Packed) else pack(system)
        qdd0, lam0 = compiled_accelerations(packed, q0, qd0, t0)

        def mass_force_jacobian(q: NDArray[np.float64], qd: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
            m, f, *_, jac, _ = evaluate(packed, q, qd, t0)
            return m, f, jac
    else:
        qdd0, lam0 = accelerations(system, q0, qd0, t0)

        def mass_force_jacobian(q: NDArray[np.float64], qd: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
            tm = system.terms(q, qd, t0)
            jac = system.constraint_jacobian(q, qd, t0) if system.n_constraints else np.zeros((0, system.n))
            return tm.m, tm.q, jac

    m0, f0, jac0 = mass_force_jacobian(q0, qd0)
    curvature = None
    if static and system.n_constraints:
        raise ModelError("linearise_system: static=True takes unconstrained systems only")
    if analytic:
        tm = system.terms(q0, qd0, t0)
        k_full, c_full = tm.k, tm.c
    elif compiled is not False:
        tc = np.asarray(tangent_columns, dtype=np.int64)
        if tc.size and system.n_constraints:
            raise ModelError("linearise_system: tangent_columns take unconstrained systems only")
        differenced = np.setdiff1d(np.arange(system.n), tc)
        if differenced.size:
            k_full, c_full, curvature = residual_jacobians(packed, q0, qd0, qdd0, lam0, t0, 1e-3, rel_step, static,
                                                           differenced)
        else:                                       # every column from the tangents: no residual call
            k_full, c_full = np.zeros((system.n, system.n)), np.zeros((system.n, system.n))
        if tc.size:
            kt, ct = evaluate(packed, q0, qd0, t0)[2:4]
            k_full[:, tc] = kt[:, tc]
            if not static:
                c_full[:, tc] = ct[:, tc]
    elif len(tangent_columns):
        raise ModelError("linearise_system: tangent_columns take the compiled path (compiled=True)")
    else:
        sizes = (6 * len(system.elements), system.n_holonomic, system.n_constraints)
        _, c_full, k_full = kind_jacobians(python_kind(system), None, sizes, q0, qd0, t0, qdd0, lam0,
                                           rel_step=rel_step, static=static)
    basis = null_space(jac0) if system.n_constraints else np.eye(system.n)
    return ConstrainedLinearisation(basis.T @ m0 @ basis, basis.T @ c_full @ basis, basis.T @ k_full @ basis,
                                    basis, m0, c_full, k_full, q0, qd0, t0, qdd0, lam0, basis.T @ f0,
                                    curvature)


def modes(system: System, q0: NDArray[np.float64] | None = None, qd0: NDArray[np.float64] | None = None,
          t0: float = 0.0, rel_step: float = 1e-6) -> pd.DataFrame:
    """Damped modes of a constrained system about an operating state, labelled by body and direction.

    ``rel_step``: the linearisation's relative central-difference step (:func:`linearise_system`; a
    system with large constant forces wants a larger one, e.g. the geared drive's 1e-3: round-off
    of its ~1e6 N forces over the default 1e-9 m steps left 4e-9 in its frequencies and 4e-8 in its
    damping ratios, tests/models/test_indirect_drive.py).

    Returns
    -------
    DataFrame
        ``frequency_hz``, ``damping_ratio``, ``label`` (e.g. ``shaft_tilt_y``, ``disc_spin``) and the
        energy share of each label, ascending frequency (rigid-body modes, at zero frequency, left out).
    """
    lin = linearise_system(system, q0, qd0, t0, rel_step=rel_step)
    return modal_analysis(lin.m, lin.c, lin.k, system.coord_names, system.groups(), lin.basis, lin.m_full)


LOG_SPAN = 10.0
"""Highest over lowest frequency from which :func:`plot_modes` draws a logarithmic axis."""


def plot_modes(table: pd.DataFrame, ax: Any = None) -> Any:
    """Horizontal bars of the natural frequencies [Hz] of a mode table, labelled; returns the ``Axes``.

    The frequency axis is logarithmic (plain decade labels, no minor labels) only where the
    frequencies span :data:`LOG_SPAN` or more; nearly equal frequencies (34.212040 and 34.212043 Hz)
    get a linear axis from 0, whose equal bars show them equal.
    """
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, NullFormatter

    if ax is None:
        _, ax = plt.subplots(figsize=(7, 0.35 * max(len(table), 4) + 1.0), layout="constrained")
    f = table["frequency_hz"].to_numpy(float)
    y = np.arange(len(table))
    ax.barh(y, f, color="tab:blue")
    ax.set_yticks(y, [f"{lab} ({v:.4g} Hz)" for lab, v in zip(table["label"], f)], fontsize=8)
    ax.invert_yaxis()
    if f.size and f.min() > 0 and f.max() / f.min() >= LOG_SPAN:
        ax.set_xscale("log")
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.xaxis.set_minor_formatter(NullFormatter())
    else:
        ax.set_xlim(0.0, 1.05 * max(float(f.max(initial=0.0)), 1e-12))
    ax.set_xlabel("natural frequency [Hz]")
    return ax
