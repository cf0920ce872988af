"""Wind and rotor loads for a scene: IEC turbulence, shear, inclination, rotor and control.

``generate(scene)`` returns the hub-load time series the drive-train models take (see
:mod:`ddgsa.loads.hubloads` for the frame). Realisations are pure functions of the scene
(its seed included) and are cached in memory, so every parameter point of a scene sees the
same loads (common random numbers); :func:`ddgsa.loads.cache.set_directory` also shares them
between processes through files (each realisation generated once per study).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pandas as pd

from ddgsa.loads import cache
from ddgsa.loads.bem import simulate_bem
from ddgsa.loads.hubloads import LOAD_COLUMNS, grid_points, inflow_in_shaft_frame, simulate_rotor
from ddgsa.loads.rotor import IEA15MW, NREL5MW, ROTORS, PerformanceTable, Turbine
from ddgsa.loads.scene import Scene, max_time_step
from ddgsa.loads.turbulence import IecTurbulence, generate_field

__all__ = ["C_GEN_DEFAULT", "EXCITATION_FACTORS", "IEA15MW", "LOAD_COLUMNS", "NREL5MW", "PerformanceTable", "ROTORS",
           "Scene", "Turbine", "apply_excitation", "generate", "generate_columns", "max_time_step", "wind_field"]

#: seed 000 eq. (25): generator torque constant C_gen [N m s/rad]
C_GEN_DEFAULT = 828.26e3
#: spin-up discarded before the record (the field is periodic, so it wraps around) [s]
SPINUP_S = 30.0
#: excitation parameters (seed 001 paper C) and the hub-load column each multiplies
EXCITATION_FACTORS = {
    "thrust_factor": "Fx",
    "side_force_factor": "Fy",
    "vertical_force_factor": "Fz",
    "torque_factor": "Mx",
    "tilt_moment_factor": "My",
    "yaw_moment_factor": "Mz",
}


def wind_field(scene: Scene, turbine: Turbine = NREL5MW) -> np.ndarray:
    """Shaft-frame wind at the rotor grid (hub centre first), shape (3, n_t, n_pts) [m/s]."""
    points, _ = grid_points(turbine)
    n = scene.n_steps
    if scene.turbulence_intensity > 0.0:
        model = IecTurbulence(scene.flow_speed, scene.turbulence_intensity, turbine.hub_height)
        fluct = generate_field(points, model, scene.duration, scene.dt, np.random.SeedSequence(scene.seed))
    else:
        fluct = np.zeros((3, n, points.shape[0]))
    return inflow_in_shaft_frame(turbine, scene.flow_speed, scene.shear_exponent, scene.flow_inclination_deg,
                                 fluct, points[:, 1])


#: columns of a realisation (:func:`generate`), in the order they are computed and stored
COLUMNS = ("wind_hub", *LOAD_COLUMNS, "rotor_speed", "pitch", "gen_torque", "azimuth", "gen_speed_set", "power")


def _compute(scene: Scene, turbine: Turbine) -> np.ndarray:
    """The realisation as an (n_t, len(COLUMNS)) array."""
    inflow = wind_field(scene, turbine)
    rotor = simulate_bem if scene.loads_fidelity == "bem" else simulate_rotor
    res = rotor(turbine, inflow, scene.dt, turbine.steady_state(scene.flow_speed),
                spinup=int(round(SPINUP_S / scene.dt)))
    speed, torque = res[:, 6], res[:, 8]
    return np.column_stack([inflow[0, :, 0], res[:, :6], speed, res[:, 7], torque, res[:, 9],
                            speed - torque / C_GEN_DEFAULT, torque * speed])


@lru_cache(maxsize=8)
def _generate(scene: Scene, turbine: Turbine) -> pd.DataFrame:
    values = cache.load_or_compute(scene, turbine, _compute)
    t = pd.Index(np.arange(values.shape[0]) * scene.dt, name="time")
    df = pd.DataFrame(values, index=t, columns=list(COLUMNS))
    df.attrs.update(scene=scene.to_dict(), frame="shaft: X hub->generator, Z up, Y = Z x X",
                    turbine=f"{turbine.rotor} rotor, direct drive", units={
                        "wind_hub": "m/s", "Fx": "N", "Fy": "N", "Fz": "N", "Mx": "N m", "My": "N m",
                        "Mz": "N m", "rotor_speed": "rad/s", "pitch": "rad", "gen_torque": "N m",
                        "azimuth": "rad", "gen_speed_set": "rad/s", "power": "W"})
    return df


@lru_cache(maxsize=8)
def _as_array(scene: Scene, turbine: Turbine) -> tuple[dict[str, int], np.ndarray]:
    return {c: i for i, c in enumerate(COLUMNS)}, _generate(scene, turbine).to_numpy(dtype=float)


def generate(scene: Scene, turbine: Turbine = NREL5MW) -> pd.DataFrame:
    """Hub loads and rotor states of one realisation of ``scene``.

    Returns
    -------
    pandas.DataFrame
        Indexed by time [s]; columns ``wind_hub`` (axial wind at the hub centre [m/s]),
        ``Fx, Fy, Fz`` [N] and ``Mx, My, Mz`` [N m] (aerodynamic, on the hub, shaft frame),
        ``rotor_speed`` [rad/s], ``pitch`` [rad], ``gen_torque`` (controller demand [N m]),
        ``azimuth`` [rad], ``gen_speed_set`` (the set-point ``w - T/C_gen`` for the seed's
        ``C_gen`` = 828.26 kN m s/rad [rad/s]) and ``power`` [W]. A copy of a cached frame.

    Examples
    --------
    >>> loads = generate(Scene(wind_speed=8.0, turbulence_intensity=0.0, shear_exponent=0.0, duration=20.0))
    >>> round(float(loads["rotor_speed"].iloc[-1]), 2)   # optimal TSR 7.5: 7.5 * 8 cos(4 deg) / 63 rad/s
    0.95
    """
    return _generate(scene, turbine).copy()


def generate_columns(scene: Scene, columns: list[str], turbine: Turbine = NREL5MW) -> np.ndarray:
    """Columns of :func:`generate` as a new (n_t, k) float array, without a frame copy or a pandas
    column lookup (the models' per-point path: ~0.05 ms where ``generate`` takes ~1 ms)."""
    index, values = _as_array(scene, turbine)
    return values[:, [index[c] for c in columns]]


def apply_excitation(loads: pd.DataFrame, factors: dict[str, float]) -> pd.DataFrame:
    """Loads with hub-load components multiplied by excitation factors (``EXCITATION_FACTORS`` names)."""
    out = loads.copy()
    for name, value in factors.items():
        out[EXCITATION_FACTORS[name]] *= value
    return out
