"""Closed and total Sobol indices of groups of parameters.

For a group :math:`u` of inputs (e.g. the four parameters of one bearing) the **closed** index
:math:`S^{clo}_u = \\mathrm{Var}(E[Y | X_u]) / \\mathrm{Var}\\, Y` is the share of the variance
the group explains alone, its members' interactions among themselves included, and the **total**
index :math:`S_{T,u} = 1 - S^{clo}_{\\sim u}` the share it takes part in at all (Saltelli et al.
2008, *Global Sensitivity Analysis: The Primer*, §1.2.15). Neither is a sum of the members'
S1 or ST: Ishigami's group {x1, x3} has closed index S1 + S3 + S13 = 0.56 where S1 + S3 = 0.31.

Which method gives them, and how:

* **M-DRM** (:func:`product_form`): its surrogate :math:`h(c)^{1-n}\\prod_i h_i(x_i)` has
  :math:`S^{clo}_u = (\\prod_{i \\in u} (1 + r_i) - 1) / (\\prod_k (1 + r_k) - 1)` with
  :math:`r_i = \\mathrm{Var}\\, h_i / \\rho_i^2`: exact for products, from the same runs.
* **PCE** (:func:`from_coefficients`): the squared coefficients of the terms that involve only
  members of the group (closed) or any member (total), Sudret 2008's sums taken over groups.
* **Saltelli** (:mod:`ddgsa.gsa.salib`): one extra matrix ``AB_u`` (the group's columns from B)
  per group of two or more, ``n`` runs each, analysed by SALib's ``groups`` option.

FAST and RBD-FAST give no group indices (their designs have no group to vary alone).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import NDArray

GROUP_COLUMNS = ["output", "group", "members", "S_closed", "S_closed_conf", "ST", "ST_conf"]


@dataclass
class GroupIndices:
    """Arrays (n_outputs, n_groups) of one method's group indices [-] and their error bounds [-]."""

    S_closed: NDArray[np.float64]
    ST: NDArray[np.float64]
    S_closed_conf: NDArray[np.float64]
    ST_conf: NDArray[np.float64]


def product_form(r: NDArray[np.float64], members: Sequence[Sequence[int]]) -> tuple[NDArray[np.float64],
                                                                                     NDArray[np.float64]]:
    """Closed and total group indices of a product of one-variable functions.

    Parameters
    ----------
    r : ndarray, shape (n_params, n_outputs)
        ``Var[h_i] / E[h_i]^2`` of every cut function [-].
    members : sequence of sequences of int
        The column indices of each group.

    Returns
    -------
    S_closed, ST : ndarray, shape (n_outputs, n_groups)
    """
    log1p = np.log1p(r)                                           # (n, k)
    total = log1p.sum(axis=0)                                     # (k,)
    closed = np.stack([np.expm1(log1p[list(m)].sum(axis=0)) for m in members], axis=1)    # (k, G)
    outside = np.stack([log1p[list(m)].sum(axis=0) for m in members], axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        s_closed = closed / np.expm1(total)[:, None]
        st = -np.expm1(-outside) / -np.expm1(-total)[:, None]
    return s_closed, st


def from_coefficients(alphas: NDArray[np.int64], energy: NDArray[np.float64],
                      members: Sequence[Sequence[int]]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Closed and total group indices of an orthonormal polynomial expansion.

    Parameters
    ----------
    alphas : ndarray, shape (P - 1, n_params)
        Multi-indices of the non-constant terms.
    energy : ndarray, shape (P - 1, n_outputs)
        Their squared coefficients [output unit^2].
    members : sequence of sequences of int
        The column indices of each group.

    Returns
    -------
    S_closed, ST : ndarray, shape (n_outputs, n_groups)
    """
    involved = alphas > 0                                          # (P-1, d)
    var = energy.sum(axis=0)                                       # (k,)
    inside = np.zeros((involved.shape[0], len(members)))
    touches = np.zeros_like(inside)
    for g, m in enumerate(members):
        mask = np.zeros(involved.shape[1], dtype=bool)
        mask[list(m)] = True
        inside[:, g] = involved.any(axis=1) & ~(involved & ~mask).any(axis=1)
        touches[:, g] = (involved & mask).any(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return (energy.T @ inside) / var[:, None], (energy.T @ touches) / var[:, None]


def group_frame(outputs: Sequence[str], groups: dict[str, tuple[str, ...]],
                gi: GroupIndices | None) -> pd.DataFrame:
    """The tidy table ``output, group, members, S_closed, S_closed_conf, ST, ST_conf`` (empty without groups)."""
    if gi is None or not groups:
        return pd.DataFrame(columns=GROUP_COLUMNS)
    k, g = len(outputs), len(groups)
    return pd.DataFrame({
        "output": np.repeat(list(outputs), g),
        "group": np.tile(list(groups), k),
        "members": np.tile([" ".join(m) for m in groups.values()], k),
        "S_closed": gi.S_closed.ravel(), "S_closed_conf": gi.S_closed_conf.ravel(),
        "ST": gi.ST.ravel(), "ST_conf": gi.ST_conf.ravel(),
    })
