"""The path follower's choice of manoeuvre, once a cycle (paper §5, docs/follow.md).

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

Graded steering (``graded_shares``, ours; ``aquagait follow --steer graded``)
mixes a share of a manoeuvre into the straight gait instead of swimming one
whole: per axis, the share turns the heading towards an aim point on the path
ahead (``Follower`` aims ``AIM`` cycles' travel further along than the
nearest point), ``GAIN`` times the bearing to it over the next cycle, as a
share of the manoeuvre's own turn a cycle (its ``rate``), at most 1. The
paper's rule asks for a whole turn or none, once a cycle; a turn strong
enough for the tight bends overshoots the gentle ones, and the creature
weaves; one too weak lets a drifting straight gait run away. Measured with
the gaits learned on 2026-12-04 and each manoeuvre's rate measured from rest
(mean / max distance to the path in body lengths, until the path's end; by
the paper's rule, then graded):

- eel2d, circle of radius 0.6 m, 12 cycles: 0.12 / 0.38, 0.09 / 0.40;
- eel2d, S-curve 3 m long and 0.4 m high, 12 cycles: 0.43 / 0.94, 0.22 /
  0.61 (by the paper's rule with its older turn-right, which bites a cycle
  later: 0.16 / 0.61);
- turtle2d, line, 10 cycles: 0.43 / 1.12, 0.28 / 0.74;
- manta, vertical S 1 m long and 0.1 m high, 20 cycles (its straight gait
  and pitches learned before 2026-12-03): 0.17 / 0.34, 0.02 / 0.07.

Gains 1.5 and 1 kept the eel as close (circle 0.09, 0.07; S-curve 0.21,
0.22) but the turtle less (0.34 / 0.90, 0.46 / 1.14).
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

GAIN = 2.0
"""Graded steering: the turn asked for over the next cycle, as a multiple of the bearing to
the aim point (module docstring)."""


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


def graded_shares(aim, rates, gain: float = GAIN) -> dict[str, float]:
    """Graded steering's manoeuvres and their shares (module docstring).

    Per axis of correction (y: turning, z: pitching), the bearing ``e`` of ``aim``
    off the root's heading asks for ``gain * |e|`` of turn over the next cycle,
    the share ``gain * |e| / rate`` of the manoeuvre towards it (at most 1). Where
    both axes ask (3D) and their shares add past 1, both are scaled down to add to 1.

    Args:
        aim: (dim,) from the root to the aim point, in the root's frame [m].
        rates: ``{manoeuvre: its turn a cycle}`` [rad], > 0, of the manoeuvres
            learned; an axis whose manoeuvre has none is not corrected (the manta,
            which pitches only, follows a vertical path that its sway leaves a
            hair to one side).
        gain: ``GAIN``.

    Returns:
        ``{manoeuvre: share}`` for each axis that asks, shares in (0, 1].
    """
    aim = np.asarray(aim, dtype=float)
    shares = {}
    for axis, (positive, negative) in _TOWARDS.items():
        if axis >= len(aim) or aim[axis] == 0.0:
            continue
        bearing = np.arctan2(aim[axis], aim[0])
        name = positive if bearing > 0 else negative
        if name in rates:
            shares[name] = min(gain * abs(bearing) / rates[name], 1.0)
    total = sum(shares.values())
    return {name: share / max(total, 1.0) for name, share in shares.items()}
