"""turtle3d: a four-flippered green sea turtle (paper Table 1: 3D, 10 DOFs, 10 dims, 64x32x32)."""

import itertools

import numpy as np
import pytest

import aquagait as ag
from aquagait.app.check import prepare_check, resolving_shape
from aquagait.app.swim import prepare_swim, run_swim
from aquagait.body.shape import link_thickness, world_bounds
from aquagait.sim import CLEARANCE

LEFT = ("shoulder_flap_l", "shoulder_feather_l", "wrist_l", "hip_flap_l", "hip_feather_l")
FRONT = ("shoulder_flap", "shoulder_feather", "wrist")


@pytest.fixture(scope="module")
def turtle():
    return ag.creatures.get("turtle3d")


@pytest.fixture(scope="module")
def scene(turtle):
    return prepare_check(turtle).scene


def test_table1_numbers(turtle):
    assert turtle.dim == 3
    assert len(turtle.model.actuated_dofs) == 10
    assert turtle.gait.size == 10
    assert tuple(turtle.resolution) == (64, 32, 32)


def test_right_side_mirrors_the_left_and_front_flippers_go_first(turtle):
    gait = turtle.gait
    assert gait.independent == LEFT
    # a mirror image in the x-z plane negates rotations about local x (flap,
    # wrist) and keeps those about the span axis (feather)
    signs = {dof: sign for dof, _, sign in gait.mirror}
    assert {src: dof for dof, src, _ in gait.mirror} == {d: d[:-1] + "r" for d in LEFT}
    assert [signs[d[:-1] + "r"] for d in LEFT] == [-1, 1, -1, -1, 1]
    front, rear = gait.groups
    assert set(front) == {f"{d}_{s}" for d in FRONT for s in "lr"}
    assert set(rear) == {f"hip_{d}_{s}" for d in ("flap", "feather") for s in "lr"}


def test_mirrored_gait_poses_the_body_symmetrically(turtle, scene):
    gait = turtle.gait.unpack(turtle.default_gait)
    model = turtle.model
    qpos = {j.name: j.qpos for j in model.joints}
    links = list(model.links)
    flip = np.diag([1.0, -1.0, 1.0])
    for t in (0.1, 0.35, 0.8):
        q = model.qpos0.copy()
        for dof, angle in zip(gait.dofs, gait.angles(t), strict=True):
            q[qpos[dof]] = angle
        pos, rot = scene.dynamics.link_poses(q)
        for name in ("arm", "hand", "rear"):
            left, right = links.index(f"{name}_l"), links.index(f"{name}_r")
            np.testing.assert_allclose(pos[right], flip @ pos[left], atol=1e-9)
            # the right link's frame is the mirrored left frame with local y flipped
            np.testing.assert_allclose(rot[right], flip @ rot[left] @ flip, atol=1e-9)


def test_every_link_is_at_least_one_and_a_half_cells_thick(turtle, scene):
    thickness = link_thickness(resolving_shape(turtle.model, scene.shape))
    assert np.all(thickness / turtle.cell_size >= 1.5), dict(
        zip(turtle.model.links, np.round(thickness / turtle.cell_size, 2), strict=True)
    )


def test_every_pose_within_the_limits_fits_the_default_grid(turtle, scene):
    # Across the 32 cells the flippers' span must leave CLEARANCE cells of water
    # on both sides in any pose the optimizer may try: every left joint at its
    # limits or at rest, the right side mirrored.
    model, gait = turtle.model, turtle.gait
    joints = {j.name: j for j in model.joints}
    widest = np.zeros(3)
    for signs in itertools.product((-1, 0, 1), repeat=len(LEFT)):
        angle = {d: s * joints[d].range[1] for d, s in zip(LEFT, signs, strict=True)}
        angle |= {dof: sign * angle[src] for dof, src, sign in gait.mirror}
        q = model.qpos0.copy()
        for dof, a in angle.items():
            q[joints[dof].qpos] = a
        box = world_bounds(scene.shape, *scene.dynamics.link_poses(q))
        widest = np.maximum(widest, (box[1] - box[0]) / turtle.cell_size)
    assert np.all(widest <= np.array(turtle.resolution) - 2 * CLEARANCE), widest


def test_masses(turtle):
    mass = dict(zip(turtle.model.links, turtle.model.link_mass, strict=True))
    # the shell ellipsoid, 4/3 pi 0.35 0.26 0.11 m^3 of water, and the head
    shell = 4 / 3 * np.pi * (0.35 * 0.26 * 0.11 + 0.09 * 0.06 * 0.05) * 1000
    assert mass["shell"] == pytest.approx(shell, rel=1e-3)
    assert mass["arm_l"] == pytest.approx(mass["arm_r"])
    assert mass["arm_l"] + mass["hand_l"] > 1.5 * mass["rear_l"]
    assert 40 < sum(mass.values()) < 70  # a 0.7 m green turtle weighs 40-50 kg


def test_shipped_gait_swims_forward_on_its_front_flippers():
    # One cycle from rest at the default grid (about 10 s of wall time). The
    # shipped gait travels 0.028 m in it (it recoils backwards in the first
    # third); the test asks for forward travel, no sideways drift beyond a
    # hundredth of that (the gait is mirror symmetric), and that the front
    # flippers, swinging 4-6 times the rear ones' amplitude, do most of the work.
    run = run_swim(prepare_swim("turtle3d", seconds=1.0))
    model, trajectory = run.setup.creature.model, run.trajectory
    x, y = trajectory.qpos[-1, :2]
    assert x > 0.01
    assert abs(y) < 0.05 * x
    work = dict(zip(model.dof_names, trajectory.energy[-1], strict=True))
    front = sum(work[f"{d}_{s}"] for d in FRONT for s in "lr")
    assert front > 0.9 * sum(work[model.dof_names[i]] for i in model.actuated_dofs)
