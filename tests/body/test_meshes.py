"""Link meshes: closed outward surfaces of the geoms, in each link's frame, in their colours."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.body.dynamics import describe
from aquagait.body.geometry import geom_points, link_volumes
from aquagait.body.meshes import link_meshes

# Every primitive once, turned and moved off the link origin, in a turned link.
PRIMITIVES = """<mujoco><default><geom density="1000"/></default>
  <worldbody><body name="b" pos=".1 .2 .3" euler="10 20 30"><freejoint/>
    <geom type="box" size=".02 .03 .04" pos=".1 0 0" euler="0 30 0"/>
    <geom type="sphere" size=".03" pos="-.1 0 0" rgba="0 1 0 1"/>
    <geom type="ellipsoid" size=".03 .02 .01" pos="0 .1 0" euler="20 0 0"/>
    <geom type="capsule" size=".02 .03" pos="0 -.1 0" euler="0 0 40"/>
    <geom type="cylinder" size=".02 .03" pos="0 0 .1" euler="45 45 0"/>
  </body></worldbody></mujoco>"""


@pytest.fixture(scope="module")
def fish():
    return ag.creatures.get("fish").model


def test_primitive_meshes_are_closed_outward_surfaces_of_the_geoms_volume():
    model = ag.load_model(PRIMITIVES)
    (mesh,) = link_meshes(model)
    a, b, c = (mesh.vertices[mesh.triangles[:, i]] for i in range(3))
    face_normals = np.cross(b - a, c - a)
    # divergence theorem: a closed surface wound outward encloses a positive volume; an
    # inscribed 32-gon keeps cos(pi/32)^2 > 99 % of a round section, a polar lattice of 17
    # rows about as much again, so the volume is within 3 % of the geoms' own
    volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6
    assert volume == pytest.approx(link_volumes(model)[0], rel=0.03)
    assert volume < link_volumes(model)[0]  # inscribed: never more
    # each vertex normal leans the way its triangles face (winding and normals agree)
    corner_normals = mesh.normals[mesh.triangles]
    assert (np.einsum("tj,tkj->tk", face_normals, corner_normals) >= -1e-12).all()
    assert np.allclose(np.linalg.norm(mesh.normals, axis=1), 1)


def test_link_meshes_carry_the_geoms_colours_and_mujocos_grey_by_default():
    (mesh,) = link_meshes(ag.load_model(PRIMITIVES))
    colours = {tuple(np.round(c, 3)) for c in mesh.colours}
    assert colours == {(0.0, 1.0, 0.0, 1.0), (0.5, 0.5, 0.5, 1.0)}


def test_link_meshes_are_in_the_link_frame(fish):
    """Placed at the reference poses, each link's mesh covers that link's geom points."""
    facts = describe(fish.mj)
    links, points = geom_points(fish, world=True)
    for k, mesh in enumerate(link_meshes(fish)):
        world = facts.link_pos[k] + mesh.vertices @ facts.link_rot[k].T
        ours = points[links == k]
        assert np.allclose(world.min(0), ours.min(0), atol=1e-9)
        assert np.allclose(world.max(0), ours.max(0), atol=1e-9)


def test_a_link_with_visual_geoms_is_drawn_by_them_and_the_others_by_their_shape():
    """A massless red ball beside a massive box: the body is drawn as the ball alone
    (``visual=True``), or as the box the water sees (``visual=False``); the tail, which
    has no look, the same either way."""
    xml = """<mujoco><worldbody><body name="body" euler="0 0 30"><freejoint/>
      <geom type="box" size=".05 .03 .02"/>
      <geom name="ball" type="sphere" size=".04" pos=".08 0 0" density="0" rgba="1 0 0 1"/>
      <body name="tail" pos="-.05 0 0"><joint type="hinge" axis="0 0 1"/>
        <geom type="box" size=".03 .004 .015" pos="-.03 0 0"/></body>
    </body></worldbody></mujoco>"""
    model = ag.load_model(xml)
    drawn, shape = link_meshes(model), link_meshes(model, visual=False)
    # the ball, in the body's frame: every vertex on its sphere, all of it red
    radius = np.linalg.norm(drawn[0].vertices - [0.08, 0, 0], axis=1)
    np.testing.assert_allclose(radius, 0.04, rtol=1e-12)
    np.testing.assert_allclose(drawn[0].colours, [[1, 0, 0, 1]] * len(radius))
    # the fluid's picture: the box's corners, in grey
    np.testing.assert_allclose(np.abs(shape[0].vertices), [[0.05, 0.03, 0.02]] * 24)
    for a, b in zip(drawn[1:], shape[1:], strict=True):
        np.testing.assert_array_equal(a.vertices, b.vertices)
