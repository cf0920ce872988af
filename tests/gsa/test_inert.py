"""The inert check (``ddgsa.gsa.inert``, M-DRM's ``followup``, ``auto``'s reduced PCE): inputs proven
inert are trusted zeros; an input flat on the cut lines that interacts is not."""

from __future__ import annotations

import numpy as np
import pytest

import ddgsa
from ddgsa.bench.heldout import held_out_case
from ddgsa.gsa.inert import group_test, partners
from ddgsa.gsa.space import ParameterSpace
from ddgsa.gsa.testfunctions import ishigami


def _space(d: int) -> ParameterSpace:
    return ParameterSpace.from_dict({f"x{i + 1}": {"low": 0.0, "high": 1.0} for i in range(d)})


def test_group_test_is_jansens_estimator_and_proves_only_exact_zeros() -> None:
    base = np.array([[1.0, 5.0, 7.0], [2.0, 5.0, 7.0], [3.0, 6.0, 7.0], [4.0, 6.0, 7.0]])
    partner = np.array([[1.0, 5.0, 7.0], [2.0, 5.0, 7.0], [3.0, 6.0 * (1 + 1e-14), 7.0], [6.0, 6.0, 7.0]])
    estimate, inert = group_test(base, partner)
    both = np.vstack([base, partner])[:, 0]
    assert estimate[0] == pytest.approx((2.0 ** 2 / 4) / (2 * np.var(both, ddof=1)))   # one pair differs by 2
    assert not inert[0]
    assert inert[1] and estimate[1] == 0.0                      # a difference at round-off is none
    assert not inert[2] and np.isnan(estimate[2])               # a constant output: nothing to prove
    estimate, inert = group_test(base[:3], partner[:3])
    assert inert[0] and estimate[0] == 0.0


def test_partners_redraw_only_the_group() -> None:
    space = _space(4)
    base = space.sample(16, seed=0, rule="sobol")
    p = partners(space, base, [1, 3], seed=5)
    assert np.array_equal(p[:, [0, 2]], base[:, [0, 2]])
    assert not np.isclose(p[:, [1, 3]], base[:, [1, 3]]).any()


def test_an_interaction_invisible_on_the_cut_lines_is_not_proven_inert() -> None:
    # f = 2 + x1 + 4 x2 (x3 - 1/2): along the cut lines through the means x2's cut function is flat
    # (x3 = 1/2 there), yet ST_2 = ST_3 = (16/144)/(1/12 + 16/144) = 4/7
    def f(x: np.ndarray) -> np.ndarray:
        return 2.0 + x[:, 0] + 4.0 * x[:, 1] * (x[:, 2] - 0.5)

    res = ddgsa.sobol(f, _space(4), "mdrm", points=5)
    t = res.indices.set_index("parameter")
    assert res.n_evals == 4 * 5 + 1 + 32 + 32                   # the check sample's 32 pairs
    notes = [d.message for d in res.diagnostics if d.name == "mdrm_inert_check"]
    assert len(notes) == 1 and "'y': x2 drawn anew" in notes[0] and "nothing is proven" in notes[0]
    assert t.loc["x2", "ST"] == 0.0 and not t.loc["x2", "trusted"]


def test_the_inert_inputs_of_a_held_out_block_sum_are_proven() -> None:
    # block_sum_5000 (ddgsa.bench.heldout): 11 inputs, 4 inert (c = 0), interacting blocks with
    # normal, lognormal and cubic inputs, which M-DRM's check sample cannot vouch for
    f = held_out_case(5000)
    inert = np.flatnonzero(f.c == 0.0)
    assert inert.size == 4
    plain = ddgsa.sobol(f, f.space, "mdrm", inert_check=False).indices
    assert not plain["trusted"].to_numpy()[inert].any()         # untrusted zeros without the check
    res = ddgsa.sobol(f, f.space, "mdrm")
    t = res.indices
    assert res.n_evals == f.space.dim * 5 + 1 + 32 + 32
    assert t["trusted"].to_numpy()[inert].all()
    assert (t[["S1", "ST", "S1_conf", "ST_conf"]].to_numpy()[inert] == 0.0).all()
    assert not any(d.name == "mdrm_index_error" and d.parameter in {f"x{i + 1}" for i in inert}
                   for d in res.diagnostics)


def test_ishigami_x3_flat_on_the_cut_lines_stays_untrusted() -> None:
    tf = ishigami()
    res = ddgsa.sobol(lambda x: tf.f(x) + 12.0, tf.space, "mdrm", points=7)      # one-signed
    t = res.indices.set_index("parameter")
    assert t.loc["x3", "ST"] == 0.0 and tf.ST[2] > 0.2          # M-DRM misses x1-x3 entirely
    assert not t.loc["x3", "trusted"]
    assert res.n_evals == 3 * 7 + 1 + 32 + 32


def test_without_the_check_no_extra_runs() -> None:
    def g(x: np.ndarray) -> np.ndarray:
        return 2.0 + x[:, 0] + x[:, 2] ** 2

    res = ddgsa.sobol(g, _space(4), "mdrm", points=5, inert_check=False)
    assert res.n_evals == 4 * 5 + 1 + 32
    with pytest.raises(ddgsa.MethodError, match="inert_check"):
        ddgsa.sobol(g, _space(4), "mdrm", inert_check="yes")


def test_auto_fits_its_pce_in_the_inputs_not_proven_inert() -> None:
    # 12 inputs, 8 inert; x1..x4 interact (a product): exact indices in closed form
    c = np.array([0.8, 0.6, 0.4, 0.2])
    space = _space(12)

    def f(x: np.ndarray) -> np.ndarray:
        return np.prod(1.0 + c * np.sqrt(12.0) * (x[:, :4] - 0.5), axis=1)

    v = c ** 2
    total = np.prod(1 + v) - 1
    s1, st = v / total, v * np.prod(1 + v) / (1 + v) / total
    res = ddgsa.sobol(f, space, "auto", budget=600)
    log = " | ".join(res.extras["auto_log"])
    assert "inert check" in log and "in the 4 inputs not proven inert" in log
    t = res.indices.set_index("parameter")
    assert t["trusted"].all()
    assert np.abs(t["S1"].to_numpy()[:4] - s1).max() < 0.02 and np.abs(t["ST"].to_numpy()[:4] - st).max() < 0.02
    assert (t["ST"].to_numpy()[4:] == 0.0).all()
