"""Surface patches: areas against exact shapes, outward normals, 2D side walls, buried joint
faces, the creatures' total surface, and moving the patches with the links."""

import pickle

import numpy as np
import pytest
from scipy.spatial import ConvexHull
from scipy.special import ellipeinc, ellipkinc

import aquagait as ag
from aquagait.body import Dynamics, load_model
from aquagait.body.dynamics import describe
from aquagait.body.surface import AREA_TOLERANCE, body_surface, surface_world

DEPTH = 0.04
# each body sits off the origin and turned, so the link frame is not the world frame
POSE = 'pos=".3 -.2 .1" euler="20 -35 50"'


def free(geom: str, asset: str = "") -> str:
    """A 3D model: one free link holding ``geom``, placed at ``POSE``."""
    return f"""<mujoco><asset>{asset}</asset><default><geom density="1000"/></default>
      <worldbody><body name="root" {POSE}><freejoint/>{geom}</body></worldbody></mujoco>"""


def planar(inner: str) -> str:
    """A planar (2D) model whose root link holds ``inner``."""
    return f"""<mujoco><custom><numeric name="aquagait_depth" data="{DEPTH}"/></custom>
      <default><geom density="1000"/></default>
      <worldbody><body name="root" pos=".1 .2 0">
        <joint type="slide" axis="1 0 0"/><joint type="slide" axis="0 1 0"/>
        <joint type="hinge" axis="0 0 1" range="-90 90"/>{inner}</body></worldbody></mujoco>"""


def ellipsoid_area(a: float, b: float, c: float) -> float:
    """Exact surface area of an ellipsoid (Legendre's formula, a >= b >= c)."""
    a, b, c = sorted((a, b, c), reverse=True)
    phi = np.arccos(c / a)
    m = a**2 * (b**2 - c**2) / (b**2 * (a**2 - c**2))
    e, f = ellipeinc(phi, m), ellipkinc(phi, m)
    return 2 * np.pi * c**2 + 2 * np.pi * a * b / np.sin(phi) * (
        e * np.sin(phi) ** 2 + f * np.cos(phi) ** 2
    )


BOX = (0.05, 0.02, 0.01)
BOX_AREA = 8 * (BOX[0] * BOX[1] + BOX[1] * BOX[2] + BOX[2] * BOX[0])
MESH_BOX = " ".join(f"{x * BOX[0]} {y * BOX[1]} {z * BOX[2]}"
                    for x in (-1, 1) for y in (-1, 1) for z in (-1, 1))  # fmt: skip
R, HALF = 0.02, 0.05  # capsule and cylinder radius and half length [m]
CASES = {
    "box": ('<geom type="box" size="{} {} {}"/>'.format(*BOX), BOX_AREA),
    "sphere": ('<geom type="sphere" size=".03"/>', 4 * np.pi * 0.03**2),
    "capsule": (
        f'<geom type="capsule" size="{R} {HALF}"/>',
        4 * np.pi * R**2 + 4 * np.pi * R * HALF,
    ),
    "cylinder": (
        f'<geom type="cylinder" size="{R} {HALF}"/>',
        2 * np.pi * R**2 + 4 * np.pi * R * HALF,
    ),
    "ellipsoid": ('<geom type="ellipsoid" size=".06 .03 .02"/>', ellipsoid_area(0.06, 0.03, 0.02)),
    "mesh box": ('<geom type="mesh" mesh="b"/>', BOX_AREA),
}


def case_model(name: str):
    geom, _ = CASES[name]
    asset = f'<mesh name="b" vertex="{MESH_BOX}"/>' if name == "mesh box" else ""
    return load_model(free(geom, asset))


@pytest.mark.parametrize("name", list(CASES))
@pytest.mark.parametrize("resolution", [0.02, 0.004])
def test_areas_sum_to_the_exact_surface_area(name, resolution):
    surface = body_surface(case_model(name), resolution)
    exact = CASES[name][1]
    assert abs(surface.area.sum() - exact) <= AREA_TOLERANCE * exact
    assert np.all(surface.area > 0)


@pytest.mark.parametrize("name", list(CASES))
def test_normals_are_unit_and_point_out(name):
    model = case_model(name)
    surface = body_surface(model, 0.005)
    facts = describe(model.mj)
    centre, normal = surface_world(surface, facts.link_pos, facts.link_rot)
    np.testing.assert_allclose(np.linalg.norm(normal, axis=1), 1, atol=1e-12)
    outward = np.einsum("mi,mi->m", centre - facts.geom_pos[0], normal)
    assert np.all(outward > 0)  # every case is convex and holds its own centre


@pytest.mark.parametrize("name", ["sphere", "ellipsoid", "capsule", "box"])
def test_patches_lie_on_the_geom_in_the_world(name):
    """At qpos0 the link-frame patches, moved by the link's pose, sit on the world geom."""
    model = case_model(name)
    facts = describe(model.mj)
    centre, normal = surface_world(body_surface(model, 0.005), facts.link_pos, facts.link_rot)
    local = (centre - facts.geom_pos[0]) @ facts.geom_rot[0]  # in the geom's frame
    local_normal = normal @ facts.geom_rot[0]
    size = facts.geom_size[0]
    if name == "sphere":
        np.testing.assert_allclose(np.linalg.norm(local, axis=1), size[0], rtol=1e-12)
        np.testing.assert_allclose(local_normal, local / size[0], atol=1e-12)
    elif name == "ellipsoid":
        np.testing.assert_allclose(np.sum((local / size) ** 2, axis=1), 1, rtol=1e-12)
        gradient = local / size**2
        gradient /= np.linalg.norm(gradient, axis=1, keepdims=True)
        np.testing.assert_allclose(local_normal, gradient, atol=1e-12)
    elif name == "capsule":
        axis = np.clip(local[:, 2], -size[1], size[1])
        off_axis = local - np.outer(axis, [0, 0, 1])
        np.testing.assert_allclose(np.linalg.norm(off_axis, axis=1), size[0], rtol=1e-12)
    else:
        on_face = np.isclose(np.abs(local), size[:3], rtol=1e-12).sum(axis=1)
        assert np.all(on_face == 1)
        np.testing.assert_allclose(np.abs(local_normal).max(axis=1), 1, atol=1e-12)


def test_patches_are_no_larger_than_the_resolution():
    surface = body_surface(case_model("box"), 0.004)
    assert surface.area.max() <= 0.004**2 * (1 + 1e-12)
    assert surface.size == 2 * (25 * 10 + 10 * 5 + 5 * 25)  # ceil(2 * half / 0.004) per side


def test_planar_prisms_are_their_side_walls():
    """2D: patches on z = 0 with normals in the plane; area = perimeter x depth; no end caps."""
    model = load_model(
        planar('<geom type="box" size=".05 .01 .02" euler="0 0 30"/>'
               '<geom type="cylinder" size=".015 .02" pos=".09 0 0"/>')
    )  # fmt: skip
    surface = body_surface(model, 0.002)
    assert surface.dim == 2
    np.testing.assert_array_equal(surface.centre[:, 2], 0)
    np.testing.assert_array_equal(surface.normal[:, 2], 0)
    box = surface.geom == 0
    np.testing.assert_allclose(surface.area[box].sum(), 2 * (0.1 + 0.02) * DEPTH, rtol=1e-12)
    np.testing.assert_allclose(surface.area[~box].sum(), 2 * np.pi * 0.015 * DEPTH, rtol=1e-12)
    facts = describe(model.mj)
    centre, normal = surface_world(surface, facts.link_pos, facts.link_rot)
    for g in (0, 1):
        rows = surface.geom == g
        outward = np.einsum("mi,mi->m", centre[rows] - facts.geom_pos[g], normal[rows])
        assert np.all(outward > 0)


def test_planar_mesh_side_walls_match_its_polygon():
    creature = ag.creatures.get("eel2d")
    model = creature.model
    surface = body_surface(model, keep_buried=True)
    facts = describe(model.mj)
    for g in range(len(facts.geom_kind)):
        vertices = facts.geom_vertices[g]
        perimeter = ConvexHull(vertices[vertices[:, 2] < 0][:, :2]).area  # 2D: its perimeter
        rows = surface.geom == g
        np.testing.assert_allclose(surface.area[rows].sum(), perimeter * DEPTH, rtol=1e-12)


def test_the_joint_faces_of_the_eel_are_buried():
    """Where two links meet, both end faces are inside the other and dropped."""
    model = ag.creatures.get("eel2d").model
    every, exposed = body_surface(model, keep_buried=True), body_surface(model)
    joint_faces = 2 * (0.035 + 0.035 + 0.02534 + 0.01566) * DEPTH  # widths at the 4 joints
    np.testing.assert_allclose(every.area.sum() - exposed.area.sum(), joint_faces, rtol=1e-3)


def test_the_fish_surface_is_its_hulls():
    model = ag.creatures.get("fish").model
    surface = body_surface(model, keep_buried=True)
    facts = describe(model.mj)
    hulls = sum(ConvexHull(v).area for v in facts.geom_vertices)
    np.testing.assert_allclose(surface.area.sum(), hulls, rtol=1e-12)
    exposed = body_surface(model)
    assert 0.7 * hulls < exposed.area.sum() < hulls  # the three joint rings are dropped
    assert set(np.unique(exposed.link)) == {0, 1, 2, 3}


def test_patches_move_with_their_links():
    """At a bent pose, the patches keep their place on their own link."""
    model = ag.creatures.get("fish").model
    dynamics = Dynamics(model.mj)
    surface = body_surface(model)
    q = model.qpos0.copy()
    q[7:] = [0.2, -0.3, 0.4]
    q[3:7] = [np.cos(0.3), 0, np.sin(0.3), 0]
    pos, rot = dynamics.link_poses(q)
    centre, normal = surface_world(surface, pos, rot)
    back = np.einsum("mji,mj->mi", rot[surface.link], centre - pos[surface.link])
    np.testing.assert_allclose(back, surface.centre, atol=1e-14)
    np.testing.assert_allclose(np.linalg.norm(normal, axis=1), 1, atol=1e-12)


def test_surface_pickles_and_checks_its_resolution():
    model = case_model("capsule")
    surface = body_surface(model, 0.01)
    again = pickle.loads(pickle.dumps(surface))
    np.testing.assert_array_equal(again.centre, surface.centre)
    with pytest.raises(ValueError, match="resolution must be a positive length"):
        body_surface(model, 0.0)
