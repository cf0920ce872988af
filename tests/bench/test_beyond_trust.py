"""False trust of the estimators beyond S1/ST (groups, Shapley, target, signals) against closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa.bench.beyond_trust import CASES, Scored, exact_shapley, score, summarise, sweep


def test_score_counts_a_trusted_row_off_by_more_than_the_tolerance_and_a_wrong_order() -> None:
    """Two rows: the first trusted and off by 0.03 (> 0.02: false trust), the second untrusted and off by
    0.5 (no false trust); both placed, in the order the exact values reverse (false rank, both)."""
    run = Scored(est=np.array([[0.53, 0.6], [0.5, 0.55]]), exact=np.array([[0.5, 0.6], [0.0, 0.7]]),
                 ranked=np.array([0.6, 0.55]), ranked_exact=np.array([0.6, 0.7]), trusted=np.array([True, False]),
                 claims=np.array([2, 2], dtype=np.int8), ranks=np.array(["1", "2"], dtype=object), n_evals=10)
    false_trust, false_rank = score(run)
    assert false_trust.tolist() == [True, False] and false_rank.tolist() == [True, True]


def test_exact_shapley_of_independent_inputs_shares_each_interaction_equally() -> None:
    """v(J) of Ishigami (independent): Sh = (S1 + S13/2, S2, S13/2), full S1 = S1, independent ST = ST."""
    s1, s2, s13 = 0.31391, 0.44241, 0.24368
    parts = {(0,): s1, (1,): s2, (0, 2): s13}
    v = lambda j: sum(val for u, val in parts.items() if set(u) <= set(j))     # noqa: E731
    np.testing.assert_allclose(exact_shapley(v, 3), [[s1 + s13 / 2, s1, s1 + s13], [s2, s2, s2], [s13 / 2, 0, s13]],
                               atol=1e-12)


@pytest.mark.slow
def test_no_false_trust_or_rank_over_held_out_seeds() -> None:
    """Seeds 100-104 (the documented sweep used 0-19): every estimator and setting, no trusted row off by
    more than the tolerance and no rank claim the exact indices contradict (~3 min on one core)."""
    rows = sweep(range(100, 105), CASES)
    summary = summarise(rows)
    assert summary["false_trust"].sum() == 0, summary[summary["false_trust"] > 0]
    assert summary["false_rank"].sum() == 0, summary[summary["false_rank"] > 0]
    assert summary["trusted"].sum() > 0.2 * len(rows)          # the rule trusts something on every estimator kind
    assert set(summary[summary["trusted"] > 0]["estimator"]) == {"groups", "shapley", "target", "signal"}
