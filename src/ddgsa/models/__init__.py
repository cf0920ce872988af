"""Drive-train models, registered by name: ``ddgsa.models.get("direct_drive", fidelity="rigid")``."""

from __future__ import annotations

from typing import Any

from ddgsa.models import analytic, direct_drive, generator_radial, indirect_drive  # noqa: F401  (register the models)
from ddgsa.models.auto import AutoFidelity
from ddgsa.models.base import MODELS, ImplausibleOutputWarning, Model, ModelOutput, ModelParameter, register_model
from ddgsa.models.hss_rig import model as _hss_rig  # noqa: F401  (registers hss_rig)

__all__ = ["MODELS", "ImplausibleOutputWarning", "Model", "ModelOutput", "ModelParameter", "available", "get",
           "register_model"]


def available() -> list[str]:
    """Names of the registered models."""
    return sorted(MODELS)


def get(name: str, **options: Any) -> "Model":
    """An instance of the registered model ``name`` with ``options`` (e.g. ``fidelity="rigid"``).

    ``fidelity="auto"`` (with optional ``tolerance``, default 0.02, and ``pilot``, default 4)
    returns a :class:`~ddgsa.models.auto.AutoFidelity` that picks the cheapest adequate fidelity
    per scene.

    Raises
    ------
    ModelError
        For an unknown model name (the message lists the known ones) or invalid options.
    """
    if options.get("fidelity") == "auto":
        rest = {k: v for k, v in options.items() if k != "fidelity"}
        return AutoFidelity(name, **rest)
    cls = MODELS.lookup(name)
    cls.check_options(options)
    return cls(**options)
