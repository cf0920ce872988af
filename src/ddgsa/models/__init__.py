"""Drive-train models, registered by name: ``ddgsa.models.get("direct_drive", fidelity="rigid")``."""

from __future__ import annotations

from ddgsa.models import analytic, direct_drive, generator_radial, indirect_drive  # noqa: F401  (register the models)
from ddgsa.models.base import MODELS, Model, ModelParameter, get, register_model

__all__ = ["MODELS", "Model", "ModelParameter", "available", "get", "register_model"]


def available() -> list[str]:
    """Names of the registered models."""
    return sorted(MODELS)
