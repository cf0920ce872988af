"""The rig's record-at-once motor outputs against the per-sample steady circuit they replaced."""

from __future__ import annotations

import math

import numpy as np

from ddgsa.models.hss_rig.drive import drive_for, kloss_along, kloss_torque_at
from ddgsa.models.hss_rig.model import HssRig
from ddgsa.models.hss_rig.motor import steady_torque
from ddgsa.models.hss_rig.scenes import RigScene


def _drive(kind: str, unbalance: float, ramp: float = 0.0):
    p = {**HssRig().resolve(None).iloc[0].to_dict(), "supply_unbalance": unbalance}
    return drive_for(p, RigScene(kind, speed_rpm=1500.0, duration=1.0, sample_rate=2000.0, ramp_time=ramp), 2)


def test_record_torque_equals_the_per_sample_torque_law():
    rng = np.random.default_rng(2)
    for kind, unbalance, ramp in (("steady", 0.03, 0.0), ("startup", 0.0, 0.4), ("coastdown", 0.0, 0.0)):
        drive = _drive(kind, unbalance, ramp)
        t = np.linspace(-0.01, 0.8, 301)
        speed = 150.0 + 5.0 * rng.standard_normal(t.size)
        torque, _ = kloss_along(drive, t, speed)
        assert np.allclose(torque, [kloss_torque_at(drive, ti, w) for ti, w in zip(t, speed)], rtol=1e-12, atol=1e-12)
        if kind == "coastdown":
            assert np.all(torque[t > 0] == 0.0)                     # supply cut at t = 0


def test_record_current_amplitude_is_the_circuit_current():
    drive = _drive("steady", 0.0)
    f = drive.motor.supply_frequency
    t = np.linspace(0.0, 1.0 / f, 2001)
    speed = np.full(t.size, 148.0)
    _, current = kloss_along(drive, t, speed)
    amplitude = steady_torque(drive.motor, 148.0).current           # |i_1|, the balanced phase current's peak
    assert math.isclose(np.max(current), amplitude, rel_tol=1e-5)
    assert math.isclose(-np.min(current), amplitude, rel_tol=1e-5)
