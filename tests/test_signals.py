"""Signal processing on synthetic signals with known order and frequency content."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
import pytest

from ddgsa.models.signals import (SignalError, band_energy, band_energies, band_rms_spectrum, envelope, harmonic_amplitudes,
                                  order_amplitudes, order_map, order_spectrum, plot_order_map, plot_spectrum,
                                  record_harmonics, resample_records, resample_to_angle, shaft_angle, slip_sidebands)

FS = 5000.0


def _runup(t):
    """Shaft speed 5 -> 30 Hz linearly over the record and its angle (closed form) [rad]."""
    T = t[-1]
    return 2 * math.pi * (5 * t + 12.5 * t**2 / T)


def test_order_tracking_recovers_orders_through_a_run_up():
    """1x and 2x of a run-up 5 -> 30 Hz (amplitudes 0.3 and 0.05, phases arbitrary) within 1e-3,
    where a plain FFT of the same record smears them over 5-60 Hz."""
    t = np.arange(0.0, 4.0, 1 / FS)
    ang = _runup(t)
    x = 0.3 * np.cos(ang + 0.4) + 0.05 * np.sin(2 * ang - 1.1) + 0.02 * np.cos(3.5848 * ang)
    amps = order_amplitudes(t, x, ang, [1, 2, 3.5848])
    np.testing.assert_allclose(amps, [0.3, 0.05, 0.02], rtol=1e-3)
    # angle from a sampled speed (trapezoid) is as good here
    speed = np.gradient(ang, t, edge_order=2)
    np.testing.assert_allclose(order_amplitudes(t, x, shaft_angle(t, speed), [1, 2]), [0.3, 0.05], rtol=1e-3)
    spec_peak = np.abs(np.fft.rfft(x)).max() * 2 / len(x)
    assert spec_peak < 0.1                        # the time-domain FFT does not see a 0.3 sinusoid


def test_order_spectrum_bins_fall_on_integer_orders():
    t = np.arange(0.0, 2.0, 1 / FS)
    ang = 2 * math.pi * 25.0 * t
    x = 1e-3 * np.cos(ang) + 4e-4 * np.cos(2 * ang + 0.3)
    orders, amp = order_spectrum(t, x, ang)
    for k, a in [(1, 1e-3), (2, 4e-4)]:
        i = int(np.argmin(np.abs(orders - k)))
        assert orders[i] == pytest.approx(k, abs=1e-12)
        assert amp[i] == pytest.approx(a, rel=1e-3)


def test_order_map_follows_the_speed_and_keeps_the_amplitude():
    t = np.arange(0.0, 4.0, 1 / FS)
    ang = _runup(t)
    speed_rpm, orders, amp = order_map(t, np.cos(ang), ang, revs_per_block=4)
    assert speed_rpm[0] < speed_rpm[-1]
    true_rpm = 60 * (5 + 25 * np.linspace(0, 1, 200))
    assert speed_rpm.min() > true_rpm.min() and speed_rpm.max() < true_rpm.max()
    i1 = int(np.argmin(np.abs(orders - 1)))
    np.testing.assert_allclose(amp[:, i1], 1.0, rtol=1e-3)
    ax = plot_order_map(speed_rpm, orders, amp, unit="[m/s^2]")
    assert ax.get_xlabel() == "order [-]"
    plt.close(ax.figure)


def test_harmonic_amplitudes_at_line_frequency_and_slip_sidebands():
    """A current of 50 Hz with twice-slip sidebands (s = 3 %: 47 and 53 Hz) and a 100 Hz ripple."""
    t = np.arange(0.0, 3.0, 1 / FS)
    lo, hi = slip_sidebands(50.0, 0.03)
    assert (lo, hi) == pytest.approx((47.0, 53.0), abs=1e-12)
    x = (5.0 * np.cos(2 * math.pi * 50 * t + 0.2) + 1e-2 * np.cos(2 * math.pi * lo * t)
         + 3e-3 * np.sin(2 * math.pi * hi * t + 2) + 0.4 * np.cos(2 * math.pi * 100 * t) + 1.5)
    np.testing.assert_allclose(harmonic_amplitudes(t, x, [50.0, lo, hi, 100.0]), [5.0, 1e-2, 3e-3, 0.4], rtol=1e-3)


def test_band_energy_of_a_sinusoid_and_of_white_noise():
    t = np.arange(0.0, 4.0, 1 / FS)
    bpfo = 89.619
    x = 2e-3 * np.cos(2 * math.pi * bpfo * t + 0.7) + 1e-3 * np.cos(2 * math.pi * 2 * bpfo * t)
    assert band_energy(t, x, bpfo, 2.0) == pytest.approx(0.5 * 2e-3**2, rel=1e-3)
    assert band_energy(t, x, bpfo, 2.0, harmonics=2) == pytest.approx(0.5 * (2e-3**2 + 1e-3**2), rel=1e-3)
    assert band_energy(t, x, 300.0, 2.0) < 1e-6 * 0.5 * 2e-3**2
    # white noise of variance 1: expected band energy 2 * half_width / (FS / 2); ~ 2.5 % standard error here
    noise = np.random.default_rng(0).standard_normal(t.size)
    assert band_energy(t, noise, 500.0, 100.0) == pytest.approx(200.0 / 2500.0, rel=0.1)
    with pytest.raises(SignalError, match="narrower than the Hann main lobe"):
        band_energy(t, x, bpfo, 0.1)


def test_envelope_demodulates_an_amplitude_modulated_carrier():
    """(1 + m cos 2 pi f_m t) cos 2 pi f_c t: envelope band energy at f_m is m^2 / 2 (BPFO modulation)."""
    t = np.arange(0.0, 4.0, 1 / FS)
    fm, m = 89.619, 0.3
    x = (1 + m * np.cos(2 * math.pi * fm * t)) * np.cos(2 * math.pi * 1200 * t)
    env = envelope(t, x, band=(700.0, 1700.0))
    core = slice(2000, -2000)                                  # filter edge transients
    assert band_energy(t[core], env[core], fm, 2.0) == pytest.approx(0.5 * m * m, rel=1e-3)


def test_plot_spectrum_marks_the_orders():
    t = np.arange(0.0, 1.0, 1 / FS)
    ax = plot_spectrum(t, np.cos(2 * math.pi * 25 * t), marks={"1x": 25.0, "2x": 50.0}, max_hz=200)
    assert [tx.get_text() for tx in ax.texts] == ["1x", "2x"]
    plt.close(ax.figure)


def test_bad_signals_are_refused():
    t = np.arange(0.0, 1.0, 1e-3)
    with pytest.raises(SignalError, match="increase strictly"):
        order_amplitudes(t, np.ones_like(t), np.zeros_like(t), [1])
    with pytest.raises(SignalError, match="uniformly sampled"):
        harmonic_amplitudes(t**2, t, [1.0])
    with pytest.raises(SignalError, match="Nyquist"):
        harmonic_amplitudes(t, t, [600.0])


def test_records_resampled_together_are_scipys_spline_of_each():
    """The compiled spline of records with their own angles (a block's start-ups) against scipy's ``CubicSpline``
    (not-a-knot) of each record on its own: within 1e-12 of the record's range, NaN beyond its whole revolutions;
    one shared angle (``resample_to_angle``) likewise."""
    from scipy.interpolate import CubicSpline

    rng = np.random.default_rng(3)
    t = np.arange(1201) * 1e-3
    angles = np.cumsum(rng.uniform(0.02, 0.3, (t.size, 5)), axis=0) * [0.5, 0.8, 1.0, 1.3, 1.7]   # 15-45 revolutions
    x = rng.standard_normal((t.size, 5, 3))
    phi, y, counts = resample_records(t, x, angles, 64)
    assert len(set(counts.tolist())) > 1 and phi.size == counts.max()
    for r in range(5):
        ref = CubicSpline(angles[:, r], x[:, r], axis=0)(angles[0, r] + phi[:counts[r]])
        assert np.allclose(y[:counts[r], r], ref, rtol=0.0, atol=1e-12 * np.ptp(x[:, r]))
        assert counts[r] == 64 * math.floor((angles[-1, r] - angles[0, r]) / (2 * math.pi) + 1e-9)
        assert np.isnan(y[counts[r]:, r]).all()
    shared = angles[:, 0]
    phi1, y1 = resample_to_angle(t, x[:, 0], shared, 32)
    assert np.allclose(y1, CubicSpline(shared, x[:, 0], axis=0)(shared[0] + phi1), rtol=0.0, atol=1e-12 * np.ptp(x))
    with pytest.raises(SignalError, match="increase strictly"):
        resample_records(t, x, angles[::-1], 64)
    with pytest.raises(SignalError, match="need records"):
        resample_records(t, x[:, :, 0], angles, 64)


@pytest.mark.parametrize("n", [1000, 1001])
def test_band_energies_take_scipys_periodogram(n):
    """Band energies and band RMS from the one-FFT periodogram against scipy's ``periodogram`` (Hann, mean removed,
    density) summed over the same lines, even and odd record lengths (the one-sided doubling differs)."""
    from scipy.signal import periodogram

    rng = np.random.default_rng(n)
    t = np.arange(n) * 1e-3
    x = rng.standard_normal((n, 3)) + 2.0
    f, p = periodogram(x, fs=1e3, window="hann", scaling="density", detrend="constant", axis=0)
    ref = np.array([p[np.abs(f - h * 37.0) <= 5.0].sum(axis=0) for h in (1, 2)]).sum(axis=0) * (f[1] - f[0])
    assert np.allclose(band_energies(t, x, [37.0], 5.0, harmonics=2)[0], ref, rtol=1e-12, atol=0.0)
    edges = np.array([0.0, 100.0, 250.0, 500.0])
    k = np.searchsorted(edges, f, side="right") - 1
    ref_rms = np.sqrt([p[k == b].sum(axis=0) * (f[1] - f[0]) for b in range(3)])
    assert np.allclose(band_rms_spectrum(x, 1e-3, edges), ref_rms, rtol=1e-12, atol=0.0)


def test_records_at_their_own_frequencies_recover_their_sinusoids():
    """Each record's line and sidebands at its own speed (a block of start-ups): the amplitudes written into it
    (exact for stationary sinusoids), and the same as :func:`harmonic_amplitudes` of that record alone."""
    t = np.arange(0.0, 1.0, 5e-4)
    speeds = np.array([11.0, 17.5, 23.0])
    freqs = np.column_stack([np.full(3, 50.0), 50.0 - speeds, 50.0 + speeds])
    amps = np.array([[5.0, 4.0, 3.0], [1e-2, 2e-2, 0.0], [3e-3, 0.0, 1e-3]])
    x = 0.7 + sum(amps[j] * np.cos(2 * math.pi * freqs[:, j] * t[:, None] + j) for j in range(3))
    got = record_harmonics(t, x, freqs)
    assert np.allclose(got, amps, rtol=0.0, atol=1e-12)
    for r in range(3):
        assert np.allclose(got[:, r], harmonic_amplitudes(t, x[:, r], freqs[r]), rtol=0.0, atol=1e-13)
    with pytest.raises(SignalError, match="Nyquist"):
        record_harmonics(t, x, freqs * 30)
