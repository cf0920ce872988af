"""The result of any GSA method: one tidy table of indices plus what the method checked."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import pandas as pd
from numpy.typing import NDArray

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

INDEX_COLUMNS = ["output", "parameter", "S1", "S1_conf", "ST", "ST_conf", "trusted", "rank_confirmed", "rank"]
GROUP_COLUMNS = ["output", "group", "members", "S_closed", "S_closed_conf", "ST", "ST_conf", "trusted",
                 "rank_confirmed", "rank"]
"""Columns of ``SobolResult.groups`` (:mod:`ddgsa.gsa.groups`): the group indices with the same trust and
rank claims as the parameters' rows."""
Severity = Literal["info", "warning", "untrusted"]
VERDICTS = ("trusted", "rank-confirmed", "confirmed tie", "nothing to rank", "screened", "unconfirmed")
"""The verdicts of a (scene, output) pair, best first (:func:`ddgsa.execute.confirm.confirmation_table`)."""
CONFIRMED = VERDICTS[:4]
"""The verdicts that need no more runs (exit 0)."""
ROW_COLUMNS = frozenset({"study", "scene", "method", "output", "parameter", "S1", "S1_conf", "ST", "ST_conf",
                         "trusted", "rank_confirmed", "rank", "verdict", "n_evals", "output_unit", "source"})
"""Columns of a study's ``indices.csv`` that describe the row, not its scene: every other column is a
scene field (wind speed, scene kind...). Readers of the file (HTML report, NetCDF export) split on it."""


@dataclass(frozen=True)
class Diagnostic:
    """One finding a method made about its own validity.

    Parameters
    ----------
    name : str
        Stable identifier, e.g. ``"mdrm_sign_change"``; tests and reports key on it.
    message : str
        Human-readable explanation with the numbers that triggered it.
    severity : {"info", "warning", "untrusted"}
        ``"untrusted"`` marks the affected rows of the table ``trusted = False``.
    output : str or None
        The output concerned (None: all outputs).
    parameter : str or None
        The parameter concerned (None: all parameters of the output).
    value : float
        The number that was tested (NaN if none).
    """

    name: str
    message: str
    severity: Severity = "warning"
    output: str | None = None
    parameter: str | None = None
    value: float = float("nan")

    def to_dict(self) -> dict[str, Any]:
        """Plain-dict form (for JSON provenance)."""
        return {"name": self.name, "message": self.message, "severity": self.severity,
                "output": self.output, "parameter": self.parameter,
                "value": None if not np.isfinite(self.value) else float(self.value)}


@dataclass
class SobolResult:
    """Sobol indices from one method.

    Attributes
    ----------
    indices : pandas.DataFrame
        One row per (output, parameter): ``output, parameter, S1, S1_conf, ST, ST_conf,
        trusted, rank_confirmed, rank`` (:func:`rank_structure`: ``rank`` is the confirmed place by ST,
        ``"2="`` in a tied group, ``"negligible"``, or empty). NaN where the method does not give a quantity (e.g. ``ST`` for
        RBD-FAST) or where the result was refused (see ``diagnostics``).
    n_evals : int
        Model evaluations the method spent.
    method : str
        Registry name of the method.
    options : dict
        The options it ran with.
    diagnostics : list of Diagnostic
        What the method checked about its own validity.
    extras : dict
        Method-specific numbers (e.g. M-DRM's ``rho``/``theta``, PCE's LOO error).
    groups : pandas.DataFrame
        One row per (output, group) of the space's groups: ``output, group, members, S_closed,
        S_closed_conf, ST, ST_conf, trusted, rank_confirmed, rank`` (:mod:`ddgsa.gsa.groups`: the
        ``_conf`` columns are the method's error bounds, judged as the parameters' are); empty when
        the space has no groups or the method gives none.
    """

    indices: pd.DataFrame
    n_evals: int
    method: str
    options: dict[str, Any] = field(default_factory=dict)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    extras: dict[str, Any] = field(default_factory=dict)
    groups: pd.DataFrame = field(default_factory=lambda: pd.DataFrame(columns=GROUP_COLUMNS))

    @classmethod
    def from_arrays(cls, *, outputs: Sequence[str], parameters: Sequence[str],
                    S1: NDArray[np.float64], ST: NDArray[np.float64],
                    S1_conf: NDArray[np.float64] | None = None,
                    ST_conf: NDArray[np.float64] | None = None,
                    n_evals: int, method: str, options: dict[str, Any] | None = None,
                    diagnostics: list[Diagnostic] | None = None,
                    extras: dict[str, Any] | None = None,
                    ST_error: NDArray[np.float64] | None = None,
                    ST_diff_error: NDArray[np.float64] | None = None) -> "SobolResult":
        """Build the tidy table from ``(n_outputs, n_params)`` arrays and mark distrust and rank
        confirmation (``ST_error``: the method's estimate of each ST's error, default ``ST_conf``;
        ``ST_diff_error`` (n_outputs, n_params, n_params), where the method gives it: its estimate of the
        error of each difference ``ST_i - ST_j``, :func:`rank_structure`'s ``diff_error``)."""
        shape = (len(outputs), len(parameters))
        nan = np.full(shape, np.nan)

        def arr(a: NDArray[np.float64] | None) -> NDArray[np.float64]:
            return nan if a is None else np.asarray(a, dtype=float).reshape(shape)

        cols = {"S1": arr(S1), "S1_conf": arr(S1_conf), "ST": arr(ST), "ST_conf": arr(ST_conf)}
        table = pd.DataFrame({
            "output": np.repeat(list(outputs), shape[1]),
            "parameter": np.tile(list(parameters), shape[0]),
            **{k: v.ravel() for k, v in cols.items()},
        })
        diags = list(diagnostics or [])
        table["trusted"] = trusted_mask(table, diags)
        err = arr(ST_conf if ST_error is None else ST_error).ravel()
        pairs = None if ST_diff_error is None else \
            np.asarray(ST_diff_error, dtype=float).reshape(shape[0] * shape[1], shape[1])
        claims, ranks = rank_structure(table, err, diags, (options or {}).get("tolerance", 0.02), diff_error=pairs)
        table["rank_confirmed"] = claims > 0
        table["rank"] = ranks
        more = {} if pairs is None else {"rank_diff_error": pairs}
        return cls(indices=table, n_evals=int(n_evals), method=method, options=dict(options or {}),
                   diagnostics=diags, extras={**(extras or {}), "rank_claims": claims, "rank_error": err, **more})

    def rerank(self, margin: float | None = None, floor: float | None = None) -> "SobolResult":
        """This result with its rank claims made again with a tie ``margin`` and a negligible ``floor``
        (:func:`rank_structure`; default: the method's tolerance) [-]; values and trust unchanged."""
        err = self.extras.get("rank_error")
        if err is None:
            return self
        table = self.indices.copy()
        claims, ranks = rank_structure(table, np.asarray(err, dtype=float), self.diagnostics,
                                       self.options.get("tolerance", 0.02), margin, floor,
                                       quantity=self.extras.get("rank_by", "ST"),
                                       diff_error=self.extras.get("rank_diff_error"))
        table["rank_confirmed"] = claims > 0
        table["rank"] = ranks
        return replace(self, indices=table, extras={**self.extras, "rank_claims": claims})

    @property
    def confirmed(self) -> bool:
        """True when every row is ``trusted`` or ``rank_confirmed``."""
        return bool((self.indices["trusted"] | self.indices["rank_confirmed"]).all())

    @property
    def trusted(self) -> bool:
        """True when no row of the table is marked untrusted."""
        return bool(self.indices["trusted"].all())

    def diagnostic_names(self) -> set[str]:
        """Names of the diagnostics that fired."""
        return {d.name for d in self.diagnostics}

    def pivot(self, quantity: str = "ST") -> pd.DataFrame:
        """``quantity`` as an (output x parameter) table."""
        return self.indices.pivot(index="output", columns="parameter", values=quantity)

    def to_frame(self) -> pd.DataFrame:
        """The tidy table with ``method`` and ``n_evals`` columns added."""
        out = self.indices.copy()
        out.insert(0, "method", self.method)
        out["n_evals"] = self.n_evals
        return out

    def _repr_html_(self) -> str:
        """The indices as an HTML table in Jupyter, untrusted rows shaded, with the diagnostics that fired."""
        from ddgsa.gsa.notebook import result_html

        facts = [f"{self.n_evals} model evaluations",
                 "every row trusted" if self.trusted else f"{int((~self.indices['trusted']).sum())} rows untrusted"]
        facts += [f"{d.name} ({d.severity}): {d.message}" for d in self.diagnostics[:5]]
        if len(self.diagnostics) > 5:
            facts.append(f"... and {len(self.diagnostics) - 5} more diagnostics (result.diagnostics)")
        return result_html(f"Sobol indices, method {self.method}", facts, self.indices)

    def diagnostics_frame(self) -> pd.DataFrame:
        """Diagnostics as a table (one row each)."""
        cols = ["name", "severity", "output", "parameter", "value", "message"]
        return pd.DataFrame([d.to_dict() for d in self.diagnostics], columns=cols)

    def plot_bars(self, output: str | None = None, ax: "Axes | None" = None) -> "Axes":
        """Bar chart of S1 and ST (with confidence bars) for one output; untrusted bars hatched."""
        import matplotlib.pyplot as plt

        out = output if output is not None else str(self.indices["output"].iloc[0])
        t = self.indices[self.indices["output"] == out]
        if ax is None:
            _, ax = plt.subplots(figsize=(max(4.0, 0.6 * len(t) + 2), 3.2))
        draw_index_bars(ax, t)
        ax.set_ylabel("Sobol index [-]")
        ax.set_title(f"{out} ({self.method}, {self.n_evals} evals)")
        ax.legend()
        return ax


def draw_index_bars(ax: "Axes", table: pd.DataFrame, fontsize: float = 10.0, rotation: float = 45.0,
                    horizontal: bool = False) -> None:
    """S1 and ST bars of one output's rows, confidence half-widths as error bars (none where the
    method gives no interval), untrusted hatched in white over the bar's colour: dotted where the
    row's place is rank-confirmed, striped where it is neither; ``horizontal``: parameters down the
    y axis (long names read without rotation)."""
    x = np.arange(len(table))
    w = 0.38
    for k, (q, color) in enumerate((("S1", "tab:blue"), ("ST", "tab:orange"))):
        conf = table[f"{q}_conf"].to_numpy(float)
        has = np.isfinite(conf)
        pos, val = x + (k - 0.5) * w, table[q].to_numpy(float)
        bars = (ax.barh(pos, val, w, label=q, color=color) if horizontal
                else ax.bar(pos, val, w, label=q, color=color))
        if has.any():
            err = {"xerr" if horizontal else "yerr": conf[has]}
            ax.errorbar(*((val[has], pos[has]) if horizontal else (pos[has], val[has])), **err, fmt="none",
                        ecolor="0.2", elinewidth=0.8, capsize=2)
        ranked = table["rank_confirmed"].to_numpy(bool) if "rank_confirmed" in table else np.zeros(len(table), bool)
        for bar, ok, placed in zip(bars, table["trusted"].to_numpy(bool), ranked):
            if not ok:
                bar.set_hatch(".." if placed else "///")
                bar.set_edgecolor("white")
                bar.set_linewidth(0.0)
    if horizontal:
        ax.set_yticks(x, table["parameter"].to_list(), fontsize=fontsize)
        if not ax.yaxis_inverted():     # panels sharing y: inverting in each would undo it in every other one
            ax.invert_yaxis()
        ax.set_xlabel("Sobol index [-]", fontsize=fontsize)
    else:
        ax.set_xticks(x, table["parameter"].to_list(), rotation=rotation, ha="right", fontsize=fontsize)
        ax.set_ylabel("Sobol index [-]", fontsize=fontsize)


def trusted_mask(table: pd.DataFrame, diagnostics: list[Diagnostic]) -> NDArray[np.bool_]:
    """Rows not hit by any ``untrusted`` diagnostic and whose S1 and ST are both finite (a row with
    a missing or non-finite index cannot be within any tolerance of the truth)."""
    ok = np.isfinite(table["S1"].to_numpy(float)) & np.isfinite(table["ST"].to_numpy(float))
    for d in diagnostics:
        if d.severity != "untrusted":
            continue
        hit = np.ones(len(table), dtype=bool)
        if d.output is not None:
            hit &= (table["output"] == d.output).to_numpy()
        if d.parameter is not None:
            hit &= (table["parameter"] == d.parameter).to_numpy()
        ok &= ~hit
    return ok


def index_error_rule(name: str) -> bool:
    """Whether diagnostic ``name`` is an error-estimate rule (``*_index_error``): the rules a rank
    confirmation may pass although the value is not within the tolerance."""
    return name.endswith("index_error")


NEGLIGIBLE, SEPARATED, TIED = 1, 2, 3
"""Codes of :func:`rank_claims` (0: no claim)."""


def rank_structure(table: pd.DataFrame, st_error: NDArray[np.float64], diagnostics: list[Diagnostic],
                   tolerance: float, margin: float | None = None, floor: float | None = None,
                   quantity: str = "ST", diff_error: NDArray[np.float64] | None = None
                   ) -> tuple[NDArray[np.int8], NDArray[np.object_]]:
    """Rows whose place in their output's ranking by ``ST`` (or ``quantity``) the error bounds
    guarantee, how, and the ranking as tied groups.

    Each row's total index lies in ``[ST - e, ST + e]`` (``e`` = ``st_error``, the method's
    calibrated estimate) when no other ``untrusted`` rule (one that is not an error-estimate rule:
    sign change, unresolved cut function, failed evaluations...) hits it; a row that such a rule
    hits, or without a finite ``ST`` and ``e``, may hold anything in [0, 1]. A row is
    **rank-confirmed** when either

    * its interval lies within ``[0, floor]``: the parameter is confirmed negligible; the
      negligible parameters form one group whose inner order is not claimed (code :data:`NEGLIGIBLE`), or
    * its interval excludes zero and, against every other row of the output, either the two
      intervals are disjoint (the order is certain) or the interval of the difference,
      ``|ST_i - ST_j| + e_i + e_j``, lies within ``margin``: a **confirmed tie** (an equivalence
      test, two one-sided bounds). A row with no tie has code :data:`SEPARATED`, else :data:`TIED`.
      Where the method bounds the difference itself (``diff_error``: a sampling estimator's two
      estimates share their design, so their errors move together and the difference's bound ``D_ij``
      is often well below ``e_i + e_j``), the pair is also apart when ``|ST_i - ST_j| > D_ij`` and
      tied when ``|ST_i - ST_j| + D_ij <= margin``.
      Ties must form cliques: rows joined by ties into one group are all pairwise tied, or none of
      that group is confirmed (a chain a ~ b ~ c with a, c apart has no well-defined place); and a row
      tied (with overlapping intervals) to a row whose place is not confirmed has no place either (the
      order within the tie is open, so its place moves with the other's).

    Parameters
    ----------
    table : DataFrame
        The indices table (``output, parameter, S1, ST``...).
    st_error : array
        Each row's ST error bound [-].
    diagnostics : list of Diagnostic
        The method's findings (non-error-estimate ``untrusted`` rules void a row's interval).
    tolerance : float
        The trust tolerance [-]: the default of ``margin`` and ``floor``.
    margin : float, optional
        Largest ST difference still called a tie [-] (default ``tolerance``).
    floor : float, optional
        ST below which a parameter is negligible [-] (default ``tolerance``).
    quantity : str
        The column ranked (default ``ST``; Shapley effects rank by ``Sh``), ``st_error`` its error bound.
    diff_error : array (n_rows, m), optional
        Bounds on the differences [-]: ``diff_error[r, c]`` bounds the error of ``ST_r - ST_s``, ``s``
        the ``c``-th row of ``r``'s output in the table's order (``m`` rows an output; NaN: no bound,
        the sum of the two rows' bounds then serves alone).

    Returns
    -------
    codes : ndarray of int8
        Per row: 0 (not confirmed), :data:`NEGLIGIBLE`, :data:`SEPARATED` or :data:`TIED`.
    ranks : ndarray of str
        Per row: the confirmed rank by ST, ``"1"``, ``"2="`` for a tied group (standard competition
        ranking: a group of two at 2 is followed by 4), ``"negligible"``, or ``""`` (not confirmed).
        ``ddgsa bench trust`` scores the claims against the exact indices (false rank-confirmation).

    Examples
    --------
    >>> t = pd.DataFrame({"output": ["y"] * 4, "parameter": list("abcd"), "S1": [0.5, 0.2, 0.2, 0.0],
    ...                   "ST": [0.60, 0.200, 0.205, 0.001]})
    >>> codes, ranks = rank_structure(t, np.array([0.01, 0.004, 0.004, 0.002]), [], 0.02)
    >>> codes.tolist(), ranks.tolist()
    ([2, 3, 3, 1], ['1', '2=', '2=', 'negligible'])
    """
    tol = float(tolerance)
    margin = tol if margin is None else float(margin)
    floor = tol if floor is None else float(floor)
    st = table[quantity].to_numpy(float)
    err = np.asarray(st_error, dtype=float)
    usable = trusted_mask(table, [d for d in diagnostics if not index_error_rule(d.name)]) \
        & np.isfinite(st) & np.isfinite(err)
    lo = np.where(usable, np.clip(st - err, 0.0, 1.0), 0.0)
    hi = np.where(usable, np.clip(st + err, 0.0, 1.0), 1.0)
    codes = np.zeros(len(table), dtype=np.int8)
    ranks = np.full(len(table), "", dtype=object)
    for _, idx in table.groupby("output", sort=False).indices.items():
        neg = usable[idx] & (hi[idx] <= floor)
        codes[idx[neg]] = NEGLIGIBLE
        ranks[idx[neg]] = "negligible"
        both = usable[idx][:, None] & usable[idx][None, :]
        gap = np.abs(st[idx][:, None] - st[idx][None, :])
        bound = err[idx][:, None] + err[idx][None, :]
        apart = (lo[idx][:, None] > hi[idx][None, :]) | (hi[idx][:, None] < lo[idx][None, :])
        with np.errstate(invalid="ignore"):
            if diff_error is not None:             # the difference's own bound, where the method gives one (NaN: none)
                own = np.asarray(diff_error, dtype=float)[idx][:, :len(idx)]
                apart |= both & (gap > own)
                bound = np.fmin(bound, own)
            tied = both & ~neg[:, None] & ~neg[None, :] & (gap + bound <= margin)
        np.fill_diagonal(tied, False)
        ok = usable[idx] & ~neg & (lo[idx] > 0.0)
        ok &= np.all(apart | tied | np.eye(len(idx), dtype=bool), axis=1)
        while True:                # tied (and not apart) with a row whose place is not certain: neither is its own
            loose = ok & np.any(tied & ~apart & ~ok[None, :], axis=1)
            if not loose.any():
                break
            ok &= ~loose
        groups = _tie_groups(tied & ok[:, None] & ok[None, :], ok)
        for g in groups:                       # a chain that is not a clique: no place is claimed
            if len(g) > 1 and not tied[np.ix_(g, g)][~np.eye(len(g), dtype=bool)].all():
                ok[g] = False
        groups = [g for g in groups if ok[g].all()]
        for g in groups:                       # every other row is apart from the group: its place is certain
            place = 1 + int(np.sum(np.delete(st[idx], g) > np.mean(st[idx[g]])))
            codes[idx[g]] = TIED if len(g) > 1 else SEPARATED
            ranks[idx[g]] = f"{place}=" if len(g) > 1 else f"{place}"
    return codes, ranks


def _tie_groups(tied: NDArray[np.bool_], members: NDArray[np.bool_]) -> list[NDArray[np.intp]]:
    """Connected components of the tie graph over the ``members`` (positions within the output)."""
    seen = ~members.copy()
    out = []
    for start in np.flatnonzero(members):
        if seen[start]:
            continue
        comp, todo = [], [start]
        seen[start] = True
        while todo:
            k = todo.pop()
            comp.append(k)
            nxt = np.flatnonzero(tied[k] & ~seen)
            seen[nxt] = True
            todo.extend(nxt.tolist())
        out.append(np.array(sorted(comp), dtype=np.intp))
    return out


def rank_claims(table: pd.DataFrame, st_error: NDArray[np.float64], diagnostics: list[Diagnostic],
                tolerance: float, margin: float | None = None, floor: float | None = None,
                quantity: str = "ST", diff_error: NDArray[np.float64] | None = None) -> NDArray[np.int8]:
    """The codes of :func:`rank_structure` alone (0: no claim)."""
    return rank_structure(table, st_error, diagnostics, tolerance, margin, floor, quantity, diff_error)[0]


def need_per_row(st: NDArray[np.float64], tolerance: float,
                 pair_ratio: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """Bound on each ST that would confirm its row (:func:`rank_claims`, or trusted): the tolerance, or half the row's distance to
    zero and to every other row, whichever is larger (NaN rows: the tolerance).

    ``pair_ratio`` (d, d), where the estimator bounds differences (:func:`difference_ratio`): each pair's
    bound on ``ST_i - ST_j`` over the sum of the two rows' bounds. The pair is then apart once ``ratio (e_i +
    e_j)`` is below its distance ``g`` and tied once it is below ``margin - g`` (the margin is the
    tolerance): each row needs ``max(g, tolerance - g) / (2 ratio)`` against each other row, and half its
    distance to zero. With a ratio of 1 this is the rule above."""
    st = np.asarray(st, dtype=float)
    need = np.full(len(st), tolerance)
    for i in range(len(st)):
        if np.isfinite(st[i]):
            gaps = np.abs(st[i] - np.delete(st, i))
            if pair_ratio is not None:
                ratio = np.clip(np.nan_to_num(np.delete(np.asarray(pair_ratio, dtype=float)[i], i), nan=1.0), 1e-3, 1.0)
                gaps = np.fmax(gaps, np.where(gaps < tolerance, tolerance - gaps, 0.0)) / ratio
            gap = min(st[i], np.nanmin(gaps, initial=np.inf))
            need[i] = max(tolerance, gap / 2.0)
    return need


def difference_ratio(result: SobolResult, output: str) -> NDArray[np.float64] | None:
    """Per pair of ``output``'s rows (d, d), the bound ``result`` gives their ST difference over the sum of
    their own bounds (at most 1; NaN where it gives none), or None where it bounds no difference: what
    :func:`need_per_row` scales a pair's need by."""
    pairs = result.extras.get("rank_diff_error")
    if pairs is None:
        return None
    rows = np.flatnonzero(result.indices["output"].to_numpy() == output)
    err = np.asarray(result.extras["rank_error"], dtype=float)[rows]
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.asarray(pairs, dtype=float)[rows][:, :len(rows)] / (err[:, None] + err[None, :])
    return np.fmin(ratio, 1.0)


CONSTANT_CV = 1e-9
"""An output whose standard deviation over a scene's points is at most this fraction of its mean is
constant to the model's numerical noise (solver tolerances leave ~1e-10 relative; a physical
sensitivity that small is beyond any engineering use): no parameter moves it, there is nothing to rank."""


def nothing_to_rank(values: NDArray[np.float64], resolution: float = 0.0) -> bool:
    """Whether the finite ``values`` (an output over a design) spread no more than the output's
    ``resolution`` (the model's declared noise, in the output's unit) or than :data:`CONSTANT_CV` of
    their mean (the numerical floor): no parameter moves the output by more than the model can tell
    from its noise, so there is nothing to rank (False with fewer than two values).

    Examples
    --------
    >>> nothing_to_rank(np.array([1.2e-5, 1.5e-5, 0.9e-5]), resolution=0.05)   # 3e-6 N m against 0.05 N m noise
    True
    >>> nothing_to_rank(np.array([1.0, 2.0, 3.0]), resolution=0.05)
    False
    """
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if len(v) < 2:
        return False
    return bool(below_resolution(float(np.std(v, ddof=1)), float(np.mean(v)), resolution) or np.ptp(v) == 0)


def below_resolution(std: float, mean: float, resolution: float = 0.0) -> bool:
    """The rule of :func:`nothing_to_rank` on an output's standard deviation and mean [unit]."""
    return bool(np.isfinite(std) and np.isfinite(mean) and std <= max(float(resolution), CONSTANT_CV * abs(mean)))
