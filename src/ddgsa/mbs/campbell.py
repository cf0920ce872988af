"""Campbell diagrams: modes of a spinning constrained system against rotor speed.

At each speed the system is linearised about steady spin (gyroscopic terms in the damping
matrix, :func:`ddgsa.mbs.modal.linearise_system`) and its damped modes are computed on the null
space of the constraint Jacobian. Each mode's **whirl** is read from its shape: the orbit of every
body's centre ``(y, z)`` and of its axis tip ``(theta, psi)`` turns with the spin (forward) or
against it (backward); orbits are weighted by their share of the mode's kinetic energy.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.modal import damped_eigen, linearise_system

if TYPE_CHECKING:
    from ddgsa.mbs.assembly import System

Array = NDArray[np.float64]


@dataclass(frozen=True)
class CampbellDiagram:
    """Modes against rotor speed.

    Attributes
    ----------
    frame : DataFrame
        One row per (speed, mode): ``speed_rad_s``, ``speed_rpm``, ``mode`` (rank by frequency,
        from 1), ``frequency_hz``, ``damping_ratio``, ``whirl`` (forward, backward, mixed; none for modes without lateral motion, standstill at zero speed),
        ``whirl_index`` (+1 circular forward ... -1 circular backward), ``label``.
    orders : tuple of float
        Excitation orders drawn as lines ``f = n speed / 2 pi`` (1P, 3P, ...).
    """

    frame: pd.DataFrame
    orders: tuple[float, ...] = (1.0,)

    def to_frame(self) -> pd.DataFrame:
        """The table (a copy)."""
        return self.frame.copy()

    def crossings(self, order: float = 1.0) -> pd.DataFrame:
        """Speeds where a mode meets the order line ``f = order * speed / 2 pi`` (linear interpolation).

        Returns
        -------
        DataFrame
            ``mode``, ``speed_rad_s``, ``speed_rpm``, ``frequency_hz``, ``whirl`` per crossing.
        """
        rows = []
        for mode, grp in self.frame.groupby("mode"):
            grp = grp.sort_values("speed_rad_s")
            w = grp["speed_rad_s"].to_numpy()
            gap = grp["frequency_hz"].to_numpy() - order * w / (2 * np.pi)
            for i in np.nonzero(np.sign(gap[:-1]) * np.sign(gap[1:]) <= 0)[0]:
                if gap[i] == gap[i + 1]:
                    continue
                s = gap[i] / (gap[i] - gap[i + 1])
                speed = w[i] + s * (w[i + 1] - w[i])
                rows.append({"mode": int(mode), "speed_rad_s": speed, "speed_rpm": speed * 30 / np.pi,
                             "frequency_hz": order * speed / (2 * np.pi), "whirl": grp["whirl"].iloc[i]})
        return pd.DataFrame(rows, columns=["mode", "speed_rad_s", "speed_rpm", "frequency_hz", "whirl"])

    def plot(self, ax: Any = None, max_frequency_hz: float | None = None) -> Any:
        """Frequencies against speed [rpm] per mode (forward solid, backward dashed) with the order lines.

        Returns the matplotlib ``Axes``; the library never shows the figure.
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(7, 4.5))
        fr = self.frame
        for mode, grp in fr.groupby("mode"):
            grp = grp.sort_values("speed_rad_s")
            whirl = grp["whirl"].mode().iloc[0]
            style = {"forward": "-", "backward": "--"}.get(whirl, ":")
            ax.plot(grp["speed_rpm"], grp["frequency_hz"], style, marker=".", label=f"{mode}: {grp['label'].iloc[0]}"
                    f" ({whirl})")
        rpm = np.array([fr["speed_rpm"].min(), fr["speed_rpm"].max()])
        for n in self.orders:
            ax.plot(rpm, n * rpm / 60.0, color="0.5", lw=0.8)
            ax.annotate(f"{n:g}P", (rpm[1], n * rpm[1] / 60.0), fontsize=8, color="0.4")
        top = max_frequency_hz if max_frequency_hz is not None else 1.1 * fr["frequency_hz"].max()
        ax.set_ylim(0.0, top)
        ax.set_xlabel("rotor speed [rpm]")
        ax.set_ylabel("frequency [Hz]")
        ax.set_title("Campbell diagram")
        ax.legend(fontsize=7, loc="upper left")
        return ax


def whirl_index(system: "System", shape: NDArray[np.complex128], m_full: Array) -> tuple[float, float]:
    """Energy-weighted orbit direction of a mode shape about +x, and the lateral share of its energy.

    For each body the pairs ``(y, z)`` and ``(ry, rz)`` orbit with direction
    ``2 Im(Y conj(Z)) / (|Y|^2 + |Z|^2)`` (+1: circular, counter-clockwise about +x); the index is
    their average weighted by kinetic energy.
    """
    pairs = []
    for b in system.bodies:
        for cy, cz in (("y", "z"), ("ry", "rz")):
            try:
                pairs.append((system.index(f"{b.name}.{cy}"), system.index(f"{b.name}.{cz}")))
            except ModelError:
                continue
    return orbit_average(shape, np.abs(shape) ** 2 * np.diag(m_full), pairs)


def orbit_average(shape: NDArray[np.complex128], energy: Array,
                  pairs: Sequence[tuple[int, int]]) -> tuple[float, float]:
    """Orbit direction ``2 Im(Y conj(Z)) / (|Y|^2 + |Z|^2)`` of the coordinate ``pairs`` of ``shape``,
    averaged with the pairs' kinetic ``energy`` [J, any common scale] as weights, and the pairs' share
    of the total energy."""
    num = den = 0.0
    for iy, iz in pairs:
        amp = abs(shape[iy]) ** 2 + abs(shape[iz]) ** 2
        if amp == 0.0:
            continue
        w = energy[iy] + energy[iz]
        num += w * 2.0 * float(np.imag(shape[iy] * np.conj(shape[iz]))) / amp
        den += w
    total = energy.sum()
    return (num / den if den > 0 else 0.0), (den / total if total > 0 else 0.0)


def campbell(system: "System", speeds: ArrayLike, spin: str, q0: Array | None = None,
             orders: Sequence[float] = (1.0, 3.0), n_modes: int | None = None) -> CampbellDiagram:
    """Campbell diagram of ``system`` with coordinate ``spin`` turning at each of ``speeds`` [rad/s].

    Parameters
    ----------
    spin : str
        The driving spin coordinate, e.g. ``"rotor.rx"``; the other rates follow from the
        constraints (:meth:`System.consistent_state` holding this one).
    q0 : ndarray, optional
        Operating pose (default the system's initial pose).
    orders : sequence of float
        Excitation orders for the plot and :meth:`CampbellDiagram.crossings`.
    n_modes : int, optional
        Keep the lowest ``n_modes`` modes at each speed.
    """
    from ddgsa.mbs.modal import modal_analysis

    idx = system.index(spin)
    rows = []
    for speed in np.asarray(speeds, dtype=float):
        qd = np.zeros(system.n)
        qd[idx] = speed
        q, qd = system.consistent_state(q0, qd, keep=[idx])
        lin = linearise_system(system, q, qd)
        lam, vec = damped_eigen(lin.m, lin.c, lin.k)
        labels = modal_analysis(lin.m, lin.c, lin.k, system.coord_names, system.groups(), lin.basis,
                                lin.m_full)["label"].to_numpy()
        shapes = lin.basis @ vec
        count = lam.size if n_modes is None else min(n_modes, lam.size)
        for j in range(count):
            rows.append(mode_row(speed, j + 1, lam[j], *whirl_index(system, shapes[:, j], lin.m_full), labels[j]))
    return CampbellDiagram(pd.DataFrame(rows), tuple(float(o) for o in orders))


def mode_row(speed: float, mode: int, eigenvalue: complex, index: float, lateral: float, label: str) -> dict[str, Any]:
    """One row of a Campbell table: the damped mode ``eigenvalue`` [1/s] at ``speed`` [rad/s], its whirl
    from the orbit ``index`` and the ``lateral`` share of its energy (:func:`whirl_index`): ``none``
    below 1 % lateral energy, ``standstill`` at zero speed, else ``forward`` / ``backward`` beyond
    +-0.5 (signed with the spin) and ``mixed`` between."""
    signed = index * np.sign(speed)
    whirl = ("none" if lateral < 0.01 else "standstill" if speed == 0 else "forward" if signed > 0.5
             else "backward" if signed < -0.5 else "mixed")
    return {"speed_rad_s": float(speed), "speed_rpm": float(speed) * 30.0 / np.pi, "mode": mode,
            "frequency_hz": float(abs(eigenvalue) / (2 * np.pi)),
            "damping_ratio": float(-eigenvalue.real / abs(eigenvalue)), "whirl": whirl,
            "whirl_index": float(index), "label": label}


def campbell_from_tables(tables: dict[float, pd.DataFrame], orders: Sequence[float] = (1.0, 3.0)) -> CampbellDiagram:
    """A Campbell diagram from mode tables computed at each speed [rad/s] by other means (a model's ``modes``).

    The tables need ``frequency_hz``, ``damping_ratio`` and ``label``; whirl is not known there
    (``whirl`` is ``"unknown"``).
    """
    rows = []
    for speed, table in sorted(tables.items()):
        tab = table.sort_values("frequency_hz").reset_index(drop=True)
        for j, row in tab.iterrows():
            rows.append({"speed_rad_s": float(speed), "speed_rpm": float(speed) * 30.0 / np.pi, "mode": int(j) + 1,
                         "frequency_hz": float(row["frequency_hz"]), "damping_ratio": float(row["damping_ratio"]),
                         "whirl": "unknown", "whirl_index": np.nan, "label": row["label"]})
    return CampbellDiagram(pd.DataFrame(rows), tuple(float(o) for o in orders))
