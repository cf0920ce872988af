"""Rotor, controller and hub loads: steady curves, 1P/3P content, reproducibility, scene validation."""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa import SceneError
from ddgsa.loads import NREL5MW, Scene, Turbine, _generate, generate

NO_TILT = Turbine(tilt_deg=0.0)
WINDS = np.arange(4.0, 25.01, 0.25)


@pytest.fixture(scope="module")
def curves() -> dict[str, np.ndarray]:
    states = [NREL5MW.steady_state(v) for v in WINDS]
    return {k: np.array([s[k] for s in states]) for k in states[0]}


def test_rated_point_of_the_reference_turbine(curves) -> None:
    cp, tsr, pitch = NREL5MW.optimum
    assert (cp, tsr, pitch) == pytest.approx((0.466, 7.5, 0.0), abs=1e-3)   # NREL 5-MW published
    assert 10.8 < NREL5MW.rated_wind_speed < 11.6                            # published 11.4 m/s


def test_power_capped_and_torque_constant_above_rated(curves) -> None:
    above = WINDS > NREL5MW.rated_wind_speed + 0.01
    np.testing.assert_allclose(curves["power"][above], NREL5MW.rated_power, rtol=1e-6)
    np.testing.assert_allclose(curves["aero_torque"][above], NREL5MW.rated_torque, rtol=1e-6)
    assert np.all(curves["power"][~above] <= NREL5MW.rated_power * (1 + 1e-9))
    assert np.all(np.diff(curves["power"][~above]) > 0)


def test_thrust_peaks_at_rated_wind(curves) -> None:
    v_peak = WINDS[np.argmax(curves["thrust"])]
    assert abs(v_peak - NREL5MW.rated_wind_speed) <= 0.5


def test_rotor_speed_within_range(curves) -> None:
    assert np.all(curves["rotor_speed"] >= 0.9 * NREL5MW.min_speed)
    assert np.all(curves["rotor_speed"] <= NREL5MW.rated_speed * (1 + 1e-9))


@pytest.mark.parametrize("v", [7.0, 16.0])
def test_time_domain_settles_on_the_steady_state(v: float) -> None:
    """The rotor/controller loop (numba) against the algebraic steady state (brentq)."""
    scene = Scene(wind_speed=v, turbulence_intensity=0.0, shear_exponent=0.0, duration=60.0)
    loads = _generate(scene, NO_TILT)
    ss = NO_TILT.steady_state(v)
    assert loads["rotor_speed"].iloc[-1] == pytest.approx(ss["rotor_speed"], rel=2e-3)
    assert loads["Fx"].iloc[-1] == pytest.approx(ss["thrust"], rel=1e-2)
    assert loads["Mx"].iloc[-1] == pytest.approx(ss["aero_torque"], rel=1e-2)


def _mean_and_3p(loads, col: str) -> tuple[float, float]:
    x = loads[col].to_numpy()
    amp = np.abs(np.fft.rfft(x - x.mean())) * 2 / x.size
    f = np.fft.rfftfreq(x.size, 0.05)
    f3 = 3 * loads["rotor_speed"].mean() / (2 * np.pi)
    return float(x.mean()), float(amp[np.abs(f - f3) < 0.02].max(initial=0.0))


def test_uniform_wind_gives_no_tilt_or_yaw_moment() -> None:
    loads = _generate(Scene(wind_speed=9.0, turbulence_intensity=0.0, shear_exponent=0.0, duration=60.0),
                      NO_TILT)
    for col in ("My", "Mz", "Fy", "Fz"):
        mean, a3 = _mean_and_3p(loads, col)
        assert abs(mean) < 1.0 and a3 < 1.0           # [N m], [N]: zero to round-off


@pytest.mark.parametrize("shear, incl, col", [(0.2, 0.0, "My"), (0.0, 10.0, "Mz")])
def test_shear_and_inclination_give_mean_moment_and_3p(shear: float, incl: float, col: str) -> None:
    loads = _generate(Scene(wind_speed=9.0, turbulence_intensity=0.0, shear_exponent=shear,
                            inclination_deg=incl, duration=60.0), NO_TILT)
    mean, a3 = _mean_and_3p(loads, col)
    assert abs(mean) > 1e5                            # shear: ~1.5 MN m tilt; 10 deg: ~0.2 MN m yaw
    x = loads[col].to_numpy()
    amp = np.abs(np.fft.rfft(x - x.mean()))
    f = np.fft.rfftfreq(x.size, 0.05)
    f3 = 3 * loads["rotor_speed"].mean() / (2 * np.pi)
    assert abs(f[np.argmax(amp)] - f3) < 0.02         # the dominant oscillation is 3P
    assert a3 > 1e3


def test_seeds_reproduce_and_differ_with_equal_statistics() -> None:
    base = dict(wind_speed=14.0, turbulence_intensity=0.12, duration=600.0)
    a, b = generate(Scene(seed=4, **base)), generate(Scene(seed=4, **base))
    c = generate(Scene(seed=5, **base))
    assert a.equals(b)
    assert not np.allclose(a["Fx"], c["Fx"])
    assert a["wind_hub"].mean() == pytest.approx(c["wind_hub"].mean(), rel=0.05)
    assert a["wind_hub"].std() == pytest.approx(c["wind_hub"].std(), rel=0.35)
    assert a["power"].mean() == pytest.approx(c["power"].mean(), rel=0.05)


def test_cached_frames_are_not_shared() -> None:
    scene = Scene(wind_speed=8.0, turbulence_intensity=0.0, duration=20.0)
    a = generate(scene)
    a["Fx"] = 0.0
    assert generate(scene)["Fx"].iloc[0] > 1e5


@pytest.mark.parametrize("field, value, match", [
    ("wind_speed", -3.0, r"'wind_speed' must be in \(0, 50\] m/s, got -3.0"),
    ("turbulence_intensity", 1.2, r"'turbulence_intensity' must be in \[0, 1\), got 1.2"),
    ("duration", 0.0, r"'duration' must be > 0 s, got 0.0"),
    ("dt", 0.5, r"'dt' = 0.5 s is too coarse for the rotor's 3P frequency"),
    ("inclination_deg", 45.0, r"'inclination_deg' must be in \[-30, 30\] deg"),
    ("seed", -1, r"'seed' must be an integer >= 0"),
    ("wind_speed", "fast", r"'wind_speed' must be a finite number, got 'fast'"),
])
def test_bad_scene_values_name_the_field(field: str, value, match: str) -> None:
    with pytest.raises(SceneError, match=match):
        Scene(**{field: value})
