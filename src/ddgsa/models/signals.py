"""Vibration signal processing for rotating machines: order tracking, harmonic amplitudes, band energy.

Model-agnostic (it knows time series, shaft angles and frequencies, nothing of a model):

* **Order tracking** by resampling to the shaft angle (computed order tracking, Fyfe & Munck,
  MSSP 11 (1997)): a signal sampled uniformly in time is interpolated (cubic spline) at equal
  angle increments, so the ``k``-th order (``k`` times per revolution) becomes a stationary
  sinusoid of ``k`` cycles per revolution even while the speed changes. Order amplitudes are read
  by least squares on that angle-domain signal (exact for stationary order content, any order,
  not only integers), or from the FFT of whole revolutions (:func:`order_spectrum`).
* **Harmonic amplitudes** at given frequencies (supply line frequency, twice it, slip sidebands
  ``f (1 +- 2 s)``) by least squares on a steady record.
* **Band energy** (mean square) of a signal or of its envelope around a frequency such as the
  bearing's BPFO or BPFI, from a Hann-windowed periodogram (Parseval).
* **Plots**: a run-up order map (order against speed, amplitude in colour) and a steady spectrum
  with orders marked. Plot functions take ``ax=None`` and return the Axes; nothing calls ``show``.

Amplitudes are peak amplitudes of the sinusoid (``A`` in ``A cos(...)``), in the signal's unit.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from numba import njit
from scipy.integrate import cumulative_trapezoid
from scipy.signal import butter, hilbert, sosfiltfilt

from ddgsa.errors import DdgsaError

__all__ = ["SignalError", "angle_amplitudes", "angle_samples", "band_energy", "band_rms_spectrum", "envelope", "harmonic_amplitudes", "order_amplitudes",
           "order_map", "order_spectrum", "plot_order_map", "plot_spectrum", "record_harmonics", "resample_records",
           "resample_to_angle",
           "shaft_angle", "slip_sidebands"]


class SignalError(DdgsaError, ValueError):
    """A signal too short, unevenly sampled or with a non-monotonic shaft angle."""


def _uniform(t: ArrayLike, x: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
    t = np.asarray(t, float)
    x = np.asarray(x, float)
    if t.ndim != 1 or t.shape != x.shape[:1] or t.size < 8:
        raise SignalError(f"need a 1-D time vector of >= 8 samples matching the signal, got shapes {t.shape}, "
                          f"{x.shape}")
    dt = np.diff(t)
    if np.any(dt <= 0) or np.ptp(dt) > 1e-6 * dt.mean():
        raise SignalError("the time vector must be increasing and uniformly sampled")
    return t, x, float(dt.mean())


def shaft_angle(t: ArrayLike, speed: ArrayLike) -> NDArray[np.float64]:
    """Shaft angle [rad] from its speed [rad/s] (trapezoidal integral, 0 at ``t[0]``)."""
    return cumulative_trapezoid(np.asarray(speed, float), np.asarray(t, float), initial=0.0)


def resample_to_angle(t: ArrayLike, x: ArrayLike, angle: ArrayLike,
                      samples_per_rev: int = 64) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The signal at equal shaft-angle increments over the whole revolutions of the record.

    Parameters
    ----------
    t, x : array_like
        Times [s] and signal samples, ``x`` (n,) or (n, m) (m signals sharing the angle).
    angle : array_like
        Shaft angle [rad] at ``t``, strictly increasing.
    samples_per_rev : int
        Angle samples per revolution; orders up to ``samples_per_rev / 2`` are represented.

    Returns
    -------
    phi : ndarray
        Angles [rad] from ``angle[0]``, ``samples_per_rev`` per revolution, whole revolutions only
        (:func:`angle_samples`).
    y : ndarray
        Signal at ``phi``: the not-a-knot cubic spline of ``x`` against ``angle``
        (``scipy.interpolate.CubicSpline``'s default; :func:`resample_records`).
    """
    t, x, _ = _uniform(t, x)
    phi, y, _ = resample_records(t, x.reshape(t.size, 1, -1), np.asarray(angle, float)[:, None], samples_per_rev)
    return phi, y[:, 0].reshape((phi.size,) + x.shape[1:])


def resample_records(t: ArrayLike, x: ArrayLike, angles: ArrayLike, samples_per_rev: int = 64
                     ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.intp]]:
    """:func:`resample_to_angle` of ``R`` records that share their times but not their shaft angles (the
    start-ups of a block of parameter points), in one compiled pass.

    Parameters
    ----------
    t : array_like (n,)
        Times [s], uniform.
    x : array_like (n, R, m)
        ``m`` signals of each record.
    angles : array_like (n, R)
        Each record's shaft angle [rad], strictly increasing.
    samples_per_rev : int
        Angle samples per revolution.

    Returns
    -------
    phi : ndarray (n_phi,)
        Angles [rad] from each record's first angle, ``samples_per_rev`` a revolution, over the most whole
        revolutions any record holds.
    y : ndarray (n_phi, R, m)
        The signals at ``phi`` (a not-a-knot cubic spline against the record's angle, as
        ``scipy.interpolate.CubicSpline``), NaN beyond a record's own whole revolutions.
    counts : ndarray (R,)
        Each record's angle samples (``samples_per_rev`` times its whole revolutions).
    """
    t, _, _ = _uniform(t, np.asarray(t, float))
    a = np.asarray(angles, float)
    v = np.asarray(x, float)
    if a.ndim != 2 or a.shape[0] != t.size or v.shape[:2] != a.shape or v.ndim != 3:
        raise SignalError(f"need records (n, R, m) and angles (n, R) on {t.size} times; got shapes {v.shape}, {a.shape}")
    if not np.all(np.isfinite(a)) or np.any(np.diff(a, axis=0) <= 0):
        raise SignalError("the shaft angle must match the time vector, be finite and increase strictly")
    revs = np.floor((a[-1] - a[0]) / (2 * math.pi) + 1e-9).astype(np.intp)
    if revs.min() < 1:
        raise SignalError(f"a record holds {(a[-1] - a[0]).min() / (2 * math.pi):.3g} revolutions; need at least 1")
    counts = revs * samples_per_rev
    phi = np.arange(counts.max()) * (2 * math.pi / samples_per_rev)
    return phi, _spline_records(a, np.ascontiguousarray(v), phi, counts), counts


@njit(cache=True)
def _spline_records(knots: NDArray[np.float64], values: NDArray[np.float64], phi: NDArray[np.float64],
                    counts: NDArray[np.intp]) -> NDArray[np.float64]:  # pragma: no cover (compiled)
    """Each record ``r``'s not-a-knot cubic spline through ``(knots[:, r], values[:, r, :])`` at
    ``knots[0, r] + phi[:counts[r]]`` (NaN beyond): scipy's ``CubicSpline`` (the slopes at the knots from its
    tridiagonal system with the not-a-knot end rows, here by elimination without pivoting, then the cubic of
    each interval; ``tests/test_signals.py`` holds it to scipy's within 1e-12). Needs ``n >= 4`` knots (its callers
    go through :func:`_uniform`'s 8)."""
    n, n_rec = knots.shape
    m = values.shape[2]
    out = np.full((phi.size, n_rec, m), np.nan)
    h = np.empty(n - 1)
    lower, diag, upper = np.empty(n), np.empty(n), np.empty(n)
    rhs, slope = np.empty((n, m)), np.empty((n - 1, m))
    for r in range(n_rec):
        x = knots[:, r]
        y = values[:, r, :]
        for i in range(n - 1):
            h[i] = x[i + 1] - x[i]
            for j in range(m):
                slope[i, j] = (y[i + 1, j] - y[i, j]) / h[i]
        d0, d1 = x[2] - x[0], x[n - 1] - x[n - 3]
        diag[0], upper[0] = h[1], d0
        for j in range(m):
            rhs[0, j] = ((h[0] + 2 * d0) * h[1] * slope[0, j] + h[0] * h[0] * slope[1, j]) / d0
        for i in range(1, n - 1):
            lower[i], diag[i], upper[i] = h[i], 2 * (h[i - 1] + h[i]), h[i - 1]
            for j in range(m):
                rhs[i, j] = 3 * (h[i] * slope[i - 1, j] + h[i - 1] * slope[i, j])
        lower[n - 1], diag[n - 1] = d1, h[n - 3]
        for j in range(m):
            rhs[n - 1, j] = (h[n - 2] * h[n - 2] * slope[n - 3, j] + (2 * d1 + h[n - 2]) * h[n - 3] * slope[n - 2, j]) / d1
        for i in range(1, n):                                       # elimination
            w = lower[i] / diag[i - 1]
            diag[i] -= w * upper[i - 1]
            for j in range(m):
                rhs[i, j] -= w * rhs[i - 1, j]
        for j in range(m):                                          # the slopes at the knots
            rhs[n - 1, j] /= diag[n - 1]
        for i in range(n - 2, -1, -1):
            for j in range(m):
                rhs[i, j] = (rhs[i, j] - upper[i] * rhs[i + 1, j]) / diag[i]
        k = 0
        for q in range(counts[r]):
            v = x[0] + phi[q]
            while k < n - 2 and x[k + 1] <= v:
                k += 1
            dx = v - x[k]
            for j in range(m):
                c3 = (rhs[k, j] + rhs[k + 1, j] - 2 * slope[k, j]) / h[k]
                c2 = (slope[k, j] - rhs[k, j]) / h[k] - c3
                out[q, r, j] = ((c3 / h[k] * dx + c2) * dx + rhs[k, j]) * dx + y[k, j]
    return out


def angle_samples(angle: ArrayLike, samples_per_rev: int = 64) -> NDArray[np.float64]:
    """The angles [rad] from ``angle[0]`` at which :func:`resample_to_angle` reads a record whose shaft
    ``angle`` [rad] (increasing) it is: ``samples_per_rev`` a revolution over its whole revolutions. A
    caller that has a record as a function of the angle (a periodic steady state's harmonics) evaluates it
    there instead of interpolating its samples."""
    a = np.asarray(angle, float)
    revs = math.floor((a[-1] - a[0]) / (2 * math.pi) + 1e-9)
    if revs < 1:
        raise SignalError(f"the record holds {(a[-1] - a[0]) / (2 * math.pi):.3g} revolutions; need at least 1")
    return np.arange(revs * samples_per_rev) * (2 * math.pi / samples_per_rev)


def order_amplitudes(t: ArrayLike, x: ArrayLike, angle: ArrayLike, orders: Sequence[float],
                     samples_per_rev: int = 64) -> NDArray[np.float64]:
    """Peak amplitudes of the given shaft ``orders`` (cycles per revolution) by order tracking.

    A least-squares fit of a mean plus ``cos(k phi), sin(k phi)`` for every order ``k`` on the
    angle-domain signal (:func:`resample_to_angle`).

    Examples
    --------
    >>> t = np.arange(0, 2, 1e-3); ang = 2 * np.pi * (10 * t + 5 * t**2)       # run-up 10 -> 30 Hz
    >>> x = 0.5 * np.cos(ang) + 0.1 * np.sin(2 * ang + 1)
    >>> np.round(order_amplitudes(t, x, ang, [1, 2]), 4)
    array([0.5, 0.1])
    """
    return angle_amplitudes(*resample_to_angle(t, x, angle, samples_per_rev), orders)


def angle_amplitudes(phi: ArrayLike, y: ArrayLike, orders: Sequence[float]) -> NDArray[np.float64]:
    """Peak amplitudes of the given ``orders`` in an angle-domain signal ``y`` at uniform shaft
    angles ``phi`` [rad] (from :func:`resample_to_angle`, when a caller reuses the resampled record);
    ``y`` (n, m) holds m signals, the amplitudes are then (n_orders, m).

    Examples
    --------
    >>> phi = np.linspace(0, 8 * np.pi, 256, endpoint=False)
    >>> np.round(angle_amplitudes(phi, 0.3 * np.cos(2 * phi), [1, 2]), 4)
    array([0. , 0.3])
    """
    return _lsq_amplitudes(np.asarray(phi, float), np.asarray(y, float), np.asarray(orders, float))


def _lsq_amplitudes(phase: NDArray[np.float64], y: NDArray[np.float64], k: NDArray[np.float64]) -> NDArray[np.float64]:
    """Peak amplitudes of the sinusoids ``cos(k phase), sin(k phase)`` fitted jointly with a mean, by least squares:
    ``k`` (n_k,) one design for every column of ``y`` (n, ...), amplitudes (n_k, ...); ``k`` (R, n_k) one design
    for each column of ``y`` (n, R), amplitudes (n_k, R)."""
    own = k.ndim == 2
    k2 = np.atleast_2d(k)
    if np.any(k2 * (phase[1] - phase[0]) >= math.pi):
        raise SignalError(f"an order/frequency in {np.unique(k2).tolist()} is at or above the Nyquist limit of the sampling")
    arg = phase[None, :, None] * k2[:, None, :]                                    # (R, n, n_k)
    design = np.concatenate([np.ones(arg.shape[:2] + (1,)), np.cos(arg), np.sin(arg)], axis=2)
    rhs = y.T[:, :, None] if own else y.reshape(1, y.shape[0], -1)                # (R, n, m)
    # least squares by a thin QR of each design (a tenth of the SVD's cost on these tall, well-conditioned
    # designs); the SVD's minimum-norm answer where its columns are (nearly) dependent
    qm, r = np.linalg.qr(design)
    diag = np.abs(np.diagonal(r, axis1=1, axis2=2))
    coef = np.empty((design.shape[0], design.shape[2], rhs.shape[2]))
    good = diag.min(axis=1) > 1e-10 * diag.max(axis=1)
    if good.any():
        coef[good] = np.linalg.solve(r[good], np.swapaxes(qm[good], 1, 2) @ rhs[good])
    for b in np.flatnonzero(~good):
        coef[b] = np.linalg.lstsq(design[b], rhs[b], rcond=None)[0]
    n_k = k2.shape[1]
    amps = np.hypot(coef[:, 1:1 + n_k], coef[:, 1 + n_k:])                       # (R, n_k, m)
    return amps[:, :, 0].T if own else amps[0].reshape((n_k,) + y.shape[1:])


def order_spectrum(t: ArrayLike, x: ArrayLike, angle: ArrayLike,
                   samples_per_rev: int = 64) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Order spectrum of whole revolutions: ``(orders [-], peak amplitudes)``.

    Rectangular window over an integer number of revolutions, so every order ``j / revs`` is a
    bin and integer orders do not leak.
    """
    phi, y = resample_to_angle(t, x, angle, samples_per_rev)
    return _spectrum(y, samples_per_rev, len(y) / samples_per_rev)


def _spectrum(y: NDArray[np.float64], per_unit: float, units: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    n = len(y)
    amp = np.abs(np.fft.rfft(y - y.mean())) * 2.0 / n
    return np.arange(amp.size) / units, amp


def order_map(t: ArrayLike, x: ArrayLike, angle: ArrayLike, revs_per_block: int = 8, samples_per_rev: int = 64
              ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Run-up order map: order spectra of consecutive blocks of ``revs_per_block`` revolutions.

    Returns
    -------
    speed_rpm : ndarray, shape (blocks,)
        Mean shaft speed of each block [rpm].
    orders : ndarray, shape (bins,)
    amplitude : ndarray, shape (blocks, bins)
        Peak amplitudes.
    """
    t, x, _ = _uniform(t, x)
    a = np.asarray(angle, float)
    phi, y = resample_to_angle(t, x, a, samples_per_rev)
    n = revs_per_block * samples_per_rev
    blocks = len(y) // n
    if blocks < 1:
        raise SignalError(f"the record is shorter than one block of {revs_per_block} revolutions")
    t_phi = np.interp(phi + a[0], a, t)
    speed, amps = [], []
    for b in range(blocks):
        sl = slice(b * n, (b + 1) * n)
        orders, amp = _spectrum(y[sl], samples_per_rev, revs_per_block)
        amps.append(amp)
        speed.append(revs_per_block * 60.0 / (t_phi[sl][-1] - t_phi[sl][0]) * (n - 1) / n)
    return np.asarray(speed), orders, np.asarray(amps)


def harmonic_amplitudes(t: ArrayLike, x: ArrayLike, frequencies: Sequence[float]) -> NDArray[np.float64]:
    """Peak amplitudes of sinusoids at the given ``frequencies`` [Hz] (joint least squares with a mean).

    Exact for a stationary signal made of those sinusoids; the frequencies must differ by more
    than about ``1 / duration`` to be told apart.
    """
    t, x, _ = _uniform(t, x)
    return _lsq_amplitudes(2 * math.pi * (t - t[0]), x, np.asarray(frequencies, float))


def record_harmonics(t: ArrayLike, x: ArrayLike, frequencies: ArrayLike) -> NDArray[np.float64]:
    """:func:`harmonic_amplitudes` of each record ``x[:, r]`` (n, R) at its own ``frequencies[r]`` (R, n_f) [Hz]
    (the current lines of start-ups at different speeds), all at once: (n_f, R)."""
    t, x, _ = _uniform(t, x)
    f = np.asarray(frequencies, float)
    if x.ndim != 2 or f.ndim != 2 or f.shape[0] != x.shape[1]:
        raise SignalError(f"need records (n, R) and frequencies (R, n_f); got shapes {x.shape}, {f.shape}")
    return _lsq_amplitudes(2 * math.pi * (t - t[0]), x, f)


def slip_sidebands(line_hz: float, slip: float) -> tuple[float, float]:
    """The twice-slip sidebands ``f (1 - 2 s), f (1 + 2 s)`` [Hz] of the line frequency ``f`` [Hz]."""
    return line_hz * (1 - 2 * slip), line_hz * (1 + 2 * slip)


def envelope(t: ArrayLike, x: ArrayLike, band: tuple[float, float] | None = None) -> NDArray[np.float64]:
    """Amplitude envelope ``|x + j H(x)|`` (Hilbert transform), optionally of ``x`` band-passed to ``band`` [Hz]
    first (4th-order Butterworth, zero phase): the demodulation step of bearing envelope analysis.
    ``x`` (n, m) holds m signals (each column's envelope)."""
    t, x, dt = _uniform(t, x)
    if band is not None:
        lo, hi = band
        nyq = 0.5 / dt
        if not 0 < lo < hi < nyq:
            raise SignalError(f"envelope band must satisfy 0 < low < high < Nyquist {nyq:g} Hz, got {band}")
        x = sosfiltfilt(butter(4, [lo, hi], btype="band", fs=1 / dt, output="sos"), x, axis=0)
    return np.abs(hilbert(x, axis=0))


def band_energy(t: ArrayLike, x: ArrayLike, center: float, half_width: float, harmonics: int = 1) -> float:
    """Mean square of ``x`` [unit^2] in the bands ``h * center +- half_width`` [Hz], ``h = 1..harmonics``.

    From the Hann-windowed one-sided periodogram (Parseval: a sinusoid of amplitude ``A`` inside a
    band gives ``A^2 / 2`` when the band spans its main lobe, ``half_width >= 2 / duration``).
    Use it on :func:`envelope` for bearing defects (BPFO, BPFI).
    """
    return float(band_energies(t, x, [center], half_width, harmonics)[0])


def band_energies(t: ArrayLike, x: ArrayLike, centers: Sequence[float], half_width: float,
                  harmonics: int = 1) -> NDArray[np.float64]:
    """:func:`band_energy` of one record for each of ``centers`` [Hz] (one periodogram for them all):
    (n_centers,); of each column of ``x`` (n, m): (n_centers, m)."""
    t, x, dt = _uniform(t, x)
    duration = len(t) * dt
    if half_width < 2.0 / duration:
        raise SignalError(f"half_width {half_width:g} Hz is narrower than the Hann main lobe of this record "
                          f"(2 / duration = {2 / duration:.3g} Hz)")
    f, p = _periodogram(x, dt)
    df = f[1] - f[0]
    out = np.zeros((len(centers),) + x.shape[1:])
    for c, center in enumerate(centers):
        for h in range(1, harmonics + 1):
            sel = np.abs(f - h * center) <= half_width
            out[c] += p[sel].sum(axis=0) * df
    return out


def _periodogram(x: NDArray[np.float64], dt: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Frequencies [Hz] and the one-sided power spectral density [unit^2/Hz] of the columns of ``x`` (n, ...)
    sampled every ``dt`` [s]: mean removed, periodic Hann window, one FFT (``scipy.signal.periodogram(x, 1 / dt,
    "hann", detrend="constant", scaling="density", axis=0)``, whose one-segment Welch path costs three times
    as much; ``tests/test_signals.py`` holds the two together)."""
    n = x.shape[0]
    w = 0.5 - 0.5 * np.cos(2 * math.pi * np.arange(n) / n)
    spec = np.fft.rfft((x - x.mean(axis=0)) * w.reshape((n,) + (1,) * (x.ndim - 1)), axis=0)
    p = (spec.real ** 2 + spec.imag ** 2) * (dt / (w @ w))
    p[1:(n + 1) // 2] *= 2.0                                   # one-sided: all but DC (and an even record's Nyquist)
    return np.fft.rfftfreq(n, dt), p


def band_rms_spectrum(x: ArrayLike, dt: float, edges: ArrayLike) -> NDArray[np.float64]:
    """RMS of ``x`` in each frequency band ``[edges[k], edges[k+1])`` [Hz], in the signal's unit.

    The mean square per band from the Hann-windowed one-sided periodogram (mean removed), so the
    squares of all bands up to Nyquist add to the record's variance (Parseval): a sinusoid of
    amplitude ``A`` whose main lobe (``+- 2 / duration``) lies inside one band gives ``A / sqrt 2``
    there. A fixed grid of bands (unlike FFT bins) does not depend on the record's length: a
    spectrum that is the same output at every parameter point and in every scene.

    Parameters
    ----------
    x : array_like, shape (n,) or (n, m)
        The record(s), sampled every ``dt`` [s] (columns: several signals at once).
    dt : float
        Sampling interval [s].
    edges : array_like, shape (n_bands + 1,)
        Increasing band edges [Hz], the last at most Nyquist ``1 / (2 dt)``.

    Examples
    --------
    >>> t = np.arange(0.0, 100.0, 0.05)
    >>> x = 3.0 * np.sin(2 * np.pi * 0.6 * t) + 1.0 * np.sin(2 * np.pi * 1.6 * t)
    >>> np.round(band_rms_spectrum(x, 0.05, [0.0, 0.5, 1.0, 1.5, 2.0]) * np.sqrt(2), 3)
    array([0., 3., 0., 1.])
    """
    x = np.asarray(x, float)
    e = np.asarray(edges, float)
    if x.shape[0] < 8 or np.any(np.diff(e) <= 0) or e[0] < 0 or e[-1] > 0.5 / dt * (1 + 1e-12):
        raise SignalError(f"band edges must increase within [0, Nyquist {0.5 / dt:g} Hz] on a record of >= 8 samples; "
                          f"got edges {e[0]:g} .. {e[-1]:g} Hz on {x.shape[0]} samples")
    if np.diff(e).min() < 2.0 / (x.shape[0] * dt):
        raise SignalError(f"a band of {np.diff(e).min():g} Hz is narrower than the Hann main lobe of this "
                          f"{x.shape[0] * dt:g} s record (2 / duration = {2.0 / (x.shape[0] * dt):.3g} Hz)")
    f, p = _periodogram(x, dt)
    df = f[1] - f[0]
    k = np.searchsorted(e, f, side="right") - 1                  # band of each frequency line
    inside = (k >= 0) & (k < len(e) - 1)
    power = np.zeros((len(e) - 1,) + p.shape[1:])
    np.add.at(power, k[inside], p[inside] * df)
    return np.sqrt(power)


# -- plots -----------------------------------------------------------------------------------------
def plot_order_map(speed_rpm: ArrayLike, orders: ArrayLike, amplitude: ArrayLike, max_order: float = 10.0,
                   ax=None, unit: str = ""):
    """Order map of a run-up (from :func:`order_map`): speed [rpm] against order, amplitude in colour (log)."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    ax = ax if ax is not None else plt.figure(figsize=(7, 4.5)).add_subplot()
    orders = np.asarray(orders)
    keep = orders <= max_order
    amp = np.asarray(amplitude)[:, keep]
    positive = amp[amp > 0]
    norm = LogNorm(vmin=max(positive.max() * 1e-4, positive.min()), vmax=positive.max()) if positive.size else None
    mesh = ax.pcolormesh(orders[keep], np.asarray(speed_rpm), np.where(amp > 0, amp, np.nan), norm=norm,
                         shading="nearest", cmap="viridis")
    ax.figure.colorbar(mesh, ax=ax, label=f"peak amplitude {unit}".strip())
    ax.set_xlabel("order [-]")
    ax.set_ylabel("shaft speed [rpm]")
    return ax


def plot_spectrum(t: ArrayLike, x: ArrayLike, marks: Mapping[str, float] | None = None, max_hz: float | None = None,
                  ax=None, unit: str = ""):
    """Amplitude spectrum of a steady record (Hann window, amplitude-corrected) with frequencies marked.

    ``marks`` maps labels to frequencies [Hz], e.g. ``{"1x": 25.0, "2x": 50.0, "BPFO": 89.6}``.
    """
    import matplotlib.pyplot as plt

    t, x, dt = _uniform(t, x)
    ax = ax if ax is not None else plt.figure(figsize=(7, 4)).add_subplot()
    w = np.hanning(len(x))
    amp = np.abs(np.fft.rfft((x - x.mean()) * w)) * 2.0 / w.sum()
    f = np.fft.rfftfreq(len(x), dt)
    keep = f <= (max_hz if max_hz is not None else f[-1])
    peak = float(amp[keep].max()) if keep.any() and amp[keep].max() > 0 else 1.0
    ax.semilogy(f[keep], np.maximum(amp[keep], 1e-300), lw=0.8)
    ax.set_ylim(peak * 1e-6, peak * 3.0)                 # six decades below the peak, room for the labels
    ax.set_xlim(0.0, f[keep][-1])
    for label, fm in (marks or {}).items():
        if not 0.0 <= fm <= f[keep][-1]:
            continue
        ax.axvline(fm, color="C3", ls="--", lw=0.7)
        ax.annotate(label, (fm, 0.98), xycoords=("data", "axes fraction"), xytext=(2, 0), textcoords="offset points",
                    rotation=90, va="top", ha="left", fontsize=8, color="C3", annotation_clip=True)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel(f"peak amplitude {unit}".strip())
    return ax
