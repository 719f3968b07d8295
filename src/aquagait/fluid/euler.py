"""One step of the incompressible Euler equations around static solids (paper §3.1).

    u*      = advect(u^n)                      BFECC, semi-Lagrangian underneath
    u^{n+1} = project(u*)                      pressure makes it divergence free

This is the fluid alone; ``coupling`` and ``sim`` replace the projection with
the simultaneous fluid-body solve. Schemes are passed in as functions.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aquagait.fluid.advection import advect_velocity, bfecc
from aquagait.fluid.pcg import PressureSystem, pressure_system
from aquagait.fluid.projection import DEFAULT_TOLERANCE, WATER_DENSITY, Projection, project
from aquagait.grid import Grid, Velocity


@dataclass(frozen=True)
class Obstacles:
    """Static solids in the flow: fixed for a run, so their pressure system is built once.

    Attributes:
        solid: boolean cell mask, ``grid.shape``.
        velocity: face velocities of the solids [m/s], or None for solids at rest.
        system: the pressure operator for ``solid`` (enclosed fluid sealed).
    """

    solid: np.ndarray
    velocity: Velocity | None
    system: PressureSystem

    @classmethod
    def at_rest(cls, grid: Grid, solid: np.ndarray | None = None) -> Obstacles:
        """Solids that do not move; ``None`` means open water."""
        solid = grid.zeros_cells(bool) if solid is None else np.asarray(solid, dtype=bool)
        grid.check_cells(solid, "solid")
        return cls(solid, None, pressure_system(solid))


def step(
    grid: Grid,
    velocity: Velocity,
    dt: float,
    obstacles: Obstacles | None = None,
    pressure: np.ndarray | None = None,
    density: float = WATER_DENSITY,
    tol: float = DEFAULT_TOLERANCE,
    scheme=bfecc,
) -> Projection:
    """Advance the fluid by ``dt``: advect, then project.

    Args:
        grid: the MAC grid.
        velocity: face velocities at the start of the step [m/s].
        dt: time step [s]; refused if it moves fluid far more than a cell.
        obstacles: static solids, or None for open water.
        pressure: last step's pressure, a warm start for the solve [Pa].
        density: fluid density [kg/m^3].
        tol: projection tolerance, ``max |h div u| / U``.
        scheme: the advection scheme (``bfecc`` or ``semi_lagrangian``).
    Returns:
        the new velocity, its pressure and solver statistics.
    """
    grid.check_dt(velocity, dt)
    obstacles = obstacles or Obstacles.at_rest(grid)
    advected = advect_velocity(grid, velocity, dt, scheme=scheme)
    return project(
        grid, advected, dt, solid_velocity=obstacles.velocity, density=density,
        pressure=pressure, tol=tol, system=obstacles.system,
    )  # fmt: skip
