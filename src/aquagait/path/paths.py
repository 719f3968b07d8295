"""Paths to follow (paper §5, docs/follow.md): polylines in metres, from files or shapes.

    path = shape("circle", dim=2, radius=1.0)          # or line, s-curve
    path = read_path("my_path.csv", dim=3)             # x,y[,z] rows; or JSON
    point, tangent = path.nearest([0.2, 0.1])          # for the follower's rule

A ``Path`` is a polyline of at least two distinct points, in world
coordinates [m], 2D (x, y: the swim plane) or 3D. Named shapes start at the
origin and go along +x, where a library creature starts and faces, so a
shape needs no placing (an S-curve crosses the x axis there):
``line(length)``, ``circle(radius, turns)`` (turning left, counter-clockwise
seen from +z; in 3D in the horizontal plane) and
``s_curve(length, amplitude, periods, vertical)`` (one sine period by default;
in 3D ``vertical`` puts it in the x-z plane, as the paper's manta follows).
"""

from __future__ import annotations

import inspect
import json
from dataclasses import dataclass
from pathlib import Path as FilePath

import numpy as np

SAMPLES_PER_METRE = 200
"""Polyline points per metre of a named shape: 5 mm apart."""


class PathError(ValueError):
    """A path that cannot be followed: the message says what is wrong and what would be right."""


@dataclass(frozen=True, eq=False)
class Path:
    """A polyline to follow.

    Attributes:
        points: (n, dim) world positions [m], n >= 2, consecutive points distinct.
    """

    points: np.ndarray

    def __post_init__(self):
        points = np.asarray(self.points, dtype=float)
        if points.ndim != 2 or points.shape[1] not in (2, 3):
            raise PathError(
                f"a path is a list of 2D (x, y) or 3D (x, y, z) points; got shape {points.shape}"
            )
        if len(points) < 2:
            raise PathError(f"a path needs at least two points; got {len(points)}")
        if not np.isfinite(points).all():
            bad = int(np.flatnonzero(~np.isfinite(points).all(axis=1))[0])
            raise PathError(f"path point {bad} is not a number: {points[bad].tolist()}")
        points = points[np.r_[True, np.linalg.norm(np.diff(points, axis=0), axis=1) > 0]]
        if len(points) < 2:
            raise PathError("the path's points are all the same point: give two distinct ones")
        object.__setattr__(self, "points", points)

    @property
    def dim(self) -> int:
        return self.points.shape[1]

    @property
    def length(self) -> float:
        """The polyline's length [m]."""
        return float(np.linalg.norm(np.diff(self.points, axis=0), axis=1).sum())

    def nearest(self, position, around: float | None = None, reach: float = np.inf):
        """The path's point nearest ``position`` (dim,) [m] and the unit tangent there.

        The tangent points along the path's direction (from its first point to
        its last); at a vertex, the segment the nearest point lies on (the
        later one where two are equally near). With ``around`` [m], only the
        stretch of the path within ``reach`` [m] of that arc length is searched:
        a follower that knows where it is on a closed or crossing path is not
        sent to another lap (``progress``).
        """
        k, t = self._foot(position, around, reach)
        step = self.points[k + 1] - self.points[k]
        return self.points[k] + t * step, step / np.linalg.norm(step)

    def at(self, arc_length: float):
        """The path's point ``arc_length`` [m] along it (clamped to its ends) and the unit
        tangent there (at a vertex, the later segment's)."""
        lengths = self._lengths
        ends = np.cumsum(lengths)
        k = min(int(np.searchsorted(ends, arc_length, side="right")), len(ends) - 1)
        step = self.points[k + 1] - self.points[k]
        t = np.clip((arc_length - (ends[k] - lengths[k])) / lengths[k], 0.0, 1.0)
        return self.points[k] + t * step, step / np.linalg.norm(step)

    def _foot(self, position, around=None, reach=np.inf) -> tuple[int, float]:
        """The segment ``k`` holding the point nearest ``position`` (the later one where two
        are equally near; within ``reach`` of arc length ``around``, if given) and where
        on it, ``t`` in [0, 1]."""
        position = np.asarray(position, dtype=float)
        if position.shape != (self.dim,):
            raise PathError(f"a {self.dim}D path is followed from {self.dim}D positions; "
                            f"got {position.shape}")  # fmt: skip
        start, step = self.points[:-1], np.diff(self.points, axis=0)
        t = np.clip(((position - start) * step).sum(1) / (step * step).sum(1), 0.0, 1.0)
        distance = np.linalg.norm(start + t[:, None] * step - position, axis=1)
        if around is not None:
            ends = np.cumsum(self._lengths)
            near = (ends >= around - reach) & (ends - self._lengths <= around + reach)
            distance = np.where(near, distance, np.inf) if near.any() else distance
        k = len(distance) - 1 - int(np.argmin(distance[::-1]))
        return k, float(t[k])

    @property
    def _lengths(self) -> np.ndarray:
        return np.linalg.norm(np.diff(self.points, axis=0), axis=1)

    def progress(self, position, around: float | None = None, reach: float = np.inf) -> float:
        """How far along the path [m] its point nearest ``position`` (dim,) [m] lies (the
        same point as ``nearest``, with the same ``around`` and ``reach``)."""
        k, t = self._foot(position, around, reach)
        lengths = self._lengths
        return float(lengths[:k].sum() + t * lengths[k])

    def distance(self, position) -> float:
        """How far ``position`` (dim,) [m] is from the path [m]."""
        point, _ = self.nearest(position)
        return float(np.linalg.norm(point - np.asarray(position, dtype=float)))

    def check_start(self, position, body_length: float, within: float = 2.0) -> None:
        """Refuse a path that starts far from the creature.

        Raises:
            PathError: the path passes more than ``within`` body lengths from
                ``position``; the message says how far and how to move it.
        """
        gap = self.distance(position)
        if gap > within * body_length:
            point, _ = self.nearest(position)
            raise PathError(
                f"the path passes {gap:.3g} m ({gap / body_length:.1f} body lengths) from the "
                f"creature's start at {np.round(position, 3).tolist()}; it must come within "
                f"{within:g} body lengths: move the path by "
                f"{np.round(np.asarray(position) - point, 3).tolist()} m"
            )


def line(length: float = 5.0, dim: int = 2) -> Path:
    """Straight ahead along +x for ``length`` [m]."""
    _positive(length=length)
    return Path(np.pad(np.array([[0.0], [length]]), ((0, 0), (0, dim - 1))))


def circle(radius: float = 1.0, turns: float = 1.0, dim: int = 2) -> Path:
    """A circle of ``radius`` [m] turning left from the origin, heading +x, ``turns`` times."""
    _positive(radius=radius, turns=turns)
    angle = np.linspace(0.0, 2 * np.pi * turns, _count(2 * np.pi * radius * turns))
    xy = radius * np.stack([np.sin(angle), 1 - np.cos(angle)], axis=1)
    return Path(np.pad(xy, ((0, 0), (0, dim - 2))))


def s_curve(
    length: float = 4.0, amplitude: float = 0.5, periods: float = 1.0, dim: int = 2,
    vertical: bool = False,
) -> Path:  # fmt: skip
    """An S: ``y = amplitude sin(2 pi periods x / length)`` for x in [0, length] [m].

    In 3D with ``vertical``, z instead of y (the paper's manta follows a vertical S).
    """
    _positive(length=length, amplitude=amplitude, periods=periods)
    x = np.linspace(0.0, length, _count(length * (1 + 2 * np.pi * amplitude * periods / length)))
    points = np.zeros((len(x), dim))
    points[:, 0] = x
    side = 2 if (vertical and dim == 3) else 1
    if vertical and dim == 2:
        raise PathError("a vertical S-curve is 3D: give dim=3, or a 2D S-curve in the plane")
    points[:, side] = amplitude * np.sin(2 * np.pi * periods * x / length)
    return Path(points)


def shape(name: str, dim: int = 2, **parameters) -> Path:
    """A named shape ('line', 'circle', 's-curve') with its parameters (keyword arguments).

    Raises:
        PathError: an unknown shape or parameter (it lists what each shape takes).
    """
    if name not in _MAKERS:
        raise PathError(f"unknown path shape {name!r}; shapes: {shapes_help()}, or a file")
    known = _parameters(name)
    unknown = [key.replace("_", "-") for key in parameters if key.replace("_", "-") not in known]
    if unknown:
        raise PathError(
            f"path shape {name!r} takes {', '.join(known)}, not {', '.join(unknown)}: "
            f"{_usage(name)} (the defaults)"
        )
    return _MAKERS[name](dim=dim, **parameters)


def shapes_help() -> str:
    """The shapes and their parameters with defaults, as a path is written on the command
    line: ``line:length=5.0; circle:radius=1.0,turns=1.0; ...``."""
    return "; ".join(_usage(name) for name in SHAPES)


def _usage(name: str) -> str:
    """A shape as written on the command line with its defaults: ``circle:radius=1.0,...``."""
    return f"{name}:{','.join(f'{k}={v}' for k, v in _parameters(name).items())}"


def _parameters(name: str) -> dict[str, object]:
    """A shape's parameters and their defaults, as written on the command line."""
    signature = inspect.signature(_MAKERS[name])
    return {
        key.replace("_", "-"): str(p.default).lower() if isinstance(p.default, bool) else p.default
        for key, p in signature.parameters.items()
        if key != "dim"
    }


_MAKERS = {"line": line, "circle": circle, "s-curve": s_curve}
SHAPES = tuple(_MAKERS)
"""The named shapes, as the command line writes them."""


def read_path(file, dim: int) -> Path:
    """A path from a CSV file (rows x,y or x,y,z [m]; a header row is skipped) or a JSON file
    (a list of points, or ``{"points": [...]}``).

    Raises:
        PathError: no such file, unreadable rows, or points of another dimension than ``dim``.
    """
    file = FilePath(file)
    if not file.is_file():
        raise PathError(f"path file {file} does not exist")
    try:
        if file.suffix.lower() == ".json":
            data = json.loads(file.read_text())
            points = np.asarray(data["points"] if isinstance(data, dict) else data, dtype=float)
        else:
            rows = [r for r in file.read_text().splitlines() if r.strip()]
            if rows and not _numeric(rows[0]):
                rows = rows[1:]  # a header
            points = np.array([[float(v) for v in r.split(",")] for r in rows])
    except (ValueError, KeyError, TypeError, json.JSONDecodeError) as err:
        raise PathError(f"{file}: not a list of points ({err}); give rows x,y[,z] in m") from None
    path = Path(points)
    if path.dim != dim:
        raise PathError(f"{file} holds {path.dim}D points but the creature swims in {dim}D")
    return path


def parse_path(path, dim: int, start=None) -> tuple[Path, str]:
    """A path as the command line and the jobs take it, and where it came from.

    Args:
        path: a ``Path``; a named shape with parameters, ``NAME[:key=value,...]``
            (``circle:radius=0.6``, ``s-curve:length=4,amplitude=0.5,vertical=true``),
            moved to start at ``start``; or a CSV or JSON file of points [m] (``read_path``).
        dim: the creature's dimension, 2 or 3.
        start: (dim,) where a shape starts [m]; default the origin.

    Returns:
        ``(path, source)``: the path and a description (the shape as given, the file's name).
    Raises:
        PathError: the wrong dimension, a malformed shape, no such file (what would be right).
    """
    if isinstance(path, Path):
        if path.dim != dim:
            raise PathError(f"a {path.dim}D path for a {dim}D creature")
        return path, "a given path"
    text = str(path)
    name, _, arguments = text.partition(":")
    if name in SHAPES:
        parameters = {}
        for item in filter(None, arguments.split(",")):
            key, sep, value = item.partition("=")
            try:
                parameters[key.strip().replace("-", "_")] = _value(value)
            except ValueError:
                raise PathError(
                    f"path shape {text!r}: give parameters as key=value, e.g. "
                    "circle:radius=0.6 or s-curve:length=4,amplitude=0.5"
                ) from None
            if not sep:
                raise PathError(f"path shape {text!r}: {item!r} is not key=value")
        made = shape(name, dim=dim, **parameters)
        offset = np.zeros(dim) if start is None else np.asarray(start, dtype=float)
        return Path(made.points + offset), text
    looks_like_file = FilePath(text).suffix.lower() in (".csv", ".json", ".txt")
    if not FilePath(text).exists() and not looks_like_file:
        raise PathError(
            f"{text!r} is neither a path file nor a shape; shapes (NAME:key=value,..., "
            f"the defaults shown): {shapes_help()}; or a CSV or JSON file of points"
        )
    return read_path(text, dim), text


def _value(text: str):
    text = text.strip()
    if text.lower() in ("true", "false"):
        return text.lower() == "true"
    return float(text)


def _numeric(row: str) -> bool:
    try:
        [float(v) for v in row.split(",")]
    except ValueError:
        return False
    return True


def _count(length: float) -> int:
    return max(2, int(np.ceil(length * SAMPLES_PER_METRE)) + 1)


def _positive(**values) -> None:
    for name, value in values.items():
        if not (np.isfinite(value) and value > 0):
            raise PathError(f"{name} must be a positive number, got {value!r}")
