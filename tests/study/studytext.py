"""Study texts the study and CLI tests share (imported by ``conftest.py`` and by tests that start
the CLI in a separate process)."""

from __future__ import annotations

MDRM_AND_SALTELLI = "  - {{method: mdrm, points: 5}}\n  - {{method: saltelli, n: {n}, seed: 0}}\n"
SALTELLI = "  - {{method: saltelli, n: {n}, seed: 0}}\n"

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
{methods}run: {{jobs: {jobs}, batch_size: {batch}}}
"""


def analytic_study(name: str = "demo", options: str = "{}", n: int = 64, batch: int = 8, jobs: int = 1,
                   methods: str = MDRM_AND_SALTELLI) -> str:
    """The analytic (Ishigami) model's study at two wind speeds with ``methods`` (a YAML list's lines
    with ``{n}`` for the Saltelli base sample)."""
    return ANALYTIC.format(name=name, options=options, methods=methods.format(n=n), jobs=jobs, batch=batch)


ISHIGAMI = """\
name: {name}
model: {{name: analytic, fidelity: exact}}
parameters:
  x1: {{low: -{pi}, high: {pi}}}
  x2: {{low: -{pi}, high: {pi}}}
  x3: {{low: -{pi}, high: {pi}}}
scenes: {{wind_speed: [{speeds}], turbulence_intensity: 0.0, duration: 1.0, dt: 0.05}}
outputs: [{output}]
"""


def ishigami_study(name: str, tail: str, speeds: str = "8.0", output: str = "y_positive",
                   pi: str = "3.14159265") -> str:
    """The analytic model's study of one output (one realisation per scene at ``speeds``) over the
    Ishigami inputs on [-``pi``, ``pi``], followed by ``tail`` (its methods and any other fields, as YAML)."""
    return ISHIGAMI.format(name=name, speeds=speeds, output=output, pi=pi) + tail
