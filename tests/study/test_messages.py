"""One "unknown field / value; known: ...; did you mean ..." for every part of the schema, ``ddgsa
models [NAME]``, the defaults a newcomer meets (``--jobs``, where ``ddgsa modes`` writes), the
evaluation plan announced (M-DRM's check sample included) and no lock file left behind."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from ddgsa import cli
from ddgsa.cli import main
from ddgsa.errors import StudyError
from ddgsa.report.outdir import LOCK_NAME, claim
from ddgsa.study.spec import load_study

BASE = """\
name: typo
model: {name: direct_drive, fidelity: rigid}
parameters:
  k_front_z: {nominal: 1e10, spread: 0.2}
scenes: {wind_speed: 11, duration: 60}
outputs: [damage_front]
methods:
  - {method: mdrm, points: 3}
"""


@pytest.mark.parametrize(("old", "new", "message"), [
    ("name: typo\n", "name: typo\nmodle: 3\n", r"field 'modle': unknown field 'modle'; did you mean 'model'"),
    # (15 top-level fields: more than errors.LIST_AT_MOST, so the close matches and the count, not the list)
    ("fidelity: rigid}", "fidelity: rigid, fidelty: x}", r"field 'model\.fidelty': .*did you mean 'fidelity'"),
    ("duration: 60}", "duration: 60, turbulance: 0.1}", r"field 'scenes\.turbulance': unknown field 'turbulance'; "
                                                        r"known: aggregate, dt, .*did you mean 'turbulence_intensity'"),
    ("duration: 60}", "duration: 60, aggregate: maen}", r"field 'scenes\.aggregate': unknown value 'maen'; "
                                                        r"known: max, mean, median; did you mean 'mean'"),
    ("[damage_front]", "[damage_frnt]", r"field 'outputs\[0\]': unknown output 'damage_frnt'; known: damage_front, "
                                        r".*; did you mean 'damage_front'"),
    ("points: 3}", "points: 3}\nrun: {jbos: 2}", r"field 'run\.jbos': .*known: address, backend, batch_size, jobs, timeout; "
                                                 r"did you mean 'jobs'"),
    ("points: 3}", "points: 3, chekc: 8}", r"field 'methods\[0\]': method 'mdrm': unknown option 'chekc'; known: "
                                           r"check, .*did you mean 'check'"),
    ("spread: 0.2}", "spread: 30%}", r"'spread' must be a number, got '30%' \(a relative spread is a fraction: "
                                     r"write 0\.3\)"),
])
def test_every_part_of_the_schema_says_what_is_known_and_what_was_meant(tmp_path: Path, old: str, new: str,
                                                                        message: str) -> None:
    path = tmp_path / "typo.yaml"
    path.write_text(BASE.replace(old, new, 1))
    with pytest.raises(StudyError, match=message):
        load_study(path)


def test_models_takes_one_name_and_refuses_an_unknown_one(capsys) -> None:
    assert main(["models", "direct_drive"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("direct_drive: fidelities flexible, rigid, linear")
    assert "wind_speed [m/s]" in out and "k_front_z" in out and "N/m" in out and "hss_rig" not in out
    assert main(["models", "direct_driv"]) == 2
    assert "did you mean 'direct_drive'" in capsys.readouterr().err


def test_jobs_default_to_the_cores_unless_the_study_says(write_study, tmp_path: Path, monkeypatch) -> None:
    seen = []
    monkeypatch.setattr(cli, "_run", lambda study, args: seen.append(args.jobs) or 0)
    text = write_study().read_text()
    (tmp_path / "nojobs.yaml").write_text(text.replace("run: {jobs: 1, ", "run: {"))
    assert main(["-q", "run", str(tmp_path / "nojobs.yaml")]) == 0
    assert main(["-q", "run", str(write_study())]) == 0                      # run: {jobs: 1}
    assert main(["-q", "run", str(write_study()), "--jobs", "3"]) == 0
    assert seen == [len(os.sched_getaffinity(0)), None, 3]                    # None: the study's own run.jobs


def test_modes_writes_under_runs_not_the_committed_results(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(["-q", "modes", "generator_radial"]) == 0
    assert (tmp_path / "runs" / "modes_generator_radial" / "modes.csv").exists()
    assert not (tmp_path / "results").exists()


def test_the_mdrm_check_sample_is_announced(write_study, capsys) -> None:
    assert main(["validate", str(write_study())]) == 0
    err = capsys.readouterr().err
    # analytic: 3 parameters; M-DRM 5 x 3 + 1 = 16 points + its default 32-point check; Saltelli n (d + 2) = 64 x 5
    assert ("mdrm 48 (including its 32-point check sample; set by the method's `check:` option; up to 32 more for "
            "its inert check), saltelli 320") in err
    assert "x 2 scenes x 2 realisations" in err


def test_no_lock_file_is_left_behind(tmp_path: Path) -> None:
    with claim(tmp_path / "out", "demo"):
        assert (tmp_path / "out" / LOCK_NAME).exists()
    assert not (tmp_path / "out" / LOCK_NAME).exists()
    with claim(tmp_path / "out", "demo"):                   # and the folder can be claimed again
        pass


RIG = """\
name: typo
model: {name: hss_rig, fidelity: linear}
parameters:
  bearing_stiffness: {nominal: 2e7, spread: 0.2}
scenes: {kind: steady, speed_rpm: 1500, duration: 0.5}
outputs: [rms_disk_z]
methods:
  - {method: mdrm, points: 3}
"""
GENERATOR = BASE.replace("{name: direct_drive, fidelity: rigid}", "{name: generator_radial, options: {config: one_mass}}") \
    .replace("k_front_z: {nominal: 1e10", "bearing_stiffness: {nominal: 1e10").replace("damage_front", "bearing_frequency_hz")


@pytest.mark.parametrize(("base", "old", "new", "message"), [
    (BASE, "method: mdrm", "method: mdmr", r"field 'methods\[0\]\.method': unknown GSA method 'mdmr'; known: auto, "
                                           r"fast, hsic, mdrm, pce, rbd_fast, saltelli, shapley; did you mean 'mdrm'\?"),
    (BASE, "fidelity: rigid", "fidelity: rigd", r"field 'model\.fidelity': model 'direct_drive': unknown fidelity 'rigd'; known: "
                                                r"flexible, rigid, linear; did you mean 'rigid'\?"),
    (BASE, "spread: 0.2", "sprad: 0.2", r"parameter 'k_front_z': unknown key\(s\) \['sprad'\] for dist 'uniform'; "
                                        r"allowed: .*; did you mean 'spread'\?"),
    (BASE, "{nominal: 1e10, spread: 0.2}", "{dist: normall, mean: 1e10, std: 1e9}",
     r"unknown dist 'normall'; allowed: .*; did you mean 'normal' or"),
    (BASE, "fidelity: rigid}", "fidelity: rigid, options: {beam: timoshenk}}",
     r"field 'model\.options': model 'direct_drive': option 'beam' must be one of euler_bernoulli, timoshenko, got "
     r"'timoshenk'; did you mean 'timoshenko'\?"),
    (BASE, "fidelity: rigid}", "fidelity: rigid, options: {integrater: gen_alpha}}",
     r"unknown option 'integrater'; .*did you mean 'integrator'\?"),   # names or a count of the known ones
    (BASE, "fidelity: rigid}", "fidelity: rigid, options: {deflection: totl}}",
     r"option 'deflection' must be one of total, frame, elastic, got 'totl'; did you mean 'total'\?"),
    (GENERATOR, "config: one_mass", "config: one_mas", r"option 'config' must be one of one_mass, substructure, "
                                                       r"tower_side_to_side, tower_torsion, tower_bending_torsion, "
                                                       r"got 'one_mas'; did you mean 'one_mass'\?"),
    (GENERATOR, "config: one_mass", "confg: one_mass", r"unknown option 'confg'; known: .*; did you mean 'config'\?"),
    (RIG, "kind: steady", "kind: stedy", r"rig scene field 'kind' must be one of startup, steady, coastdown, got "
                                         r"'stedy'; did you mean 'steady'\?"),
    (BASE, "duration: 60}", "duration: 60, loads: {fidelity: bme}}",
     r"field 'scenes\.loads\.fidelity': unknown value 'bme'; known: auto, bem, table; did you mean 'bem' or"),
    (BASE, "[damage_front]", "[damage_frnt]", r"field 'outputs\[0\]': unknown output 'damage_frnt'.*did you mean "
                                              r"'damage_front'"),
    (BASE, "[damage_front]", "[{name: damage_front, unit: '-'}]\noutput_units: {damage_frnt: '-'}",
     r"field 'output_units\.damage_frnt': not an output of the study; known: damage_front; did you mean 'damage_front'\?"),
    (BASE, "method: mdrm, points: 3", "method: pce, order: 2, fit: regresion",
     r"method 'pce': option 'fit' must be one of regression, sparse, quadrature; got 'regresion'; did you mean "
     r"'regression'\?"),
    # unit hints: a value 10^3 or 10^6 outside the range that a prefix brings inside
    (BASE, "spread: 0.2}", "spread: 0.2}\n  k_front_y: {nominal: 5e5, spread: 0.1}",
     r"field 'parameters\.k_front_y': parameter 'k_front_y' support \[450000, 550000\] N/m leaves its allowed range "
     r"\[1e\+06, 1e\+12\] N/m \(hint: 450000, 550000 kN/m = 4\.5e\+08, 5\.5e\+08 N/m is inside it: if the number is "
     r"in kN/m, write unit: kN/m\)"),
    (BASE, "outputs:", "fixed: {shaft_length: 6000}\noutputs:",
     r"field 'fixed\.shaft_length': parameter 'shaft_length' = 6000 m leaves its allowed range \[2, 20\] m \(hint: "
     r"6000 mm = 6 m is inside it: if the number is in mm, write unit: mm\)"),
    (BASE, "outputs:", "fixed: {hub_mass: 4e7}\noutputs:", r"parameter 'hub_mass' = 4e\+07 kg leaves its allowed "
                                                           r"range \[1, 1e\+06\] kg \(hint: 4e\+07 g = 40000 kg"),
    (BASE, "outputs:", "fixed: {bearing_C_front: 10}\noutputs:", r"'bearing_C_front' = 10 N leaves its allowed range "
                                                                 r"\[100000, 1e\+09\] N \(hint: 10 MN = 1e\+07 N"),
    (BASE, "outputs:", "fixed: {shaft_length: 60}\noutputs:", r"'shaft_length' = 60 m leaves its allowed range "
                                                              r"\[2, 20\] m$"),
    # a unit written beside it (t where kg was meant): its numbers are not in kg, so no prefix of kg is advised
    (BASE, "spread: 0.2}", "spread: 0.2}\n  hub_mass: {nominal: 40000, spread: 0.05, unit: t}",
     r"'hub_mass' support \[3\.8e\+07, 4\.2e\+07\] kg leaves its allowed range \[1, 1e\+06\] kg$"),
    # 1000x too stiff: mN/m would bring it inside, but nobody types a stiffness in it -- no hint
    (BASE, "outputs:", "fixed: {k_front_y: 5e14}\noutputs:", r"'k_front_y' = 5e\+14 N/m leaves its allowed range "
                                                            r"\[1e\+06, 1e\+12\] N/m$"),
])
def test_validate_says_what_was_meant(tmp_path: Path, capsys, base: str, old: str, new: str, message: str) -> None:
    """``ddgsa validate`` on a study with one mistake exits 2 with the field, the known values and the
    close match (difflib, the one helper ``errors.did_you_mean``), or the unit prefix that brings a
    value 10^3 or 10^6 outside its range inside it (none for a value 3x off)."""
    assert old in base
    path = tmp_path / "typo.yaml"
    path.write_text(base.replace(old, new, 1))
    assert main(["validate", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    import re
    assert any(re.search(message, line) for line in err), err
