"""Signal outputs of the models: the direct drive's band spectra and the rig's 1x order tracks."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from ddgsa import models
from ddgsa.errors import ModelError
from ddgsa.loads.scene import Scene
from ddgsa.models.direct_drive import SPECTRUM_EDGES_HZ
from ddgsa.models.signals import band_rms_spectrum

TURBULENT_60S = Scene(wind_speed=11.0, turbulence_intensity=0.12, duration=60.0, seed=1)
SPECTRA = ("front_Fz_spectrum", "front_Fy_spectrum", "rear_Fz_spectrum", "hub_dz_spectrum")


def test_direct_drive_spectra_are_the_records_bands_and_scale_with_the_loads() -> None:
    """The spectra come with the same scalar outputs as a plain evaluation, are the band RMS of the
    time series ``simulate`` gives (the batch path against the series path), and double when every
    hub load doubles (a nearly linear drive train: the mean, which gravity holds, is removed; 0.1 %
    from the operating point moving with the mean loads)."""
    model = models.get("direct_drive", fidelity="linear")
    plain = model.evaluate(None, TURBULENT_60S)
    doubled = {f: 2.0 for f in ("thrust_factor", "side_force_factor", "vertical_force_factor", "torque_factor",
                                "tilt_moment_factor", "yaw_moment_factor")}
    out = model.evaluate(pd.DataFrame([{k: 1.0 for k in doubled}, doubled]), TURBULENT_60S, signals=SPECTRA)
    np.testing.assert_array_equal(out.iloc[[0]].to_numpy(), plain.to_numpy())
    sig = out.attrs["signals"]
    assert all(sig[s].shape == (2, 50) for s in SPECTRA)
    series = model.simulate(TURBULENT_60S)
    for name, column in (("front_Fz_spectrum", "front_Fz"), ("rear_Fz_spectrum", "rear_Fz")):
        np.testing.assert_allclose(sig[name][0], band_rms_spectrum(series[column].to_numpy(), 0.05,
                                                                   SPECTRUM_EDGES_HZ), rtol=1e-6)
        # within 0.5 %, not exactly: the linear fidelity is linearised about the (doubled) mean loads
        np.testing.assert_allclose(sig[name][1], 2.0 * sig[name][0], rtol=5e-3)
    np.testing.assert_allclose(model.signal_axis("front_Fz_spectrum", TURBULENT_60S)[[0, -1]], [0.025, 2.475])


def test_a_scene_too_short_for_the_bands_is_refused() -> None:
    model = models.get("direct_drive", fidelity="linear")
    with pytest.raises(ModelError, match="duration >= 40 s"):
        model.signal_axis("front_Fz_spectrum", Scene(duration=20.0))
    with pytest.raises(ModelError, match="signal output"):
        model.signal_axis("front_Fr_spectrum", TURBULENT_60S)


@pytest.mark.slow
def test_rig_1x_track_peaks_just_past_the_first_lateral_critical_speed() -> None:
    """The disk's 1x amplitude through a direct-on-line start-up peaks just above the first bending
    critical speed of the spinning rig (its eigenvalues, :meth:`HssRig.modes`): a resonance passed
    quickly peaks late (Lewis 1932), by less than a fifth of the critical speed here."""
    from ddgsa.models.hss_rig.scenes import RigScene

    model = models.get("hss_rig", fidelity="linear", time_step=5e-4)
    scene = RigScene("startup", speed_rpm=1500.0, duration=1.2, sample_rate=2000.0)
    out = model.evaluate(None, scene, signals=("order1x_track_disk_y",))
    track = out.attrs["signals"]["order1x_track_disk_y"][0]
    speeds = model.signal_axis("order1x_track_disk_y", scene)
    peak = speeds[np.argmax(track)]
    modes = model.modes(rotor_speed=peak * np.pi / 30)
    critical = 60.0 * modes[modes["label"].str.startswith("hss_bending")]["frequency_hz"].min()
    assert 0.0 < peak - critical < 0.2 * critical, (peak, critical)
    with pytest.raises(ModelError, match="startup or coastdown"):
        model.signal_axis("order1x_track_disk_y", RigScene("steady", speed_rpm=1500.0, duration=1.2))
