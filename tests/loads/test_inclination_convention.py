"""The scene's inclination convention (issue 32): ``upflow`` (ddgsa's, speed along the flow) and
``downflow_horizontal`` (the reading under which seed 000's inclination trends come out)."""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa import SceneError
from ddgsa.loads import NREL5MW, Scene, cache, wind_field

TAU = np.deg2rad(NREL5MW.tilt_deg)


def ground_wind_at_hub(scene: Scene) -> tuple[float, float]:
    """Horizontal (downwind) and vertical (up) wind at the hub centre, from the shaft-frame field,
    with the shaft frame of docs/loads.md: X = (cos tau, 0, -sin tau), Z = (sin tau, 0, cos tau)."""
    u = wind_field(scene)[:, 0, 0]
    return u[0] * np.cos(TAU) + u[2] * np.sin(TAU), -u[0] * np.sin(TAU) + u[2] * np.cos(TAU)


@pytest.mark.parametrize("chi", [10.0, 20.0, -15.0])
def test_conventions_in_the_ground_frame(chi: float) -> None:
    """upflow: speed V along a flow tilted up by chi (horizontal V cos chi, vertical V sin chi);
    downflow_horizontal: horizontal V, vertical -V tan chi (tilted down by chi)."""
    steady = dict(wind_speed=8.0, turbulence_intensity=0.0, shear_exponent=0.0, duration=1.0, inclination_deg=chi)
    c = np.deg2rad(chi)
    assert ground_wind_at_hub(Scene(**steady)) == pytest.approx((8.0 * np.cos(c), 8.0 * np.sin(c)), abs=1e-12)
    down = Scene(**steady, inclination_convention="downflow_horizontal")
    assert ground_wind_at_hub(down) == pytest.approx((8.0, -8.0 * np.tan(c)), abs=1e-12)
    assert (down.flow_speed, down.flow_inclination_deg) == pytest.approx((8.0 / np.cos(c), -chi))


def test_zero_inclination_is_one_scene_and_defaults_keep_keys() -> None:
    base = dict(wind_speed=11.0, duration=60.0, loads_fidelity="bem")
    flat = Scene(**base, inclination_convention="downflow_horizontal")
    assert flat == Scene(**base) and cache.key(flat, NREL5MW) == cache.key(Scene(**base), NREL5MW)
    assert "inclination_convention" not in Scene(**base, inclination_deg=10.0).to_dict()
    tilted = Scene(**base, inclination_deg=10.0, inclination_convention="downflow_horizontal")
    assert tilted.to_dict()["inclination_convention"] == "downflow_horizontal"
    assert Scene(**tilted.to_dict()) == tilted
    assert cache.key(tilted, NREL5MW) != cache.key(Scene(**base, inclination_deg=10.0), NREL5MW)
    with pytest.raises(SceneError, match="inclination_convention.*upflow, downflow_horizontal"):
        Scene(**base, inclination_convention="down")


def test_study_field_and_digest() -> None:
    from ddgsa.study.spec import validate_study

    spec = {"name": "s", "kind": "sweep", "model": {"name": "direct_drive", "fidelity": "linear"},
            "scenes": {"wind_speed": [8.0], "inclination_deg": [20.0], "duration": 60, "loads": {"fidelity": "bem"}}}
    upflow = validate_study(spec)
    loads = {"fidelity": "bem", "inclination_convention": "downflow_horizontal"}
    down = validate_study({**spec, "scenes": {**spec["scenes"], "loads": loads}})
    sc = down.spec.scenes
    assert sc.scene(sc.grid()[0], 0).inclination_convention == "downflow_horizontal"
    # the default convention leaves the digest of a study written before the field as it was
    explicit = validate_study({**spec, "scenes": {**spec["scenes"], "loads": {"fidelity": "bem",
                                                                             "inclination_convention": "upflow"}}})
    assert explicit.digest == upflow.digest != down.digest
