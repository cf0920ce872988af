"""Scenes are the model's: a study of the test rig validates its ``scenes:`` against ``RigScene``
(errors name the file, the field, the value and the allowed fields), runs end to end and labels
its scenes by the rig's fields; wind studies keep their schema (and their digests)."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest

from ddgsa.cli import main
from ddgsa.errors import StudyError
from ddgsa.loads.scene import Scene
from ddgsa.models.hss_rig.scenes import RigScene
from ddgsa.runner import ModelId, task_key
from ddgsa.study.spec import ModelScenesSpec, ScenesSpec, load_study, load_yaml, plan_scenes, validate_study

ROOT = Path(__file__).resolve().parents[2]

RIG = """\
name: rig_tiny
model: {{name: hss_rig, fidelity: linear}}
parameters:
  disk_mass: {{nominal: 15.0, spread: 0.1}}
scenes: {{{scenes}}}
outputs: [order1x_disk_y, rms_housing_1_y]
methods:
  - {{method: mdrm, points: 3}}
"""
STEADY = "kind: steady, speed_rpm: [1200, 1500], duration: 0.5, sample_rate: 2000, settle: 0.05, realisations: 2"


def _write(tmp_path: Path, scenes: str) -> Path:
    path = tmp_path / "rig.yaml"
    path.write_text(RIG.format(scenes=scenes))
    return path


def test_rig_study_builds_rig_scenes_over_its_grid(tmp_path: Path) -> None:
    study = load_study(_write(tmp_path, STEADY))
    assert isinstance(study.spec.scenes, ModelScenesSpec)
    assert study.scene_fields == ["kind", "speed_rpm"] and not study.wind
    planned = plan_scenes(study)
    assert [ps.fields for ps in planned] == [{"kind": "steady", "speed_rpm": 1200},
                                             {"kind": "steady", "speed_rpm": 1500}]
    first = planned[0].scenes
    assert first == (RigScene("steady", 1200.0, 0.5, 2000.0, 0.05, seed=1),
                     RigScene("steady", 1200.0, 0.5, 2000.0, 0.05, seed=2))       # seeds: seed + realisation


def test_a_list_of_kinds_labels_every_scene(tmp_path: Path) -> None:
    study = load_study(_write(tmp_path, "kind: [startup, steady, coastdown], speed_rpm: 1500, duration: 0.5, "
                                        "sample_rate: 2000, settle: 0.1"))
    assert [ps.fields for ps in plan_scenes(study)] == [{"kind": k, "speed_rpm": 1500}
                                                         for k in ("startup", "steady", "coastdown")]


def test_a_mapping_gives_each_kind_its_own_record_length(tmp_path: Path) -> None:
    """``duration: {startup: ..., steady: ..., coastdown: ...}`` beside ``kind: [...]``: each scene takes its
    kind's value (units converted per value), no new axis, and the store keys a run by it (the scene's
    ``to_dict`` carries the duration)."""
    study = load_study(_write(tmp_path, "kind: [startup, steady, coastdown], speed_rpm: 1500, "
                                        "duration: {startup: 1.2 s, steady: 600 ms, coastdown: 3}, "
                                        "sample_rate: 2000, settle: 0.1"))
    planned = plan_scenes(study)
    assert [ps.fields for ps in planned] == [{"kind": k, "speed_rpm": 1500} for k in ("startup", "steady", "coastdown")]
    assert [ps.scenes[0].duration for ps in planned] == [1.2, 0.6, 3.0]
    assert study.scene_fields == ["kind", "speed_rpm"]
    # the store keys a run by its whole scene: the coast-down at 3 s is not the one at 2 s
    shorter = plan_scenes(load_study(_write(tmp_path, "kind: [startup, steady, coastdown], speed_rpm: 1500, "
                                                      "duration: {startup: 1.2 s, steady: 600 ms, coastdown: 2}, "
                                                      "sample_rate: 2000, settle: 0.1")))
    key = [[task_key(ModelId("hss_rig", "linear"), ps.scenes[0].to_dict(), {"disk_mass": 15.0}, "v") for ps in p]
           for p in (planned, shorter)]
    assert key[0][:2] == key[1][:2] and key[0][2] != key[1][2]
    # a quantity ({value, unit}) stays one value, on numeric axes too: speeds per value of the speed axis
    quantity = load_study(_write(tmp_path, "kind: steady, speed_rpm: {value: [20, 25], unit: Hz}, "
                                           "duration: {1200: 0.7, 1500: 0.6}, sample_rate: 2000, settle: 0.1"))
    assert [(ps.fields["speed_rpm"], ps.scenes[0].duration) for ps in plan_scenes(quantity)] == [(1200, 0.7),
                                                                                               (1500, 0.6)]


def test_a_wind_scene_refuses_one_value_per_axis_value(tmp_path: Path) -> None:
    path = tmp_path / "wind.yaml"
    path.write_text("name: w\nparameters:\n  hub_mass: {nominal: 1.0e5, spread: 0.1}\n"
                    "scenes: {wind_speed: [11, 14], duration: {11: 60, 14: 30}}\noutputs: [damage_front]\n"
                    "methods:\n  - {method: mdrm, points: 3}\n")
    with pytest.raises(StudyError, match=r"field 'scenes\.duration': one value per value of a grid axis is for a "
                                         r"model's own scene type"):
        load_study(path)


@pytest.mark.parametrize("scenes, message", [
    ("kind: [startup, coastdown], speed_rpm: 1500, duration: {startup: 1.2}",
     r"field 'scenes\.duration': a mapping gives one value per value of a list-valued scene field, keyed by all of "
     r"its values, each once \(the lists here: kind: startup, coastdown\); got keys startup"),
    ("kind: [startup, coastdown], speed_rpm: {startup: 1200, coastdown: 1500}",
     r"field 'scenes\.speed_rpm': 'speed_rpm' labels the scenes and cannot take one value per value of another field"),
    ("kind: steady, settle: [0.1, 0.2], ramp_time: [0.1, 0.2], duration: {0.1: 2, 0.2: 3}",
     r"field 'scenes\.duration': its keys are the values of settle and of ramp_time"),
    ("kind: steady, speed_rpm: [1, 0], duration: {true: 2, false: 3}", r"field 'scenes\.duration': .*not true or false"),
    ("kind: [startup, coastdown], duration: {}", r"field 'scenes\.duration': an empty mapping gives no value"),
    ("kind: steady, speed_rpm: [[1200], 1500], duration: {1200: 2, 1500: 3}", r"field 'scenes\.duration': a mapping"),
    ("kind: steady, speed_rpm: 1500, duration: {steady: 1.2}",
     r"field 'scenes\.duration': .*\(the lists here: none\)"),
    ("kind: [startup, coastdown], duration: {startup: 1.2, coastdown: [3, 4]}",
     r"field 'scenes\.duration': a mapping gives one value per kind: \[3, 4\] is not one value"),
    ("kind: [startup, coastdown], duration: {startup: 1.2, coastdown: 3 kg}",
     r"field 'scenes\.duration': unit 'kg' is a mass"),
    ("kind: steady, speed: 1500, duration: 0.45",
     r"rig\.yaml: field 'scenes\.speed': unknown hss_rig scene field 'speed'; known: aggregate, duration, kind, "
     r"ramp_time, realisations, sample_rate, seed, settle, speed_rpm; did you mean .*'speed_rpm'.*\(given: 1500\)"),
    ("wind_speed: [8.0, 11.0]", r"field 'scenes\.wind_speed': unknown hss_rig scene field 'wind_speed'; known: .*speed_rpm"),
    ("kind: steady, speed_rpm: [], duration: 0.45", r"field 'scenes\.speed_rpm': an empty list"),
    ("kind: stedy, speed_rpm: 1500", r"field 'scenes' \(scene 0: kind=stedy, speed_rpm=1500\): rig scene field 'kind' "
                                     r"must be one of startup, steady, coastdown, got 'stedy'"),
    ("kind: steady, speed_rpm: [1500, 9000], duration: 0.45, settle: 0.05",
     r"field 'scenes' \(scene 1: kind=steady, speed_rpm=9000\): rig scene field 'speed_rpm' must be in \(0, 6000\] rpm"),
    ("kind: steady, duration: 0.45, realisations: 0", r"field 'scenes\.realisations': must be >= 1"),
])
def test_a_wrong_rig_scene_is_refused_naming_file_field_and_value(tmp_path: Path, scenes: str, message: str) -> None:
    with pytest.raises(StudyError, match=message):
        load_study(_write(tmp_path, scenes))


def test_cli_validate_refuses_a_wrong_rig_scene_field_with_exit_2(tmp_path: Path, capsys) -> None:
    assert main(["validate", str(_write(tmp_path, "kind: steady, speed: 1500"))]) == 2
    assert "did you mean" in capsys.readouterr().err


def test_wind_studies_keep_their_schema_and_digest() -> None:
    study = load_study(ROOT / "studies" / "quickstart.yaml")
    assert isinstance(study.spec.scenes, ScenesSpec) and study.wind
    assert all(isinstance(s, Scene) for ps in plan_scenes(study) for s in ps.scenes)
    committed = json.loads((ROOT / "results" / "quickstart" / "provenance.json").read_text())
    assert study.digest == committed["study_sha256"]             # the validated study is the one committed
    data, _ = load_yaml(ROOT / "studies" / "quickstart.yaml")
    data["scenes"]["kind"] = "steady"                            # a rig field in a wind study
    with pytest.raises(StudyError, match=r"quickstart\.yaml: field 'scenes\.kind': unknown field"):
        validate_study(data, ROOT / "studies" / "quickstart.yaml")


def test_rig_study_runs_end_to_end_and_labels_rig_scenes(tmp_path: Path) -> None:
    path = tmp_path / "rig_run.yaml"
    path.write_text(RIG.format(scenes="kind: steady, speed_rpm: 1500, duration: 0.45, sample_rate: 1000, settle: 0.05")
                    .replace("points: 3", "points: 2, check: 0"))
    out = tmp_path / "out"
    assert main(["-q", "run", str(path), "--out", str(out), "--allow-untrusted"]) == 0
    table = pd.read_csv(out / "indices.csv")
    assert set(table[["kind", "speed_rpm"]].itertuples(index=False, name=None)) == {("steady", 1500)}
    assert "wind_speed" not in table
    evaluations = pd.read_csv(out / "evaluations.csv")
    assert evaluations["error"].isna().all() and set(evaluations["sample_rate"]) == {1000.0}
    assert "kind=steady, speed_rpm=1500" in (out / "summary.md").read_text()
    assert not (out / "loads").exists()                            # no wind loads, no loads cache
    assert {f"spectrum_{s}_scene0.png" for s in ("housing_1_y", "disk_y", "motor_current")} <= \
        {p.name for p in out.iterdir()}                              # the model's own signal plots
