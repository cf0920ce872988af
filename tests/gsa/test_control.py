"""Saltelli with a Gaussian-process control variate (:mod:`ddgsa.gsa.control`, issue 25).

Oracles: the process's exact Sobol variances against a tensor Gauss quadrature of its own
predictions (a second computation of the same integrals); the estimator with ``g = 0`` against
SALib's ``sobol.analyze``; the controlled estimates against Ishigami's and the g-function's closed
forms, with their error bounds.
"""

from __future__ import annotations

import numpy as np
import pytest
from SALib.analyze import sobol as salib_sobol
from SALib.sample import sobol as salib_sample

import ddgsa
from ddgsa.errors import MethodError
from ddgsa.gsa.control import GaussianSurrogate, controlled_level, controlled_saltelli
from ddgsa.gsa.escalate import SALTELLI_NAME, confirm
from ddgsa.gsa.testfunctions import ishigami, sobol_g


def _ishigami_unit(u: np.ndarray) -> np.ndarray:
    x = 2 * np.pi * u - np.pi
    return np.sin(x[:, 0]) + 7 * np.sin(x[:, 1]) ** 2 + 0.1 * x[:, 2] ** 4 * np.sin(x[:, 0])


@pytest.fixture(scope="module")
def process() -> GaussianSurrogate:
    u = np.random.default_rng(1).random((150, 3))
    return GaussianSurrogate.fit(u, _ishigami_unit(u))


def test_the_process_evaluated_in_threaded_chunks_is_its_kernel_sum(process, monkeypatch: pytest.MonkeyPatch) -> None:
    """``process(u)`` on 40 000 points (many chunks, on two threads and in turn) against its definition written
    out, ``offset + sum_j w_j exp(-|(u - c_j) / length|^2 / 2)`` with the differences taken directly: within 1e-12
    of the values' range (the one product's round-off)."""
    import ddgsa.gsa.control as control

    u = np.random.default_rng(2).random((40_000, 3))
    diff = (u[:, None, :] - process.centres[None, :, :]) / process.length
    direct = process.offset + np.exp(-0.5 * (diff ** 2).sum(axis=2)) @ process.weights
    scale = np.ptp(direct)
    for threads in (2, 1):
        monkeypatch.setattr(control, "THREADS", threads)
        np.testing.assert_allclose(process(u), direct, rtol=0, atol=1e-12 * scale)


def test_exact_variances_of_the_process_equal_a_tensor_quadrature_of_its_predictions(process) -> None:
    """The closed forms (error functions) against 60^3 Gauss-Legendre nodes of ``process(u)``."""
    var, first, total = process.variances()
    x, w = np.polynomial.legendre.leggauss(60)
    x, w = (x + 1) / 2, w / 2
    grid = np.stack(np.meshgrid(x, x, x, indexing="ij"), axis=-1).reshape(-1, 3)
    m = process(grid).reshape(60, 60, 60)
    weights = np.einsum("i,j,k->ijk", w, w, w)
    mean = (weights * m).sum()
    v = (weights * (m - mean) ** 2).sum()
    s1, st = [], []
    for i in range(3):
        rest = tuple(k for k in range(3) if k != i)
        main = (weights * m).sum(axis=rest) / w                  # E[m | u_i] at the nodes
        s1.append((w * (main - mean) ** 2).sum() / v)
        others = (weights * m).sum(axis=i) / np.outer(w, w)      # E[m | u_-i]
        st.append(1 - (np.outer(w, w) * (others - mean) ** 2).sum() / v)
    np.testing.assert_allclose(var, v, rtol=1e-6)
    np.testing.assert_allclose(first / var, s1, atol=1e-6)
    np.testing.assert_allclose(total / var, st, atol=1e-6)


def test_without_a_surrogate_the_estimates_are_salibs() -> None:
    """``g = 0`` with zero variances reduces the controlled estimator to SALib's Saltelli (2010) and
    Jansen estimators, to round-off."""
    problem = {"num_vars": 3, "names": ["a", "b", "c"], "bounds": [[0.0, 1.0]] * 3}
    u = salib_sample.sample(problem, 256, calc_second_order=False, scramble=True, seed=np.random.default_rng(3))
    y = _ishigami_unit(u)
    ref = salib_sobol.analyze(problem, y, calc_second_order=False, seed=np.random.default_rng(0))
    z = (y - y.mean()) / y.std()
    c = controlled_saltelli(z.reshape(256, 5), np.zeros((256, 5)), (0.0, np.zeros(3), np.zeros(3)))
    np.testing.assert_allclose(c.S1, ref["S1"], atol=1e-12)
    np.testing.assert_allclose(c.ST, ref["ST"], atol=1e-12)


def test_a_perfect_surrogate_gives_its_exact_indices_with_no_error(process) -> None:
    """When the output *is* the surrogate every per-row difference vanishes: the estimates are the
    process's exact indices whatever the sample, and the error estimate is zero."""
    var, first, total = process.variances()
    u = np.random.default_rng(7).random((64 * 5, 3))
    g = process(u).reshape(64, 5)
    c = controlled_saltelli(g, g, (var, first, total))
    np.testing.assert_allclose(c.S1, first / var, atol=1e-12)
    np.testing.assert_allclose(c.ST, total / var, atol=1e-12)
    assert np.all(c.S1_error < 1e-12) and np.all(c.ST_error < 1e-12)


def test_controlled_saltelli_on_ishigami_is_within_its_bounds_and_several_times_tighter() -> None:
    """n = 512 with a 256-point pilot: every row trusted, every index within 0.02 and within twice
    its error bound of the closed form, and the bounds on ST at most half the plain estimator's at
    the same base sample (where no row is trusted)."""
    tf = ishigami()
    plain = ddgsa.sobol(tf.f, tf.space, "saltelli", n=512, seed=2)
    ctl = ddgsa.sobol(tf.f, tf.space, "saltelli", n=512, seed=2, control="gp", pilot=256)
    assert ctl.n_evals == 512 * 5 + 256
    t = ctl.indices
    assert t["trusted"].all() and not plain.indices["trusted"].any()
    for q in ("S1", "ST"):
        err = np.abs(t[q].to_numpy() - getattr(tf, q))
        assert np.all(err <= 0.02) and np.all(err <= 2 * ctl.extras[f"{q}_error"][0])
    assert np.all(ctl.extras["ST_error"][0] <= 0.5 * plain.extras["ST_error"][0])
    assert 0.0 < ctl.extras["control_loo"][0] < 0.5


def test_the_control_options_are_checked() -> None:
    tf = ishigami()
    with pytest.raises(MethodError, match="'control'"):
        ddgsa.sobol(tf.f, tf.space, "saltelli", n=64, control="kriging")
    with pytest.raises(MethodError, match="'pilot'"):
        ddgsa.sobol(tf.f, tf.space, "saltelli", n=64, pilot=64)


def test_the_cost_rule_caps_a_rows_level_at_twice_the_squared_loo_error() -> None:
    np.testing.assert_allclose(controlled_level(np.array([0.5, 0.01]), 0.1), [0.02, 0.01])


def test_an_escalation_on_a_kinked_function_confirms_with_a_controlled_saltelli_stage() -> None:
    """The g-function (a kink at a = 0): the pooled expansion converges too slowly; the escalation fits
    a process on its pooled points and runs the largest controlled Saltelli base its budget allows (a
    fraction of what the cost rule asks for), which confirms the output in about 3 000 runs, where the
    plain estimator needed 12 288 (``test_escalate``); no trusted row is off by more than 0.02."""
    g6 = sobol_g([0.0, 1.0, 4.5, 9.0, 99.0, 99.0])
    c = confirm(g6.f, g6.space, "mdrm", budget=5000, seed=3)
    assert c.n_evals < 3100
    assert any("the largest base the budget allows" in line for line in c.log)
    salt = next(r for r in c.results if r.method == SALTELLI_NAME)
    assert any("control variate" in line for line in c.log)
    assert c.confirmed == {"y": True} and salt.confirmed
    assert salt.options["control"] == "gp"
    t = salt.indices
    ok = t["trusted"].to_numpy(bool)
    assert np.all(np.abs(t["S1"].to_numpy() - g6.S1)[ok] <= 0.02)
    assert np.all(np.abs(t["ST"].to_numpy() - g6.ST)[ok] <= 0.02)


def test_a_controlled_designs_sub_samples_keep_its_pilot_and_its_draws_are_counted() -> None:
    """The convergence curve analyses nested Saltelli prefixes: each keeps the whole pilot (the
    process is fitted on it), so every level has finite indices near Ishigami's; the pilot rows are
    draws of the input distribution (the given-data cross-check uses them), a group's rows are not."""
    from ddgsa.gsa.base import get_method
    from ddgsa.gsa.convergence import convergence, sub_rows
    from ddgsa.gsa.givendata import drawn_rows

    tf = ishigami()
    design = get_method("saltelli").design(tf.space, n=256, control="gp", pilot=128)
    rows = sub_rows(design, 64, 3)
    assert len(rows) == 64 * 5 + 128 and rows[-1] == design.n_points - 1
    curve = convergence(tf.space, design, tf.f(design.points)[:, None], ["y"])
    assert sorted(curve["n_evals"].unique()) == [m * 5 + 128 for m in (8, 16, 32, 64, 128, 256)]
    assert np.isfinite(curve[["S1", "ST"]].to_numpy(float)).all()
    last = curve[curve["n_evals"] == 256 * 5 + 128]
    assert np.all(np.abs(last["ST"].to_numpy() - tf.ST) < 0.05)
    drawn = drawn_rows(design)
    assert drawn.sum() == 2 * 256 + 128 and drawn[-128:].all()


def test_an_escalation_from_a_studys_own_controlled_saltelli_design_extends_it() -> None:
    """Review: a study's ``saltelli`` with ``control: gp`` ends in pilot rows; the escalation takes its
    Saltelli rows only (the pilot trains its processes), extends the design to a larger base (the
    g-function's kink keeps the pooled PCE from confirming first), and the result is within 0.02 of
    the closed form where trusted."""
    from ddgsa.gsa.base import get_method
    from ddgsa.gsa.escalate import Escalation

    tf = sobol_g([0.0, 1.0, 4.5, 9.0])
    design = get_method("saltelli").design(tf.space, n=64, control="gp", pilot=128)
    y = tf.f(design.points)[:, None]
    esc = Escalation(tf.space, ["y"], 8000, design.points, y, saltelli=(design, y))
    x = esc.start()
    while x is not None:
        x = esc.feed(tf.f(x)[:, None])
    salt = esc.salt
    assert salt is not None and salt.options["control"] == "gp" and salt.n_evals > 64 * 5
    t = salt.indices
    ok = t["trusted"].to_numpy(bool)
    assert ok.any()
    assert np.all(np.abs(t["S1"].to_numpy() - tf.S1)[ok] <= 0.02)
    assert np.all(np.abs(t["ST"].to_numpy() - tf.ST)[ok] <= 0.02)


def test_the_estimate_stays_unbiased_under_a_poor_surrogate() -> None:
    """Review: a deliberately wrong process (fitted to another function) costs precision, not
    correctness: over 40 seeds the mean controlled estimate of Ishigami's ST is within 0.01 of the
    closed form."""
    from SALib.sample import sobol as sampler

    rng = np.random.default_rng(4)
    u = rng.random((120, 3))
    wrong = GaussianSurrogate.fit(u, np.cos(3 * u[:, 0]) + u[:, 2] ** 2)
    assert wrong is not None
    tf = ishigami()
    problem = {"num_vars": 3, "names": ["a", "b", "c"], "bounds": [[0.0, 1.0]] * 3}
    sts = []
    for seed in range(40):
        unit = sampler.sample(problem, 128, calc_second_order=False, scramble=True, seed=np.random.default_rng(seed))
        f = _ishigami_unit(unit)
        c = controlled_saltelli(f.reshape(128, 5), wrong(unit).reshape(128, 5), wrong.variances(), resamples=20)
        sts.append(c.ST)
    np.testing.assert_allclose(np.mean(sts, axis=0), tf.ST, atol=0.01)


def _resonance(x: np.ndarray) -> np.ndarray:
    """A lightly damped resonance inside the ranges (2 % damping): ``c / |1 - r^2 + 0.02 i r|``,
    ``r = a b``; its inverse square is a quadratic in ``r^2``."""
    r = x[:, 0] * x[:, 1]
    return x[:, 2] / np.sqrt((1 - r**2) ** 2 + (0.02 * r) ** 2)


def _resonance_unit(u: np.ndarray) -> np.ndarray:
    return _resonance(np.column_stack([0.8 + 0.4 * u[:, 0], 0.8 + 0.4 * u[:, 1], 0.9 + 0.2 * u[:, 2]]))


@pytest.fixture(scope="module")
def resonance_control():
    """The resonance's control variate on 512 Sobol' points, its variances sampled with 2^18 surrogate
    runs (an eighth of the default: the tests compare within the standard errors, which grow)."""
    from scipy.stats import qmc

    import ddgsa.gsa.control as control

    u = qmc.Sobol(3, seed=11).random(512)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(control, "SURROGATE_RUNS", 1 << 18)
        g = control.fit_control(u, _resonance_unit(u), seed=2)
        g.variances()                                    # sampled now, with the smaller budget
    return u, g


def test_a_resonance_is_followed_by_a_power_transform_whose_sampled_variances_match_a_quadrature(
        resonance_control) -> None:
    """The process of ``y`` itself misses the peak (leave-one-out error > 0.2); the control is the
    process of ``y^-2`` mapped back, within 0.1. Its Sobol variances (scrambled quasi-Monte Carlo)
    agree with a 300 x 300 x 4 tensor Gauss rule over the same surrogate within four standard errors
    (plus 2e-3 for the rule on the ridge), and the standard errors are small."""
    from ddgsa.gsa.control import TransformedSurrogate
    from ddgsa.gsa.testfunctions import tensor_indices
    from ddgsa.gsa.space import ParameterSpace

    u, g = resonance_control
    assert GaussianSurrogate.fit(u, _resonance_unit(u), max_loo=10.0).loo > 0.2
    assert isinstance(g, TransformedSurrogate) and g.power == -2.0 and g.loo < 0.1
    var, first, total = g.variances()
    var_se, first_se, total_se = g.variance_errors()
    cube = ParameterSpace.from_dict({k: {"dist": "uniform", "low": 0.0, "high": 1.0} for k in "abc"})
    s1, st = tensor_indices(g, cube, [300, 300, 4])
    assert np.all(first_se / var < 0.01) and np.all(total_se / var < 0.01)
    np.testing.assert_array_less(np.abs(first / var - s1.ravel()), 4 * first_se / var + 2e-3)
    np.testing.assert_array_less(np.abs(total / var - st.ravel()), 4 * total_se / var + 2e-3)


def test_the_transformed_control_estimates_a_resonance_within_its_bounds_where_the_plain_one_cannot(
        resonance_control) -> None:
    """Saltelli N = 512 on the resonance (exact indices by a 400 x 400 x 4 tensor Gauss rule): the
    transformed control's estimates are within their error bounds, and its bounds on the two
    dominant totals (ST ~0.98) are below 0.03, where the plain estimator's exceed 0.05."""
    from ddgsa.gsa.testfunctions import tensor_indices
    from ddgsa.gsa.space import ParameterSpace

    u0, g = resonance_control
    problem = {"num_vars": 3, "names": ["a", "b", "c"], "bounds": [[0.0, 1.0]] * 3}
    u = salib_sample.sample(problem, 512, calc_second_order=False, scramble=True, seed=np.random.default_rng(5))
    f = _resonance_unit(u).reshape(512, 5)
    space = ParameterSpace.from_dict({"a": {"dist": "uniform", "low": 0.8, "high": 1.2},
                                      "b": {"dist": "uniform", "low": 0.8, "high": 1.2},
                                      "c": {"dist": "uniform", "low": 0.9, "high": 1.1}})
    s1, st = (v.ravel() for v in tensor_indices(_resonance, space, [400, 400, 4]))
    ctl = controlled_saltelli(f, g(u).reshape(512, 5), g.variances(), exact_error=g.variance_errors(), seed=1)
    plain = controlled_saltelli(f, np.zeros_like(f), (0.0, np.zeros(3), np.zeros(3)), seed=1)
    np.testing.assert_array_less(np.abs(ctl.S1 - s1), ctl.S1_error)
    np.testing.assert_array_less(np.abs(ctl.ST - st), ctl.ST_error)
    assert np.all(ctl.ST_error[:2] < 0.03) and np.all(plain.ST_error[:2] > 0.05)


def test_the_transform_is_chosen_whatever_the_outputs_unit(resonance_control) -> None:
    """The same output x 1e-12 and x 1e12: the same power and leave-one-out error, and the same
    surrogate in its units (the transform acts on the output over its median)."""
    from ddgsa.gsa.control import fit_control

    u, g = resonance_control
    y = _resonance_unit(u)
    for c in (1e-12, 1e12):
        h = fit_control(u, c * y, seed=2)
        assert h.power == g.power and h.loo == pytest.approx(g.loo, rel=1e-6)
        np.testing.assert_allclose(h(u[:50]) / c, g(u[:50]), rtol=1e-6)


def test_the_leave_one_out_error_is_taken_over_the_drawn_points() -> None:
    """With points off the input distribution among the training points (focus points), the
    leave-one-out error is the RMS of the drawn points' leave-one-out residuals over their spread:
    here the resonance's peak region, where the process errs most, is left out of it."""
    from scipy.stats import qmc

    from sklearn.gaussian_process import GaussianProcessRegressor

    u = qmc.Sobol(3, seed=4).random(256)
    y = _resonance_unit(u)
    drawn = np.arange(256) % 2 == 0
    g = GaussianSurrogate.fit(u, y, max_loo=10.0, drawn=drawn, exact=False)
    gp, sd = g.regressor
    # the closed-form leave-one-out predictions against refits without the point (same kernel)
    for i in (0, 17, 200):
        rest = np.arange(256) != i
        alone = GaussianProcessRegressor(gp.kernel, optimizer=None).fit(u[rest], (y[rest] - g.offset) / sd)
        assert g.loo_values[i] == pytest.approx(g.offset + sd * alone.predict(u[i:i + 1])[0], rel=1e-6)
    gap = (y - g.loo_values)[drawn]
    assert g.loo == pytest.approx(np.sqrt(np.mean(gap ** 2)) / y[drawn].std(), rel=1e-9)
    assert GaussianSurrogate.fit(u, y, max_loo=10.0).loo != pytest.approx(g.loo, rel=1e-3)


def test_a_constant_output_is_not_escalated() -> None:
    """An output constant to its numerical noise (spread 1e-10 of its mean) has nothing to rank:
    the escalation does not spend runs on it (``ddgsa.gsa.result.nothing_to_rank``)."""
    from ddgsa.gsa.escalate import Escalation
    from ddgsa.gsa.result import nothing_to_rank
    from ddgsa.gsa.space import ParameterSpace

    space = ParameterSpace.from_dict({"a": {"low": 0.0, "high": 1.0}, "b": {"low": 0.0, "high": 1.0}})
    x = np.random.default_rng(0).random((40, 2))
    flat = 6.9 * (1 + 1e-10 * x[:, 0])
    assert nothing_to_rank(flat) and not nothing_to_rank(6.9 * (1 + 1e-6 * x[:, 0]))
    esc = Escalation(space, ["flat"], 1000, x, flat[:, None])
    assert esc.unconfirmed() == [] and esc.start() is None


@pytest.mark.parametrize("d, noise", [(27, 0.0), (8, 1e-2)])
def test_the_likelihood_and_its_gradient_are_scikit_learns(d: int, noise: float) -> None:
    """Oracle: scikit-learn's own log marginal likelihood and gradient (its (n, n, d) kernel gradient) at the
    start of the fit and at random log-hyperparameters; and the optimiser's end point, rounded as
    :meth:`GaussianSurrogate.fit` rounds it, is scikit-learn's fit."""
    import warnings

    from sklearn.gaussian_process import GaussianProcessRegressor
    from sklearn.gaussian_process.kernels import RBF, ConstantKernel, WhiteKernel

    from ddgsa.gsa.control import _max_likelihood, _neg_log_likelihood

    rng = np.random.default_rng(d)
    u = rng.random((200, d))
    y = 1.0 / (0.05 + (u[:, 0] - 0.5) ** 2 + (u[:, 1] - 0.4) ** 2) + 0.1 * u[:, 2:].sum(axis=1) \
        + noise * rng.normal(size=len(u))
    z = (y - y.mean()) / y.std()
    kernel = (ConstantKernel(1.0, (1e-3, 1e3)) * RBF(np.full(d, 0.3), (0.01, 1e2))
              + WhiteKernel(1e-3, (1e-6, 1.0)))
    reference = GaussianProcessRegressor(kernel)
    reference.X_train_, reference.y_train_, reference.kernel_ = u, z, kernel.clone_with_theta(kernel.theta)
    for theta in (kernel.theta, kernel.theta + 0.5 * rng.normal(size=d + 2)):
        lml, grad = reference.log_marginal_likelihood(theta, eval_gradient=True)
        mine, my_grad = _neg_log_likelihood(theta, u, z)
        assert -mine == pytest.approx(lml, rel=1e-10)
        np.testing.assert_allclose(-my_grad, grad, rtol=0, atol=1e-9 * np.abs(grad).max())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fitted = GaussianProcessRegressor(kernel).fit(u, z).kernel_.theta
    # the optimum, not the optimiser's path: on a flat likelihood round-off moves where L-BFGS-B stops
    mine_at = _neg_log_likelihood(_max_likelihood(kernel.theta, kernel.bounds, u, z), u, z)[0]
    assert mine_at <= -reference.log_marginal_likelihood(fitted) + 1e-3


def test_refined_moments_shrink_their_error_as_the_surrogate_runs_grow_and_still_match_a_quadrature() -> None:
    """:func:`~ddgsa.gsa.control.refine_moments`: a resonance control sampled on 2^16 surrogate runs, refined
    towards an unreachable target, ends at the cap (2^20, 16 times as many) with the standard errors of its total
    variances more than 2.5 times smaller (a quarter at Monte Carlo's ``runs^-1/2``; scrambled Sobol' points converge
    faster on a smooth surrogate: 3-17 times here), its indices within four of them of the
    300 x 300 x 4 tensor Gauss rule over the same surrogate; a control already within the target is left as
    it is."""
    from scipy.stats import qmc

    import ddgsa.gsa.control as control
    from ddgsa.gsa.space import ParameterSpace
    from ddgsa.gsa.testfunctions import tensor_indices

    u = qmc.Sobol(3, seed=11).random(512)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(control, "SURROGATE_RUNS", 1 << 16)
        mp.setattr(control, "MAX_SURROGATE_RUNS", 1 << 20)
        g = control.fit_control(u, _resonance_unit(u), seed=2)
        var, _, total = g.variances()
        before = g.variance_errors()[2] / var
        control.refine_moments([g], target=1.0)                 # met already: nothing sampled again
        assert "moment_runs" not in g.core.__dict__
        control.refine_moments([g], target=1e-9)
        assert g.core.__dict__["moment_runs"] == 1 << 20
    var, _, total = g.variances()
    after = g.variance_errors()[2] / var
    np.testing.assert_array_less(after, before / 2.5)
    cube = ParameterSpace.from_dict({k: {"dist": "uniform", "low": 0.0, "high": 1.0} for k in "abc"})
    _, st = tensor_indices(g, cube, [300, 300, 4])
    np.testing.assert_array_less(np.abs(total / var - st.ravel()), 4 * after + 2e-3)


def test_the_sampled_variances_do_not_depend_on_the_chunk_size(resonance_control) -> None:
    """The same points and estimators whatever :data:`~ddgsa.gsa.control.CHUNK_VALUES` (here 64 coordinates at a
    time against the default, the one on :data:`~ddgsa.gsa.control.THREADS` threads, the other in turn): equal
    within 1e-6 of the variance (measured 3e-8: the matrix products' round-off, which the map back of ``y^-2``
    near the peak amplifies; a chunk lost or misplaced moves them by the whole of its share)."""
    import ddgsa.gsa.control as control

    _, g = resonance_control
    whole = control._sampled_variances([g.core], 3, 5, runs=1 << 14)[0]
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(control, "CHUNK_VALUES", 64)
        chunked = control._sampled_variances([g.core], 3, 5, runs=1 << 14)[0]
    for a, b in zip(whole[0] + whole[1], chunked[0] + chunked[1]):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-6 * whole[0][0])
