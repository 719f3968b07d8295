"""The creature library: a registry of named creatures, and creatures from files.

A library creature is an MJCF file beside this module, its side-car
``<name>.aquagait.json`` (``aquagait.creatures.metadata``) and a module whose
docstring tables it; every shipped side-car is registered under its stem.
``load(path)`` makes a creature of any MJCF file the same way, and
``resolve(name_or_path)`` takes either.

A creature from a file has its thin parts thickened for the fluid to at least
``THICKEN_CELLS`` of its default grid's cells (``aquagait.body.reshape``;
masses unchanged, a note names each part). ``load(path, thicken=False)``
keeps them as written; its key for ``resolve`` (and for worker processes)
is the path with ``AS_WRITTEN`` appended (``as_written``).

Why a registry: docs/development.md, "How the code reads".
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
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

THICKEN_CELLS = 1.0
"""Thinnest part the fluid gets, in default-grid cells: every library creature was built at
least this thick by hand (the sub-cell faces see it in part; ``aquagait check``)."""

AS_WRITTEN = "#as-written"
"""Appended to an MJCF path, the creature with its thin parts as written (``--no-thicken``)."""

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
    """The library creature called ``name`` (built on first use, then cached); ``resolve``
    also takes the path of an MJCF file."""
    if name not in _FACTORIES:
        hint = ""
        if str(name).lower().endswith(".xml") or Path(str(name)).exists():
            hint = "; for an MJCF file, ag.creatures.resolve(path) or load(path)"
        raise UnknownCreatureError(
            f"unknown creature {name!r}; known creatures: {', '.join(names())}{hint}"
        )
    if name not in _BUILT:
        _BUILT[name] = _FACTORIES[name]()
    return _BUILT[name]


def format_table() -> str:
    """The library as a text table: name, dim, DOFs, optimized parameters, grid, cell size,
    the shipped gaits (``swim NAME --gait G``) and the learned manoeuvres (``--maneuver M``)."""
    header = ("name", "dim", "DOFs", "optimized parameters", "default grid", "cell size",
              "gaits", "manoeuvres")  # fmt: skip
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
                ",".join(g for g in c.gaits if g not in c.maneuvers or g == "straight"),
                ",".join(c.maneuvers[1:]) or "-",  # the first is straight, always learned
            )
        )
    widths = [max(len(r[i]) for r in rows) for i in range(len(header))]
    lines = [
        "  ".join(cell.ljust(w) for cell, w in zip(row, widths, strict=True)).rstrip()
        for row in rows
    ]
    return "\n".join(lines)


_LOADED: dict[tuple, Creature] = {}


def load(path, thicken: bool = True) -> Creature:
    """The creature in an MJCF file, with its side-car ``<stem>.aquagait.json`` if there is one.

    What the side-car leaves out (or all of it, without one) comes from the
    model (``aquagait.creatures.defaults``); ``Creature.notes`` lists it. The
    creature is named after the file's stem. Loaded once per file, choice of
    ``thicken`` and modification time (of the MJCF and its side-car).

    Args:
        path: the MJCF file (a side-car's path finds its MJCF beside it).
        thicken: widen parts thinner than ``THICKEN_CELLS`` default cells for the
            fluid (module doc); False keeps them as written.

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
    times = (mjcf.stat().st_mtime_ns, side.stat().st_mtime_ns if side.is_file() else None)
    key = (str(mjcf), thicken, *times)
    if key not in _LOADED:
        meta = read_metadata(side) if side.is_file() else Metadata()
        read = dict(forward=meta.forward, planar_fluid=meta.planar_fluid or "2d")
        creature = build_creature(load_model(mjcf, **read), meta, name=mjcf.stem)
        if thicken:
            model = load_model(mjcf, thicken_to=THICKEN_CELLS * creature.cell_size, **read)
            if model.notes != creature.model.notes:  # something was thickened
                creature = build_creature(model, meta, name=mjcf.stem)
        else:
            creature = replace(creature, as_written=True)
        for old in [k for k in _LOADED if k[:2] == key[:2]]:  # an edited file's older versions
            del _LOADED[old]
        _LOADED[key] = creature
    return _LOADED[key]


def as_written(name_or_path) -> str:
    """The key ``resolve`` takes for this creature with its thin parts as written.

    A library name is returned as it is: library creatures need no thickening.
    """
    text = str(name_or_path)
    return text if text in _FACTORIES or text.endswith(AS_WRITTEN) else text + AS_WRITTEN


def resolve(name_or_path) -> Creature:
    """A library creature by name, else the creature in that MJCF file (``load``).

    A path ending in ``AS_WRITTEN`` loads the file with ``thicken=False``.

    Raises:
        UnknownCreatureError: neither a library name nor a file; the message
            lists the known names and says that a path works too.
        CreatureError, ModelError: as ``load``.
    """
    text = str(name_or_path)
    if not isinstance(name_or_path, Path) and text in _FACTORIES:
        return get(text)
    thicken = not text.endswith(AS_WRITTEN)
    text = text.removesuffix(AS_WRITTEN)
    path = Path(text).expanduser()
    if path.exists() or path.suffix.lower() == ".xml" or "/" in text or "\\" in text:
        return load(path, thicken)
    raise UnknownCreatureError(
        f"unknown creature {text!r}; known creatures: {', '.join(names())}; "
        "or give the path of an MJCF file (e.g. my_creature.xml)"
    )


def register_library() -> None:
    """Register every creature shipped with the package: each ``*.aquagait.json`` here."""
    for side in sorted(HERE.glob(f"*{SUFFIX}")):
        name = side.name[: -len(SUFFIX)]
        register(name, lambda mjcf=HERE / f"{name}.xml": load(mjcf), replace=True)
