"""``ddgsa validate`` runs the model's own checks over the whole study (:mod:`ddgsa.study.checks`): the
rig's sampling of every scene, the valid region over the support, unit hints; and the run's
console names the first failure reason of an output whose indices are refused."""

from __future__ import annotations

import warnings
from pathlib import Path
from types import SimpleNamespace

import pandas as pd
import pytest

from ddgsa.study.checks import study_findings, support_points
from ddgsa.cli import main
from ddgsa.loads.scene import Scene
from ddgsa.models import get as get_model
from ddgsa.models.hss_rig.model import BEARING_GEOMETRY
from ddgsa.report.write import no_effect_lines
from ddgsa.study.spec import StudyWarning, load_study

RIG = """\
name: rig
model: {{name: hss_rig, fidelity: linear}}
parameters:
  disk_mass: {{nominal: 15.0, spread: 0.1}}
scenes: {{kind: steady, speed_rpm: {speeds}, duration: 1.0, sample_rate: {rate}, settle: 0.1}}
outputs: [order1x_disk_y]
methods:
  - {{method: mdrm, points: 3}}
"""
DD = """\
name: dd
model: {{name: direct_drive, fidelity: rigid}}
parameters:
  rear_bearing_x: {{low: {low}, high: {high}}}
  k_front_z: {{nominal: {k}, spread: 0.2}}
scenes: {{wind_speed: 11, duration: 60}}
outputs: [damage_front]
methods:
  - {{method: mdrm, points: 3}}
"""


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "s.yaml"
    path.write_text(text)
    return path


def test_an_aliased_rig_scene_is_refused_by_validate_with_the_limit_as_a_rate(tmp_path: Path, capsys) -> None:
    # the second scene (1500 rpm) at 500 Hz: 3 x BPFI = 406 Hz gets 1.2 samples a period; the first (600 rpm) is fine
    path = _write(tmp_path, RIG.format(speeds="[600, 1500]", rate=500))
    assert main(["validate", str(path)]) == 2
    err = capsys.readouterr().err
    bpfi3 = 3 * float(BEARING_GEOMETRY.bpfi(25.0))
    assert "scene 1 (kind=steady, speed_rpm=1500)" in err and "scene 0" not in err
    assert f"bearing defect frequency 3 x BPFI at {bpfi3:.4g} Hz" in err
    assert f"more than {2 * bpfi3:.4g} Hz avoids aliasing" in err and " mode" not in err
    assert "Traceback" not in err


def test_a_coarse_rig_scene_is_a_note_that_minus_q_hides(tmp_path: Path, capsys) -> None:
    path = _write(tmp_path, RIG.format(speeds=1500, rate=2000))
    with warnings.catch_warnings():
        warnings.simplefilter("error")                        # the note is not a raw Python warning
        assert main(["validate", str(path)]) == 0
        err = capsys.readouterr().err
        assert err.count("samples per period") == 1 and "ddgsa: note: " in err and "4.9 samples per period" in err
        assert "warnings.warn" not in err
        assert main(["-q", "validate", str(path)]) == 0
    err = capsys.readouterr().err              # only the default shaft basis's warning (tests/models/test_basis.py)
    assert "note" not in err and all("field 'model.options': scene 0: shaft basis" in x for x in err.splitlines())


def test_a_speed_that_reads_like_hz_gets_a_hint(tmp_path: Path, capsys) -> None:
    path = _write(tmp_path, RIG.format(speeds=25, rate=2000))
    assert main(["validate", str(path)]) == 2
    assert "if you meant Hz write '25 Hz' (= 1500 rpm)" in capsys.readouterr().err


def test_the_support_is_checked_against_the_valid_region(tmp_path: Path, capsys) -> None:
    # rear bearing from 0.5 to 7 m: it crosses the front bearing (1 m) below 1 m and leaves the 6 m shaft above 6 m,
    # so a share (1 - 0.5) / 6.5 + (7 - 6) / 6.5 = 23 % of the uniform support is invalid
    study = load_study(_write(tmp_path, DD.format(low=0.5, high=7, k=1e10)))
    points = support_points(study)
    assert len(points) == 4 + 64
    (found,) = [f for f in study_findings(study) if f.field == "parameters"]
    bad = sum(p["rear_bearing_x"] < 1 or p["rear_bearing_x"] > 6 for p in points)   # the closed form of the region
    assert found.level == "warning" and found.message.startswith(f"{bad} of 68 checked points")
    assert "bearing positions must satisfy" in found.message
    sampled = [p["rear_bearing_x"] for p in points[4:]]
    assert sum(x < 1 or x > 6 for x in sampled) / 64 == pytest.approx(1.5 / 6.5, abs=0.06)
    # wholly outside: refused
    with pytest.warns(StudyWarning, match="nominal point is outside"):
        study = load_study(_write(tmp_path, DD.format(low=6.5, high=7, k=1e10)))
    assert [f.level for f in study_findings(study) if f.field == "parameters"] == ["error"]
    assert main(["validate", str(tmp_path / "s.yaml")]) == 2
    assert "every evaluation would fail" in capsys.readouterr().err


def test_a_parameter_1000x_off_its_nominal_gets_a_unit_warning_even_when_quiet(tmp_path: Path, capsys) -> None:
    """Inside its range but 1000x below the nominal, where kN/m would bring it back: a likely units
    mistake, so a warning that ``-q`` does not hide (exit 0: the value may be meant)."""
    path = _write(tmp_path, DD.format(low=4, high=5, k=1e7))
    assert main(["validate", str(path)]) == 0
    err = capsys.readouterr().err
    assert "field 'parameters.k_front_z': 1e+07 N/m is 1,000x below the model's nominal 1e+10 N/m" in err
    assert "unit: kN/m" in err
    quiet = (main(["-q", "validate", str(path)]), capsys.readouterr().err)
    assert quiet[0] == 0 and "warning" in quiet[1] and "unit: kN/m" in quiet[1]


def test_the_console_names_the_first_failure_reason(write_study, tmp_path: Path, capsys) -> None:
    path = write_study("failing", options="{fail_above: 2.5}")
    assert main(["-q", "run", str(path), "--out", str(tmp_path / "out")]) == 3
    err = capsys.readouterr().err
    assert "output 'y': no method's indices are confirmed" in err
    assert "evaluations failed, the first: RuntimeError: x1 = " in err and "above fail_above = 2.5" in err


def test_the_rigid_direct_drive_names_exactly_the_parameters_without_effect() -> None:
    # independent check: change each parameter by 30 % and compare the outputs bit for bit
    model = get_model("direct_drive", fidelity="rigid")
    unused = model.unused_parameters()
    scene = Scene(wind_speed=11.0, duration=10.0, seed=1)
    names = ["k_front_z", "hub_mass", *unused]
    rows = [model.nominal] + [{**model.nominal, n: 1.3 * model.nominal[n]} for n in names]
    y = model.evaluate(pd.DataFrame(rows), scene).to_numpy()
    changed = {n: bool((y[i + 1] != y[0]).any()) for i, n in enumerate(names)}
    assert changed == {n: n in ("k_front_z", "hub_mass") for n in names}
    assert set(unused) == {"shaft_bending_stiffness", "shaft_torsional_stiffness", "shaft_axial_stiffness",
                           "shaft_damping_ratio", "shaft_radius"}
    assert get_model("direct_drive", fidelity="flexible").unused_parameters() == {}


def test_parameters_without_effect_are_warned_and_listed_in_the_summary(tmp_path: Path, capsys) -> None:
    path = _write(tmp_path, DD.format(low=4, high=5, k=1e10).replace(
        "parameters:\n", "parameters:\n  shaft_bending_stiffness: {nominal: 1e9, spread: 0.2}\n"))
    assert main(["validate", str(path)]) == 0
    assert ("field 'parameters.shaft_bending_stiffness': has no effect at fidelity rigid"
            in capsys.readouterr().err)
    study = load_study(path)
    indices = pd.DataFrame({"parameter": ["rear_bearing_x", "k_front_z", "shaft_bending_stiffness"] * 2,
                            "ST": [0.7, 0.3, 0.0, 0.6, 0.0, 0.0]})
    lines = no_effect_lines(SimpleNamespace(study=study, indices=indices))
    assert "- `shaft_bending_stiffness`: has no effect at fidelity rigid" in "\n".join(lines)
    assert not any("k_front_z" in line for line in lines)      # 0 in one row only: it has an effect


GEARED = """\
name: geared
model: {{name: indirect_drive, fidelity: linear}}
parameters:
  k_mount_z: {{low: {low}, high: {high}}}
scenes: {{wind_speed: 11, duration: 60}}
outputs: [housing_rx_mean]
methods:
  - {{method: mdrm, points: 3}}
"""


def test_geared_drive_mounts_too_soft_for_the_torque_are_found_before_running(tmp_path: Path, capsys) -> None:
    from ddgsa.loads import NREL5MW

    # the check's closed form, roll = Q_rated / (2 k_z a^2), against the model's own operating state
    # (nonlinear static equilibrium of the constrained system under the rated torque)
    model = get_model("indirect_drive", fidelity="rigid")
    for k in (2e7, 2e8):
        asm, q, _ = model.build({"k_mount_z": k}, NREL5MW.rated_speed, NREL5MW.rated_torque)
        assert q[asm.system.index("housing.rx")] == pytest.approx(NREL5MW.rated_torque / (2 * k * 1.2 ** 2), rel=0.02)
    limit = NREL5MW.rated_torque / (2 * 0.1 * 1.2 ** 2)                  # k_z giving 0.1 rad: 1.37e7 N/m
    assert model.point_problems({"k_mount_z": 1.01 * limit}) == []
    (problem,) = model.point_problems({"k_mount_z": 0.99 * limit})
    assert "torque-arm mounts too soft" in problem and f"k_mount_z >= {limit:.3g} N/m" in problem
    # a support partly below the limit is warned with the share that will fail; wholly below, refused
    study = load_study(_write(tmp_path, GEARED.format(low=1e7, high=4e7)))
    (found,) = [f for f in study_findings(study) if f.field == "parameters"]
    bad = sum(p["k_mount_z"] < limit for p in support_points(study))
    assert found.level == "warning" and found.message.startswith(f"{bad} of 66 checked points")
    with pytest.warns(StudyWarning, match="nominal point is outside"):
        load_study(_write(tmp_path, GEARED.format(low=1e6, high=5e6)))
    assert main(["validate", str(tmp_path / "s.yaml")]) == 2
    err = capsys.readouterr().err
    assert "every evaluation would fail" in err and "torque-arm mounts too soft" in err and "Traceback" not in err


def test_an_mdrm_cut_point_outside_the_valid_region_is_refused(tmp_path: Path, capsys) -> None:
    # rear bearing uniform on [0.5, 1.1] m: its mean 0.8 m lies in front of the front bearing (1 m), so every M-DRM
    # cut line runs through an invalid point although (1.1 - 1) / 0.6 of the support is valid
    with pytest.warns(StudyWarning, match="nominal point is outside"):
        study = load_study(_write(tmp_path, DD.format(low=0.5, high=1.1, k=1e10)))
    (cut,) = [f for f in study_findings(study) if f.field == "methods[0]"]
    assert cut.level == "error" and "rear_bearing_x=0.8" in cut.message and "bearing positions must satisfy" in cut.message
    assert main(["validate", str(tmp_path / "s.yaml")]) == 2
    assert "every cut line runs through it" in capsys.readouterr().err


SOBOL = """\
name: sobol
model: {name: analytic, fidelity: exact}
parameters:
  x1: {low: -3.14159265, high: 3.14159265}
  x2: {low: -3.14159265, high: 3.14159265}
  x3: {low: -3.14159265, high: 3.14159265}
scenes: {wind_speed: [8.0], turbulence_intensity: 0.0, duration: 1.0, dt: 0.05}
outputs: [y_positive]
methods:
  - {method: mdrm, points: 7, check: 48}
  - {method: pce, order: 2, n: 100}
"""


def test_a_sobol_size_other_than_a_power_of_two_is_one_hint_naming_the_field(tmp_path: Path, capsys) -> None:
    """Newcomer trial: ``check: 48`` printed scipy's raw UserWarning (with its source line) twice. Now
    one hint per field with the two nearest powers of two, and no raw warning from ddgsa's own draws."""
    from scipy.stats import qmc

    from ddgsa.gsa.space import ParameterSpace

    with pytest.warns(UserWarning, match="balance properties of Sobol"):   # scipy does warn for 48 points
        qmc.Sobol(3, rng=0).random(48)
    path = _write(tmp_path, SOBOL)
    assert main(["validate", str(path)]) == 0
    err = capsys.readouterr().err
    assert err.count("field 'methods[0].check': 48 Sobol' points are not a power of two") == 1
    assert "use 32 or 64" in err
    assert "field 'methods[1].n': 100 Sobol' points" in err and "use 64 or 128" in err
    assert "methods[0].points" not in err
    assert "balance properties" not in err and "UserWarning" not in err
    space = ParameterSpace.from_dict({"a": {"low": 0.0, "high": 1.0}, "b": {"low": 0.0, "high": 1.0}})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert space.sample(48, seed=0).shape == (48, 2)
