"""Pressure projection: make a face velocity field divergence free (paper §3.1).

For a static solid with a prescribed velocity (the fluid half of the coupled
step of docs/method-coupling.md, without the body's unknowns): faces that
touch a solid cell take the solid's velocity; every other face, the
open-boundary faces included, is updated by the pressure gradient

    u = u* - dt / (rho h) (p_hi - p_lo),      p = 0 in the ghost cells outside,

and zero net outflow from every fluid cell gives ``L p = -(rho h / dt) D u*``
(``L`` and ``D`` as in ``pcg`` and ``operators``; ``D u`` is outflow per unit
face area). Since the update is ``u = u* + (dt / (rho h)) D^T p`` on the free
faces, the projection is orthogonal there: it never adds kinetic energy when
the solids are at rest.

Tolerance is relative to the flow's speed ``U``: the solve stops when every
fluid cell's ``|h div u| <= tol * U``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from aquagait.fluid.cells import interior, pad
from aquagait.fluid.pcg import PressureSystem, pcg, pressure_system
from aquagait.grid import Grid, Velocity

WATER_DENSITY = 1000.0
"""Density of water [kg/m^3]."""

DEFAULT_TOLERANCE = 1e-6
"""Default ``max |h div u| / U`` after a projection."""


@dataclass(frozen=True)
class Projection:
    """A projected velocity field and what it took.

    Attributes:
        velocity: divergence-free face velocities [m/s].
        pressure: cell pressure, ``grid.shape`` [Pa] (zero in solid cells).
        iterations: CG iterations of the pressure solve.
        max_divergence: largest ``|div u|`` over fluid cells afterwards [1/s].
    """

    velocity: Velocity
    pressure: np.ndarray
    iterations: int
    max_divergence: float


def project(
    grid: Grid,
    velocity: Velocity,
    dt: float,
    solid: np.ndarray | None = None,
    solid_velocity: Velocity | None = None,
    density: float = WATER_DENSITY,
    pressure: np.ndarray | None = None,
    tol: float = DEFAULT_TOLERANCE,
    system: PressureSystem | None = None,
    solve=pcg,
) -> Projection:
    """Project ``velocity`` onto divergence-free fields around static solids.

    Args:
        grid: the MAC grid.
        velocity: face velocities after advection, ``u*`` [m/s].
        dt: the time step the pressure acts over [s].
        solid: boolean cell mask, ``grid.shape``; None for no solids.
        solid_velocity: face velocities of the solids [m/s], read only on faces
            that touch a solid cell; None for solids at rest.
        density: fluid density ``rho`` [kg/m^3].
        pressure: warm start for the solve (the last step's pressure) [Pa].
        tol: stop when ``max |h div u| <= tol * U`` over fluid cells.
        system: a prebuilt ``pressure_system(solid)`` to reuse across steps.
        solve: the linear solver, ``pcg`` by default.
    Returns:
        the projected field, the pressure and solver statistics.
    """
    grid.check_velocity(velocity)
    if not np.isfinite(dt) or dt <= 0:
        raise ValueError(f"dt must be a positive time in seconds, got {dt!r}")
    if not density > 0:
        raise ValueError(f"density must be positive (water: 1000 kg/m^3), got {density!r}")
    if system is None:
        system = pressure_system(grid.zeros_cells(bool) if solid is None else _mask(grid, solid))
    elif system.shape != grid.shape:
        raise ValueError(f"pressure system is for {system.shape} cells, grid has {grid.shape}")
    if solid_velocity is not None:
        grid.check_velocity(solid_velocity, "solid_velocity")
    u = tuple(np.array(c, dtype=float) for c in velocity)
    speed = set_solid_faces_(grid, u, system.solid, solid_velocity)
    if speed == 0.0:
        return Projection(u, grid.zeros_cells(), 0, 0.0)
    scale = density * grid.cell_size / dt
    rhs = -scale * fluid_outflow(grid, u, system.solid)
    result = solve(system, rhs, atol=tol * speed * scale, x0=pressure)
    subtract_gradient_(grid, u, result.x, system.solid, 1.0 / scale)
    max_divergence = float(np.abs(fluid_outflow(grid, u, system.solid)).max()) / grid.cell_size
    return Projection(u, result.x, result.iterations, max_divergence)


def set_solid_faces_(
    grid: Grid, velocity: Velocity, solid: np.ndarray, solid_velocity: Velocity | None = None
) -> float:
    """Give every face that touches a solid cell the solid's velocity, in place.

    Args:
        grid: the MAC grid.
        velocity: face velocities, changed in place [m/s].
        solid: boolean cell mask, ``grid.shape``.
        solid_velocity: the solids' face velocities [m/s]; None for zero.
    Returns:
        the largest ``|u|`` over all faces afterwards [m/s].
    """
    comps = _as_3d(velocity)
    sources = comps if solid_velocity is None else _as_3d(solid_velocity)
    return _fix_solid_faces(comps, sources, solid_velocity is None, _padded(solid), grid.dim)


def fluid_outflow(grid: Grid, velocity: Velocity, solid: np.ndarray) -> np.ndarray:
    """``D u`` of every fluid cell (0 in solid cells), ``grid.shape`` [m/s]."""
    solid_padded = _padded(solid)
    out = np.zeros_like(solid_padded)
    _outflow(_as_3d(velocity), solid_padded, 1.0, out, grid.dim)
    return interior(out, grid.dim).copy()


def subtract_gradient_(
    grid: Grid, velocity: Velocity, pressure: np.ndarray, solid: np.ndarray, factor: float
) -> None:
    """``u -= factor (p_hi - p_lo)`` on faces between two non-solid cells, in place.

    ``p = 0`` outside the grid (open boundary); faces touching a solid keep
    their velocity. With ``factor = dt / (rho h)`` this is the pressure's
    acceleration of the fluid over a step.
    """
    _subtract_gradient(_as_3d(velocity), pad(pressure), _padded(solid), factor, grid.dim)


def _padded(solid: np.ndarray) -> np.ndarray:
    return pad(np.asarray(solid, dtype=float))


def _as_3d(velocity: Velocity) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Views of the components in the 3D kernel layout (a dummy w in 2D)."""
    if len(velocity) == 3:
        return tuple(velocity)
    u, v = velocity
    return (u.reshape(u.shape + (1,)), v.reshape(v.shape + (1,)), np.zeros((1, 1, 1)))


# Kernels. Face index f along axis a lies between cells f - e_a and f; in the
# padded layout (cells.py) those are f + 1 - e_a and f + 1 (x, y; z too in 3D).


@numba.njit(cache=True, nogil=True)
def _fix_solid_faces(comps, solid_comps, at_rest, solid, dim):
    """Set faces touching a solid to the solid's velocity; return the max speed."""
    kz = 1 if dim == 3 else 0
    speed = 0.0
    for a in range(dim):
        c, s = comps[a], solid_comps[a]
        di, dj, dk = a == 0, a == 1, a == 2
        nx, ny, nz = c.shape
        for i in range(nx):
            for j in range(ny):
                for k in range(nz):
                    I, J, K = i + 1, j + 1, k + kz
                    if solid[I, J, K] != 0.0 or solid[I - di, J - dj, K - dk] != 0.0:
                        c[i, j, k] = 0.0 if at_rest else s[i, j, k]
                    speed = max(speed, abs(c[i, j, k]))
    return speed


@numba.njit(cache=True, nogil=True)
def _outflow(comps, solid, factor, out, dim):
    """``out = factor * D u`` at fluid cells of the padded ``out``, 0 at solid ones."""
    u, v, w = comps
    kz = 1 if dim == 3 else 0
    nx, ny, nz = solid.shape
    for i in range(1, nx - 1):
        for j in range(1, ny - 1):
            for k in range(kz, nz - kz):
                if solid[i, j, k] != 0.0:
                    out[i, j, k] = 0.0
                    continue
                f, g, h = i - 1, j - 1, k - kz
                d = u[f + 1, g, h] - u[f, g, h] + v[f, g + 1, h] - v[f, g, h]
                if dim == 3:
                    d += w[f, g, h + 1] - w[f, g, h]
                out[i, j, k] = factor * d


@numba.njit(cache=True, nogil=True)
def _subtract_gradient(comps, p, solid, factor, dim):
    """``u -= factor * (p_hi - p_lo)`` on faces between two non-solid cells, in place."""
    kz = 1 if dim == 3 else 0
    for a in range(dim):
        c = comps[a]
        di, dj, dk = a == 0, a == 1, a == 2
        nx, ny, nz = c.shape
        for i in range(nx):
            for j in range(ny):
                for k in range(nz):
                    I, J, K = i + 1, j + 1, k + kz
                    if solid[I, J, K] == 0.0 and solid[I - di, J - dj, K - dk] == 0.0:
                        c[i, j, k] -= factor * (p[I, J, K] - p[I - di, J - dj, K - dk])


def _mask(grid: Grid, solid) -> np.ndarray:
    solid = np.asarray(solid)
    grid.check_cells(solid, "solid")
    if solid.dtype != np.bool_:
        raise ValueError(f"solid must be a boolean cell mask, got dtype {solid.dtype}")
    return solid
