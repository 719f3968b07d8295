"""``gait.json``: a creature's gait as a named, flat parameter vector (docs/method-search.md).

    {
      "creature": "eel2d",
      "maneuver": "straight",
      "names": ["amplitude[j1]", ..., "phase[j4]"],
      "params": [0.25, ..., 1.78]
    }

``names`` and ``params`` are the creature's ``GaitSpec.names`` and the vector
x that CMA-ES searches (amplitudes and phases in rad, periods in s). The
names make a file readable and catch a vector meant for another gait.
``maneuver`` (absent: ``straight``) says which parameterization the vector
is in: a turn or a pitch has its offsets free (``Creature.spec``); a gait
searched with its period free (``--free-period``) names ``period`` among them.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from aquagait.creatures import Creature
from aquagait.io.run import read_json, write_json
from aquagait.objectives import MANEUVERS, STRAIGHT


class GaitFileError(ValueError):
    """A gait file is missing, malformed or does not fit the creature; the message says how."""


@dataclass(frozen=True)
class GaitFile:
    """A gait read from disk: ``creature`` name, parameter ``names``, ``params`` (n,) and the
    ``maneuver`` it swims."""

    creature: str
    names: tuple[str, ...]
    params: np.ndarray
    maneuver: str = STRAIGHT

    @property
    def free_period(self) -> bool:
        """Whether its period is among its parameters (``Creature.spec``'s ``free_period``)."""
        return "period" in self.names


def write_gait(
    path, creature: Creature, params=None, maneuver: str = STRAIGHT, free_period: bool = False
) -> Path:
    """Write ``params`` (default: the creature's ``default_gait``) as ``gait.json`` at ``path``.

    Args:
        maneuver: the manoeuvre the gait swims, whose parameterization
            ``params`` is in (``Creature.spec``).
        free_period: ``params`` sets the period too (``Creature.spec``).

    Raises:
        GaitFileError: ``params`` does not fit the creature's gait.
    """
    params = creature.default_gait if params is None else np.asarray(params, dtype=float)
    names = tuple(creature.spec(maneuver, free_period).names)
    gait = GaitFile(creature.name, names, params, maneuver)
    _check_fits(gait, creature, source="the gait to write")
    return write_json(
        path,
        {"creature": gait.creature, "maneuver": maneuver, "names": gait.names, "params": params},
    )


def read_gait(path, creature: Creature | None = None) -> GaitFile:
    """Read a ``gait.json``; with ``creature``, check that it is this creature's gait.

    Raises:
        GaitFileError: no such file, not JSON, fields missing or of the wrong
            kind, or (with ``creature``) another creature's gait or a vector of
            the wrong length or names; the message names the file and the fix.
    """
    path = Path(path)
    if not path.is_file():
        raise GaitFileError(f"gait file {path} does not exist")
    try:
        data = read_json(path)
    except ValueError as err:
        raise GaitFileError(str(err)) from None
    if not isinstance(data, dict) or not {"creature", "names", "params"} <= set(data):
        raise GaitFileError(
            f"{path}: a gait file is a JSON object with 'creature', 'names' and 'params'"
        )
    try:
        params = np.array(data["params"], dtype=float)
    except (TypeError, ValueError):
        raise GaitFileError(f"{path}: 'params' must be a list of numbers") from None
    names = data["names"]
    if params.ndim != 1 or not isinstance(names, list) or len(names) != params.size:
        raise GaitFileError(
            f"{path}: 'names' and 'params' must be lists of the same length; "
            f"got {len(names) if isinstance(names, list) else names!r} names and "
            f"{params.size} numbers"
        )
    if not np.all(np.isfinite(params)):
        raise GaitFileError(f"{path}: 'params' must be finite numbers, got {params.tolist()}")
    maneuver = data.get("maneuver", STRAIGHT)
    if maneuver not in MANEUVERS:
        raise GaitFileError(
            f"{path}: 'maneuver' is {maneuver!r}; manoeuvres are {', '.join(MANEUVERS)}"
        )
    gait = GaitFile(str(data["creature"]), tuple(str(n) for n in names), params, maneuver)
    if creature is not None:
        _check_fits(gait, creature, source=str(path))
    return gait


def _check_fits(gait: GaitFile, creature: Creature, source: str) -> None:
    spec = creature.spec(gait.maneuver, gait.free_period)
    if gait.creature != creature.name:
        raise GaitFileError(f"{source} is a gait for {gait.creature!r}, not for {creature.name!r}")
    if gait.params.shape != (spec.size,):
        raise GaitFileError(
            f"{source} has {gait.params.size} gait parameters; {creature.name}'s "
            f"{gait.maneuver} gait has {spec.size}: {', '.join(spec.names)}"
        )
    if tuple(gait.names) != tuple(spec.names):
        raise GaitFileError(
            f"{source} names its parameters {', '.join(gait.names)}; {creature.name}'s gait "
            f"expects {', '.join(spec.names)}, in that order"
        )
