"""Analytic models with known answers, for studies that test the workbench itself.

``analytic`` evaluates the Ishigami function (:func:`ddgsa.closed_forms.ishigami`) scaled by
``wind_speed / 11`` so that scenes matter, at microseconds a point. Options make it fail on
purpose (``fail_above``: raise for ``x1`` above a value) or slow (``delay_s`` per point), which
is how the runner's failure handling and kill/resume are tested. ``fault_shift`` adds a known
shift to known spread, the oracle of the fault-detection statistics.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping

import numpy as np
import pandas as pd

from ddgsa.closed_forms import ishigami
from ddgsa.loads.scene import Scene
from ddgsa.models.base import Model, ModelOption, ModelOutput, ModelParameter, SignalOutput, register_model

WAVES_T = np.linspace(0.0, 0.5, 26)
"""Grid of the ``waves`` signal [s]."""


class _Static(Model):
    """A static model: its time series is one sample, it has no modes."""

    def simulate(self, scene: Scene, params: Mapping[str, float] | None = None) -> pd.DataFrame:
        """A one-sample 'time series' of the outputs (the model is static)."""
        p = self.resolve(params).iloc[0].to_dict()
        return pd.DataFrame([self._evaluate_one(p, scene)], index=pd.Index([0.0], name="time"))

    def modes(self, params: Mapping[str, float] | None = None, rotor_speed: float = 0.0) -> pd.DataFrame:
        """A static model has no modes: an empty table."""
        self.standstill_only(rotor_speed)
        return pd.DataFrame(columns=["frequency_hz", "damping_ratio", "label"])


@register_model("analytic")
class Analytic(_Static):
    """Ishigami test model: parameters ``x1, x2, x3`` on [-pi, pi]; outputs ``y`` and ``y_positive``.

    ``y_positive`` is ``y + 12`` (never negative: M-DRM's sign diagnostics stay quiet, its
    check sample does not). Options: ``fidelity`` (only ``exact``), ``fail_above`` [-],
    ``delay_s`` [s].

    Signal ``waves`` (a time series on :data:`WAVES_T`): ``(12 + x1 sin(4 pi t) + 2 x2 sin(10 pi t))
    wind_speed / 11``: bin ``t`` has ``S1[x1] = s1^2 / (s1^2 + 4 s2^2)`` (``s1 = sin 4 pi t``,
    ``s2 = sin 10 pi t``), ``S1[x2]`` the rest, ``x3`` none; the generalised ``S1[x1] = sum s1^2 /
    sum (s1^2 + 4 s2^2)`` over the grid.
    """

    parameters = tuple(ModelParameter(f"x{i}", 0.0, "-", f"Ishigami input {i}", -math.pi, math.pi)
                       for i in (1, 2, 3))
    outputs = (ModelOutput("y", "-", "Ishigami function times wind_speed / 11", -100.0, 100.0),
               ModelOutput("y_positive", "-", "y + 12 (positive for wind speeds up to 11 m/s)", -88.0, 112.0))
    signal_outputs = (SignalOutput("waves", "-", "12 + x1 sin(4 pi t) + 2 x2 sin(10 pi t), times wind_speed / 11",
                                   "time", "s"),)
    fidelities = ("exact",)
    scene_fields_read = ("wind_speed",)
    options = (ModelOption("fail_above", "number", "raise for x1 above this value", optional=True),
               ModelOption("delay_s", "number", "sleep per point", 0.0, 60.0, "s"))

    def __init__(self, fidelity: str = "exact", fail_above: float | None = None, delay_s: float = 0.0) -> None:
        self.check_options({"fidelity": fidelity, "fail_above": fail_above, "delay_s": delay_s})
        self.fidelity = fidelity
        self.fail_above = fail_above
        self.delay_s = float(delay_s)

    def _evaluate_one(self, params: dict[str, float], scene: Scene) -> dict[str, float]:
        if self.delay_s:
            time.sleep(self.delay_s)
        if self.fail_above is not None and params["x1"] > self.fail_above:
            raise RuntimeError(f"x1 = {params['x1']:.3f} above fail_above = {self.fail_above}")
        y = float(ishigami(np.array([[params["x1"], params["x2"], params["x3"]]]))[0]) * scene.wind_speed / 11.0
        return {"y": y, "y_positive": y + 12.0}

    def signal_axis(self, name: str, scene: Scene) -> np.ndarray:
        """The ``waves`` grid :data:`WAVES_T` [s] (any scene)."""
        self.signal_output(name)
        return WAVES_T

    def _evaluate_signals_one(self, params: dict[str, float], scene: Scene,
                              signals: tuple[str, ...]) -> tuple[dict[str, float], dict[str, np.ndarray]]:
        waves = (12.0 + params["x1"] * np.sin(4 * np.pi * WAVES_T) + 2.0 * params["x2"] * np.sin(10 * np.pi * WAVES_T))
        return self._evaluate_one(params, scene), {"waves": waves * scene.wind_speed / 11.0}


@register_model("fault_shift")
class FaultShift(_Static):
    """Fault test model: a known shift on known spread, for detection statistics.

    Parameters ``fault`` (the shift ``Delta`` [-]) and ``x1``, ``x2`` [-] (give them a
    distribution in the study); outputs ``full = x1 + Delta``, ``half_1 = x1 + Delta / 2`` and
    ``half_2 = x2 + Delta / 2`` (two sensors that each see half the fault). With ``x1, x2`` iid
    ``N(0, sigma^2)``: ``POD(full) = Phi(Delta / sigma - z_(1-alpha))``; the two halves together
    reach ``Phi(Delta / (sigma sqrt 2) - z_(1-alpha))``. Static: the scene is ignored.
    """

    parameters = (ModelParameter("fault", 0.0, "-", "fault size (shift)", -1e3, 1e3),
                  *(ModelParameter(f"x{i}", 0.0, "-", f"spread of sensor {i}", -math.inf, math.inf)
                    for i in (1, 2)))
    outputs = (ModelOutput("full", "-", "x1 plus the whole fault shift (a sensor that sees all of it)", -100.0, 100.0),
               ModelOutput("half_1", "-", "x1 plus half the fault shift (first half-sensor)", -100.0, 100.0),
               ModelOutput("half_2", "-", "x2 plus half the fault shift (second half-sensor)", -100.0, 100.0))
    fidelities = ("exact",)
    options = ()

    def __init__(self, fidelity: str = "exact") -> None:
        self.check_fidelity(fidelity)
        self.fidelity = fidelity

    def _evaluate_one(self, params: dict[str, float], scene: Scene) -> dict[str, float]:
        d = params["fault"]
        return {"full": params["x1"] + d, "half_1": params["x1"] + d / 2, "half_2": params["x2"] + d / 2}
