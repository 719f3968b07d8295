"""The path follower's choice of manoeuvre, once a cycle (paper §5, DESIGN.md §2.5).

At the start of every gait cycle the follower takes the path's point ``p``
nearest the creature's root and the path's tangent ``d`` (``Follower`` reads it
a cycle's travel further along: ``follower.LOOK_AHEAD``), both in the root's
frame (x forward, y to the left, z up; in 2D x and y), and per axis of
correction (y: turning, z: pitching) applies the paper's rule:

- the path lies to one side (``p_y > eps``) and does not come back towards
  the creature (``d_y > -eps``): turn that way (turn-left; mirrored for the
  right);
- the path lies to one side but heads back towards the creature
  (``p_y > eps`` and ``d_y < -eps``): the creature is already closing in, so
  swim straight;
- the path lies within the dead band ``eps`` (``|p_y| <= eps``): straight, so
  that small deviations do not make the creature dither between turns;
  unless the path leaves the heading by more than ``ALIGN`` there
  (``|d_y| > 0.25``, 14.5 degrees): then turn towards the path's direction.
  This last case is ours: the paper's rule says nothing of the heading on
  the path, and an eel that met an S-curve 50 degrees off its tangent swam
  straight across it, and the 2D turtle, whose straight gait pitches 25
  degrees a cycle, left a line it had just reached (measured: mean / max
  distance 0.85 / 1.80 body lengths over 10 cycles with a threshold of sin
  30 degrees, 0.31 / 0.76 with 0.25; the eel's circle 0.18 / 0.41 with either,
  its S-curve 0.39 / 1.31 and 0.45 / 1.52).

The same for z with pitch-up and pitch-down. Where both axes ask for a
correction (3D), the larger offset wins.
"""

from __future__ import annotations

import numpy as np

from aquagait import objectives
from aquagait.objectives import STRAIGHT

MANEUVERS = tuple(objectives.MANEUVERS)
ALIGN = 0.25
"""On the path (within the dead band), the tangent's sideways component beyond which the
creature turns to align with it (14.5 degrees)."""
_TOWARDS = {1: ("turn-left", "turn-right"), 2: ("pitch-up", "pitch-down")}
"""Per root-frame axis, the manoeuvres towards its + and - side."""


def root_frame(vector, root_rotation) -> np.ndarray:
    """A world vector (dim,) in the root's frame: ``R^T v`` with ``R`` the root's rotation.

    Args:
        vector: (2,) or (3,) world vector.
        root_rotation: (3, 3) the root link's world rotation (2D: about z).
    """
    vector = np.asarray(vector, dtype=float)
    padded = np.zeros(3)
    padded[: len(vector)] = vector
    return (np.asarray(root_rotation, dtype=float).T @ padded)[: len(vector)]


def choose_maneuver(offset, tangent, dead_band: float) -> str:
    """The manoeuvre the paper's rule picks (module docstring).

    Args:
        offset: (dim,) from the root to the nearest path point, in the root's frame [m].
        tangent: (dim,) the path's unit tangent there, in the root's frame.
        dead_band: ``eps`` [m for the offset; the same number bounds the tangent's
            component, as in the paper].

    Returns:
        one of ``MANEUVERS``.
    """
    offset, tangent = np.asarray(offset, dtype=float), np.asarray(tangent, dtype=float)
    eps = float(dead_band)
    wanted = []
    for axis, (positive, negative) in _TOWARDS.items():
        if axis >= len(offset):
            continue
        p, d = offset[axis], tangent[axis]
        if p > eps and d > -eps:
            wanted.append((p, positive))
        elif p < -eps and d < eps:
            wanted.append((-p, negative))
        elif abs(p) <= eps and abs(d) > ALIGN:
            wanted.append((0.0, positive if d > 0 else negative))
    return max(wanted)[1] if wanted else STRAIGHT
