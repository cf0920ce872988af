"""Detection statistics against closed forms: Gaussian shift POD and AUC, the multi-sensor gain,
Clopper-Pearson, refusals (failures, inf, zero spread, too few measurements), seeds; clustered
and paired (common-random-number) designs: the issue-33 case, ties, and the coverage of the
intervals measured by simulation (fast here, bigger under ``slow``)."""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pandas as pd
import pytest
from scipy import stats

from ddgsa.detection import (COMBINED, DetectionError, DetectionSettings, add_noise, assess,
                             clopper_pearson, detect, detect_combined, fisher_scores, layout, select_sensors,
                             threshold_at)
from ddgsa.detection.single import _Independent, _Pairs

matplotlib.use("Agg")
FAST = DetectionSettings(bootstrap=400)
Z95 = stats.norm.ppf(0.95)


def _gauss(n: int, shift: float, sigma: float, seed: int, k: int = 1) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    return rng.normal(0.0, sigma, (n, k)).squeeze(), rng.normal(shift, sigma, (n, k)).squeeze()


def _gauss_qmc(n: int, shift: float, sigma: float, seed: int, k: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Like ``_gauss`` from a scrambled Sobol' sequence (n a power of 2): the samples follow the
    normal law far more evenly than random draws, so the intervals are checked against
    the distribution, not against one draw's luck (they are conservative for such samples)."""
    u = stats.qmc.Sobol(2 * k, scramble=True, rng=np.random.default_rng(seed)).random(n)
    z = stats.norm.ppf(u)
    return (sigma * z[:, :k]).squeeze(), (shift + sigma * z[:, k:]).squeeze()


@pytest.mark.parametrize("shift", [0.5, 1.5, 2.5, -1.5])
def test_gaussian_shift_reproduces_analytic_pod_and_auc(shift: float) -> None:
    """N(0, 2^2) against N(2 shift, 2^2), 2048 each (quasi-random): POD = Phi(|Delta|/sigma - z_0.95)
    and AUC = Phi(|Delta|/(sigma sqrt 2)) lie inside their 95 % intervals, which are narrow (POD
    interval < 0.12 wide: the threshold estimate dominates; AUC < 0.05); a downward fault alarms
    below the threshold."""
    sigma = 2.0
    h, f = _gauss_qmc(2048, shift * sigma, sigma, seed=int(10 * abs(shift)) + (shift < 0))
    d = detect(h, f, settings=FAST, seed=1)
    pod = stats.norm.cdf(abs(shift) - Z95)
    auc = stats.norm.cdf(abs(shift) / math.sqrt(2))
    assert d.pod_low <= pod <= d.pod_high
    assert d.auc_low <= auc <= d.auc_high
    assert d.pod_high - d.pod_low < 0.12 and d.auc_high - d.auc_low < 0.05
    assert d.direction == (1 if shift > 0 else -1)
    # out of sample: a healthy value of rank r (0-based) alarms against the other 2047 when
    # r >= ceil(0.95 * 2047) = 1945: 103 of 2048
    assert d.false_alarm == pytest.approx(103 / 2048, abs=1e-12)
    assert d.effect_size == pytest.approx(abs(shift), abs=0.1)
    assert d.detectable is False                    # POD <= Phi(2.5 - 1.645) = 0.80 < 0.9 here


def test_verdict_is_decided_by_the_lower_bound_not_the_point_estimate() -> None:
    """Delta/sigma = 3: POD = Phi(3 - 1.645) = 0.912 > 0.9. With 60 faulty measurements the
    point estimate can pass the target while the lower bound (Clopper-Pearson 0.81 at 55/60)
    cannot: not detectable. With 6000 the bound passes."""
    h, f = _gauss(60, 3.0, 1.0, seed=4)
    small = detect(h, f, settings=FAST, seed=0)
    assert small.pod_low < 0.9 and small.detectable is False
    h, f = _gauss(6000, 3.5, 1.0, seed=5)
    big = detect(h, f, settings=FAST, seed=0)
    assert stats.norm.cdf(3.5 - Z95) == pytest.approx(0.968, abs=1e-3)
    assert big.pod_low >= 0.9 and big.detectable is True


def test_clopper_pearson_known_values() -> None:
    """All n detected: lower bound (alpha/2)^(1/n); 0 of n: upper 1 - (alpha/2)^(1/n) (exact)."""
    lo, hi = clopper_pearson(20, 20, 0.95)
    assert lo == pytest.approx(0.025 ** (1 / 20), rel=1e-9) and hi == 1.0
    lo, hi = clopper_pearson(0, 20, 0.95)
    assert lo == 0.0 and hi == pytest.approx(1 - 0.025 ** (1 / 20), rel=1e-9)


def test_threshold_keeps_false_alarms_at_or_below_the_rate() -> None:
    """On 1..100 the 5 % threshold is 95 (5 values beyond it); alarming low, 6 (5 below)."""
    x = np.arange(1.0, 101.0)
    assert threshold_at(x, 0.05) == 95.0 and threshold_at(x, 0.05, direction=-1) == 6.0


def test_two_sensors_each_seeing_half_the_fault_combine_to_beat_either() -> None:
    """Sensors x1 + Delta/2 and x2 + Delta/2 (iid N(0, 1), 2048 quasi-random, Delta = 2), plus an unrelated third:
    each half alone POD = Phi(1 - 1.645) = 0.259, the Fisher combination
    Phi(sqrt(2) - 1.645) = 0.409; held-out combined POD >= the best single one and within 0.05
    of the analytic value (its spread over 30 random draws of 3000: 0.018; mean 0.412)."""
    h, f = _gauss_qmc(2048, 0.0, 1.0, seed=7, k=3)
    f[:, :2] += 1.0
    singles = [detect(h[:, j], f[:, j], settings=FAST, seed=j) for j in range(2)]
    both = detect_combined(h, f, settings=FAST, seed=3)
    assert both.output == COMBINED
    assert both.pod >= max(s.pod for s in singles)
    assert both.pod == pytest.approx(stats.norm.cdf(math.sqrt(2) - Z95), abs=0.05)
    assert both.pod_low < both.pod < both.pod_high
    for s in singles:
        assert s.pod_low <= stats.norm.cdf(1.0 - Z95) <= s.pod_high


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_failed_or_infinite_measurements_refuse_the_verdict(bad: float) -> None:
    h, f = _gauss(200, 5.0, 1.0, seed=1)
    f[3] = bad
    d = detect(h, f, settings=FAST)
    assert d.detectable is None and math.isnan(d.pod) and math.isnan(d.auc)
    assert "0 of 200 healthy and 1 of 200 faulty measurements failed or are not finite" in d.reason
    c = detect_combined(np.column_stack([h, h]), np.column_stack([f, f]), settings=FAST)
    assert c.detectable is None and "1 of 200 faulty" in c.reason


def test_all_failed_refuses_instead_of_infinite_separation() -> None:
    d = detect(np.full(21, np.nan), np.full(21, np.nan), settings=FAST)
    assert d.detectable is None and "21 of 21 healthy" in d.reason and math.isnan(d.effect_size)


def test_zero_spread_is_refused_or_unchanged() -> None:
    """Constant healthy output: no threshold can be set -> refused (not 'infinite separation');
    constant and equal in both populations -> not detectable, said so."""
    d = detect(np.full(40, 2.0), np.linspace(2.5, 3.0, 40), settings=FAST)
    assert d.detectable is None and "zero spread" in d.reason and d.std_healthy == 0.0
    same = detect(np.full(40, 2.0), np.full(40, 2.0), settings=FAST)
    assert same.detectable is False and "unchanged" in same.reason


def test_too_few_healthy_measurements_for_the_false_alarm_rate() -> None:
    h, f = _gauss(19, 9.0, 1.0, seed=2)
    d = detect(h, f, settings=FAST)
    assert d.detectable is None and "need >= 20 healthy" in d.reason


def test_seeded_statistics_are_reproducible() -> None:
    h, f = _gauss(300, 1.0, 1.0, seed=9)
    assert detect(h, f, settings=FAST, seed=5) == detect(h, f, settings=FAST, seed=5)
    assert detect(h, f, settings=FAST, seed=5).auc_low != detect(h, f, settings=FAST, seed=6).auc_low
    np.testing.assert_array_equal(add_noise(h, 0.1, 0.0, seed=3), add_noise(h, 0.1, 0.0, seed=3))


def test_add_noise_has_the_stated_standard_deviation() -> None:
    """absolute 0.3 and relative 0.4 on the value 1: std sqrt(0.09 + 0.16) = 0.5 (+-2 % at n = 40 000)."""
    y = add_noise(np.ones(40_000), absolute=0.3, relative=0.4, seed=0)
    assert np.std(y) == pytest.approx(0.5, rel=0.02) and np.mean(y) == pytest.approx(1.0, abs=0.01)
    with pytest.raises(DetectionError, match="noise must be >= 0"):
        add_noise(np.ones(3), absolute=-1.0)


def test_grouped_bootstrap_widens_the_interval_of_correlated_measurements() -> None:
    """40 points x 10 identical 'realisations': re-drawing whole groups gives a wider POD
    interval than treating the 400 copies as independent."""
    rng = np.random.default_rng(0)
    h, f = np.repeat(rng.normal(0, 1, 40), 10), np.repeat(rng.normal(1.5, 1, 40), 10)
    groups = np.repeat(np.arange(40), 10)
    iid = detect(h, f, settings=FAST, seed=1)
    grouped = detect(h, f, settings=FAST, seed=1, units_healthy=groups, units_faulty=groups + 40)
    assert grouped.pod_high - grouped.pod_low > 1.5 * (iid.pod_high - iid.pod_low)


def test_assess_curve_and_smallest_detectable_fault() -> None:
    """Levels 0 (healthy), 1, 2, 3, 4 on N(0, 1) with 1024 each (quasi-random): POD =
    Phi(level - 1.645) reaches 0.9 at level z_0.9 + z_0.95 = 2.927; linear interpolation between
    levels 2 (0.741) and 3 (0.958) gives 2.73. Plots return Axes."""
    def frame(shift: float) -> pd.DataFrame:
        h, f = _gauss_qmc(1024, shift, 1.0, seed=int(shift), k=1)
        return pd.DataFrame({"a": f, "b": h})
    det = assess(frame(0.0), {lev: frame(lev) for lev in (1.0, 2.0, 3.0, 4.0)}, 0.0, FAST, seed=2)
    table = det.to_frame()
    assert set(table["output"]) == {"a", "b", COMBINED} and len(table) == 12
    sm = det.smallest_detectable().set_index("output")
    pods = stats.norm.cdf(np.array([2.0, 3.0]) - Z95)
    linear = 2.0 + (0.9 - pods[0]) / (pods[1] - pods[0])
    assert sm.loc["a", "level_at_target"] == pytest.approx(linear, abs=0.05)
    assert sm.loc["a", "level_at_target_lower"] >= sm.loc["a", "level_at_target"]
    assert math.isnan(sm.loc["b", "level_at_target"]) and "does not reach" in sm.loc["b", "reason"]
    assert det.deciding_output() == "a"
    assert det.plot_curve() is not None and det.plot_histograms(3.0).get_xlabel() == "a [-]"
    import matplotlib.pyplot as plt
    plt.close("all")


def test_settings_are_validated() -> None:
    with pytest.raises(DetectionError, match=r"false_alarm = 0.6; allowed: in \(0, 0.5\)"):
        DetectionSettings(false_alarm=0.6)
    with pytest.raises(DetectionError, match="confidence"):
        DetectionSettings(confidence=1.0)


def _crossed(n_points: int, n_real: int, shift: float, paired: bool, rng: np.random.Generator,
             var_real: float = 0.9, var_point: float = 0.05, tie: float | None = None
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Healthy and faulty measurements ``a_point + b_record + e`` (total variance 1) of ``n_points`` x
    ``n_real``, the faulty shifted by ``shift``; ``paired``: the faulty share the points and records
    (common random numbers), else their own. Returns values and units (point, record) of both."""
    sd_e = math.sqrt(1.0 - var_real - var_point)

    def draw(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return (a[:, None] + b[None, :] + sd_e * rng.standard_normal((n_points, n_real))).ravel()

    def effects() -> tuple[np.ndarray, np.ndarray]:
        return math.sqrt(var_point) * rng.standard_normal(n_points), math.sqrt(var_real) * rng.standard_normal(n_real)

    a, b = effects()
    h = draw(a, b)
    f = draw(*(effects() if not paired else (a, b))) + shift
    if tie is not None:
        h, f = np.round(h / tie) * tie, np.round(f / tie) * tie
    units = np.column_stack([np.repeat(np.arange(n_points), n_real), np.tile(np.arange(n_real), n_points)])
    return h, f, units, units if paired else units + [n_points, n_real]


def test_issue_33_four_tight_record_clusters_with_common_random_numbers() -> None:
    """The issue's study: 16 points x 4 records, the record sets the value (std 2.4e-10 between
    records, 1e-13 inside) and each faulty value sits 0.02-0.06 healthy std above its healthy twin
    (same point, same record). The old count gave AUC 0.625 = 0.5 + 1/(2 x 4) with a narrow
    interval and POD 0.25. Compared only across points and records, AUC is within 0.03 of the
    true ~0.50-0.52 with an interval that contains 0.5, POD's interval contains the false-alarm
    rate, and the verdict says the design cannot answer."""
    rng = np.random.default_rng(33)
    records = 2.4e-10 * rng.standard_normal(4)
    h = (records[None, :] + 1e-13 * rng.standard_normal((16, 4))).ravel() + 1e-8
    units = np.column_stack([np.repeat(np.arange(16), 4), np.tile(np.arange(4), 16)])
    for frac in (0.02, 0.06):
        f = h + frac * np.std(h, ddof=1)
        d = detect(h, f, settings=FAST, seed=1, units_healthy=units, units_faulty=units)
        assert abs(d.auc - 0.5) <= 0.03 and d.auc_low <= 0.5 <= d.auc_high, d
        assert d.pod_low <= 0.05 <= d.pod_high, d
        assert d.detectable is None and d.reason.startswith("4 realisations: POD resolution"), d.reason
        assert d.n_eff_healthy < 8
        old = detect(h, f, settings=FAST, seed=1)          # treated as 64 independent measurements: the bias
        assert old.auc == pytest.approx(0.625, abs=1e-9) and old.auc_low > 0.5 and old.pod == 0.25


def test_pairs_sharing_no_unit_are_counted_exactly() -> None:
    """2 points x 2 records, CRN: healthy [[0, 10], [1, 11]], faulty = healthy + 0.5. Pairs sharing no
    point and no record: (h[0,0], f[1,1]), (h[0,1], f[1,0]), (h[1,0], f[0,1]), (h[1,1], f[0,0]):
    0 < 11.5, 10 > 1.5, 1 < 10.5, 11 > 0.5 -> AUC 2/4; the dense and the sorted counts agree on
    independent measurements with ties (weights of 50 re-draws)."""
    h = np.array([0.0, 10.0, 1.0, 11.0])
    units = np.array([[0, 0], [0, 1], [1, 0], [1, 1]])
    lay = layout(units, units, 4, 4)
    one = np.ones((1, 4), np.float32)
    assert _Pairs.of(h, h + 0.5, lay).stats(one, one, 0.05)[0, 0] == 0.5
    rng = np.random.default_rng(0)
    h, f = np.round(rng.normal(0, 1, 300), 1), np.round(rng.normal(1, 1, 250), 1)
    free = layout(None, None, 300, 250)
    wh, wf = free.weights(50, rng)
    np.testing.assert_allclose(_Pairs.of(h, f, free).stats(wh, wf, 0.05), _Independent.of(h, f).stats(wh, wf, 0.05),
                               atol=1e-6)


def test_ties_at_the_threshold_never_let_a_cluster_through() -> None:
    """Healthy: 90 zeros and 10 ones; the 5 % threshold is the 95th smallest, 1: no healthy value
    lies beyond it (false alarms 0, not 0.10), and a faulty population of ones is never detected
    (POD 0), however many there are. Faulty 2s are all detected."""
    h = np.r_[np.zeros(90), np.ones(10)]
    assert threshold_at(h, 0.05) == 1.0
    d = detect(h, np.ones(50), settings=FAST)
    assert d.false_alarm == 0.0 and d.pod == 0.0 and d.pod_low == 0.0
    assert detect(h, np.full(50, 2.0), settings=FAST).pod == 1.0


def _coverage(designs: list[tuple[int, int, bool, float | None]], shifts: tuple[float, ...], reps: int,
              n_boot: int) -> tuple[float, float, float, int]:
    """Coverage of AUC = Phi(D / sqrt 2) and POD = Phi(D - z_0.95) by the 95 % intervals, and the mean AUC error."""
    settings = DetectionSettings(bootstrap=n_boot)
    rng = np.random.default_rng(2024)
    hits_auc = hits_pod = n = 0
    err = []
    for n_points, n_real, paired, tie in designs:
        for shift in shifts:
            auc, pod = stats.norm.cdf(shift / math.sqrt(2)), stats.norm.cdf(shift - Z95)
            for i in range(reps):
                h, f, uh, uf = _crossed(n_points, n_real, shift, paired, rng,
                                        *((0.9, 0.05) if n_real < 10 else (0.5, 0.2)), tie=tie)
                d = detect(h, f, settings=settings, seed=i, units_healthy=uh, units_faulty=uf, direction=1)
                hits_auc += d.auc_low <= auc <= d.auc_high
                hits_pod += d.pod_low <= pod <= d.pod_high
                err.append(d.auc - auc)
                n += 1
    return hits_auc / n, hits_pod / n, float(np.mean(err)), n


def test_interval_coverage_fast() -> None:
    """Clustered (own points and records) and paired (common random numbers) Gaussian designs, 4 and
    20 records, shifts 0-3, ties: 95 % intervals cover AUC and POD in >= 93 % of 192 data sets and
    the AUC is unbiased (mean error within 0.02, the sampling spread of this small run)."""
    designs = [(8, 4, True, None), (8, 4, False, None), (4, 20, True, None), (4, 20, False, 0.5)]
    cov_auc, cov_pod, bias, n = _coverage(designs, (0.0, 1.0, 2.0, 3.0), 12, 100)
    assert n == 192
    assert cov_auc >= 0.93 and cov_pod >= 0.93, (cov_auc, cov_pod)
    assert abs(bias) <= 0.02, bias


@pytest.mark.slow
def test_interval_coverage() -> None:
    """The coverage study at size: 8 designs (16 points x 4 or 20 records, clustered or paired, with
    and without ties) x shifts 0, 1, 2, 3 x 60 data sets, 400 re-draws each: coverage >= 93 % of
    both intervals and |mean AUC error| <= 0.01."""
    designs = [(16, n_real, paired, tie) for n_real in (4, 20) for paired in (True, False) for tie in (None, 0.25)]
    cov_auc, cov_pod, bias, n = _coverage(designs, (0.0, 1.0, 2.0, 3.0), 60, 400)
    assert n == 1920
    assert cov_auc >= 0.93 and cov_pod >= 0.93, (cov_auc, cov_pod)
    assert abs(bias) <= 0.01, bias


def test_combined_interval_carries_the_training_variability() -> None:
    """12 sensors, one of which sees a shift of 1.5, 60 measurements each: the discriminant trained on
    30 points is noisy. Its interval (re-trained on each re-draw) is wider than the interval of the
    same held-out scores taken as one fixed sensor."""
    rng = np.random.default_rng(5)
    h, f = rng.normal(0, 1, (60, 12)), rng.normal(0, 1, (60, 12))
    f[:, 0] += 1.5
    both = detect_combined(h, f, settings=FAST, seed=3)
    sh, sf = fisher_scores(h, f, seed=np.random.SeedSequence(3).spawn(2)[0])
    fixed = detect(sh, sf, settings=FAST, seed=3, direction=1)
    assert both.auc == pytest.approx(fixed.auc, abs=1e-12)
    assert both.auc_high - both.auc_low > 1.2 * (fixed.auc_high - fixed.auc_low)


def test_greedy_sensor_choice_finds_the_informative_sensors_and_validates_them() -> None:
    """Six sensors; two see half the fault each (Delta = 3 over unit noise), four see nothing. The
    greedy search on the selection half picks exactly the two; on held-out points their Fisher
    detector has AUC Phi(3 / sqrt 2 / sqrt 2) = Phi(1.5) = 0.933 inside its interval."""
    rng = np.random.default_rng(11)
    h, f = rng.normal(0, 1, (400, 6)), rng.normal(0, 1, (400, 6))
    f[:, [1, 4]] += 1.5
    names = [f"s{i}" for i in range(6)]
    pick = select_sensors(pd.DataFrame(h, columns=names), pd.DataFrame(f, columns=names), FAST, seed=2)
    assert sorted(pick["sensors"]) == ["s1", "s4"]
    v = pick["validation"]
    assert v.n_healthy + v.n_faulty < 800 and v.auc_low <= stats.norm.cdf(1.5) <= v.auc_high
    assert v.auc >= pick["validation_all"].auc - 0.02
