"""Paths and the follower's rule (paper §5, DESIGN.md §2.5): what to follow, and which
manoeuvre to swim at each cycle's start.

    from aquagait.path import shape, read_path, choose_maneuver, root_frame

``paths``: polylines from files (CSV, JSON) or named shapes (line, circle,
S-curve), their nearest point and tangent, with clear errors for paths that
cannot be followed. ``rule``: the paper's choice among straight, turns and
pitches with a dead band. The manoeuvres themselves (optimized gaits) and
the follower that switches between them are issue 13's next part.
"""

from aquagait.path.paths import SHAPES, Path, PathError, circle, line, read_path, s_curve, shape
from aquagait.path.rule import MANEUVERS, choose_maneuver, root_frame

__all__ = [
    "MANEUVERS",
    "SHAPES",
    "Path",
    "PathError",
    "choose_maneuver",
    "circle",
    "line",
    "read_path",
    "root_frame",
    "s_curve",
    "shape",
]
