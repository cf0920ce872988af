"""Objectives and mode tables of ``hss_rig`` and ``indirect_drive`` on fixed points and scenes.

Regression guards for the kernel's consolidation (issue 24), not oracles: the tables were written
by the code as it stood before the consolidation, and ``test_model_regression.py`` holds the
consolidated code to them (1e-6 relative, or 1e-6 of a column's largest value: what holds across
CPUs and BLAS builds, issue 48), so a change of numbers is seen and must be explained.
Whether the numbers are right is for the oracle tests (Radau reference, closed forms, ROSS).

``python tests/models/model_regression.py`` (with ``PYTHONPATH=src``) writes the tables under
``tests/models/data/`` from the code as it is.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from ddgsa import models
from ddgsa.loads.scene import Scene
from ddgsa.models.hss_rig.scenes import RigScene

DATA = Path(__file__).parent / "data"
RIG_OBJECTIVES = DATA / "hss_rig_objectives.csv"
RIG_MODES = DATA / "hss_rig_modes.csv"
GEARED_OBJECTIVES = DATA / "indirect_drive_objectives.csv"
GEARED_MODES = DATA / "indirect_drive_modes.csv"
#: today's tables of the two ported models (the port tables hold them to 1e-6 of the code before their port)
DIRECT_TODAY = DATA / "direct_drive_objectives_today.csv"
DIRECT_MODES_TODAY = DATA / "direct_drive_modes_today.csv"
GENERATOR_TODAY = DATA / "generator_radial_objectives_today.csv"
GENERATOR_MODES_TODAY = DATA / "generator_radial_modes_today.csv"

#: (fidelity, scene) pairs of the rig: every fidelity in a steady scene, the transients where cheap
RIG_CASES = (
    ("dq", RigScene("steady", speed_rpm=1500.0, duration=0.45, sample_rate=2000.0, settle=0.05)),
    ("kloss", RigScene("steady", speed_rpm=1500.0, duration=0.45, sample_rate=2000.0, settle=0.05)),
    ("kloss", RigScene("coastdown", speed_rpm=1500.0, duration=0.4, sample_rate=2000.0)),
    ("linear", RigScene("steady", speed_rpm=1500.0, duration=0.45, sample_rate=2000.0, settle=0.05)),
    ("linear", RigScene("steady", speed_rpm=900.0, duration=0.7, sample_rate=2000.0, settle=0.05)),
    ("linear", RigScene("startup", speed_rpm=1500.0, duration=1.2, sample_rate=2000.0)),
    ("linear", RigScene("coastdown", speed_rpm=1500.0, duration=1.2, sample_rate=2000.0)),
)
"""The rig's guarded cases. Every row must evaluate: until version 0.4.0 the dq, kloss and linear
transient rows were NaN (the 2e-4 s default step did not divide the 2 kHz sensor interval; the
0.2-0.3 s transients were too short for their order outputs), and NaN compared equal to NaN."""
RIG_POINTS = ({}, {"eccentric_mass": 1.5, "coupling_asymmetry": 0.5, "bearing_stiffness": 0.8})
RIG_SPEEDS = (0.0, 157.0)

#: (fidelity, scene) pairs of the geared drive
GEARED_CASES = (
    ("flexible", Scene(wind_speed=11.0, turbulence_intensity=0.12, duration=1.0, seed=3)),
    ("rigid", Scene(wind_speed=11.0, turbulence_intensity=0.12, duration=2.0, seed=3)),
    ("linear", Scene(wind_speed=11.0, turbulence_intensity=0.12, duration=60.0, seed=1)),
    ("linear", Scene(wind_speed=18.0, turbulence_intensity=0.20, duration=60.0, seed=2)),
)
GEARED_POINTS = ({}, {"c_gen": 1.2, "k_mount_z": 0.8, "rotor_inertia_x": 1.1, "lss_bending_stiffness": 0.9})
GEARED_SPEEDS = (0.0, 1.2)


def points_frame(nominal: dict[str, float], points: tuple[dict[str, float], ...]) -> pd.DataFrame:
    """The points: nominal, and some parameters scaled by a factor (those the model has)."""
    rows = []
    for change in points:
        row = dict(nominal)
        row.update({name: nominal[name] * factor for name, factor in change.items() if name in nominal})
        rows.append(row)
    return pd.DataFrame(rows)


def _objectives(name: str, cases: tuple, points: tuple) -> pd.DataFrame:
    frames = []
    for case, (fidelity, scene) in enumerate(cases):
        model = models.get(name, fidelity=fidelity)
        out = model.evaluate(points_frame(model.nominal, points), scene).reset_index(drop=True)
        out.insert(0, "point", range(len(out)))
        out.insert(0, "case", case)
        out.insert(0, "fidelity", fidelity)
        frames.append(out)
    return pd.concat(frames, ignore_index=True)


def _modes(name: str, fidelities: tuple[str, ...], points: tuple, speeds: tuple[float, ...]) -> pd.DataFrame:
    frames = []
    for fidelity in fidelities:
        model = models.get(name, fidelity=fidelity)
        for i, row in points_frame(model.nominal, points).iterrows():
            for speed in speeds:
                table = model.modes(row.to_dict(), rotor_speed=speed).reset_index(drop=True)
                table = table[["label", "frequency_hz", "damping_ratio"]]
                table.insert(0, "speed", speed)
                table.insert(0, "point", i)
                table.insert(0, "fidelity", fidelity)
                frames.append(table)
    return pd.concat(frames, ignore_index=True)


def rig_objectives() -> pd.DataFrame:
    """One row per (rig case, point) with every output of ``hss_rig``."""
    return _objectives("hss_rig", RIG_CASES, RIG_POINTS)


def rig_modes() -> pd.DataFrame:
    """``modes()`` of the rig (all fidelities share it) at each point and speed."""
    return _modes("hss_rig", ("kloss",), RIG_POINTS, RIG_SPEEDS)


def geared_objectives() -> pd.DataFrame:
    """One row per (geared-drive case, point) with every output of ``indirect_drive``."""
    return _objectives("indirect_drive", GEARED_CASES, GEARED_POINTS)


def geared_modes() -> pd.DataFrame:
    """``modes()`` of the geared drive (flexible and rigid) at each point and speed."""
    return _modes("indirect_drive", ("flexible", "rigid"), GEARED_POINTS, GEARED_SPEEDS)


def direct_modes() -> pd.DataFrame:
    """``modes()`` of the direct drive at every fidelity, nominal parameters, standstill."""
    frames = []
    for fidelity in ("flexible", "rigid", "linear"):
        table = models.get("direct_drive", fidelity=fidelity, shaft="table2").modes().reset_index(drop=True)
        table = table[["label", "frequency_hz", "damping_ratio"]]
        table.insert(0, "fidelity", fidelity)
        frames.append(table)
    return pd.concat(frames, ignore_index=True)


if __name__ == "__main__":
    import generator_port_regression
    import port_regression

    DATA.mkdir(exist_ok=True)
    for path, make in ((DIRECT_TODAY, port_regression.objectives), (DIRECT_MODES_TODAY, direct_modes),
                       (GENERATOR_TODAY, generator_port_regression.objectives),
                       (GENERATOR_MODES_TODAY, generator_port_regression.modes),
                       (RIG_OBJECTIVES, rig_objectives), (RIG_MODES, rig_modes),
                       (GEARED_OBJECTIVES, geared_objectives), (GEARED_MODES, geared_modes)):
        make().to_csv(path, index=False, float_format="%.17g")
        print(f"wrote {path}")
