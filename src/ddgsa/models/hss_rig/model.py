"""The ``hss_rig`` model: the test rig of seed 001 paper A on the multibody kernel, with sensors and faults.

Fidelities (the motor's, "model no more than a scene needs"):

``dq``
    Fifth-order dq motor (flux transients, direct-on-line inrush, supply-unbalance ripple from
    the fluxes); the rig integrated by the kernel's generalised-alpha (nonlinear, any scene).
``kloss``
    Steady equivalent-circuit torque at the instantaneous speed and supply; generalised-alpha.
``linear``
    ``kloss`` motor and the cheapest exact path each scene allows. Steady scenes: the rig
    linearised about its steady operating point (spinning, gravity sag) in non-rotating bending
    coordinates (:mod:`ddgsa.mbs.nonrotating`); when every input repeats once per revolution (the
    eccentric mass; no supply unbalance, no defect) its periodic steady state is solved harmonic by
    harmonic in the frequency domain, else it is integrated exactly from the periodic state of one
    revolution (inputs: the eccentric mass, the motor's torque ripple, the defect impacts).
    Start-up and coast-down: the rig linear about its sag as a speed sweep (the gyroscopic,
    circulatory and softening terms follow the spin; :mod:`ddgsa.models.hss_rig.transient`,
    :mod:`ddgsa.mbs.sweep`) with the ``kloss`` motor, the load law and the unbalance as nonlinear
    inputs, a coast-down starting from its periodic steady state; within 0.3 % of the nonlinear
    ``kloss`` rig on the vibration outputs at a tenth of its cost. The coupling's turning stiffness
    anisotropy would make the steady rig periodic rather than time-invariant: the linear fidelity
    builds the rig with the mean coupling and, in steady scenes, carries its action on the
    coupling's static stretch (a misalignment, the gravity sag's lift of the overhang, the torque's
    twist) as an external 2x load on the coupling (:mod:`ddgsa.models.hss_rig.faults`; refused
    where the coupling's 2x vibration is not small against the stretch); in start-up and
    coast-down the sweep carries ``dK(theta)`` on the stretch along the sweep as a nonlinear
    input (within 0.25 % of the nonlinear ``kloss`` rig with the nominal coupling). Transients
    refuse a misalignment (not checked against the nonlinear rig).

``fidelity: auto`` pilots ``linear`` against ``kloss`` (:attr:`HssRig.pilot_fidelities`): the
``dq`` machine's flux transients are a motor study's concern, and its steady runs start from the
static sag (a 2 %-damped bending mode needs about 2 s to settle), so it is chosen by name, never
by the pilot.

Scenes are :class:`~ddgsa.models.hss_rig.scenes.RigScene` (start-up, steady, coast-down).

Sensors (``simulate`` columns): housing accelerometers ``housing_{1,2}_{y,z}`` [m/s^2],
proximity probes at the disk ``disk_{y,z}`` [m] (shaft centre against the frame), the motor's
air-gap torque ``motor_torque`` [N m] and phase-a current ``motor_current`` [A], and the shaft
speed ``speed`` [rad/s] and angle ``angle`` [rad] (the once-per-revolution key). With
``noise=True`` seeded white measurement noise is added (``NOISE``; the scene's seed, so every
parameter point sees the same noise).

Outputs (on the analysed record: after ``settle`` for steady scenes, the whole record
otherwise): for every sensor ``rms_<s>`` and ``peak_<s>`` (about the record's mean),
``order1x_<s>`` and ``order2x_<s>`` (order tracking, :func:`ddgsa.models.signals.order_amplitudes`);
for the accelerometers ``bpfo_<s>`` and ``bpfi_<s>`` (mean square in +-0.25 orders around the
first three multiples of the ball-pass orders of the 6205, in the order domain so a run-up is
covered too) and ``envbpfo_<s>`` (the same BPFO band of the envelope of the record band-passed
to :data:`ENVELOPE_BAND`: envelope analysis); steady records are low-passed before the angle
resampling (:data:`ANTI_ALIAS`), so impacts do not fold into the low orders; ``torque_2f``
(motor torque at twice the supply frequency: supply unbalance), ``current_line`` (current at the
supply frequency), ``current_sideband_1x`` (mean of the current
at ``f -+ f_r``: mechanical 1x load modulation), ``current_sideband_2s`` (mean at
``f (1 -+ 2 s)``: the broken-bar band; no broken bars are modelled, it measures leakage) and
``mean_speed_rpm``. Steady records are stationary, so the frequency-domain outputs read exact
frequencies; for start-up and coast-down the time-domain ones are whole-record least-squares
fits and mean little (use ``peak_*``, the peak through resonance, and the order outputs).
"""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np
import pandas as pd
from scipy.signal import butter, sosfiltfilt

from ddgsa.errors import ModelError, SceneError
from ddgsa.mbs import AppliedLoad, genalpha, linearise_system, nonrotating
from ddgsa.mbs.campbell import CampbellDiagram, mode_row, tracked_frame
from ddgsa.mbs.compiled import evaluate
from ddgsa.mbs.beam import BEAMS
from ddgsa.mbs.bodies import MAX_BENDING_MODES
from ddgsa.mbs.modal import damped_eigen, modal_analysis
from ddgsa.mbs.sampling import AliasingWarning
from ddgsa.models.base import BAND_FACTOR, BasisRule, Model, ModelOption, ModelOutput, SignalOutput, register_model
from ddgsa.models.hss_rig import steady_block, sweep_block, transient
from ddgsa.models.hss_rig.bearing import defect_impulses, on_grid
from ddgsa.models.hss_rig.faults import anisotropy_loads, check_small, misaligned, operating_stretch
from ddgsa.models.hss_rig.drive import (FLUX_STATES, Drive, drive_for, dq_parts, kloss_along, kloss_parts,
                                        steady_flux, steady_speed)
from ddgsa.models.hss_rig.parameters import BEARING_GEOMETRY, PARAMETERS, RATED_SPEED
from ddgsa.models.hss_rig.rig import Rig, ShaftBasis, build, tangent_columns
from ddgsa.models.hss_rig.scenes import RigScene
from ddgsa.models.signals import (angle_amplitudes, angle_samples, band_energies, envelope, harmonic_amplitudes, order_map, plot_order_map,
                           plot_spectrum, record_harmonics, resample_records, resample_to_angle)

ACCELEROMETERS = ("housing_1_y", "housing_1_z", "housing_2_y", "housing_2_z")
PROBES = ("disk_y", "disk_z")
SENSORS = ACCELEROMETERS + PROBES + ("motor_torque", "motor_current")
NOISE = {"housing": 0.05, "disk": 1e-6, "motor_torque": 0.05, "motor_current": 0.02}
"""Standard deviation of the measurement noise per sensor kind [m/s^2, m, N m, A] (assumption:
industrial ICP accelerometers, eddy-current probes, a torque transducer and a current clamp)."""
_SENSOR_UNIT = {"housing": ("m/s^2", 1e3), "disk": ("m", 1e-2), "motor_torque": ("N m", 1e3),
                "motor_current": ("A", 200.0)}
"""Unit and plausible upper bound of a sensor kind (a lab-scale rig: a 3-hp motor, mm-scale shaft motion)."""
_KINDS = {"rms": "RMS about the record's mean", "peak": "peak about the record's mean",
          "order1x": "1x order amplitude (order tracking)", "order2x": "2x order amplitude (order tracking)"}


def _noise_scale(sensor: str) -> float:
    """Measurement-noise standard deviation of ``sensor`` (:data:`NOISE`)."""
    for kind in ("housing", "disk"):
        if sensor.startswith(kind):
            return NOISE[kind]
    return NOISE[sensor]


def _sensor_unit(sensor: str) -> tuple[str, float]:
    return next(v for k, v in _SENSOR_UNIT.items() if sensor.startswith(k))


_BAND_SHARE = 3 * 0.5 / 64.0
"""Share of white noise's mean square in the ball-pass bands: three bands of 0.5 orders out of the
64 orders below the angle domain's Nyquist order (:data:`SAMPLES_PER_REV` / 2)."""
_RECORD_SAMPLES = 2000
"""Samples of the shortest record the committed rig studies analyse (1.2 s at 2 kHz less the 0.2 s
settle): a statistic averaged over a record sees the noise reduced by ``sqrt(2 / n)``."""


def _resolution(sensor: str, kind: str) -> float:
    """An output's resolution (:attr:`ModelOutput.resolution`) from its sensor's noise standard deviation
    ``sd`` (:data:`NOISE`) [sensor unit]: for a record's peak the standard deviation of the largest of
    ``n`` (:data:`_RECORD_SAMPLES`) noise samples, ``sd pi / sqrt(12 ln n)`` (Gumbel's limit: 0.33 sd),
    by which the noise alone moves a peak from record to record; ``sd sqrt(2 / n)`` for a statistic
    averaged over the record -- an RMS, an order or a spectral line's amplitude; for a band energy
    [sensor unit^2] the noise's mean square in the bands (:data:`_BAND_SHARE`) times that factor.

    Examples
    --------
    >>> float(round(_resolution("housing_1_y", "peak"), 4)), float(round(_resolution("housing_1_y", "average"), 5))
    (0.0164, 0.00158)
    """
    sd = _noise_scale(sensor)
    average = np.sqrt(2.0 / _RECORD_SAMPLES)
    if kind == "peak":
        return sd * np.pi / np.sqrt(12.0 * np.log(_RECORD_SAMPLES))
    if kind == "band":
        return sd ** 2 * _BAND_SHARE * average
    return sd * average


FEATURES = tuple(ModelOutput(f"lateral_ratio_{j}", "-", f"the 1x order over the rig's {which} lateral natural "
                             "frequency at the steady speed (its linearisation about the sag, seen from the frame)")
                 for j, which in ((1, "lowest"), (2, "second")))
"""The rig's control features in a steady scene (:meth:`HssRig.control_features`): its steady outputs are
resonant (the shaft's diameter and span move the first lateral critical speed against the 1x order), and
these ratios are smooth in the parameters where the outputs are peaks."""
SWEEP_FEATURES = (
    ModelOutput("critical_ratio_1", "-", "the supply's synchronous speed over the rig's lowest lateral natural frequency "
                "at that speed (the sweep's linearisation about the sag, seen from the frame)"),
    ModelOutput("end_ratio_1", "-", "the shaft's speed at the record's end over the rig's lowest lateral natural "
                "frequency at the synchronous speed"),
)
"""The ``linear`` rig's control features in a start-up or coast-down (:meth:`HssRig.control_features`): a sweep's
vibration peaks where its speed passes the first lateral critical, and whether a coast-down's record reaches it
(``end_ratio_1`` near 1) is a threshold in the parameters that these smooth ratios place."""
OUTPUTS = tuple(ModelOutput(f"{k}_{s}", _sensor_unit(s)[0], f"{what} of sensor {s}", 0.0, _sensor_unit(s)[1],
                            _resolution(s, "peak" if k == "peak" else "average"))
                for k, what in _KINDS.items() for s in SENSORS) + tuple(
    ModelOutput(f"{k}_{s}", "m^2/s^4", f"{k.upper()} band energy of {s}: mean square in +-0.25 orders around the "
                "first three ball-pass orders of the 6205", 0.0, 1e6, _resolution(s, "band"))
    for k in ("bpfo", "bpfi") for s in ACCELEROMETERS) + tuple(
    ModelOutput(f"envbpfo_{s}", "m^2/s^4", f"BPFO band energy of the envelope of {s} band-passed to "
                "500-2000 Hz (envelope analysis; the upper end at most 0.45 of the sample rate)", 0.0, 1e6,
                _resolution(s, "band"))
    for s in ACCELEROMETERS) + (
    ModelOutput("torque_2f", "N m", "motor air-gap torque at twice the supply frequency (supply unbalance)",
                0.0, 1e3, _resolution("motor_torque", "average")),
    ModelOutput("current_line", "A", "phase current at the supply frequency", 0.0, 200.0,
                _resolution("motor_current", "average")),
    ModelOutput("current_sideband_1x", "A", "mean phase current at f -+ f_r (mechanical 1x load modulation)",
                0.0, 200.0, _resolution("motor_current", "average")),
    ModelOutput("current_sideband_2s", "A", "mean phase current at f (1 -+ 2 s) (broken-bar band; leakage here)",
                0.0, 200.0, _resolution("motor_current", "average")),
    ModelOutput("mean_speed_rpm", "rpm", "mean shaft speed over the analysed record (deterministic: the "
                "numerical floor only)", 0.0, 4000.0))
TRACK_FRACTIONS = np.round(np.arange(0.40, 0.951, 0.05), 2)
"""Grid of the 1x order tracks: shaft speeds as fractions of the scene's synchronous speed [-]."""
SIGNALS = tuple(SignalOutput(f"order1x_track_{sensor}", unit, f"1x order amplitude of {sensor} against shaft speed "
                             "through a start-up or coast-down (1-revolution blocks, interpolated onto the grid)",
                             "shaft speed", "rpm")
                for sensor, unit in (("disk_y", "m"), ("housing_1_y", "m/s^2")))
SAMPLES_PER_REV = 128
"""Angle-domain resampling of order tracking (orders up to 64)."""
ANTI_ALIAS = 0.8
"""Low-pass cutoff before angle resampling of steady records, as a fraction of the Nyquist order [-]."""
ENVELOPE_BAND = (500.0, 2000.0)
"""Band [Hz] demodulated for the envelope outputs: above the third BPFI harmonic at 1500 rpm (406 Hz),
around the housings' vertical resonance on bearing and support (about 900 Hz at the nominal values);
below a 4.4 kHz sample rate its upper end is 0.45 of the rate (500-900 Hz at 2 kHz)."""
POLE_PAIRS = 2
_SHOWN: set[tuple[str, str]] = set()
"""Warnings of :meth:`HssRig.sampling_checks` already issued in this process, as (category, message).
A study checks every batch's scene and the runner resets Python's own once-per-place memory
around each batch, so the same aliasing note came once per batch and worker; forked workers
inherit this set from the study's process, which checks the first scene before forking them."""


#: the longest generalised-alpha step [s] the rig takes when none is given (its former fixed default)
MAX_DEFAULT_STEP = 2e-4


def _rig_basis(model: "HssRig") -> dict[str, Any]:
    """The rig's shaft basis as model options."""
    b = model.basis
    return {"bending_modes": b.bending_modes, "beam": b.beam, "shaft_elements": b.elements_per_span,
            "shaft_axial": b.axial}


def _rig_band(model: "HssRig", scene: Any) -> float:
    """The rig's band of interest [Hz]: its outputs read up to the highest frequency its sampling checks
    name (3 x BPFI, 2 x the supply, the 2x order) times :data:`~ddgsa.models.base.BAND_FACTOR`, capped at
    the record's Nyquist frequency."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rows = model.sampling_checks(scene)
    return min(BAND_FACTOR * max(r["frequency_hz"] for r in rows), 0.5 * model._scene(scene).sample_rate)


BASIS_RULE = BasisRule(
    reference={"bending_modes": 10, "shaft_elements": 64, "shaft_axial": True},
    ladder=(({"bending_modes": 3}, "about +11 % time per linear steady run against 2 modes"),
            ({"bending_modes": 5, "shaft_elements": 32, "shaft_axial": True},
             "the default basis; about +27 % time per linear run and +4 to +15 % per kloss run against "
             "2 modes on 8 elements")),
    light={"bending_modes": 2, "shaft_elements": 8, "shaft_axial": False},
    fidelity="kloss", options=_rig_basis, band_hz=_rig_band,
    nominal=lambda: {p.name: p.nominal for p in PARAMETERS})
"""The rig's shaft basis rule (:mod:`ddgsa.models.basis`). Reference: 10 modes per plane on 64 elements,
axially elastic; the default 5 modes on 32 elements move by <= 0.34 % below 600 Hz against it
(docs/physics.md). Ladder costs measured on the shared 2-core machine against the light basis (load 2-3;
start-up, steady and coast-down at 1500 rpm, 1.2 s, and kloss 0.6 s records). Light: the second stage's
default, 2 modes per plane on 8 elements, axially rigid (2.5 % high on its first pair and 44 % low on the
disk's 1x amplitude at the critical speed), for studies that keep it for speed."""


@register_model("hss_rig")
class HssRig(Model):
    """High-speed-shaft test rig (seed 001 paper A) on the multibody kernel; see the module.

    Parameters
    ----------
    fidelity : str
        ``dq``, ``kloss`` or ``linear`` (``kloss`` with steady scenes linearised; see the module).
    time_step : float, optional
        Generalised-alpha step [s] (``dq``, ``kloss`` and the ``linear`` transients); the sensor interval
        must be a multiple. Default: the largest step of at most :data:`MAX_DEFAULT_STEP` that divides
        the scene's sensor interval (2e-4 s at 5 kHz, 1.67e-4 s at 2 kHz).
    noise : bool
        Add seeded measurement noise to the sensors.
    bending_modes : int
        Bending modes per plane of the high-speed shaft (default 5; docs/physics.md: convergence).
    beam : {"euler_bernoulli", "timoshenko"}
        The shaft's FE bending elements.
    shaft_elements : int
        FE elements per bearing span of the high-speed shaft (default 32).
    shaft_axial : bool
        Give the high-speed shaft an axial elastic mode (default true; false: axially rigid, its axial mode 2.7 % high).
    """

    fidelities: ClassVar[tuple[str, ...]] = ("dq", "kloss", "linear")
    pilot_fidelities: ClassVar[tuple[str, ...]] = ("kloss", "linear")
    options_note: ClassVar[str] = ("options: time_step [s] (generalised-alpha, default the largest step <= 2e-4 "
                                   "dividing the sensor interval), noise true | false; "
                                   "scenes are rig scenes: {kind: startup | steady | coastdown, speed_rpm, duration, "
                                   "sample_rate, settle, ramp_time, seed}")
    parameters = PARAMETERS
    outputs = OUTPUTS
    signal_outputs = SIGNALS
    scene_type = RigScene
    basis_rule = BASIS_RULE
    options = (ModelOption("time_step", "number", "generalised-alpha step (default: the largest step <= 2e-4 s "
                           "dividing the sensor interval)", 0.0, 1e-2, "s", low_open=True, optional=True),
               ModelOption("noise", "bool", "seeded measurement noise on the sensors"),
               ModelOption("bending_modes", "integer", "high-speed shaft bending modes per plane (default 5)",
                           1, MAX_BENDING_MODES),
               ModelOption("beam", "choice", "high-speed shaft FE bending elements", choices=BEAMS),
               ModelOption("shaft_elements", "integer", "high-speed shaft FE elements per bearing span (default 32)",
                           2, 256),
               ModelOption("shaft_axial", "bool", "axial elastic mode of the high-speed shaft (default true; false: axially rigid)"))

    def __init__(self, fidelity: str = "dq", time_step: float | None = None, noise: bool = False, bending_modes: int = 5,
                 beam: str = "euler_bernoulli", shaft_elements: int = 32, shaft_axial: bool = True) -> None:
        self.check_options({"fidelity": fidelity, "time_step": time_step, "noise": noise, "bending_modes": bending_modes,
                            "beam": beam, "shaft_elements": shaft_elements, "shaft_axial": shaft_axial})
        self.fidelity, self.noise = fidelity, noise
        self.time_step = None if time_step is None else float(time_step)
        self.basis = ShaftBasis(bending_modes, beam, shaft_elements, shaft_axial)

    # -- assembly ------------------------------------------------------------------------------
    def _scene(self, scene: Any) -> RigScene:
        if isinstance(scene, RigScene):
            return scene
        if isinstance(scene, Mapping):
            return RigScene.from_fields(scene)
        raise SceneError(f"model 'hss_rig' needs a rig scene (RigScene or a mapping of its fields), got "
                         f"{type(scene).__name__}")

    def build(self, params: Mapping[str, float] | None = None, scene: Any = None) -> tuple[Rig, Drive, float]:
        """The rig for ``params`` (missing -> nominal) in ``scene`` (a :class:`RigScene` or a mapping of
        its fields; required), its drive and its initial spin [rad/s]."""
        if scene is None:
            raise ModelError("model 'hss_rig': build needs the rig scene (its kind and speed set the drive)")
        return self._build(self.resolve(params).iloc[0].to_dict(), self._scene(scene))

    def _build(self, p: dict[str, float], scene: RigScene) -> tuple[Rig, Drive, float]:
        """:meth:`build` for a full parameter set ``p`` (resolved)."""
        drive, spin = self.drive(p, scene)
        if self.fidelity == "dq":
            parts = dq_parts(drive, steady_flux(drive, spin) if scene.kind != "startup" else None)
        else:
            parts = kloss_parts(drive)
        extras = []
        if p["defect_amplitude"] > 0.0 and scene.kind == "steady":
            extras.append(_defect_loads(p, scene, spin))
        eff = self.effective(p)
        if self.fidelity == "linear" and scene.kind == "steady" and p["coupling_asymmetry"] > 0.0:
            # the static stretch of the rig without its turning loads (a frozen snapshot is not static)
            steady = {**eff, "eccentric_mass": 0.0, "supply_unbalance": 0.0}
            plain = build(steady, kloss_parts(drive_for(steady, scene, POLE_PAIRS)), spin=spin, basis=self.basis)
            stretch = operating_stretch(plain, *self.initial_state(plain, steady))
            extras.append(anisotropy_loads(p, stretch, spin, scene.duration, 1.0 / scene.sample_rate))
        extra = (lambda markers: [e for f in extras for e in f(markers)]) if extras else None
        return build(eff, parts, spin=spin, extra=extra, basis=self.basis), drive, spin

    @staticmethod
    def drive(p: Mapping[str, float], scene: RigScene) -> tuple[Drive, float]:
        """The drive of a full parameter set ``p`` in ``scene`` and the rig's initial spin [rad/s] (0 for a
        start-up, else the steady speed)."""
        drive = drive_for(p, scene, POLE_PAIRS)
        spin = 0.0
        if scene.kind != "startup":
            spin = steady_speed(drive, p["load_torque"], p["load_speed_exponent"], RATED_SPEED)
        return drive, spin

    def effective(self, p: Mapping[str, float]) -> dict[str, float]:
        """The parameters the fidelity builds the rig with: ``linear`` takes the coupling at its
        mean stiffness (``coupling_asymmetry = 0``); in steady scenes :meth:`build` adds the
        anisotropy's action on the coupling's static stretch (misalignment, gravity sag) as an
        external 2x load (:mod:`ddgsa.models.hss_rig.faults`), in start-up and coast-down the
        sweep carries it as a turning input (:mod:`ddgsa.models.hss_rig.transient`), and
        :meth:`simulate` refuses a misalignment there (not checked against the nonlinear rig)."""
        if self.fidelity != "linear":
            return dict(p)
        return {**p, "coupling_asymmetry": 0.0}

    # -- time integration ----------------------------------------------------------------------
    def simulate(self, scene: Any, params: Mapping[str, float] | None = None) -> pd.DataFrame:
        """Sensor time series (see the module), indexed by time [s]."""
        return self._simulate(self._scene(scene), self.resolve(params).iloc[0].to_dict())

    def _simulate(self, sc: RigScene, raw: dict[str, float]) -> pd.DataFrame:
        """:meth:`simulate` for a full parameter set ``raw`` (resolved: what :meth:`evaluate` passes on)."""
        if self.fidelity == "linear" and sc.kind != "steady" and misaligned(raw):
            raise ModelError("model 'hss_rig': fidelity 'linear' carries a coupling misalignment in steady scenes "
                             f"only (not verified in a {sc.kind}); got misalignment_parallel = "
                             f"{raw['misalignment_parallel']} m, misalignment_angular = {raw['misalignment_angular']} "
                             "rad; use 'kloss' or 'dq'")
        rig, drive, spin = self._build(raw, sc)
        p = self.effective(raw)
        h = 1.0 / sc.sample_rate
        if self.fidelity == "linear" and sc.kind == "steady":
            t, q, qd = self._linear_run(rig, p, sc, spin)
            if raw["coupling_asymmetry"] > 0.0:
                check_small(rig, q, t, spin)
        else:
            step, every = self.step_for(h)
            if self.fidelity == "linear":
                # the sweep carries the coupling's anisotropy and misalignment itself, from the sag of
                # the anisotropic rig standing at hub angle 0 (as the nonlinear rig starts)
                q0, _ = self.initial_state(rig, raw)
                t, q, qd, lateral = transient.run(drive, raw, q0, sc.kind, spin, sc.duration, step, every,
                                                     self.basis)
                series = self._sensors(rig, drive, sc, t, q, qd)
                series.attrs["features"] = sweep_features(drive, lateral, float(series["speed"].iloc[-1]))
                return series
            else:
                q0, qd0 = self.initial_state(rig, p)
                if sc.kind != "startup" and self.fidelity == "kloss":
                    q0, qd0 = self.periodic_state(rig, q0, qd0, spin)
                run = genalpha.simulate(rig.system, sc.duration, step, q0=q0, qd0=qd0,
                                        output_every=every)
                t, q, qd = run.t, run.q, run.qd
        return self._sensors(rig, drive, sc, t, q, qd)

    def step_for(self, interval: float) -> tuple[float, int]:
        """The generalised-alpha step [s] for a sensor interval [s] and the steps per interval: the
        ``time_step`` given (the interval must be a multiple of it), else the largest step of at most
        :data:`MAX_DEFAULT_STEP` that divides the interval.

        Examples
        --------
        >>> HssRig().step_for(5e-4)           # 2 kHz sensors: three steps a sample
        (0.00016666666666666666, 3)
        >>> HssRig(time_step=2.5e-4).step_for(5e-4)
        (0.00025, 2)
        """
        if self.time_step is None:
            every = max(1, math.ceil(interval / MAX_DEFAULT_STEP * (1.0 - 1e-9)))
            return interval / every, every
        every = int(round(interval / self.time_step))
        if every < 1 or abs(every * self.time_step - interval) > 1e-9 * interval:
            raise ModelError(f"model 'hss_rig': the sensor interval 1/sample_rate = {interval:.6g} s must be a multiple "
                             f"of time_step = {self.time_step:g} s (or leave time_step out: the largest step of at most "
                             f"{MAX_DEFAULT_STEP:g} s that divides the interval)")
        return self.time_step, every

    @staticmethod
    def initial_state(rig: Rig, p: Mapping[str, float], tangents: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """The rig's initial state with the static gravity sag (from the rig at rest, motor and load off).

        Spin rates and flux states are the rig's own (:meth:`build`); the sag is solved on the
        linearised rig standing still, so a run starts without a gravity transient (``tangents``: on
        :func:`still_rig`'s stiffness with the kernel's tangents where they are exact, as the block path).
        """
        sag = _sag(still_key(p), rig.basis, tangents)
        q0 = rig.system.q0.copy()
        q0[: sag.size] += sag
        return q0, rig.system.qd0.copy()

    @staticmethod
    def periodic_state(rig: Rig, q0: np.ndarray, qd0: np.ndarray, spin: float) -> tuple[np.ndarray, np.ndarray]:
        """The state at ``t = 0`` of the steady unbalance response at ``spin`` [rad/s] about ``(q0, qd0)``.

        The rig linearised in non-rotating coordinates, its eccentric mass solved in the
        frequency domain (:func:`ddgsa.mbs.nonrotating.periodic`): a ``kloss`` steady scene or
        coast-down then starts in the steady state instead of ringing from the static sag for
        seconds (the 2 %-damped bending mode). Exact for the ``linear`` fidelity's rig; for
        ``kloss`` the coupling's turning anisotropy and a misalignment are left out of this start
        (their 2x part rings in).
        """
        system = rig.system
        lin = nonrotating.linearise(system, q0, qd0)
        unbalance = [e for e in system.elements if e.name == "unbalance"]
        _, q, qd = nonrotating.periodic(system, lin, 0.0, 1.0, unbalance, 2 * math.pi / spin)
        return q[0], qd[0]

    def _linear_run(self, rig: Rig, p: Mapping[str, float], sc: RigScene, spin: float,
                    harmonic: bool | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The linear fidelity's record: in the frequency domain (:func:`ddgsa.mbs.nonrotating.periodic`)
        when every input repeats once per revolution (``harmonic=None``: no supply unbalance, no
        defect), else by exact time integration (:func:`ddgsa.mbs.nonrotating.simulate`); both start
        from the periodic state of one revolution."""
        system = rig.system
        varying = [e for e in system.elements if e.name in ("unbalance", "motor", "defect_housing", "defect_shaft",
                                                             "anisotropy_hub", "anisotropy_shaft")]
        q0, qd0 = self.initial_state(rig, p)
        lin = nonrotating.linearise(system, q0, qd0)
        if harmonic is None:
            harmonic = p["supply_unbalance"] == 0.0 and p["defect_amplitude"] == 0.0
        run = nonrotating.periodic if harmonic else nonrotating.simulate
        return run(system, lin, sc.duration, 1.0 / sc.sample_rate, varying, 2 * math.pi / spin)

    def _sensors(self, rig: Rig, drive: Drive, sc: RigScene, t: np.ndarray, q: np.ndarray,
                 qd: np.ndarray) -> pd.DataFrame:
        system = rig.system
        out: dict[str, np.ndarray] = {}
        for i in (1, 2):
            for ax in ("y", "z"):
                out[f"housing_{i}_{ax}"] = np.gradient(qd[:, system.index(f"housing_{i}.{ax}")], t, edge_order=2)
        disk = system.positions(rig.markers["disk"], q, qd, t)
        out["disk_y"], out["disk_z"] = disk[:, 1], disk[:, 2]
        speed = qd[:, system.index("hss.rx")]
        motor_speed = qd[:, system.index("motor.rx")]
        if self.fidelity == "dq":
            flux = qd[:, [system.index(f"flux.{s}") for s in FLUX_STATES]]
            el = next(e for e in system.elements if e.name == "motor")
            torque, current = [], []
            for ti, psi, w in zip(t, flux, motor_speed):
                torque.append(el.rates(ti, psi, w)[1])
                current.append(el.phase_current(ti, psi))
            out["motor_torque"], out["motor_current"] = np.array(torque), np.array(current)
        else:
            out["motor_torque"], out["motor_current"] = kloss_along(drive, t, motor_speed)
        if self.noise:
            rng = np.random.default_rng(np.random.SeedSequence([sc.seed, 13]))
            for s in SENSORS:
                out[s] = out[s] + _noise_scale(s) * rng.standard_normal(t.size)
        out["speed"] = speed
        out["angle"] = q[:, system.index("hss.rx")]
        return pd.DataFrame(out, index=pd.Index(t, name="time"))

    # -- objectives ----------------------------------------------------------------------------
    def _evaluate_one(self, params: dict[str, float], scene: Any) -> dict[str, float]:
        sc = self._scene(scene)
        series = self._simulate(sc, params)
        out = objectives(series, sc, drive_for(params, sc, POLE_PAIRS))
        if "features" in series.attrs:
            out.update(series.attrs["features"])
        elif self.control_features(sc):
            out.update(zip(map(str, FEATURES), self._lateral_ratios(params, sc)))
        return out

    def control_features(self, scene: Any) -> tuple[ModelOutput, ...]:
        """:data:`FEATURES` in a steady scene (the 1x order over the lowest lateral natural frequencies at the
        steady speed, which set the resonant steady responses); :data:`SWEEP_FEATURES` in the ``linear``
        fidelity's start-up and coast-down (the synchronous and the record's last speed over the lowest lateral
        natural frequency, from the sweep's own linearisation); none in the other fidelities' sweeps."""
        if self._scene(scene).kind == "steady":
            return FEATURES
        return SWEEP_FEATURES if self.fidelity == "linear" else ()

    def _lateral_ratios(self, raw: dict[str, float], sc: RigScene) -> np.ndarray:
        """:data:`FEATURES` of one point (resolved ``raw``) in the steady scene ``sc``: the rig without its
        turning loads, linearised about its sag at the steady speed as the block path's
        (:mod:`~ddgsa.models.hss_rig.steady_block`), with the ``kloss`` motor at every fidelity (as :meth:`modes`).
        At ``kloss`` and ``dq`` the coupling keeps its two-fold anisotropy, taken at its angle at ``t = 0`` (a
        snapshot of a periodic system: the two ratios split, 1.273 and 1.243 at the nominal point against
        the ``linear`` rig's 1.257 and 1.256)."""
        drive = drive_for(raw, sc, POLE_PAIRS)
        spin = steady_speed(drive, raw["load_torque"], raw["load_speed_exponent"], RATED_SPEED)
        plain = {**self.effective(raw), "eccentric_mass": 0.0}
        rig = build(plain, kloss_parts(drive), spin=spin, basis=self.basis)
        q0, qd0 = self.initial_state(rig, plain, tangents=True)
        lin = nonrotating.linearise(rig.system, q0, qd0, tangent_columns=tangent_columns(rig.system))
        return spin / nonrotating.lateral_frequencies(rig.system, lin, len(FEATURES))

    def evaluate(self, points: Any, scene: Any, signals: tuple[str, ...] = ()) -> pd.DataFrame:
        """Objective functions (and ``signals``) at each point for a rig scene (see :meth:`Model.evaluate`)."""
        sc = self._scene(scene)
        self.sampling_checks(sc)                             # refuses an aliased record before running
        return super().evaluate(points, sc, signals)

    @property
    def block_parts(self) -> dict[str, Any]:
        """What the block paths (:mod:`~ddgsa.models.hss_rig.steady_block`, :mod:`~ddgsa.models.hss_rig.sweep_block`)
        take from this module: the pole
        pairs, the rig at rest (``still_key``, ``still_rig``), the sensors, their objectives and the sweeps' control
        features -- handed
        over, so that module needs no import of this one (which imports it)."""
        return {"pole_pairs": POLE_PAIRS, "still_key": still_key, "still_rig": still_rig, "sensors": SENSORS,
                "record_objectives": record_objectives, "objectives": objectives, "samples_per_rev": SAMPLES_PER_REV,
                "sweep_features": sweep_features}

    def _evaluate_block(self, params: pd.DataFrame, scene: Any, signals: tuple[str, ...] = ()) -> pd.DataFrame:
        """The block's outputs: the ``linear`` fidelity's steady points whose inputs repeat once per
        revolution at once (:mod:`ddgsa.models.hss_rig.steady_block`), its start-up and coast-down points
        on sweeps reduced to the scene's band (:mod:`ddgsa.models.hss_rig.sweep_block`), the others one by one
        (:meth:`Model._evaluate_block`); ``attrs["block_points"]`` counts the first two."""
        sc = self._scene(scene)
        path = steady_block if sc.kind == "steady" else sweep_block
        block = path.holds(self, params, sc, signals)
        if not block.any():
            out = super()._evaluate_block(params, sc, signals)
        else:
            run = steady_block.steady_block if sc.kind == "steady" else sweep_block.sweep_block
            out = run(self, params[block].reset_index(drop=True), sc)
            if not block.all():
                rest = super()._evaluate_block(params[~block].reset_index(drop=True), sc, signals)
                rows = np.concatenate([np.flatnonzero(block), np.flatnonzero(~block)])
                order = np.argsort(rows, kind="stable")
                failures = {int(rows[i]): why for i, why in out.attrs["failures"].items()}
                failures.update({int(rows[block.sum() + i]): why for i, why in rest.attrs["failures"].items()})
                features = {f: tuple(np.asarray(v + rest.attrs["features"][f])[order].tolist())
                            for f, v in out.attrs.get("features", {}).items()}
                out.attrs, rest.attrs = {}, {}
                out = pd.concat([out, rest], ignore_index=True).iloc[order].reset_index(drop=True)
                out.attrs["failures"] = dict(sorted(failures.items()))
                if features:
                    out.attrs["features"] = features
        out.attrs["block_points"] = int(block.sum())
        return out

    def signal_axis(self, name: str, scene: Any) -> np.ndarray:
        """Shaft speeds [rpm] of the 1x order tracks: :data:`TRACK_FRACTIONS` of the synchronous speed;
        start-up and coast-down scenes only (a steady record has one speed)."""
        self.signal_output(name)
        sc = self._scene(scene)
        if sc.kind == "steady":
            raise ModelError(f"model 'hss_rig': signal {name!r} is a track against speed; it needs a startup or "
                             "coastdown scene, got kind steady")
        return TRACK_FRACTIONS * sc.speed_rpm

    def _evaluate_signals_one(self, params: dict[str, float], scene: Any,
                              signals: tuple[str, ...]) -> tuple[dict[str, float], dict[str, np.ndarray]]:
        """Outputs and 1x order tracks of one run: the 1x amplitude of 1-revolution blocks
        (:func:`ddgsa.models.signals.order_map`) at the blocks' mean speeds, interpolated onto :meth:`signal_axis`."""
        sc = self._scene(scene)
        series = self._simulate(sc, params)
        scalars = objectives(series, sc, drive_for(params, sc, POLE_PAIRS))
        t, angle = series.index.to_numpy(), series["angle"].to_numpy()
        tracks = {}
        for name in signals:
            speed, orders, amp = order_map(t, series[name.removeprefix("order1x_track_")].to_numpy(), angle,
                                           revs_per_block=1, samples_per_rev=SAMPLES_PER_REV)
            order = np.argsort(speed)
            tracks[name] = np.interp(self.signal_axis(name, sc), speed[order], amp[order, int(np.argmin(abs(orders - 1)))])
        return scalars, tracks

    def modes(self, params: Mapping[str, float] | None = None, rotor_speed: float = 0.0) -> pd.DataFrame:
        """Damped modes of the rig spinning at ``rotor_speed`` [rad/s] (0: standing still), labelled.

        Linearised about the static sag in non-rotating bending coordinates
        (:mod:`ddgsa.mbs.nonrotating`), so the frequencies are those seen from the frame (a
        Campbell diagram: ``ddgsa modes hss_rig --campbell``); the motor at ``kloss`` with its
        supply at the synchronous frequency of ``rotor_speed`` (its slope damps the torsion).
        With the spin stiffening of the disk and hubs (:func:`ddgsa.mbs.nonrotating.spin_stiffness`;
        the time-domain fidelities do not carry it, docs/physics.md gives its size).
        """
        p = self.resolve(params).iloc[0].to_dict()
        rpm = max(abs(rotor_speed) * 30.0 / math.pi, 60.0)
        drive = drive_for(p, RigScene("steady", speed_rpm=rpm, duration=10.0), POLE_PAIRS)
        rig = build(p, kloss_parts(drive), spin=rotor_speed, basis=self.basis)
        q0, qd0 = self.initial_state(rig, p)
        lin = nonrotating.linearise(rig.system, q0, qd0, spin_stiffening=True)
        return modal_analysis(lin.m, lin.c, lin.k, rig.system.coord_names, rig.system.groups())

    def campbell(self, speeds: Any, orders: Any = (1.0, 2.0), params: Mapping[str, float] | None = None,
                 max_frequency_hz: float = 150.0) -> CampbellDiagram:
        """Campbell diagram of the rig seen from the frame: the modes of :meth:`modes` at each of
        ``speeds`` [rad/s], those below ``max_frequency_hz`` [Hz] at standstill (the band the
        orders up to 2x and the supply reach), with their whirl from the non-rotating shapes
        (:func:`ddgsa.mbs.nonrotating.whirl_index`), each branch followed across speeds by its
        shape (:func:`ddgsa.mbs.campbell.track`, modal assurance criterion). ``ddgsa modes hss_rig --campbell`` calls it.
        """
        p = self.resolve(params).iloc[0].to_dict()
        per_speed = []
        for speed in np.sort(np.asarray(speeds, dtype=float)):
            rpm = max(abs(speed) * 30.0 / math.pi, 60.0)
            drive = drive_for(p, RigScene("steady", speed_rpm=rpm, duration=10.0), POLE_PAIRS)
            rig = build(p, kloss_parts(drive), spin=float(speed), basis=self.basis)
            lin = nonrotating.linearise(rig.system, *self.initial_state(rig, p), spin_stiffening=True)
            lam, vec = damped_eigen(lin.m, lin.c, lin.k)
            labels = modal_analysis(lin.m, lin.c, lin.k, rig.system.coord_names, rig.system.groups())["label"]
            per_speed.append(([mode_row(speed, j + 1, lam[j], *nonrotating.whirl_index(rig.system, lin, vec[:, j]),
                                        labels.iloc[j]) for j in range(lam.size)], vec))
        frame = tracked_frame(per_speed)
        first = frame[frame["speed_rad_s"] == frame["speed_rad_s"].min()]
        keep = first.loc[first["frequency_hz"] < max_frequency_hz, "mode"]
        return CampbellDiagram(frame[frame["mode"].isin(keep)].reset_index(drop=True),
                               tuple(float(o) for o in orders), max_frequency_hz)

    def scene_figures(self, scene: Any, params: Mapping[str, float] | None = None) -> list[tuple[Any, str]]:
        """Signal plots of one run at ``params`` (a study's report draws them at its nominal point).

        Start-up and coast-down: order maps (2-revolution blocks, :func:`ddgsa.models.signals.order_map`)
        of the housing-1 vertical accelerometer and the disk probe against shaft speed. Steady:
        spectra of the analysed record with the orders, ball-pass frequencies, the supply frequency
        and its 1x sidebands marked (:func:`ddgsa.models.signals.plot_spectrum`). Returns ``(figure, name)``.
        """
        import matplotlib.pyplot as plt

        sc = self._scene(scene)
        s = self.simulate(sc, params)
        if sc.kind == "steady":
            s = s[s.index >= sc.settle - 1e-12]
        t, angle = s.index.to_numpy(), s["angle"].to_numpy()
        f_r = float(s["speed"].mean()) / (2 * math.pi)
        title = f"{sc.kind} at {sc.speed_rpm:g} rpm synchronous"
        figs = []
        if sc.kind != "steady":
            for sensor in ("housing_1_y", "disk_y"):
                speed, orders, amp = order_map(t, s[sensor].to_numpy(), angle, revs_per_block=2)
                fig, ax = plt.subplots(figsize=(7, 4.5))
                plot_order_map(speed, orders, amp, max_order=8.0, ax=ax, unit=f"[{_sensor_unit(sensor)[0]}]")
                ax.set_title(f"{sensor}, {title}", fontsize=9)
                figs.append((fig, f"order_map_{sensor}"))
            return figs
        supply = drive_for(self.resolve(params).iloc[0].to_dict(), sc, POLE_PAIRS).motor.supply_frequency
        marks = {"housing_1_y": {"1x": f_r, "2x": 2 * f_r, "BPFO": float(BEARING_GEOMETRY.bpfo(f_r)),
                                 "BPFI": float(BEARING_GEOMETRY.bpfi(f_r))},
                 "disk_y": {"1x": f_r, "2x": 2 * f_r},
                 "motor_current": {"f": supply, "f-fr": supply - f_r, "f+fr": supply + f_r}}
        for sensor, mark in marks.items():
            fig, ax = plt.subplots(figsize=(7, 4))
            reads = ENVELOPE_BAND[1] if sensor.startswith("housing") else 1.3 * max(mark.values())
            plot_spectrum(t, s[sensor].to_numpy(), mark, max_hz=min(0.5 * sc.sample_rate, reads), ax=ax,
                          unit=f"[{_sensor_unit(sensor)[0]}]")
            ax.set_title(f"{sensor}, {title}", fontsize=9)
            figs.append((fig, f"spectrum_{sensor}"))
        return figs

    def sampling_checks(self, scene: Any) -> list[dict[str, Any]]:
        """The sensor sample interval against the frequencies the outputs read (at the synchronous speed).

        Refuses an aliased record (:class:`~ddgsa.errors.ModelError`) at every call; each distinct
        :class:`~ddgsa.mbs.sampling.AliasingWarning` is issued once per process (:data:`_SHOWN`;
        the caller's warning filters then apply as usual, and a message they hide counts as
        issued), so a study's batches and workers do not repeat it (its sampling table keeps every
        row); other warnings pass as they come.
        """
        sc = self._scene(scene)
        f_r = sc.speed_hz
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", AliasingWarning)
            rows = sc.sampling_checks({"2 x supply frequency": 2 * POLE_PAIRS * f_r,
                                       "3 x BPFI": 3 * float(BEARING_GEOMETRY.bpfi(f_r)),
                                       "2x order": 2 * f_r})
        for w in caught:
            key = (w.category.__name__, str(w.message))
            if not issubclass(w.category, AliasingWarning):
                warnings.warn(w.message, stacklevel=2)          # anything else: as it came
            elif key not in _SHOWN:
                _SHOWN.add(key)
                warnings.warn(w.message, stacklevel=2)
        return rows


_NO_TURNING_LOADS = {"eccentric_mass": 0.0, "supply_unbalance": 0.0}
"""Parameters that put no force on the rig at rest: the sag is the same without them (cached once)."""


def _sag(items: tuple[tuple[str, float], ...], basis: ShaftBasis, tangents: bool = False) -> np.ndarray:
    """Static gravity sag (n_still,) of the rig at rest, motor and load off, for parameters ``items``
    (the sorted parameter items): :func:`still_rig`'s first part."""
    return still_rig(items, basis, tangents)[0]


@functools.lru_cache(maxsize=8)
def still_rig(items: tuple[tuple[str, float], ...], basis: ShaftBasis,
              tangents: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Static gravity sag (n_still,) of the rig at rest, motor and load off, for parameters ``items``
    (the sorted parameter items), and the stiffness (n, n) it was solved with (kept for the few calls of
    one run: an assembly, its steady stretch, its start; the block path's chord iteration takes the
    stiffness as its tangent). ``tangents``: the stiffness's :func:`~ddgsa.models.hss_rig.rig.tangent_columns`
    are the kernel's tangents, the others central differences (the block path's: half the residual calls;
    the sag then differs from the all-differenced one by the differences' round-off), and every column a
    tangent where no element is loaded at rest (no misalignment: no geometric term to miss, as
    :func:`~ddgsa.models.hss_rig.steady_block._at_rest`), on the compiled path (a rig whose Python elements
    push at rest is differenced whole)."""
    still = build(dict(items), lambda marker: ([], []), spin=0.0, basis=basis)
    # the rig's parts are all compiled (the unbalance and the load law since issue 24); a Python element
    # added to it would be checked here: one that puts no force on the rig at rest for any position
    # leaves the packed part's stiffness the same, in compiled code
    system, hybrid = still.system, still.system.fast_terms
    idle = all(not np.any(el.wrench(0.0, system.states_of(el.markers, system.q0, system.qd0, 0.0))[0])
               for _, el in hybrid.python)
    columns: Any = ()
    if tangents and idle:                 # nothing loaded at rest: no geometric term, every column a tangent
        loaded = np.any(evaluate(hybrid.packed, system.q0, np.zeros(system.n), 0.0)[4])
        columns = tangent_columns(system) if loaded else np.arange(system.n)
    lin = linearise_system(system, compiled=hybrid.packed if idle else False, static=True, tangent_columns=columns)
    sag = lin.basis @ np.linalg.lstsq(lin.k, lin.r0, rcond=None)[0]
    sag.flags.writeable = False
    k = lin.basis @ lin.k @ lin.basis.T
    k.flags.writeable = False
    return sag, k


def still_key(p: Mapping[str, float]) -> tuple[tuple[str, float], ...]:
    """The key of :func:`still_rig` for parameters ``p``: their sorted items without the turning loads."""
    return tuple(sorted({**p, **_NO_TURNING_LOADS}.items()))


def _defect_loads(p: Mapping[str, float], scene: RigScene, spin: float):
    """Outer-race defect impacts in bearing 2: downwards on the housing, upwards on the shaft.

    The half-sine pulses are projected onto the sensor grid keeping each impulse
    (:func:`~ddgsa.models.hss_rig.bearing.on_grid`), so the outputs converge with the sample rate
    instead of catching or missing pulses shorter than a sample interval. The impacts follow the
    steady shaft angle ``spin t``; in start-up and coast-down scenes the defect is not modelled
    (its timing would need the speed history the run computes).
    """
    width, step = p["defect_pulse_width"], 1.0 / scene.sample_rate
    dt = min(width, step) / 16.0
    t_fine = np.arange(0.0, scene.duration + 3 * step, dt)
    f = defect_impulses(t_fine, spin * t_fine, BEARING_GEOMETRY, p["defect_amplitude"], width, seed=scene.seed)
    t = step * np.arange(int(round(scene.duration / step)) + 3)
    force = np.zeros((t.size, 3))
    force[:, 2] = -on_grid(f, dt, step, t.size)

    def loads(markers: dict) -> list:
        return [AppliedLoad(markers["housing_2"], t, force, name="defect_housing"),
                AppliedLoad(markers["bearing_2"], t, -force, name="defect_shaft")]
    return loads


def _anti_alias(t: np.ndarray, f_r: float):
    """Zero-phase low-pass (8th-order Butterworth) at :data:`ANTI_ALIAS` of the angle domain's
    Nyquist order at the shaft speed ``f_r`` [Hz], or the identity where the sensor's own Nyquist
    frequency lies below it: resampling to :data:`SAMPLES_PER_REV` samples a revolution folds an
    impact's kHz content into the low orders otherwise (an order tracker filters first too)."""
    fs = (t.size - 1) / (t[-1] - t[0])
    cutoff = ANTI_ALIAS * SAMPLES_PER_REV / 2 * f_r
    if cutoff >= 0.5 * fs:
        return lambda x: x
    sos = butter(8, cutoff, fs=fs, output="sos")
    return lambda x: sosfiltfilt(sos, x, axis=0)


def _envelope_bpfo(t: np.ndarray, x: np.ndarray, angle: np.ndarray) -> float | np.ndarray:
    """BPFO band energy of the envelope of ``x`` band-passed to :data:`ENVELOPE_BAND` (bearing
    envelope analysis, Randall & Antoni 2011 §3), in the order domain; each end of the band held
    below the sensor's Nyquist frequency (at most 0.2 and 0.45 of the sample rate). ``x`` (n,): a
    float; ``x`` (n, m): one per column (m,)."""
    return _order_bpfo(t, _band_envelope(t, x), angle)


def _band_envelope(t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """The envelope of ``x`` (n,) or (n, m) band-passed to :data:`ENVELOPE_BAND` (see :func:`_envelope_bpfo`)."""
    fs = (t.size - 1) / (t[-1] - t[0])
    return envelope(t, x, (min(ENVELOPE_BAND[0], 0.2 * fs), min(ENVELOPE_BAND[1], 0.45 * fs)))


def _order_bpfo(t: np.ndarray, env: np.ndarray, angle: np.ndarray) -> float | np.ndarray:
    """The BPFO band energy of envelopes ``env`` at ``t`` [s] in the order domain of the shaft ``angle`` [rad]."""
    phi, y = resample_to_angle(t, env, angle, SAMPLES_PER_REV)
    return _bpfo_band(phi / (2 * math.pi), y)


def _bpfo_band(cycles: np.ndarray, env: np.ndarray) -> float | np.ndarray:
    """The BPFO band energy (3 harmonics, +-0.25 orders) of envelopes ``env`` (n,) or (n, m) at shaft ``cycles``
    [revolutions]: the envelope outputs' (:func:`record_objectives`) and :func:`_order_bpfo`'s."""
    return band_energies(cycles, env, [float(BEARING_GEOMETRY.bpfo())], 0.25, harmonics=3)[0]


def sweep_features(drive: Drive, lateral: float, end_speed: float) -> dict[str, float]:
    """:data:`SWEEP_FEATURES` of one sweep: the supply's synchronous speed and the shaft's speed at the record's end
    ``end_speed`` [rad/s] over the rig's lowest lateral natural frequency ``lateral`` [rad/s]
    (:attr:`~ddgsa.models.hss_rig.transient.Sweep.lateral`)."""
    ratios = (transient.synchronous_speed(drive) / lateral, end_speed / lateral)
    return {str(f): float(r) for f, r in zip(SWEEP_FEATURES, ratios)}


def objectives(series: pd.DataFrame, scene: RigScene, drive: Drive) -> dict[str, float]:
    """The model's outputs (see the module) from its sensor series in ``scene``."""
    t_all = series.index.to_numpy()
    keep = t_all >= (scene.settle if scene.kind == "steady" else 0.0) - 1e-12
    s = series.loc[keep]
    xs = np.column_stack([s[name].to_numpy() for name in SENSORS])[:, None, :]
    f_r = float(np.mean(s["speed"])) / (2 * math.pi)
    return record_objectives(s.index.to_numpy(), xs, s["angle"].to_numpy(), f_r, scene, drive)[0]


def record_objectives(t: np.ndarray, xs: np.ndarray, angle: np.ndarray, f_r: float | np.ndarray, scene: RigScene,
                      drive: Drive, in_angle: np.ndarray | None = None) -> list[dict[str, float]]:
    """The outputs of ``P`` analysed records that share their times ``t`` [s] (n_t,) and motor: ``xs``
    (n_t, P, len(SENSORS)) the sensors in :data:`SENSORS` order, the shaft ``angle`` [rad] (n_t,) and speed
    ``f_r`` [Hz] shared (a steady block), or one per record, (n_t, P) and (P,) (start-ups and coast-downs).
    Every signal operation runs once on all the records' columns (one record: :func:`objectives`; a block of
    points: :mod:`ddgsa.models.hss_rig.steady_block`, :mod:`ddgsa.models.hss_rig.sweep_block`): records with their
    own angles are resampled together (:func:`~ddgsa.models.signals.resample_records`), and their order amplitudes
    and bands taken once for each count of whole revolutions among them.

    ``in_angle`` (n_phi, P, len(SENSORS)): the records in the order domain where the caller has them as
    functions of a shared ``angle`` (a steady block's harmonics), at
    :func:`~ddgsa.models.signals.angle_samples` of it with :data:`SAMPLES_PER_REV`: taken for their order
    amplitudes and ball-pass bands instead of the anti-aliased, resampled ``xs`` (the envelopes are still
    resampled: they are made from the time records)."""
    n_t, n_rec, n_s = xs.shape
    if in_angle is not None and np.ndim(angle) != 1:
        raise ValueError("record_objectives: records in the order domain need one shared shaft angle")
    flat = xs.reshape(n_t, n_rec * n_s)
    smooth = _anti_alias(t, float(np.mean(f_r))) if scene.kind == "steady" else (lambda x: x)
    bpfo, bpfi = float(BEARING_GEOMETRY.bpfo()), float(BEARING_GEOMETRY.bpfi())
    acc = (np.arange(n_rec)[:, None] * n_s + np.arange(len(ACCELEROMETERS))).ravel()   # the accelerometers lead SENSORS
    angles = np.asarray(angle, dtype=float)
    env_t = _band_envelope(t, flat[:, acc])                                   # every record's at once
    n_a = len(ACCELEROMETERS)
    amps, bands = np.empty((2, n_rec, n_s)), np.empty((2, n_rec, n_a))
    env = np.empty((n_rec, n_a))
    # the order domain: the records (and their envelopes) at uniform shaft angles in one pass, then each set of
    # records with as many whole revolutions at once
    env_t = env_t.reshape(n_t, n_rec, n_a)
    if angles.ndim == 1:
        phi = angle_samples(angles, SAMPLES_PER_REV)
        counts = np.full(n_rec, phi.size)
        ys = (in_angle if in_angle is not None
              else resample_to_angle(t, smooth(flat), angles, SAMPLES_PER_REV)[1].reshape(phi.size, n_rec, n_s))
        env_a = resample_to_angle(t, env_t.reshape(n_t, -1), angles, SAMPLES_PER_REV)[1].reshape(phi.size, n_rec, n_a)
    else:
        phi, ys, counts = resample_records(t, smooth(xs), angles, SAMPLES_PER_REV)
        env_a = resample_records(t, env_t, angles, SAMPLES_PER_REV)[1]
    cycles = phi / (2 * math.pi)
    for n_phi in np.unique(counts):
        recs = np.flatnonzero(counts == n_phi)
        on = ys[:n_phi, recs]
        amps[:, recs] = angle_amplitudes(phi[:n_phi], on.reshape(n_phi, -1), [1.0, 2.0]).reshape(2, recs.size, n_s)
        bands[:, recs] = band_energies(cycles[:n_phi], on[:, :, :n_a].reshape(n_phi, -1), [bpfo, bpfi], 0.25,
                                       harmonics=3).reshape(2, recs.size, n_a)
        env[recs] = _bpfo_band(cycles[:n_phi], env_a[:n_phi, recs].reshape(n_phi, -1)).reshape(recs.size, n_a)
    dev = xs - xs.mean(axis=0)
    rms, peak = np.sqrt(np.mean(dev**2, axis=0)), np.max(np.abs(dev), axis=0)
    f = drive.motor.supply_frequency
    speeds = np.broadcast_to(np.asarray(f_r, dtype=float), (n_rec,))
    torque, cur = xs[:, :, SENSORS.index("motor_torque")], xs[:, :, SENSORS.index("motor_current")]
    torque_2f = harmonic_amplitudes(t, torque, [2 * f])[0]
    slip = 1.0 - speeds * drive.motor.pole_pairs / f                  # the current's lines and sidebands, each
    lines = record_harmonics(t, cur, np.column_stack([np.full(n_rec, f), f - speeds, f + speeds]))  # record's speed
    slips = record_harmonics(t, cur, np.column_stack([np.full(n_rec, f), f * (1 - 2 * slip), f * (1 + 2 * slip)]))[1:]
    outs = []
    for r in range(n_rec):
        out: dict[str, float] = {}
        for j, name in enumerate(SENSORS):
            out[f"rms_{name}"], out[f"peak_{name}"] = float(rms[r, j]), float(peak[r, j])
            out[f"order1x_{name}"], out[f"order2x_{name}"] = float(amps[0, r, j]), float(amps[1, r, j])
            if j < len(ACCELEROMETERS):
                out[f"bpfo_{name}"], out[f"bpfi_{name}"] = float(bands[0, r, j]), float(bands[1, r, j])
                out[f"envbpfo_{name}"] = float(env[r, j])
        out["torque_2f"] = float(torque_2f[r])
        out["current_line"] = float(lines[0, r])
        out["current_sideband_1x"] = float(0.5 * (lines[1, r] + lines[2, r]))
        out["current_sideband_2s"] = float(np.mean(slips[:, r]))
        out["mean_speed_rpm"] = float(speeds[r]) * 60.0
        outs.append(out)
    return outs
