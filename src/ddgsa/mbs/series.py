"""Sampled inputs and their C1 cubic (Catmull-Rom) interpolation, shared by every integrator.

The one place the interpolation of a uniformly sampled input lives: :func:`catmull_rom_coefficients`
(the cubic per interval), :func:`interpolate` (its value or rate at a time, compiled) and
:func:`sub_sampled` (its values on a sub-step grid, vectorised), which
:class:`Series` (``value(t)``, ``value.derivative(t)``) calls from Python and the packed and exact
paths (:mod:`ddgsa.mbs.compiled`, :mod:`ddgsa.mbs.linear`) from compiled code.
"""

from __future__ import annotations

import numpy as np
from numba import njit
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


def sub_sampled(w: ArrayLike, n_sub: int) -> NDArray[np.float64]:
    """The C1 cubic interpolant of samples ``w`` (n_t, k) at ``n_sub`` equal sub-steps per interval:
    ((n_t - 1) n_sub + 1, k) rows, the grid of :func:`ddgsa.mbs.linear.lti_response` (vectorised
    :class:`Series` values).

    Examples
    --------
    >>> sub_sampled([[0.0], [1.0], [4.0]], 2)[:, 0].round(3).tolist()
    [0.0, 0.312, 1.0, 2.562, 4.0]
    """
    v = np.asarray(w, dtype=float)
    v = v.reshape(v.shape[0], -1)
    c0, c1, c2, c3 = catmull_rom_coefficients(v)
    s = (np.arange(n_sub) / n_sub)[None, :, None]
    fine = c0[:, None] + s * (c1[:, None] + s * (c2[:, None] + s * c3[:, None]))    # (n_t - 1, n_sub, k)
    return np.vstack([fine.reshape(-1, v.shape[1]), v[-1:]])


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
        self._flat = self.coef.ravel()

    def __call__(self, t: float) -> Array:
        out = interpolate(self._flat, 0, self.n, self.coef.shape[2], self.t0, self.dt, float(t), False)
        return out[0] if self.scalar else out

    def derivative(self, t: float) -> Array:
        """Time derivative of the interpolant [unit/s]."""
        out = interpolate(self._flat, 0, self.n, self.coef.shape[2], self.t0, self.dt, float(t), True)
        return out[0] if self.scalar else out


@njit(cache=True)
def interpolate(coef, base, n, k, t0, dt, t, deriv):  # pragma: no cover (compiled)
    """Value (or, with ``deriv``, time derivative) (k,) at ``t`` of the C1 cubic of ``n`` samples from
    ``t0`` every ``dt``, whose coefficients (4, n - 1, k) (:func:`catmull_rom_coefficients`) are
    ``coef[base:]`` flattened; held cubic beyond the ends."""
    pos = (t - t0) / dt
    j = int(pos)
    if j < 0:
        j = 0
    if j > n - 2:
        j = n - 2
    s = pos - j
    out = np.empty(k)
    stride = (n - 1) * k
    for c in range(k):
        c0 = coef[base + j * k + c]
        c1 = coef[base + stride + j * k + c]
        c2 = coef[base + 2 * stride + j * k + c]
        c3 = coef[base + 3 * stride + j * k + c]
        if deriv:
            out[c] = (c1 + s * (2.0 * c2 + 3.0 * s * c3)) / dt
        else:
            out[c] = c0 + s * (c1 + s * (c2 + s * c3))
    return out
