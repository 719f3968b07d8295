"""MAC grid geometry: coordinates, shapes, CFL, sealed pockets, and the errors bad input gets."""

import numpy as np
import pytest

from aquagait.grid import CFLError, Grid, sealed


def test_face_and_cell_coordinates_are_staggered():
    grid = Grid((4, 3), 0.5, origin=(1.0, -2.0))
    x, y = grid.cell_centers()
    assert x.shape == (4, 3)
    assert x[0, 0] == pytest.approx(1.25) and y[0, 0] == pytest.approx(-1.75)
    fx, fy = grid.face_centers(0)
    assert fx.shape == grid.face_shape(0) == (5, 3)
    assert fx[0, 0] == pytest.approx(1.0) and fy[0, 0] == pytest.approx(-1.75)
    fx, fy = grid.face_centers(1)
    assert fy[0, 0] == pytest.approx(-2.0) and fx[0, 0] == pytest.approx(1.25)


def test_3d_grid_shapes_and_extent():
    grid = Grid((8, 4, 2), 0.1)
    assert grid.dim == 3
    assert [c.shape for c in grid.zeros_velocity()] == [(9, 4, 2), (8, 5, 2), (8, 4, 3)]
    assert grid.extent == pytest.approx((0.8, 0.4, 0.2))
    assert grid.cell_volume == pytest.approx(1e-3)


def test_cfl_time_step_moves_fastest_fluid_one_cell():
    grid = Grid((8, 8), 0.1)
    u, v = grid.zeros_velocity()
    u[3, 3] = 2.0
    v[1, 1] = -4.0
    assert grid.cfl_dt((u, v)) == pytest.approx(0.1 / 4.0)
    assert grid.cfl_dt(grid.zeros_velocity(), max_dt=0.5) == 0.5


def test_ball_marks_cells_inside():
    grid = Grid((10, 10), 1.0)
    mask = grid.ball((5.0, 5.0), 2.0)
    assert mask[4, 4] and mask[5, 5] and not mask[0, 0]
    assert mask.sum() == 12  # centres at half-integers within radius 2 of (5, 5)


def test_shifted_grid_moves_origin_by_whole_cells():
    grid = Grid((4, 4), 0.25, origin=(0.0, 1.0))
    assert grid.shifted((2, -1)).origin == pytest.approx((0.5, 0.75))


@pytest.mark.parametrize(
    "kwargs, fragment",
    [
        (dict(shape=(0, 4), cell_size=0.1), "whole numbers of cells"),
        (dict(shape=(4,), cell_size=0.1), "2 or 3 entries"),
        (dict(shape=(4, 4), cell_size=0.0), "positive length"),
        (dict(shape=(4, 4), cell_size=-1.0), "positive length"),
        (dict(shape=(4, 4), cell_size=0.1, origin=(0.0,)), "one per axis"),
    ],
)
def test_bad_grid_is_refused_with_a_clear_message(kwargs, fragment):
    with pytest.raises(ValueError, match=fragment):
        Grid(**kwargs)


def test_mismatched_velocity_shape_is_named():
    grid = Grid((4, 4), 0.1)
    with pytest.raises(ValueError, match=r"velocity\[1\] has shape \(4, 4\).*need shape \(4, 5\)"):
        grid.check_velocity((np.zeros((5, 4)), np.zeros((4, 4))))
    with pytest.raises(ValueError, match="2 components but the grid is 3D"):
        Grid((4, 4, 4), 0.1).check_velocity(grid.zeros_velocity())


def test_dt_far_beyond_cfl_is_refused_and_says_what_to_use():
    grid = Grid((8, 8), 0.1)
    u, v = grid.zeros_velocity()
    u[:] = 1.0
    grid.check_dt((u, v), 0.3)  # three cells: fine for semi-Lagrangian
    with pytest.raises(CFLError, match=r"use dt <= 0\.1 s"):
        grid.check_dt((u, v), 1.0)
    with pytest.raises(ValueError, match="positive time"):
        grid.check_dt((u, v), -0.1)


def distance(shape, centre: int, norm: str) -> np.ndarray:
    """Integer distance of each cell from cell ``(centre, centre[, centre])``: "max" or "sum"."""
    offsets = np.abs(np.indices(shape) - centre)
    return offsets.max(axis=0) if norm == "max" else offsets.sum(axis=0)


def test_fluid_inside_a_ring_is_sealed_and_a_one_cell_gap_opens_it():
    d = distance((12, 10), 5, "max")  # a square ring of cells 2..8, inside the grid
    solid = d == 3
    np.testing.assert_array_equal(sealed(solid), d < 3)  # a 2D grid has no z border
    solid[5, 2] = False  # a gap of one cell in the wall
    assert not sealed(solid).any()


def test_fluid_inside_a_closed_box_shell_is_sealed_and_a_one_cell_hole_opens_it():
    d = distance((9, 9, 9), 4, "max")  # a cube shell of cells 1..7
    solid = d == 3
    np.testing.assert_array_equal(sealed(solid), d < 3)
    solid[4, 4, 7] = False  # a hole of one cell in the lid
    assert not sealed(solid).any()


@pytest.mark.parametrize("shape", [(11, 11), (11, 11, 11)])
def test_fluid_passes_between_cells_through_faces_not_edges_or_corners(shape):
    # A diamond (octahedron) shell of cells that touch only at edges and corners: a
    # step to a face neighbour changes the |i|+|j|+|k| distance by exactly one, so no
    # face-connected path crosses it; a diagonal step would.
    d = distance(shape, 5, "sum")
    np.testing.assert_array_equal(sealed(d == 3), d < 3)
