"""NAME or PATH: every job takes a library creature's name or a path to an MJCF file."""

from __future__ import annotations

from pathlib import Path

from aquagait import creatures
from aquagait.app.errors import SetupError
from aquagait.creatures import Creature


def find_creature(name_or_path: str | Path) -> Creature:
    """The library creature called ``name_or_path``, or the creature in that MJCF file.

    Raises:
        SetupError: an unknown name that is no file, or a file that is not a
            usable creature (the message lists every problem with its fix).
    """
    try:
        return creatures.resolve(name_or_path)
    except (ValueError, KeyError, OSError) as err:
        message = err.args[0] if isinstance(err, KeyError) and err.args else str(err)
        raise SetupError(message) from None


def creature_key(creature: Creature) -> str:
    """What a worker process passes to ``creatures.resolve`` to find this creature again.

    A library creature by its name; any other by the absolute path of its
    MJCF file (a worker on another machine needs the same file at that path).
    """
    if creature.name in creatures.names() and creatures.get(creature.name) is creature:
        return creature.name
    return str(Path(creature.source).resolve())
