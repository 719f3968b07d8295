"""Every shipped manoeuvre does what it is named, in water (paper §5).

Two cycles of each learned gait from rest: a turn yaws the way it is named,
a pitch raises or lowers the nose, straight stays straight. The rotation is
the root's, averaged over the second cycle's frames (``turned``): the root
(the head) sways within every cycle, by 10 degrees in the eel's straight
gait, which a single frame would count as turning. The eel's run in
the default suite (2D, a few seconds each); the turtle's and the manta's are
slow (``-m slow``). A turn's rotation over two cycles must be at least
``TURNED`` and the unwanted rotation at most ``OFF_AXIS`` of it.
"""

import numpy as np
import pytest

import aquagait as ag
from aquagait.app.follow import NEEDED
from aquagait.body.rotations import quat_conj, quat_log, quat_mul
from aquagait.objectives import MANEUVERS

TURNED = 0.2
"""Least rotation about a manoeuvre's axis by the second cycle [rad] (11 degrees): twice
what the straight gaits may drift (``STRAIGHT``; they drift 0.01-0.03)."""

OFF_AXIS = 0.5
"""Most rotation about other axes, as a share of the wanted rotation."""

STRAIGHT = 0.1
"""Most rotation of the straight gait by the second cycle [rad] (6 degrees)."""

SLOW = {"turtle2d", "manta"}
"""Creatures whose manoeuvres are checked with ``-m slow``."""

LIBRARY = {"eel2d": NEEDED[1], "turtle2d": NEEDED[1], "manta": NEEDED[2]}
"""The creatures that ship manoeuvres, and which (issue 13)."""

GRIDS = {"eel2d": (96, 96)}
"""Where the default grid is too narrow for a turning body (the grid of its optimization)."""


def _cases():
    for name, maneuvers in LIBRARY.items():
        marks = [pytest.mark.slow] if name in SLOW else []
        for maneuver in maneuvers:
            yield pytest.param(name, maneuver, marks=marks, id=f"{name}-{maneuver}")
        if name != "turtle2d":  # the turtle cannot swim straight open-loop (paper §7)
            yield pytest.param(name, "straight", marks=marks, id=f"{name}-straight")


def turned(model, trajectory, frames: int = 30) -> np.ndarray:
    """The root's rotation from the first frame, a world rotation vector [rad], averaged over
    the last ``frames`` frames (a cycle)."""
    q = trajectory.qpos
    if model.dim == 2:
        return np.array([0.0, 0.0, np.mean(q[-frames:, 2] - q[0, 2])])
    start = quat_conj(q[0, 3:7])
    return np.mean([quat_log(quat_mul(r, start)) for r in q[-frames:, 3:7]], axis=0)


@pytest.mark.parametrize("name, maneuver", list(_cases()))
def test_a_shipped_manoeuvre_turns_the_way_it_is_named(name, maneuver):
    creature = ag.creatures.get(name)
    assert maneuver in creature.maneuvers, f"{name} ships no {maneuver!r} gait"
    scene = ag.make_scene(creature, resolution=GRIDS.get(name), fluid="euler")
    policy = creature.policy(maneuver=maneuver)
    trajectory = ag.rollout(scene, ag.init_state(scene), policy, 2.0, record_fluid=False)
    rotation = turned(creature.model, trajectory)
    _, axis = MANEUVERS[maneuver]
    print(f"{name} {maneuver}: rotation vector {np.round(rotation, 3).tolist()} rad")
    if axis is None:
        assert np.linalg.norm(rotation) < STRAIGHT
        return
    wanted = float(np.dot(axis, rotation))
    assert wanted > TURNED
    assert np.linalg.norm(rotation - wanted * np.asarray(axis)) < OFF_AXIS * wanted
