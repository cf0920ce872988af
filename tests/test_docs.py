"""The documentation: README short and runnable (its example is a doctest), the mkdocs site builds
with ``--strict`` (no broken link), and the studies reference names every field of the schema
and of both scene types."""

from __future__ import annotations

import dataclasses
import doctest
import itertools
import re
import subprocess
import sys
from pathlib import Path

import pytest
import annotated_types
from pydantic import BaseModel
from pydantic.fields import FieldInfo

from ddgsa.loads.scene import Scene
from ddgsa.models.hss_rig.scenes import RigScene
from ddgsa.study.spec import ModelScenesSpec, StudySpec

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


def _scene_table(text: str, heading: str) -> dict[str, tuple[str, str]]:
    """``field -> (default, allowed)`` of the scene-field table that follows ``heading``."""
    rows = itertools.takewhile(lambda line: line.startswith("|") or not line,
                               text.split(heading, 1)[1].splitlines()[2:])
    cells = [[c.strip() for c in line.split("|")[1:-1]] for line in rows if line.startswith("| `")]
    return {c[0].strip("`"): (c[2].strip("`"), c[3]) for c in cells}


def test_the_scene_limits_the_docs_quote_are_the_codes() -> None:
    """Each default and allowed range in docs/studies.md's scene tables is the one the scene checks
    (``SCENE_LIMITS``, ``RIG_SCENE_LIMITS``, ``max_time_step()``, ``MIN_SAMPLES``, ``MIN_STEADY_REVS``), and
    the rig's default step in docs/hss_rig.md is ``MAX_DEFAULT_STEP``: a limit changed in one place fails here."""
    from ddgsa.loads.scene import SCENE_LIMITS, max_time_step
    from ddgsa.models.hss_rig.model import MAX_DEFAULT_STEP
    from ddgsa.models.hss_rig.scenes import MIN_SAMPLES, MIN_STEADY_REVS, RIG_SCENE_LIMITS

    text = (ROOT / "docs" / "studies.md").read_text()
    for scene_type, limits, heading in ((Scene, SCENE_LIMITS, "Wind scenes"), (RigScene, RIG_SCENE_LIMITS,
                                                                             "Test-rig scenes")):
        table = _scene_table(text, heading)
        defaults = {f.name: f.default for f in dataclasses.fields(scene_type)}
        for name, (default, allowed) in table.items():
            want = defaults[name]
            assert default == (f"{want:g}" if isinstance(want, float) else str(want)), name
            if name in limits:
                assert allowed.startswith(str(limits[name])), (name, allowed, str(limits[name]))
        assert set(limits) <= set(table)
    wind, rig = _scene_table(text, "Wind scenes"), _scene_table(text, "Test-rig scenes")
    assert f"({max_time_step():.3g} s)" in wind["dt"][1]
    assert f">= {MIN_STEADY_REVS} revolutions" in rig["duration"][1]
    assert f">= {MIN_SAMPLES} samples" in rig["sample_rate"][1]
    step = re.search(r"the largest step of at most ([0-9.e+-]+) s", (ROOT / "docs" / "hss_rig.md").read_text())
    assert step is not None and float(step[1]) == MAX_DEFAULT_STEP


def _bounded_fields(model: type[BaseModel], prefix: str = "") -> dict[str, FieldInfo]:
    """Every schema field, dotted, with its pydantic FieldInfo (defaults and bounds)."""
    out = {}
    for name, field in model.model_fields.items():
        out[prefix + name] = field
        for sub in (*getattr(field.annotation, "__args__", ()), field.annotation):
            if isinstance(sub, type) and issubclass(sub, BaseModel) and sub is not model:
                out |= _bounded_fields(sub, prefix + name + ".")
    return out


def test_the_studies_reference_quotes_the_schemas_defaults_and_bounds() -> None:
    """A default the field table of docs/studies.md gives as a number is the schema's, and a bound it
    quotes (``at most N``) is the schema's ``le``: written once in the code, checked in the docs."""
    text = (ROOT / "docs" / "studies.md").read_text()
    rows = {c[0].strip("`"): c for c in ([x.strip() for x in line.split("|")[1:-1]]
                                          for line in text.splitlines() if line.startswith("| `")) if len(c) == 3}
    fields = _bounded_fields(StudySpec)
    checked = 0
    for name, (_, default, meaning) in rows.items():
        field = fields.get(name)
        if field is None:
            continue
        if re.fullmatch(r"[-+]?[0-9][0-9.e+-]*", default):     # a number (not "the number of cores", "--")
            assert float(default) == field.default, name
            checked += 1
        le = [m.le for m in field.metadata if isinstance(m, annotated_types.Le)]
        quoted = re.findall(r"at most ([0-9][0-9 ,]*)", meaning)
        if le and quoted:
            assert float(quoted[0].replace(" ", "").replace(",", "")) == le[0], name
            checked += 1
    assert checked >= 10
