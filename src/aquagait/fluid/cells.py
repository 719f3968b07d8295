"""Cell classification and the padded layout the pressure kernels work in.

The pressure kernels see every grid, 2D or 3D, as a 3D array with one ghost
layer around it (``padded_shape``). Ghost cells stand for the open boundary:
they hold ``p = 0`` for ever (Dirichlet, docs/method-fluid.md). Solid cells
hold ``p = 0`` too and have no unknown. Because both are zero, the Laplacian of a
fluid cell is ``diag * p - (sum of the six neighbours)`` with no branches,
where ``diag`` counts the neighbours that are not solid (ghosts included).

A 2D grid of ``(nx, ny)`` cells becomes ``(nx + 2, ny + 2, 1)``: no ghosts along z.
"""

from __future__ import annotations

import numpy as np

from aquagait.grid import sealed


def padded_shape(shape: tuple[int, ...]) -> tuple[int, int, int]:
    """Shape of the ghost-padded 3D array for a grid of ``shape`` cells."""
    if len(shape) == 2:
        return (shape[0] + 2, shape[1] + 2, 1)
    return (shape[0] + 2, shape[1] + 2, shape[2] + 2)


def interior(padded: np.ndarray, dim: int) -> np.ndarray:
    """View of the real cells of a padded array, in the grid's own shape."""
    if dim == 2:
        return padded[1:-1, 1:-1, 0]
    return padded[1:-1, 1:-1, 1:-1]


def padded_flat(cells: np.ndarray, padded: tuple[int, int, int]) -> np.ndarray:
    """Flat indices into the padded layout of grid cell indices, (n, dim); -1 and the
    grid's size along an axis are the ghosts on either side."""
    cells = np.asarray(cells, dtype=np.int64) + 1
    if cells.shape[1] == 2:
        cells = np.column_stack([cells, np.zeros(len(cells), np.int64)])
    return np.ravel_multi_index(tuple(cells.T), padded)


def pad(field: np.ndarray) -> np.ndarray:
    """Copy a cell field into a new zero-ghosted padded array."""
    out = np.zeros(padded_shape(field.shape))
    interior(out, field.ndim)[...] = field
    return out


def seal_pockets(solid: np.ndarray) -> np.ndarray:
    """Treat fluid that cannot reach the open boundary as solid.

    Fluid enclosed by solid cells has no Dirichlet neighbour, so its block of
    the Laplacian is singular (docs/method-coupling.md): such pockets move
    with the body.

    Args:
        solid: boolean cell mask, ``grid.shape``.
    Returns:
        a new mask, ``solid`` plus every enclosed fluid cell (``grid.sealed``).
    """
    return np.asarray(solid, dtype=np.bool_) | sealed(solid)
