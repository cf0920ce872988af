"""Hostile and malformed study files (issue 29 failures 2 and 3): each is exit 2 from ``ddgsa
validate``, names the file and the field, prints no traceback and a bounded message, and is
refused in bounded memory (tracemalloc peak) and CPU time, before anything is built.

Every case here failed before: the alias bomb grew without bound, the large sizes allocated
or hung, the encodings and nesting exited 1 with a raw error, and the names, duplicates and
model options passed validation.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from bounded import measured_validate
from ddgsa.study.spec import load_study

BASE = """\
name: demo
model: {name: analytic, fidelity: exact, options: {}}
parameters:
  x1: {low: -3.14159, high: 3.14159}
  x2: {low: -3.14159, high: 3.14159}
  x3: {low: -3.14159, high: 3.14159}
scenes: {wind_speed: [8.0, 11.0], turbulence_intensity: 0.0, duration: 1.0, dt: 0.05, realisations: 2}
outputs: [y, y_positive]
methods:
  - {method: mdrm, points: 5}
  - {method: saltelli, n: 64, seed: 0}
run: {jobs: 1, batch_size: 8}
"""
PEAK_BYTES = 64 << 20
"""Memory a refusal may take (the alias bomb below names 9^9 values)."""
CPU_S = 10.0
"""CPU time a refusal may take (generous: a loaded machine; it takes milliseconds)."""


def validate(path: Path) -> tuple[int, str]:
    """``ddgsa validate path`` in this process: exit code and stderr, with the memory and CPU bounds checked."""
    rc, text, peak, cpu = measured_validate(path)
    assert cpu < CPU_S
    assert peak < PEAK_BYTES, f"peak {peak / 2**20:.1f} MiB"
    assert "Traceback" not in text
    assert len(text) < 2000 and all(len(line) <= 620 for line in text.splitlines())
    return rc, text


def write(tmp_path: Path, text: str | bytes, name: str = "bad.yaml") -> Path:
    path = tmp_path / name
    path.write_bytes(text if isinstance(text, bytes) else text.encode())
    return path


BOMB = "".join(f"{c}: &{c} [" + ",".join([f"*{p}" if p else '"lol"'] * 9) + "]\n"
               for c, p in zip("abcdefghi", ["", *"abcdefgh"])) + "name: *i\n"


def test_an_alias_bomb_is_refused_after_counting_not_expanding(tmp_path: Path) -> None:
    rc, err = validate(write(tmp_path, BOMB))
    assert rc == 2 and "bad.yaml: names more than 200000 values once YAML aliases are expanded" in err


def test_a_recursive_alias_is_refused(tmp_path: Path) -> None:
    rc, err = validate(write(tmp_path, BASE + "description: &r [*r]\n"))
    assert rc == 2 and "recursive structure" in err


def test_a_long_bad_value_is_echoed_clipped(tmp_path: Path) -> None:
    rc, err = validate(write(tmp_path, BASE.replace("name: demo", "name: [" + ",".join(["1"] * 2000) + "]")))
    assert rc == 2 and "field 'name': Input should be a valid string (given: [1, 1, 1, 1, ...])" in err
    rc, err = validate(write(tmp_path, BASE + "kind: " + "x" * 100_000 + "\n"))
    assert rc == 2 and "field 'kind'" in err and "... (100002 characters)" in err and len(err) < 2000


@pytest.mark.parametrize("text, field", [
    (BASE.replace("wind_speed: [8.0, 11.0], turbulence_intensity: 0.0",
                  "wind_speed: [{}], turbulence_intensity: [{}]".format(
                      ", ".join(f"{5 + 1e-3 * i:.4f}" for i in range(3000)),
                      ", ".join(f"{1e-5 * i:.5f}" for i in range(3000)))), "scenes.wind_speed"),
    (BASE.replace("n: 64", "n: 1073741824"), "methods[1].n"),
    (BASE.replace("{method: mdrm, points: 5}", "{method: mdrm, points: 5, check: 1000000000}"), "methods[0].check"),
    (BASE.replace("{method: mdrm, points: 5}", "{method: auto, budget: 100000000000}"), "methods[0].budget"),
    (BASE.replace("realisations: 2", "realisations: 1000").replace("n: 64", "n: 4194304"), "methods[1].n"),
], ids=["grid_3000x3000", "saltelli_n", "mdrm_check", "auto_budget", "realisations_x_n"])
def test_a_run_too_large_for_the_machine_is_refused_naming_the_field_and_the_estimate(
        tmp_path: Path, text: str, field: str) -> None:
    """Before: a 3000 x 3000 grid hung the per-scene check; n, check and budget allocated 22, 48
    and 768 GiB. Now exit 2 naming the field and the estimate, before any design is built."""
    rc, err = validate(write(tmp_path, text))
    assert rc == 2 and f"bad.yaml: field '{field}': the study asks for" in err
    assert "GiB of memory" in err and "this machine has" in err


def test_the_run_size_estimate_counts_the_evaluations_the_pipeline_runs(write_study) -> None:
    """The estimate's evaluation count against the designs' own sizes: 2 scenes x 2 realisations
    x (M-DRM 1 + 3 x 5 + 32 check points + Saltelli 64 x 5)."""
    from ddgsa.study.limits import check_run_size, run_size

    study = load_study(write_study("demo", n=64))
    size = run_size(study.spec, study.space, 2)
    assert size.evaluations == 2 * 2 * (1 + 3 * 5 + 32 + 64 * 5)
    assert size.store_bytes == size.evaluations * (300 + 40 * 3 + 30 * 2)
    with pytest.raises(ValueError, match=r"field 'methods\[1\]\.n'.*this machine has 1 MiB"):
        check_run_size("demo.yaml", study.spec, study.space, 2, memory=lambda: 1 << 20)


@pytest.mark.parametrize("raw, message", [
    (BASE.encode("utf-16"), "the file is UTF-16 text (byte-order mark)"),
    (BASE.encode("utf-16-le"), "NUL character at line 1"),
    (BASE.replace("name: demo", "name: démo").encode("latin-1"), "not UTF-8 text (byte 0xe9 at line 1)"),
    (b"\xff" * 64, "not UTF-8 text"),
    (b"name: x\nmodel: " + b"[" * 5000 + b"]" * 5000, "nesting deeper than 32 levels"),
    ("".join(" " * i + f"k{i}:\n" for i in range(40)).encode(), "nesting deeper than 32 levels"),
    (b"x" * (1 << 20) + b"x", "a study file is at most 1 MiB"),
], ids=["utf16_bom", "utf16_no_bom", "latin1", "binary", "flow_nesting", "block_nesting", "over_1MiB"])
def test_encodings_nesting_and_size_of_the_file_are_exit_2_naming_the_file(tmp_path: Path, raw: bytes,
                                                                           message: str) -> None:
    """Before: UnicodeDecodeError and RecursionError, exit 1 with a raw error."""
    rc, err = validate(write(tmp_path, raw))
    assert rc == 2 and f"bad.yaml: {message}" in err


@pytest.mark.parametrize("old, new, message", [
    ("name: demo", "name: " + "n" * 300, "field 'name': String should have at most 64 characters"),
    ("name: demo", "name: '.'", "field 'name': '.' is not a folder name"),
    ("name: demo", "name: '..'", "field 'name': '..' is not a folder name"),
    ("outputs: [y, y_positive]", "outputs: [y, y_positive, y]", "field 'outputs[2]': 'y' is listed twice (also at [0])"),
    ("{method: mdrm, points: 5}", "{method: mdrm, points: 5}\n  - {method: mdrm, points: 5}",
     "field 'methods[1]': an identical entry is listed twice"),
    ("{method: saltelli, n: 64, seed: 0}", "{method: saltelli, n: 64, seed: 0}\n  - {method: mdrm, points: 3}",
     "field 'methods[2].method': method 'mdrm' is already given as methods[0]; one entry per method"),
    ("wind_speed: [8.0, 11.0]", "wind_speed: [8.0, 11.0, 8.0]", "field 'scenes.wind_speed[2]': 8.0 is listed twice"),
    ("options: {}", "options: {delay_s: .nan}",
     "field 'model.options': model 'analytic': option 'delay_s' must be a finite number in [0, 60] s, got nan"),
    ("options: {}", "options: {delay_s: -1}", "option 'delay_s' must be a finite number in [0, 60] s, got -1"),
    ("options: {}", "options: {delay_s: 1.0e+400}", "option 'delay_s' must be a finite number"),
    ("options: {}", "options: {fail_above: [1]}", "option 'fail_above' must be a finite number"),
    ("options: {}", "options: {delays: 1}", "unknown option 'delays'; known: delay_s, fail_above; did you mean 'delay_s'?"),
    ("name: demo", "name: demo\nname: again", "YAML syntax error at line 2, column 1: found duplicate key"),
], ids=["long_name", "name_dot", "name_dotdot", "duplicate_output", "duplicate_method", "repeated_method",
        "duplicate_scene_value",
        "delay_nan", "delay_negative", "delay_overflow", "fail_above_list", "option_misspelt", "duplicate_key"])
def test_names_duplicates_and_model_options_are_exit_2_naming_the_field(tmp_path: Path, old: str, new: str,
                                                                        message: str) -> None:
    """Before: a long name failed at run time (File name too long), '.' and '..' wrote into runs/
    or the current folder, duplicate outputs ran every point then failed, and delay_s: .nan made
    every evaluation fail."""
    assert old in BASE
    rc, err = validate(write(tmp_path, BASE.replace(old, new, 1)))
    assert rc == 2 and message in err and err.startswith(f"ddgsa: error: {tmp_path / 'bad.yaml'}: ")


def test_every_model_declares_its_options_and_the_declarations_match_the_constructors() -> None:
    """Each declared option is a constructor argument (and the reverse), so no option goes unchecked."""
    import inspect

    from ddgsa.models import MODELS

    for name in MODELS:
        cls = MODELS.lookup(name)
        assert cls.options is not None, name
        args = set(inspect.signature(cls.__init__).parameters) - {"self", "fidelity"}
        assert {o.name for o in cls.options} == args, name
