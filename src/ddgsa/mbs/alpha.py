"""The step formulas of generalised-alpha (Arnold & Bruls 2007), written once for every loop.

:func:`ddgsa.mbs.integrate.genalpha.simulate` (any System, Python), the packed System's numba
loop (:mod:`ddgsa.mbs.compiled`, which compiles :func:`predict` as it is) and the linear speed
sweep (:mod:`ddgsa.mbs.sweep`) take their coefficients, predictor and auxiliary-acceleration
update from here.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ddgsa.errors import ModelError

Array = NDArray[np.float64]


def coefficients(rho_inf: float) -> tuple[float, float, float, float]:
    """``(alpha_m, alpha_f, gamma, beta)`` of generalised-alpha for spectral radius ``rho_inf``."""
    if not 0.0 <= rho_inf <= 1.0:
        raise ModelError(f"rho_inf = {rho_inf} not allowed; 0 <= rho_inf <= 1")
    am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
    af = rho_inf / (rho_inf + 1.0)
    gamma = 0.5 - am + af
    beta = 0.25 * (1.0 - am + af) ** 2
    return am, af, gamma, beta


def primed(am: float, af: float, gamma: float, beta: float) -> tuple[float, float]:
    """``(beta', gamma')``: the position and velocity change per unit change of the new
    acceleration within a step, in units of ``h^2`` and ``h`` (the iteration matrix is
    ``M + gamma' h C + beta' h^2 K``)."""
    return beta * (1.0 - af) / (1.0 - am), gamma * (1.0 - af) / (1.0 - am)


def next_aux(acc: Array, aux: Array, acc_new: Array, am: float, af: float) -> Array:
    """The auxiliary acceleration of the next step from the step's old and new accelerations."""
    return (af * acc - am * aux + (1.0 - af) * acc_new) / (1.0 - am)


def predict(q: Array, qd: Array, acc: Array, aux: Array, h: float, am: float, af: float, gamma: float,
            beta: float) -> tuple[Array, Array, Array]:
    """The predictor of a step of ``h`` [s]: the new acceleration guessed equal to the old one,
    positions and velocities from it; returns ``(acc_new, q, qd)`` (new arrays). Plain arithmetic,
    so :mod:`ddgsa.mbs.compiled` compiles this same function for its loop."""
    acc_new = acc.copy()
    aux_new = (af * acc - am * aux + (1.0 - af) * acc_new) / (1.0 - am)      # next_aux, inline for numba
    return (acc_new, q + h * qd + h * h * ((0.5 - beta) * aux + beta * aux_new),
            qd + h * ((1.0 - gamma) * aux + gamma * aux_new))
