"""Sampled inputs and their C1 cubic (Catmull-Rom) interpolation, shared by every integrator.

The one place the interpolation of a uniformly sampled input lives: :class:`Series` for a
Python-side element (``value(t)``, ``value.derivative(t)``), :func:`catmull_rom_coefficients` for
the packed and exact paths (:mod:`ddgsa.mbs.compiled`, :mod:`ddgsa.mbs.linear`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ddgsa.errors import ModelError

Array = NDArray[np.float64]

CATMULL_ROM = np.array([[0.0, 1.0, 0.0, 0.0], [-0.5, 0.0, 0.5, 0.0], [1.0, -2.5, 2.0, -0.5],
                        [-0.5, 1.5, -1.5, 0.5]])
"""``c_j = sum_l CATMULL_ROM[j, l] w[k - 1 + l]``: the C1 cubic (Catmull-Rom) on interval k from
its four neighbouring samples (the end samples repeated at the ends)."""


def _padded(w: NDArray[np.float64]) -> NDArray[np.float64]:
    """Samples with the first and last repeated: ``w[k - 1 + l]`` of interval k is row ``k + l``."""
    return np.concatenate([w[:1], w, w[-1:], w[-1:]])


def catmull_rom_coefficients(w: NDArray[np.float64]) -> list[NDArray[np.float64]]:
    """Cubic coefficients ``c_0..c_3`` per interval (n_t - 1, k) of the C1 interpolant the integrators use."""
    wp, n = _padded(w), w.shape[0] - 1
    return [sum(CATMULL_ROM[j, l] * wp[l:l + n] for l in range(4)) for j in range(4)]


class Series:
    """A uniformly sampled signal with the C1 cubic (Catmull-Rom) interpolation of the integrators.

    Parameters
    ----------
    times : (n_t,) uniformly spaced sample times [s]
    values : (n_t,) or (n_t, k) samples

    Examples
    --------
    >>> s = Series([0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 2.0, 3.0])
    >>> float(s(1.5)), float(s.derivative(1.5))
    (1.5, 1.0)
    """

    def __init__(self, times: ArrayLike, values: ArrayLike) -> None:
        t = np.asarray(times, dtype=float)
        v = np.asarray(values, dtype=float)
        self.scalar = v.ndim == 1
        v = v.reshape(t.size, -1)
        if t.size < 2 or not np.allclose(np.diff(t), t[1] - t[0], rtol=1e-9, atol=0.0) or t[1] <= t[0]:
            raise ModelError(f"a time series needs >= 2 increasing, uniformly spaced times; got {t.size} samples")
        self.t0, self.dt, self.n = float(t[0]), float(t[1] - t[0]), t.size
        self.coef = np.stack(catmull_rom_coefficients(v))           # (4, n_t - 1, k)

    def _locate(self, t: float) -> tuple[int, float]:
        k = min(max(int((t - self.t0) / self.dt), 0), self.n - 2)
        return k, (t - self.t0) / self.dt - k

    def __call__(self, t: float) -> Array:
        k, s = self._locate(t)
        c = self.coef[:, k]
        out = c[0] + s * (c[1] + s * (c[2] + s * c[3]))
        return out[0] if self.scalar else out

    def derivative(self, t: float) -> Array:
        """Time derivative of the interpolant [unit/s]."""
        k, s = self._locate(t)
        c = self.coef[:, k]
        out = (c[1] + s * (2 * c[2] + 3 * s * c[3])) / self.dt
        return out[0] if self.scalar else out
