"""The documentation: the site builds strictly, its references are made from the code, every
public name has a docstring and a place in the API reference. (Its Python blocks run and
its commands parse: tests/test_docs_examples.py.)"""

import importlib
import importlib.util
import inspect
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PUBLIC = ("aquagait", "aquagait.sim", "aquagait.creatures", "aquagait.optimize",
          "aquagait.app", "aquagait.metrics", "aquagait.io", "aquagait.io.export",
          "aquagait.envs")  # fmt: skip
"""The modules whose public names the API reference documents (docs/api/*.md)."""


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The site, built once with ``mkdocs build --strict`` into a temporary directory."""
    for module in ("mkdocs", "material", "mkdocstrings"):
        pytest.importorskip(module, reason="the docs extra: pip install -e '.[docs]'")
    out = tmp_path_factory.mktemp("site")
    done = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(out)],
        cwd=ROOT, capture_output=True, text=True, timeout=600,
        env={**os.environ, "NO_MKDOCS_2_WARNING": "1"},
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-4000:]
    return out


def test_the_site_builds_strictly(site):
    for page in ("index", "getting-started", "cli", "gallery", "api/sim", "api/app"):
        assert (site / f"{page}.html").is_file()
    cli = (site / "cli.html").read_text()
    assert "aquagait swim" in cli and "--wake" in cli  # made from the parser
    api = (site / "api" / "sim.html").read_text()
    assert 'id="aquagait.sim.rollout.rollout"' in api  # the function, not its module
    assert 'id="aquagait.sim.Trajectory"' in api  # made from the docstrings


def module_names(module) -> list[str]:
    """A module's public names: its ``__all__``, or else the classes and functions it
    defines whose names do not start with an underscore."""
    if hasattr(module, "__all__"):
        return list(module.__all__)
    return [
        name
        for name, obj in vars(module).items()
        if not name.startswith("_")
        and (inspect.isclass(obj) or inspect.isfunction(obj))
        and obj.__module__ == module.__name__
    ]


def test_every_public_name_is_in_the_api_reference(site):
    """Each public name of ``PUBLIC`` has a heading on an API page (``docs/api/*.md``): its
    anchor is the name as imported (``aquagait.sim.make_scene``), or, for a class or a
    function, the path of its definition (``aquagait.sim.rollout.rollout``, where the
    module of the same name hides the function), or, for a module, the module's own
    name. A name that starts with an underscore (``__version__``), which the reference's
    filter leaves out, must be named in the text of a page."""
    pages = sorted((site / "api").glob("*.html"))
    text = "\n".join(page.read_text() for page in pages)
    anchors = set(re.findall(r'\bid="([^"]+)"', text))
    missing = []
    for module_name in PUBLIC:
        if module_name == "aquagait.envs" and importlib.util.find_spec("gymnasium") is None:
            continue  # the gym extra is not installed
        module = importlib.import_module(module_name)
        for name in module_names(module):
            obj = getattr(module, name)
            if name.startswith("_"):
                found = f"{module_name}.{name}" in text
            else:
                paths = {f"{module_name}.{name}"}
                if inspect.isclass(obj) or inspect.isfunction(obj):
                    paths.add(f"{obj.__module__}.{obj.__qualname__}")
                elif inspect.ismodule(obj):
                    paths.add(obj.__name__)
                found = bool(paths & anchors)
            if not found:
                missing.append(f"{module_name}.{name}")
    assert not missing, f"public names missing from docs/api/*.md: {', '.join(missing)}"


def test_the_cli_reference_has_every_command_and_option():
    from docs_hooks import cli_reference

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
    from docs_hooks import gallery

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
        for name in module_names(mod):
            obj = getattr(mod, name)
            if inspect.isclass(obj) or inspect.isfunction(obj):
                yield pytest.param(obj, id=f"{module}.{name}")


@pytest.mark.parametrize("obj", list(public_names()))
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
