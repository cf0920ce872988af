"""The documentation: README short and runnable (its example is a doctest), the mkdocs site builds
with ``--strict`` (no broken link), and the studies reference names every field of the schema
and of both scene types."""

from __future__ import annotations

import dataclasses
import doctest
import subprocess
import sys
from pathlib import Path

import pytest
from pydantic import BaseModel

from ddgsa.loads.scene import Scene
from ddgsa.models.hss_rig.scenes import RigScene
from ddgsa.study import ModelScenesSpec, StudySpec

ROOT = Path(__file__).resolve().parents[1]
COMMANDS = ("pip install -e . && ddgsa run studies/quickstart.yaml",
            "pip install -e '.[test]' && python -m pytest -q -n auto")


def test_readme_is_short_and_starts_with_the_two_commands() -> None:
    lines = (ROOT / "README.md").read_text().splitlines()
    assert len(lines) <= 150
    top = "\n".join(lines[:6])
    assert all(c in top for c in COMMANDS)


def test_readme_example_runs_as_written() -> None:
    result = doctest.testfile(str(ROOT / "README.md"), module_relative=False, verbose=False,
                              optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted >= 6 and result.failed == 0


def _fields(model: type[BaseModel], prefix: str = "") -> list[str]:
    """The leaf fields of a schema part, dotted (a field with fields of its own gives those)."""
    out = []
    for name, field in model.model_fields.items():
        subs = [s for s in (*getattr(field.annotation, "__args__", ()), field.annotation)
                if isinstance(s, type) and issubclass(s, BaseModel) and s is not ModelScenesSpec]
        out += [f for s in subs for f in _fields(s, prefix + name + ".")] if subs else [prefix + name]
    return out


def test_the_studies_reference_names_every_field_and_scene_field_with_its_unit() -> None:
    text = (ROOT / "docs" / "studies.md").read_text()
    rows = {line.split("|")[1].strip().strip("`") for line in text.splitlines() if line.startswith("| `")}
    fields = _fields(StudySpec)
    # noise and parameters are maps: their rows are written per entry (fault.noise.<output>.absolute)
    documented = {f for f in fields if f in rows or any(r.startswith(f + ".<") for r in rows)}
    assert documented == set(fields) - {"scenes.wind_speed", "scenes.turbulence_intensity", "scenes.inclination_deg",
                                        "scenes.shear_exponent", "scenes.duration", "scenes.dt",
                                        "fault.faulty.start", "fault.faulty.stop", "fault.faulty.num",
                                        "fault.noise.absolute", "fault.noise.relative", "methods.method"}
    assert {"methods[].method", "fault.noise.<output>.absolute", "fault.noise.<output>.relative"} <= rows
    for scene_type in (Scene, RigScene):                        # the scene tables: field | unit | ...
        for f in dataclasses.fields(scene_type):
            if f.name != "seed":
                unit = scene_type.units[f.name] or "--"
                assert f"| `{f.name}` | {unit} |" in text, f.name


def test_the_documentation_site_builds_strictly(tmp_path: Path) -> None:
    pytest.importorskip("mkdocs", reason="mkdocs is in the test extra: pip install -e '.[test]'")
    run = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-q", "-d", str(tmp_path / "site")],
                         cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert (tmp_path / "site" / "studies" / "index.html").exists()
