"""Units a study writes are converted to the model's SI unit or refused (exit 2) naming file, field,
the unit given and the dimension expected: one test per place (parameters, fixed values, grid
values, scene fields of wind and rig scenes, fault levels, outputs). Each compares the study
written with units against the same study written in SI (an independent spelling of it)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ddgsa.cli import main
from ddgsa.errors import StudyError
from ddgsa.study.spec import load_study, plan_scenes
from ddgsa.units import UnitError, convert, factor, parameter_in

DD = """\
name: units
model: {{name: direct_drive, fidelity: rigid}}
parameters:
  k_front_z: {k_front_z}
{more}scenes: {scenes}
outputs: {outputs}
methods:
  - {{method: mdrm, points: 3}}
"""


def _study(tmp_path: Path, name: str = "u", k_front_z: str = "{nominal: 1e10, spread: 0.2}", more: str = "",
           scenes: str = "{wind_speed: 11.0, duration: 60}", outputs: str = "[damage_front]") -> Path:
    path = tmp_path / f"{name}.yaml"
    path.write_text(DD.format(k_front_z=k_front_z, more=more, scenes=scenes, outputs=outputs))
    return path


def test_factors_against_hand_values() -> None:
    assert factor("kN/m", "N/m") == 1e3
    assert factor("GN/m", "N/m") == 1e9
    assert factor("kN m s/rad", "N m s/rad") == 1e3
    assert factor("%", "-") == pytest.approx(0.01)
    assert factor("t", "kg") == 1e3
    assert factor("kg mm^2", "kg m^2") == pytest.approx(1e-6)
    assert convert("25 Hz", "rpm") == pytest.approx(1500.0)           # Hz counts cycles: 25 rev/s
    assert convert("5kHz", "Hz") == pytest.approx(5000.0)
    assert convert({"value": [36, 72], "unit": "km/h"}, "m/s") == pytest.approx([10.0, 20.0])
    for given, expected, words in (("kN", "N/m", "force"), ("rad/s", "rpm", "angular velocity"),
                                   ("degC", "K", "offset"), ("furlong/fortnight^3", "m", "length")):
        with pytest.raises(UnitError, match=words):
            factor(given, expected)


def test_a_parameter_in_kN_per_m_runs_at_1e10_N_per_m(tmp_path: Path) -> None:
    si = load_study(_study(tmp_path, "si"))
    kn = load_study(_study(tmp_path, "kn", "{nominal: 1e7, spread: 0.2, unit: kN/m}"))
    assert kn.space["k_front_z"].nominal == pytest.approx(1e10)
    assert kn.space["k_front_z"].support == pytest.approx(si.space["k_front_z"].support)
    np.testing.assert_allclose(kn.space.sample(8, seed=3), si.space.sample(8, seed=3), rtol=1e-12)
    # lognormal: the median scales, mu shifts by log(1000)
    ln = parameter_in({"dist": "lognormal", "mu": np.log(1e7), "sigma": 0.1, "unit": "kN/m"}, "N/m")
    assert np.exp(ln["mu"]) == pytest.approx(1e10) and ln["sigma"] == 0.1 and ln["unit"] == "N/m"


def test_fixed_and_grid_values_take_quantities(tmp_path: Path) -> None:
    study = load_study(_study(tmp_path, more='fixed: {k_rear_z: "8 GN/m", hub_mass: {value: 40, unit: t}}\n'))
    assert study.spec.fixed == pytest.approx({"k_rear_z": 8e9, "hub_mass": 4e4})
    sweep = _study(tmp_path, "sw", more="grid: {k_rear_z: {value: [5, 10], unit: GN/m}}\n").read_text()
    sweep = sweep.replace("name: units", "name: units\nkind: sweep").replace("parameters:\n  k_front_z: "
                                                                             "{nominal: 1e10, spread: 0.2}\n", "")
    sweep = sweep.replace("methods:\n  - {method: mdrm, points: 3}\n", "")
    (tmp_path / "sweep.yaml").write_text(sweep)
    assert load_study(tmp_path / "sweep.yaml").spec.grid == {"k_rear_z": pytest.approx([5e9, 1e10])}


def test_wind_scene_fields_take_quantities(tmp_path: Path) -> None:
    study = load_study(_study(tmp_path, scenes='{wind_speed: {value: [36, 43.2], unit: km/h}, duration: 1 min, '
                                               'turbulence_intensity: 12 %}'))
    scenes = [ps.scenes[0] for ps in plan_scenes(study)]
    assert [s.wind_speed for s in scenes] == pytest.approx([10.0, 12.0])
    assert scenes[0].duration == pytest.approx(60.0) and scenes[0].turbulence_intensity == pytest.approx(0.12)


def test_rig_scene_fields_take_quantities(tmp_path: Path) -> None:
    path = tmp_path / "rig.yaml"
    path.write_text("name: rig\nmodel: {name: hss_rig, fidelity: linear}\nparameters:\n"
                    "  disk_mass: {nominal: 15.0, spread: 0.1}\n"
                    "scenes: {kind: steady, speed_rpm: 25 Hz, duration: 500 ms, sample_rate: 2 kHz, settle: 50 ms}\n"
                    "outputs: [order1x_disk_y]\nmethods:\n  - {method: mdrm, points: 3}\n")
    scene = plan_scenes(load_study(path))[0].scenes[0]
    assert (scene.speed_rpm, scene.duration, scene.sample_rate, scene.settle) == pytest.approx((1500, 0.5, 2000, 0.05))


def test_fault_levels_take_the_fault_unit(tmp_path: Path) -> None:
    text = _study(tmp_path, k_front_z="{nominal: 1e7, spread: 0.1, unit: kN/m}").read_text()
    text = text.replace("name: units", "name: units\nkind: fault") + (
        "fault: {parameter: k_front_z, healthy: 1e7, faulty: [5e6, 2e6], unit: kN/m, samples: 32}\n")
    (tmp_path / "fault.yaml").write_text(text)
    fault = load_study(tmp_path / "fault.yaml").spec.fault
    assert fault.healthy == pytest.approx(1e10) and fault.levels == pytest.approx([5e9, 2e9])


def test_an_output_in_mm_reports_1000_times_the_metres(tmp_path: Path) -> None:
    study = load_study(_study(tmp_path, outputs="[damage_front, {name: rms_deflection_hub, unit: mm}]"))
    assert study.outputs == ["damage_front", "rms_deflection_hub"]
    np.testing.assert_allclose(study.output_factors(study.outputs), [1.0, 1e3])
    decl = study.output_declaration(study.make_model(), "rms_deflection_hub")
    si = study.make_model().output("rms_deflection_hub")
    assert decl.unit == "mm" and decl.high == pytest.approx(1e3 * si.high) and decl.label.endswith("[mm]")


@pytest.mark.parametrize(("where", "kwargs", "message"), [
    ("parameters", {"k_front_z": "{nominal: 10, spread: 0.2, unit: GN}"},
     r"field 'parameters\.k_front_z\.unit': unit 'GN' is a force .*expected a stiffness"),
    ("fixed", {"more": "fixed: {hub_mass: 40 m}\n"}, r"field 'fixed\.hub_mass': unit 'm' is a length .*expected a mass"),
    ("scenes", {"scenes": "{wind_speed: 11 rpm, duration: 60}"},
     r"field 'scenes\.wind_speed': unit 'rpm' is a frequency .*expected a speed .*in m/s"),
    ("outputs", {"outputs": "[{name: damage_front, unit: mm}]"},
     r"field 'outputs\[0\]\.unit': output 'damage_front': unit 'mm' is a length"),
    ("unreadable", {"k_front_z": "{nominal: 10, spread: 0.2, unit: kN/mm/}"}, r"field 'parameters\.k_front_z\.unit': cannot read unit 'kN/mm/'"),
])
def test_a_unit_of_another_dimension_is_refused_with_exit_2(tmp_path: Path, capsys, where: str, kwargs: dict,
                                                           message: str) -> None:
    path = _study(tmp_path, **kwargs)
    with pytest.raises(StudyError, match=r"u\.yaml: " + message):
        load_study(path)
    assert main(["validate", str(path)]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and str(path) in err
