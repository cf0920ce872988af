"""IEC turbulence: variances, Kaimal spectra and u coherence of generated fields."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

from ddgsa.loads.turbulence import IecTurbulence, generate_field

MODEL = IecTurbulence(wind_speed=15.0, turbulence_intensity=0.14, hub_height=80.0)
POINTS = np.array([[0.0, 0.0], [0.0, 8.0], [30.0, 0.0]])   # (y, z) [m]; 8 m and 30 m apart
DURATION, DT, N_REC = 3600.0, 0.1, 24


@pytest.fixture(scope="module")
def records() -> np.ndarray:
    """24 one-hour realisations (seeds 0..23): shape (N_REC, 3, n_t, 3)."""
    return np.stack([generate_field(POINTS, MODEL, DURATION, DT, seed) for seed in range(N_REC)])


def test_iec_parameters() -> None:
    assert MODEL.sigma == pytest.approx(0.14 * (0.75 * 15 + 5.6) * np.array([1, 0.8, 0.5]))
    assert MODEL.length_scales == pytest.approx([340.2, 113.4, 27.72])
    assert IecTurbulence(10.0, 0.1, 50.0).scale_parameter == pytest.approx(35.0)


def test_standard_deviations_within_5_percent(records: np.ndarray) -> None:
    sigma = records.std(axis=2).mean(axis=(0, 2))          # mean over records and points
    # expected loss below 1/T and above Nyquist is < 3 % of sigma for these scales
    np.testing.assert_allclose(sigma, MODEL.sigma, rtol=0.05)


def test_welch_spectra_match_kaimal(records: np.ndarray) -> None:
    f, p = signal.welch(records[:, :, :, 0], fs=1.0 / DT, nperseg=4096, axis=2)
    p = p.mean(axis=0)                                      # (3, n_f)
    band = (f >= 0.01) & (f <= 1.0)
    ratio = p[:, band] / MODEL.spectra(f[band])
    # log-spaced bins of ~10 Welch estimates each: every bin within -20 % / +25 % of Kaimal
    edges = np.geomspace(0.01, 1.0, 9)
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = (f[band] >= lo) & (f[band] < hi)
        assert np.all((ratio[:, sel].mean(axis=1) > 0.8) & (ratio[:, sel].mean(axis=1) < 1.25)), (lo, hi)


@pytest.mark.parametrize("j, sep", [(1, 8.0), (2, 30.0)])
def test_u_coherence_matches_iec(records: np.ndarray, j: int, sep: float) -> None:
    u = records[:, 0]                                      # (N_REC, n_t, 3)
    f, pxy = signal.csd(u[:, :, 0], u[:, :, j], fs=1.0 / DT, nperseg=2048, axis=1)
    _, pxx = signal.welch(u[:, :, 0], fs=1.0 / DT, nperseg=2048, axis=1)
    _, pyy = signal.welch(u[:, :, j], fs=1.0 / DT, nperseg=2048, axis=1)
    coh = np.real(pxy.mean(axis=0)) / np.sqrt(pxx.mean(axis=0) * pyy.mean(axis=0))
    sel = (f > 0.005) & (f < 0.3)
    expected = MODEL.coherence(f[sel], sep)
    assert np.abs(coh[sel] - expected).max() < 0.1           # ~2000 averaged segments


def test_same_seed_identical_other_seed_different() -> None:
    a = generate_field(POINTS, MODEL, 120.0, 0.05, 5)
    b = generate_field(POINTS, MODEL, 120.0, 0.05, 5)
    c = generate_field(POINTS, MODEL, 120.0, 0.05, 6)
    assert np.array_equal(a, b)
    assert not np.allclose(a, c)
