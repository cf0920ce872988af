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
        One row per (speed, mode): ``speed_rad_s``, ``speed_rpm``, ``mode`` (the branch, followed
        across speeds by its mode shape, :func:`track`; numbered from 1 by frequency at the first
        speed) -- or the rank by frequency at each speed where no shapes are known
        (:func:`campbell_from_tables`), ``frequency_hz``, ``damping_ratio``, ``whirl`` (forward, backward, mixed; none for modes without lateral motion, standstill at zero speed),
        ``whirl_index`` (+1 circular forward ... -1 circular backward), ``label``.
    orders : tuple of float
        Excitation orders drawn as lines ``f = n speed / 2 pi`` (1P, 3P, ...).
    band_hz : float
        The band the diagram was computed for [Hz]: its modes are those below it (``inf``: every mode
        the model has).
    """

    frame: pd.DataFrame
    orders: tuple[float, ...] = (1.0,)
    band_hz: float = float("inf")

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
        """Frequencies against speed [rpm] per mode (forward solid, backward dashed, mixed or not
        known solid) with the order lines labelled inside the axes and the legend outside them.

        The frequency axis ends (unless ``max_frequency_hz``) 12 % above the highest mode of a diagram
        computed for a finite band (:attr:`band_hz`: the model chose which modes matter), else at the
        larger of 1.5 times the highest order line and the lowest mode's highest frequency plus 10 %,
        so the order lines and their crossings fill the plot; modes above it are counted in the title.
        Colours run through the ten hues of a 20-colour map before its lighter shades, so up to 20 modes have distinct colours.

        Returns the matplotlib ``Axes``; the library never shows the figure.
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(8.5, 4.5))
        fr = self.frame
        rpm = np.array([fr["speed_rpm"].min(), fr["speed_rpm"].max()])
        order_top = max(self.orders, default=1.0) * rpm[1] / 60.0
        lowest = fr.groupby("mode")["frequency_hz"].max().min()
        peak = fr["frequency_hz"].max()
        if max_frequency_hz is not None:
            top = max_frequency_hz
        elif np.isfinite(self.band_hz):
            top = 1.12 * peak
        else:
            top = min(max(1.5 * order_top, 1.1 * lowest), 1.05 * peak)
        colours = plt.get_cmap("tab20")
        hidden = 0
        for k, (mode, grp) in enumerate(fr.groupby("mode")):
            grp = grp.sort_values("speed_rad_s")
            if grp["frequency_hz"].min() > top:
                hidden += 1
                continue
            moving = grp.loc[grp["speed_rad_s"] > 0, "whirl"]
            whirl = (moving if len(moving) else grp["whirl"]).mode().iloc[0]
            style = {"forward": "-", "backward": "--"}.get(whirl, "-")
            known = whirl in ("forward", "backward", "mixed")
            ax.plot(grp["speed_rpm"], grp["frequency_hz"], style, marker=".", color=colours((2 * k) % 20 + (k // 10) % 2),
                    label=f"{mode}: {grp['label'].iloc[0]}" + (f" ({whirl})" if known else ""))
        for n in self.orders:
            ax.plot(rpm, n * rpm / 60.0, color="0.5", lw=0.8)
            x = min(rpm[1], 0.95 * top * 60.0 / n)               # where the line leaves the axes, inside
            ax.annotate(f"{n:g}P", (x, n * x / 60.0), xytext=(-4, 2), textcoords="offset points", ha="right",
                        va="bottom", fontsize=8, color="0.3")
        ax.set_xlim(rpm[0], rpm[1])
        ax.set_ylim(0.0, top)
        ax.set_xlabel("rotor speed [rpm]")
        ax.set_ylabel("frequency [Hz]")
        ax.set_title("Campbell diagram" + (f" ({hidden} modes above {top:.3g} Hz not shown)" if hidden else ""),
                     fontsize=9)
        if not (fr["whirl"].isin(["forward", "backward", "mixed"])).any():
            ax.text(0.01, 0.98, "whirl not known: modes from tables", transform=ax.transAxes, fontsize=7,
                    va="top", color="0.4")
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
        ax.figure.tight_layout()
        return ax


def whirl_index(system: "System", shape: NDArray[np.complex128], m_full: Array) -> tuple[float, float]:
    """Energy-weighted orbit direction of a mode shape about +x, and the lateral share of its energy.

    For each body the pairs ``(y, z)`` and ``(ry, rz)`` orbit with direction
    ``2 Im(Y conj(Z)) / (|Y|^2 + |Z|^2)`` (+1: circular, counter-clockwise about +x); the index is
    their average weighted by kinetic energy.
    """
    return orbit_average(shape, np.abs(shape) ** 2 * np.diag(m_full), orbit_pairs(system))


def orbit_pairs(system: "System") -> list[tuple[int, int]]:
    """Indices of every body's lateral ``(y, z)`` and tilt ``(ry, rz)`` coordinate pairs (those it has)."""
    pairs = []
    for b in system.bodies:
        for cy, cz in (("y", "z"), ("ry", "rz")):
            names = (f"{b.name}.{cy}", f"{b.name}.{cz}")
            if all(n in system.coord_names for n in names):
                pairs.append((system.index(names[0]), system.index(names[1])))
    return pairs


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


def mac(a: NDArray[np.complex128], b: NDArray[np.complex128]) -> Array:
    """Modal assurance criterion ``|a_i^H b_j|^2 / ((a_i^H a_i)(b_j^H b_j))`` between the columns of
    two complex shape matrices (n, m_a) and (n, m_b): (m_a, m_b), 1 for the same shape, 0 for orthogonal."""
    num = np.abs(a.conj().T @ b) ** 2
    den = np.outer(np.sum(np.abs(a) ** 2, axis=0), np.sum(np.abs(b) ** 2, axis=0))
    return np.divide(num, den, out=np.zeros_like(num), where=den > 0)


def track(shapes: Sequence[NDArray[np.complex128]]) -> list[NDArray[np.int_]]:
    """Branches of modes across a sequence of speeds, followed by their mode shapes.

    Speed ``k + 1``'s modes are matched one to one with speed ``k``'s by the assignment that
    maximises the summed modal assurance criterion (:func:`mac`; Hungarian algorithm), i.e.
    eigenvector continuation: a branch keeps its identity where it crosses another one in
    frequency (the shapes stay distinct), where ranking by frequency swaps the names. Modes
    of a degenerate pair (equal frequencies, shapes any mix) may swap within the pair, which
    no frequency or shape can tell apart.

    Parameters
    ----------
    shapes : sequence of (n, m_k) complex arrays
        Mode shapes at each speed, in the same coordinates (columns: modes).

    Returns
    -------
    list of (m_k,) int arrays
        The branch of each mode at each speed; branches are numbered from 0 in the order of the
        first speed's modes, and a mode with no partner at the previous speed (more modes there)
        opens a new branch.
    """
    from scipy.optimize import linear_sum_assignment

    if not shapes:
        return []
    out = [np.arange(shapes[0].shape[1])]
    fresh = shapes[0].shape[1]
    for prev, cur in zip(shapes[:-1], shapes[1:]):
        rows, cols = linear_sum_assignment(-mac(prev, cur))
        branch = np.full(cur.shape[1], -1)
        branch[cols] = out[-1][rows]
        for j in np.nonzero(branch < 0)[0]:
            branch[j], fresh = fresh, fresh + 1
        out.append(branch)
    return out


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
        Keep the ``n_modes`` branches lowest at the first speed (followed by shape, :func:`track`).
    """
    from ddgsa.mbs.modal import modal_analysis

    idx = system.index(spin)
    per_speed = []
    for speed in np.sort(np.asarray(speeds, dtype=float)):
        qd = np.zeros(system.n)
        qd[idx] = speed
        q, qd = system.consistent_state(q0, qd, keep=[idx])
        lin = linearise_system(system, q, qd)
        lam, vec = damped_eigen(lin.m, lin.c, lin.k)
        labels = modal_analysis(lin.m, lin.c, lin.k, system.coord_names, system.groups(), lin.basis,
                                lin.m_full)["label"].to_numpy()
        shapes = lin.basis @ vec
        rows = [mode_row(speed, j + 1, lam[j], *whirl_index(system, shapes[:, j], lin.m_full), labels[j])
                for j in range(lam.size)]
        per_speed.append((rows, shapes))
    frame = tracked_frame(per_speed)
    if n_modes is not None:
        frame = frame[frame["mode"] <= n_modes].reset_index(drop=True)
    return CampbellDiagram(frame, tuple(float(o) for o in orders))


def tracked_frame(per_speed: Sequence[tuple[list[dict[str, Any]], NDArray[np.complex128]]]) -> pd.DataFrame:
    """A Campbell table whose ``mode`` is the branch (:func:`track`), not the rank at each speed.

    ``per_speed``: for each speed in increasing order, its rows (:func:`mode_row`, one per mode, in
    the order of the shape columns) and its mode shapes (n, m). Branches are numbered from 1 by
    their frequency rank at the first speed (a branch opened later comes after them); a branch's
    ``label`` is its label at the first speed it appears (labels read from a shape at each speed
    change name where a mode changes character)."""
    branches = track([shapes for _, shapes in per_speed])
    rows = []
    for (speed_rows, _), branch in zip(per_speed, branches):
        for row, b in zip(speed_rows, branch):
            rows.append({**row, "mode": int(b)})
    frame = pd.DataFrame(rows)
    first = frame.groupby("mode", sort=False).first()
    start = frame.groupby("mode")["speed_rad_s"].transform("min")
    opening = frame[frame["speed_rad_s"] == start].sort_values(["speed_rad_s", "frequency_hz"])["mode"]
    rank = {int(b): i + 1 for i, b in enumerate(opening)}
    frame["label"] = frame["mode"].map(first["label"])
    frame["mode"] = frame["mode"].map(rank)
    return frame.sort_values(["speed_rad_s", "frequency_hz"]).reset_index(drop=True)


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


def campbell_from_tables(tables: dict[float, pd.DataFrame], orders: Sequence[float] = (1.0, 3.0),
                         band_hz: float = float("inf")) -> CampbellDiagram:
    """A Campbell diagram from mode tables computed at each speed [rad/s] by other means (a model's ``modes``).

    The tables need ``frequency_hz``, ``damping_ratio`` and ``label``; whirl is not known there
    (``whirl`` is ``"unknown"``). ``band_hz``: the band the tables were cut to [Hz] (:attr:`CampbellDiagram.band_hz`).
    """
    rows = []
    for speed, table in sorted(tables.items()):
        tab = table.sort_values("frequency_hz").reset_index(drop=True)
        for j, row in tab.iterrows():
            rows.append({"speed_rad_s": float(speed), "speed_rpm": float(speed) * 30.0 / np.pi, "mode": int(j) + 1,
                         "frequency_hz": float(row["frequency_hz"]), "damping_ratio": float(row["damping_ratio"]),
                         "whirl": "unknown", "whirl_index": np.nan, "label": row["label"]})
    return CampbellDiagram(pd.DataFrame(rows), tuple(float(o) for o in orders), float(band_hz))
