"""Shared pytest fixtures."""

from __future__ import annotations

import sys

import matplotlib
import pytest

matplotlib.use("Agg")


@pytest.fixture(autouse=True)
def _fresh_aliasing_memory():
    """Each test starts with the rig's once-per-process aliasing memory empty
    (``ddgsa.models.hss_rig.model._SHOWN``), so no test hides a warning from the next."""
    module = sys.modules.get("ddgsa.models.hss_rig.model")
    if module is not None:
        module._SHOWN.clear()
    yield
