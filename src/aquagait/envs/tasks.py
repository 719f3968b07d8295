"""What the swimmer is asked to do: ``forward``, ``target`` or ``follow`` (``SwimEnv``'s ``task``).

A task sees the creature's ``Pose`` at every control step and gives three things:
what it adds to the observation (``observe``, ``names``), the reward's task
term (``progress``, in m/s) and whether the episode is over because the task
is done (``reached``). The environment subtracts the power term from the
progress (``aquagait.envs.swim``), so every task's reward reads in m/s.

- ``forward``: progress is the root's speed along the creature's own forward
  axis (its heading at the start of the control step). Nothing to observe;
  never reached.
- ``target``: swim to a point. Progress is the rate at which the distance to
  it shrinks [m/s]; reached within ``radius`` of it. The observation is the
  target's offset in the creature's frame [m]. Without a given point, each
  ``reset`` draws one ahead of the creature from the episode's generator:
  ``TARGET_DISTANCE`` body lengths away, within ``TARGET_BEARING`` of straight
  ahead (in 3D also within ``TARGET_ELEVATION`` of level).
- ``follow``: swim along a path (``aquagait.path.parse_path``: a shape such as
  ``circle:radius=0.6``, starting at the root; a CSV or JSON file; a ``Path``).
  Where the creature is on the path is tracked from step to step: the nearest
  point is sought within ``REACH`` body lengths (of arc) of the last one, so a
  closed path's end is not taken for its start. Progress is the rate of
  advance along the path minus ``distance_weight`` [1/s] times the distance
  from it [m]; reached within ``radius`` of the path's end (in arc length). The
  observation is the offset to the nearest path point and the path's unit
  tangent there, both in the creature's frame.

The creature's frame is the root link's orientation relative to its rest
pose: at rest it is the world's (+x forward, the way aquagait's creatures
face; +y left; +z up), and it turns with the root.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aquagait.path import parse_path

TASKS = ("forward", "target", "follow")
"""The tasks ``SwimEnv(task=...)`` knows (``make_task``)."""

REACHED = 0.5
"""Default radius of ``target`` and of the end of ``follow``, in body lengths."""

TARGET_DISTANCE = (2.0, 4.0)
"""A drawn target's distance from the start, in body lengths."""

TARGET_BEARING = np.radians(60.0)
"""A drawn target lies within this angle [rad] left or right of the start heading."""

TARGET_ELEVATION = np.radians(30.0)
"""In 3D, a drawn target lies within this angle [rad] above or below level."""

REACH = 1.0
"""``follow`` seeks the nearest path point within this many body lengths of arc of the last."""

DISTANCE_WEIGHT = 1.0
"""``follow``'s weight on the distance from the path [1/s]: 0.1 m off costs 0.1 m/s."""


@dataclass(frozen=True)
class Pose:
    """The creature at a control step, as the tasks see it.

    Attributes:
        time: t [s].
        position: (dim,) the root link's origin in the world [m].
        frame: (3, 3) the creature's frame in the world (its columns: forward,
            left, up; module docstring).
    """

    time: float
    position: np.ndarray
    frame: np.ndarray

    def local(self, vector) -> np.ndarray:
        """A world vector (dim,) in the creature's frame, (dim,)."""
        vector = np.asarray(vector, dtype=float)
        dim = len(vector)
        padded = np.zeros(3)
        padded[:dim] = vector
        return (self.frame.T @ padded)[:dim]


class Forward:
    """Swim ahead as fast as the power allows (module docstring)."""

    name = "forward"

    def __init__(self, dim: int, body_length: float):
        self.dim = dim

    @property
    def names(self) -> tuple[str, ...]:
        return ()

    def reset(self, start: Pose, rng: np.random.Generator) -> None:
        """Nothing to choose."""

    def observe(self, pose: Pose) -> np.ndarray:
        return np.zeros(0)

    def progress(self, before: Pose, after: Pose) -> float:
        """Speed along the heading at ``before`` over the step [m/s]."""
        ahead = before.frame[: self.dim, 0]
        return float(ahead @ (after.position - before.position) / (after.time - before.time))

    def reached(self, pose: Pose) -> bool:
        return False

    def describe(self) -> dict:
        return {"task": self.name}


class Target:
    """Reach a point (module docstring).

    Args:
        dim: 2 or 3.
        body_length: the creature's [m].
        target: (dim,) the point [m] in the world, or None to draw one per episode.
        radius: how near counts as reached [m]; default ``REACHED`` body lengths.
    """

    name = "target"

    def __init__(self, dim: int, body_length: float, target=None, radius: float | None = None):
        self.dim, self.body_length = dim, body_length
        self.given = None if target is None else np.asarray(target, dtype=float)
        given = self.given
        if given is not None and (given.shape != (dim,) or not np.isfinite(given).all()):
            raise ValueError(
                f"target must be {dim} numbers, a point in metres for this {dim}D creature; "
                f"got {target!r}"
            )
        self.radius = REACHED * body_length if radius is None else float(radius)
        if not self.radius > 0:
            raise ValueError(f"radius must be a positive number of metres, got {radius!r}")
        self.point = self.given

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f"target:{axis}" for axis in "xyz"[: self.dim])

    def reset(self, start: Pose, rng: np.random.Generator) -> None:
        """The given point, or one drawn ahead of ``start`` from ``rng`` (module docstring)."""
        if self.given is not None:
            self.point = self.given
            return
        distance = rng.uniform(*TARGET_DISTANCE) * self.body_length
        bearing = rng.uniform(-TARGET_BEARING, TARGET_BEARING)
        elevation = rng.uniform(-TARGET_ELEVATION, TARGET_ELEVATION) if self.dim == 3 else 0.0
        level = np.cos(elevation)
        local = distance * np.array(
            [level * np.cos(bearing), level * np.sin(bearing), np.sin(elevation)]
        )
        self.point = start.position + (start.frame @ local)[: self.dim]

    def observe(self, pose: Pose) -> np.ndarray:
        return pose.local(self.point - pose.position)

    def distance(self, pose: Pose) -> float:
        return float(np.linalg.norm(self.point - pose.position))

    def progress(self, before: Pose, after: Pose) -> float:
        """How fast the distance to the point shrank over the step [m/s]."""
        return (self.distance(before) - self.distance(after)) / (after.time - before.time)

    def reached(self, pose: Pose) -> bool:
        return self.distance(pose) < self.radius

    def describe(self) -> dict:
        point = None if self.point is None else self.point.tolist()
        return {"task": self.name, "target": point, "radius": self.radius}


class Follow:
    """Swim along a path (module docstring).

    Args:
        dim: 2 or 3.
        body_length: the creature's [m].
        path: what ``aquagait.path.parse_path`` takes; a shape starts at ``start``.
        start: (dim,) the root's position at rest [m].
        radius: how near the path's end counts as reached [m]; default ``REACHED``
            body lengths.
        distance_weight: the weight on the distance from the path [1/s].
    """

    name = "follow"

    def __init__(self, dim: int, body_length: float, path, start, radius: float | None = None,
                 distance_weight: float = DISTANCE_WEIGHT):  # fmt: skip
        if path is None:
            raise ValueError(
                "the follow task needs a path: a shape (circle:radius=0.6, "
                "s-curve:length=3,amplitude=0.4), a CSV or JSON file of points, or a Path"
            )
        self.dim = dim
        self.path, self.source = parse_path(path, dim, start)
        self.path.check_start(start, body_length)
        self.radius = REACHED * body_length if radius is None else float(radius)
        if not self.radius > 0:
            raise ValueError(f"radius must be a positive number of metres, got {radius!r}")
        if not distance_weight >= 0:
            raise ValueError(f"distance_weight must be >= 0 per second, got {distance_weight!r}")
        self.distance_weight = float(distance_weight)
        self.reach = REACH * body_length
        self.arc = 0.0

    @property
    def names(self) -> tuple[str, ...]:
        axes = "xyz"[: self.dim]
        return tuple(f"path_offset:{a}" for a in axes) + tuple(f"path_tangent:{a}" for a in axes)

    def reset(self, start: Pose, rng: np.random.Generator) -> None:
        """The path is fixed; the creature starts at its beginning."""
        self.arc = self.path.progress(start.position, around=0.0, reach=self.reach)

    def _locate(self, pose: Pose) -> float:
        return self.path.progress(pose.position, around=self.arc, reach=self.reach)

    def observe(self, pose: Pose) -> np.ndarray:
        point, tangent = self.path.nearest(pose.position, around=self.arc, reach=self.reach)
        return np.concatenate([pose.local(point - pose.position), pose.local(tangent)])

    def progress(self, before: Pose, after: Pose) -> float:
        """Advance along the path [m/s] less ``distance_weight`` times the distance from it;
        moves the tracked place on the path on to ``after``."""
        arc = self._locate(after)
        rate = (arc - self.arc) / (after.time - before.time)
        self.arc = arc
        point, _ = self.path.nearest(after.position, around=arc, reach=self.reach)
        return rate - self.distance_weight * float(np.linalg.norm(point - after.position))

    def reached(self, pose: Pose) -> bool:
        return self.arc >= self.path.length - self.radius

    def describe(self) -> dict:
        return {"task": self.name, "path": self.source, "radius": self.radius,
                "distance_weight": self.distance_weight}  # fmt: skip


def make_task(name: str, dim: int, body_length: float, start, target=None, path=None,
              radius: float | None = None, distance_weight: float = DISTANCE_WEIGHT):  # fmt: skip
    """The task called ``name`` for a creature of ``dim`` and ``body_length`` [m] whose root
    rests at ``start`` (dim,) [m].

    Raises:
        ValueError: an unknown task, or settings it does not take or cannot use.
    """
    if name not in TASKS:
        raise ValueError(f"unknown task {name!r}; tasks: {', '.join(TASKS)}")
    if target is not None and name != "target":
        raise ValueError(f"target= is for task='target', not {name!r}")
    if path is not None and name != "follow":
        raise ValueError(f"path= is for task='follow', not {name!r}")
    if name == "forward":
        return Forward(dim, body_length)
    if name == "target":
        return Target(dim, body_length, target, radius)
    return Follow(dim, body_length, path, start, radius, distance_weight)


__all__ = ["TASKS", "Follow", "Forward", "Pose", "Target", "make_task"]
