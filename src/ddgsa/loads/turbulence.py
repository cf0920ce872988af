"""IEC 61400-1 normal turbulence (Kaimal spectra, exponential coherence) by the Veers method.

Facts used (IEC 61400-1 ed. 3, §6.3 and Annex C):

- ``sigma_1 = I_ref (0.75 V_hub + 5.6)`` [m/s]; ``sigma_2 = 0.8 sigma_1``, ``sigma_3 = 0.5 sigma_1``;
- ``Lambda_1 = 0.7 z_hub`` for ``z_hub < 60 m``, else 42 m; ``L_u = 8.1, L_v = 2.7, L_w = 0.66``
  times ``Lambda_1``;
- Kaimal ``S_k(f) = 4 sigma_k^2 (L_k/V) / (1 + 6 f L_k/V)^(5/3)`` (one-sided);
- coherence ``exp(-12 sqrt((f r/V)^2 + (0.12 r/L_c)^2))``, ``L_c = 8.1 Lambda_1``. The standard
  gives it for u only; ddgsa applies the same model to v and w (documented choice; an
  uncorrelated v, w field would overstate in-plane rotor loads).

Generation (Veers 1988): per frequency, the cross-spectral matrix ``S(f) C(f)`` is factored
``L L^T`` (Cholesky, cached per grid and ``f/V``), and Fourier amplitudes
``sqrt(2 S df) L z`` with complex standard normal ``z`` are summed by an inverse real FFT.
Above the frequency where every off-diagonal coherence is below ``COHERENCE_TOL`` the factor
is the identity (points independent), which keeps memory small.

Variance: a realisation is **not** rescaled to the target sigma. A record of length T
holds the Kaimal variance above ``1/T`` only, a fraction ``(1 + 6 L/(V T))^(-2/3)`` of it
(e.g. 82 % of the u variance for V = 10 m/s, T = 600 s); rescaling every record to
``sigma`` would remove the physical record-to-record spread of turbulence, which is one
of the uncertainties a GSA over realisations should see.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.fft
from numpy.typing import NDArray

COHERENCE_TOL = 1e-4
_COH_A, _COH_B = 12.0, 0.12


@dataclass(frozen=True)
class IecTurbulence:
    """IEC normal turbulence model parameters for one hub wind speed.

    Parameters
    ----------
    wind_speed : float
        Mean hub-height wind speed V_hub [m/s].
    turbulence_intensity : float
        Reference turbulence intensity I_ref [-] (IEC class A 0.16, B 0.14, C 0.12).
    hub_height : float
        Hub height z_hub [m].
    """

    wind_speed: float
    turbulence_intensity: float
    hub_height: float

    @property
    def sigma(self) -> NDArray[np.float64]:
        """Standard deviations of u, v, w [m/s]."""
        s1 = self.turbulence_intensity * (0.75 * self.wind_speed + 5.6)
        return s1 * np.array([1.0, 0.8, 0.5])

    @property
    def scale_parameter(self) -> float:
        """Longitudinal turbulence scale parameter Lambda_1 [m]."""
        return 0.7 * self.hub_height if self.hub_height < 60.0 else 42.0

    @property
    def length_scales(self) -> NDArray[np.float64]:
        """Integral length scales L_u, L_v, L_w [m]."""
        return self.scale_parameter * np.array([8.1, 2.7, 0.66])

    @property
    def coherence_scale(self) -> float:
        """Coherence scale parameter L_c [m]."""
        return 8.1 * self.scale_parameter

    def spectra(self, f: NDArray[np.float64]) -> NDArray[np.float64]:
        """One-sided Kaimal spectra of u, v, w at frequencies ``f`` [Hz]: shape (3, n_f) [m^2/s]."""
        f = np.asarray(f, dtype=float)
        lv = (self.length_scales / self.wind_speed)[:, None]
        return 4.0 * self.sigma[:, None] ** 2 * lv / (1.0 + 6.0 * f[None, :] * lv) ** (5.0 / 3.0)

    def coherence(self, f: NDArray[np.float64], r: NDArray[np.float64]) -> NDArray[np.float64]:
        """IEC exponential coherence at frequencies ``f`` [Hz] and separations ``r`` [m] (broadcast)."""
        return np.exp(-_COH_A * np.sqrt((f * r / self.wind_speed) ** 2
                                         + (_COH_B * r / self.coherence_scale) ** 2))


def frequencies(duration: float, dt: float) -> tuple[NDArray[np.float64], int]:
    """Positive FFT frequencies [Hz] of a record of ``duration`` [s] sampled at ``dt`` [s], and n."""
    n = int(round(duration / dt))
    return np.arange(1, n // 2 + (n % 2)) / (n * dt), n


def _cholesky_factors(points: NDArray[np.float64], f: NDArray[np.float64],
                      model: IecTurbulence) -> tuple[NDArray[np.float64], int]:
    """Cholesky factors of the coherence matrix for the low frequencies that need one.

    Returns the factors (n_low, n_pts, n_pts) and n_low; above index n_low the coherence
    matrix equals the identity within :data:`COHERENCE_TOL`.
    """
    diff = points[:, None, :] - points[None, :, :]
    r = np.sqrt((diff ** 2).sum(axis=-1))
    r_min = r[r > 0].min() if points.shape[0] > 1 else np.inf
    coh_at = model.coherence(f, r_min) if np.isfinite(r_min) else np.zeros_like(f)
    n_low = int(np.searchsorted(-coh_at, -COHERENCE_TOL))     # coherence decreases with f
    return _factor_cached(r.tobytes(), r.shape[0], tuple(f[:n_low].tolist()), model), n_low


@lru_cache(maxsize=2)       # 20-60 MB each for a 600 s record; refactoring costs 0.05-0.15 s
def _factor_cached(r_bytes: bytes, n: int, f_low: tuple[float, ...],
                   model: IecTurbulence) -> NDArray[np.float64]:
    r = np.frombuffer(r_bytes).reshape(n, n)
    f = np.asarray(f_low)
    # the coherence is a function of the distance: evaluated once per distinct one (a rotor grid of
    # rings has ~10x fewer than point pairs) and gathered; the same numbers, element by element
    distances, where = np.unique(r, return_inverse=True)
    coh = model.coherence(f[:, None], distances[None, :])[:, where.reshape(n, n)]
    return np.linalg.cholesky(coh)


def generate_field(points: NDArray[np.float64], model: IecTurbulence, duration: float, dt: float,
                   seed: int | np.random.SeedSequence) -> NDArray[np.float64]:
    """Turbulent velocity fluctuations u, v, w at fixed points of the rotor plane.

    Parameters
    ----------
    points : ndarray (n_pts, 2)
        Lateral and vertical coordinates (y, z) of the points in the rotor plane [m].
    model : IecTurbulence
    duration, dt : float
        Record length and time step [s].
    seed : int or SeedSequence
        Seed of this realisation.

    Returns
    -------
    ndarray (3, n_t, n_pts)
        Zero-mean fluctuations of u (along the mean wind), v (lateral), w (vertical) [m/s].
    """
    f, n = frequencies(duration, dt)
    df = 1.0 / (n * dt)
    factors, n_low = _cholesky_factors(np.asarray(points, dtype=float), f, model)
    rng = np.random.default_rng(seed)
    # Fourier amplitudes sqrt(2 S df) z n / 2 with z = (a + i b) / sqrt(2): one real scale per frequency
    scale = np.sqrt(2.0 * model.spectra(f) * df) * (n / 2.0) / np.sqrt(2.0)   # (3, n_f)
    n_pts = points.shape[0]
    out = np.empty((3, n, n_pts))
    spec = np.zeros((n_pts, n // 2 + 1), dtype=complex)     # one point per row: each FFT reads contiguous memory
    for k in range(3):
        re = rng.standard_normal((f.size, n_pts))          # real and imaginary parts, drawn in that order
        im = rng.standard_normal((f.size, n_pts))
        low = np.matmul(factors, np.stack([re[:n_low], im[:n_low]], axis=-1))   # real factors act on both parts
        re[:n_low], im[:n_low] = low[..., 0], low[..., 1]
        spec.real[:, 1:1 + f.size] = (re * scale[k][:, None]).T
        spec.imag[:, 1:1 + f.size] = (im * scale[k][:, None]).T
        out[k] = scipy.fft.irfft(spec, n=n, axis=1).T
    return out
