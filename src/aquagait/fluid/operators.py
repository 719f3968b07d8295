"""Discrete operators and diagnostics on the MAC grid: divergence, vorticity, energy.

These are NumPy, not kernels: they run once per frame for diagnostics and
pictures, not inside the solver's inner loops.
"""

from __future__ import annotations

import numpy as np

from aquagait.grid import Grid, Velocity


def net_outflow(grid: Grid, velocity: Velocity) -> np.ndarray:
    """``D u``: each cell's net outflow through its faces per unit face area.

    Args:
        grid: the MAC grid.
        velocity: face velocities [m/s].
    Returns:
        ``grid.shape`` array [m/s]; ``divergence = net_outflow / h``.
    """
    grid.check_velocity(velocity)
    out = np.zeros(grid.shape)
    for axis, comp in enumerate(velocity):
        out += np.diff(comp, axis=axis)
    return out


def divergence(grid: Grid, velocity: Velocity) -> np.ndarray:
    """Velocity divergence at cell centres, ``grid.shape`` [1/s]."""
    return net_outflow(grid, velocity) / grid.cell_size


def cell_centered(grid: Grid, velocity: Velocity) -> np.ndarray:
    """Face velocities averaged to cell centres, shape ``(dim, *grid.shape)`` [m/s]."""
    grid.check_velocity(velocity)
    return np.stack(
        [
            0.5 * (np.take(c, range(n), axis=a) + np.take(c, range(1, n + 1), axis=a))
            for a, (c, n) in enumerate(zip(velocity, grid.shape, strict=True))
        ]
    )


def vorticity(grid: Grid, velocity: Velocity) -> np.ndarray:
    """Curl of the velocity at cell centres: ``curl`` of the cell-centred velocity.

    Returns:
        2D: the scalar ``dv/dx - du/dy``, shape ``grid.shape`` [1/s]
        (positive is counter-clockwise). 3D: the vector, shape ``(3, *grid.shape)``.
    """
    return curl(cell_centered(grid, velocity), grid.cell_size)


def curl(centred: np.ndarray, cell_size: float) -> np.ndarray:
    """Curl of a cell-centred velocity field (the vorticity).

    Central differences (one-sided on the border), second order where the
    field is smooth. Serves the MAC grid (``vorticity``) and recorded planes
    of cell-centred velocity (the pictures) alike.

    Args:
        centred: ``(dim, *shape)`` velocity at cell centres [m/s], dim 2 or 3;
            any float dtype, computed in float64.
        cell_size: ``h`` [m].
    Returns:
        2D: the scalar ``dv/dx - du/dy``, shape ``shape`` [1/s] (positive is
        counter-clockwise). 3D: the vector, shape ``(3, *shape)``.
    """
    centred = np.asarray(centred, dtype=np.float64)
    if centred.shape[0] not in (2, 3) or centred.ndim != centred.shape[0] + 1:
        raise ValueError(
            f"centred has shape {centred.shape}; give (2, nx, ny) or (3, nx, ny, nz): "
            f"one cell-centred array per axis"
        )

    def d(component, axis):
        return np.gradient(centred[component], cell_size, axis=axis)

    if centred.shape[0] == 2:
        return d(1, 0) - d(0, 1)
    return np.stack([d(2, 1) - d(1, 2), d(0, 2) - d(2, 0), d(1, 0) - d(0, 1)])


def kinetic_energy(grid: Grid, velocity: Velocity, density: float = 1000.0) -> float:
    """Kinetic energy of the fluid, ``rho/2 sum_faces u^2 h^dim``.

    Returns:
        energy [J] in 3D, energy per metre of depth [J/m] in 2D.
    """
    grid.check_velocity(velocity)
    return 0.5 * density * grid.cell_volume * float(sum(np.sum(c * c) for c in velocity))
