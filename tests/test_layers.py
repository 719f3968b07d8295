"""The layer rules of DESIGN.md §3: a module imports only from layers below it."""

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

# Third-party engines, each behind one adapter (STYLE.md §8).
ADAPTERS = {
    "mujoco": {"body/dynamics.py"},
    "cma": {"optimize/"},
    "distributed": {"optimize/"},
    "dask": {"optimize/"},
    "gymnasium": {"envs/"},
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
        return [f"{rel}: unit {unit!r} has no layer in DESIGN.md §3; add it to LAYERS"]
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
    bad = tmp_path / "cli.py"
    bad.write_text("from aquagait.viz import render_swim\n")
    assert _violations("cli.py", bad)
