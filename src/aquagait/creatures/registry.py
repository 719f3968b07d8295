"""The creature library: a registry of named creatures (STYLE.md §14), and creatures from files.

A library creature is an MJCF file beside this module, its side-car
``<name>.aquagait.json`` (``aquagait.creatures.metadata``) and a module whose
docstring tables it; every shipped side-car is registered under its stem.
``load(path)`` makes a creature of any MJCF file the same way, and
``resolve(name_or_path)`` takes either.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from aquagait.body.model import load_model
from aquagait.creatures.creature import Creature, CreatureError, UnknownCreatureError
from aquagait.creatures.metadata import (
    SUFFIX,
    Metadata,
    build_creature,
    read_metadata,
    sidecar_path,
)

HERE = Path(__file__).resolve().parent

_FACTORIES: dict[str, Callable[[], Creature]] = {}
_BUILT: dict[str, Creature] = {}


def register(name: str, creature: Creature | Callable[[], Creature], replace: bool = False):
    """Add a creature (or a function that builds one on first ``get``) to the library.

    Raises:
        ValueError: the name is taken and ``replace`` is False.
    """
    if name in _FACTORIES and not replace:
        raise ValueError(f"creature {name!r} is already registered; pass replace=True")
    _FACTORIES[name] = creature if callable(creature) else (lambda: creature)
    _BUILT.pop(name, None)


def names() -> list[str]:
    """Registered creature names, sorted."""
    return sorted(_FACTORIES)


def get(name: str) -> Creature:
    """The creature called ``name`` (built on first use, then cached)."""
    if name not in _FACTORIES:
        raise UnknownCreatureError(
            f"unknown creature {name!r}; known creatures: {', '.join(names())}"
        )
    if name not in _BUILT:
        _BUILT[name] = _FACTORIES[name]()
    return _BUILT[name]


def format_table() -> str:
    """The library as a text table: name, dim, DOFs, optimized parameters, grid, cell size."""
    header = ("name", "dim", "DOFs", "optimized parameters", "default grid", "cell size")
    rows = [header]
    for name in names():
        c = get(name)
        rows.append(
            (
                name,
                f"{c.dim}D",
                str(len(c.model.actuated_dofs)),
                str(c.gait.size),
                "x".join(str(n) for n in c.resolution),
                f"{c.cell_size * 1000:g} mm",
            )
        )
    widths = [max(len(r[i]) for r in rows) for i in range(len(header))]
    lines = [
        "  ".join(cell.ljust(w) for cell, w in zip(row, widths, strict=True)).rstrip()
        for row in rows
    ]
    return "\n".join(lines)


_LOADED: dict[tuple, Creature] = {}


def load(path) -> Creature:
    """The creature in an MJCF file, with its side-car ``<stem>.aquagait.json`` if there is one.

    What the side-car leaves out (or all of it, without one) comes from the
    model (``aquagait.creatures.defaults``); ``Creature.notes`` lists it. The
    creature is named after the file's stem. Loaded once per file and
    modification time (of the MJCF and its side-car).

    Args:
        path: the MJCF file (a side-car's path finds its MJCF beside it).

    Raises:
        CreatureError: no such file, or a side-car that is malformed or does
            not fit the model (every problem listed).
        ModelError: the MJCF is not a creature aquagait can simulate
            (``aquagait.body.model``; every problem listed).
    """
    mjcf = Path(path).expanduser().resolve()
    if mjcf.name.endswith(SUFFIX):
        mjcf = mjcf.with_name(mjcf.name[: -len(SUFFIX)] + ".xml")
    if not mjcf.is_file():
        what = "is a directory" if mjcf.is_dir() else "does not exist"
        raise CreatureError(f"{path} {what}: give the path of an MJCF file (.xml)")
    side = sidecar_path(mjcf)
    key = (str(mjcf), mjcf.stat().st_mtime_ns, side.stat().st_mtime_ns if side.is_file() else None)
    if key not in _LOADED:
        meta = read_metadata(side) if side.is_file() else Metadata()
        creature = build_creature(load_model(mjcf), meta, name=mjcf.stem)
        for old in [k for k in _LOADED if k[0] == key[0]]:  # an edited file's older versions
            del _LOADED[old]
        _LOADED[key] = creature
    return _LOADED[key]


def resolve(name_or_path) -> Creature:
    """A library creature by name, else the creature in that MJCF file (``load``).

    Raises:
        UnknownCreatureError: neither a library name nor a file; the message
            lists the known names and says that a path works too.
        CreatureError, ModelError: as ``load``.
    """
    text = str(name_or_path)
    if not isinstance(name_or_path, Path) and text in _FACTORIES:
        return get(text)
    path = Path(text).expanduser()
    if path.exists() or path.suffix.lower() == ".xml" or "/" in text or "\\" in text:
        return load(path)
    raise UnknownCreatureError(
        f"unknown creature {text!r}; known creatures: {', '.join(names())}; "
        "or give the path of an MJCF file (e.g. my_creature.xml)"
    )


def register_library() -> None:
    """Register every creature shipped with the package: each ``*.aquagait.json`` here."""
    for side in sorted(HERE.glob(f"*{SUFFIX}")):
        name = side.name[: -len(SUFFIX)]
        register(name, lambda mjcf=HERE / f"{name}.xml": load(mjcf), replace=True)
