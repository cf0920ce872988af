"""A scene: the wind conditions and record length one model evaluation sees."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any, ClassVar

from ddgsa.errors import SceneError, with_hint

#: samples per period of the highest rotor harmonic the loads must resolve (3P at rated speed)
SAMPLES_PER_3P = 8
_RATED_SPEED_RAD_S = 12.1 * math.pi / 30.0
#: loads fidelities a scene may name (``auto`` resolves to one of the others)
LOADS_FIDELITIES = ("table", "bem", "auto")
#: inclination from which ``loads_fidelity: auto`` chooses the BEM rotor [deg] (see docs/loads.md)
AUTO_BEM_INCLINATION_DEG = 2.5
#: how ``inclination_deg`` and ``wind_speed`` describe an inclined flow (see :attr:`Scene.inclination_convention`)
INCLINATION_CONVENTIONS = ("upflow", "downflow_horizontal")


@dataclass(frozen=True)
class Interval:
    """The allowed range of a scene field [its unit], each end included or not; ``str`` writes it as
    the docs quote it (``(0, 50]``, ``> 0``), which ``tests/test_docs.py`` checks.

    Examples
    --------
    >>> str(Interval(0.0, 50.0, low_closed=False)), str(Interval(0.0, low_closed=False)), 50.0 in Interval(0.0, 50.0)
    ('(0, 50]', '> 0', True)
    """

    low: float
    high: float = math.inf
    low_closed: bool = True
    high_closed: bool = True

    def __contains__(self, value: float) -> bool:
        above = value >= self.low if self.low_closed else value > self.low
        below = value <= self.high if self.high_closed else value < self.high
        return above and below

    def __str__(self) -> str:
        if math.isinf(self.high):
            return f"{'>=' if self.low_closed else '>'} {self.low:g}"
        return f"{'[' if self.low_closed else '('}{self.low:g}, {self.high:g}{']' if self.high_closed else ')'}"

    def must(self, unit: str = "") -> str:
        """``in (0, 50] m/s`` or ``> 0 s``: what a message says a value must be."""
        return ("" if math.isinf(self.high) else "in ") + str(self) + (f" {unit}" if unit not in ("", "-") else "")


#: the allowed range of each numeric field of a wind :class:`Scene` [the field's unit]
SCENE_LIMITS = {"wind_speed": Interval(0.0, 50.0, low_closed=False),
                "turbulence_intensity": Interval(0.0, 1.0, high_closed=False),
                "inclination_deg": Interval(-30.0, 30.0), "shear_exponent": Interval(0.0, 1.0),
                "duration": Interval(0.0, low_closed=False), "dt": Interval(0.0, low_closed=False)}


@dataclass(frozen=True)
class Scene:
    """Wind conditions of one simulation; a realisation of the loads is a pure function of it.

    Parameters
    ----------
    wind_speed : float
        Mean wind speed at hub height V_hub [m/s], in (0, 50].
    turbulence_intensity : float
        IEC reference turbulence intensity I_ref [-] in [0, 1): the standard deviation of the
        longitudinal wind is ``I_ref (0.75 V_hub + 5.6)``. 0 gives steady wind.
    inclination_deg : float
        Upward inclination of the inflow [deg], in [-30, 30].
    shear_exponent : float
        Power-law shear exponent alpha [-] in [0, 1] (IEC normal wind profile: 0.2).
    duration : float
        Record length [s], > 0.
    dt : float
        Time step of the loads [s]; at most ``1 / (8 f_3P)`` at rated rotor speed (:func:`max_time_step`:
        0.207 s).
    seed : int
        Seed of the turbulence realisation (>= 0); all parameter points of a scene see the
        same realisation (common random numbers).
    loads_fidelity : str
        Rotor aerodynamics of the loads: ``table`` (quasi-steady Cp/Ct table rotor,
        :mod:`ddgsa.loads.hubloads`), ``bem`` (blade-element momentum, :mod:`ddgsa.loads.bem`) or
        ``auto`` (``bem`` where ``|inclination_deg| >= AUTO_BEM_INCLINATION_DEG``, else ``table``;
        resolved on construction, so the scene and its cache key name the fidelity used).
    inclination_convention : str
        How ``inclination_deg`` and ``wind_speed`` describe the flow: ``upflow`` (ddgsa's
        convention: a positive inclination tilts the flow upwards, ``wind_speed`` is the mean speed
        along the inclined flow) or ``downflow_horizontal`` (a positive inclination tilts it
        downwards and ``wind_speed`` is its horizontal component, so the speed along the flow is
        ``wind_speed / cos(inclination)``: the reading under which seed 000's inclination trends
        come out, results/README.md). At zero inclination the two are the same flow and the
        scene holds ``upflow`` (one cache key). See :attr:`flow_speed`, :attr:`flow_inclination_deg`.

    Examples
    --------
    >>> Scene(wind_speed=11.0, turbulence_intensity=0.12, duration=60.0).dt
    0.05
    """

    wind_speed: float = 11.0
    turbulence_intensity: float = 0.12
    inclination_deg: float = 0.0
    shear_exponent: float = 0.2
    duration: float = 600.0
    dt: float = 0.05
    seed: int = 1
    loads_fidelity: str = "table"
    inclination_convention: str = "upflow"
    units: ClassVar[dict[str, str]] = {"wind_speed": "m/s", "turbulence_intensity": "-", "inclination_deg": "deg",
                                       "shear_exponent": "-", "duration": "s", "dt": "s",
                                       "loads_fidelity": "", "inclination_convention": ""}
    """The SI unit of each field (a study may write another unit, :mod:`ddgsa.units`)."""

    def __post_init__(self) -> None:
        if self.loads_fidelity not in LOADS_FIDELITIES:
            raise SceneError(with_hint(f"scene field 'loads_fidelity' must be one of {', '.join(LOADS_FIDELITIES)}, "
                                       f"got {self.loads_fidelity!r}", self.loads_fidelity, LOADS_FIDELITIES))
        if self.inclination_convention not in INCLINATION_CONVENTIONS:
            raise SceneError(with_hint(f"scene field 'inclination_convention' must be one of "
                                       f"{', '.join(INCLINATION_CONVENTIONS)}, got {self.inclination_convention!r}",
                                       self.inclination_convention, INCLINATION_CONVENTIONS))
        for name in ("wind_speed", "turbulence_intensity", "inclination_deg", "shear_exponent",
                     "duration", "dt"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise SceneError(f"scene field {name!r} must be a finite number, got {value!r}")
            object.__setattr__(self, name, float(value))
        if not isinstance(self.seed, int) or isinstance(self.seed, bool) or self.seed < 0:
            raise SceneError(f"scene field 'seed' must be an integer >= 0, got {self.seed!r}")
        for name, allowed in SCENE_LIMITS.items():
            if getattr(self, name) not in allowed:
                raise SceneError(f"scene field {name!r} must be {allowed.must(self.units[name])}, "
                                 f"got {getattr(self, name)}")
        dt_max = max_time_step()
        if self.dt > dt_max:
            raise SceneError(f"scene field 'dt' = {self.dt} s is too coarse for the rotor's 3P frequency "
                             f"({3 * _RATED_SPEED_RAD_S / (2 * math.pi):.3f} Hz at rated speed): need "
                             f"dt <= {dt_max:.3f} s ({SAMPLES_PER_3P} samples per 3P period)")
        if self.loads_fidelity == "auto":
            chosen = "bem" if abs(self.inclination_deg) >= AUTO_BEM_INCLINATION_DEG else "table"
            object.__setattr__(self, "loads_fidelity", chosen)
        if self.inclination_deg == 0.0:
            object.__setattr__(self, "inclination_convention", "upflow")
        if self.duration < 10 * self.dt:
            raise SceneError(f"scene field 'duration' = {self.duration} s holds fewer than 10 steps of "
                             f"dt = {self.dt} s")

    @property
    def n_steps(self) -> int:
        """Number of samples in the record."""
        return int(round(self.duration / self.dt))

    @property
    def flow_speed(self) -> float:
        """Mean wind speed along the inclined flow at hub height [m/s]."""
        if self.inclination_convention == "downflow_horizontal":
            return self.wind_speed / math.cos(math.radians(self.inclination_deg))
        return self.wind_speed

    @property
    def flow_inclination_deg(self) -> float:
        """Upward inclination of the flow [deg] (ddgsa's ``upflow`` convention)."""
        return -self.inclination_deg if self.inclination_convention == "downflow_horizontal" else self.inclination_deg

    def to_dict(self) -> dict[str, Any]:
        """The scene's fields as a plain dict; ``loads_fidelity`` and ``inclination_convention`` only
        where they are not their defaults (``table``, ``upflow``), so the evaluation-store and
        loads-cache keys of scenes written before those fields existed stay what they were."""
        fields = asdict(self)
        for name, default in (("loads_fidelity", "table"), ("inclination_convention", "upflow")):
            if fields[name] == default:
                del fields[name]
        return fields

    def replace(self, **changes: Any) -> "Scene":
        """A copy with some fields changed (validated again)."""
        return Scene(**{**self.to_dict(), **changes})


def max_time_step() -> float:
    """Largest allowed load time step [s]: ``SAMPLES_PER_3P`` samples per 3P period at rated speed."""
    return 2.0 * math.pi / (3.0 * _RATED_SPEED_RAD_S) / SAMPLES_PER_3P
