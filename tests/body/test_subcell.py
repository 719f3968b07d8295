"""Sub-cell boundaries: water fractions against exact volumes, continuity in the pose,
thin parts, the bookkeeping the coupled system relies on, and sealed pockets."""

import numpy as np
import pytest
from test_voxelize import FRAME, free, planar

import aquagait as ag
from aquagait.body import Dynamics, load_model
from aquagait.body.subcell import WEIGHT_FLOOR, voxelize_fractions, voxelize_subcell
from aquagait.body.voxelize import body_shape
from aquagait.grid import Grid

H = 0.01


def fractions(xml, offset, resolution=16, pose=None, boundary=voxelize_subcell):
    """The body of ``xml`` voxelized on a grid of ``resolution`` cells a side around
    the origin, shifted by ``offset`` (m); returns the grid and the voxels."""
    model = load_model(xml)
    pos, rot = Dynamics(model.mj).link_poses(model.qpos0 if pose is None else pose)
    origin = tuple(-resolution / 2 * H + np.asarray(offset))
    grid = Grid((resolution,) * model.dim, H, origin)
    return grid, boundary(body_shape(model, H), grid, pos, rot)


def solid_volume(grid, voxels, axis):
    """The body's volume as the faces normal to ``axis`` see it: the solid shares of
    the coupled faces plus whole faces between solid cells, times a face's volume."""
    solid = voxels.solid
    widths = [(1, 1) if a == axis else (0, 0) for a in range(grid.dim)]
    padded = np.pad(solid, widths)
    n = solid.shape[axis]
    inside = np.take(padded, range(n + 1), axis=axis) & np.take(padded, range(1, n + 2), axis=axis)
    shares = voxels.face_share[voxels.face_axis == axis].sum()
    return (shares + inside.sum()) * grid.cell_size**grid.dim


SHAPES = [
    pytest.param(planar('<geom type="box" size=".043 .027 .02"/>'), 2, 0.086 * 0.054, id="box-2d"),
    pytest.param(planar('<geom type="cylinder" size=".04 .02"/>'), 2, np.pi * 0.04**2, id="disc"),
    pytest.param(
        free('<geom type="box" size=".043 .027 .031"/>'), 3, 0.086 * 0.054 * 0.062, id="box-3d"
    ),
    pytest.param(free('<geom type="sphere" size=".04"/>'), 3, 4 / 3 * np.pi * 0.04**3, id="sphere"),
]


@pytest.mark.parametrize("xml, dim, volume", SHAPES)
def test_the_faces_of_every_axis_hold_the_body_s_volume(xml, dim, volume):
    """Four cells a radius, random sub-cell offsets: every axis's faces hold the
    exact volume within 0.6% (measured at most 0.51%, the 3D box: its edges and
    corners are where a sample's signed distance stops being a plane's)."""
    rng = np.random.default_rng(7)
    for offset in rng.uniform(0, H, (3, 3)):
        grid, voxels = fractions(xml, offset[:dim])
        for axis in range(grid.dim):
            assert solid_volume(grid, voxels, axis) == pytest.approx(volume, rel=0.006)


def test_a_wall_parallel_to_the_faces_is_cut_exactly():
    """A box face at a random position inside a cell: the faces across it have water
    fraction equal to the share of their control volume outside the box."""
    half = 0.0437
    grid, voxels = fractions(planar(f'<geom type="box" size="{half} .05 .02"/>'), (0.0031, 0.0))
    x_faces = voxels.face_axis == 0
    centre_x = voxels.face_center[x_faces, 0]
    exact = np.clip((np.abs(centre_x) + H / 2 - half) / H, 0, 1)  # the water's share
    along = np.abs(voxels.face_center[x_faces, 1]) < 0.05 - H  # away from the corners
    np.testing.assert_allclose(voxels.face_weight[x_faces][along], exact[along], atol=1e-6)


def test_the_fractions_change_continuously_with_the_pose():
    """Moving the disc by a thousandth of a cell changes no face's fraction by more
    than a few thousandths (the staircase flips whole faces)."""
    xml = planar('<geom type="cylinder" size=".037 .02"/>')
    _, before = fractions(xml, (0.0, 0.0))
    _, after = fractions(xml, (1e-3 * H, 0.5e-3 * H))

    def table(v):
        rows = zip(v.face_axis, v.face_index, v.face_weight, strict=True)
        return {(int(a), *map(int, i)): w for a, i, w in rows}

    a, b = table(before), table(after)
    change = max(abs(a.get(key, 1.0) - b.get(key, 1.0)) for key in set(a) | set(b))
    assert 0 < change < 5e-3


PLATE = planar('<geom type="box" size=".0015 .05 .02"/>')
"""A plate 0.3 cells thick across x, 10 cells tall."""


def test_water_fractions_alone_block_a_thin_plate_in_proportion_to_its_thickness():
    """Without the closure, no cell is solid, and every row of x faces through the
    plate is partly closed, by 0.3 faces in all (its volume) within 5%: the
    water passes through the rest."""
    grid, voxels = fractions(PLATE, (0.0012, 0.0), boundary=voxelize_fractions)
    assert not voxels.solid.any()
    x_faces = voxels.face_axis == 0
    rows = voxels.face_index[x_faces, 1]
    middle = np.abs(voxels.face_center[x_faces, 1]) < 0.05 - H
    for row in np.unique(rows[middle]):
        closed = voxels.face_share[x_faces][rows == row].sum()
        assert closed == pytest.approx(0.3, rel=0.05)


def test_a_thin_plate_closes_one_whole_face_in_every_row():
    """With the closure, every row of x faces through the same plate has one face
    with no water, all of it the plate's, and the other faces of the row open."""
    grid, voxels = fractions(PLATE, (0.0012, 0.0))
    x_faces = voxels.face_axis == 0
    rows = voxels.face_index[x_faces, 1]
    middle = np.abs(voxels.face_center[x_faces, 1]) < 0.05 - H
    for row in np.unique(rows[middle]):
        weight = voxels.face_weight[x_faces][rows == row]
        assert np.count_nonzero(weight == 0) == 1
        assert voxels.face_share[x_faces][rows == row][weight == 0].sum() == pytest.approx(1.0)


def test_bookkeeping_of_a_bent_body(snake, snake_dynamics):
    """Solid cells have no open face and an owner; every coupled face touches water;
    the links' shares of a face add up to its solid part; the sides are the cells
    with water beside each face."""
    rng = np.random.default_rng(3)
    bend = rng.normal(size=snake.nv)
    bend[:6] = 0
    q = snake_dynamics.integrate(snake.qpos0, bend, 0.5)
    pos, rot = snake_dynamics.link_poses(q)
    h = 0.012
    grid = Grid((40, 40, 40), h, tuple(pos.mean(axis=0) - 20 * h))
    voxels = voxelize_subcell(body_shape(snake, h), grid, pos, rot)
    assert (voxels.owner[voxels.solid] >= 0).all()
    assert set(np.unique(voxels.face_link)) == set(range(len(snake.links)))
    key = np.column_stack([voxels.face_axis, voxels.face_index])
    faces, inverse = np.unique(key, axis=0, return_inverse=True)
    shares = np.bincount(inverse.ravel(), weights=voxels.face_share)
    weight = np.zeros(len(faces))
    weight[inverse.ravel()] = voxels.face_weight
    np.testing.assert_allclose(shares, 1 - weight, atol=1e-12)
    assert (weight < 1).all() and ((weight == 0) | (weight >= WEIGHT_FLOOR)).all()
    face, cells, signs = voxels.sides()
    assert set(face) == set(range(voxels.face_count))  # water on at least one side
    assert not voxels.solid[tuple(cells.T)].any()
    step = np.eye(3, dtype=int)[voxels.face_axis[face]]
    np.testing.assert_array_equal(cells + (signs < 0)[:, None] * step, voxels.face_index[face])


def test_water_enclosed_by_a_frame_of_links_is_sealed_and_owned():
    model = load_model(FRAME)
    grid = Grid((40, 40), 0.004, (-0.0801, -0.0797))
    pos, rot = Dynamics(model.mj).link_poses(model.qpos0)
    voxels = voxelize_subcell(body_shape(model, 0.004), grid, pos, rot)
    x, y = grid.cell_centers()
    hollow = (np.abs(x) < 0.04) & (np.abs(y) < 0.04)
    assert voxels.solid[hollow].all() and (voxels.owner[hollow] >= 0).all()
    assert not hollow[tuple(voxels.sides()[1].T)].any()  # no coupled face inside


def test_no_body_in_the_grid_gives_no_solid_and_no_faces():
    model = load_model(planar('<geom type="cylinder" size=".04 .02"/>'))
    grid = Grid((16, 8), 0.01, (5.0, 5.0))
    pos, rot = Dynamics(model.mj).link_poses(model.qpos0)
    voxels = voxelize_subcell(body_shape(model, 0.01), grid, pos, rot)
    assert not voxels.solid.any() and voxels.face_count == 0
    assert voxels.face_index.shape == (0, 2) and voxels.face_center.shape == (0, 3)


def test_a_body_symmetric_about_its_swim_plane_gets_mirror_symmetric_fractions():
    """The fish is symmetric top to bottom, and its joints bend it in the x-y plane; on a
    grid whose mid-plane is the fish's, the faces' water fractions must mirror to round-off
    at any bent pose. The signed distance was sampled from its box's lower corner, and the
    lattice overhung the top by part of a spacing: the fractions differed by up to 0.4%,
    enough for the fish to pitch 14 degrees over 20 s of a straight swim."""
    fish = ag.creatures.get("fish")
    scene = ag.make_scene(fish, fluid="euler")
    grid = scene.grid
    pose = fish.model.qpos0.copy()
    pose[-3:] = 0.3, -0.4, 0.5  # the three joints, about z
    voxels = voxelize_subcell(scene.shape, grid, *scene.dynamics.link_poses(pose))
    weight = [np.ones(grid.face_shape(a)) for a in range(3)]
    faces = zip(voxels.face_axis, voxels.face_index, voxels.face_weight, strict=True)
    for a, index, w in faces:
        weight[a][tuple(index)] = min(weight[a][tuple(index)], w)
    assert voxels.face_count > 1000
    for a in range(3):
        np.testing.assert_allclose(weight[a], weight[a][:, :, ::-1], atol=1e-12)
    np.testing.assert_array_equal(voxels.solid, voxels.solid[:, :, ::-1])
