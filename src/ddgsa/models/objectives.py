"""Objective functions shared by the drive-train models (seed 000 §3.2.1).

Bearing damage by Palmgren-Miner with the equivalent dynamic load ``P`` and the L10 life
``(C / P)^(10/3)`` million revolutions; the direct and the indirect drive both use it.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def equivalent_load(fr: NDArray[np.float64], fa: NDArray[np.float64], rule: str) -> NDArray[np.float64]:
    """Equivalent dynamic bearing load P [N] from radial ``fr`` and axial ``fa`` forces [N].

    ``rule="seed"``: seed 000 eq. (29), ``P = 2.5 Fr + 3.7 Fa``; otherwise ISO 281 for a spherical
    roller bearing (``Fr + 2.5 Fa`` while ``Fa <= 0.27 Fr``, else ``0.67 Fr + 3.7 Fa``).

    >>> float(equivalent_load(np.array([1.0]), np.array([1.0]), "seed")[0])
    6.2
    """
    if rule == "seed":
        return 2.5 * fr + 3.7 * fa                                    # seed 000 eq. (29)
    with np.errstate(divide="ignore", invalid="ignore"):
        low_axial = fa <= 0.27 * fr
    return np.where(low_axial, fr + 2.5 * fa, 0.67 * fr + 3.7 * fa)  # ISO 281 spherical roller


def damage_rate(fr: NDArray[np.float64], fa: NDArray[np.float64], speed: NDArray[np.float64], rating: float,
                rule: str) -> float:
    """Palmgren-Miner damage rate [1/s]: mean of ``(w / 2 pi) (P / C)^(10/3) / 1e6``.

    ``speed`` [rad/s], ``rating`` the dynamic load rating C [N]; 1 means the L10 life is used up
    in one second.
    """
    p = equivalent_load(fr, fa, rule)
    return float(np.mean(np.abs(speed) / (2 * np.pi) * (p / rating) ** (10.0 / 3.0)) / 1e6)
