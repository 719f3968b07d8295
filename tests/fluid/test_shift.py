"""Shifting the grid by whole cells: the fluid stays where it is in the world."""

import numpy as np
import pytest

from aquagait.fluid.shift import recentre_offset, shift, shift_field
from aquagait.grid import Grid


@pytest.mark.parametrize("shape, cells", [((12, 8), (3, -2)), ((8, 6, 5), (-1, 2, 4))])
def test_shifted_field_equals_the_original_moved(shape, cells):
    grid = Grid(shape, 0.1, origin=(0.5,) * len(shape))
    rng = np.random.default_rng(0)
    u = tuple(rng.standard_normal(grid.face_shape(a)) for a in range(grid.dim))
    p = rng.standard_normal(shape)
    moved, v, q = shift(grid, u, cells, p)
    assert moved.origin == pytest.approx(tuple(0.5 + 0.1 * c for c in cells))
    for a in range(grid.dim):
        # the same world point has the same value: compare at face centres
        old_points = np.stack(grid.face_centers(a), -1).reshape(-1, grid.dim)
        old_values = dict(zip(map(tuple, np.round(old_points, 9)), u[a].ravel(), strict=True))
        new_points = np.stack(moved.face_centers(a), -1).reshape(-1, grid.dim)
        for point, value in zip(map(tuple, np.round(new_points, 9)), v[a].ravel(), strict=True):
            assert value == old_values.get(point, 0.0)  # entering faces hold still fluid
    kept = tuple(slice(max(-c, 0), n - max(c, 0)) for n, c in zip(shape, cells, strict=True))
    src = tuple(slice(max(c, 0), n + min(c, 0)) for n, c in zip(shape, cells, strict=True))
    assert np.array_equal(q[kept], p[src])
    assert np.count_nonzero(q) == q[kept].size


def test_shift_by_more_than_the_grid_leaves_still_fluid():
    field = np.ones((4, 4))
    assert not shift_field(field, (5, 0)).any()


def test_recentre_only_near_a_wall():
    grid = Grid((20, 10), 0.1)
    assert recentre_offset(grid, (1.0, 0.5), margin=0.3) == (0, 0)
    assert recentre_offset(grid, (1.8, 0.5), margin=0.3) == (8, 0)


def test_shift_checks_its_fields():
    grid = Grid((8, 8), 0.1)
    with pytest.raises(ValueError, match="cell field 0 has shape"):
        shift(grid, grid.zeros_velocity(), (1, 0), np.zeros((3, 3)))
