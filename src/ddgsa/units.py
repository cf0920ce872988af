"""Units a user writes, converted to the SI unit a model declares (with :mod:`pint`).

Every number in a study is in the model's SI unit unless a unit is written beside it:

* a parameter's ``unit:`` key (``k_front_z: {nominal: 1e7, spread: 0.2, unit: kN/m}`` is 1e10 N/m);
* a quantity string (``fixed: {speed: "12 rpm"}``, ``scenes: {sample_rate: 5 kHz}``);
* a mapping ``{value: ..., unit: ...}`` whose value may be a list (``{value: [8, 12], unit: km/h}``).

A unit of another dimension is refused with the expected one (:class:`UnitError`). Frequencies
count cycles: ``Hz`` is one cycle (revolution) per second, so ``25 Hz`` is ``1500 rpm``; an
angular velocity (``rad/s``) is refused where a cycle frequency is declared and vice versa,
because pint would silently equate ``1 rad/s`` with ``1 Hz``. Offset units (``degC``) are refused
(no model declares a temperature).

Examples
--------
>>> factor("kN/m", "N/m")
1000.0
>>> round(convert("25 Hz", "rpm"), 9)
1500.0
>>> convert({"value": [36, 72], "unit": "km/h"}, "m/s")
[10.0, 20.0]
>>> convert(0.2, "-")
0.2
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from functools import lru_cache
from typing import Any

import pint

from ddgsa.errors import DdgsaError

UREG = pint.UnitRegistry(on_redefinition="ignore")
UREG.define("revolution = 1 = rev = cycle = turn")      # a count: Hz = rev/s, rpm = rev/min
UREG.define("@alias ohm = Ohm")
_QUANTITY = re.compile(r"^([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(\S.*)$")
_DIMENSIONLESS = ("", "-", "1")
_ANGLES = ("radian", "degree", "arcminute", "arcsecond", "gradian")
_NAMED = {                                                # dimensionality -> a word for messages
    "[mass] / [time] ** 2": "stiffness (force per length)",
    "[mass] * [length] / [time] ** 2": "force",
    "[mass] * [length] ** 2 / [time] ** 2": "torque or energy",
    "[mass] / [time]": "damping (force per velocity)",
    "[mass] * [length] ** 2 / [time]": "torsional damping",
    "[mass] * [length] ** 2": "moment of inertia",
    "[mass]": "mass",
    "[length]": "length",
    "[time]": "time",
    "1 / [time]": "frequency",
    "[length] / [time]": "speed",
    "[length] / [time] ** 2": "acceleration",
    "[mass] / [length] / [time] ** 2": "pressure",
    "[mass] / [length] ** 3": "density",
    "dimensionless": "dimensionless",
}


class UnitError(DdgsaError, ValueError):
    """A unit that cannot be read, or one of another dimension than the model declares."""


@lru_cache(maxsize=256)
def _unit(text: str) -> pint.Unit:
    text = text.strip()
    if text in _DIMENSIONLESS:
        return UREG.dimensionless
    try:
        return UREG.parse_units(text)
    except (pint.errors.PintError, AssertionError, AttributeError, TypeError, ValueError, SyntaxError):
        raise UnitError(f"cannot read unit {text!r}; write e.g. 'kN/m', 'rpm', 'kHz', "
                        "'%', 'N m/rad'") from None


def dimension(unit: str) -> str:
    """The dimension of ``unit`` in words, e.g. ``"force ([mass] * [length] / [time] ** 2)"``."""
    dim = str(_unit(unit).dimensionality)
    word = _NAMED.get(dim)
    return f"{word} ({dim})" if word and word != "dimensionless" else (word or dim)


def _angular(unit: pint.Unit) -> bool:
    return any(a in str(unit) for a in _ANGLES)


@lru_cache(maxsize=256)
def factor(given: str, expected: str) -> float:
    """The factor that takes a value in ``given`` to ``expected`` (``value_expected = factor * value_given``).

    Raises
    ------
    UnitError
        For an unreadable unit, another dimension (the message names both), an angular velocity
        against a cycle frequency, or an offset unit.
    """
    g, e = _unit(given), _unit(expected)
    if g.dimensionality != e.dimensionality:
        raise UnitError(f"unit {given!r} is a {dimension(given)}; expected a {dimension(expected)} "
                        f"such as {expected or '-'!r}")
    if g.dimensionality == UREG.parse_units("Hz").dimensionality and _angular(g) != _angular(e):
        raise UnitError(f"unit {given!r} is {'an angular velocity' if _angular(g) else 'a cycle frequency'} and "
                        f"{expected!r} {'an angular velocity' if _angular(e) else 'a cycle frequency'}; "
                        "write it in the expected kind (1 Hz = 60 rpm = 2 pi rad/s)")
    try:
        zero = UREG.Quantity(0.0, g).to(e).magnitude
        one = UREG.Quantity(1.0, g).to(e).magnitude
    except pint.errors.PintError as exc:
        raise UnitError(f"cannot convert {given!r} to {expected!r}: {exc}") from None
    if zero != 0.0:
        raise UnitError(f"unit {given!r} has an offset from {expected!r}; give the value in {expected!r}")
    return float(one)


def _scalar(value: Any, expected: str) -> float:
    """One number: a plain number (already in ``expected``) or a quantity string such as ``"5 kHz"``."""
    if isinstance(value, bool):
        raise UnitError(f"expected a number, got {value!r}")
    if isinstance(value, (int, float)):
        return float(value)
    if isinstance(value, str):
        text = value.strip()
        try:
            return float(text)                      # "1e10" from a YAML 1.1 writer
        except ValueError:
            pass
        match = _QUANTITY.match(text)
        if match is None:
            raise UnitError(f"cannot read quantity {value!r}: write a number and a unit, e.g. '5 kHz'")
        return float(match[1]) * factor(match[2], expected)
    raise UnitError(f"expected a number or a quantity such as '5 kHz', got {type(value).__name__} {value!r}")


def has_unit(value: Any) -> bool:
    """Whether ``value`` carries a unit (a quantity string, a ``{value, unit}`` mapping, or a list of them)."""
    if isinstance(value, list):
        return any(has_unit(v) for v in value)
    if isinstance(value, Mapping):
        return "unit" in value
    if isinstance(value, str):
        try:
            float(value)
        except ValueError:
            return True
    return False


def convert(value: Any, expected: str) -> Any:
    """``value`` in the unit ``expected``: a number or list of numbers (taken as already in it), a
    quantity string or list of them, or ``{value: number or list, unit: text}``.

    Raises
    ------
    UnitError
        See :func:`factor`; also for a mapping with other keys than ``value`` and ``unit``.
    """
    if isinstance(value, Mapping):
        extra = sorted(set(value) - {"value", "unit"})
        if extra or "value" not in value or "unit" not in value:
            raise UnitError(f"a quantity mapping is {{value, unit}}, got keys {sorted(value)}")
        f = factor(str(value["unit"]), expected)
        inner = value["value"]
        if isinstance(inner, list):
            return [_scalar(v, "-") * f for v in inner]
        return _scalar(inner, "-") * f
    if isinstance(value, list):
        return [_scalar(v, expected) for v in value]
    out = _scalar(value, expected)
    if not math.isfinite(out):
        raise UnitError(f"expected a finite number, got {value!r}")
    return out


SCALED_KEYS = ("nominal", "low", "high", "mean", "std", "mode", "median")
"""Keys of a parameter specification that carry its unit (``spread`` and ``sigma`` are relative)."""


def parameter_in(spec: Mapping[str, Any], expected: str) -> dict[str, Any]:
    """A parameter specification (see :mod:`ddgsa.gsa.space`) whose ``unit`` is converted to ``expected``.

    Numbers under :data:`SCALED_KEYS` are scaled, a lognormal ``mu`` shifted by ``log(factor)``;
    the returned spec says ``unit: expected``. A spec without ``unit`` is returned unchanged
    (its numbers are taken as in ``expected``).

    Examples
    --------
    >>> parameter_in({"nominal": 1e7, "spread": 0.2, "unit": "kN/m"}, "N/m")
    {'nominal': 10000000000.0, 'spread': 0.2, 'unit': 'N/m'}
    """
    if "unit" not in spec:
        return dict(spec)
    f = factor(str(spec["unit"]), expected)
    if f == 1.0:                                          # as written (the study's digest stays)
        return dict(spec)
    out: dict[str, Any] = {}
    for key, value in spec.items():
        if key in SCALED_KEYS and isinstance(value, (int, float, str)) and not isinstance(value, bool):
            out[key] = _scalar(value, "-") * f
        elif key == "mu" and isinstance(value, (int, float)) and not isinstance(value, bool):
            out[key] = float(value) + math.log(f)
        else:
            out[key] = value
    out["unit"] = expected
    return out


PREFIX_SCALES = (1e3, 1e-3, 1e6, 1e-6)
"""The factors a unit hint tries: a value typed in N/m where kN/m was meant is 1e3 too small."""
_PREFIXES = ("", "k", "M", "G", "m", "u")
_SMALL_STEMS = ("m", "s", "g", "A", "V")
"""Symbols whose milli- and micro- forms an engineer types (mm, ms, mg, mA, mV): a hint towards a smaller
unit names only these (a stiffness too large is not advised as mN/m); a larger one never names ks."""


@lru_cache(maxsize=256)
def prefixed_unit(unit: str, scale: float) -> str | None:
    """A unit that differs from ``unit`` by a prefix on its first symbol (or by ``t`` for ``kg``)
    and is ``scale`` times it, checked with :func:`factor`; ``None`` if there is none.

    Examples
    --------
    >>> prefixed_unit("N/m", 1e3), prefixed_unit("kg m^2", 1e3), prefixed_unit("kg", 1e3), prefixed_unit("m", 1e-3)
    ('kN/m', 't m^2', 't', 'mm')
    >>> prefixed_unit("N/m", 1e-3) is None           # mN/m: nobody types a shaft's stiffness in it
    True
    """
    match = re.match(r"([A-Za-z]+)(.*)$", unit.strip())
    if match is None or unit.strip() in _DIMENSIONLESS:
        return None
    first, rest = match[1], match[2]
    stems = [first] + ([first[1:]] if len(first) > 1 and first[0] in "kMGmu" else [])
    candidates = (["t"] if first == "kg" else []) + [p + s for s in stems for p in _PREFIXES
                                                      if ((s in _SMALL_STEMS) if scale < 1 else (s != "s"))]
    for cand in dict.fromkeys(c + rest for c in candidates):
        try:
            if cand != unit and math.isclose(factor(cand, unit), scale, rel_tol=1e-12):
                return cand
        except UnitError:
            continue
    return None


def prefix_hint(values: tuple[float, ...], unit: str, low: float, high: float) -> str:
    """A hint for numbers outside ``[low, high]`` [unit] that a unit prefix would bring inside
    (all of ``values`` times one of :data:`PREFIX_SCALES`), e.g. a stiffness typed in kN/m where
    N/m is declared; empty when no prefix does.

    Examples
    --------
    >>> prefix_hint((1e7,), "N/m", 1e8, 1e12)
    ' (hint: 1e+07 kN/m = 1e+10 N/m is inside it: if the number is in kN/m, write unit: kN/m)'
    >>> prefix_hint((5.0,), "N/m", 1e8, 1e12)
    ''
    """
    for scale in PREFIX_SCALES:
        scaled = [v * scale for v in values]
        if all(low <= v <= high for v in scaled):
            cand = prefixed_unit(unit, scale)
            if cand is not None:
                given = ", ".join(f"{v:g}" for v in values)
                inside = ", ".join(f"{v:g}" for v in scaled)
                return (f" (hint: {given} {cand} = {inside} {unit} is inside it: if the number is in {cand}, "
                        f"write unit: {cand})")
    return ""


def scene_hints(scene_type: type, values: dict[str, list[Any]]) -> list[tuple[str, str]]:
    """``(field, hint)`` for scene values that look written in another unit: a field in rpm below
    60 (Hz?), in Hz below 100 (kHz?), a wind speed above 30 m/s that km/h would bring below it (km/h?).

    >>> from ddgsa.loads.scene import Scene
    >>> scene_hints(Scene, {"wind_speed": [40.0]})[0][1]
    "40 m/s is above storm speed; if you meant km/h write '40 km/h' (= 11.1 m/s)"
    >>> scene_hints(Scene, {"wind_speed": [11000.0]})      # 3 056 m/s in km/h: no hint
    []
    """
    units = getattr(scene_type, "units", {})
    out = []
    for key, vals in values.items():
        nums = [v for v in vals if isinstance(v, (int, float)) and not isinstance(v, bool)]
        if not nums:
            continue
        unit, low, high = units.get(key), min(nums), max(nums)
        if unit == "rpm" and low < 60:
            out.append((key, f"{low:g} rpm is less than one revolution per second; if you meant Hz write "
                             f"'{low:g} Hz' (= {60 * low:g} rpm)"))
        elif unit == "Hz" and low < 100:
            out.append((key, f"{low:g} Hz is a low rate; if you meant kHz write '{low:g} kHz'"))
        elif unit == "m/s" and key == "wind_speed" and 30 < high <= 30 * 3.6:     # km/h brings it below 30 m/s
            out.append((key, f"{high:g} m/s is above storm speed; if you meant km/h write '{high:g} km/h' "
                             f"(= {high / 3.6:.3g} m/s)"))
    return out
