"""The seeds' own numbers: every printed model output of seed 000 and seed 003 against ddgsa's (issue 47).

One row per printed number or claim, computed from the models (cheap rows: modes and the seed's Table 1
problem) or read from the committed results of the studies that reproduce it (``results/<study>/``,
whose values a slow test recomputes from the model). ``python -m ddgsa.bench.seed_numbers`` writes
``results/seed_numbers/numbers.csv`` and its rendered ``README.md``; ``tests/bench/test_seed_numbers.py``
fails when a committed row no longer follows from the code.

Columns: ``id``, ``statement`` (what the seed prints), ``source`` (where), ``paper_value`` and ``unit``,
``ddgsa_value`` (same unit), ``reading`` (the model, options and reading that give it), ``rel_error``
(``ddgsa / paper - 1``), ``verdict`` (``within 5 %`` or ``outside 5 %``; for a qualitative claim, ``claim
holds`` or ``claim fails``) and ``explanation`` (for every row outside 5 % and every failed claim, with the
computation that explains it).
"""

from __future__ import annotations

import functools
import math
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from scipy.optimize import brentq

from ddgsa import models
from ddgsa.mbs.beam import ShaftModes, shaft_modes
from ddgsa.mbs.sampling import RESOLVED
from ddgsa.models.seed_readings import TABLE1_HZ, table1_spec

TOLERANCE = 0.05
"""A printed number is reproduced when ddgsa's is within this relative distance of it [-]."""
COLUMNS = ("id", "statement", "source", "paper_value", "unit", "ddgsa_value", "reading", "rel_error", "verdict",
           "explanation")
RESULTS = Path(__file__).resolve().parents[3] / "results"
"""The repository's ``results/`` folder (the committed study outputs the result rows read)."""
VIDYN_MM = {6.0: 0.6, 11.0: 1.6, 18.0: 2.5}
"""Seed 000 §3.2.1: ViDyn's "minimum radius" at the hub [mm] per mean wind speed [m/s] (OS 1-3)."""


@dataclass(frozen=True)
class Row:
    """One printed number: how ddgsa computes it (``value``, in ``unit``) and, for a row outside
    :data:`TOLERANCE`, the computation that explains the gap (``explain``, called with ddgsa's value).
    ``slow``: ``value`` reads a committed study result that only a rerun (minutes) recomputes."""

    id: str
    statement: str
    source: str
    paper_value: float
    unit: str
    reading: str
    value: Callable[[], float]
    explain: Callable[[float], str]
    slow: bool = False
    claim: Callable[[float], bool] | None = None
    """For a qualitative claim: whether ddgsa's value bears it out (its verdict is then ``claim holds`` or
    ``claim fails``, and ``paper_value`` the number the claim is judged against)."""


@functools.lru_cache(maxsize=2)
def table1_modes(shaft: str) -> ShaftModes:
    """Seed 000 Table 1's problem (:func:`~ddgsa.models.seed_readings.table1_spec`: rigid supports, free-free
    torsion, elongation on the front bearing's axial spring) for the direct drive's ``shaft`` reading."""
    p = models.get("direct_drive", shaft=shaft).nominal
    return shaft_modes(table1_spec(p, p["k_front_x"]), n_axial=3, n_torsion=2, n_bending=2)


def _table1_frequency(family: str, n: int, shaft: str) -> float:
    """Mode ``n`` (0-based) of ``family`` in Table 1's order (elongation: the spring's bouncing mode skipped)."""
    md = table1_modes(shaft)
    freq = {"bending": md.freq_bending, "axial": md.freq_axial[1:], "torsion": md.freq_torsion}[family]
    return float(freq[n])


def _wavenumber(family: str, n: int, shaft: str) -> float:
    """Table 1's wavenumber of mode ``n`` [1/m]: ``beta = (w^2 mu / EI)^(1/4)`` (eq. 18),
    ``lambda_X = w sqrt(mu / EA)`` (eq. 19), ``lambda_T = w / c_S`` with ``c_S^2 = GJ / (mu r^2 / 2)`` (eq. 20)."""
    p = models.get("direct_drive", shaft=shaft).nominal
    w = 2.0 * math.pi * _table1_frequency(family, n, shaft)
    mu = p["shaft_mass"] / p["shaft_length"]
    if family == "bending":
        return (w * w * mu / p["shaft_bending_stiffness"]) ** 0.25
    if family == "axial":
        return w * math.sqrt(mu / p["shaft_axial_stiffness"])
    return w * math.sqrt(mu * p["shaft_radius"] ** 2 / 2.0 / p["shaft_torsional_stiffness"])


def _other_reading(family: str, n: int, wavenumber: bool = False) -> Callable[[float], str]:
    """The explanation of a Table 1 row: the ``table2`` shaft's value beside the default's."""
    def text(value: float) -> str:
        other = (_wavenumber if wavenumber else _table1_frequency)(family, n, "table2")
        return (f"table2 shaft (EI 1e9 N m^2, hollow 5.03 t, R1, R2 as radii of gyration) gives {other:.4g}: "
                f"{other / value - 1:+.1%} from the table1 value")
    return text


def _summary(study: str) -> pd.DataFrame:
    return pd.read_csv(RESULTS / study / "sweep_summary.csv")


def hub_deflection_mm(study: str, wind_speed: float) -> float:
    """Mean RMS hub deflection [mm] of ``results/<study>`` at ``wind_speed`` [m/s]."""
    frame = _summary(study)
    return float(frame.loc[frame["wind_speed"] == wind_speed, "rms_deflection_hub_mean"].iloc[0]) * 1e3


def _vidyn_explanation(wind_speed: float) -> Callable[[float], str]:
    def text(value: float) -> str:
        table2 = hub_deflection_mm("seed000_full_vs_rigid", wind_speed)
        rigid = hub_deflection_mm("seed000_full_vs_rigid_rigid_table1", wind_speed)
        return (f"ddgsa's RMS hub deflection about the static state (flexible, 3 x 300 s, NREL 5-MW loads) is "
                f"{value:.2f} mm on the table1 shaft and {table2:.2f} mm ({table2 / VIDYN_MM[wind_speed] - 1:+.0%}) "
                f"on table2's softer one; the rigid shaft's is {rigid:.3f} mm, so the shaft's bending carries "
                f"{1 - rigid / value:.0%} of it. The paper does not define ViDyn's 'minimum radius' nor give its "
                "turbine's loads; ddgsa's loads are the NREL 5-MW rotor's (docs/loads.md)")
    return text


def front_damage_peak(study: str, intensity: float) -> float:
    """Mean wind speed [m/s] of the largest mean front-bearing damage at ``intensity`` in ``results/<study>``."""
    frame = _summary(study)
    frame = frame[np.isclose(frame["turbulence_intensity"], intensity)]
    return float(frame.loc[frame["damage_front_mean"].idxmax(), "wind_speed"])


def rigid_flexible_damage(output: str, wind_speed: float) -> float:
    """Rigid / flexible ratio of mean ``output`` at ``wind_speed`` (``seed000_full_vs_rigid*_table1``)."""
    flex, rigid = _summary("seed000_full_vs_rigid_table1"), _summary("seed000_full_vs_rigid_rigid_table1")
    pick = lambda f: float(f.loc[f["wind_speed"] == wind_speed, f"{output}_mean"].iloc[0])  # noqa: E731
    return pick(rigid) / pick(flex)


@functools.lru_cache(maxsize=8)
def static_hub(wind_speed: float | None, shaft: str = "table1") -> tuple[float, float]:
    """Lateral and vertical hub displacement ``(Y_st, Z_st)`` [mm] of the direct drive's static state under
    the mean hub loads of the 600 s, I_ref 0.12 scene at ``wind_speed`` [m/s] (``None``: gravity only)."""
    from ddgsa.models.direct_drive import SceneInputs, deflection_ends, input_map

    model = models.get("direct_drive", fidelity="linear", shaft=shaft)
    asm, p = model.build(), model.resolve(None).iloc[0].to_dict()
    if wind_speed is None:
        force = moment = np.zeros(3)
    else:
        u0 = SceneInputs.of(_scene(wind_speed)).mean @ input_map(p)
        force, moment = u0[0:3], u0[3:6]
    ends = deflection_ends(model.static(asm, force, moment)[None, :], asm, "total")[0]
    return float(ends[1]) * 1e3, float(ends[2]) * 1e3


def _scene(wind_speed: float) -> Any:
    from ddgsa import Scene

    return Scene(wind_speed=wind_speed, turbulence_intensity=0.12, duration=600.0, seed=1)


@functools.lru_cache(maxsize=4)
def hub_rms(wind_speed: float, shaft: str = "table1") -> tuple[float, float]:
    """RMS lateral and vertical hub deflection ``(y, z)`` [mm] about the static state (seed eq. 28's reference),
    direct drive ``linear`` (default basis), 600 s at ``wind_speed`` [m/s], I_ref 0.12, seed 1."""
    sim = models.get("direct_drive", fidelity="linear", shaft=shaft).simulate(_scene(wind_speed))
    d = sim[["hub_dy", "hub_dz"]].to_numpy() - sim.attrs["static_hub"][1:]
    rms = np.sqrt((d ** 2).mean(axis=0)) * 1e3
    return float(rms[0]), float(rms[1])


def vertical_over_lateral(wind_speed: float) -> float:
    """Vertical / lateral RMS hub deflection about the static state at ``wind_speed`` (:func:`hub_rms`)."""
    lateral, vertical = hub_rms(wind_speed)
    return vertical / lateral


def _vertical_explanation(value: float) -> str:
    lateral, vertical = hub_rms(11.0)
    y_g, z_g = static_hub(None)
    y_st, z_st = static_hub(11.0)
    about_rest = (math.hypot(vertical, z_st - z_g), math.hypot(lateral, y_st - y_g))
    rigid = hub_deflection_mm("seed000_full_vs_rigid_rigid_table1", 11.0) / hub_deflection_mm(
        "seed000_full_vs_rigid_table1", 11.0)
    return (f"about the static state under the mean loads (eq. 28) the hub moves {vertical:.2f} mm vertically and "
            f"{lateral:.2f} mm laterally (RMS, 11 m/s): the fluctuation is the shaft's bending under the turbulent "
            "tilt and yaw moments, which the rotor samples about equally, and the axisymmetric shaft carries "
            f"{1 - rigid:.0%} of it (the bearings' anisotropy, 3 against 10 GN/m, shows only in the rigid shaft's "
            f"{rigid:.0%}, "
            "results/seed000_full_vs_rigid*_table1). Measured about the rest state "
            f"under gravity alone, the mean tilt moment's deflection counts ({z_st - z_g:.2f} mm up) and the vertical "
            f"is {about_rest[0]:.2f} mm against {about_rest[1]:.2f} mm lateral ({about_rest[0] / about_rest[1]:.2f}x): "
            "the paper's statement holds if its 'quasi-static solution' is the rest state, not the mean-load state")


def static_growth() -> float:
    """Rise of the hub's static vertical position from 5 to 20 m/s [mm] (:func:`static_hub`)."""
    return static_hub(20.0)[1] - static_hub(5.0)[1]


def _static_growth_explanation(value: float) -> str:
    from ddgsa.models.direct_drive import SceneInputs, input_map

    z_g = static_hub(None)[1]
    p = models.get("direct_drive", shaft="table1").resolve(None).iloc[0].to_dict()
    tilt = {v: float((SceneInputs.of(_scene(v)).mean @ input_map(p))[4]) / 1e6 for v in (5.0, 20.0)}
    compliance = (static_hub(20.0)[1] - static_hub(5.0)[1]) / (tilt[20.0] - tilt[5.0])
    y5, y20 = static_hub(5.0)[0], static_hub(20.0)[0]
    return (f"Z_st rises {value:.2f} mm from 5 to 20 m/s, {value / abs(z_g):.1f}x the gravity sag ({z_g:.3f} mm): "
            "it is "
            f"linear in the mean tilt moment of the NREL 5-MW rotor ({tilt[5.0]:.2f} -> {tilt[20.0]:.2f} MN m: shear "
            f"exponent 0.2 and the 4 deg shaft tilt), {compliance:.2f} mm per MN m at the hub; Y_st moves "
            f"{y5:+.2f} -> {y20:+.2f} mm with the mean yaw moment. A 'small increase' needs a mean tilt moment small "
            "against the hub weight's about the front bearing (0.39 MN m); the paper gives neither its loads nor "
            "this moment")


PAPER_BEARING_HZ = 49.5
"""Seed 003's bearing mode of the full electro-mechanical model [Hz] (§3.1), the mode its time-step study sees."""


def guard_samples(interval_s: float) -> float:
    """Samples per period of the 49.5 Hz bearing mode at the communication interval ``interval_s`` [s], as
    ddgsa's aliasing guard counts them (:func:`ddgsa.mbs.sampling.sampling_row`)."""
    from ddgsa.mbs.sampling import sampling_row

    row = sampling_row("communication interval", interval_s, PAPER_BEARING_HZ, "bearing", "")
    return float(row["samples_per_period"])


def _aliasing_explanation(value: float) -> str:
    from ddgsa.mbs.sampling import sampling_row

    rows = {dt: sampling_row("communication interval", dt, PAPER_BEARING_HZ, "bearing", "")
            for dt in (1e-4, 1e-3, 1e-2, 2e-2)}
    counts = ", ".join(f"{dt:g} s: {r['samples_per_period']:.1f} ({r['verdict']})" for dt, r in rows.items())
    lags = ", ".join(f"{math.degrees(2 * math.pi * PAPER_BEARING_HZ * dt):.0f} deg at {dt:g} s" for dt in (1e-4, 1e-3))
    return (f"the guard counts samples per period of the {PAPER_BEARING_HZ} Hz mode ({counts}) and passes 0.001 s, "
            "where the paper saw the spurious peak, while it flags 0.01 s, where the paper saw none: the peak is not "
            "aliasing, which grows with the interval. A two-way coupling that exchanges forces once per interval "
            f"lags the aerodynamic force by about one interval at the mode ({lags}), a phase error that can feed the "
            "lightly damped bearing mode (a likely mechanism, not computed here); at 0.01 s the aerodynamic "
            "side's Nyquist frequency (50 Hz) sits at the mode "
            "and passes nothing to it. ddgsa's loads are one-way (computed beforehand), so it has no such loop to "
            "reproduce; its guard judges sampling, not the coupling's delay")


@functools.lru_cache(maxsize=8)
def generator_frequency(config: str, magnetic: bool, label: str) -> float:
    """Natural frequency [Hz] of mode ``label`` of ``generator_radial`` (``config``, ``magnetic``) at nominal."""
    table = models.get("generator_radial", config=config, magnetic=magnetic).modes()
    return float(table.loc[table["label"] == label, "frequency_hz"].iloc[0])


FULL_MODEL_HZ = 49.5
"""Seed 003 §3.1, Fig. 12: the bearing mode of the full (one-step) electro-mechanical model [Hz]."""
ONE_STEP = "tower_bending_torsion"
"""The ``generator_radial`` configuration of the one-step reading (both tower paths on the stator)."""


def _one_step_frequency(params: dict[str, float]) -> float:
    """Bearing mode [Hz] of the one-step configuration with the magnetic pull at ``params`` (else nominal)."""
    table = models.get("generator_radial", config=ONE_STEP, magnetic=True).modes(params)
    return float(table.loc[table["label"] == "bearing_radial", "frequency_hz"].iloc[0])


@functools.lru_cache(maxsize=1)
def one_step_mass_scale(target_hz: float = FULL_MODEL_HZ) -> float:
    """Factor [-] on both tower paths' masses (``tower_mass``, ``tower_torsion_mass``) that puts the one-step
    bearing mode at ``target_hz`` [Hz], the rest nominal (Brent's method on the model's modes, to 1e-9)."""
    nominal = models.get("generator_radial", config=ONE_STEP).nominal
    masses = {k: nominal[k] for k in ("tower_mass", "tower_torsion_mass")}
    return float(brentq(lambda s: _one_step_frequency({k: s * v for k, v in masses.items()}) - target_hz,
                        1e-3, 1.0, xtol=1e-12, rtol=1e-9))


@functools.lru_cache(maxsize=1)
def one_step_rotating_mass(target_hz: float = FULL_MODEL_HZ) -> float:
    """Rotating mass [kg] in the bearing mode that puts the one-step mode at ``target_hz`` [Hz] with Table 3's
    tower masses (Brent's method, to 1e-9)."""
    nominal = models.get("generator_radial", config=ONE_STEP).nominal["rotating_mass"]
    return float(brentq(lambda m: _one_step_frequency({"rotating_mass": m}) - target_hz, 0.1 * nominal, nominal,
                        xtol=1e-6, rtol=1e-9))


def apparent_mass(tower_mass: float, torsion_mass: float) -> float:
    """Non-rotating mass [kg] the stator presents to a lateral force when the tower-top translation (``m_1``)
    and yaw (apparent mass ``J / l^2``) both move it: ``1 / (1/m_1 + l^2/J)``."""
    return 1.0 / (1.0 / tower_mass + 1.0 / torsion_mass)


def _none(value: float) -> str:
    return ""


BEARING_FORCES = "seed003_bearing_forces"
"""The committed study of the generator's bearing forces under the IEA 15 MW rotor (issue 47 item 2)."""
LOCK, ON_BEARINGS = "rotor=iea15mw, hub_moments=lock", "rotor=iea15mw, hub_moments=bearings"


def bearing_force_kn(variant: str, wind_speed: float, bearings: int = 1) -> float:
    """Mean over the realisations of the peak dynamic (wind's part of the) radial force of one bearing
    [kN] in ``results/seed003_bearing_forces``, times ``bearings`` (2: the load on the generator rotor)."""
    frame = _summary(BEARING_FORCES)
    hit = frame[(frame["variant"] == variant) & (frame["wind_speed"] == wind_speed)]
    return float(hit["peak_dynamic_bearing_force_n_mean"].iloc[0]) * bearings / 1e3


def _bearing_force_explanation(value: float) -> str:
    speeds = sorted(_summary(BEARING_FORCES)["wind_speed"].unique())
    each = " / ".join(f"{bearing_force_kn(LOCK, s):.0f}" for s in speeds)
    both = " / ".join(f"{bearing_force_kn(LOCK, s, 2):.0f}" for s in speeds)
    moments = " / ".join(f"{bearing_force_kn(ON_BEARINGS, s) / 1e3:.0f}" for s in speeds)
    winds = " / ".join(f"{s:g}" for s in speeds)
    return (f"IEA 15 MW rotor (table rotor, TI 0.14, 3 x 600 s), wind {winds} m/s: per bearing under the paper's "
            f"tilt lock {each} kN, just below the band; both bearings together (the radial load on the generator "
            f"rotor) {both} kN, inside it from rated wind; with the hub moments carried by the bearings as a couple "
            f"over their 1.2 m spacing (hub_moments: bearings) {moments} MN per bearing, far above it. The paper's "
            "range matches its own locked model's rotor load (results/seed003_bearing_forces, docs/models.md)")


def rows() -> list[Row]:
    """The table's rows: seed 000 Table 1 (frequencies, wavenumbers), §3.2.1's ViDyn radii and four of its
    claims (two of issue 47's qualitative gaps); seed 003's time-step finding against the aliasing guard (the
    third) and its bearing-mode frequencies (§2.1, §3.1, Table 3 text)."""
    out: list[Row] = []
    names = {"bending": "bending", "axial": "elongation", "torsion": "torsional"}
    symbols = {"bending": "beta_n", "axial": "lambda_n^X", "torsion": "lambda_n^T"}
    printed_k = {"bending": (0.2156, 0.4751), "axial": (0.1591, 0.5756), "torsion": (0.0760, 0.5354)}
    reading = "direct_drive shaft: table1 (default), Table 1's FE problem (seed_readings.table1_spec)"
    for family in ("bending", "axial", "torsion"):
        for n in range(2):
            out.append(Row(f"s000-table1-{family}-{n + 1}-hz", f"FE eigenfrequency, {names[family]} mode {n + 1}",
                           "seed 000 Table 1", TABLE1_HZ[family][n], "Hz", reading,
                           functools.partial(_table1_frequency, family, n, "table1"), _other_reading(family, n)))
    for family in ("bending", "axial", "torsion"):
        for n in range(2):
            out.append(Row(f"s000-table1-{family}-{n + 1}-wavenumber",
                           f"{symbols[family]}, {names[family]} mode {n + 1}",
                           "seed 000 Table 1", printed_k[family][n], "1/m", reading,
                           functools.partial(_wavenumber, family, n, "table1"),
                           _other_reading(family, n, wavenumber=True)))
    flexible = "direct_drive flexible, shaft: table1, Euler-Bernoulli 2 modes (results/seed000_full_vs_rigid_table1)"
    for k, (speed, mm) in enumerate(VIDYN_MM.items()):
        out.append(Row(f"s000-vidyn-hub-{int(speed)}", f"ViDyn's minimum radius at the hub, OS{k + 1} ({speed:g} m/s); "
                       "the paper's model agrees 'quite good'", "seed 000 §3.2.1, Fig. 13", mm, "mm", flexible,
                       functools.partial(hub_deflection_mm, "seed000_full_vs_rigid_table1", speed),
                       _vidyn_explanation(speed), slow=True))
    out.append(Row("s000-front-damage-peak", "front-bearing damage peaks at 11 m/s (I_ref 0.12; every case)",
                   "seed 000 §4, Figs 15-16", 11.0, "m/s",
                   "direct_drive linear, shaft: table1 (results/seed000_wind_sweep_table1)",
                   functools.partial(front_damage_peak, "seed000_wind_sweep_table1", 0.12), _none, slow=True))
    out.append(Row("s000-rigid-flexible-damage-18", "bearing forces (damage) of full and simplified models "
                   "almost identical: rigid / flexible front damage at 18 m/s", "seed 000 §3.2.1, Fig. 14, §5",
                   1.0, "-",
                   "direct_drive flexible vs rigid, shaft: table1 (results/seed000_full_vs_rigid*_table1)",
                   functools.partial(rigid_flexible_damage, "damage_front", 18.0), _rigid_flexible_explanation,
                   slow=True))
    linear = "direct_drive linear, shaft: table1 (default basis), 600 s, I_ref 0.12, seed 1"
    out.append(Row("s000-vertical-over-lateral-11", "tip deflection larger vertically than laterally: vertical / "
                   "lateral RMS hub deflection at 11 m/s above 1.05 (claim; ddgsa's ratio)", "seed 000 §3.2.1",
                   1.0, "-",
                   linear, functools.partial(vertical_over_lateral, 11.0), _vertical_explanation,
                   claim=lambda v: v > 1.0 + TOLERANCE))
    out.append(Row("s000-static-z-growth", "static solution: a small increase in Z_st with wind speed (claim: ddgsa's "
                   "rise 5 -> 20 m/s, below the gravity sag)", "seed 000 §3.2.1", abs(static_hub(None)[1]), "mm",
                   "direct_drive static state under the mean hub loads, shaft: table1", static_growth,
                   _static_growth_explanation, claim=lambda v: v < abs(static_hub(None)[1])))
    out.append(Row("s003-aliasing-0001", "aerodynamic communication interval 0.001 s gives a spurious peak at the "
                   "bearing mode, 0.0001 s much less, 0.01 s none (claim: ddgsa's aliasing guard flags 0.001 s, i.e. "
                   "fewer samples per period of the 49.5 Hz mode than its threshold)", "seed 003 §3.2, Fig. 15",
                   RESOLVED, "samples/period", "ddgsa.mbs.sampling guard (warns below 10 samples per period)",
                   functools.partial(guard_samples, 1e-3), _aliasing_explanation, claim=lambda v: v < RESOLVED))
    out.append(Row("s003-claim-bearing-forces", "bearing (bending) forces of 100 kN - 1 MN (claim: ddgsa's peak "
                   "dynamic radial force of one bearing at rated wind 10.6 m/s within the band)", "seed 003 §2.2.2",
                   100.0, "kN", f"generator_radial rotor: iea15mw, hub_moments: lock ({BEARING_FORCES})",
                   functools.partial(bearing_force_kn, LOCK, 10.6), _bearing_force_explanation,
                   claim=lambda v: 100.0 <= v <= 1000.0))
    gen = "generator_radial"
    for ident, text, source, paper, config, magnetic, label in (
            ("s003-one-mass", "one-mass estimate f_B,est of the bearing mode", "seed 003 §2.1", 34.5, "one_mass",
             False,
             "bearing_radial"),
            ("s003-substructure", "bearing mode of the drive-train substructure model (Fig. 4b)", "seed 003 §3.1",
             34.17,
             "substructure", True, "bearing_radial"),
            ("s003-2dof-side-to-side-1", "2-DoF-2-mass model, first mode, side-to-side", "seed 003 §3.1, Table 3",
             0.19,
             "tower_side_to_side", False, "tower_side_to_side"),
            ("s003-2dof-torsion-1", "2-DoF-2-mass model, first mode, torsion", "seed 003 §3.1, Table 3", 5.1,
             "tower_torsion", False, "tower_torsion"),
            ("s003-2dof-side-to-side-2", "2-DoF-2-mass model, second (bearing) mode, side-to-side", "seed 003 §3.1",
             38.0,
             "tower_side_to_side", False, "bearing_radial"),
            ("s003-2dof-torsion-2", "2-DoF-2-mass model, second (bearing) mode, torsion", "seed 003 §3.1", 38.0,
             "tower_torsion", False, "bearing_radial"),
            ("s003-full-model", "bearing mode of the full electro-mechanical model (Fig. 4c)",
             "seed 003 §3.1, Fig. 12",
             FULL_MODEL_HZ, ONE_STEP, True, "bearing_radial")):
        out.append(Row(ident, text, source, paper, "Hz", f"{gen} config: {config}, magnetic: {str(magnetic).lower()}",
                       functools.partial(generator_frequency, config, magnetic, label),
                       _full_model_explanation if ident == "s003-full-model" else _none))
    return out


def _rigid_flexible_explanation(value: float) -> str:
    rear = rigid_flexible_damage("damage_rear", 18.0)
    return (f"the flexible shaft's rotor-rocking (first bending) mode, ~6 Hz and 1 % damped on the table1 shaft, adds "
            f"dynamic bearing load under turbulence; rear {rear:.3f}. The seed's damping as printed (eq. 44a, "
            "bending_rayleigh: printed) overdamps that mode and gives 1.000 / 0.999 on the table2 shaft "
            "(results/seed000_full_vs_rigid_published)")


def _full_model_explanation(value: float) -> str:
    f = {cfg: generator_frequency(cfg, True, "bearing_radial")
         for cfg in ("substructure", "tower_side_to_side", "tower_torsion")}
    nominal = models.get("generator_radial", config=ONE_STEP).nominal
    m_app = apparent_mass(nominal["tower_mass"], nominal["tower_torsion_mass"])
    scale, m_rot = one_step_mass_scale(), one_step_rotating_mass()
    rest = FULL_MODEL_HZ - value
    m_1 = nominal["tower_mass"] / 1e3
    return (f"the bearing mode with the magnetic pull, part by part (all on Table 3's m_1 = {m_1:.1f} t, c_SS,lin "
            f"{nominal['tower_stiffness']:.3g} N/m, c_tor,lin {nominal['tower_torsion_stiffness']:.3g} N/m): "
            f"drive-train substructure {f['substructure']:.2f} Hz; on "
            f"the tower's side-to-side path {f['tower_side_to_side']:.2f} Hz, on its torsion path "
            f"{f['tower_torsion']:.2f} Hz (the 2-DoF-2-mass models); on both at once (the bending-torsion coupling, "
            f"reading table3: the stator's apparent non-rotating mass halves, {m_1:.0f} -> "
            f"{m_app / 1e3:.0f} t) {value:.2f} Hz, +{value - f['tower_torsion']:.2f} Hz. Unexplained: {rest:.2f} Hz "
            f"({rest / FULL_MODEL_HZ:.0%} of the paper's value). {FULL_MODEL_HZ:g} Hz needs the structure's apparent "
            f"mass at the stator at {scale:.3f} of Table 3's ({scale * m_app / 1e3:.0f} t), or, with Table 3's, "
            f"{m_rot / 1e3:.0f} t of the 426.7 t rotating mass in the mode (the blades' modes decoupling part of "
            "the rotor assembly); the seed gives neither the tower top's yaw inertia and lever, the tower's "
            "distributed mass nor the blades' modal masses, so which of the two (or both) closes the gap is not "
            "computed here (docs/models.md, 'The one-step bearing mode')")


def evaluate(selected: list[Row] | None = None) -> pd.DataFrame:
    """The table of ``selected`` rows (default: all of :func:`rows`), one per row, in :data:`COLUMNS`."""
    records = []
    for row in rows() if selected is None else selected:
        value = float(row.value())
        rel = value / row.paper_value - 1.0
        if row.claim is None:
            verdict = "within 5 %" if abs(rel) <= TOLERANCE else "outside 5 %"
        else:
            verdict = "claim holds" if row.claim(value) else "claim fails"
        records.append({"id": row.id, "statement": row.statement, "source": row.source,
                        "paper_value": row.paper_value, "unit": row.unit, "ddgsa_value": float(f"{value:.6g}"),
                        "reading": row.reading, "rel_error": round(rel, 4),
                        "verdict": verdict,
                        "explanation": row.explain(value)})
    return pd.DataFrame(records, columns=list(COLUMNS))


def render(table: pd.DataFrame) -> str:
    """``README.md`` of the table: counts, then every row."""
    inside = int((table["verdict"] == "within 5 %").sum())
    numeric = int(table["verdict"].isin(["within 5 %", "outside 5 %"]).sum())
    holds = int((table["verdict"] == "claim holds").sum())
    outputs = table["id"].str.match(r"s000-(table1|vidyn)-|s003-(?!aliasing|claim)")
    printed, printed_inside = int(outputs.sum()), int((outputs & (table["verdict"] == "within 5 %")).sum())
    lines = ["# The seeds' own numbers", "",
             "Every printed model output of seed 000 (the direct drive) and seed 003 (the radial generator) that",
             "ddgsa computes, against ddgsa's value under the named reading, written by",
             "`python -m ddgsa.bench.seed_numbers` into `numbers.csv` (issue 47). A row is reproduced when it is",
             f"within {TOLERANCE:.0%}; every other row, and every claim ddgsa does not bear out, says why, with the "
             "computation. `tests/bench/test_seed_numbers.py` recomputes every row in its default run (a row that "
             "reads a committed study result from that result) and reruns the ViDyn rows' scenes from the model in "
             "its slow run. The seeds' printed numeric model outputs are the rows `s000-table1-*`, `s000-vidyn-*` "
             "and `s003-*` but the claims (aliasing, bearing forces).", "",
             f"**{inside} of {numeric} numeric rows within {TOLERANCE:.0%} ({printed_inside} of the {printed} printed "
             f"numeric model outputs); {holds} of {len(table) - numeric} qualitative claims hold.**", "",
             "| id | statement | source | paper | ddgsa | unit | rel. error | verdict | reading | explanation |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in table.itertuples(index=False):
        lines.append(f"| `{r.id}` | {r.statement} | {r.source} | {r.paper_value:g} | {r.ddgsa_value:.4g} | {r.unit} | "
                     f"{r.rel_error:+.1%} | {r.verdict} | {r.reading} | {r.explanation} |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    """Write ``results/seed_numbers/numbers.csv`` and ``README.md`` (or under the folder given)."""
    args = sys.argv[1:] if argv is None else argv
    folder = Path(args[0]) if args else RESULTS / "seed_numbers"
    folder.mkdir(parents=True, exist_ok=True)
    table = evaluate()
    table.to_csv(folder / "numbers.csv", index=False)
    (folder / "README.md").write_text(render(table))
    print(f"{folder / 'numbers.csv'}: {(table['verdict'] == 'within 5 %').sum()} of {len(table)} within 5 %")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
