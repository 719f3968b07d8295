"""Cell classification and the padded layout the pressure kernels work in.

The pressure kernels see every grid, 2D or 3D, as a 3D array with one ghost
layer around it (``padded_shape``). Ghost cells stand for the open boundary:
they hold ``p = 0`` for ever (Dirichlet, DESIGN.md §2.1). Solid cells hold
``p = 0`` too and have no unknown. Because both are zero, the Laplacian of a
fluid cell is ``diag * p - (sum of the six neighbours)`` with no branches,
where ``diag`` counts the neighbours that are not solid (ghosts included).

A 2D grid of ``(nx, ny)`` cells becomes ``(nx + 2, ny + 2, 1)``: no ghosts along z.
"""

from __future__ import annotations

import numba
import numpy as np


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


def pad(field: np.ndarray) -> np.ndarray:
    """Copy a cell field into a new zero-ghosted padded array."""
    out = np.zeros(padded_shape(field.shape))
    interior(out, field.ndim)[...] = field
    return out


def seal_pockets(solid: np.ndarray) -> np.ndarray:
    """Treat fluid that cannot reach the open boundary as solid.

    Fluid enclosed by solid cells has no Dirichlet neighbour, so its block of
    the Laplacian is singular (DESIGN.md §2.3): such pockets move with the body.

    Args:
        solid: boolean cell mask, ``grid.shape``.
    Returns:
        a new mask, ``solid`` plus every enclosed fluid cell.
    """
    solid3 = solid.reshape(solid.shape + (1,) * (3 - solid.ndim)).astype(np.bool_)
    reached = np.zeros(solid3.shape, dtype=np.bool_)
    _flood_from_boundary(solid3, reached)
    return ~reached.reshape(solid.shape)


@numba.njit(cache=True)
def _flood_from_boundary(solid, reached):
    nx, ny, nz = solid.shape
    stack = np.empty((nx * ny * nz, 3), dtype=np.int64)
    top = 0
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                on_border = i == 0 or j == 0 or i == nx - 1 or j == ny - 1
                if nz > 1:
                    on_border = on_border or k == 0 or k == nz - 1
                if on_border and not solid[i, j, k]:
                    reached[i, j, k] = True
                    stack[top] = (i, j, k)
                    top += 1
    offsets = ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1))
    while top > 0:
        top -= 1
        i, j, k = stack[top]
        for di, dj, dk in offsets:
            a, b, c = i + di, j + dj, k + dk
            if 0 <= a < nx and 0 <= b < ny and 0 <= c < nz:
                if not solid[a, b, c] and not reached[a, b, c]:
                    reached[a, b, c] = True
                    stack[top] = (a, b, c)
                    top += 1
