"""DESIGN's boundaries, checked on the imports: each layer can be used and tested alone."""

from __future__ import annotations

import ast
from pathlib import Path

import pandas as pd

import ddgsa.mbs.sampling as sampling
from ddgsa.runner import EvaluationStore, ModelId, Task, run_tasks, task_key

SRC = Path(__file__).parents[1] / "src" / "ddgsa"


def _imports(path: Path) -> set[str]:
    """Every module a file imports (``from a.b import c`` gives ``a.b`` and ``a.b.c``)."""
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module:
            out |= {node.module} | {f"{node.module}.{a.name}" for a in node.names}
    return out


def _uses(path: Path, package: str) -> bool:
    return any(m == package or m.startswith(package + ".") for m in _imports(path))


def test_runner_imports_neither_models_nor_scenes_nor_gsa() -> None:
    for package in ("ddgsa.models", "ddgsa.loads", "ddgsa.gsa", "ddgsa.study.spec"):
        assert not _uses(SRC / "runner.py", package), package


def test_models_do_not_import_the_gsa_layer_and_the_kernel_imports_no_model() -> None:
    """Every file of every subpackage (``rglob``: ``models/hss_rig``, ``models/indirect_drive`` too)."""
    assert len(list((SRC / "models").rglob("*.py"))) > len(list((SRC / "models").glob("*.py")))
    for path in (SRC / "models").rglob("*.py"):
        assert not _uses(path, "ddgsa.gsa"), path.name
    for path in (SRC / "mbs").rglob("*.py"):
        assert not _uses(path, "ddgsa.models") and not _uses(path, "ddgsa.loads"), path.name
    for path in (SRC / "gsa").rglob("*.py"):
        assert not _uses(path, "ddgsa.models") and not _uses(path, "ddgsa.loads"), path.name


def test_no_core_module_imports_the_benchmarks() -> None:
    """``ddgsa.bench`` sits on top: only the CLI reaches it (issue 24)."""
    for path in SRC.rglob("*.py"):
        if path.parent.name != "bench" and path.name != "cli.py":
            assert not _uses(path, "ddgsa.bench"), path


def _module_graph() -> dict[str, set[str]]:
    """Module -> the modules of ``src/ddgsa`` it imports, at any depth of the file (a function's
    ``import`` too: a deferred import hides a circle, it does not remove it). ``from a import b``
    counts as ``a.b`` where that is a module, else as ``a``."""
    modules = {}
    for path in SRC.rglob("*.py"):
        parts = ("ddgsa", *path.relative_to(SRC).with_suffix("").parts)
        modules[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    graph = {}
    for name, path in modules.items():
        out = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                out |= {a.name for a in node.names}
            elif isinstance(node, ast.ImportFrom) and node.module:
                subs = {f"{node.module}.{a.name}" for a in node.names} & modules.keys()
                out |= subs or {node.module}
        graph[name] = (out & modules.keys()) - {name}
    return graph


def _circle(graph: dict[str, set[str]]) -> list[str]:
    """One import circle of ``graph`` (depth-first search for a back edge), empty when there is none."""
    state: dict[str, int] = {}                          # 1: on the current path, 2: done
    path: list[str] = []

    def visit(node: str) -> list[str]:
        state[node] = 1
        path.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                return path[path.index(nxt):] + [nxt]
            if nxt not in state and (found := visit(nxt)):
                return found
        state[node] = 2
        path.pop()
        return []

    for node in sorted(graph):
        if node not in state and (found := visit(node)):
            return found
    return []


def test_the_circle_finder_finds_a_circle() -> None:
    assert _circle({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}) == ["a", "b", "c", "a"]
    assert _circle({"a": {"b"}, "b": set()}) == []


def test_no_import_circles_in_src() -> None:
    """No module of ``src/ddgsa`` reaches itself through imports (issue 24)."""
    graph = _module_graph()
    assert {"ddgsa.mbs.assembly", "ddgsa.models.hss_rig.model", "ddgsa.models.indirect_drive.linear"} <= graph.keys()
    assert _circle(graph) == []


ROOMS: dict[str, set[str]] = {
    "errors": set(), "_version": set(), "closed_forms": set(),
    "registry": {"errors"}, "units": {"errors"}, "runner": {"errors"},
    "mbs": {"errors"},
    "loads": {"errors", "_version"},
    "detection": {"errors"},
    "gsa": {"errors", "registry", "closed_forms", "runner"},
    "models": {"errors", "registry", "units", "closed_forms", "mbs", "loads"},
    "__init__": {"errors", "_version", "gsa", "loads", "models"},
    "study": {"errors", "units", "registry", "mbs", "loads", "models", "gsa"},
    "execute": {"__init__", "errors", "runner", "study", "gsa", "detection", "models", "loads", "mbs"},
    "report": {"errors", "execute", "study", "gsa", "detection", "models", "loads", "mbs"},
    "bench": {"__init__", "errors", "runner", "execute", "report", "study", "gsa", "models", "loads", "mbs"},
    "cli": {"__init__", "errors", "runner", "bench", "report", "execute", "study", "gsa", "models", "loads", "mbs"},
}
"""Each room of ``src/ddgsa`` (a package or a top-level module) and the rooms it may import (issue 50;
docs/architecture.md draws them): the kernel, the loads, detection and the runner know no model, study or
statistics of the workbench; the models know no GSA; the study file's validation never runs anything;
execution never writes a report; only the CLI reaches the report and the benchmarks."""


def _rooms() -> dict[str, set[str]]:
    """Room -> the rooms its files import, at any depth of a file (``ddgsa`` alone is the room ``__init__``)."""
    out: dict[str, set[str]] = {}
    for path in SRC.rglob("*.py"):
        room = path.relative_to(SRC).with_suffix("").parts[0]
        uses = out.setdefault(room, set())
        for module in _imports(path):
            parts = module.split(".")
            if parts[0] == "ddgsa":
                uses.add(parts[1] if len(parts) > 1 and parts[1] in ROOMS else "__init__")
        uses.discard(room)
    return out


def test_every_room_imports_only_what_it_may() -> None:
    """The package layout's rules, on the imports: a new import across rooms either follows them or
    changes :data:`ROOMS` (and the architecture page) on purpose."""
    rooms = _rooms()
    assert rooms.keys() == ROOMS.keys(), "a room was added or removed: place it in ROOMS and docs/architecture.md"
    bad = {room: sorted(uses - ROOMS[room]) for room, uses in rooms.items() if uses - ROOMS[room]}
    assert not bad


def test_the_top_of_the_package_is_small_and_every_package_says_what_it_holds() -> None:
    """At most 8 modules beside the packages (issue 50), and each package's ``__init__`` opens with a
    docstring (what it holds; the larger ones also what they may import)."""
    top = sorted(p.name for p in SRC.glob("*.py"))
    assert len(top) <= 8, top
    for init in SRC.glob("*/__init__.py"):
        assert ast.get_docstring(ast.parse(init.read_text())), init.parent.name


def test_the_kernels_sampling_table_carries_only_the_callers_words() -> None:
    assert not hasattr(sampling, "controller_row")
    ok = sampling.sampling_row("step", 0.001, 10.0, "m1", "caller's text")
    coarse = sampling.sampling_row("step", 0.02, 10.0, "m1", "caller's text")
    assert (ok["verdict"], ok["consequence"]) == ("ok", "")
    assert (coarse["verdict"], coarse["samples_per_period"], coarse["consequence"]) == ("coarse", 5.0, "caller's text")


def double_it(model: ModelId) -> object:
    """A model factory that knows no ddgsa model: y = factor * x * scene['gain'] (factor from the options)."""
    factor = dict(model.options)["factor"]

    def evaluate(points: pd.DataFrame, scene: dict[str, float]) -> pd.DataFrame:
        return pd.DataFrame({"y": factor * points["x"] * scene["gain"]})

    return evaluate


def test_the_runner_evaluates_any_factory_with_plain_scene_dicts(tmp_path: Path) -> None:
    mid = ModelId("double", "exact", (("factor", 2.0),))
    scenes = [{"gain": 1.0}, {"gain": 10.0}]
    tasks = [Task(task_key(mid, s, {"x": x}, "test"), mid, s, {"x": x}) for s in scenes for x in (1.0, 2.0, 3.0)]
    for jobs in (1, 2):
        store = EvaluationStore(tmp_path / f"store{jobs}.sqlite")
        counts = run_tasks(tasks + tasks[:2], store, double_it, jobs=jobs, batch_size=2, quiet=True)
        assert counts == {"total": 6, "cached": 0, "evaluated": 6, "failed": 0}
        got = store.get([t.key for t in tasks])
        assert [got[t.key].outputs["y"] for t in tasks] == [2.0, 4.0, 6.0, 20.0, 40.0, 60.0]  # type: ignore[index]
        assert run_tasks(tasks, store, double_it, quiet=True)["cached"] == 6
        store.close()


def test_the_package_version_is_the_one_pyproject_declares() -> None:
    """``ddgsa.__version__`` (written into every provenance.json) and pyproject's version agree: a
    bump of one alone left the 0.5.0 studies saying 0.4.0."""
    import tomllib
    from pathlib import Path

    import ddgsa

    meta = tomllib.loads((Path(__file__).resolve().parents[1] / "pyproject.toml").read_text())
    assert ddgsa.__version__ == meta["project"]["version"]
