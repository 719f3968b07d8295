"""Move the fluid grid by whole cells, so the grid follows the swimmer (paper §6).

Shifting by whole cells moves no value between sample points, so it adds no
numerical diffusion: every kept value is copied exactly, and the cells that
enter the grid hold still fluid. Growing the grid (``regrid`` to a larger
shape) is the same copy into a larger window: the cells added hold still
fluid, which is what the open boundary already assumed beyond the old walls.
"""

from __future__ import annotations

import numpy as np

from aquagait.grid import Grid, Velocity


def shift_field(field: np.ndarray, cells, fill: float = 0.0, shape=None) -> np.ndarray:
    """Move the window over a field by ``cells``: ``out[i] = field[i + cells]``.

    Args:
        field: any array on the grid (a face component or a cell field).
        cells: whole cells along each axis; positive moves the window toward +axis.
        fill: value of the entries that enter the window.
        shape: the window's array shape; default the field's own.
    """
    out = np.full(field.shape if shape is None else tuple(shape), fill, dtype=field.dtype)
    src, dst = [], []
    for n, m, c in zip(field.shape, out.shape, cells, strict=True):
        lo, hi = max(c, 0), min(n, m + c)  # the field's entries that land in the window
        if hi <= lo:
            return out
        src.append(slice(lo, hi))
        dst.append(slice(lo - c, hi - c))
    out[tuple(dst)] = field[tuple(src)]
    return out


def shift(grid: Grid, velocity: Velocity, cells, *cell_fields: np.ndarray):
    """Move the grid by whole cells, keeping the fluid where it is in the world.

    Args:
        grid: the current grid.
        velocity: face velocities on it [m/s].
        cells: whole cells to move along each axis (e.g. ``(3, 0)``: 3 cells toward +x).
        cell_fields: other cell-centred fields to carry along (pressure, dye).
    Returns:
        ``(new_grid, new_velocity, *new_cell_fields)``; cells that enter hold
        still fluid (zero velocity) and zero in the other fields.
    """
    return regrid(grid, velocity, cells, grid.shape, *cell_fields)


def regrid(grid: Grid, velocity: Velocity, cells, shape, *cell_fields: np.ndarray):
    """A grid of ``shape`` cells whose lower corner lies ``cells`` whole cells from this
    one's, holding the fluid where it is in the world (``shift`` keeps the shape).

    Returns:
        ``(new_grid, new_velocity, *new_cell_fields)`` as ``shift``: cells outside the
        old grid hold still fluid and zero in the other fields.
    """
    grid.check_velocity(velocity)
    cells = tuple(int(c) for c in cells)
    moved = Grid(tuple(shape), grid.cell_size, grid.shifted(cells).origin)
    for i, f in enumerate(cell_fields):
        grid.check_cells(f, f"cell field {i}")
    return (
        moved,
        tuple(shift_field(c, cells, shape=moved.face_shape(a)) for a, c in enumerate(velocity)),
        *(shift_field(f, cells, shape=moved.shape) for f in cell_fields),
    )


def recentre_offset(grid: Grid, point, margin: float) -> tuple[int, ...]:
    """Whole cells to shift so that ``point`` sits at the grid's centre again.

    Returns zeros while ``point`` stays at least ``margin`` [m] inside every
    wall: the grid moves only when the swimmer nears one.
    """
    point = np.asarray(point, dtype=float)
    lo = np.asarray(grid.origin)
    hi = lo + np.asarray(grid.extent)
    if np.all(point - lo >= margin) and np.all(hi - point >= margin):
        return (0,) * grid.dim
    centre = lo + 0.5 * np.asarray(grid.extent)
    return tuple(int(c) for c in np.round((point - centre) / grid.cell_size))
