"""What every model is: declared parameters, named outputs, ``evaluate``/``simulate``/``modes``."""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
import pandas as pd

from ddgsa.errors import ModelError, unknown_name_message
from ddgsa.loads.scene import Scene
from ddgsa.registry import Registry

MODELS: Registry[type["Model"]] = Registry("model", ModelError)
register_model = MODELS.register


def get(name: str, **options: Any) -> "Model":
    """An instance of the registered model ``name`` with ``options`` (e.g. ``fidelity="rigid"``).

    ``fidelity="auto"`` (with optional ``tolerance``, default 0.02, and ``pilot``, default 4)
    returns a :class:`ddgsa.models.auto.AutoFidelity` that picks the cheapest adequate fidelity
    per scene.

    Raises
    ------
    ModelError
        For an unknown model name (the message lists the known ones) or invalid options.
    """
    if options.get("fidelity") == "auto":
        from ddgsa.models.auto import AutoFidelity

        rest = {k: v for k, v in options.items() if k != "fidelity"}
        return AutoFidelity(name, **rest)
    return MODELS.lookup(name)(**options)


@dataclass(frozen=True)
class ModelParameter:
    """A declared model parameter (OpenMDAO-style ``declare``).

    Attributes
    ----------
    name : str
    nominal : float
        Nominal value [unit].
    unit : str
    description : str
    low, high : float
        Allowed physical range (a study may not sample outside it).
    """

    name: str
    nominal: float
    unit: str
    description: str
    low: float = -math.inf
    high: float = math.inf


class Model(ABC):
    """Base class: parameters declared once, evaluated many points at a time.

    Subclasses set ``name`` (by :func:`register_model`), ``parameters`` and ``outputs`` and
    implement :meth:`_evaluate_one`, :meth:`simulate` and :meth:`modes`.
    """

    name: ClassVar[str] = ""
    parameters: tuple[ModelParameter, ...] = ()        # per class, or per instance where options change them
    outputs: tuple[str, ...] = ()
    fidelities: ClassVar[tuple[str, ...]] = ()
    options_note: ClassVar[str] = ""                   # how options change parameters/outputs (``ddgsa models``)
    fidelity: str = ""

    @property
    def nominal(self) -> dict[str, float]:
        """Parameter name -> nominal value (SI units)."""
        return {p.name: p.nominal for p in self.parameters}

    def parameter(self, name: str) -> ModelParameter:
        """The declaration of parameter ``name``."""
        for p in self.parameters:
            if p.name == name:
                return p
        raise ModelError(unknown_name_message(f"parameter of model {self.name!r}", name,
                                              [p.name for p in self.parameters], where="ddgsa models"))

    def parameter_table(self) -> pd.DataFrame:
        """Declared parameters as a table (name, nominal, unit, low, high, description)."""
        return pd.DataFrame([{"name": p.name, "nominal": p.nominal, "unit": p.unit, "low": p.low,
                              "high": p.high, "description": p.description} for p in self.parameters])

    def resolve(self, points: pd.DataFrame | Mapping[str, Any] | None) -> pd.DataFrame:
        """Full parameter table: given columns, nominal values for the missing ones.

        Raises
        ------
        ModelError
            For an unknown parameter name or a value outside its declared range.
        """
        if points is None:
            frame = pd.DataFrame([{}])
        elif isinstance(points, Mapping):
            frame = pd.DataFrame([dict(points)])
        else:
            frame = points.reset_index(drop=True)
        known = {p.name for p in self.parameters}
        unknown = [c for c in frame.columns if c not in known]
        if unknown:
            raise ModelError(f"model {self.name!r} has no parameter(s) {unknown}; known: {', '.join(sorted(known))}")
        out = pd.DataFrame({p.name: frame[p.name].astype(float) if p.name in frame else p.nominal
                            for p in self.parameters}, index=range(len(frame)))
        for p in self.parameters:
            col = out[p.name].to_numpy()
            bad = ~((col >= p.low) & (col <= p.high))
            if bad.any():
                raise ModelError(f"model {self.name!r}: parameter {p.name!r} = {col[bad][0]} is outside its "
                                 f"allowed range [{p.low}, {p.high}] {p.unit}")
        return out

    def evaluate(self, points: pd.DataFrame | Mapping[str, Any] | None, scene: Scene) -> pd.DataFrame:
        """Objective functions at each parameter point for ``scene``.

        Returns one row per point and one column per output. A point whose simulation fails
        gets NaN outputs and its reason in ``result.attrs["failures"]`` ({row: reason}); it is
        never imputed.
        """
        params = self.resolve(points)
        rows, failures = [], {}
        for i, row in enumerate(params.to_dict("records")):
            try:
                rows.append(self._evaluate_one(row, scene))
            except (ArithmeticError, RuntimeError, ValueError, np.linalg.LinAlgError) as exc:
                failures[i] = f"{type(exc).__name__}: {exc}"
                rows.append({o: np.nan for o in self.outputs})
        out = pd.DataFrame(rows, columns=list(self.outputs))
        out.attrs["failures"] = failures
        return out

    @abstractmethod
    def _evaluate_one(self, params: dict[str, float], scene: Scene) -> dict[str, float]:
        """Outputs for one full parameter set."""

    @abstractmethod
    def simulate(self, scene: Scene, params: Mapping[str, float] | None = None) -> pd.DataFrame:
        """Time series (indexed by time [s]) of states, bearing forces and loads."""

    @abstractmethod
    def modes(self, params: Mapping[str, float] | None = None) -> pd.DataFrame:
        """Natural frequencies [Hz] and labels."""

    def sampling_checks(self, scene: Scene) -> list[dict[str, Any]]:
        """The aliasing guard's table for ``scene`` at nominal parameters
        (:func:`ddgsa.mbs.sampling.sampling_row` rows); none for a model without modes."""
        return []
