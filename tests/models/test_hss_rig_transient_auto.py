"""``fidelity: auto`` on the rig pilots ``linear`` against ``kloss`` (``HssRig.pilot_fidelities``).

The pilot's reference is ``kloss`` (nonlinear rig, generalised-alpha), not ``dq``: see the model's
module. At the nominal point the coupling's two-fold anisotropy (``coupling_asymmetry`` 0.2)
turns against the gravity sag's stretch of the coupling and excites a 2x in the housings; the
``linear`` fidelity now carries it in every scene (steady: an external 2x load; transients: a
turning input of the sweep). Measured on the pilot's 0.45 s steady record at 1500 rpm (this
round): ``order2x_housing_1_y`` 5.4e-3 apart (before: 0.128 m/s^2 at kloss against 2e-9), the
disk's 1x 6.4 %, housing RMS 8-43 %. The pilot still keeps ``kloss``, for three reasons none of
which is the anisotropy: the steady ``linear`` path's ``order1x_motor_torque`` and
``current_sideband_1x`` are 12-33x the nonlinear rig's (its spinning linearisation's
lateral-to-torsion terms, docs/hss_rig.md; errors 1.05), the band energies are noise-level numbers
(relative errors ~1), and the ``kloss`` steady run starts from a periodic state without the
anisotropy's orbit, so its 0.45 s record still rings (the 2 %-damped bending mode: the disk and
housing 1x and RMS differences above).
"""

from __future__ import annotations

import warnings

import pytest

from ddgsa import models
from ddgsa.models.hss_rig.scenes import RigScene


def test_auto_pilots_linear_against_kloss_only():
    auto = models.get("hss_rig", fidelity="auto", tolerance=0.02, pilot=0)
    assert auto.fidelities == ("kloss", "linear")
    assert list(auto.variants) == ["kloss", "linear"]
    costs = {fid: model.fidelity_cost(fid) for fid, model in auto.variants.items()}
    assert costs["linear"] < costs["kloss"]


@pytest.mark.slow
def test_auto_keeps_kloss_at_nominal():
    auto = models.get("hss_rig", fidelity="auto", tolerance=0.02, pilot=0, time_step=5e-4)
    scene = RigScene("steady", speed_rpm=1500.0, duration=0.45, sample_rate=2000.0, settle=0.05)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = auto.evaluate(None, scene)
    choice = out.attrs["fidelity"]
    assert set(choice["errors"]) == {"kloss", "linear"}
    assert choice["chosen"] == "kloss"
    errors = choice["errors"]["linear"]
    assert errors["order2x_housing_1_y"] < 0.02                          # the 2x it carries (measured 5.4e-3)
    assert errors["order1x_disk_y"] < 0.15                               # the 1x (measured 0.064)
