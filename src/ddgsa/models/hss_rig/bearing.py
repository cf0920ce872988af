"""Rolling-bearing kinematics (defect frequencies) and the outer-race defect force.

Defect frequencies of a bearing with ``n`` rolling elements of diameter ``d`` on a pitch
diameter ``D`` at contact angle ``alpha``, inner ring turning at ``f_r`` and outer ring fixed
(Randall & Antoni, *Rolling element bearing diagnostics -- a tutorial*, MSSP 25 (2011), eqs. 1-4;
also Harris, *Rolling Bearing Analysis*)::

    BPFO = n f_r / 2 (1 - d/D cos alpha)          ball pass, outer race
    BPFI = n f_r / 2 (1 + d/D cos alpha)          ball pass, inner race
    FTF  =   f_r / 2 (1 - d/D cos alpha)          cage
    BSF  = D f_r / (2 d) (1 - (d/D cos alpha)^2)  ball spin

Default geometry: the SKF 6205 deep-groove ball bearing (9 balls of 7.94 mm on a 39.04 mm
pitch diameter, ``alpha`` = 0), a common size for a lab-scale shaft of 25 mm and the bearing of
the Case Western Reserve University bearing data set, whose published defect orders (BPFO
3.5848, BPFI 5.4152, FTF 0.39828, BSF 2.357 times the shaft speed) the tests use as the oracle.

Outer-race defect: a localised spall in the load zone of the fixed outer ring is struck by
each rolling element, a train of short impulses at BPFO in the direction of the load zone
(Randall & Antoni §2; McFadden & Smith, JSV 96 (1984)). Each impact is a half-sine force
pulse of duration ``width`` and peak ``amplitude``; the ball passage jitters randomly by a
fraction of the period (rolling elements slip: 1-2 % in Randall & Antoni), seeded.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ddgsa.errors import ModelError


@dataclass(frozen=True)
class BearingGeometry:
    """Rolling-element bearing geometry (default: SKF 6205).

    Attributes
    ----------
    rolling_elements : int
        Number of balls or rollers ``n`` [-].
    element_diameter : float
        Ball diameter ``d`` [m].
    pitch_diameter : float
        Pitch diameter ``D`` [m].
    contact_angle : float
        Contact angle ``alpha`` [rad].
    """

    rolling_elements: int = 9
    element_diameter: float = 0.3126 * 0.0254
    pitch_diameter: float = 1.537 * 0.0254
    contact_angle: float = 0.0

    def __post_init__(self) -> None:
        if int(self.rolling_elements) != self.rolling_elements or self.rolling_elements < 3:
            raise ModelError(f"bearing 'rolling_elements' must be an integer >= 3, got {self.rolling_elements}")
        if not 0 < self.element_diameter < self.pitch_diameter:
            raise ModelError(f"bearing 'element_diameter' must be in (0, pitch_diameter = {self.pitch_diameter}) m, "
                             f"got {self.element_diameter}")
        if not 0 <= self.contact_angle < math.pi / 2:
            raise ModelError(f"bearing 'contact_angle' must be in [0, pi/2) rad, got {self.contact_angle}")

    @property
    def _ratio(self) -> float:
        return self.element_diameter / self.pitch_diameter * math.cos(self.contact_angle)

    def bpfo(self, shaft_hz: ArrayLike = 1.0) -> NDArray[np.float64]:
        """Ball-pass frequency of the outer race [Hz] at shaft speed ``shaft_hz`` [Hz] (1: the order)."""
        return np.asarray(shaft_hz, float) * self.rolling_elements / 2 * (1 - self._ratio)

    def bpfi(self, shaft_hz: ArrayLike = 1.0) -> NDArray[np.float64]:
        """Ball-pass frequency of the inner race [Hz] at shaft speed ``shaft_hz`` [Hz]."""
        return np.asarray(shaft_hz, float) * self.rolling_elements / 2 * (1 + self._ratio)

    def ftf(self, shaft_hz: ArrayLike = 1.0) -> NDArray[np.float64]:
        """Fundamental train (cage) frequency [Hz] at shaft speed ``shaft_hz`` [Hz]."""
        return np.asarray(shaft_hz, float) / 2 * (1 - self._ratio)

    def bsf(self, shaft_hz: ArrayLike = 1.0) -> NDArray[np.float64]:
        """Ball spin frequency [Hz] at shaft speed ``shaft_hz`` [Hz]."""
        r = self._ratio
        return (np.asarray(shaft_hz, float) * self.pitch_diameter / (2 * self.element_diameter)
                * (1 - r * r))


SKF_6205 = BearingGeometry()
"""Deep-groove ball bearing 6205 (the default; see the module)."""


def defect_impulses(t: ArrayLike, shaft_angle: ArrayLike, geometry: BearingGeometry, amplitude: float,
                    width: float, jitter: float = 0.01, seed: int = 0) -> NDArray[np.float64]:
    """Force of an outer-race defect [N] at times ``t`` [s], in the direction of the load zone.

    The ``k``-th impact happens when the cage has carried ``k`` rolling elements past the defect,
    i.e. when ``shaft_angle * BPFO-order`` reaches ``2 pi k`` (so the train follows the speed in a
    run-up), shifted by a seeded random fraction (``jitter``, standard deviation, of one period)
    for rolling-element slip.

    Parameters
    ----------
    t : array_like
        Increasing times [s].
    shaft_angle : array_like
        Shaft angle [rad] at ``t``.
    amplitude : float
        Peak force of one impact [N] (0: healthy).
    width : float
        Duration of one half-sine pulse [s].
    jitter : float
        Standard deviation of the impact times as a fraction of the local period [-].
    seed : int
        Seed of the jitter.
    """
    t = np.asarray(t, float)
    phi = np.asarray(shaft_angle, float) * float(geometry.bpfo())     # defect-passage phase [rad]
    out = np.zeros_like(t)
    if amplitude == 0.0 or t.size == 0:
        return out
    k = np.arange(math.ceil(phi[0] / (2 * math.pi)), math.floor(phi[-1] / (2 * math.pi)) + 1)
    if k.size == 0:
        return out
    if np.any(np.diff(phi) <= 0):
        raise ModelError("defect_impulses needs a strictly increasing shaft angle (the shaft turns one way)")
    t_hit = np.interp(2 * math.pi * k, phi, t)
    period = np.gradient(t_hit) if k.size > 1 else np.full(1, width)
    rng = np.random.default_rng(seed)
    t_hit = t_hit + jitter * period * rng.standard_normal(k.size)
    for th in t_hit:
        lo, hi = np.searchsorted(t, [th, th + width])
        out[lo:hi] += amplitude * np.sin(math.pi * (t[lo:hi] - th) / width)
    return out


def on_grid(force_fine: ArrayLike, dt_fine: float, step: float, n: int) -> NDArray[np.float64]:
    """Samples on a grid of spacing ``step`` [s] (``n`` samples from ``t = 0``) that carry the impulse
    of a finely sampled force exactly: ``f_k = (1/step) integral f(t) phi_k(t) dt`` with ``phi_k``
    the hat function of sample ``k`` (the lumped projection onto linear elements).

    A defect pulse (0.2 ms) is shorter than a sensor interval (0.5 ms at 2 kHz): sampled
    point-wise it is caught or missed by chance, and the response integrated from the samples
    (:func:`ddgsa.mbs.linear.lti_response`, whose C1 interpolant integrates to ``step sum f_k``)
    changes by orders of magnitude with the sample rate. Projected, every impact keeps its
    impulse [N s] and its centroid time to within the grid, so the band below the grid's
    Nyquist frequency (the ball-pass orders and the housing resonance) converges with the rate.

    Parameters
    ----------
    force_fine : array_like
        Force [N] at ``t_j = j dt_fine``.
    dt_fine : float
        Fine sample interval [s].
    step : float
        Grid spacing [s].
    n : int
        Number of grid samples; the impulse past ``(n - 1) step`` is dropped.
    """
    f = np.asarray(force_fine, float)
    pos = np.arange(f.size) * dt_fine / step
    k = np.floor(pos).astype(int)
    frac = pos - k
    w = f * dt_fine / step
    out = np.bincount(k, w * (1 - frac), minlength=n + 1) + np.bincount(k + 1, w * frac, minlength=n + 2)[: n + 1]
    return out[:n]
