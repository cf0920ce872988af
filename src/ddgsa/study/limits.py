"""Bounds on a study: the file it is read from, and the run it asks for.

A study file is read in bounded time and memory whatever it holds: at most
:data:`MAX_FILE_BYTES`, UTF-8 (a UTF-16 or other encoding is named, not guessed), nesting at
most :data:`MAX_DEPTH` levels (checked on the text before parsing, so ``[[[[...`` never
reaches the parser's recursion), and at most :data:`MAX_NODES` values once YAML aliases are
expanded (a "billion laughs" file of a few hundred bytes names a billion values: refused
after counting, never expanded). Every refusal is a :class:`~ddgsa.errors.StudyError`
naming the file (exit 2).

The run a valid study asks for is estimated before anything is written (:func:`run_size`):
model evaluations, the memory the pipeline holds for them and the evaluation store's size
on disk. A study whose estimate exceeds the machine's memory is refused, naming the field
that makes it large (the largest factor) and the estimate (:func:`check_run_size`).
"""

from __future__ import annotations

import math
import os
import re
import stat
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ruamel.yaml import YAML
from ruamel.yaml.error import YAMLError

from ddgsa.errors import MESSAGE_INPUT_CHARS, StudyError, clip

MAX_FILE_BYTES = 1 << 20
"""A study file is at most 1 MiB (the committed studies are under 10 kB)."""
MAX_DEPTH = 32
"""Nesting levels a study may use (a study uses at most 5)."""
MAX_NODES = 200_000
"""Values (mapping entries, list items, scalars) a study may name, aliases expanded."""

_BOMS = ((b"\xff\xfe\x00\x00", "UTF-32"), (b"\x00\x00\xfe\xff", "UTF-32"), (b"\xff\xfe", "UTF-16"),
         (b"\xfe\xff", "UTF-16"))
_QUOTED_OR_COMMENT = re.compile(r"'(?:[^']|'')*'|\"(?:[^\"\\]|\\.)*\"|(?:^|(?<=\s))#[^\n]*")


def read_text(path: Path, what: str = "study file") -> str:
    """The text of a study file, or of a file it names (``what``): a regular file of at most
    :data:`MAX_FILE_BYTES`, UTF-8 (a UTF-8 byte-order mark is dropped).

    A path that is not a regular file (a FIFO, a device, a folder, a socket) is refused from
    its ``stat``, before it is opened for reading (opening a FIFO would wait for a writer), and
    the file is opened non-blocking and checked again once open.

    Raises
    ------
    StudyError
        For a missing or unreadable file, one that is not a regular file, one too large, or one
        that is not UTF-8 text.
    """
    try:
        kind = _file_kind(os.stat(path).st_mode)
        if kind is None:
            fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
            with os.fdopen(fd, "rb") as handle:
                kind = _file_kind(os.fstat(handle.fileno()).st_mode)
                raw = handle.read(MAX_FILE_BYTES + 1) if kind is None else b""
    except FileNotFoundError:
        raise StudyError(f"{path}: no such {what}") from None
    except OSError as exc:
        raise StudyError(f"{path}: cannot read the {what}: {exc.strerror or exc}") from None
    if kind is not None:
        raise StudyError(f"{path}: the {what} is {kind}, not a regular file; name a file")
    if len(raw) > MAX_FILE_BYTES:
        raise StudyError(f"{path}: a {what} is at most {MAX_FILE_BYTES >> 20} MiB; this one is larger")
    for bom, name in _BOMS:
        if raw.startswith(bom):
            raise StudyError(f"{path}: the file is {name} text (byte-order mark); study files are UTF-8: save it "
                             "as UTF-8")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[:exc.start].count(b"\n") + 1
        raise StudyError(f"{path}: not UTF-8 text (byte 0x{raw[exc.start]:02x} at line {line}); study files are "
                         "UTF-8: save it as UTF-8") from None
    if "\x00" in text:
        line = text[:text.index("\x00")].count("\n") + 1
        raise StudyError(f"{path}: NUL character at line {line} (UTF-16 text without a byte-order mark?); study "
                         "files are UTF-8 text")
    return text


def _file_kind(mode: int) -> str | None:
    """None for a regular file, else what the file is (``a FIFO``, ``a folder``, ...)."""
    if stat.S_ISREG(mode):
        return None
    kinds = ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISCHR, "a character device"),
             (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))
    return next((name for test, name in kinds if test(mode)), "not a regular file")


def text_depth(text: str) -> int:
    """An upper estimate of the nesting depth of YAML ``text``: block indentation levels plus
    flow brackets (``[``, ``{``) open on the deepest line, outside quotes and comments."""
    bare = _QUOTED_OR_COMMENT.sub("", text)
    deepest, flow, indents = 0, 0, [0]
    for line in bare.splitlines():
        stripped = line.lstrip(" ")
        if not stripped.strip():
            continue
        indent = len(line) - len(stripped)
        if flow == 0:
            while indent < indents[-1]:
                indents.pop()
            if indent > indents[-1]:
                indents.append(indent)
        dashes = re.match(r"(?:-\s+)*", stripped).group(0).count("-")          # "- - x" nests twice
        peak = flow
        for ch in stripped:
            if ch in "[{":
                flow += 1
                peak = max(peak, flow)
            elif ch in "]}":
                flow = max(flow - 1, 0)
        deepest = max(deepest, len(indents) + dashes + peak)
    return deepest


def _expanded_size(data: Any, path: Path) -> tuple[int, int]:
    """``(values, depth)`` of loaded YAML data with aliases expanded, counted without expanding
    them (each shared object once, memoised); a structure that contains itself is refused."""
    memo: dict[int, tuple[int, int]] = {}
    stack: list[tuple[Any, bool]] = [(data, False)]
    open_ids: set[int] = set()
    while stack:
        obj, done = stack.pop()
        if not isinstance(obj, (dict, list)):
            continue
        key = id(obj)
        children = list(obj.keys()) + list(obj.values()) if isinstance(obj, dict) else obj
        if done:
            open_ids.discard(key)
            size, depth = 1, 1
            for child in children:
                s, d = memo.get(id(child), (1, 0)) if isinstance(child, (dict, list)) else (1, 0)
                size += s
                depth = max(depth, d + 1)
            memo[key] = (min(size, MAX_NODES + 1), depth)
            continue
        if key in memo:
            continue
        if key in open_ids:
            raise StudyError(f"{path}: a YAML alias refers to a mapping or list that contains it (a recursive "
                             "structure); a study is a tree")
        open_ids.add(key)
        stack.append((obj, True))
        stack.extend((child, False) for child in children if isinstance(child, (dict, list)))
    return memo.get(id(data), (1, 0))


def load_yaml(path: Path, what: str = "study file") -> tuple[Any, str]:
    """Read a YAML 1.2 study file (or a YAML file it names, ``what``) in bounded time and memory
    (``1e10`` is a number); errors name the file and the line.

    Raises
    ------
    StudyError
        For an unreadable, oversized or non-UTF-8 file, nesting deeper than :data:`MAX_DEPTH`,
        more than :data:`MAX_NODES` values (aliases expanded), a recursive alias, a YAML
        syntax error (duplicate keys included), or an unordered ``!!set``.
    """
    text = read_text(path, what)
    if text_depth(text) > MAX_DEPTH:
        raise StudyError(f"{path}: nesting deeper than {MAX_DEPTH} levels; a study needs at most a few")
    try:
        data = YAML(typ="safe", pure=True).load(text)
    except YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        problem = problem if len(problem) <= MESSAGE_INPUT_CHARS else problem[:MESSAGE_INPUT_CHARS] + "..."
        raise StudyError(f"{path}: YAML syntax error{where}: {problem}") from None
    except RecursionError:                               # not reached past text_depth; kept as a last guard
        raise StudyError(f"{path}: nesting deeper than {MAX_DEPTH} levels; a study needs at most a few") from None
    refuse_unordered(data, str(path))
    size, depth = _expanded_size(data, path)
    if size > MAX_NODES:
        raise StudyError(f"{path}: names more than {MAX_NODES} values once YAML aliases are expanded (an alias "
                         "bomb?); a study needs a few hundred")
    if depth > MAX_DEPTH:
        raise StudyError(f"{path}: nesting deeper than {MAX_DEPTH} levels; a study needs at most a few")
    return data, text


def refuse_unordered(data: Any, where: str) -> None:
    """Refuse a set anywhere in study data (YAML's ``!!set``, or a Python set given to the API):
    its order, and with it the order of outputs and the study's digest, would depend on the
    process's hash seed (``PYTHONHASHSEED``).

    Raises
    ------
    StudyError
        Naming ``where`` and the field that holds the set.
    """
    stack: list[tuple[Any, str]] = [(data, "")]
    seen: set[int] = set()
    while stack:
        obj, field = stack.pop()
        if isinstance(obj, (set, frozenset)):
            at = f" field '{field}':" if field else ""
            raise StudyError(f"{where}:{at} an unordered set (YAML '!!set' or '? item' entries); its order would "
                             "change from run to run: write a list ('- item' or '[a, b]')")
        if not isinstance(obj, (dict, list)) or id(obj) in seen:
            continue
        seen.add(id(obj))
        items = obj.items() if isinstance(obj, dict) else enumerate(obj)
        stack.extend((v, f"{field}.{k}" if field and isinstance(k, str) else f"{field}[{k}]" if field else str(k))
                     for k, v in items)


BYTES_PER_EVALUATION = (1000.0, 300.0, 100.0)
"""Memory the pipeline holds per model evaluation [B]: ``a + b d + c k`` for ``d`` parameters and
``k`` outputs (task, key, point and scene dicts, stored outcome, evaluation table row, the
analyses' arrays). Measured: peak RSS of ``ddgsa run`` on the analytic model (d = 3, k = 2)
grew by 1.85 kB per evaluation from 5 120 to 81 920 evaluations; the constants give 2.1 kB."""
STORE_BYTES_PER_EVALUATION = (300.0, 40.0, 30.0)
"""Evaluation-store size per evaluation [B], ``a + b d + c k``. Measured: 456 B (d = 3, k = 2,
81 920 evaluations, 37.4 MB); the constants give 480 B."""
BYTES_PER_SCENE = 2000.0
"""Memory per planned scene realisation [B] (its scene object and grid entry)."""
MAX_CHECKED_SCENES = 10_000
"""Scene grids up to this size are validated point by point; larger ones axis by axis (every value
of every axis, the other axes at their first value), so validation stays within seconds."""
SIZE_OPTIONS = ("n", "budget", "check", "points", "order", "samples")
"""Method options that set a design's size, the field a too-large study is told to reduce."""


@dataclass(frozen=True)
class RunSize:
    """What a study asks for: evaluations, memory [B], evaluation-store size [B], and the factors
    ``(field, size)`` they are products of."""

    evaluations: int
    scenes: int
    realisations: int
    memory_bytes: float
    store_bytes: float
    factors: tuple[tuple[str, int], ...]
    groups: tuple[tuple[str, int], ...]
    """The factors grouped (the scene grid, the realisations, the points per scene...), each
    named by its largest field."""

    @property
    def largest(self) -> str:
        """The field to reduce: the largest field of the largest group."""
        return max(self.groups, key=lambda f: f[1])[0] if self.groups else "scenes"

    def describe(self) -> str:
        """``N model evaluations (field = size x ...), about X GiB of memory and Y GiB of store``."""
        per_scene = self.evaluations // max(self.scenes * self.realisations, 1)
        return (f"{self.evaluations:.4g} model evaluations ({self.scenes:.4g} scenes x {self.realisations} "
                f"realisations x {per_scene:.4g} points), about {gib(self.memory_bytes)} of memory "
                f"and {gib(self.store_bytes)} of evaluation store")


def gib(n_bytes: float) -> str:
    """``12.3 GiB`` (MiB below one GiB)."""
    return f"{n_bytes / 2**30:.3g} GiB" if n_bytes >= 2**30 else f"{n_bytes / 2**20:.3g} MiB"


def scene_axes(scenes: Any) -> dict[str, list[Any]]:
    """The grid axes of a ``scenes:`` spec (every label field, one value for a scalar), as its
    ``grid()`` forms them, without forming the grid."""
    if hasattr(scenes, "label_fields"):                       # a model's own scene type
        import dataclasses

        defaults = {f.name: f.default for f in dataclasses.fields(scenes._type)}
        values = {k: scenes.fields.get(k, defaults[k]) for k in scenes.label_fields}
    else:
        values = {k: getattr(scenes, k) for k in ("wind_speed", "turbulence_intensity", "inclination_deg",
                                                   "shear_exponent")}
    return {k: (v if isinstance(v, list) else [v]) for k, v in values.items()}


def scenes_to_check(scenes: Any) -> list[dict[str, Any]]:
    """The grid points a study's validation builds a scene for: all of them up to
    :data:`MAX_CHECKED_SCENES`, else every value of every axis with the others at their first."""
    axes = scene_axes(scenes)
    if math.prod(len(v) for v in axes.values()) <= MAX_CHECKED_SCENES:
        return scenes.grid()
    first = {k: v[0] for k, v in axes.items()}
    return [first] + [{**first, k: x} for k, values in axes.items() for x in values[1:]]


def _size_field(prefix: str, options: dict[str, Any]) -> str:
    given = [(k, v) for k, v in options.items() if k in SIZE_OPTIONS and isinstance(v, (int, float))
             and not isinstance(v, bool)]
    return f"{prefix}.{max(given, key=lambda kv: kv[1])[0]}" if given else prefix


def _method_points(methods: list[Any], space: Any, prefix: str = "methods") -> list[tuple[str, int]]:
    """``(field, points)`` of each method's design on ``space``; a method whose options are invalid
    counts 0 (the study's method checks report it, before any design is built)."""
    from ddgsa.errors import DdgsaError
    from ddgsa.gsa.auto import resolve_auto_options
    from ddgsa.gsa.base import get_method

    out = []
    for i, m in enumerate(methods):
        try:
            n = (resolve_auto_options(space, m.options)["budget"] if m.method == "auto"
                 else get_method(m.method).n_points(space, **m.options))
        except (DdgsaError, TypeError, ValueError, OverflowError):
            n = 0
        out.append((_size_field(f"{prefix}[{i}]", m.options), int(n)))
    return out


def run_size(spec: Any, space: Any, n_outputs: int) -> RunSize:
    """Estimate what a validated study spec asks for (see :class:`RunSize`), without building
    its designs or its scene grid."""
    axes = scene_axes(spec.scenes)
    realisations = int(spec.scenes.realisations)
    factors: list[tuple[str, int]] = [(f"scenes.{k}", len(v)) for k, v in axes.items()]
    factors.append(("scenes.realisations", realisations))
    n_scenes = math.prod(len(v) for v in axes.values())
    groups = [(max(factors[:-1], key=lambda f: f[1])[0], n_scenes), ("scenes.realisations", realisations)]
    d = space.dim if space is not None else len(spec.grid)
    if spec.kind == "sweep":
        grid = [(f"grid.{k}", len(v)) for k, v in spec.grid.items()]
        variants = max(1, len(spec.model.variants))
        factors += grid + [("model.variants", variants)]
        points = math.prod(n for _, n in grid) * variants
        groups += [(max(grid, key=lambda f: f[1])[0], math.prod(n for _, n in grid)) if grid else ("grid", 1),
                   ("model.variants", variants)]
    elif space is None:
        points = 0
    else:
        methods = _method_points(spec.methods, space)
        factors += methods
        points = sum(n for _, n in methods)
        groups.append((max(methods, key=lambda f: f[1])[0] if methods else "methods", points))
        if spec.kind == "fault" and spec.fault is not None and space.dim > 1:
            from ddgsa.gsa.space import ParameterSpace

            others = ParameterSpace.from_parameters([p for p in space.parameters if p.name != spec.fault.parameter])
            per_level = spec.fault.samples + sum(n for _, n in _method_points(spec.methods, others))
            levels = 1 + len(spec.fault.levels)
            factors += [("fault.faulty", levels), ("fault.samples", spec.fault.samples)]
            groups += [("fault.faulty", levels), ("fault.samples", per_level)]
            points += levels * per_level
    evaluations = n_scenes * realisations * points
    if spec.model.fidelity == "auto":
        from ddgsa.models import MODELS

        evaluations += n_scenes * (spec.model.auto.pilot + 1) * len(MODELS.lookup(spec.model.name).pilot_pool())
    a, b, c = BYTES_PER_EVALUATION
    sa, sb, sc = STORE_BYTES_PER_EVALUATION
    return RunSize(evaluations, n_scenes, realisations,
                   evaluations * (a + b * d + c * n_outputs) + n_scenes * realisations * BYTES_PER_SCENE,
                   evaluations * (sa + sb * d + sc * n_outputs), tuple(factors), tuple(groups))


def machine_memory() -> int:
    """This machine's physical memory [B]."""
    import psutil

    return int(psutil.virtual_memory().total)


def check_run_size(where: str, spec: Any, space: Any, n_outputs: int,
                   memory: Callable[[], int] = machine_memory) -> RunSize:
    """Refuse a study whose run needs more memory than ``memory()`` (the machine's), naming the
    field of its largest factor and the estimate; returns the estimate.

    Raises
    ------
    StudyError
        Naming ``where``, the field and the estimate.
    """
    size = run_size(spec, space, n_outputs)
    total = memory()
    if size.memory_bytes > total:
        raise StudyError(f"{where}: field '{size.largest}': the study asks for {size.describe()}; this machine "
                         f"has {gib(total)} of memory: reduce {size.largest}")
    return size


MAX_NAME_CHARS = 64
"""A study's name is one safe path component (it names the output folder ``runs/<name>``)."""


def check_names(where: str, spec: Any) -> None:
    """Refuse a study name that is not a single safe path component (``.``, ``..``, a dot name)
    and lists that name one thing twice (outputs, combined outputs, methods, scene or grid values).

    Raises
    ------
    StudyError
        Naming ``where``, the field and the repeated value.
    """
    if set(spec.name) == {"."}:
        raise StudyError(f"{where}: field 'name': {spec.name!r} is not a folder name (it names the output folder "
                         "runs/<name>); use letters, digits, '_', '-' and '.'")
    _once(where, "outputs", spec.outputs)
    if spec.fault is not None and spec.fault.combine:
        _once(where, "fault.combine", spec.fault.combine)
    if spec.fault is not None and isinstance(spec.fault.faulty, list):
        _once(where, "fault.faulty", spec.fault.levels)
    _once(where, "methods", [repr(sorted(m.model_dump().items())) for m in spec.methods], "an identical entry")
    for key, values in scene_axes(spec.scenes).items():
        _once(where, f"scenes.{key}", values)
    for key, values in spec.grid.items():
        _once(where, f"grid.{key}", values)
    _once(where, "model.variants", [repr(sorted(v.items())) for v in spec.model.variants], "an identical entry")


def _once(where: str, field: str, values: list[Any], what: str | None = None) -> None:
    seen: dict[Any, int] = {}
    for i, v in enumerate(values):
        key = repr(v) if not isinstance(v, (str, int, float)) else v
        if key in seen:
            raise StudyError(f"{where}: field '{field}[{i}]': {what or clip(v)} is listed twice (also at "
                             f"[{seen[key]}]); list each once")
        seen[key] = i
