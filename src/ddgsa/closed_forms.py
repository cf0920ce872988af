"""Closed-form functions shared across layers.

The analytic test model (:mod:`ddgsa.models.analytic`) and the GSA layer's reference
functions (:mod:`ddgsa.gsa.testfunctions`) both evaluate these; keeping them here lets each
layer be used and tested without the other (models know nothing of Sobol indices).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def ishigami(x: NDArray[np.float64], a: float = 7.0, b: float = 0.1) -> NDArray[np.float64]:
    """Ishigami & Homma (1990): ``sin x1 + a sin^2 x2 + b x3^4 sin x1`` [-].

    Parameters
    ----------
    x : ndarray, shape (n_points, 3)
        Inputs [-], usually on ``[-pi, pi]``.
    a, b : float
        The function's constants [-].

    Examples
    --------
    >>> float(ishigami(np.array([[np.pi / 2, np.pi / 2, 1.0]]))[0])
    8.1
    """
    return np.sin(x[:, 0]) + a * np.sin(x[:, 1]) ** 2 + b * x[:, 2] ** 4 * np.sin(x[:, 0])
