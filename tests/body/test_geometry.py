"""Points on geoms and the tail tip, on models whose geometry is known exactly."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.body.geometry import geom_point_sets, geom_points, tail_tip, tail_tip_path

SHAPES = """<mujoco><worldbody><body name="a" pos=".1 .2 .3"><freejoint/>
    <geom type="box" size=".04 .02 .01" pos=".01 0 0" density="1000"/>
    <geom type="sphere" size=".03" pos="-.05 0 0" density="1000"/>
    <body name="b" pos="-.1 0 0" euler="0 0 90">
      <joint name="j" type="hinge" axis="0 0 1" range="-30 30"/>
      <geom type="capsule" fromto="0 0 0 0 .1 0" size=".01" density="1000"/>
      <geom type="cylinder" fromto="0 .1 0 0 .16 0" size=".005" density="1000"/>
    </body></body></worldbody></mujoco>"""


def test_points_lie_on_their_geoms():
    model = ag.load_model(SHAPES)
    (a, box), (_, sphere), (b, capsule), (_, cylinder) = geom_point_sets(model)
    assert model.links[a] == "a" and model.links[b] == "b"
    corners = [[x, y, z] for x in (-0.03, 0.05) for y in (-0.02, 0.02) for z in (-0.01, 0.01)]
    np.testing.assert_allclose(sorted(box.tolist()), sorted(corners), atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(sphere - [-0.05, 0, 0], axis=1), 0.03, atol=1e-12)
    # link b's frame is turned 90 degrees about z: its +y points back along the world's -x
    on_axis = np.clip(capsule[:, 1], 0, 0.1)
    gap = np.linalg.norm(capsule - np.stack([0 * on_axis, on_axis, 0 * on_axis], 1), axis=1)
    np.testing.assert_allclose(gap, 0.01, atol=1e-12)
    np.testing.assert_allclose(np.hypot(cylinder[:, 0], cylinder[:, 2]), 0.005, atol=1e-12)
    np.testing.assert_allclose(sorted(set(np.round(cylinder[:, 1], 12))), [0.1, 0.16])


def test_world_points_are_the_link_points_placed_at_the_reference_pose():
    model = ag.load_model(SHAPES)
    links, world = geom_points(model, world=True)
    _, local = geom_points(model)
    # link a sits at (.1, .2, .3); link b 0.1 m behind it, turned 90 degrees about z
    a, b = links == 0, links == 1
    np.testing.assert_allclose(world[a], local[a] + [0.1, 0.2, 0.3], atol=1e-12)
    turned = local[b] @ np.array([[0, 1, 0], [-1, 0, 0], [0, 0, 1]])
    np.testing.assert_allclose(world[b], turned + [0.0, 0.2, 0.3], atol=1e-12)


def test_tail_tip_is_the_rearmost_point_of_the_body(eel):
    tip = tail_tip(eel.model)
    assert eel.model.links[tip.link] == "tail"
    np.testing.assert_allclose(tip.offset, [-0.1, 0, 0], atol=1e-9)  # mid-point of the end
    fish = ag.creatures.get("fish").model
    tip = tail_tip(fish)
    assert fish.links[tip.link] == "caudal"
    np.testing.assert_allclose(tip.offset, [-0.02, 0, 0], atol=1e-9)  # middle of the fin's edge
    _, points = geom_points(fish, world=True)
    assert points[:, 0].min() == pytest.approx(tail_tip_path(fish, [fish.qpos0])[0, 0])


def test_tail_tip_of_round_geoms():
    model = ag.load_model(SHAPES)
    tip = tail_tip(model)
    assert model.links[tip.link] == "b"
    np.testing.assert_allclose(tip.offset, [0, 0.16, 0], atol=1e-9)  # the cylinder's end


def test_tail_tip_path_follows_the_root_and_the_tail_joint(eel):
    # eel2d: the tail link's tip is 0.1 m behind joint j4; turn the whole eel by
    # `heading`, shift it by `shift` and bend j4 by `bend`: the tip moves rigidly with them
    heading, shift, bend = 0.7, np.array([0.3, -0.2]), 0.25
    rest = tail_tip_path(eel.model, [eel.model.qpos0])[0]
    q = eel.model.qpos0.copy()
    q[:2], q[2] = shift, heading
    q[eel.model.joint("j4").qpos] = bend
    joint = rest + [0.1, 0.0]  # j4 sits 0.1 m ahead of the tip on the straight eel
    bent = joint + 0.1 * np.array([-np.cos(bend), -np.sin(bend)])
    turn = np.array([[np.cos(heading), -np.sin(heading)], [np.sin(heading), np.cos(heading)]])
    root = np.array([0.2, 0.0])  # the head's origin, about which the planar root turns
    expected = root + shift + turn @ (bent - root)
    path = tail_tip_path(eel.model, [eel.model.qpos0, q])
    assert path.shape == (2, 2)
    np.testing.assert_allclose(path[1], expected, atol=1e-7)  # float32 mesh vertices
