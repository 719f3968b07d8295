"""NAME or PATH: every job takes a library creature's name or a path to an MJCF file;
a gait is a ``gait.json`` or the name of a gait the creature ships (``find_gait``);
a run directory says which creature (or group) swam (``run_creature``)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from aquagait import creatures
from aquagait.app.errors import SetupError
from aquagait.body.group import GroupError, Pose, compose
from aquagait.body.model import Model
from aquagait.creatures import Creature
from aquagait.io.gait import GaitFileError, read_gait
from aquagait.io.run import Run, read_run
from aquagait.objectives import MANEUVERS


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
    MJCF file (a worker on another machine needs the same file at that path),
    marked ``creatures.AS_WRITTEN`` when its thin parts were not thickened.
    """
    if creature.name in creatures.names() and creatures.get(creature.name) is creature:
        return creature.name
    path = str(Path(creature.source).resolve())
    return creatures.as_written(path) if creature.as_written else path


def find_gait(creature: Creature, gait: str | Path) -> tuple[np.ndarray, str, str, bool]:
    """A gait of ``creature``: the name of one its side-car ships (``hand-set``,
    ``optimized``, a manoeuvre's), or the path of a ``gait.json``.

    Returns:
        ``(params, source, maneuver, free_period)``: the parameter vector, where it
        came from (``shipped NAME`` or the path), the manoeuvre whose parameterization
        it is in (a manoeuvre's own name; ``straight`` for the other shipped gaits),
        and whether its period is among its parameters (``Creature.spec``).

    Raises:
        SetupError: no such file or shipped gait (the message lists the shipped
            ones), or a file that is not this creature's gait.
    """
    if isinstance(gait, str) and gait in creature.gaits and not Path(gait).exists():
        maneuver = gait if gait in MANEUVERS else "straight"
        shipped = creature.gaits[gait]
        return shipped.params, f"shipped {gait}", maneuver, shipped.free_period
    try:
        found = read_gait(gait, creature)
    except GaitFileError as err:
        shipped = ", ".join(creature.gaits)
        raise SetupError(f"{err}; {creature.name}'s shipped gaits: {shipped}") from None
    return found.params, str(gait), found.maneuver, found.free_period


def run_creature(run_dir) -> tuple[Run, Creature | Swimmers]:
    """A run directory read back, and the creature that swam in it (a group's run: its
    ``Swimmers``, the members composed again).

    Raises:
        SetupError: not a run directory, a damaged trajectory, a creature that
            cannot be found, or one whose MJCF no longer fits the trajectory.
    """
    try:
        run = read_run(run_dir)
    except FileNotFoundError as err:
        raise SetupError(f"{err}; give a directory written by aquagait swim") from None
    except Exception as err:  # a truncated .npz raises zipfile, EOF or value errors
        raise SetupError(
            f"{run_dir}: the run cannot be read ({type(err).__name__}: {err}); its "
            "trajectory.npz may be damaged or cut short: swim it again"
        ) from None
    if "school" in run.config:
        return run, _school(run)
    source = run.config.get("creature_source") or run.config.get("creature")
    if source is None:
        raise SetupError(f"{run_dir}/config.json does not say which creature swam")
    try:
        creature = find_creature(source)
    except SetupError as err:
        raise SetupError(f"the run's creature {source!r}: {err}") from None
    if creature.model.nq != run.trajectory.qpos.shape[1]:
        raise SetupError(
            f"the run's creature {source!r} has {creature.model.nq} position coordinates but "
            f"its trajectory {run.trajectory.qpos.shape[1]}: its MJCF changed since the run"
        )
    return run, creature


@dataclass(frozen=True)
class Swimmers:
    """The creatures of a group's run, as pictures and exports see one creature: ``name``,
    ``model`` (the composed group, ``aquagait.body.group``), ``view`` (the first member's),
    ``dim``."""

    name: str
    model: Model
    view: str
    dim: int


def _school(run: Run) -> Swimmers:
    """The group that swam in a run of ``aquagait swim --formation`` or a scene file."""
    members = run.config["school"]["members"]
    try:
        found = [find_creature(m["creature_source"]) for m in members]
        group = compose([c.model for c in found], [m["label"] for m in members],
                        [Pose(tuple(m["offset"]), m["heading"]) for m in members])  # fmt: skip
    except (SetupError, GroupError, KeyError, TypeError) as err:
        raise SetupError(f"{run.path}: the group that swam cannot be made again: {err}") from None
    if group.model.nq != run.trajectory.qpos.shape[1]:
        raise SetupError(
            f"{run.path}: the group has {group.model.nq} position coordinates but its trajectory "
            f"{run.trajectory.qpos.shape[1]}: a creature's MJCF changed since the run"
        )
    return Swimmers(group.model.source, group.model, found[0].view, group.model.dim)
