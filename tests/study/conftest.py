"""Helpers for study and CLI tests: write small study files."""

from __future__ import annotations

from pathlib import Path

import pytest

ANALYTIC = """\
name: {name}
model: {{name: analytic, fidelity: exact, options: {options}}}
parameters:
  x1: {{low: -3.14159, high: 3.14159}}
  x2: {{low: -3.14159, high: 3.14159}}
  x3: {{low: -3.14159, high: 3.14159}}
scenes: {{wind_speed: [8.0, 11.0], turbulence_intensity: 0.0, duration: 1.0, dt: 0.05, realisations: 2}}
outputs: [y, y_positive]
methods:
  - {{method: mdrm, points: 5}}
  - {{method: saltelli, n: {n}, seed: 0}}
run: {{jobs: 1, batch_size: {batch}}}
"""


@pytest.fixture
def write_study(tmp_path: Path):
    def write(name: str = "demo", options: str = "{}", n: int = 64, batch: int = 8, text: str | None = None) -> Path:
        path = tmp_path / f"{name}.yaml"
        path.write_text(text if text is not None else ANALYTIC.format(name=name, options=options, n=n, batch=batch))
        return path

    return write
