"""The ``indirect_drive`` model: fidelities, scene inputs, simulation and objective functions."""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.errors import ModelError
from ddgsa.loads import EXCITATION_FACTORS, NREL5MW, apply_excitation, generate
from ddgsa.loads.scene import Scene
from ddgsa.mbs.campbell import CampbellDiagram
from ddgsa.mbs.compiled import Packed, constraint_values, pack
from ddgsa.mbs.integrate import genalpha, reference
from ddgsa.mbs.linear import input_window
from ddgsa.mbs.modal import modes as system_modes
from ddgsa.mbs.sampling import NYQUIST, check_interval, sampling_row
from ddgsa.models.base import Model, ModelOption, ModelOutput, controller_row, register_model
from ddgsa.models.constants import GRAVITY
from ddgsa.models.indirect_drive.assembly import FLEXIBLE_FIELDS, Assembly, build, check_geometry, spin_inertia
from ddgsa.models.indirect_drive.linear import (LINEARISATION_STEP, StateSpace, linear_response, operating_state,
                                                reduced_response, state_space)
from ddgsa.models.indirect_drive.outputs import (bearing_outputs, constraint_drift, gear_force_outputs,
                                                  housing_motion_outputs, rotated_x_axis, signal_statistics)
from ddgsa.models.indirect_drive.parameters import BEARINGS, PARAMETERS
from ddgsa.models.indirect_drive.series import (FORCE_MULTIPLIERS, TRANSVERSE, force_series, housing_series,
                                                time_series)

Array = NDArray[np.float64]

_COMPONENT = {"d": ("m", 0.1, "displacement"), "r": ("rad", 0.1, "rotation")}
_STAT = {"mean": "mean", "rms": "RMS about the mean", "p2p": "peak-to-peak"}
HOUSING_OUTPUTS = tuple(
    ModelOutput(f"housing_{c}{a}_{st}", _COMPONENT[c][0], f"{what} of the housing point's {_COMPONENT[c][2]} "
                f"along/about {a} (bedplate frame)", -_COMPONENT[c][1] if st == "mean" else 0.0, _COMPONENT[c][1])
    for c in ("d", "r") for a in ("x", "y", "z") for st, what in _STAT.items())


def _bearing_outputs(b: str) -> tuple[ModelOutput, ...]:
    out = (ModelOutput(f"damage_{b}", "1/s", f"{b} bearing damage rate (Palmgren-Miner, as the direct drive)",
                       0.0, 1e-6),
           ModelOutput(f"{b}_Fr_mean", "N", f"{b} bearing mean radial force", 0.0, 1e8))
    return out if b in TRANSVERSE else (*out, ModelOutput(f"{b}_Fa_mean", "N", f"{b} bearing mean axial force",
                                                          -1e8, 1e8))   # transverse bearings carry no Fa


OUTPUTS = (*HOUSING_OUTPUTS,
           ModelOutput("gear_force_mean", "N", "mean tooth (line-of-action) force of the gear mesh", 0.0, 1e8),
           ModelOutput("gear_force_rms", "N", "RMS of the tooth force about its mean", 0.0, 1e8),
           ModelOutput("gear_force_del", "N", "damage-equivalent tooth-force range (rainflow, 1 Hz, Woehler exponent 8.7)",
                       0.0, 1e8),
           *(o for b in BEARINGS for o in _bearing_outputs(b)),
           ModelOutput("housing_torque_mean", "N m", "mean reaction torque of the torque-arm mounts on the housing",
                       -1e8, 1e8),
           ModelOutput("housing_torque_rms", "N m", "RMS of that reaction torque about its mean", 0.0, 1e8),
           ModelOutput("position_drift", "m", "largest position-level constraint violation over the run (the linear "
                       "fidelity's is its linearisation error)", 0.0, 1e-2),
           ModelOutput("gear_drift", "m/s", "largest violation of the eq. 2.4 gear velocity constraint (linear "
                       "fidelity: its linearisation error)", 0.0, 1e-2))
#: default housing point: the upwind top corner on the +Y side of the 2.0 x 2.5 x 2.5 m housing,
#: housing frame relative to its centre of mass [m]
HOUSING_POINT = (-1.0, 1.25, 1.25)
#: highest frequency drawn in the Campbell diagram [Hz] (drive-train, rotor-tilt and housing modes)
CAMPBELL_MAX_HZ = 25.0
#: linearisations of the linear fidelity: at the loads' mean speed, then (from the second) at the
#: previous response's mean speed. One: since the rotor's tilting inertia is the hub's (version
#: 0.4.0) more passes move the outputs by <= 4.7e-5 relative (600 s records at 6-18 m/s, I_ref
#: 0.12-0.20; housing peak-to-peak the most; 2.2e-4 on a 60 s record), 250 times below the fidelity's error against
#: ``flexible`` (<= 1.2 %), for a fifth of the run's cost; with the whole rotor tilting it was 0.1-0.2 %.
SPEED_PASSES = 1
#: hub-load columns of the scene inputs [N], [N m]
LOAD_KEYS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")
#: samples of the record at which the linear fidelity evaluates the nonlinear constraint residual
DRIFT_SAMPLES = 50


def scene_inputs(scene: Scene, p: Mapping[str, float], fluctuation_scale: float = 1.0) -> dict[str, Array]:
    """Hub loads, set speed and times of a scene for parameters ``p``.

    The hub torque is the aerodynamic torque net of the inertial torque of the rotor inertia the
    loads model spins but this model does not (negative here: this model also spins the
    generator through the gear), ``M_x - (J_loads - J_model) dw/dt``, so the drive turns at the
    loads model's speed; the generator set speed is ``w - torque_factor T_ctrl / c_gen`` (seed 000
    eq. 25; ``torque_factor`` scales the torque through the drive train). ``fluctuation_scale``
    multiplies every input's deviation from its record mean (hub loads, rotor and set speed): 1
    is the scene as generated, smaller values a smaller-amplitude scene with the same means and
    spectra (amplitude sweeps of the linear fidelity).
    """
    loads = _excited(scene, tuple(p[k] for k in EXCITATION_FACTORS))
    out = {c: loads[c].copy() for c in (*LOAD_KEYS, "rotor_speed")}
    out["Mx"] -= (NREL5MW.rotor_inertia - spin_inertia(p)) * loads["acceleration"]
    out["w_set"] = out["rotor_speed"] - p["torque_factor"] * loads["gen_torque"] / p["c_gen"]
    out["times"] = loads["times"]
    if fluctuation_scale != 1.0:
        for key in (*LOAD_KEYS, "rotor_speed", "w_set"):
            out[key] = out[key].mean() + fluctuation_scale * (out[key] - out[key].mean())
    return out


@functools.lru_cache(maxsize=4)
def _excited(scene: Scene, factors: tuple[float, ...]) -> dict[str, Array]:
    """The scene's loads with the excitation factors (:data:`~ddgsa.loads.EXCITATION_FACTORS`, in that
    order) applied, as arrays, and the rotor's acceleration [rad/s^2]: kept for the few last scenes, which
    every point of a batch shares (a point's own parameters enter in :func:`scene_inputs`). Read only."""
    loads = apply_excitation(generate(scene), dict(zip(EXCITATION_FACTORS, factors)))
    out = {c: loads[c].to_numpy() for c in (*LOAD_KEYS, "rotor_speed", "gen_torque")}
    out["acceleration"] = np.gradient(out["rotor_speed"], scene.dt)
    out["times"] = loads.index.to_numpy()
    for v in out.values():
        v.flags.writeable = False
    return out


_NOMINAL_MODES: dict[tuple[str, ...], pd.DataFrame] = {}
""":attr:`IndirectDrive.nominal_modes` per set of LSS fields (they depend on nothing else)."""

STATIC_LIMIT = 0.1
"""Largest static housing roll [rad] and sag [m] a point may ask of the mounts (:meth:`IndirectDrive.point_problems`)."""


@register_model("indirect_drive")
class IndirectDrive(Model):
    """Geared (one-stage) drive train with the gearbox as kinematic constraints (seed 001 paper D).

    See :mod:`ddgsa.models.indirect_drive` for the bodies, constraints and loads and
    :mod:`~ddgsa.models.indirect_drive.parameters` for every default and its source.

    Parameters
    ----------
    fidelity : {"flexible", "rigid", "linear"}
        ``flexible``: FFR LSS (axial and two bending modes per plane); ``rigid``: rigid LSS; both
        by constrained generalised-alpha. ``linear``: the flexible system linearised about the
        scene's mean loads at its mean speed and integrated exactly (:mod:`.linear`).
    time_step : float, optional
        Generalised-alpha step [s] (default 0.005); must divide the scene's ``dt``.
    rho_inf : float
        Generalised-alpha spectral radius at infinite frequency (default 0.8).
    integrator : {"gen_alpha", "Radau", "BDF"}
        Generalised-alpha, or the kernel's ``solve_ivp`` reference (index-1 with Baumgarte
        stabilisation; slow) on the same system.
    equivalent_load : {"iso281", "seed"}
        Bearing equivalent-load rule (:func:`ddgsa.models.objectives.equivalent_load`).
    housing_point : sequence of 3 floats
        The observed housing point in the housing frame, from its centre of mass [m].
    fluctuation_scale : float
        Multiplies the inputs' deviations from their record means (default 1: the scene as
        generated); in (0, 1] for small-amplitude checks (:func:`scene_inputs`).
    """

    parameters = PARAMETERS
    outputs = OUTPUTS
    fidelities = ("flexible", "rigid", "linear")
    numerical_outputs = ("position_drift", "gear_drift")
    options = (ModelOption("time_step", "number", "integration step (default 0.005)", 0.0, 0.05, "s", low_open=True,
                           optional=True),
               ModelOption("rho_inf", "number", "generalised-alpha spectral radius at infinity", 0.0, 1.0),
               ModelOption("integrator", "choice", "time integrator (linear: its exact discretisation only)",
                           choices=("gen_alpha", "Radau", "BDF")),
               ModelOption("equivalent_load", "choice", "bearing equivalent-load rule", choices=("iso281", "seed")),
               ModelOption("housing_point", "numbers", "observed housing point from its centre of mass", unit="m",
                           length=3),
               ModelOption("fluctuation_scale", "number", "scale of the inputs' fluctuations", 0.0, 1.0, low_open=True))

    def __init__(self, fidelity: str = "flexible", time_step: float | None = None, rho_inf: float = 0.8,
                 integrator: str = "gen_alpha", equivalent_load: str = "iso281",
                 housing_point: tuple[float, float, float] | list[float] = HOUSING_POINT,
                 fluctuation_scale: float = 1.0) -> None:
        self.check_options({"fidelity": fidelity, "time_step": time_step, "rho_inf": rho_inf, "integrator": integrator,
                            "equivalent_load": equivalent_load, "housing_point": housing_point,
                            "fluctuation_scale": fluctuation_scale})
        if time_step is None:
            time_step = 0.005
        point = np.asarray(housing_point, dtype=float)
        self.fluctuation_scale = float(fluctuation_scale)
        self.fidelity = fidelity
        self.time_step = float(time_step)
        self.rho_inf = float(rho_inf)
        self.integrator = integrator
        self.rule = equivalent_load
        self.housing_point = point
        self.fields: tuple[str, ...] = () if fidelity == "rigid" else FLEXIBLE_FIELDS

    # -- building -----------------------------------------------------------------------------------
    def build(self, params: Mapping[str, float] | None = None, rotor_speed: float = 0.0,
                 lss_torque: float = 0.0) -> tuple[Assembly, Array, Array]:
        """The system under constant loads (hub torque ``lss_torque`` [N m], generator balancing it
        at ``rotor_speed`` [rad/s]) and its operating state ``(q, qd)``."""
        p = self.resolve(params).iloc[0].to_dict()
        times = np.array([0.0, 1.0])
        zero = np.zeros((2, 3))
        moment = zero.copy()
        moment[:, 0] = lss_torque
        w_set = np.full(2, rotor_speed - lss_torque / p["c_gen"])
        asm = build(p, self.fields, times, zero, moment, w_set, rotor_speed)
        q, qd, _ = operating_state(asm.system, asm.system.q0, asm.system.qd0, asm.system.index("hss.rx"))
        return asm, q, qd

    # -- simulation ---------------------------------------------------------------------------------
    def simulate(self, scene: Scene, params: Mapping[str, float] | None = None) -> pd.DataFrame:
        """Time series of a scene (indexed by time [s]).

        Columns: ``housing_dx, dy, dz`` (displacement of the housing point [m]) and ``housing_rx,
        ry, rz`` (housing rotation vector [rad]) from the unloaded assembly; ``lss_speed``,
        ``hss_speed``, ``housing_roll_rate`` [rad/s] (Bryant angle rates); ``spin_ratio`` (pinion over wheel
        spin relative to the housing, :func:`~.series.spin_ratio`); ``rotor_twist`` (rotor against LSS flange
        [rad]); ``gear_force`` (normal tooth force [N]); ``{main,lss1,lss3,hss2,hss4}_F{x,y,z}``
        (bearing forces on the outer rings, global [N]); ``mount_{left,right}_F{x,y,z}`` [N];
        ``housing_torque`` [N m]; ``gen_torque`` (on the HSS [N m]); the applied hub loads
        ``Fx ... Mz``; ``position_drift`` (largest holonomic constraint residual [m]) and
        ``gear_drift`` (residual of the gear's velocity constraint [m/s]), NaN between the
        :data:`DRIFT_SAMPLES` samples where the linear fidelity evaluates them.
        """
        p = self.resolve(params).iloc[0].to_dict()
        inp = scene_inputs(scene, p, self.fluctuation_scale)
        times, dt = inp["times"], scene.dt
        forces = np.column_stack([inp["Fx"], inp["Fy"], inp["Fz"]])
        moments = np.column_stack([inp["Mx"], inp["My"], inp["Mz"]])
        if self.fidelity == "linear":
            asm, _, ss, u, start, window = linearised(p, self.fields, inp, dt)
            res = linear_response(ss, u, dt, start, window)
            q, qd, lam = res.q, res.qd, res.lam
            pos, gear, _ = constraint_residuals(asm, q, qd, np.linspace(0, len(times) - 1, DRIFT_SAMPLES).astype(int))
            info: dict[str, Any] = {"method": "exact (linearised)", "reduced_dofs": ss.lin.m.shape[0],
                                    "linearisation_speed": float(ss.lin.qd0[asm.system.index("wheel.rx")])}
        else:
            n_sub = int(round(dt / self.time_step))
            if n_sub < 1 or abs(n_sub * self.time_step - dt) > 1e-9 * dt:
                raise ModelError(f"model 'indirect_drive': time_step {self.time_step} s must divide the scene's "
                                 f"dt {dt} s")
            asm = build(p, self.fields, times, forces, moments, inp["w_set"], float(inp["rotor_speed"][0]))
            q0, qd0, _ = operating_state(asm.system, asm.system.q0, asm.system.qd0, asm.system.index("hss.rx"))
            t_end = float(times[-1])
            if self.integrator == "gen_alpha":
                self._check_step()
                traj = genalpha.simulate(asm.system, t_end, self.time_step, q0, qd0, rho_inf=self.rho_inf,
                                         output_every=n_sub)
            else:
                traj = reference.simulate(asm.system, t_end, dt, q0, qd0, method=self.integrator)
            q, qd, lam = traj.q, traj.qd, traj.lam
            pos, gear, qd = constraint_residuals(asm, q, qd, np.arange(len(times)), project=True)
            info = dict(traj.info)
        out = time_series(asm, p, times, q, qd, lam, {**inp}, self.housing_point, (pos, gear))
        out.attrs.update(fidelity=self.fidelity, solver=info, duration=scene.duration)
        return out

    def _evaluate_one(self, params: dict[str, float], scene: Scene) -> dict[str, float]:
        if self.fidelity == "linear":                      # params: resolved by evaluate
            return objective_values(linear_records(params, self.fields,
                                                   scene_inputs(scene, params, self.fluctuation_scale),
                                                   scene.dt, self.housing_point), params, self.rule, scene.duration)
        return objectives(self.simulate(scene, params), params, self.rule)

    def point_problems(self, params: Mapping[str, float]) -> list[str]:
        """Why ``params`` (missing ones nominal) lie outside the valid region: positions out of the
        topology's order, or torque-arm mounts so soft that the housing's static roll under the
        rated rotor torque, or its sag under its weight, leaves the model's range.

        The roll is ``Q_rated / (2 k_mount_z mount_arm^2)`` and the sag ``m_h g / (2 k_mount_z)``
        (two mounts at +-``mount_arm``), both above :data:`STATIC_LIMIT` (0.1 rad, 0.1 m: the
        plausible range of ``housing_rx_mean`` and ``housing_dz_mean``); the nonlinear operating
        state stops converging near 1 rad (k_mount_z ~ 1e6 N/m)."""
        p = {**self.nominal, **params}
        try:
            check_geometry(p)
        except ModelError as exc:
            return [str(exc)]
        k = p["k_mount_z"]
        roll = NREL5MW.rated_torque / (2.0 * k * p["mount_arm"] ** 2)
        sag = p["housing_mass"] * GRAVITY / (2.0 * k)
        problems = []
        if roll > STATIC_LIMIT:
            problems.append(f"indirect_drive: torque-arm mounts too soft: the rated rotor torque "
                            f"{NREL5MW.rated_torque / 1e6:.2f} MN m would roll the housing by {roll:.3g} rad "
                            f"(k_mount_z {k:.4g} N/m at mount_arm {p['mount_arm']:.4g} m); the model holds to "
                            f"{STATIC_LIMIT} rad, i.e. k_mount_z >= "
                            f"{NREL5MW.rated_torque / (2 * STATIC_LIMIT * p['mount_arm'] ** 2):.3g} N/m")
        if sag > STATIC_LIMIT:
            problems.append(f"indirect_drive: torque-arm mounts too soft: the housing ({p['housing_mass']:.4g} kg) "
                            f"would sag {sag:.3g} m on k_mount_z {k:.4g} N/m; the model holds to {STATIC_LIMIT} m")
        return problems

    # -- modes and sampling ---------------------------------------------------------------------
    def modes(self, params: Mapping[str, float] | None = None, rotor_speed: float = 0.0,
              lss_torque: float = 0.0) -> pd.DataFrame:
        """Damped modes of the constrained system about its operating state (kernel
        :func:`ddgsa.mbs.modal.modes` with the linear fidelity's step
        :data:`~ddgsa.models.indirect_drive.linear.LINEARISATION_STEP`), at ``rotor_speed`` [rad/s] under
        ``lss_torque`` [N m];
        labels ``<body>_<direction>`` of the coordinate holding most of the mode's energy (``hss_spin``:
        the drive-train torsion mode, whose energy is mostly the generator's)."""
        asm, q, qd = self.build(params, rotor_speed, lss_torque)
        return system_modes(asm.system, q, qd, rel_step=LINEARISATION_STEP)

    def campbell(self, speeds: Any = None, orders: Any = (1.0, 3.0), params: Mapping[str, float] | None = None,
                 max_frequency_hz: float = CAMPBELL_MAX_HZ) -> CampbellDiagram:
        """Campbell diagram (:meth:`Model.campbell`): :meth:`modes` below ``max_frequency_hz`` at each
        rotor speed of ``speeds`` [rad/s] (default 0 to 15 rpm), every body spinning at its operating
        speed (rotor, blades and wheel at the rotor speed, the HSS at -N times it), no load. Whirl directions
        are not classified."""
        speeds = np.linspace(0.0, 15.0 * np.pi / 30.0, 11) if speeds is None else speeds
        return super().campbell(speeds, orders, params, max_frequency_hz)

    @property
    def nominal_modes(self) -> pd.DataFrame:
        """:meth:`modes` at nominal parameters, standstill: computed once per process and set of
        fields (a study's checks and its provenance ask it of several instances; ~0.5 s each)."""
        if self.fields not in _NOMINAL_MODES:
            _NOMINAL_MODES[self.fields] = self.modes()
        return _NOMINAL_MODES[self.fields].copy()

    def _check_step(self) -> None:
        """Aliasing guard: warn when the step does not resolve the lowest mode."""
        check_interval(self.time_step, float(self.nominal_modes["frequency_hz"].min()),
                       "indirect_drive integration step", refuse=False, warn_below=NYQUIST)

    def sampling_checks(self, scene: Scene) -> list[dict[str, Any]]:
        """Integration step against the lowest mode and the load interval against the highest."""
        m = self.nominal_modes
        low, top = m.loc[m["frequency_hz"].idxmin()], m.loc[m["frequency_hz"].idxmax()]
        rows = []
        if self.fidelity != "linear":
            rows.append(sampling_row("integration step", self.time_step, low["frequency_hz"], low["label"],
                                     "the mode's period and damping are approximated"))
        return rows + [controller_row(scene.dt, top["frequency_hz"], top["label"])]


def constraint_residuals(asm: Assembly, q: Array, qd: Array, rows: Array,
                         project: bool = False) -> tuple[Array, Array, Array]:
    """Largest holonomic residual [m] and the gear constraint's velocity residual [m/s] at ``rows``
    of a record (NaN elsewhere), from the nonlinear constraint equations, and the rates.

    ``project``: return the rates projected on the velocity-level constraints, ``qd - C_q^+ (C_q qd)``
    at every row (``rows`` must then be all of them). Index-3 generalised-alpha holds the bearings
    at position level; its rates miss their velocity-level form by ~1e-7 m/s (O(h^2)), which shows
    as a 3e-8 error of the spin ratio; projected, the rates satisfy every constraint to round-off.
    The gear residual is taken before the projection (what the integrator enforced).
    """
    s = asm.system
    row = s.multiplier_names.index("gear.normal_force_on_j")          # rows: holonomic, then velocity-level
    pos, gear = np.full(len(q), np.nan), np.full(len(q), np.nan)
    qd = qd.copy()
    for i in np.unique(rows):
        states = s.marker_states(q[i], qd[i], 0.0)
        pos[i] = np.max(np.abs(s.holonomic_residual(q[i], qd[i], 0.0, states)[0]))
        v, cq = s.velocity_residual(q[i], qd[i], 0.0, states)
        gear[i] = abs(v[row])
        if project:
            qd[i] -= np.linalg.lstsq(cq, v, rcond=None)[0]
    return pos, gear, qd


def linearised(p: Mapping[str, float], fields: tuple[str, ...], inp: Mapping[str, Array],
               dt: float) -> tuple[Assembly, Packed, StateSpace, Array, float, Array]:
    """The linear fidelity's system for parameters ``p`` and scene inputs ``inp`` (:func:`scene_inputs`):
    the assembly under the record's mean loads, packed, its state space linearised at the drive's
    mean speed over the record, the inputs ``u`` (n_t, 7), the initial spin over the operating one
    and the inputs' window (:func:`ddgsa.mbs.linear.input_window` of ``[u - mean, 1]``).

    :data:`SPEED_PASSES` linearisations: at the loads model's mean speed, then (from the second) at the
    mean speed of the previous one's response (they differ by ~0.06 %); the assembly is built once (the
    spin enters only its initial rates; its constant loads as two samples spanning the record) and a
    later operating state starts from the previous one, with its stiffness.
    """
    u = np.column_stack([inp["Fx"], inp["Fy"], inp["Fz"], inp["Mx"], inp["My"], inp["Mz"], inp["w_set"]])
    u0 = u.mean(axis=0)
    window = input_window(np.column_stack([u - u0, np.ones(len(u))]))
    const = np.ones((2, 1))
    spin = float(np.mean(inp["rotor_speed"]))
    asm = build(p, fields, inp["times"][[0, -1]], const * u0[:3], const * u0[3:6], const[:, 0] * u0[6], spin)
    s = asm.system
    packed = pack(s)
    wheel = s.index("wheel.rx")
    _, _, lin = operating_state(s, s.q0, s.qd0, s.index("hss.rx"), packed=packed)
    ss = state_space(asm, lin, packed)
    for _ in range(SPEED_PASSES - 1):
        # the mean speed of this pass's response (its only output), then the operating state there
        new = float(lin.qd0[wheel] + np.mean(reduced_response(ss, u, dt, float(inp["rotor_speed"][0]) / spin,
                                                              out=ss.rates[wheel][:, None], window=window)))
        _, _, lin = operating_state(s, lin.q0, lin.qd0 * (new / spin), s.index("hss.rx"), start=lin, packed=packed)
        ss, spin = state_space(asm, lin, packed), new
    return asm, packed, ss, u, float(inp["rotor_speed"][0]) / spin, window


def linear_records(p: Mapping[str, float], fields: tuple[str, ...], inp: Mapping[str, Array], dt: float,
                   housing_point: Array) -> dict[str, Array]:
    """The columns of :meth:`IndirectDrive.simulate` the objective functions read, of the linear fidelity.

    The reduced states of the record (:func:`~.linear.reduced_response`) give only the housing's
    coordinates and rates, the two shaft speeds and the multipliers of the gear and the bearings
    (not every coordinate, rate and multiplier of every sample, as :meth:`simulate` forms), and the
    nonlinear constraint residuals at :data:`DRIFT_SAMPLES` samples (compiled); the same numbers as
    :meth:`simulate` to round-off (tested).
    """
    asm, packed, ss, u, start, window = linearised(p, fields, inp, dt)
    s, lin = asm.system, ss.lin
    y = reduced_response(ss, u, dt, start, window=window)
    times = dt * np.arange(len(u))
    h = s.slices[id(asm.housing)]
    speeds = [s.index("wheel.rx"), s.index("hss.rx")]
    q_h = lin.q0[h] + np.outer(times, lin.qd0[h]) + y @ ss.positions[h].T
    qd = lin.qd0[[*range(h.start, h.stop), *speeds]] + y @ ss.rates[[*range(h.start, h.stop), *speeds]].T
    rows = [s.multiplier_names.index(n) for n in FORCE_MULTIPLIERS]
    du = u - u.mean(axis=0)
    mult = ss.multipliers[rows]
    lam = lin.lam0[rows] + y @ mult[:, :y.shape[1]].T + du @ mult[:, y.shape[1]:-1].T + mult[:, -1]
    cols, a_h = housing_series(asm, p, q_h, qd[:, :6], housing_point)
    cols.update(force_series(FORCE_MULTIPLIERS, lam, a_h))
    cols["lss_speed"], cols["hss_speed"], cols["housing_roll_rate"] = qd[:, 6], qd[:, 7], qd[:, 3]
    drift = np.linspace(0, len(u) - 1, DRIFT_SAMPLES).astype(int)
    gear = s.multiplier_names.index("gear.normal_force_on_j")
    residuals = [constraint_values(packed, lin.q0 + t * lin.qd0 + ss.positions @ yi, lin.qd0 + ss.rates @ yi, 0.0)
                 for t, yi in zip(times[drift], y[drift])]
    cols["position_drift"] = np.array([np.max(np.abs(r[0])) for r in residuals])
    cols["gear_drift"] = np.array([abs(r[2][gear]) for r in residuals])
    return cols


def objectives(sim: pd.DataFrame, params: Mapping[str, float], rule: str) -> dict[str, float]:
    """Objective functions of a simulated record (:data:`OUTPUTS`)."""
    return objective_values(sim, params, rule, float(sim.attrs["duration"]))


def objective_values(cols: Mapping[str, Any], params: Mapping[str, float], rule: str,
                     duration: float) -> dict[str, float]:
    """Objective functions (:data:`OUTPUTS`) of the columns ``cols`` of a record of ``duration`` [s] (a
    :meth:`IndirectDrive.simulate` frame, or the arrays of :func:`linear_records`; NaN drift samples
    are the ones not evaluated)."""
    def col(*names: str) -> Array:
        return np.column_stack([np.asarray(cols[n], dtype=float) for n in names]) if len(names) > 1 \
            else np.asarray(cols[names[0]], dtype=float)

    disp = col("housing_dx", "housing_dy", "housing_dz")
    ang = col("housing_rx", "housing_ry", "housing_rz")
    out = housing_motion_outputs(disp, ang)
    out.update(gear_force_outputs(col("gear_force"), duration))
    w_lss, w_hss = col("lss_speed"), col("hss_speed")
    w_h = col("housing_roll_rate")
    axis = rotated_x_axis(ang)                             # housing (and, to LSS bending, shaft) axis
    for b in BEARINGS:
        f = col(f"{b}_Fx", f"{b}_Fy", f"{b}_Fz")
        speed = w_lss if b == "main" else (w_lss - w_h if b.startswith("lss") else w_hss - w_h)
        out.update(bearing_outputs(b, f, axis, speed, params[f"bearing_C_{b}"], rule))
    torque = signal_statistics(col("housing_torque"))
    out["housing_torque_mean"], out["housing_torque_rms"] = float(torque["mean"]), float(torque["rms"])
    drift = {k: col(f"{k}_drift") for k in ("position", "gear")}
    out.update(constraint_drift({k: v[~np.isnan(v)] for k, v in drift.items()}))
    return {k: out[k] for k in OUTPUTS}
