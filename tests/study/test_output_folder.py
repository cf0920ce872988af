"""Output folders: one study per folder unless --force, no stale artefacts, no foreign folders."""

from __future__ import annotations

import json
from pathlib import Path

from ddgsa.cli import main
from ddgsa.report.outdir import replaced_version
from ddgsa.study.spec import load_study
from studytext import ishigami_study


def one_scene(name: str, speeds: str) -> str:
    """An Ishigami study at ``speeds`` with a 3-point M-DRM."""
    return ishigami_study(name, "methods: [{method: mdrm, points: 3, check: 0}]\n", speeds=speeds, pi="3.14159")


def test_another_studys_folder_is_refused_unless_forced_and_then_cleaned(write_study, tmp_path: Path,
                                                                       capsys) -> None:
    out = tmp_path / "out"
    first = write_study("first", text=one_scene(name="first", speeds="8.0, 11.0"))
    assert main(["-q", "run", str(first), "--out", str(out), "--allow-untrusted"]) == 0
    assert {"bars_scene1.png", "heatmap_ST_mdrm.png"} <= {p.name for p in out.iterdir()}
    second = write_study("second", text=one_scene(name="second", speeds="8.0"))
    assert main(["-q", "run", str(second), "--out", str(out), "--allow-untrusted"]) == 2
    err = capsys.readouterr().err
    assert f"{out}: holds the results of study 'first', not 'second'" in err and "--force" in err
    assert "# first" in (out / "summary.md").read_text()                 # untouched
    assert main(["-q", "run", str(second), "--out", str(out), "--allow-untrusted", "--force"]) == 0
    names = {p.name for p in out.iterdir()}
    assert "bars_scene1.png" not in names and "heatmap_ST_mdrm.png" not in names
    assert "# second" in (out / "summary.md").read_text()
    prov = json.loads((out / "provenance.json").read_text())
    assert set(prov["files"]) == names - {"study.yaml", "evaluations.sqlite", ".ddgsa.lock",
                                          "evaluations.sqlite-wal", "evaluations.sqlite-shm"}


def test_the_same_study_with_fewer_scenes_leaves_no_stale_plots(write_study, tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert main(["-q", "run", str(write_study("s", text=one_scene(name="s", speeds="8.0, 11.0"))),
                 "--out", str(out), "--allow-untrusted"]) == 0
    assert (out / "bars_scene1.png").exists()
    assert main(["-q", "run", str(write_study("s", text=one_scene(name="s", speeds="8.0"))),
                 "--out", str(out), "--allow-untrusted"]) == 0
    assert not (out / "bars_scene1.png").exists() and not (out / "heatmap_ST_mdrm.png").exists()
    assert (out / "bars_scene0.png").exists()


def test_a_folder_ddgsa_did_not_write_is_refused(write_study, tmp_path: Path, capsys) -> None:
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("my notes")
    study = write_study("s", text=one_scene(name="s", speeds="8.0"))
    assert main(["-q", "run", str(study), "--out", str(out)]) == 2
    assert "is not empty and is not a ddgsa output folder (notes.txt)" in capsys.readouterr().err
    assert main(["-q", "run", str(study), "--out", str(out), "--force", "--allow-untrusted"]) == 0
    assert (out / "notes.txt").read_text() == "my notes"                 # --force never deletes what is not ours


def test_another_version_of_a_study_with_the_same_name_says_it_replaces_the_results(write_study, tmp_path: Path,
                                                                                   capsys) -> None:
    """Newcomer trial: a copied study that kept ``name:`` silently replaced the first one's folder.
    Now one warning line names the folder, both study files and that the old results are replaced;
    rerunning the same study (equal digest) says nothing."""
    out = tmp_path / "out"
    first = write_study("first", text=one_scene(name="s", speeds="8.0"))
    assert main(["-q", "run", str(first), "--out", str(out), "--allow-untrusted"]) == 0
    assert replaced_version(out, "s", load_study(first).digest) is None          # rerunning it: no warning
    assert replaced_version(out, "other", "0" * 64) is None                      # another name: claim refuses
    capsys.readouterr()
    copy = write_study("copy", text=one_scene(name="s", speeds="11.0"))
    assert main(["-q", "run", str(copy), "--out", str(out), "--allow-untrusted"]) == 0
    lines = [line for line in capsys.readouterr().err.splitlines() if "replaced" in line]
    assert lines == [f"ddgsa: warning: {out}: holds the results of study 's' from {first.name} with other contents; "
                     f"they are replaced by those of {copy} (stored evaluations with equal keys are reused)"]
    assert json.loads((out / "provenance.json").read_text())["study_file"] == copy.name
    assert "wind_speed=11" in (out / "summary.md").read_text()
