"""The layer rules of docs/development.md, "Layers": a module imports only from layers below it."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "aquagait"

# Lowest first. Units in the same layer may not import each other.
LAYERS = [
    {"grid"},
    {"fluid", "body"},
    {"coupling", "drag"},
    {"sim"},
    {"control"},
    {"objectives", "metrics"},
    {"optimize"},
    {"path"},
    {"creatures"},
    {"io"},
    {"viz"},
    {"app", "envs"},  # envs: the Gymnasium environment, a user's loop beside the jobs
    {"bench"},
    {"cli"},
]
LAYER_OF = {unit: level for level, units in enumerate(LAYERS) for unit in units}

# Third-party engines, each behind one adapter (docs/development.md).
ADAPTERS = {
    "mujoco": {"body/dynamics.py"},
    "cma": {"optimize/"},
    "distributed": {"optimize/"},
    "dask": {"optimize/"},
    "gymnasium": {"envs/"},
    "pettingzoo": {"envs/"},
}
PHYSICS = {"grid", "fluid", "body", "coupling", "sim"}
ONLY_FROM = {"viz": {"app", "envs", "bench"}}  # pictures: the jobs, the env's render, benchmarks


def _modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE).as_posix()
        if rel in ("__init__.py", "__main__.py"):
            continue  # the package root re-exports the public API
        yield rel, path


def _unit(rel: str) -> str:
    return rel.split("/")[0].removesuffix(".py")


def _imports(path: Path):
    tree = ast.parse(path.read_text(), filename=str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            yield node.module
            for alias in node.names:  # from aquagait import fluid
                if node.module == "aquagait":
                    yield f"aquagait.{alias.name}"


def _violations(rel: str, path: Path) -> list[str]:
    unit = _unit(rel)
    if unit not in LAYER_OF:
        return [f"{rel}: unit {unit!r} has no layer in docs/development.md; add it to LAYERS"]
    problems = []
    for name in _imports(path):
        top, _, rest = name.partition(".")
        if top == "aquagait" and rest:
            target = rest.split(".")[0]
            if target == unit or target not in LAYER_OF:
                continue
            if LAYER_OF[target] >= LAYER_OF[unit]:
                problems.append(f"{rel} imports aquagait.{target}, a layer at or above its own")
            if unit == "optimize" and target in PHYSICS:
                problems.append(f"{rel} imports aquagait.{target}: optimize knows no physics")
            if target in ONLY_FROM and unit not in ONLY_FROM[target]:
                problems.append(f"{rel} imports aquagait.{target}; only {ONLY_FROM[target]} may")
        elif top in ADAPTERS and not any(rel.startswith(a) for a in ADAPTERS[top]):
            problems.append(f"{rel} imports {top}; only {sorted(ADAPTERS[top])} may")
    return problems


@pytest.mark.parametrize("rel,path", list(_modules()), ids=lambda x: str(x))
def test_module_respects_layers(rel, path):
    assert _violations(rel, path) == []


def test_checker_catches_an_upward_import(tmp_path):
    bad = tmp_path / "advection.py"
    bad.write_text("from aquagait.coupling import solve\nimport mujoco\n")
    problems = _violations("fluid/advection.py", bad)
    assert len(problems) == 2


def test_checker_catches_a_sibling_import(tmp_path):
    bad = tmp_path / "voxelize.py"
    bad.write_text("import aquagait.fluid.projection as projection\n")
    assert _violations("body/voxelize.py", bad)


def test_checker_catches_pictures_drawn_outside_the_jobs(tmp_path):
    bad = tmp_path / "render.py"
    bad.write_text("from aquagait.viz import render_swim\n")
    assert _violations("cli/render.py", bad)


# --- circles between modules ---------------------------------------------------------


def _module_name(path: Path, root: Path) -> str:
    parts = path.relative_to(root.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _is_type_checking(node: ast.If) -> bool:
    test = node.test
    return getattr(test, "id", None) == "TYPE_CHECKING" or getattr(test, "attr", None) == (
        "TYPE_CHECKING"
    )


def _module_imports(path: Path, modules: set[str], annotations: bool) -> set[str]:
    """The package's modules that ``path`` imports, at the top or inside functions; with
    ``annotations``, also those imported under ``if TYPE_CHECKING:`` (types only)."""
    found = set()

    def visit(node):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and _is_type_checking(child) and not annotations:
                for branch in child.orelse:
                    visit(ast.Module(body=[branch], type_ignores=[]))
                continue
            if isinstance(child, ast.Import):
                found.update(alias.name for alias in child.names)
            elif isinstance(child, ast.ImportFrom) and child.module and child.level == 0:
                found.add(child.module)
                found.update(f"{child.module}.{alias.name}" for alias in child.names)
            visit(child)

    visit(ast.parse(path.read_text(), filename=str(path)))
    return found & modules


def _import_graph(root: Path, annotations: bool = False) -> dict[str, set[str]]:
    """Module -> the modules it imports, leaving out imports of a package's ``__init__``
    (re-exporting its modules is what that file is for)."""
    paths = {_module_name(p, root): p for p in root.rglob("*.py")}
    packages = {name for name, p in paths.items() if p.name == "__init__.py"}
    modules = set(paths) - packages
    return {name: _module_imports(p, modules, annotations) - {name} for name, p in paths.items()}


def _circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The import circles: each a path that leads back to its first module."""
    circles, done = [], set()

    def walk(name, path):
        if name in path:
            circles.append(path[path.index(name) :] + [name])
            return
        if name in done:
            return
        for target in sorted(graph.get(name, ())):
            walk(target, path + [name])
        done.add(name)

    for name in sorted(graph):
        walk(name, [])
    return circles


def _reached(graph: dict[str, set[str]], start: str) -> set[str]:
    seen, todo = set(), [start]
    while todo:
        for target in graph[todo.pop()] - seen:
            seen.add(target)
            todo.append(target)
    return seen


def test_no_module_imports_one_that_imports_it_back():
    # run-time imports, lazy ones in functions included; ``if TYPE_CHECKING:`` names types
    # for annotations and runs nothing, so a Scene named in a fluid's signature is no circle
    assert _circles(_import_graph(PACKAGE)) == []


def test_the_scene_does_not_reach_the_fluids_that_step_it():
    # sim.scene holds a fluid model by its protocol (sim.fluid_model); the models, the
    # servo and the grid that follows the swimmer build on the scene, never under it, not
    # even for their types
    graph = _import_graph(PACKAGE, annotations=True)
    above = {"aquagait.sim.fluids", "aquagait.sim.follow", "aquagait.sim.servo"}
    assert _reached(graph, "aquagait.sim.scene") & above == set()
    assert "aquagait.sim.scene" in graph["aquagait.sim.fluids"]


def test_circle_finder_catches_a_lazy_circle(tmp_path):
    root = tmp_path / "aquagait"
    (root / "sim").mkdir(parents=True)
    for name in ("__init__.py", "sim/__init__.py"):
        (root / name).write_text("from aquagait.sim.a import x\n")
    (root / "sim" / "a.py").write_text("from aquagait.sim.b import y\nx = 1\n")
    (root / "sim" / "b.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from aquagait.sim import a\n"
        "def y():\n    from aquagait.sim.a import x\n"
    )
    assert _circles(_import_graph(root)) == [["aquagait.sim.a", "aquagait.sim.b", "aquagait.sim.a"]]
    (root / "sim" / "b.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from aquagait.sim import a\n"
    )
    assert _circles(_import_graph(root)) == []
    assert _circles(_import_graph(root, annotations=True))
