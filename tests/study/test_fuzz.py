"""Property-based fuzzing of study files (issue 29): malformed studies generated from the schema.

Hypothesis draws a hundred malformed studies (three hundred in the slow run): a value that breaks
the JSON schema of :class:`ddgsa.study.spec.StudySpec` at a field (wrong type, out of range, not in the
enum, over the length, an empty grid axis), an unknown key or a missing required one, a top-level
that is not a mapping, an invalid model option, a name that is not one safe path component, a value
listed twice, and hostile files (alias bombs, deep nesting, other encodings, NUL bytes). Each is
given to ``ddgsa validate`` in this process (the CLI's ``main``) and must give exit 2, a message
naming the file (and a field, where it is a field's fault), no traceback, a bounded message,
nothing written, and stay within a memory bound (tracemalloc peak) and a CPU-time bound. A
few run as real subprocesses under an address-space limit.
"""

from __future__ import annotations

import copy
import io
import math
import os
import resource
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from ruamel.yaml import YAML

from bounded import measured_validate
from ddgsa.study.spec import StudySpec

VALID: dict[str, Any] = {
    "name": "fuzz",
    "model": {"name": "analytic", "fidelity": "exact", "options": {}},
    "parameters": {f"x{i}": {"low": -3.0, "high": 3.0} for i in (1, 2, 3)},
    "scenes": {"wind_speed": [8.0, 11.0], "turbulence_intensity": 0.0, "duration": 1.0, "dt": 0.05,
               "realisations": 2},
    "outputs": ["y", "y_positive"],
    "methods": [{"method": "mdrm", "points": 3, "check": 8}, {"method": "saltelli", "n": 16, "seed": 0}],
    "run": {"jobs": 1, "batch_size": 8},
}
PEAK_BYTES = 64 << 20
"""Memory one refusal may take [B] (Python allocations, tracemalloc)."""
CPU_S = 10.0
"""CPU time one refusal may take [s] (they take milliseconds; generous for a loaded machine)."""
CWD = Path.cwd()


def _leaves(schema: dict[str, Any]) -> list[tuple[tuple[Any, ...], dict[str, Any]]]:
    """``(path, subschema)`` of every field of the study schema (the wind scenes' and the fault
    block's branch of a union; ``methods`` items at index 0)."""
    defs = schema.get("$defs", {})
    out: list[tuple[tuple[Any, ...], dict[str, Any]]] = []

    def walk(sch: dict[str, Any], path: tuple[Any, ...]) -> None:
        if "$ref" in sch:
            sch = defs[sch["$ref"].split("/")[-1]]
        branches = [b for b in sch.get("anyOf", []) if "$ref" in b]
        if branches and path[-1:] in (("scenes",), ("fault",)):
            walk(branches[0], path)
            return
        if sch.get("type") == "array" and "$ref" in sch.get("items", {}):
            walk(sch["items"], (*path, 0))
            return
        if sch.get("type") == "object" and "properties" in sch:
            for key, sub in sch["properties"].items():
                walk(sub, (*path, key))
            return
        out.append((path, sch))

    walk(schema, ())
    return out


LEAVES = _leaves(StudySpec.model_json_schema())
OBJECTS = [(), ("model",), ("model", "auto"), ("scenes",), ("run",), ("parameters", "x1"), ("methods", 0),
           ("model", "options")]
"""Mappings of the valid study where an unknown key is refused."""


def _types(sch: dict[str, Any]) -> set[str]:
    return {sch["type"]} if "type" in sch else {t.get("type", "") for t in sch.get("anyOf", [])}


def violations(sch: dict[str, Any]) -> list[Any]:
    """Values that break ``sch``: another type, beyond a bound, outside the enum, too long."""
    types = _types(sch)
    bad: list[Any] = []
    if "enum" in sch:
        bad.append("no_such_choice")
    if types & {"integer", "number"}:
        bad += ["not a number", {"a": 1}]
        if "integer" in types:
            bad += [1.5]
        for key, step in (("minimum", -1), ("exclusiveMinimum", 0), ("maximum", 1), ("exclusiveMaximum", 0)):
            if key in sch:
                bad.append(sch[key] + step)
    if types & {"string"}:
        bad += [12345, [1, 2], {"a": 1}]
        if "maxLength" in sch:
            bad.append("n" * (sch["maxLength"] + 1))
        if "pattern" in sch:
            bad += ["a/b", "", "with space"]
    if types == {"object"}:
        bad += ["a string", [1, 2], 5]
    if types == {"array"}:
        bad += ["a string", 5, {"a": 1}]
        if sch.get("items", {}).get("type") in ("number", "integer"):
            bad.append(["x"])
        if sch.get("items", {}).get("type") == "string":
            bad.append([5])
    if types == {"number", "array"}:
        bad += [[]]                           # an empty scene axis
    return bad


def put(study: dict[str, Any], path: tuple[Any, ...], value: Any) -> None:
    """Set ``study[path]`` to ``value``, creating mappings on the way."""
    node: Any = study
    for key in path[:-1]:
        if isinstance(node, dict):
            node = node.setdefault(key, {})
        else:
            node = node[key]
    node[path[-1]] = value


def dump(data: Any) -> bytes:
    stream = io.StringIO()
    YAML(typ="safe", pure=True).dump(data, stream)
    return stream.getvalue().encode()


def bomb(levels: int) -> bytes:
    lines = ['l0: &l0 ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    lines += [f"l{k}: &l{k} [" + ", ".join([f"*l{k - 1}"] * 9) + "]" for k in range(1, levels)]
    return ("\n".join(lines) + f"\nname: *l{levels - 1}\n").encode()


@st.composite
def schema_violation(draw: st.DrawFn) -> tuple[bytes, bool]:
    path, sch = draw(st.sampled_from([(p, s) for p, s in LEAVES if violations(s)]))
    study = copy.deepcopy(VALID)
    put(study, path, draw(st.sampled_from(violations(sch))))
    return dump(study), True


@st.composite
def unknown_key(draw: st.DrawFn) -> tuple[bytes, bool]:
    study = copy.deepcopy(VALID)
    path = draw(st.sampled_from(OBJECTS))
    key = draw(st.sampled_from(["nmae", "wind_sped", "relisations", "delay", "extra_field", "typo"]))
    put(study, (*path, key), draw(st.sampled_from([1, "x", [1.0]])))
    return dump(study), True


@st.composite
def missing_key(draw: st.DrawFn) -> tuple[bytes, bool]:
    study = copy.deepcopy(VALID)
    path = draw(st.sampled_from([("name",), ("model",), ("model", "name"), ("methods", 0, "method"),
                                 ("parameters",), ("methods",)]))
    node: Any = study
    for key in path[:-1]:
        node = node[key]
    del node[path[-1]]
    return dump(study), True


@st.composite
def bad_option(draw: st.DrawFn) -> tuple[bytes, bool]:
    study = copy.deepcopy(VALID)
    key = draw(st.sampled_from(["delay_s", "fail_above"]))
    value = draw(st.sampled_from([math.nan, math.inf, -math.inf, "x", [1.0], {"a": 1}]
                                 + ([-1e-3, -1.0, 61.0, True] if key == "delay_s" else [])))
    study["model"]["options"][key] = value
    return dump(study), True


@st.composite
def bad_name_or_duplicate(draw: st.DrawFn) -> tuple[bytes, bool]:
    study = copy.deepcopy(VALID)
    choice = draw(st.integers(0, 3))
    if choice == 0:
        study["name"] = draw(st.sampled_from([".", "..", "...", "a" * 65, "a/b", "../x", "/abs"]))
    elif choice == 1:
        study["outputs"] = draw(st.permutations(["y", "y", "y_positive"]))
    elif choice == 2:
        study["scenes"]["wind_speed"] = [8.0, 11.0, draw(st.sampled_from([8.0, 11.0]))]
    else:
        study["methods"].append(copy.deepcopy(study["methods"][draw(st.integers(0, 1))]))
    return dump(study), True


@st.composite
def hostile_file(draw: st.DrawFn) -> tuple[bytes, bool]:
    """File-level problems: the message names the file (no field is at fault)."""
    choice = draw(st.integers(0, 6))
    valid = dump(VALID)
    if choice == 0:
        return bomb(draw(st.integers(7, 12))), False
    if choice == 1:
        depth = draw(st.integers(33, 3000))
        return b"name: x\nmodel: " + b"[" * depth + b"]" * depth + b"\n", False
    if choice == 2:
        return valid.decode().encode(draw(st.sampled_from(["utf-16", "utf-32", "utf-16-le", "utf-16-be"]))), False
    if choice == 3:
        k = draw(st.integers(0, len(valid) - 1))
        return valid[:k] + draw(st.sampled_from([b"\xff", b"\xc3\x28", b"\x80", b"\x00"])) + valid[k:], False
    if choice == 4:
        return draw(st.sampled_from([b"- 1\n- 2\n", b"42\n", b"just a string\n", b"", b"null\n", b"[]\n"])), False
    if choice == 5:
        return b"name: &r [*r]\n" + valid, False
    return valid + b"\n" + draw(st.sampled_from([b"name: again\n", b"model: {name: analytic}\n"])), False


MALFORMED = st.one_of(schema_violation(), schema_violation(), unknown_key(), missing_key(), bad_option(),
                      bad_name_or_duplicate(), hostile_file())


def _listing(folder: Path) -> set[str]:
    return {p.name for p in folder.iterdir()}


FUZZ = {"deadline": None, "database": None, "derandomize": True,
        "suppress_health_check": [HealthCheck.too_slow, HealthCheck.data_too_large]}


@settings(max_examples=100, **FUZZ)
@given(case=MALFORMED)
def test_every_malformed_study_is_exit_2_naming_the_file_and_field_in_bounded_time_and_memory(
        case: tuple[bytes, bool]) -> None:
    """100 drawn studies in the default run; the slow twin below draws 300. Each kind of fault is also
    checked one by one in the default run: hostile files, names, duplicates and model options in
    ``test_bad_input.py``, malformed fields in ``test_cli.py::test_malformed_studies_exit_2_naming_the_field``."""
    _malformed_is_exit_2(case)


@pytest.mark.slow
@settings(max_examples=300, **FUZZ)
@given(case=MALFORMED)
def test_three_hundred_malformed_studies_are_exit_2_naming_the_file_and_field(case: tuple[bytes, bool]) -> None:
    _malformed_is_exit_2(case)


def _malformed_is_exit_2(case: tuple[bytes, bool]) -> None:
    """``ddgsa validate`` of one drawn study: exit 2, the file (and field) named, no traceback, a bounded
    message, nothing written, within the memory and CPU bounds."""
    raw, names_field = case
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        path = folder / "study.yaml"
        path.write_bytes(raw)
        cwd_before = _listing(CWD)
        rc, text, peak, cpu = measured_validate(path)
        assert rc == 2, (raw[:300], text)
        assert text.startswith(f"ddgsa: error: {path}: "), text
        if names_field:
            assert "field '" in text, text
        assert "Traceback" not in text
        assert len(text) < 13_000 and all(len(line) <= 620 for line in text.splitlines())
        assert _listing(folder) == {"study.yaml"} and _listing(CWD) == cwd_before    # nothing written
        assert peak < PEAK_BYTES, f"peak {peak / 2**20:.1f} MiB"
        assert cpu < CPU_S, f"{cpu:.1f} s CPU"


def _limit_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))       # 3 GiB: imports need ~1 GiB of address space


@pytest.mark.parametrize("raw", [bomb(12), b"name: x\nmodel: " + b"[" * 100_000 + b"]" * 100_000],
                         ids=["alias_bomb_9^12", "nesting_100000"])
def test_hostile_files_in_a_real_process_are_exit_2_without_traceback(tmp_path: Path, raw: bytes) -> None:
    """The CLI as users run it, under a 3 GiB address-space limit (the alias bomb used to grow ~25 MB/s)."""
    path = tmp_path / "study.yaml"
    path.write_bytes(raw)
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[2] / "src")}
    proc = subprocess.run([sys.executable, "-m", "ddgsa.cli", "validate", str(path)], capture_output=True, text=True,
                          env=env, timeout=300, preexec_fn=_limit_memory)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.startswith(f"ddgsa: error: {path}: ") and "Traceback" not in proc.stderr
    assert len(proc.stderr) < 600 and _listing(tmp_path) == {"study.yaml"}
