"""SALib interop: a ProblemSpec round-trips through ``ParameterSpace.from_salib`` / ``to_salib``; on
the same samples SALib and ddgsa give the same indices; a study reads its parameters from a SALib
problem file; ddgsa's seed is SALib's sample given ``numpy.random.default_rng(seed)``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from SALib import ProblemSpec
from SALib.sample import fast_sampler, latin
from SALib.sample import sobol as salib_sobol
from scipy.stats import qmc

from ddgsa.errors import SpaceError, StudyError
from ddgsa.gsa.base import get_method
from ddgsa.gsa.space import ParameterSpace
from ddgsa.study.spec import load_study

PROBLEM = {"names": ["a", "b", "c", "d", "e"],
           "bounds": [[-np.pi, np.pi], [1.0, 0.2], [0.1, 0.3], [0.0, 4.0, 1.0, 1.5], [2.0, 5.0, 0.25]],
           "dists": ["unif", "norm", "lognorm", "truncnorm", "triang"],
           "groups": ["g1", "g1", "g2", "g2", "g2"]}


def test_problemspec_round_trips() -> None:
    sp = ProblemSpec(PROBLEM)
    space = ParameterSpace.from_salib(sp)
    assert space["e"].args == pytest.approx({"low": 2.0, "mode": 2.75, "high": 5.0})
    assert space["c"].args == {"mu": 0.1, "sigma": 0.3} and space["b"].mean == pytest.approx(1.0)
    back = space.to_salib(groups=dict(zip(PROBLEM["names"], PROBLEM["groups"])))
    again = ProblemSpec(back)
    for key in ("names", "dists", "groups"):
        assert list(again[key]) == PROBLEM[key]
    for got, want in zip(again["bounds"], PROBLEM["bounds"]):
        assert got == pytest.approx(want, rel=1e-12)
    assert again["num_vars"] == 5
    assert ParameterSpace.from_salib(back) == space


def ishigami(x: np.ndarray) -> np.ndarray:
    return np.sin(x[:, 0]) + 7 * np.sin(x[:, 1]) ** 2 + 0.1 * x[:, 2] ** 4 * np.sin(x[:, 0]) + x[:, 3] * x[:, 4]


def test_same_samples_give_the_same_indices_in_salib_and_ddgsa() -> None:
    """ddgsa's Saltelli design on the space equals SALib's own sample of the exported problem (same
    Sobol' scrambling seed; ddgsa maps through chaospy's inverse CDFs, SALib through scipy's), and SALib's
    analysis of those model values equals ddgsa's indices to 1e-9. ddgsa's ``saltelli`` runs SALib's
    estimator (``ddgsa.gsa.salib``): the design and the distribution mapping are the independent part."""
    space = ParameterSpace.from_salib(ProblemSpec(PROBLEM))
    method = get_method("saltelli")
    design = method.design(space, n=256, seed=3)
    sp = ProblemSpec(space.to_salib())
    sp.sample_sobol(256, calc_second_order=False, scramble=True, seed=np.random.default_rng(3))
    np.testing.assert_allclose(sp.samples, design.points, rtol=1e-9, atol=1e-9)
    y = ishigami(sp.samples)
    sp.set_results(y)
    sp.analyze_sobol(calc_second_order=False, num_resamples=100, seed=np.random.default_rng(0))
    ours = method.analyze(space, design, y).indices
    np.testing.assert_allclose(ours["S1"], sp.analysis["S1"], atol=1e-9)
    np.testing.assert_allclose(ours["ST"], sp.analysis["ST"], atol=1e-9)
    assert ours["ST"].max() > 0.3          # not a trivially zero comparison


UNIT = {"names": ["a", "b", "c"], "bounds": [[0.0, 1.0]] * 3}


@pytest.mark.parametrize("method, sampler, options", [
    ("saltelli", lambda problem, seed: salib_sobol.sample(problem, 16, calc_second_order=False, seed=seed), {"n": 16}),
    ("fast", lambda problem, seed: fast_sampler.sample(problem, 65, M=4, seed=seed), {"n": 65, "M": 4}),
    ("rbd_fast", lambda problem, seed: latin.sample(problem, 32, seed=seed), {"n": 32}),
])
@pytest.mark.parametrize("seed", [0, 7])
def test_a_ddgsa_seed_is_salibs_sample_given_a_fresh_generator(method: str, sampler, options: dict, seed: int) -> None:
    """ddgsa hands each SALib sampler ``numpy.random.default_rng(seed)``. SALib's ``handle_seed`` and
    scipy's ``qmc.Sobol`` spawn a child of a Generator they are given (``Generator.spawn(1)[0]``: the
    seed sequence ``SeedSequence(seed).spawn(1)[0]``) but seed an integer directly
    (``default_rng(seed)``). So SALib gives ddgsa's exact unit sample for
    ``seed=numpy.random.default_rng(seed)`` (a fresh one per call: each spawn advances it), and SALib's
    own samplers for that child seed sequence; the bare integer gives another sample (docs: SALib)."""
    ours = get_method(method).design(ParameterSpace.from_salib(UNIT), seed=seed, **options).meta["unit"]
    problem = dict(UNIT, num_vars=3)
    np.testing.assert_array_equal(sampler(problem, np.random.default_rng(seed)), ours)
    if method != "saltelli":        # SALib's own samplers take a SeedSequence (scipy's qmc does not)
        np.testing.assert_array_equal(sampler(problem, np.random.SeedSequence(seed).spawn(1)[0]), ours)
    assert not np.array_equal(sampler(problem, seed), ours)


def test_the_saltelli_design_is_sobols_sequence_in_saltellis_layout() -> None:
    """Independently of SALib: the rows are A, AB_1 .. AB_d, B per base point (A and B the two halves
    of one scrambled Sobol' sequence in 2d dimensions, scipy's ``qmc.Sobol`` seeded as above)."""
    d, n = 3, 16
    base = qmc.Sobol(2 * d, scramble=True, rng=np.random.default_rng(5)).random(n)
    a, b = base[:, :d], base[:, d:]
    blocks = [a] + [np.where(np.arange(d) == i, b, a) for i in range(d)] + [b]
    expected = np.stack(blocks, axis=1).reshape(n * (d + 2), d)
    ours = get_method("saltelli").design(ParameterSpace.from_salib(UNIT), n=n, seed=5).meta["unit"]
    np.testing.assert_array_equal(ours, expected)


@pytest.mark.parametrize("problem, match", [
    ({"names": ["a"], "bounds": [[1, 2]], "dists": ["logunif"]}, r"parameter 'a': dist 'logunif' has no ddgsa"),
    ({"names": ["a", "b"], "bounds": [[1, 2]]}, r"names \(2\), bounds \(1\)"),
    ({"names": ["a"], "bounds": [[2, 1]]}, r"parameter 'a': low \(2.0\) must be < high \(1.0\)"),
    ({"names": ["a"], "bounds": [[0, 1, 2]], "dists": ["norm"]}, r"norm needs bounds \[mean, std\]"),
    ({"bounds": [[0, 1]]}, r"missing key\(s\) \['names'\]"),
])
def test_bad_salib_problems_are_named(problem: dict, match: str) -> None:
    with pytest.raises(SpaceError, match=match):
        ParameterSpace.from_salib(problem)


STUDY = """\
name: from_salib
model: {{name: analytic, fidelity: exact}}
parameters: {file}
scenes: {{wind_speed: [8.0], turbulence_intensity: 0.0, duration: 1.0, dt: 0.05}}
outputs: [y]
methods: [{{method: saltelli, n: 64}}]
"""


def test_a_study_reads_its_parameters_from_a_salib_problem_file(tmp_path: Path) -> None:
    (tmp_path / "problem.txt").write_text("x1,-3.14159,3.14159,NA,unif\nx2,-3.14159,3.14159,NA,unif\n"
                                          "x3,0.0,1.0,G,unif\n")
    (tmp_path / "problem.json").write_text('{"names": ["x1", "x2", "x3"], "bounds": [[-3, 3], [-3, 3], [0, 2, 0.5]],'
                                           ' "dists": ["unif", "unif", "triang"]}')
    (tmp_path / "txt.yaml").write_text(STUDY.format(file="problem.txt"))
    (tmp_path / "json.yaml").write_text(STUDY.format(file="problem.json"))
    txt = load_study(tmp_path / "txt.yaml").space
    assert txt.names == ("x1", "x2", "x3") and txt["x3"].args == {"low": 0.0, "high": 1.0}
    js = load_study(tmp_path / "json.yaml").space
    assert js["x3"].args == pytest.approx({"low": 0.0, "mode": 1.0, "high": 2.0})
    (tmp_path / "bad.yaml").write_text(STUDY.format(file="nothing.json"))
    with pytest.raises(StudyError, match=r"bad.yaml: field 'parameters': SALib problem file .*nothing.json not found"):
        load_study(tmp_path / "bad.yaml")
    (tmp_path / "garbage.txt").write_text("x1 -3 3\nx2\n")
    (tmp_path / "bad.yaml").write_text(STUDY.format(file="garbage.txt"))
    with pytest.raises(StudyError, match=r"bad.yaml: field 'parameters': SALib problem file .*garbage.txt: .*name,low,high"):
        load_study(tmp_path / "bad.yaml")
    (tmp_path / "short.txt").write_text("x1,-3\n")            # no upper bound: SALib's reader raises TypeError
    (tmp_path / "bad.yaml").write_text(STUDY.format(file="short.txt"))
    with pytest.raises(StudyError, match=r"bad.yaml: field 'parameters': SALib problem file .*short.txt: .*name,low,high"):
        load_study(tmp_path / "bad.yaml")
