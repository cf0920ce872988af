"""Drive-train models, registered by name: ``ddgsa.models.get("direct_drive", fidelity="rigid")``."""

from __future__ import annotations

from ddgsa.models import analytic, direct_drive, generator_radial, indirect_drive  # noqa: F401  (register the models)
from ddgsa.models.base import (MODELS, ImplausibleOutputWarning, Model, ModelOutput, ModelParameter, get,
                               register_model)
from ddgsa.models.hss_rig import model as _hss_rig  # noqa: F401  (registers hss_rig)

__all__ = ["MODELS", "ImplausibleOutputWarning", "Model", "ModelOutput", "ModelParameter", "available", "get",
           "register_model"]


def available() -> list[str]:
    """Names of the registered models."""
    return sorted(MODELS)
