"""Linearisation and modal analysis of second-order systems ``M q_ddot = Q(q, q_dot)``."""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
import pandas as pd
from numpy.typing import NDArray
from scipy.linalg import eig

Terms = Callable[[NDArray[np.float64], NDArray[np.float64]], tuple[NDArray[np.float64], NDArray[np.float64]]]


def linearise(terms: Terms, q0: NDArray[np.float64], qd0: NDArray[np.float64],
              keep: Sequence[int] | None = None, rel_step: float = 1e-6) -> tuple[NDArray[np.float64], ...]:
    """Mass, damping and stiffness matrices at ``(q0, qd0)`` by central differences.

    Parameters
    ----------
    terms : callable
        ``terms(q, qd) -> (M, Q)``.
    keep : sequence of int, optional
        Coordinates to keep (e.g. without a cyclic spin angle); the others are held fixed.
    rel_step : float
        Finite-difference step relative to ``max(1, |q_i|)`` (and to 1e-3 for velocities).

    Returns
    -------
    M, C, K : ndarray
        ``M dq_ddot + C dq_dot + K dq = 0`` on the kept coordinates.
    """
    idx = np.arange(q0.size) if keep is None else np.asarray(keep)
    m0, _ = terms(q0, qd0)
    n = idx.size
    k, c = np.zeros((n, n)), np.zeros((n, n))
    for col, i in enumerate(idx):
        h = rel_step * max(1.0, abs(q0[i]))
        dq = np.zeros_like(q0)
        dq[i] = h
        k[:, col] = -(terms(q0 + dq, qd0)[1] - terms(q0 - dq, qd0)[1])[idx] / (2 * h)
        hv = rel_step * max(1e-3, abs(qd0[i]))
        c[:, col] = -(terms(q0, qd0 + dq * hv / h)[1] - terms(q0, qd0 - dq * hv / h)[1])[idx] / (2 * hv)
    return m0[np.ix_(idx, idx)], c, k


def modal_analysis(m: NDArray[np.float64], c: NDArray[np.float64], k: NDArray[np.float64],
                   names: Sequence[str], groups: dict[str, str]) -> pd.DataFrame:
    """Damped modes of ``M q'' + C q' + K q = 0`` with labels from their kinetic-energy shares.

    Parameters
    ----------
    names : sequence of str
        Coordinate names (same order as the matrices).
    groups : dict
        Coordinate name -> mode label; a mode is labelled by the group holding the largest
        share of its kinetic energy (a suffix ``_2``, ``_3`` ... tells repeated labels apart).

    Returns
    -------
    DataFrame
        One row per oscillating mode, ascending frequency: ``frequency_hz``, ``damping_ratio``,
        ``label`` and the energy share of each group (``share_<label>``).
    """
    n = m.shape[0]
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(m, k), -np.linalg.solve(m, c)]])
    lam, vec = eig(a)
    sel = lam.imag > 1e-6 * max(1.0, np.abs(lam).max()) * 1e-3
    lam, vec = lam[sel], vec[:n, sel]
    order = np.argsort(np.abs(lam))
    labels_all = sorted(set(groups.values()))
    rows = []
    seen: dict[str, int] = {}
    for j in order:
        v = vec[:, j]
        energy = np.real(np.conj(v) * (m @ v))
        energy = np.abs(energy) / np.abs(energy).sum()
        shares = {g: float(sum(e for e, nm in zip(energy, names) if groups[nm] == g)) for g in labels_all}
        label = max(shares, key=shares.get)
        seen[label] = seen.get(label, 0) + 1
        rows.append({"frequency_hz": float(abs(lam[j]) / (2 * np.pi)),
                     "damping_ratio": float(-lam[j].real / abs(lam[j])),
                     "label": label if seen[label] == 1 else f"{label}_{seen[label]}",
                     **{f"share_{g}": s for g, s in shares.items()}})
    return pd.DataFrame(rows)
