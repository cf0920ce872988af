"""Issue 25: ``auto`` never hides a finite answer, scale-free estimators, ``rank_confirmed``.

Every number is compared with a closed form (``product``, ``linear``: :mod:`ddgsa.gsa.testfunctions`)
or with the same method on the unscaled output.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import ddgsa
from ddgsa.bench.calibration import false_rank_claims
from ddgsa.gsa.result import NEGLIGIBLE, SEPARATED, TIED, Diagnostic, rank_claims, rank_structure
from ddgsa.gsa.testfunctions import linear, product
from ddgsa.gsa.space import ParameterSpace

UNIT3 = ParameterSpace.from_dict({f"x{i + 1}": {"low": 0.0, "high": 1.0} for i in range(3)})


def _three(x: np.ndarray) -> np.ndarray:
    """The calibration's ``several_outputs``: a product, an interacting sum, an exponential."""
    return np.column_stack([(1 + x[:, 0]) * (2 + x[:, 1]) * (3 + x[:, 2]),
                            5.0 + x[:, 0] + 2.0 * x[:, 1] ** 2 + x[:, 0] * x[:, 2],
                            np.exp(x[:, 0] * x[:, 1]) + x[:, 2]])


@pytest.mark.parametrize("method, opts", [("mdrm", {}), ("pce", {"order": 4}), ("pce", {"fit": "sparse", "order": 5}),
                                          ("saltelli", {"n": 256}), ("fast", {"n": 256}), ("rbd_fast", {"n": 256}),
                                          ("auto", {"budget": 300}), ("saltelli", {"n": 256, "control": "gp"})])
def test_every_method_is_scale_free(method: str, opts: dict) -> None:
    """The same indices and flags for an output in any units (x 1e-12, x 1e12). The outputs are
    standardised first, to within round-off (1e-16); the controlled Saltelli's process solve
    (condition up to 1e6) carries that to ~1e-7 in its indices, hence its looser tolerance."""
    base = ddgsa.sobol(_three, UNIT3, method, **opts).indices
    atol = 1e-5 if opts.get("control") == "gp" else 1e-9
    for c in (1e-12, 1e12):
        got = ddgsa.sobol(lambda x, c=c: c * _three(x), UNIT3, method, **opts).indices
        np.testing.assert_allclose(got[["S1", "ST"]].to_numpy(float), base[["S1", "ST"]].to_numpy(float),
                                   atol=atol, rtol=0)
        pd.testing.assert_frame_equal(got[["trusted", "rank_confirmed"]], base[["trusted", "rank_confirmed"]])


def test_sparse_pce_of_a_damage_rate_sized_output_is_finite() -> None:
    """Audit: a sparse PCE of an output ~1e-9 gave NaN indices with no diagnostic (the least-angle
    path selected no term); standardised first, it matches the closed form like the output x 1."""
    space = ParameterSpace.from_dict({f"x{i + 1}": {"low": 1.0, "high": 2.0} for i in range(4)})
    tf = linear(space, [1.0, 0.8, 0.5, 0.2], offset=3.0)
    res = ddgsa.sobol(lambda x: 1e-9 * tf.f(x), space, "pce", fit="sparse", order=3)
    np.testing.assert_allclose(res.indices["S1"], tf.S1, atol=1e-6)
    np.testing.assert_allclose(res.indices["ST"], tf.ST, atol=1e-6)
    assert res.trusted


def test_auto_keeps_the_rows_mdrm_trusted_on_a_heavy_tailed_product() -> None:
    """Audit: on a product of lognormal inputs M-DRM (exact on products) trusted two of three rows,
    ``auto`` threw the stage away (one row untrusted) and answered NaN (the last sparse PCE,
    preferred with an error scored 0). Now every index is finite and the trusted rows are M-DRM's."""
    space = ParameterSpace.from_dict({f"x{i + 1}": {"dist": "lognormal", "mu": 0.0, "sigma": s}
                                      for i, s in enumerate((1.0, 0.8, 0.5))})
    tf = product(space, [1.0, 1.0, 1.0])
    res = ddgsa.sobol(tf.f, space, "auto", budget=300)
    t = res.indices
    assert np.isfinite(t[["S1", "ST"]].to_numpy(float)).all()
    assert t["trusted"].tolist() == [False, True, True]              # x1: 56 % beyond the outer nodes
    assert set(t.loc[t["trusted"], "source"]) == {"mdrm"}
    np.testing.assert_allclose(t["S1"], tf.S1, atol=1e-9)           # the untrusted row: M-DRM's too
    np.testing.assert_allclose(t["ST"], tf.ST, atol=1e-9)
    assert "auto_budget_exhausted" in res.diagnostic_names()
    # every untrusted row is explained by an untrusted diagnostic on that row
    for row in t[~t["trusted"]].itertuples():
        assert any(d.severity == "untrusted" and d.output in (None, row.output) and d.parameter in (None, row.parameter)
                   for d in res.diagnostics)


def test_auto_reports_moments_of_its_sampled_points() -> None:
    space = ParameterSpace.from_dict({f"x{i + 1}": {"low": 0.0, "high": 1.0} for i in range(3)})
    tf = linear(space, [1.0, 2.0, 3.0], offset=1.0)
    res = ddgsa.sobol(tf.f, space, "auto", budget=300)
    m = res.extras["moments"]
    assert m["n"] == res.n_evals - (3 * 5 + 1)                         # every point but the cut lines
    assert m["mean"][0] == pytest.approx(1.0 + 3.0, abs=0.02)          # E = 1 + (1 + 2 + 3) / 2
    assert m["std"][0] == pytest.approx(np.sqrt(14 / 12), rel=0.05)    # Var = (1 + 4 + 9) / 12


def _table(st: list[float], output: str = "y") -> pd.DataFrame:
    return pd.DataFrame({"output": output, "parameter": [f"p{i}" for i in range(len(st))], "S1": st, "ST": st})


def test_rank_claims_by_hand() -> None:
    t = _table([0.6, 0.3, 0.05, 0.01])
    # intervals [0.55, 0.65], [0.25, 0.35], [0.03, 0.07], [0.005, 0.015]: all apart, the last within [0, 0.02]
    got = rank_claims(t, np.array([0.05, 0.05, 0.02, 0.005]), [], 0.02)
    assert got.tolist() == [SEPARATED, SEPARATED, SEPARATED, NEGLIGIBLE]
    # p2's interval [0.005, 0.095] overlaps p3's [0.005, 0.015]: p2 no longer placed, p3 still negligible
    got = rank_claims(t, np.array([0.05, 0.05, 0.045, 0.005]), [], 0.02)
    assert got.tolist() == [SEPARATED, SEPARATED, 0, NEGLIGIBLE]
    # p1 hit by a rule other than the error estimate: it may be anywhere in [0, 1]; its neighbours
    # cannot be placed against it, p3 is still negligible
    sign = [Diagnostic("mdrm_sign_change", "", "untrusted", output="y", parameter="p1")]
    got = rank_claims(t, np.array([0.05, 0.05, 0.02, 0.005]), sign, 0.02)
    assert got.tolist() == [0, 0, 0, NEGLIGIBLE]
    # an error-estimate rule does not stop a rank claim (that is its point)
    err = [Diagnostic("pce_index_error", "", "untrusted", output="y", parameter="p0")]
    assert rank_claims(t, np.array([0.05, 0.05, 0.02, 0.005]), err, 0.02)[0] == SEPARATED


def test_ties_and_the_negligible_group_by_hand() -> None:
    """Issue 51: ST 0.100 and 0.102 with bounds 0.004 can never be ordered (their intervals overlap for
    ever) but their difference lies in [-0.006, 0.010], inside the margin 0.02: a confirmed tie; twenty
    inert parameters below the floor form one negligible group; the ranking reads 1, 2=, 2=, negligible."""
    st = [0.7, 0.102, 0.100] + [0.001] * 20
    t = _table(st)
    err = np.array([0.01, 0.004, 0.004] + [0.003] * 20)
    codes, ranks = rank_structure(t, err, [], 0.02)
    assert codes.tolist() == [SEPARATED, TIED, TIED] + [NEGLIGIBLE] * 20
    assert ranks.tolist()[:4] == ["1", "2=", "2=", "negligible"]
    # a margin below the difference interval's reach (0.010): no tie is claimed, nothing placed but p0
    codes, _ = rank_structure(t, err, [], 0.02, margin=0.005)
    assert codes.tolist()[:3] == [SEPARATED, 0, 0]
    # a floor below the inert rows' upper bound (0.004): they are no longer negligible, and with
    # overlapping intervals around zero no place is certain for them
    codes, _ = rank_structure(t, err, [], 0.02, floor=0.003)
    assert codes.tolist()[3:] == [0] * 20


def test_a_tie_chain_that_is_not_a_clique_is_not_confirmed() -> None:
    """a ~ b and b ~ c within the margin but a, c apart: b has no well-defined place, so none of the
    chain is claimed; competition ranking skips places after a tied group."""
    t = _table([0.50, 0.30, 0.2875, 0.275, 0.05])
    err = np.array([0.01, 0.002, 0.002, 0.002, 0.01])
    codes, ranks = rank_structure(t, err, [], 0.02)
    # 0.30 ~ 0.2875 (0.0165), 0.2875 ~ 0.275 (0.0165), but 0.30 vs 0.275: 0.029 > 0.02 and apart
    assert codes.tolist() == [SEPARATED, 0, 0, 0, SEPARATED]
    assert ranks.tolist() == ["1", "", "", "", "5"]
    codes, ranks = rank_structure(_table([0.5, 0.3, 0.295, 0.1]), np.array([0.01, 0.002, 0.002, 0.01]), [], 0.02)
    assert ranks.tolist() == ["1", "2=", "2=", "4"]


def test_a_row_tied_to_a_row_without_a_place_has_no_place() -> None:
    """Calibration on the held-out block sums (issue 51): x3 overlaps and is tied with x1 (0.006 + 0.010 within
    the margin) and apart from everything else, but x1 overlaps x0, so x1's place is open and with it x3's
    (x1 above or below x3 moves x3 between 2nd and 3rd): before, x3 was claimed 2nd on its own."""
    t = _table([0.285, 0.300, 0.306, 0.6])
    codes, ranks = rank_structure(t, np.array([0.010, 0.006, 0.004, 0.01]), [], 0.02)
    assert codes.tolist() == [0, 0, 0, SEPARATED] and ranks.tolist() == ["", "", "", "1"]


def test_false_tie_claims_against_the_truth() -> None:
    est = np.array([[0.5, 0.30, 0.295, 0.1]])
    claims = np.array([[SEPARATED, TIED, TIED, SEPARATED]])
    ranks = np.array([["1", "2=", "2=", "4"]], dtype=object)
    assert not false_rank_claims(est, np.array([[0.5, 0.29, 0.30, 0.1]]), claims, 0.02, ranks).any()
    # the truth 0.03 apart: both tied rows are false; p3 is truly above p1, false too
    bad = false_rank_claims(est, np.array([[0.5, 0.32, 0.29, 0.31]]), claims, 0.02, ranks)
    assert bad.tolist() == [[False, True, True, True]]


def test_false_rank_claims_against_the_truth() -> None:
    est = np.array([[0.6, 0.3, 0.05, 0.01]])
    claims = np.array([[SEPARATED, SEPARATED, SEPARATED, NEGLIGIBLE]])
    ok = false_rank_claims(est, np.array([[0.5, 0.35, 0.04, 0.0]]), claims, 0.02)
    assert not ok.any()
    # p1 and p2 swapped in truth, p3 not negligible; p0 is still above all
    bad = false_rank_claims(est, np.array([[0.5, 0.04, 0.35, 0.03]]), claims, 0.02)
    assert bad.tolist() == [[False, True, True, True]]
    # a true tie with a row it claims to be above, a true zero
    assert false_rank_claims(est, np.array([[0.5, 0.5, 0.04, 0.0]]), claims, 0.02)[0, :2].tolist() == [True, True]
    assert false_rank_claims(np.array([[0.6, 0.3]]), np.array([[0.5, 0.0]]), np.array([[SEPARATED, SEPARATED]]),
                             0.02).tolist() == [[False, True]]


def test_saltelli_size_to_confirm_by_hand() -> None:
    """Error bound 3.3 sqrt(ST / N) (``SALTELLI_K``); each row needs max(tolerance, half its distance
    to zero and to the nearest other row)."""
    from ddgsa.gsa.salib import MAX_N, SALTELLI_K, saltelli_n_to_confirm

    assert SALTELLI_K == 3.3
    # 0.6 needs 0.15: 3.3^2 0.6 / 0.15^2 = 290 -> 512 (0.3: 145)
    assert saltelli_n_to_confirm(np.array([0.6, 0.3]), 0.02) == 512
    # a zero row needs 0.02 at ST 0.001: 27 -> the others still decide
    assert saltelli_n_to_confirm(np.array([0.6, 0.3, 0.0]), 0.02) == 512
    assert saltelli_n_to_confirm(np.array([0.6, np.nan]), 0.02) == 32768     # unknown: ST 1 within 0.02, 27 225
    assert saltelli_n_to_confirm(np.array([0.9, 0.89]), 0.05) == 4096        # 0.05 at 0.9: 3 920
    # 0.6 and 0.57: 0.02 (trusted) at 0.6: 16 335 -> 16 384; where a stage measured the pair's own bound at
    # half its rows' sum, the pair is apart once each row's bound is below 0.03 / (2 x 0.5): 7 260 -> 8 192
    assert saltelli_n_to_confirm(np.array([0.6, 0.57]), 0.02) == 16384
    half = np.full((2, 2), 0.5)
    assert saltelli_n_to_confirm(np.array([0.6, 0.57]), 0.02, pair_ratio=half) == 8192
    assert saltelli_n_to_confirm(np.array([0.6, 0.57]), 0.02, pair_ratio=np.ones((2, 2))) == 16384
    # a base that ran and did not confirm is doubled (the escalation's rule and the next step's), within the cap
    assert saltelli_n_to_confirm(np.array([0.6, 0.3]), 0.02, ran=1024) == 2048
    assert saltelli_n_to_confirm(np.array([0.6, 0.3]), 0.02, ran=256) == 512
    assert saltelli_n_to_confirm(np.array([0.6, 0.57]), 0.02, ran=MAX_N) == MAX_N


def test_pooled_pce_on_mdrm_points_matches_the_closed_form() -> None:
    """Zero extra runs: a sparse PCE on M-DRM's cut lines and check sample recovers a cubic
    product's indices (closed form) and trusts them (leave-one-out error ~ round-off). (With a
    16-point check sample it selects wrong terms, off by 0.10, and says so: bounds 0.33.)"""
    from ddgsa.gsa import get_method
    from ddgsa.gsa.pooled import pooled_order, pooled_pce

    assert pooled_order(3, 37) == 5          # 56 terms <= 2 x 37
    assert pooled_order(10, 83) == 2         # 66 <= 166 < 286
    assert pooled_order(50, 10) == 0         # 51 terms > 20
    space = ParameterSpace.from_dict({f"x{i + 1}": {"low": 0.0, "high": 1.0} for i in range(3)})
    tf = product(space, [0.5, 0.4, 0.3])
    x = get_method("mdrm").design(space, points=5, check=32).points
    res = pooled_pce(space, x, tf.f(x)[:, None], ["y"])
    assert res is not None and res.method == "pooled_pce" and res.n_evals == len(x) == 3 * 5 + 1 + 32
    np.testing.assert_allclose(res.indices["S1"], tf.S1, atol=1e-8)
    np.testing.assert_allclose(res.indices["ST"], tf.ST, atol=1e-8)
    assert res.trusted


def test_the_cost_per_run_is_not_inflated_by_the_first_runs_compile() -> None:
    """A fresh install's first evaluations compile the kernels (minutes); the cost to confirm uses the
    median run, so one 130 s compile among 10-12 s runs leaves the estimate at the runs' own cost."""
    from types import SimpleNamespace

    from ddgsa.execute.confirm import per_run_seconds

    runs = SimpleNamespace(evaluations=pd.DataFrame({"seconds": [130.0, 10.0, 12.0, 11.0, 11.0, 0.0]}))
    assert per_run_seconds(runs) == 11.0
    assert np.isnan(per_run_seconds(SimpleNamespace(evaluations=pd.DataFrame({"seconds": [0.0]}))))


def test_loo_error_over_the_drawn_points_equals_brute_force_refits() -> None:
    # a pooled design: 9 cut-line points (not draws) and 24 draws; the leave-one-out mean square
    # taken over the draws only must equal refitting without each draw in turn
    from ddgsa.gsa.pce import _least_squares

    rng = np.random.default_rng(3)
    x = np.vstack([np.column_stack([np.linspace(-1, 1, 9), np.zeros(9)]), rng.uniform(-1, 1, (24, 2))])
    psi = np.column_stack([np.ones(len(x)), x, x[:, 0] * x[:, 1]])
    y = (np.sin(2 * x[:, 0]) + x[:, 0] * x[:, 1] ** 2)[:, None]
    drawn = np.arange(len(x)) >= 9
    sq = []
    for i in np.flatnonzero(drawn):
        keep = np.arange(len(x)) != i
        c, *_ = np.linalg.lstsq(psi[keep], y[keep], rcond=None)
        sq.append(float((y[i, 0] - psi[i] @ c[:, 0]) ** 2))
    _, loo, _ = _least_squares(psi, y, drawn)
    assert loo[0] * np.var(y) == pytest.approx(np.mean(sq), rel=1e-9)
    _, loo_all, _ = _least_squares(psi, y)
    assert loo_all[0] != pytest.approx(loo[0], rel=1e-3)          # the cut lines do change the mean


def test_advice_after_a_stopped_escalation_asks_for_saltelli_not_a_larger_budget() -> None:
    """Where the study's ``confirm:`` escalation stopped (the pooled PCE's bound did not shrink and no
    Saltelli base fitted its budget), the advice names the Saltelli design and says a larger budget helps
    only as far as it pays for it; elsewhere it offers the budget (the one that pays for that design)."""
    from types import SimpleNamespace

    from ddgsa.execute.confirm import advice

    rows = pd.DataFrame({"scene": 0, "output": "y", "parameter": ["a", "b"], "ST": [0.5, 0.5]})
    study = SimpleNamespace(spec=SimpleNamespace(scenes=SimpleNamespace(realisations=1)), targets=[])
    log = ["pce (+41 runs, 41 of 512): unconfirmed: y", "stopped with 389 of 512 runs left: ..."]
    stopped = SimpleNamespace(indices=rows, study=study, evaluations=pd.DataFrame({"seconds": [2.0]}),
                              provenance={"confirm": [{"scene": 0, "budget": 512, "spent": 123, "log": log}]})
    text = advice(stopped, "y", [0])
    assert "add `saltelli` with n: " in text and "escalation stopped in scene 0" in text
    assert "helps only as far as it pays for that Saltelli design" in text and "confirm: {budget" not in text
    fresh = SimpleNamespace(**{**vars(stopped), "provenance": {}})
    assert "or `confirm: {budget: " in advice(fresh, "y", [0])


def test_advice_counts_the_runs_of_the_method_it_suggests() -> None:
    """A `saltelli` method added to a study runs in every scene at one ``n``: the advice quotes that,
    the largest ``n`` any unconfirmed scene needs times ``(d + 2)`` points times the realisations in
    every scene (a newcomer trial found 'n: 4096 (532 480 runs)' where 4 096 in three scenes is 798 720).
    Here scene 0 needs n = 256 (ST 0.7 / 0.3, as in test_report) and scene 1 is confirmed: 2 x 256 x 4 x 3."""
    from types import SimpleNamespace

    from ddgsa.execute.confirm import advice, cost_to_confirm

    rows = pd.DataFrame({"scene": [0, 0, 1, 1], "output": "y", "parameter": ["a", "b", "a", "b"],
                         "ST": [0.7, 0.3, 0.9, 0.0]})
    study = SimpleNamespace(spec=SimpleNamespace(scenes=SimpleNamespace(realisations=3)), targets=[])
    res = SimpleNamespace(indices=rows, study=study, evaluations=pd.DataFrame({"seconds": [1.0]}), provenance={})
    n = cost_to_confirm(res, 0, "y").n
    assert n == 256
    assert f"n: {n} ({2 * n * 4 * 3:,} runs".replace(",", " ") in advice(res, "y", [0])


def test_a_bound_on_the_difference_places_rows_whose_intervals_overlap() -> None:
    """Issue 51.1, "a difference whose interval...": ST 0.60 and 0.55 with bounds 0.04 each overlap (no
    order), but a bound of 0.03 on their difference itself (both estimates from one design) orders them;
    0.30 and 0.29 with bounds 0.02 each are no tie at margin 0.02 (0.01 + 0.04), but are with a bound of
    0.008 on the difference (0.018); a NaN bound leaves the rule of the two rows' bounds."""
    t = _table([0.60, 0.55, 0.30, 0.29, 0.005])
    err = np.array([0.04, 0.04, 0.02, 0.02, 0.004])
    assert rank_claims(t, err, [], 0.02).tolist() == [0, 0, 0, 0, NEGLIGIBLE]
    pairs = np.full((5, 5), np.nan)
    pairs[0, 1] = pairs[1, 0] = 0.03
    pairs[2, 3] = pairs[3, 2] = 0.008
    codes, ranks = rank_structure(t, err, [], 0.02, diff_error=pairs)
    assert codes.tolist() == [SEPARATED, SEPARATED, TIED, TIED, NEGLIGIBLE]
    assert ranks.tolist() == ["1", "2", "3=", "3=", "negligible"]
    pairs[0, 1] = pairs[1, 0] = 0.06                 # looser than its rows' sum: no help, no harm
    assert rank_claims(t, err, [], 0.02, diff_error=pairs).tolist()[:2] == [0, 0]


def test_saltelli_bounds_its_differences_and_they_cover() -> None:
    """The plain and the controlled Saltelli estimators bound each difference ST_i - ST_j by their rows'
    rule on the difference: on Ishigami (exact ST 0.558, 0.442, 0.244) at N = 512 the bound of every
    pair covers the exact difference in at least 9 of 10 seeds (95 % intervals), and for x1 - x2, whose
    estimates share the runs where x1 and x2 both vary, it is below the sum of the rows' bounds."""
    from ddgsa.gsa.testfunctions import ishigami

    tf = ishigami()
    exact = tf.ST[:, None] - tf.ST[None, :]
    covered, narrower = np.zeros((3, 3)), 0
    for seed in range(10):
        res = ddgsa.sobol(tf.f, tf.space, method="saltelli", n=512, seed=seed)
        pairs = res.extras["rank_diff_error"]                # (d, d): one output
        st = res.indices["ST"].to_numpy(float)
        err = res.extras["rank_error"]
        covered += np.abs(st[:, None] - st[None, :] - exact) <= pairs
        narrower += pairs[0, 1] < err[0] + err[1]
    assert covered.min() >= 9 and narrower >= 8
    res = ddgsa.sobol(tf.f, tf.space, method="saltelli", n=256, control="gp", seed=1)
    pairs = res.extras["rank_diff_error"]
    st = res.indices["ST"].to_numpy(float)
    assert np.all(np.abs(st[:, None] - st[None, :] - exact) <= pairs + 1e-12)
    assert np.allclose(np.diag(pairs), 0.0)


def test_advice_leads_with_the_budget_the_escalation_asked_for_where_it_is_cheaper() -> None:
    """Where the escalation ended with the output unconfirmed it recorded what its cost rule asked for (a
    controlled Saltelli base N and the new points of that design): the advice names the budget that pays for
    it (points spent + new points, here 21 439 + 20 480) with its runs (x 2 realisations) and model time, and
    leads with it when it is cheaper than adding a plain `saltelli` method (n = 256 in every scene: ST 0.7 and
    0.3, 2 scenes x 256 x 4 x 2 = 4 096 runs here, so the plain design leads; a larger plain need reverses it)."""
    from types import SimpleNamespace

    from ddgsa.execute.confirm import advice, budget_cost

    log = ["saltelli (+10240 runs, 21439 of 24576): unconfirmed: y", "stopped with 3137 of 24576 runs left: ..."]
    entry = {"scene": 0, "budget": 24576, "spent": 21439, "log": log, "asks": {"y": {"n": 4096, "points": 20480}}}
    study = SimpleNamespace(spec=SimpleNamespace(scenes=SimpleNamespace(realisations=2)), targets=[])

    def result(st: list[float]) -> SimpleNamespace:
        rows = pd.DataFrame({"scene": [0, 0, 1, 1], "output": "y", "parameter": ["a", "b", "a", "b"],
                             "ST": st + [0.9, 0.0]})
        return SimpleNamespace(indices=rows, study=study, evaluations=pd.DataFrame({"seconds": [0.5]}),
                               provenance={"confirm": [entry]})

    grow = budget_cost(result([0.7, 0.3]), "y", [0])
    assert (grow.budget, grow.n, grow.runs, grow.seconds) == (21439 + 20480, 4096, 40960, 20480.0)
    assert budget_cost(result([0.7, 0.3]), "y", [1]) is None          # the escalation asked nothing there
    plain = advice(result([0.7, 0.3]), "y", [0])
    assert plain.startswith("to confirm it add `saltelli` with n: 256 (4 096 runs")
    assert "; or raise the study's `confirm: {budget: 41919}`" in plain and "N = 4096 (up to 40 960 new runs" in plain
    near = advice(result([0.51, 0.49]), "y", [0])                    # a near tie: the plain design is dear
    assert near.startswith("raise the study's `confirm: {budget: 41919}`") and "; or to confirm it add `saltelli`" in near


def test_the_budget_step_counts_every_scene_it_lets_escalate_and_never_misleads() -> None:
    """The ``confirm:`` budget is one for every scene: raised to pay for scene 0's largest ask (its escalation
    plans one design for all its unconfirmed outputs: 5 000 new points for z, so y's budget is 1 000 + 5 000),
    scene 1, also left unconfirmed, may spend up to it too (6 000 - 3 000 more): 8 000 points, x 2
    realisations. A time-stopped escalation is told to take more time, never a budget below the one it had; a
    budget no study may set never leads; scenes the escalation asked nothing for are named as such."""
    from types import SimpleNamespace

    from ddgsa.execute.confirm import advice, budget_cost, leading_cost
    from ddgsa.gsa.escalate import MAX_BUDGET

    study = SimpleNamespace(spec=SimpleNamespace(scenes=SimpleNamespace(realisations=2)), targets=[])
    asks0 = {"y": {"n": 512, "points": 1000, "control": True}, "z": {"n": 2048, "points": 5000, "control": True}}
    asks1 = {"z": {"n": 1024, "points": 2000, "control": False}}

    def result(entries: list[dict], st: list[float] = [0.7, 0.3]) -> SimpleNamespace:
        rows = pd.DataFrame({"scene": [0, 0, 1, 1, 2, 2], "output": "y", "parameter": ["a", "b"] * 3, "ST": st * 3})
        return SimpleNamespace(indices=rows, study=study, evaluations=pd.DataFrame({"seconds": [0.5]}),
                               provenance={"confirm": entries})

    budget = [{"scene": 0, "budget": 2000, "spent": 1000, "log": ["budget of 2000 runs spent; unconfirmed: y, z"],
               "asks": asks0},
              {"scene": 1, "budget": 2000, "spent": 3000, "log": ["..."], "asks": asks1},
              {"scene": 2, "budget": 2000, "spent": 400, "log": ["every output confirmed"], "asks": {}}]
    grow = budget_cost(result(budget), "y", [0])
    assert (grow.budget, grow.n, grow.runs, grow.scenes, grow.timed) == (6000, 2048, (5000 + 3000) * 2, (0,), False)
    text = advice(result(budget), "y", [0, 2])
    assert "`confirm: {budget: 6000}`" in text and "ended in scene 0," in text
    assert "in scene 2 the escalation asked nothing for it" in text
    # stopped by its time limit: more time, not a budget (6 000 would be below no budget at all here)
    timed = [{**budget[0], "budget": None, "time_s": 60.0,
              "log": ["stopped by the time budget (60 s): the next stage's 5000 runs would take ~2 min"]}]
    grow = budget_cost(result(timed), "y", [0])
    assert grow.timed and grow.runs == 5000 * 2
    # the flag a run writes decides, not the log's wording (provenance before the flag: the log line)
    assert budget_cost(result([{**timed[0], "log": ["reworded"], "stopped_by_time": True}]), "y", [0]).timed
    assert not budget_cost(result([{**timed[0], "stopped_by_time": False}]), "y", [0]).timed
    text = advice(result(timed), "y", [0])
    assert "give the study's `confirm:` more time" in text and "budget:" not in text.split("; or ")[0]
    # a budget past what a study may set is named but never leads, however cheap it looks
    huge = [{**budget[0], "spent": MAX_BUDGET}]
    _, runs, _, grow, leads = leading_cost(result(huge, [0.51, 0.49]), "y", [0])
    assert grow.budget > MAX_BUDGET and grow.runs < runs and not leads
    text = advice(result(huge, [0.51, 0.49]), "y", [0])
    assert text.startswith("to confirm it add `saltelli`") and "past the largest budget a study may set" in text


@pytest.mark.slow
def test_the_budget_the_advice_names_runs_the_design_the_escalation_asked_for() -> None:
    """The g-function's kink with a 3 000-run budget: the escalation runs Saltelli N = 128 (what the budget
    allows) and stops asking N = 512, 2 304 new points; rerun with the budget it names (2 411 spent + 2 304),
    it runs exactly that design, N = 512 (3 072 points, the first 768 the same), and spends nothing more (about
    7 s). Whether N = 512 confirms is the cost rule's estimate: here it does not (nor does N = 2 048, in
    tests/gsa/test_escalate.py), and the rerun asks twice it."""
    from ddgsa.gsa.escalate import confirm
    from ddgsa.gsa.testfunctions import sobol_g

    g4 = sobol_g([0.0, 1.0, 4.5, 9.0])
    first = confirm(g4.f, g4.space, "mdrm", budget=3000, points=5)
    spent = first.n_evals - (4 * 5 + 1 + 32)
    assert not first.confirmed["y"] and first.asks == {"y": {"n": 512, "points": 2304, "control": True}} and spent == 2411
    again = confirm(g4.f, g4.space, "mdrm", budget=spent + first.asks["y"]["points"], points=5)
    assert any(line.startswith("next: saltelli N=512 (3072 new runs") for line in again.log)
    assert again.n_evals == first.n_evals + 2304 and again.asks["y"]["n"] == 1024


def test_the_plain_designs_cost_weighs_each_pair_by_the_bound_a_saltelli_stage_measured_on_it() -> None:
    """Ishigami's x1 and x2 (exact ST 0.558 and 0.442) from a Saltelli run at N = 512 in scene 0: the cost of
    confirming them weighs the pair by the ratio the run measured, its difference's bound over the sum of the
    rows' (below 1: their estimates share runs; test_saltelli_size_to_confirm_by_hand has the rule's numbers), so
    it asks no more than without the run; scene 1 has no Saltelli run and keeps the rows' rule -- until a
    Saltelli base ran there without confirming the pair: then at least twice that base."""
    from types import SimpleNamespace

    from ddgsa.execute.confirm import cost_to_confirm
    from ddgsa.gsa.result import difference_ratio
    from ddgsa.gsa.salib import saltelli_n_to_confirm
    from ddgsa.gsa.testfunctions import ishigami

    tf = ishigami()
    res = ddgsa.sobol(tf.f, tf.space, method="saltelli", n=512, seed=3)
    rows = pd.DataFrame({"scene": [0] * 3 + [1] * 3, "output": "y", "parameter": ["x1", "x2", "x3"] * 2,
                         "ST": list(tf.ST) * 2})
    study = SimpleNamespace(spec=SimpleNamespace(scenes=SimpleNamespace(realisations=1)), targets=[])
    ran = SimpleNamespace(indices=rows, study=study, evaluations=pd.DataFrame({"seconds": [1.0]}), provenance={},
                          results=[(SimpleNamespace(index=0), res)])
    ratio = difference_ratio(res, "y")
    assert 0.0 < ratio[0, 1] < 1.0
    assert cost_to_confirm(ran, 0, "y").n == saltelli_n_to_confirm(tf.ST, 0.02, pair_ratio=ratio)
    assert cost_to_confirm(ran, 0, "y").n <= cost_to_confirm(ran, 1, "y").n == saltelli_n_to_confirm(tf.ST, 0.02)
    # the escalation's controlled base N = 4 096 ran in scene 1 and left the pair unconfirmed: twice it
    stage = SimpleNamespace(method="confirm_saltelli", options={"n": 4096}, extras={}, indices=res.indices)
    failed = SimpleNamespace(**{**vars(ran), "results": [(SimpleNamespace(index=1), stage)]})
    assert saltelli_n_to_confirm(tf.ST, 0.02) < 8192 == cost_to_confirm(failed, 1, "y").n


def test_the_advice_cautions_where_a_saltelli_stage_found_a_tail_with_no_finite_mean() -> None:
    """A ``heavy_tail`` diagnostic of a Saltelli result with a shape at or above 1 (the fitted Pareto tail has no
    finite mean: on the rig's coast-down 1.1-3.5 from N = 2 048 to 8 192 while nothing confirmed) adds a caution to
    the pair's next step naming the parameter, the shape and the base; a shape below 1, another output or another
    scene's result adds none."""
    from types import SimpleNamespace

    from ddgsa.execute.confirm import advice
    from ddgsa.gsa.testfunctions import ishigami

    tf = ishigami()
    res = ddgsa.sobol(tf.f, tf.space, method="saltelli", n=512, seed=3)
    rows = pd.DataFrame({"scene": [0] * 3 + [1] * 3, "output": "y", "parameter": ["x1", "x2", "x3"] * 2,
                         "ST": list(tf.ST) * 2})
    study = SimpleNamespace(spec=SimpleNamespace(scenes=SimpleNamespace(realisations=1)), targets=[])

    def stage(shape: float, output: str = "y", n: int = 512, method: str = res.method) -> SimpleNamespace:
        tail = Diagnostic("heavy_tail", "...", "untrusted", output=output, parameter="x2", value=shape)
        return SimpleNamespace(method=method, options={**res.options, "n": n}, indices=res.indices, extras=res.extras,
                               n_evals=n * 5, diagnostics=[*res.diagnostics, tail])

    def told(*stages: SimpleNamespace, scene: int = 0) -> str:
        ran = SimpleNamespace(indices=rows, study=study, evaluations=pd.DataFrame({"seconds": [1.0]}), provenance={},
                              results=[(SimpleNamespace(index=scene), s) for s in stages])
        return advice(ran, "y", [0])

    assert "; caution: in scene 0 the total index's terms of x2 have a heavy tail (Pareto shape 1.3 >= 1 at N = 512" \
        in told(stage(1.3))
    assert "caution" not in told(stage(0.8)) and "caution" not in told(stage(1.3, output="z")) \
        and "caution" not in told(stage(1.3), scene=1)
    # the escalation's larger stage measured the tail again: its reading, not the plain design's, decides
    assert "caution" not in told(stage(1.3), stage(0.7, n=8192, method="confirm_saltelli"))
    assert "shape 1.2 >= 1 at N = 8192" in told(stage(0.9), stage(1.2, n=8192, method="confirm_saltelli"))
