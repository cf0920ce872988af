"""``fidelity="auto"`` in the Python API: per scene, the cheapest fidelity within a tolerance.

:func:`choose_fidelity` is the rule (shared with studies' ``fidelity: auto``): every fidelity is
run on a pilot set (those of the model's ``pilot_fidelities`` where it declares them), errors are
the largest relative deviation of any output from the richest (the first), and the cheapest fidelity whose error is within ``tolerance`` wins
(the richest when none is). "Cheapest" is the model's deterministic cost model
(:meth:`ddgsa.models.Model.fidelity_cost`), never measured wall time: the same study gives the
same choice on a loaded machine, a fast one, or on rerun.

:class:`AutoFidelity` applies it inside ``evaluate``: the first time it sees a scene it pilots
the nominal point plus the first ``pilot`` points it was given at every fidelity (on a record of
at most :data:`PILOT_DURATION_S`, :func:`pilot_scene`), records the
choice in ``choices`` (and each result's ``attrs["fidelity"]``), and evaluates the points with
the chosen fidelity. ``ddgsa.models.get("direct_drive", fidelity="auto", tolerance=0.02)``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.errors import ModelError
from ddgsa.loads.scene import Scene
from ddgsa.mbs.campbell import CampbellDiagram
from ddgsa.models.base import MODELS, Model

PILOT_DURATION_S = 120.0
"""Longest pilot record [s]. The pilot estimates each fidelity's error; it need not be run at the
study's full length. On paper C's scenes (6, 11, 18 m/s, nominal + 4 points) records of 60-200 s
gave the linear fidelity 0.3-0.8 % error where 600 s gave 0.07-0.3 % (short records weigh the
start-up transient more, so the estimate errs on the safe side), with the same choice in all 12
cases; the flexible reference costs a fifth."""


def pilot_scene(scene: Scene) -> Scene:
    """The scene the fidelities are piloted on: ``scene`` with its duration capped at
    :data:`PILOT_DURATION_S` (same seed; a realisation of that length, not the first seconds of
    the long one)."""
    return scene if scene.duration <= PILOT_DURATION_S else scene.replace(duration=PILOT_DURATION_S)


def choose_fidelity(values: Mapping[str, NDArray[np.float64]], costs: Mapping[str, float], outputs: list[str],
                    tolerance: float, ignore: Sequence[str] = ()) -> dict[str, Any]:
    """The cheapest fidelity whose pilot values stay within ``tolerance`` of the first (richest) one.

    Parameters
    ----------
    values : mapping
        Fidelity -> pilot values (n_points, n_outputs); the first entry is the reference.
        Failed evaluations are NaN and make that fidelity's error infinite.
    costs : mapping
        Fidelity -> relative cost of an evaluation [-] (deterministic: a cost model, not a timing).
    outputs : list of str
        Output names, the columns of ``values``.
    tolerance : float
        Largest relative error allowed [-].
    ignore : sequence of str
        Outputs reported in ``errors`` but not judged (a model's ``numerical_outputs``, e.g.
        constraint drift: 1e-12 on one path and 1e-9 on another is no difference in physics).

    Returns
    -------
    dict
        ``chosen``, ``tolerance``, ``errors`` ({fidelity: {output: max relative error}}),
        ``max_rel_error_<fidelity>`` and ``relative_cost_<fidelity>``.

    Examples
    --------
    >>> ref = np.array([[1.0, 2.0]])
    >>> choose_fidelity({"fine": ref, "coarse": ref * 1.01}, {"fine": 2.0, "coarse": 1.0}, ["a", "b"], 0.02)["chosen"]
    'coarse'
    >>> drift = {"fine": np.array([[1.0, 1e-12]]), "coarse": np.array([[1.0, 1e-9]])}
    >>> choose_fidelity(drift, {"fine": 2.0, "coarse": 1.0}, ["a", "drift"], 0.02, ignore=["drift"])["chosen"]
    'coarse'
    
    """
    fidelities = list(values)
    ref = values[fidelities[0]]
    entry: dict[str, Any] = {"tolerance": tolerance, "errors": {}}
    for fid in fidelities:
        vals = values[fid]
        with np.errstate(divide="ignore", invalid="ignore"):
            rel = np.abs(vals - ref) / np.abs(ref)
        rel = np.where((ref == 0) & (vals == 0), 0.0, rel)
        entry["errors"][fid] = {n: float(np.max(rel[:, j])) for j, n in enumerate(outputs)}
        judged = rel[:, [j for j, n in enumerate(outputs) if n not in ignore]]
        entry[f"max_rel_error_{fid}"] = (float(np.max(judged, initial=0.0)) if np.all(np.isfinite(judged))
                                         else float("inf"))
        entry[f"relative_cost_{fid}"] = float(costs[fid])
    ok = [f for f in fidelities if entry[f"max_rel_error_{f}"] <= tolerance]
    entry["chosen"] = min(ok, key=lambda f: (costs[f], fidelities.index(f))) if ok else fidelities[0]
    return entry


def pilot_choice(model: Model, values: Mapping[str, NDArray[np.float64]], outputs: list[str],
                 tolerance: float) -> dict[str, Any]:
    """The one ``fidelity: auto`` decision of the Python API and of studies: :func:`choose_fidelity`
    on pilot ``values`` ({fidelity: (n_points, n_outputs)}, the richest first) with ``model``'s
    deterministic costs (:meth:`~ddgsa.models.Model.fidelity_cost`), its ``numerical_outputs``
    reported but not judged. The pilot points are the caller's: the nominal point plus the first
    points of an ``evaluate`` call (:class:`AutoFidelity`), or plus scrambled-Sobol' points of a
    study's space (``ddgsa.execute.kinds.common.select_fidelities``)."""
    costs = {fid: model.fidelity_cost(fid) for fid in values}
    return choose_fidelity(values, costs, outputs, tolerance, ignore=model.numerical_outputs)


class AutoFidelity(Model):
    """A model that runs each scene at the cheapest adequate fidelity of ``base`` (see the module)."""

    def __init__(self, name: str, tolerance: float = 0.02, pilot: int = 4, **options: Any) -> None:
        cls = MODELS.lookup(name)
        if not (isinstance(tolerance, (int, float)) and tolerance > 0):
            raise ModelError(f"model {name!r}: fidelity 'auto' needs a positive tolerance, got {tolerance!r}")
        if not (isinstance(pilot, int) and pilot >= 0):
            raise ModelError(f"model {name!r}: fidelity 'auto' needs pilot >= 0 points, got {pilot!r}")
        pool = cls.pilot_pool()
        self.variants = {fid: cls(fidelity=fid, **options) for fid in pool}
        richest = self.variants[pool[0]]
        # the wrapped model's identity, per instance (one wrapper class serves every model)
        self.name = name  # type: ignore[misc]
        self.fidelities = pool  # type: ignore[misc]
        self.fidelity = "auto"
        self.parameters, self.outputs = richest.parameters, richest.outputs
        self.tolerance, self.pilot = float(tolerance), pilot
        self.choices: dict[Scene, dict[str, Any]] = {}

    def choice(self, scene: Scene, points: pd.DataFrame | Mapping[str, Any] | None = None) -> dict[str, Any]:
        """The fidelity chosen for ``scene`` (piloted on first use; see the module)."""
        if scene not in self.choices:
            params = self.resolve(points)
            pilot = pd.concat([self.resolve(None), params.iloc[: self.pilot]], ignore_index=True)
            values = {fid: model.evaluate(pilot, pilot_scene(scene)).to_numpy(float)
                      for fid, model in self.variants.items()}
            self.choices[scene] = pilot_choice(self.variants[self.fidelities[0]], values, list(self.outputs),
                                               self.tolerance)
        return self.choices[scene]

    def evaluate(self, points: pd.DataFrame | Mapping[str, Any] | None, scene: Scene) -> pd.DataFrame:
        """Outputs at the chosen fidelity; ``attrs["fidelity"]`` holds the choice and its errors."""
        choice = self.choice(scene, points)
        out = self.variants[choice["chosen"]].evaluate(points, scene)
        out.attrs["fidelity"] = choice
        return out

    def _evaluate_one(self, params: dict[str, float], scene: Scene) -> dict[str, float]:
        return self.evaluate(params, scene).iloc[0].to_dict()

    def simulate(self, scene: Scene, params: Mapping[str, float] | None = None) -> pd.DataFrame:
        """The chosen fidelity's time series."""
        return self.variants[self.choice(scene, params)["chosen"]].simulate(scene, params)

    def modes(self, params: Mapping[str, float] | None = None, rotor_speed: float = 0.0) -> pd.DataFrame:
        """The richest fidelity's modes."""
        return self.variants[self.fidelities[0]].modes(params, rotor_speed)

    def campbell(self, speeds: Any, orders: Any = (1.0,), params: Mapping[str, float] | None = None,
                 max_frequency_hz: float = np.inf) -> CampbellDiagram:
        """The richest fidelity's Campbell diagram."""
        return self.variants[self.fidelities[0]].campbell(speeds, orders, params, max_frequency_hz)
