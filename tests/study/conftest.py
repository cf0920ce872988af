"""Helpers for study and CLI tests: write small study files."""

from __future__ import annotations

from pathlib import Path

import pytest
from studytext import analytic_study


@pytest.fixture
def write_study(tmp_path: Path):
    def write(name: str = "demo", options: str = "{}", n: int = 64, batch: int = 8, text: str | None = None) -> Path:
        path = tmp_path / f"{name}.yaml"
        path.write_text(text if text is not None else analytic_study(name, options, n, batch))
        return path

    return write
