"""Readings of seed 000 where it is ambiguous: its shaft, damping laws and deflection objective.

Seed 000 (Asadi & Johansson 2020) admits two readings in five places; the direct drive
(:mod:`ddgsa.models.direct_drive`) takes each as a model option, the physical reading by default
(``docs/seed000_readings.md`` says why and what each changes):

``bending_rayleigh`` -- the shaft's bending damping ``C_b = eta M_b + delta K_b`` (seed eq. 43a):
    ``physical`` (default): ``delta = 2 zeta / (w1 + w2)``, ``eta = 2 zeta w1 w2 / (w1 + w2)``, the
    Rayleigh pair that gives ratio ``zeta`` at the first two bending frequencies ``w1, w2``;
    ``printed``: eq. (44a) as printed, ``delta = 2 zeta (w1 + w2)`` [s] (eq. 44b's ``eta`` is the
    physical one). With zeta = 0.01 and the ``table2`` shaft (FE bending frequencies 3.28 and
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

from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from ddgsa.errors import ModelError, with_hint
from ddgsa.mbs.beam import BeamSpec, mesh

SHAFT = ("table1", "table2")
TABLE1_HZ = {"bending": (6.0816, 29.5397), "axial": (127.8008, 462.4371), "torsion": (37.8392, 266.7413)}
"""Seed 000 Table 1's FE eigenfrequencies [Hz], first and second mode of each family."""
TABLE1_STEEL = (200e9, 0.3, 7850.0)
"""Young's modulus [Pa], Poisson's ratio [-] and density [kg/m^3] of the ``table1`` shaft (handbook steel;
Table 1's own elongation wavenumber 0.1591 1/m at 127.8 Hz gives sqrt(E / rho) = 5047 m/s, E / rho of this steel)."""
TABLE1_DISC_RADII = (7.0, 0.5)
"""Hub and generator-rotor disc radii R1, R2 [m] (seed Table 2) of the ``table1`` end inertias."""
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



def table1_shaft(radius: float, length: float, hub_mass: float, generator_mass: float) -> dict[str, float]:
    """The direct drive's parameters that the ``table1`` shaft reading sets (module notes).

    Parameters
    ----------
    radius : float
        Shaft radius R_ms [m] (solid section).
    length : float
        Shaft length L [m].
    hub_mass, generator_mass : float
        End masses m1, m2 [kg], thin discs of radii :data:`TABLE1_DISC_RADII`.

    Returns
    -------
    dict
        ``shaft_mass`` [kg], ``shaft_bending_stiffness`` EI and ``shaft_torsional_stiffness`` GJ
        [N m^2], ``shaft_axial_stiffness`` EA [N], and the hub's and generator's polar (``_x``) and
        diametral (``_yz``) inertias [kg m^2].

    Examples
    --------
    >>> p = table1_shaft(0.3258, 6.0, 40000.0, 30000.0)
    >>> round(p["shaft_mass"]), f"{p['shaft_bending_stiffness']:.3g}", p["hub_inertia_x"]
    (15706, '1.77e+09', 980000.0)
    """
    young, poisson, density = TABLE1_STEEL
    area, second_moment = np.pi * radius ** 2, np.pi * radius ** 4 / 4.0
    out = {"shaft_mass": density * area * length, "shaft_bending_stiffness": young * second_moment,
           "shaft_torsional_stiffness": young / (2.0 * (1.0 + poisson)) * 2.0 * second_moment,
           "shaft_axial_stiffness": young * area}
    for end, mass, disc in zip(("hub", "generator"), (hub_mass, generator_mass), TABLE1_DISC_RADII):
        out[f"{end}_inertia_x"] = mass * disc ** 2 / 2.0
        out[f"{end}_inertia_yz"] = mass * disc ** 2 / 4.0
    return {k: float(v) for k, v in out.items()}


def table1_spec(p: Mapping[str, float], axial_spring: float | None, element: float = 0.05) -> BeamSpec:
    """Seed 000 Table 1's FE problem for the direct drive's parameters ``p`` (SI; the ``table1`` reading's
    reproduce the table): the solid shaft (polar inertia ``m r^2 / 2``) with the hub and generator as end
    masses and inertias, bending on rigid supports at the bearings, torsion free-free, elongation free on
    the front bearing's axial spring ``axial_spring`` [N/m] (``None``: held at the front bearing), elements
    of at most ``element`` [m]; its modes: :func:`ddgsa.mbs.beam.shaft_modes`."""
    length, l1, l2 = p["shaft_length"], p["front_bearing_x"], p["rear_bearing_x"]
    ends = tuple((x, p[f"{end}_mass"], p[f"{end}_inertia_x"], p[f"{end}_inertia_yz"])
                 for x, end in ((0.0, "hub"), (length, "generator")))
    return BeamSpec(nodes=mesh([0.0, l1, l2, length], element), mass=p["shaft_mass"],
                    polar_inertia=p["shaft_mass"] * p["shaft_radius"] ** 2 / 2.0, EI=p["shaft_bending_stiffness"],
                    EA=p["shaft_axial_stiffness"], GJ=p["shaft_torsional_stiffness"], end_masses=ends,
                    supports=(l1, l2), axial_support=l1, axial_spring=axial_spring)
