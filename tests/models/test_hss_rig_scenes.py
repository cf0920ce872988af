"""Rig scenes: validation messages, grids and the aliasing guard."""

from __future__ import annotations

import warnings

import pytest

from ddgsa.errors import ModelError, SceneError
from ddgsa.mbs.sampling import AliasingWarning
from ddgsa.models.hss_rig.scenes import RigScene, scene_grid


@pytest.mark.parametrize("fields, message", [
    ({"kind": "run"}, "'kind' must be one of startup, steady, coastdown, got 'run'"),
    ({"speed_rpm": -5}, r"'speed_rpm' must be in \(0, 6000\] rpm, got -5"),
    ({"duration": 0}, "'duration' must be > 0 s, got 0"),
    ({"settle": 3.0, "duration": 2.0}, r"'settle' must be in \[0, duration = 2\) s, got 3"),
    ({"kind": "startup", "ramp_time": 5.0}, r"'ramp_time' must be in \[0, duration = 2\) s"),
    ({"speed_rpm": "fast"}, "'speed_rpm' must be a finite number, got 'fast'"),
    ({"seed": -1}, "'seed' must be an integer >= 0"),
    ({"sample_rate": 10.0}, "gives 20 samples; need at least 64"),
    ({"kind": "steady", "speed_rpm": 60.0, "duration": 2.0, "settle": 0.5}, "holds 1.35 revolutions at 10% slip; need at least 8"),
])
def test_bad_fields_are_refused_with_field_value_and_allowed(fields, message):
    with pytest.raises(SceneError, match=message):
        RigScene(**fields)


def test_unknown_field_lists_the_allowed_ones():
    with pytest.raises(SceneError, match=r"unknown field\(s\) \['speed'\]; allowed: kind, speed_rpm"):
        RigScene.from_fields({"speed": 1500})


def test_grid_expands_a_list_of_speeds():
    scenes = scene_grid({"kind": "steady", "speed_rpm": [600, 1000, 1500], "duration": 3.0, "seed": 2})
    assert [s.speed_rpm for s in scenes] == [600.0, 1000.0, 1500.0]
    assert all(s.seed == 2 and s.analysed_duration == 2.5 for s in scenes)
    assert hash(scenes[0]) != hash(scenes[1]) and scenes[0].to_dict()["kind"] == "steady"
    with pytest.raises(SceneError, match="'speed_rpm' is an empty list"):
        scene_grid({"speed_rpm": []})


def test_aliasing_guard_refuses_below_nyquist_and_warns_below_ten_samples():
    scene = RigScene("steady", speed_rpm=1500, duration=2.0, sample_rate=2000.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rows = scene.sampling_checks({"2x": 50.0})
    assert rows[0]["verdict"] == "ok" and rows[0]["samples_per_period"] == pytest.approx(40.0)
    with pytest.warns(AliasingWarning, match="5 samples per period of the bearing defect frequency BPFI harmonic at "
                                             "400 Hz .more than 800 Hz avoids aliasing; at least 4000 Hz resolves"):
        assert scene.sampling_checks({"BPFI harmonic": 400.0})[0]["verdict"] == "coarse"
    with pytest.raises(ModelError, match="would alias"):
        scene.sampling_checks({"bending mode": 1500.0})


def test_default_step_divides_the_sensor_interval() -> None:
    """Without a ``time_step`` the rig takes the largest step of at most 2e-4 s dividing the sensor
    interval (a fixed 2e-4 s refused every 2 kHz scene of the integrated fidelities); a step given that
    does not divide it is refused, naming both and the way out."""
    from ddgsa.errors import ModelError
    from ddgsa.models.hss_rig.model import HssRig

    assert HssRig().step_for(1 / 2000) == pytest.approx((1 / 6000, 3))
    assert HssRig().step_for(1 / 5000) == pytest.approx((2e-4, 1))
    assert HssRig().step_for(1 / 20000) == pytest.approx((5e-5, 1))
    with pytest.raises(ModelError, match="multiple of time_step = 0.0002 s.*leave time_step out"):
        HssRig(time_step=2e-4).step_for(1 / 2000)
