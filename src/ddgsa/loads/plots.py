"""Figures of the loads: steady curves, spectra against Kaimal, a hub-load sample."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd
from scipy import signal

from ddgsa.loads.rotor import NREL5MW, Turbine
from ddgsa.loads.scene import Scene
from ddgsa.loads.turbulence import IecTurbulence, generate_field

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure


def steady_curves(turbine: Turbine = NREL5MW, winds: np.ndarray | None = None) -> pd.DataFrame:
    """Steady operating points over wind speed [m/s]: one row per wind speed."""
    winds = np.arange(3.5, 25.01, 0.25) if winds is None else winds
    return pd.DataFrame([turbine.steady_state(float(v)) for v in winds], index=pd.Index(winds, name="wind_speed"))


def plot_steady_curves(turbine: Turbine = NREL5MW) -> "Figure":
    """Power, thrust, torque, rotor speed and pitch against wind speed."""
    import matplotlib.pyplot as plt

    c = steady_curves(turbine)
    fig, axes = plt.subplots(2, 2, figsize=(9, 6), sharex=True)
    series = [("power", 1e-6, "power [MW]"), ("thrust", 1e-3, "thrust [kN]"),
              ("aero_torque", 1e-6, "aerodynamic torque [MN m]"), ("rotor_speed", 30 / np.pi, "rotor speed [rpm]")]
    for ax, (col, k, label) in zip(axes.ravel(), series):
        ax.plot(c.index, c[col] * k)
        ax.axvline(turbine.rated_wind_speed, color="0.6", ls="--", lw=0.8)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[1, 1].plot(c.index, np.rad2deg(c["pitch"]) * 0.5, color="tab:red", label="pitch / 2 [deg]")
    axes[1, 1].legend()
    for ax in axes[1]:
        ax.set_xlabel("hub wind speed [m/s]")
    fig.suptitle("Reference rotor (NREL 5-MW, direct drive): steady operation; dashed: rated wind")
    fig.tight_layout()
    return fig


def plot_spectra(wind_speed: float = 11.0, turbulence_intensity: float = 0.12, n_records: int = 8,
                 duration: float = 1200.0, dt: float = 0.1) -> "Figure":
    """Welch spectra of generated u, v, w at the hub against the Kaimal spectra."""
    import matplotlib.pyplot as plt

    model = IecTurbulence(wind_speed, turbulence_intensity, NREL5MW.hub_height)
    recs = np.stack([generate_field(np.zeros((1, 2)), model, duration, dt, s)[:, :, 0] for s in range(n_records)])
    f, p = signal.welch(recs, fs=1 / dt, nperseg=2048, axis=2)
    fig, ax = plt.subplots(figsize=(6, 4))
    for k, (name, color) in enumerate(zip("uvw", ("tab:blue", "tab:orange", "tab:green"))):
        ax.loglog(f[1:], p[:, k, 1:].mean(axis=0), color=color, alpha=0.6, label=f"{name} generated")
        ax.loglog(f[1:], model.spectra(f[1:])[k], color=color, ls="--", label=f"{name} Kaimal")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("PSD [m$^2$/s]")
    ax.set_title(f"IEC Kaimal turbulence, V = {wind_speed} m/s, I_ref = {turbulence_intensity}")
    ax.legend(ncol=2, fontsize=8)
    fig.tight_layout()
    return fig


def plot_hub_loads(loads: pd.DataFrame, seconds: float = 120.0) -> "Figure":
    """The first ``seconds`` of hub forces, moments, rotor speed and pitch."""
    import matplotlib.pyplot as plt

    part = loads[loads.index <= seconds]
    fig, axes = plt.subplots(4, 1, figsize=(8, 8), sharex=True)
    axes[0].plot(part.index, part["wind_hub"])
    axes[0].set_ylabel("hub wind [m/s]")
    for col in ("Fx", "Fy", "Fz"):
        axes[1].plot(part.index, part[col] * 1e-3, label=col)
    axes[1].set_ylabel("force [kN]")
    for col in ("Mx", "My", "Mz"):
        axes[2].plot(part.index, part[col] * 1e-6, label=col)
    axes[2].set_ylabel("moment [MN m]")
    axes[3].plot(part.index, part["rotor_speed"] * 30 / np.pi, label="rotor speed [rpm]")
    axes[3].plot(part.index, np.rad2deg(part["pitch"]), label="pitch [deg]")
    for ax in axes[1:]:
        ax.legend(ncol=3, fontsize=8)
    axes[-1].set_xlabel("time [s]")
    scene = loads.attrs.get("scene", {})
    fig.suptitle(f"Hub loads (shaft frame), V = {scene.get('wind_speed')} m/s, I_ref = "
                 f"{scene.get('turbulence_intensity')}, seed {scene.get('seed')}")
    fig.tight_layout()
    return fig


def write_figures(out: Path) -> list[Path]:
    """Write the three load figures and the steady-curve table into ``out``; returns the paths."""
    import matplotlib.pyplot as plt

    from ddgsa.loads import generate

    out.mkdir(parents=True, exist_ok=True)
    paths = [out / "steady_curves.png", out / "turbulence_spectra.png", out / "hub_loads_11ms.png",
             out / "steady_curves.csv"]
    figs = [plot_steady_curves(), plot_spectra(),
            plot_hub_loads(generate(Scene(wind_speed=11.0, turbulence_intensity=0.12, duration=600.0, seed=1)))]
    for fig, path in zip(figs, paths):
        fig.savefig(path, dpi=110)
        plt.close(fig)
    steady_curves().round(6).to_csv(paths[-1])
    return paths
