"""Paths and the follower's rule (paper §5, docs/follow.md): what to follow, and which
manoeuvre to swim at each cycle's start.

    from aquagait.path import shape, read_path, choose_maneuver, root_frame

``paths``: polylines from files (CSV, JSON) or named shapes (line, circle,
S-curve), their nearest point and tangent, with clear errors for paths that
cannot be followed. ``rule``: the paper's choice among straight, turns and
pitches with a dead band. ``follower``: the planner that swims a creature's
learned manoeuvres along a path, choosing at every cycle's start and
blending the switches (``aquagait.app.follow`` runs it for a creature).
"""

from aquagait.path.follower import BLEND, Decision, Follower, root_pose
from aquagait.path.paths import (
    SHAPES,
    Path,
    PathError,
    circle,
    line,
    parse_path,
    read_path,
    s_curve,
    shape,
)
from aquagait.path.rule import MANEUVERS, choose_maneuver, root_frame

__all__ = [
    "BLEND",
    "MANEUVERS",
    "Decision",
    "Follower",
    "SHAPES",
    "Path",
    "PathError",
    "choose_maneuver",
    "circle",
    "line",
    "parse_path",
    "read_path",
    "root_frame",
    "root_pose",
    "s_curve",
    "shape",
]
