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

**Trust and rank** (:func:`group_frame`): each method's ``_conf`` columns are its error bounds on the
group indices, derived as for the parameters (M-DRM: the check sample's surrogate bound, or the
distance to its cross-check's group indices plus that PCE's bound where smaller; PCE: the
leave-one-out surrogate bound; Saltelli: the bootstrap half-width or twice the half-sample
difference), so a group row is judged by the parameters' rule (:mod:`ddgsa.gsa.trust`): **trusted**
when both indices are finite, both bounds are within the tolerance (diagnostic ``group_index_error``
otherwise) and no rule other than an error estimate (sign change, unresolved cut function, failed
runs...) voids the output or a member's row; ``rank_confirmed`` and ``rank`` order the groups by total
index with :func:`~ddgsa.gsa.result.rank_structure`, the total index's bound as its error.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.gsa.result import GROUP_COLUMNS, Diagnostic, index_error_rule, rank_structure, trusted_mask
from ddgsa.gsa.trust import DEFAULT_TOLERANCE, error_diagnostics

__all__ = ["GROUP_COLUMNS", "GroupIndices", "from_coefficients", "group_frame", "product_form"]


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


def group_terms(alphas: NDArray[np.int64], members: Sequence[Sequence[int]]
                ) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Which non-constant terms (``alphas`` (P - 1, n_params)) each group's closed index sums (every
    input of the term in the group) and its total index sums (some input in it): two (P - 1, n_groups)
    masks."""
    involved = alphas > 0                                          # (P-1, d)
    inside = np.zeros((involved.shape[0], len(members)), dtype=bool)
    touches = np.zeros_like(inside)
    for g, m in enumerate(members):
        mask = np.zeros(involved.shape[1], dtype=bool)
        mask[list(m)] = True
        inside[:, g] = involved.any(axis=1) & ~(involved & ~mask).any(axis=1)
        touches[:, g] = (involved & mask).any(axis=1)
    return inside, touches


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
    var = energy.sum(axis=0)                                       # (k,)
    inside, touches = group_terms(alphas, members)
    inside, touches = inside.astype(float), touches.astype(float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return (energy.T @ inside) / var[:, None], (energy.T @ touches) / var[:, None]


def group_frame(outputs: Sequence[str], groups: dict[str, tuple[str, ...]], gi: GroupIndices | None,
                diagnostics: Sequence[Diagnostic] = (), tolerance: float = DEFAULT_TOLERANCE) -> pd.DataFrame:
    """The tidy table of :data:`~ddgsa.gsa.result.GROUP_COLUMNS` (empty without groups), judged.

    Parameters
    ----------
    outputs : sequence of str
        The outputs, in the order of ``gi``'s rows.
    groups : dict
        Group name -> its member parameters.
    gi : GroupIndices or None
        The method's group indices and error bounds [-] (None: the method gives none).
    diagnostics : sequence of Diagnostic
        The method's findings on the parameters' rows: a rule other than an error estimate that voids
        the output, or a member's row, voids the group's row too.
    tolerance : float
        Absolute error allowed on every index of a trusted row [-] (and the rank margin and floor).
    """
    if gi is None or not groups:
        return pd.DataFrame(columns=GROUP_COLUMNS)
    k, g = len(outputs), len(groups)
    table = pd.DataFrame({
        "output": np.repeat(list(outputs), g),
        "group": np.tile(list(groups), k),
        "members": np.tile([" ".join(m) for m in groups.values()], k),
        "S_closed": gi.S_closed.ravel(), "S_closed_conf": gi.S_closed_conf.ravel(),
        "ST": gi.ST.ravel(), "ST_conf": gi.ST_conf.ravel(),
    })
    diags = _member_rules(diagnostics, groups) + error_diagnostics(
        "group_index_error", "the method's bound on the group indices", list(outputs), list(groups),
        gi.S_closed_conf, gi.ST_conf, tolerance)
    rows = table.rename(columns={"group": "parameter", "S_closed": "S1"})   # the parameters' table's names
    table["trusted"] = trusted_mask(rows, diags) & np.isfinite(table["S_closed_conf"].to_numpy(float)) \
        & np.isfinite(table["ST_conf"].to_numpy(float))
    codes, ranks = rank_structure(rows, table["ST_conf"].to_numpy(float), diags, tolerance)
    table["rank_confirmed"] = codes > 0
    table["rank"] = ranks
    return table[GROUP_COLUMNS]


def _member_rules(diagnostics: Sequence[Diagnostic], groups: dict[str, tuple[str, ...]]) -> list[Diagnostic]:
    """The ``untrusted`` rules other than error estimates, addressed to the groups they void: a rule on a
    whole output stays one, a rule on a parameter goes to that parameter's group (none if it is in none)."""
    owner = {p: name for name, members in groups.items() for p in members}
    out = []
    for d in diagnostics:
        if d.severity != "untrusted" or index_error_rule(d.name):
            continue
        if d.parameter is None:
            out.append(d)
        elif d.parameter in owner:
            out.append(replace(d, parameter=owner[d.parameter]))
    return out
