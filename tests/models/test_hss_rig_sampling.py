"""The rig's aliasing guard in a study: each distinct warning once, the refusal every time.

The runner evaluates every batch inside ``warnings.catch_warnings`` (which resets Python's
once-per-place memory), so the rig's note on the 3x BPFI line (406 Hz at 1500 rpm) came once per
batch and worker: 6 times in the 9-evaluation, 2-worker study below before
``hss_rig.model._SHOWN``, once after.
"""

from __future__ import annotations

import os
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from ddgsa import models
from ddgsa.errors import ModelError
from ddgsa.mbs.sampling import AliasingWarning
from ddgsa.models.hss_rig import model as rig_model
from ddgsa.models.hss_rig.scenes import RigScene

SRC = Path(rig_model.__file__).resolve().parents[3]


def test_each_aliasing_warning_is_issued_once_and_the_refusal_every_time(monkeypatch) -> None:
    monkeypatch.setattr(rig_model, "_SHOWN", set())
    scene = RigScene("steady", speed_rpm=1500.0, duration=0.6, sample_rate=2000.0, settle=0.1)
    with pytest.warns(AliasingWarning, match=r"4.9 samples per period of the bearing defect frequency 3 x BPFI at "
                                             r"406.1 Hz"):
        first = models.get("hss_rig", fidelity="linear").sampling_checks(scene)
    for _ in range(2):                                   # another batch, another model instance: silent
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            again = models.get("hss_rig", fidelity="kloss").sampling_checks(scene)
    assert again == first and [r["verdict"] for r in again] == ["ok", "coarse", "ok"]
    with pytest.warns(AliasingWarning, match=r"8.2 samples per period"):       # another rate: its own note
        models.get("hss_rig", fidelity="linear").sampling_checks(RigScene("steady", duration=0.6, settle=0.1,
                                                                          sample_rate=3333.0))
    coarse = RigScene("steady", speed_rpm=1500.0, duration=0.6, sample_rate=600.0, settle=0.1)
    for _ in range(2):                                   # 1.5 samples per period of 406 Hz: refused each time
        with pytest.raises(ModelError, match="would alias"):
            models.get("hss_rig", fidelity="linear").evaluate(None, coarse)


STUDY = """\
name: alias_once
model: {name: hss_rig, fidelity: linear}
parameters:
  hss_diameter: {nominal: 0.025, spread: 0.1, unit: m}
  disk_mass: {nominal: 15.0, spread: 0.1, unit: kg}
scenes: {kind: steady, speed_rpm: 1500, duration: 0.6, sample_rate: 2000, settle: 0.1, seed: 1}
outputs: [order1x_disk_y]
methods: [{method: mdrm, points: 3, check: 4}]
run: {jobs: 2, batch_size: 2}
"""


@pytest.mark.slow                                        # 9 linear steady runs: ~25 s on the shared machine
def test_a_two_worker_study_prints_the_aliasing_warning_once(tmp_path: Path) -> None:
    """A separate process (pytest records warnings, and forked workers would inherit its recorder):
    warm-up, 4 batches on 2 forked workers, the report's sampling table; one line (6 before)."""
    study = tmp_path / "alias_once.yaml"
    study.write_text(STUDY)
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    done = subprocess.run([sys.executable, "-m", "ddgsa.cli", "run", str(study), "--out",
                           str(tmp_path / "out"), "--allow-untrusted"], env=env, capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stderr
    note = "samples per period of the bearing defect frequency 3 x BPFI at 406.1 Hz"
    assert done.stderr.count(note) == 1 and "AliasingWarning" not in done.stderr, done.stderr   # one line, no source
    assert "ddgsa: note: " in done.stderr
