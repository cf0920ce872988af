"""Scenes of the test rig: start-up, steady state at a speed, coast-down (the wind ``Scene`` does not fit).

A rig scene says what the motor's supply does and how the sensors are recorded:

``startup``
    From rest, the motor is switched on at ``t = 0``: direct-on-line at the supply frequency of
    ``speed_rpm`` (``ramp_time = 0``) or through a frequency converter ramping from 0 to it in
    ``ramp_time`` seconds at constant V/f. The record covers the run-up through the rig's
    lateral critical speed where that lies below ``speed_rpm``.
``steady``
    The supply frequency is held at the synchronous frequency of ``speed_rpm``; the rig starts
    at its steady operating point and runs ``settle`` seconds before the analysed record of
    ``duration - settle`` seconds (order amplitudes, sidebands, band energies).
``coastdown``
    Shut-down: the rig runs steadily at ``speed_rpm`` until ``t = 0``, then the supply is cut
    and the load brakes the rotor for ``duration`` seconds.

``speed_rpm`` is the **synchronous** speed ``60 f / p`` of the supply frequency (what the
converter is set to); the shaft turns slower by the motor's slip. ``sample_rate`` is the
sensors' sampling rate; :meth:`RigScene.sampling_checks` applies the aliasing guard of
:mod:`ddgsa.mbs.sampling` to the frequencies the model says it must resolve (modes, orders,
bearing defect frequencies, supply harmonics). ``seed`` seeds the measurement noise and the
defect-impact jitter; all parameter points of a scene see the same noise (common random numbers).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, fields
from typing import Any, ClassVar

from ddgsa.errors import SceneError, with_hint
from ddgsa.loads.scene import Interval
from ddgsa.mbs.sampling import check_interval, sampling_row

KINDS = ("startup", "steady", "coastdown")
MIN_STEADY_REVS = 8
"""Whole shaft revolutions the analysed steady record must hold (order resolution 1/8)."""
MIN_SAMPLES = 64
"""Samples a record must hold (``duration * sample_rate``)."""
RIG_SCENE_LIMITS = {"speed_rpm": Interval(0.0, 6000.0, low_closed=False), "duration": Interval(0.0, low_closed=False),
                    "sample_rate": Interval(0.0, low_closed=False)}
"""The allowed range of the rig scene's numeric fields with fixed bounds [the field's unit]; ``settle`` and
``ramp_time`` lie in [0, duration)."""
SLIP_ALLOWANCE = 0.1
"""Slip the revolution count allows for [-]: the shaft turns slower than ``speed_rpm`` by the
motor's slip (3-6 % for the rig's motor at its load; 10 % leaves room for a GSA's extremes)."""


@dataclass(frozen=True)
class RigScene:
    """One operating case of the test rig (see the module).

    Parameters
    ----------
    kind : str
        ``startup``, ``steady`` or ``coastdown``.
    speed_rpm : float
        Synchronous speed of the supply frequency [rpm], in (0, 6000].
    duration : float
        Simulated record length [s] (after ``t = 0``), > 0.
    sample_rate : float
        Sensor sampling rate [Hz], > 0.
    settle : float
        ``steady`` only: seconds run before the analysed record [s], in [0, duration).
    ramp_time : float
        ``startup`` only: frequency-ramp time [s] (0: direct-on-line), in [0, duration).
    seed : int
        Seed of the measurement noise and defect jitter, >= 0.

    Examples
    --------
    >>> RigScene("steady", speed_rpm=1500.0, duration=2.0).analysed_duration
    1.5
    """

    kind: str = "steady"
    speed_rpm: float = 1500.0
    duration: float = 2.0
    sample_rate: float = 5000.0
    settle: float = 0.5
    ramp_time: float = 0.0
    seed: int = 1
    label_fields: ClassVar[tuple[str, ...]] = ("kind", "speed_rpm")
    """The fields that label a rig scene in study tables and plots."""
    units: ClassVar[dict[str, str]] = {"kind": "", "speed_rpm": "rpm", "duration": "s", "sample_rate": "Hz",
                                       "settle": "s", "ramp_time": "s"}
    """The unit of each field (a study may write another unit, :mod:`ddgsa.units`; ``kind`` is a word)."""

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise SceneError(with_hint(f"rig scene field 'kind' must be one of {', '.join(KINDS)}, got {self.kind!r}",
                                       self.kind, KINDS))
        for name in ("speed_rpm", "duration", "sample_rate", "settle", "ramp_time"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise SceneError(f"rig scene field {name!r} must be a finite number, got {value!r}")
            object.__setattr__(self, name, float(value))
        if not isinstance(self.seed, int) or isinstance(self.seed, bool) or self.seed < 0:
            raise SceneError(f"rig scene field 'seed' must be an integer >= 0, got {self.seed!r}")
        checks = (
            *((name, getattr(self, name) in allowed, allowed.must(self.units[name]))
              for name, allowed in RIG_SCENE_LIMITS.items()),
            ("settle", 0.0 <= self.settle and (self.kind != "steady" or self.settle < self.duration),
             f"in [0, duration = {self.duration:g}) s"),
            ("ramp_time", 0.0 <= self.ramp_time < self.duration, f"in [0, duration = {self.duration:g}) s"),
        )
        for name, ok, allowed in checks:
            if not ok:
                raise SceneError(f"rig scene field {name!r} must be {allowed}, got {getattr(self, name):g}")
        if self.duration * self.sample_rate < MIN_SAMPLES:
            raise SceneError(f"rig scene: duration {self.duration:g} s at sample_rate {self.sample_rate:g} Hz gives "
                             f"{self.duration * self.sample_rate:.0f} samples; need at least {MIN_SAMPLES}")
        if self.kind == "steady":
            revs = self.analysed_duration * self.speed_rpm / 60.0 * (1.0 - SLIP_ALLOWANCE)
            if revs < MIN_STEADY_REVS:
                raise SceneError(f"rig scene 'steady' at {self.speed_rpm:g} rpm: the analysed record "
                                 f"(duration - settle = {self.analysed_duration:g} s) holds {revs:.3g} revolutions "
                                 f"at {SLIP_ALLOWANCE:.0%} slip; need at least {MIN_STEADY_REVS} (duration >= "
                                 f"{self.settle + 60 * MIN_STEADY_REVS / (self.speed_rpm * (1 - SLIP_ALLOWANCE)):.3g} s)")

    @property
    def analysed_duration(self) -> float:
        """Length of the analysed record [s]: ``duration - settle`` (steady) or ``duration``."""
        return self.duration - self.settle if self.kind == "steady" else self.duration

    @property
    def speed_hz(self) -> float:
        """Synchronous shaft speed ``speed_rpm / 60`` [Hz], the upper bound of the shaft speed."""
        return self.speed_rpm / 60.0

    def to_dict(self) -> dict[str, Any]:
        """The scene's fields (for store keys and provenance)."""
        return asdict(self)

    @classmethod
    def from_fields(cls, values: Mapping[str, Any]) -> "RigScene":
        """A scene from a mapping; unknown keys are refused with the allowed ones listed."""
        allowed = [f.name for f in fields(cls)]
        bad = sorted(set(values) - set(allowed))
        if bad:
            raise SceneError(f"rig scene: unknown field(s) {bad}; allowed: {', '.join(allowed)}")
        return cls(**dict(values))

    def sampling_checks(self, frequencies: Mapping[str, float]) -> list[dict[str, object]]:
        """The aliasing guard for the sensor sample interval against ``frequencies`` ({label: Hz}).

        Returns one :func:`ddgsa.mbs.sampling.sampling_row` per frequency; warns
        (:class:`ddgsa.mbs.sampling.AliasingWarning`) below 10 samples per period.

        Raises
        ------
        ModelError
            When a frequency gets fewer than 2 samples per period (the record would alias it).
        """
        h = 1.0 / self.sample_rate
        rows = []
        for label, f_hz in frequencies.items():
            what = label if "order" in label or "frequency" in label else f"bearing defect frequency {label}"
            check_interval(h, f_hz, f"rig scene sample_rate {self.sample_rate:g} Hz", refuse=True, component=what,
                           rate=True)
            rows.append(sampling_row("sensor sample interval", h, f_hz, label,
                                     "peaks of this component are under-resolved in the recorded signals"))
        return rows


def scene_grid(spec: Mapping[str, Any]) -> list[RigScene]:
    """Scenes for every combination of the list-valued fields of ``spec`` (e.g. a list of speeds).

    Examples
    --------
    >>> [s.speed_rpm for s in scene_grid({"kind": "steady", "speed_rpm": [600, 1500], "duration": 2.0})]
    [600.0, 1500.0]
    """
    keys = list(spec)
    values = [v if isinstance(v, (list, tuple)) else [v] for v in spec.values()]
    for k, v in zip(keys, values):
        if len(v) == 0:
            raise SceneError(f"rig scene field {k!r} is an empty list; give at least one value")
    return [RigScene.from_fields(dict(zip(keys, combo))) for combo in itertools.product(*values)]
