"""Confirm on request (issue 25): escalation until every output is confirmed or the budget is spent.

Every claim (trusted, rank-confirmed) of the results the escalation returns is scored against the
closed-form indices of Ishigami and the Sobol' g-function (:mod:`ddgsa.gsa.testfunctions`).
"""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa.bench.calibration import false_rank_claims
from ddgsa.gsa.escalate import PCE_NAME, SALTELLI_NAME, Escalation, confirm
from ddgsa.gsa.testfunctions import TestFunction, ishigami, sobol_g

G4 = sobol_g([0.0, 1.0, 4.5, 9.0])


def _no_false_claim(results: list, tf: TestFunction) -> None:
    """Every trusted row within 0.02 of the exact indices; no false rank confirmation."""
    for res in results:
        t = res.indices
        ok = t["trusted"].to_numpy(bool)
        assert np.all(np.abs(t["S1"].to_numpy(float) - tf.S1)[ok] <= 0.02), res.method
        assert np.all(np.abs(t["ST"].to_numpy(float) - tf.ST)[ok] <= 0.02), res.method
        ranks = t["rank"].to_numpy(object)[None] if "rank" in t else None          # ties are claims too
        bad = false_rank_claims(t["ST"].to_numpy(float)[None], tf.ST[None], res.extras["rank_claims"][None], 0.02,
                                ranks)
        assert not bad.any(), res.method


def test_ishigami_is_confirmed_from_mdrm_with_a_few_pce_points() -> None:
    """M-DRM (5 points, its 32-point check sample) confirms nothing of Ishigami (cut function
    through zero); the pooled expansion on those 48 points plus 48 Sobol' points places every
    parameter, and the escalation stops there, far below its budget."""
    tf = ishigami()
    c = confirm(tf.f, tf.space, "mdrm", budget=400, points=5)
    assert c.confirmed == {"y": True}
    assert c.n_evals == 48 + 48
    assert [r.method for r in c.results] == ["mdrm", "pooled_pce", PCE_NAME]
    assert not c.results[0].confirmed and c.results[-1].confirmed
    _no_false_claim(c.results, tf)


def test_the_escalation_stops_at_the_budget_and_says_so() -> None:
    """The g-function's kink (a = 0) needs ~10^4 runs; with a budget of 120 the escalation spends
    exactly 120 runs (a PCE step that doubles the pool, then the rest), claims nothing false, and
    logs the unconfirmed output."""
    c = confirm(G4.f, G4.space, "mdrm", budget=120, points=5)
    assert c.confirmed == {"y": False}
    assert c.n_evals == 4 * 5 + 1 + 32 + 120
    assert c.log[-1] == "budget of 120 runs spent; unconfirmed: y"
    _no_false_claim(c.results, G4)


def test_nothing_to_confirm_and_a_zero_budget_run_nothing() -> None:
    tf = ishigami()
    x = tf.space.sample(256, seed=1, rule="sobol")
    y = tf.f(x)[:, None]
    esc = Escalation(tf.space, ["y"], 0, x, y)
    assert esc.start() is None and esc.spent == 0 and esc.unconfirmed() == ["y"]
    with pytest.raises(Exception, match="budget"):
        Escalation(tf.space, ["y"], -1, x, y)


@pytest.mark.slow
def test_a_slowly_converging_expansion_hands_over_to_saltelli() -> None:
    """On the g-function the pooled expansion's bound shrinks ~n^-0.2 (measured between fits): after a few PCE
    steps the escalation estimates controlled Saltelli stages as cheaper and runs N = 512, 1 024 and 2 048
    (12 288 runs) -- every row it trusts within 0.02 of the exact indices, no false rank claim -- and stops
    when N = 4 096 no longer fits, saying so. It does not confirm the output: the rows of x3 and x4 (ST 0.034
    and 0.010) are flagged ``heavy_tail``, their controlled residual's Jansen terms at a Pareto shape of
    0.70-0.71 against the limit 0.70 (the kink |4 x1 - 2| the process does not follow), which voids their
    place in the ranking (this test asked for a confirmation at N = 2 048 until it was seen failing, since at
    least 0.7.x; the rule is the calibrated one, docs/confirm.md). About 10 s."""
    c = confirm(G4.f, G4.space, "mdrm", budget=20_000, points=5)
    salt = [r for r in c.results if r.method == SALTELLI_NAME]
    assert [r.n_evals for r in salt] == [2048 * (4 + 2)]               # the last stage's result is kept
    assert any(line.startswith("next: saltelli N=512") for line in c.log)
    assert c.log[-1].startswith("stopped with 6069 of 20000 runs left") and c.confirmed == {"y": False}
    flagged = {d.parameter for d in salt[0].diagnostics if d.name == "heavy_tail"}
    assert flagged <= {"x3", "x4"} and salt[0].indices.set_index("parameter").loc[["x1", "x2"], "trusted"].all()
    _no_false_claim(c.results, G4)


def test_saltelli_designs_of_one_seed_nest_so_a_larger_base_reuses_the_smaller() -> None:
    """What the escalation's Saltelli step relies on: the base-N design is the first N (d + 2)
    rows of the base-2N design (SALib's scrambled Sobol' stream, one seed); and a study's own
    Saltelli design counts as run: the next base is at least twice it, asking only the new rows."""
    from ddgsa.gsa.base import get_method

    d = G4.space.dim
    small = get_method("saltelli").design(G4.space, n=64, seed=3)
    big = get_method("saltelli").design(G4.space, n=128, seed=3)
    np.testing.assert_array_equal(big.points[:64 * (d + 2)], small.points)
    esc = Escalation(G4.space, ["y"], 10_000, small.points, G4.f(small.points)[:, None],
                     saltelli=(small, G4.f(small.points)[:, None]))
    assert esc._saltelli_n(["y"]) >= 128


def test_what_a_zero_budget_escalation_asks_for_is_the_new_points_of_twice_the_base_that_ran() -> None:
    """A study's own Saltelli base N = 64 left the g-function unconfirmed and the budget is 0: the escalation
    runs nothing and asks for at least N = 128 (a base that ran and did not confirm is doubled), whose new points
    are the rows past the first 64 (d + 2) -- the designs of one seed nest -- with no control variate fitted."""
    from ddgsa.gsa.base import get_method

    d = G4.space.dim
    small = get_method("saltelli").design(G4.space, n=64, seed=3)
    y = G4.f(small.points)[:, None]
    esc = Escalation(G4.space, ["y"], 0, small.points, y, saltelli=(small, y))
    assert esc.start() is None and esc.unconfirmed() == ["y"]
    ask = esc.asks()["y"]
    assert ask["n"] >= 128 and ask["points"] == (ask["n"] - 64) * (d + 2) and ask["control"] is False
    big = get_method("saltelli").design(G4.space, n=ask["n"], seed=3)
    assert len(big.points) - len(small.points) == ask["points"]


def test_a_grouped_saltelli_stage_keeps_its_rows_in_the_designs_layout() -> None:
    """With a named group the Saltelli design appends the group's AB_u rows (N of them) after Saltelli's rows,
    so a larger base's design does not start with the smaller one's group rows: a stage of base 256 after
    64 runs the new Saltelli rows and all 256 group rows (what ``asks`` counts), and the values the estimator
    reads are the function's own at the larger design's points, in its order (before, the smaller stage's
    group rows sat among the new Saltelli rows); its group indices equal a direct Saltelli analysis there."""
    from ddgsa.gsa.base import get_method
    from ddgsa.gsa.space import ParameterSpace

    space = ParameterSpace.from_dict(G4.space.to_dict(), groups={"ab": ["x1", "x2"]})
    d = space.dim
    method = get_method("saltelli")
    small, big = method.design(space, n=64, seed=3), method.design(space, n=256, seed=3)
    y = G4.f(small.points)[:, None]
    esc = Escalation(space, ["y"], 0, small.points, y, saltelli=(small, y))
    assert esc._stage_points(256) == len(big.points) - 64 * (d + 2) == (256 - 64) * (d + 2) + 256
    esc.budget = 10 ** 6
    esc._pending = ("saltelli", big.points[64 * (d + 2):], big)          # the stage the escalation runs
    esc.feed(G4.f(big.points[64 * (d + 2):])[:, None])
    np.testing.assert_array_equal(esc._salt_y, G4.f(big.points)[:, None])
    # the group's closed and total indices of the product function: 0.955 and 0.969 (the misplaced rows read
    # S_closed -0.06 +- 0.16); the stage's estimates cover them within their intervals, as a direct analysis
    v = 1.0 / (3.0 * (1.0 + np.array([0.0, 1.0, 4.5, 9.0])) ** 2)
    total = np.prod(1 + v) - 1
    exact = {"S_closed": (np.prod(1 + v[:2]) - 1) / total, "ST": 1 - (np.prod(1 + v[2:]) - 1) / total}
    direct = method.analyze(space, big, G4.f(big.points)[:, None], outputs=["y"]).groups.iloc[0]
    got = esc.salt.groups.iloc[0]
    for q, value in exact.items():
        assert abs(got[q] - value) <= got[f"{q}_conf"] and got[q] == pytest.approx(direct[q])


def test_an_escalation_that_cannot_confirm_says_why_and_claims_nothing_false() -> None:
    """A lightly damped resonance inside the parameter ranges (a rig running near its critical speed),
    less a constant so that it crosses zero and no power transform of it is tried: the pooled
    expansion's bound does not shrink; the escalation grows a pilot to ~1 000 points for a
    Gaussian-process control variate (leave-one-out error ~0.3), whose Saltelli base (N = 8 192) is
    beyond the budget, and stops with what is left and says why -- and nothing it reports is trusted
    or rank-confirmed falsely (the exact indices by a 400 x 400 x 4 tensor Gauss rule; a constant
    moves no index)."""
    from ddgsa.gsa.space import ParameterSpace

    space = ParameterSpace.from_dict({"a": {"dist": "uniform", "low": 0.8, "high": 1.2},
                                      "b": {"dist": "uniform", "low": 0.8, "high": 1.2},
                                      "c": {"dist": "uniform", "low": 0.9, "high": 1.1}})

    def f(x: np.ndarray) -> np.ndarray:
        r = x[:, 0] * x[:, 1]
        return x[:, 2] / np.sqrt((1 - r**2) ** 2 + (0.02 * r) ** 2) - 2.0

    c = confirm(f, space, "mdrm", budget=4000)
    assert c.confirmed == {"y": False}
    assert c.n_evals == 48 + 952
    assert [line.split(" (")[0] for line in c.log if line.startswith("next:")] == \
        ["next: pce points +48", "next: pce points +96", "next: pce points +192", "next: pce points +384",
         "next: pce points +232"]
    assert c.log[-1].startswith("stopped with") and "unconfirmed: y" in c.log[-1]
    assert "saltelli N=8192" in c.log[-1]
    from ddgsa.gsa.testfunctions import tensor_indices, TestFunction

    s1, st = tensor_indices(f, space, [400, 400, 4])
    _no_false_claim(c.results, TestFunction("resonance", space, f, s1.ravel(), st.ravel()))

def test_a_resonance_is_confirmed_with_focus_points_that_the_pooled_expansion_never_sees(monkeypatch) -> None:
    """The same resonance, positive (no constant taken off): its control variate is a process of
    ``1 / y^2`` (:mod:`ddgsa.gsa.control`), so every other pilot step is of focus points where that
    process is least certain -- near the peak. The escalation confirms it at 1 616 of 2 000 runs with a
    controlled Saltelli N = 256 (without focus points it was not confirmed at 5 456 runs), nothing
    reported is trusted or rank-confirmed falsely (the 400 x 400 x 4 tensor Gauss rule), and the
    pooled expansion is fitted on the drawn points only."""
    from ddgsa.gsa.testfunctions import TestFunction, tensor_indices
    from ddgsa.gsa.space import ParameterSpace

    space = ParameterSpace.from_dict({"a": {"dist": "uniform", "low": 0.8, "high": 1.2},
                                      "b": {"dist": "uniform", "low": 0.8, "high": 1.2},
                                      "c": {"dist": "uniform", "low": 0.9, "high": 1.1}})

    def f(x: np.ndarray) -> np.ndarray:
        r = x[:, 0] * x[:, 1]
        return x[:, 2] / np.sqrt((1 - r**2) ** 2 + (0.02 * r) ** 2)

    import ddgsa.gsa.control as control

    monkeypatch.setattr(control, "SURROGATE_RUNS", 1 << 18)      # the process's variances: an eighth of the default
    c = confirm(f, space, "mdrm", budget=2000)
    assert c.confirmed == {"y": True} and c.n_evals == 48 + 1616
    steps = [line.split(" (")[0] for line in c.log if line.startswith("next:")]
    assert steps[:3] == ["next: pce points +48", "next: focus points +96", "next: pce points +192"]
    pce = next(r for r in c.results if r.method == "confirm_pce")
    assert pce.n_evals == 48 + 1616 - 96
    s1, st = tensor_indices(f, space, [400, 400, 4])
    _no_false_claim(c.results, TestFunction("resonance", space, f, s1.ravel(), st.ravel()))
