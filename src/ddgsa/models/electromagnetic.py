"""Quasi-static radial magnetic pull of a surface-PM generator: the sector model of seed 003 §2.2.1.

Field model (stated, not taken from the seed, which cites Jaen-Sola 2017 without its equations):

* The air gap is cut into ``N`` sectors of width ``beta = 2 pi / N`` centred at
  ``theta_i = beta/2 + i beta``. With the rotor displaced by the eccentricity vector
  ``e = (e_y, e_z)`` the local mechanical gap is ``delta_i = g - e . n_i`` (``n_i`` the unit
  radial vector of sector ``i``; seed Eq. 1 with zero mean eccentricity: ``delta = delta_0 - eps sin theta``).
* A surface-mounted magnet of height ``h_m`` and relative permeability ``mu_r`` is part of the
  magnetic gap, so the flux density under a pole is ``B = B_r h_m / (h_m + mu_r k_C delta)``
  (``k_C`` Carter's factor for stator slotting; 1 for a smooth stator).
* Magnets cover the pole-arc fraction ``alpha_p`` of the circumference and the field between
  them is neglected, so the mean Maxwell pressure is ``p = alpha_p B^2 / (2 mu_0)``.
* Each sector pulls the rotor towards the stator across its own gap with ``p(delta_i) R L beta``;
  the forces are resolved into y and z and summed (seed: "split into the global y and z
  components ... summed ... combined to the resulting single radial force").

Armature reaction, slot harmonics and rotation are not modelled (quasi-static, open-circuit
field). The net force points towards the smallest gap, i.e. along ``e``: a negative stiffness.
Its slope at zero eccentricity is, in closed form (``sum cos^2 theta_i beta = pi`` for ``N >= 3``),

``k_mag = pi R L alpha_p k_C B0^2 / (mu_0 (h_m / mu_r + k_C g))``

which :func:`linear_stiffness` returns. With the IEA 15 MW values (seed 003 Table 2 and the
public design data: ``h_m`` = 0.1 m, ``alpha_p`` = 0.8) that is 0.28 GN/m; the mechanical gap
alone (``h_m -> 0`` at the same ``B0``) would give ``pi R L alpha_p B0^2 / (mu_0 g)`` = 2.9 GN/m.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.machines import MU_0, air_gap_pull

__all__ = ["MU_0", "PMGenerator", "linear_stiffness", "pull_jacobian", "pull_vector", "radial_pull"]



@dataclass(frozen=True)
class PMGenerator:
    """Air-gap data of a surface-PM radial-flux generator (defaults: IEA 15 MW RWT, seed 003 Table 2).

    Attributes
    ----------
    air_gap_radius : float
        Air-gap radius R [m] (5.08).
    core_length : float
        Active (stack) length L [m] (2.17).
    air_gap : float
        Mechanical air gap g at zero eccentricity [m] (0.010).
    magnet_remanence : float
        Remanent flux density B_r [T] (1.28).
    relative_permeability : float
        Magnet recoil permeability mu_r [-] (1.06).
    magnet_height : float
        Radial magnet height h_m [m] (0.1; IEA 15 MW public design data, not in seed Table 2).
    pole_arc_ratio : float
        Magnet arc / pole pitch alpha_p [-] (0.8; public design data).
    carter_factor : float
        Carter's factor k_C [-] (1.0: smooth stator; the slot opening is not in Table 2).
    sectors : int
        Number of sectors N (200, one per pole as in the seed).
    """

    air_gap_radius: float = 5.08
    core_length: float = 2.17
    air_gap: float = 0.010
    magnet_remanence: float = 1.28
    relative_permeability: float = 1.06
    magnet_height: float = 0.1
    pole_arc_ratio: float = 0.8
    carter_factor: float = 1.0
    sectors: int = 200

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ModelError(f"generator field {f.name!r} must be a positive number, got {value!r}")
        if self.sectors < 3 or int(self.sectors) != self.sectors:
            raise ModelError(f"generator field 'sectors' must be an integer >= 3, got {self.sectors!r}")
        if self.pole_arc_ratio > 1:
            raise ModelError(f"generator field 'pole_arc_ratio' must be in (0, 1], got {self.pole_arc_ratio}")

    def updated(self, values: Mapping[str, float] | None) -> "PMGenerator":
        """A copy with the named fields replaced (unknown names are ignored: model parameters pass through)."""
        if not values:
            return self
        names = {f.name for f in fields(self)}
        changes: dict[str, Any] = {k: v for k, v in values.items() if k in names}
        return replace(self, **changes)

    @property
    def constants(self) -> NDArray[np.float64]:
        """The air gap's constants for the kernel's compiled pull (:func:`ddgsa.mbs.machines.air_gap_pull`)."""
        beta = 2 * math.pi / self.sectors
        return np.array([self.air_gap, self.magnet_height / self.relative_permeability, self.carter_factor,
                         self.magnet_remanence, self.pole_arc_ratio, self.air_gap_radius * self.core_length * beta,
                         float(self.sectors)])

    @property
    def magnetic_gap(self) -> float:
        """Effective gap ``h_m / mu_r + k_C g`` at zero eccentricity [m]."""
        return self.magnet_height / self.relative_permeability + self.carter_factor * self.air_gap

    def flux_density(self, gap: ArrayLike) -> NDArray[np.float64]:
        """Air-gap flux density under a pole [T] for the local mechanical gap ``gap`` [m]."""
        hm = self.magnet_height / self.relative_permeability
        return self.magnet_remanence * hm / (hm + self.carter_factor * np.asarray(gap, dtype=float))


def pull_vector(ecc_y: ArrayLike, ecc_z: ArrayLike, gen: PMGenerator = PMGenerator()) -> NDArray[np.float64]:
    """Net magnetic force on the rotor [N], components (y, z), for eccentricities ``(ecc_y, ecc_z)`` [m].

    Broadcasts over the eccentricity arrays; the result has their shape plus a last axis of 2.

    Raises
    ------
    ValueError
        Where the eccentricity closes the gap (``|e| >= g``): the model has no meaning there.
    """
    ey, ez = np.broadcast_arrays(np.asarray(ecc_y, dtype=float), np.asarray(ecc_z, dtype=float))
    if np.any(np.hypot(ey, ez) >= gen.air_gap):
        raise ValueError(f"eccentricity {float(np.max(np.hypot(ey, ez))):.4g} m closes the "
                         f"{gen.air_gap} m air gap")
    c = gen.constants
    return np.array([air_gap_pull(c, y, z)[0] for y, z in zip(ey.ravel(), ez.ravel())]).reshape(*ey.shape, 2)


def radial_pull(eccentricity: ArrayLike, gen: PMGenerator = PMGenerator()) -> NDArray[np.float64]:
    """Net radial force [N] towards the smallest gap for a radial eccentricity ``eccentricity`` [m].

    The rotor is displaced along z (any direction gives the same magnitude up to the sector
    discretisation, which the residual at zero eccentricity measures: < 1e-6 N for N = 200).
    """
    e = np.asarray(eccentricity, dtype=float)
    return pull_vector(np.zeros_like(e), e, gen)[..., 1]


def linear_stiffness(gen: PMGenerator = PMGenerator()) -> float:
    """Slope of the net pull at zero eccentricity [N/m] (closed form, see the module)."""
    b0 = float(gen.flux_density(gen.air_gap))
    return (math.pi * gen.air_gap_radius * gen.core_length * gen.pole_arc_ratio * gen.carter_factor * b0 ** 2
            / (MU_0 * gen.magnetic_gap))


def pull_jacobian(ecc_y: float, ecc_z: float, gen: PMGenerator = PMGenerator()) -> NDArray[np.float64]:
    """``d(F_y, F_z)/d(e_y, e_z)`` [N/m] of :func:`pull_vector` at one eccentricity (analytic)."""
    return air_gap_pull(gen.constants, float(ecc_y), float(ecc_z))[1]
