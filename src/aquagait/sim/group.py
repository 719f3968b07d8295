"""Several creatures in one fluid: their grid, the gaps between them, each one's swim.

A group is one composed model (``aquagait.body.group``), so a scene, a step
and a rollout take it as they take one creature; this module adds what only
a group has:

- ``group_grid``: the grid that holds every member's own default grid at
  its starting pose, in the finest of their cells;
- ``check_apart``: aquagait has no contact between creatures, so a swim in
  which two touch stops cleanly (``CreaturesTouched``), saying which two and
  when (``step`` checks after every step); ``make_scene`` refuses creatures
  that overlap at their starting poses, with how deep;
- ``member_trajectory``: one member's part of a group's trajectory, for its
  own metrics.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from aquagait.body.dynamics import Dynamics
from aquagait.body.group import Group, Member, deepest_overlap, member_gaps, posed
from aquagait.sim.servo import SimulationError

if TYPE_CHECKING:
    from aquagait.sim.rollout import Trajectory
    from aquagait.sim.scene import Scene, State

GRID_MULTIPLE = 8
"""A group's grid has a multiple of this many cells along each axis (halvings for the
multigrid)."""


class CreaturesTouched(SimulationError):
    """Two creatures of a group touched: aquagait has no contact between creatures."""


def group_grid(group: Group, resolutions, cell_sizes) -> tuple[tuple[int, ...], float, tuple]:
    """The grid that holds each member's own grid at its starting pose.

    Each member's grid (``resolutions[i]`` cells of ``cell_sizes[i]``, centred on
    its centre of mass as ``make_scene`` centres one creature's) is placed at
    its pose; the group's covers them all, in the smallest of their cells,
    rounded up to ``GRID_MULTIPLE`` cells along each axis.

    Returns:
        ``(resolution, cell_size, origin)`` for ``make_scene``.
    """
    h = float(min(cell_sizes))
    lows, highs = [], []
    for member, shape, size in zip(group.members, resolutions, cell_sizes, strict=True):
        model = member.model
        centre = Dynamics(model.mj).center_of_mass(posed(model, member.pose))[: model.dim]
        half = 0.5 * np.asarray(shape, dtype=float) * size
        lows.append(centre - half)
        highs.append(centre + half)
    lo, hi = np.min(lows, axis=0), np.max(highs, axis=0)
    cells = [GRID_MULTIPLE * math.ceil((b - a) / h / GRID_MULTIPLE - 1e-9)
             for a, b in zip(lo, hi, strict=True)]  # fmt: skip
    centre = 0.5 * (lo + hi)
    origin = centre - 0.5 * np.asarray(cells) * h
    return tuple(cells), h, tuple(float(x) for x in origin)


def gaps(scene: Scene, qpos) -> np.ndarray:
    """How far each member's surface keeps out of each other member at ``qpos``, (n, n) [m]
    (``aquagait.body.group.member_gaps``: negative inside, inf when not near)."""
    link_pos, link_rot = scene.dynamics.link_poses(qpos)
    surfaces, shape = scene.gap_geometry
    return member_gaps(scene.group, shape, surfaces, link_pos, link_rot)


def check_apart(scene: Scene, state: State) -> None:
    """Stop a group's swim where two of its creatures touch (``step`` calls it after every
    step; one creature passes).

    Raises:
        CreaturesTouched: which two, when, and how deep.
    """
    if scene.group is None:
        return
    overlap = deepest_overlap(scene.group, gaps(scene, state.qpos))
    if overlap is not None:
        a, b, inside = overlap
        raise CreaturesTouched(
            f"at t = {state.time:.4g} s {a.label} and {b.label} touched ({inside}); aquagait "
            "has no contact between creatures: start them further apart, or change their gaits"
        )


def member_trajectory(trajectory: Trajectory, member: Member) -> Trajectory:
    """``member``'s own part of a group's trajectory (its positions, velocities, torques
    and work), for its metrics; the fluid stays the group's."""
    return replace(
        trajectory,
        qpos=trajectory.qpos[:, member.qpos],
        qvel=trajectory.qvel[:, member.dofs],
        torque=trajectory.torque[:, member.dofs],
        energy=trajectory.energy[:, member.dofs],
    )
