"""The documentation: the site builds strictly, its references are made from the code, and
every public name has a docstring. (Its Python blocks run and its commands parse:
tests/test_docs_examples.py.)"""

import importlib
import inspect
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PUBLIC = ("aquagait", "aquagait.sim", "aquagait.creatures", "aquagait.optimize",
          "aquagait.io.export", "aquagait.envs")  # fmt: skip
"""The modules whose public names the API reference documents."""


def test_the_site_builds_strictly(tmp_path):
    for module in ("mkdocs", "material", "mkdocstrings"):
        pytest.importorskip(module, reason="the docs extra: pip install -e '.[docs]'")
    done = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path)],
        cwd=ROOT, capture_output=True, text=True, timeout=600,
        env={**os.environ, "NO_MKDOCS_2_WARNING": "1"},
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-4000:]
    for page in ("index", "getting-started", "cli", "gallery", "api/sim"):
        assert (tmp_path / f"{page}.html").is_file()
    cli = (tmp_path / "cli.html").read_text()
    assert "aquagait swim" in cli and "--wake" in cli  # made from the parser
    api = (tmp_path / "api" / "sim.html").read_text()
    assert "rollout" in api and "Trajectory" in api  # made from the docstrings


def test_the_cli_reference_has_every_command_and_option():
    sys.path.insert(0, str(ROOT / "tools"))
    try:
        from docs_hooks import cli_reference
    finally:
        sys.path.pop(0)
    from aquagait.cli import build_parser

    parser = build_parser()
    text = cli_reference(parser)
    commands = next(a for a in parser._actions if a.dest == "command").choices
    for name, command in commands.items():
        assert f"## aquagait {name}\n" in text
        for action in command._actions:
            for option in set(action.option_strings) - {"-h", "--help"}:
                assert f"`{option}`" in text, (name, option)


def test_the_gallery_has_each_creature_with_its_picture_and_rows():
    sys.path.insert(0, str(ROOT / "tools"))
    try:
        from docs_hooks import gallery
    finally:
        sys.path.pop(0)
    import aquagait as ag

    text = gallery((ROOT / "docs" / "library.md").read_text())
    for name in ag.creatures.names():
        section = text.split(f"## {name}\n")[1].split("\n## ")[0]
        assert f"(gallery/{name}.png)" in section
        assert (ROOT / "docs" / "gallery" / f"{name}.png").is_file()
        assert section.count(f"`{name}`") == 2  # its row of each table


def public_names():
    for module in PUBLIC:
        mod = importlib.import_module(module)
        for name in mod.__all__:
            obj = getattr(mod, name)
            if inspect.isclass(obj) or inspect.isfunction(obj):
                yield pytest.param(obj, id=f"{module}.{name}")


@pytest.mark.parametrize("obj", public_names())
def test_every_public_name_and_method_has_a_docstring(obj):
    assert inspect.getdoc(obj), f"{obj.__qualname__} has no docstring"
    if inspect.isclass(obj):
        for name, member in vars(obj).items():
            if not name.startswith("_") and inspect.isfunction(member):
                assert member.__doc__, f"{obj.__qualname__}.{name} has no docstring"


OUTSIDE = re.compile(r"DESIGN\.md|STYLE\.md|DEVELOPERS\.md|\.\./shared")
"""Notes kept beside the repository, not in it: a user who follows a citation of one finds
nothing. The docs pages hold what they said (docs/development.md, the method pages)."""


def test_nothing_cites_a_file_outside_the_repository():
    skip = {"node_modules", "__pycache__"}
    paths = [ROOT / "README.md"]
    for folder in ("src", "docs", "examples", "tools"):
        paths += sorted(p for p in (ROOT / folder).rglob("*") if p.is_file())
    found = []
    for path in paths:
        parts = path.relative_to(ROOT).parts
        if skip.intersection(parts) or any(part.endswith(".egg-info") for part in parts):
            continue
        try:
            text = path.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            continue  # not a text file
        for number, line in enumerate(text.splitlines(), 1):
            if OUTSIDE.search(line):
                found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()[:100]}")
    listed = "\n".join(found)
    assert not found, f"cites a file outside the repository (cite a docs page):\n{listed}"
