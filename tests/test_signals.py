"""Signal processing on synthetic signals with known order and frequency content."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
import pytest

from ddgsa.models.signals import (SignalError, band_energy, envelope, harmonic_amplitudes, order_amplitudes, order_map,
                           order_spectrum, plot_order_map, plot_spectrum, shaft_angle, slip_sidebands)

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
