"""Thin parts closed to water: no open path through a plate at any pose or thickness,
thick bodies left to their fractions."""

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from test_voxelize import free, planar

from aquagait.body import Dynamics, load_model
from aquagait.body.subcell import voxelize_fractions, voxelize_subcell
from aquagait.body.voxelize import body_shape
from aquagait.coupling import water_fractions
from aquagait.grid import Grid

H = 0.01


def plate(dim: int, thickness: float, degrees: float) -> str:
    """A plate wider than the grid, ``thickness`` [m], turned about z by ``degrees``."""
    if dim == 2:
        return planar(f'<geom type="box" size=".2 {thickness / 2} .02" euler="0 0 {degrees}"/>')
    return free(
        f'<geom type="box" size=".13 {thickness / 2} .13" euler="{degrees / 2} 0 {degrees}"/>'
    )


def open_components(grid: Grid, voxels) -> np.ndarray:
    """Every cell's label of the cells it reaches through faces with water."""
    weight = water_fractions(grid, voxels)
    index = np.arange(np.prod(grid.shape)).reshape(grid.shape)
    pairs = []
    for axis in range(grid.dim):
        below = [slice(None)] * grid.dim
        above = [slice(None)] * grid.dim
        inner = [slice(None)] * grid.dim
        below[axis], above[axis], inner[axis] = slice(0, -1), slice(1, None), slice(1, -1)
        opened = weight[axis][tuple(inner)] > 0
        pairs.append((index[tuple(below)][opened], index[tuple(above)][opened]))
    rows, cols = (np.concatenate(side) for side in zip(*pairs, strict=True))
    graph = coo_matrix((np.ones(rows.size), (rows, cols)), shape=(index.size,) * 2)
    return connected_components(graph, directed=False)[1].reshape(grid.shape)


def sides_joined(dim, thickness_cells, degrees, offset, boundary, cells=24):
    """Whether water on one side of a plate spanning the grid reaches the other through
    open faces (cells more than a cell from its mid-plane on either side)."""
    model = load_model(plate(dim, thickness_cells * H, degrees))
    pos, rot = Dynamics(model.mj).link_poses(model.qpos0)
    grid = Grid((cells,) * dim, H, tuple(-cells / 2 * H + np.asarray(offset) * H))
    voxels = boundary(body_shape(model, H), grid, pos, rot)
    label = open_components(grid, voxels)
    normal = rot[0] @ model_normal(dim, degrees)
    centres = np.asarray(grid.origin) + (np.indices(grid.shape).reshape(dim, -1).T + 0.5) * H
    side = (centres @ normal[:dim]).reshape(grid.shape) / H
    water = ~voxels.solid
    return bool(set(label[(side > 1) & water]) & set(label[(side < -1) & water]))


def model_normal(dim, degrees):
    """The plate's normal in its link's frame (its thin axis, y, turned with the geom)."""
    z, x = np.radians(degrees), np.radians(degrees / 2)
    turn_z = np.array([[np.cos(z), -np.sin(z), 0], [np.sin(z), np.cos(z), 0], [0, 0, 1]])
    turn_x = np.array([[1, 0, 0], [0, np.cos(x), -np.sin(x)], [0, np.sin(x), np.cos(x)]])
    return (turn_z if dim == 2 else turn_x @ turn_z) @ np.array([0.0, 1.0, 0.0])


def random_poses(count, seed):
    rng = np.random.default_rng(seed)
    return [(rng.uniform(0, 90), rng.uniform(0, 1, 3)) for _ in range(count)]


@pytest.mark.parametrize("thickness", [0.2, 0.3, 0.6, 1.0])
def test_water_cannot_cross_a_plate_thinner_than_a_cell_at_any_pose(thickness):
    """20 random angles and sub-cell offsets in 2D: the two sides never share an open
    path. With water fractions alone, water crosses every plate below a cell
    (checked on the first poses, so this test can tell the two apart)."""
    for degrees, offset in random_poses(20, seed=int(thickness * 10)):
        assert not sides_joined(2, thickness, degrees, offset[:2], voxelize_subcell), (
            f"a {thickness}-cell plate at {degrees:.1f} degrees, offset {offset[:2]} leaks"
        )
    degrees, offset = random_poses(1, seed=int(thickness * 10))[0]
    assert sides_joined(2, thickness, degrees, offset[:2], voxelize_fractions)


@pytest.mark.parametrize("thickness", [0.2, 0.5])
def test_water_cannot_cross_a_thin_plate_in_3d(thickness):
    """Tilted about two axes, four random poses on a 14^3 grid."""
    for degrees, offset in random_poses(4, seed=7):
        assert not sides_joined(3, thickness, degrees, offset, voxelize_subcell, cells=14)
    assert sides_joined(3, thickness, *random_poses(1, seed=7)[0], voxelize_fractions, cells=14)


@pytest.mark.parametrize(
    "xml, dim",
    [
        pytest.param(planar('<geom type="cylinder" size=".04 .02"/>'), 2, id="disc"),
        pytest.param(free('<geom type="sphere" size=".04"/>'), 3, id="sphere"),
        pytest.param(planar('<geom type="box" size=".043 .027 .02" euler="0 0 20"/>'), 2, id="box"),
    ],
)
def test_a_thick_body_keeps_its_water_fractions(xml, dim):
    """Four cells a radius: no face of a disc, a sphere or a turned box is closed by the
    thin-part rule, at several sub-cell offsets."""
    model = load_model(xml)
    pos, rot = Dynamics(model.mj).link_poses(model.qpos0)
    shape = body_shape(model, H)
    for offset in np.random.default_rng(0).uniform(0, 1, (3, dim)):
        grid = Grid((16,) * dim, H, tuple(-8 * H + offset * H))
        closed, fractions = (
            f(shape, grid, pos, rot) for f in (voxelize_subcell, voxelize_fractions)
        )
        np.testing.assert_array_equal(closed.solid, fractions.solid)
        np.testing.assert_array_equal(closed.face_weight, fractions.face_weight)


def test_a_geom_under_one_and_a_half_samples_thick_is_baked_finer():
    """A plate a fifth of a cell thick gets 8 samples a cell (1.6 across), a tenth 16;
    a disc 8 cells across keeps 4; the finest stays within ``MAX_REFINE``."""
    for thickness, refine in ((0.2, 8), (0.1, 16), (0.01, 16)):
        model = load_model(plate(2, thickness * H, 0.0))
        assert round(H / body_shape(model, H).spacing) == refine
    disc = load_model(planar('<geom type="cylinder" size=".04 .02"/>'))
    assert round(H / body_shape(disc, H).spacing) == 4
    assert round(H / body_shape(disc, H, refine=2).spacing) == 2  # as asked
