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
from ddgsa.outdir import LOCK_NAME, claim
from ddgsa.study import load_study

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
    assert "mdrm 48 (including its 32-point check sample; set by the method's `check:` option), saltelli 320" in err
    assert "x 2 scenes x 2 realisations" in err


def test_no_lock_file_is_left_behind(tmp_path: Path) -> None:
    with claim(tmp_path / "out", "demo"):
        assert (tmp_path / "out" / LOCK_NAME).exists()
    assert not (tmp_path / "out" / LOCK_NAME).exists()
    with claim(tmp_path / "out", "demo"):                   # and the folder can be claimed again
        pass
