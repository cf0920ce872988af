"""Two readings of seed 000's damping laws and deflection objective: the physical one and the printed one.

Seed 000 (Asadi & Johansson 2020) admits two readings in three places; the direct drive
(:mod:`ddgsa.models.direct_drive`) takes each as a model option, the physical reading by default
(``docs/seed000_readings.md`` says why and what each changes):

``bending_rayleigh`` -- the shaft's bending damping ``C_b = eta M_b + delta K_b`` (seed eq. 43a):
    ``physical`` (default): ``delta = 2 zeta / (w1 + w2)``, ``eta = 2 zeta w1 w2 / (w1 + w2)``, the
    Rayleigh pair that gives ratio ``zeta`` at the first two bending frequencies ``w1, w2``;
    ``printed``: eq. (44a) as printed, ``delta = 2 zeta (w1 + w2)`` [s] (eq. 44b's ``eta`` is the
    physical one). With zeta = 0.01 and the nominal shaft (FE bending frequencies 3.28 and
    21.9 Hz), delta = 3.17 s: a bending mode at ``w`` gets ratio ``(eta / w + delta w) / 2``, far
    above 1 -- the shaft creeps to its elastic deflection with a time constant of seconds.
``bearing_damping`` -- the main bearings' dampers (seed eq. 48-49, Table 2's "longitudinal damping
    ratio zeta = 0.01 sec"):
    ``modal`` (default): a ratio, ``C = 2 zeta sqrt(K m / 2)`` per direction (m the shaft line's
    total mass, shared by two bearings); ``stiffness_proportional``: Table 2's unit taken
    literally, ``C = zeta K`` with zeta in seconds (3e7 N s/m for 3 GN/m, 141x the ratio's 2.1e5).
``deflection`` -- what the tip-deflection objective (seed eq. 28) measures at the shaft ends:
    ``total`` (default): the shaft-axis point's displacement, rigid-body motion and elastic
    deflection; ``frame``: the floating frame's point only (the rigid-body motion, all the
    simplified model has; the elastic shapes are pinned at the bearings, so this is the motion
    the bearings' compliance allows); ``elastic``: the elastic deflection ``A S q_f`` only (zero
    in the simplified model).
``deflection_reference`` -- eq. (28)'s ``X_st``, "the quasi-static solution with constant wind speed":
    ``static`` (default): the static equilibrium under the scene's mean loads, shaft not turning;
    ``mean``: the record's time mean, the turning shaft's steady state under those loads. They
    coincide in the physical reading (0.06 mm apart at 11 m/s) but not under the printed Rayleigh
    law: a stiffness-proportional damping that turns with the shaft adds ``Omega delta K`` of
    cross stiffness (Omega delta = 4 at 11 m/s), which turns and shrinks the gravity sag of the
    running shaft, so the static reference is 3.3 mm off the running shaft's mean position.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from ddgsa.errors import ModelError, with_hint

BENDING_RAYLEIGH = ("physical", "printed")
BEARING_DAMPING = ("modal", "stiffness_proportional")
DEFLECTION = ("total", "frame", "elastic")
DEFLECTION_REFERENCE = ("static", "mean")


def checked(option: str, value: object, allowed: Sequence[str]) -> str:
    """``value`` if it is one of ``allowed``, else a :class:`~ddgsa.errors.ModelError` naming the option."""
    if value not in allowed:
        raise ModelError(with_hint(f"model 'direct_drive': option {option!r} must be one of {', '.join(allowed)}; "
                                   f"got {value!r}", value, allowed))
    return str(value)


def rayleigh_coefficients(w1: float, w2: float, zeta: float, reading: str) -> tuple[float, float]:
    """``(eta, delta)`` of ``C = eta M + delta K`` through the bending frequencies ``w1, w2`` [rad/s].

    ``eta`` [1/s] is seed eq. (44b) in both readings; ``delta`` [s] is ``2 zeta / (w1 + w2)``
    (``physical``) or eq. (44a) as printed, ``2 zeta (w1 + w2)`` (``printed``). ``zeta`` [-].
    """
    eta = 2.0 * zeta * w1 * w2 / (w1 + w2)
    delta = 2.0 * zeta / (w1 + w2) if checked("bending_rayleigh", reading, BENDING_RAYLEIGH) == "physical" \
        else 2.0 * zeta * (w1 + w2)
    return eta, delta


def bending_damping(fields: Sequence[str], m_ff: NDArray[np.float64], k_ff: NDArray[np.float64],
                    damping: NDArray[np.float64], w1: float, w2: float, zeta: float,
                    reading: str) -> NDArray[np.float64]:
    """``damping`` (n_f, n_f) with its bending block set to ``eta M + delta K`` of ``reading``
    (:func:`rayleigh_coefficients`); ``m_ff``, ``k_ff`` the elastic mass [kg] and stiffness [N/m]
    of the ``fields``; axial and torsion entries kept (seed eq. 43b-c: the same in both readings)."""
    eta, delta = rayleigh_coefficients(w1, w2, zeta, reading)
    out = np.array(damping, dtype=float)
    bend = [i for i, f in enumerate(fields) if f.startswith("bending")]
    ix = np.ix_(bend, bend)
    out[ix] = eta * m_ff[ix] + delta * k_ff[ix]
    return out


def bearing_damping(k: NDArray[np.float64], mass: float, zeta: float, reading: str) -> NDArray[np.float64]:
    """Bearing damper coefficients [N s/m] for stiffnesses ``k`` [N/m]: ``2 zeta sqrt(k mass / 2)``
    (``modal``, zeta [-], ``mass`` [kg] the supported mass shared by two bearings) or ``zeta k``
    (``stiffness_proportional``, zeta [s])."""
    if checked("bearing_damping", reading, BEARING_DAMPING) == "modal":
        return 2.0 * zeta * np.sqrt(np.asarray(k, dtype=float) * mass / 2.0)
    return zeta * np.asarray(k, dtype=float)

