"""Two-way coupling: fluid and articulated body in one SPD pressure solve (paper §3.3).

Derivation (DESIGN.md §2.3). Cells are FLUID or SOLID (inside a link, or a
fluid pocket sealed in by links). A *coupled face* f lies between a fluid cell
c(f) and a solid cell owned by link k(f); its unit normal ``n_f = s_f e_a``
points from the solid into the fluid, its centre is ``x_f``, its area ``A``
(``h^2`` in 3D; ``h * depth`` in 2D, where the fluid is a slab as deep as the
creature's prism). ``J_f`` (3 x nv) is the Jacobian of the point ``x_f`` moving
with link k(f), so the body's velocity there is ``J_f qd``.

Unknowns: the pressure ``p`` of the fluid cells; ghost cells outside the grid
hold ``p = 0`` (open boundary). Given ``u*`` (advected) and ``qd*`` (the body
predicted without pressure, ``Mt qd* = Mt qd - dt (c + PD terms)``):

1. Fluid faces (both sides fluid or ghost) feel the pressure gradient:
   ``u_f = u*_f - dt / (rho h) (p_hi - p_lo)``.
2. The fluid at pressure ``p_c`` pushes on the body's surface with force
   ``-p_c A n_f`` at ``x_f`` (into the solid). Its generalized force is
   ``sum_f J_f^T (-p_c A n_f) = -B p`` with ``B = sum_f A J_f^T n_f e_c(f)^T``
   (nv x cells), so ``Mt qd = Mt qd* - dt B p``:  ``qd = qd* - dt Mt^-1 B p``.
3. A coupled face moves with the body: its normal velocity is ``n_f . J_f qd``.
4. No fluid cell gains or loses volume. Outflow of cell c through a fluid face
   is ``A u.n_out``; summed, ``A (D u*)_c + A dt / (rho h) (L p)_c`` where
   ``D`` sums over fluid faces only and ``L p = sum (p_c - p_neighbour)``
   (ghosts count, coupled faces do not). Through a coupled face the outward
   normal of c is ``-n_f``, so the outflow is ``-A n_f . J_f qd``; summed over
   c's coupled faces, ``-(B^T qd)_c``. Zero net outflow with step 2:

       A D u* + A dt / (rho h) L p - B^T qd* + dt B^T Mt^-1 B p = 0

   and multiplying by ``rho h / (dt A)``:

       (L + (rho h / A) B^T Mt^-1 B) p = (rho h / (dt A)) (B^T qd* - A D u*).

``L`` is SPD when every fluid region touches the open boundary (pockets are
sealed), and ``B^T Mt^-1 B`` is PSD of rank at most nv, so CG applies; the
body term enters ``pcg`` as a ``LowRank`` with rows ``A n_f^T J_f`` (one per
coupled face, at cell c(f)) and core ``(rho h / A) Mt^-1``.

``dense_coupled_system`` assembles the same equations from the physics
(apply a unit pressure in one cell, measure every cell's outflow) rather than
from the formula above; tests hold the two against each other.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from aquagait.body.voxelize import Voxels
from aquagait.fluid.operators import net_outflow
from aquagait.fluid.pcg import LowRank, PressureSystem, pcg, pressure_system
from aquagait.fluid.projection import (
    fluid_outflow,
    set_solid_faces_,
    subtract_gradient_,
)
from aquagait.grid import Grid, Velocity

COUPLED_TOLERANCE = 1e-5
"""Default tolerance of the coupled solve, relative to the fastest speed. The fish
and the eel swim the same to seven digits at 1e-4, 1e-5 and 1e-6."""

PointVelocity = Callable[[np.ndarray, np.ndarray], np.ndarray]
"""``point_velocity(points (n, 3), links (n,)) -> (n, 3)``: the rigid velocity of
points moving with the given links [m/s]; the seam from the body to the fluid."""


@dataclass(frozen=True)
class CoupledSolve:
    """Outcome of a coupled pressure solve.

    Attributes:
        velocity: face velocities after the pressure acted [m/s]; faces that
            touch a solid are still ``u*`` (``rigid_faces_`` sets them).
        qvel: (nv,) body velocities ``qd^{n+1}`` [m/s, rad/s].
        pressure: cell pressure, ``grid.shape`` [Pa] (0 in solid cells).
        force: (nv,) generalized force of the pressure on the body, ``-B p`` [N, N m].
        iterations: CG iterations.
    """

    velocity: Velocity
    qvel: np.ndarray
    pressure: np.ndarray
    force: np.ndarray
    iterations: int


def face_area(grid: Grid, depth: float | None) -> float:
    """``A``: a face's area, ``h^2`` in 3D and ``h * depth`` in 2D [m^2]."""
    if grid.dim == 3:
        return grid.cell_size**2
    if depth is None or not depth > 0:
        raise ValueError(f"a 2D coupling needs the creature's prism depth in metres, got {depth!r}")
    return grid.cell_size * depth


def coupled_rows(voxels: Voxels, jacobians: np.ndarray, area: float) -> np.ndarray:
    """Rows of ``B^T``, one per coupled face: ``A n_f^T J_f``, (m, nv) [m^2].

    Args:
        voxels: the voxelized body.
        jacobians: (m, 3, nv) point Jacobians at the coupled face centres.
        area: ``A`` [m^2].
    """
    m = len(voxels.face_axis)
    return area * voxels.face_sign[:, None] * jacobians[np.arange(m), voxels.face_axis, :]


def coupled_system(
    voxels: Voxels, rows: np.ndarray, mass_t: np.ndarray, grid: Grid, density: float, area: float
) -> PressureSystem:
    """The operator ``L + (rho h / A) B^T Mt^-1 B`` for ``pcg``.

    Args:
        voxels: solid cells and coupled faces.
        rows: ``coupled_rows`` (m, nv).
        mass_t: ``Mt = M + dt Kd``, (nv, nv).
        grid: the MAC grid.
        density: ``rho`` [kg/m^3].
        area: ``A`` [m^2].
    """
    core = (density * grid.cell_size / area) * np.linalg.inv(mass_t)
    core = 0.5 * (core + core.T)  # symmetric to round-off, as CG assumes
    low_rank = LowRank(voxels.face_cell, rows, core)
    return pressure_system(voxels.solid, low_rank, sealed=True)  # voxelize sealed pockets


@dataclass(frozen=True, eq=False)
class CoupledProblem:
    """One coupled pressure solve's inputs, at the body's pose ``q^n`` (module docstring).

    Attributes:
        grid: the MAC grid.
        voxels: the body voxelized at ``q^n``.
        velocity_star: advected face velocities ``u*`` [m/s].
        qvel_star: (nv,) body velocities predicted without pressure ``qd*``.
        mass_t: ``Mt = M + dt Kd``, (nv, nv) [kg, kg m^2].
        jacobians: (m, 3, nv) point Jacobians at the coupled face centres.
        dt: time step [s].
        density: ``rho`` [kg/m^3].
        area: a coupled face's area ``A`` [m^2] (``face_area``).
    """

    grid: Grid
    voxels: Voxels
    velocity_star: Velocity
    qvel_star: np.ndarray
    mass_t: np.ndarray
    jacobians: np.ndarray
    dt: float
    density: float
    area: float

    @property
    def rows(self) -> np.ndarray:
        """Rows of ``B^T``, (m, nv): ``coupled_rows``."""
        return coupled_rows(self.voxels, self.jacobians, self.area)

    @property
    def scale(self) -> float:
        """``rho h / (dt A)``: turns a net outflow [m^3/s] into the equations' units."""
        return self.density * self.grid.cell_size / (self.dt * self.area)


def solve_coupled(
    problem: CoupledProblem,
    pressure: np.ndarray | None = None,
    tol: float = COUPLED_TOLERANCE,
    solve=pcg,
) -> CoupledSolve:
    """Solve for the pressure that moves fluid and body together (module docstring).

    Args:
        problem: ``u*``, ``qd*``, ``Mt``, the voxels and Jacobians at ``q^n``.
        pressure: warm start [Pa].
        tol: stop when every cell's ``|net outflow| <= tol * U * A`` (U: the
            fastest face or body-surface speed).
        solve: the linear solver.
    Returns:
        the fluid and body velocities after the pressure acted, and the pressure.
    """
    grid, voxels, area = problem.grid, problem.voxels, problem.area
    grid.check_velocity(problem.velocity_star, "velocity_star")
    u = tuple(np.array(c, dtype=float) for c in problem.velocity_star)
    set_solid_faces_(grid, u, voxels.solid)  # D sums over fluid faces only
    rows, scale = problem.rows, problem.scale
    system = coupled_system(voxels, rows, problem.mass_t, grid, problem.density, area)
    surface_outflow = rows @ problem.qvel_star
    body_outflow = _per_cell(grid, voxels, surface_outflow)  # B^T qd*
    rhs = scale * (body_outflow - area * fluid_outflow(grid, u, voxels.solid))
    speed = max(max(np.abs(c).max() for c in u), np.abs(surface_outflow).max(initial=0.0) / area)
    result = solve(system, rhs, atol=tol * max(speed, 1e-30) * scale * area, x0=pressure)
    subtract_gradient_(
        grid, u, result.x, voxels.solid, problem.dt / (problem.density * grid.cell_size)
    )
    force = -rows.T @ result.x[tuple(voxels.face_cell.T)]  # -B p
    qvel = problem.qvel_star + problem.dt * np.linalg.solve(problem.mass_t, force)
    return CoupledSolve(u, qvel, result.x, force, result.iterations)


def rigid_faces_(
    grid: Grid, velocity: Velocity, voxels: Voxels, point_velocity: PointVelocity
) -> None:
    """Give every face that touches a solid cell the rigid velocity of its link, in place.

    Coupled faces so get the body's normal velocity (step 3 of the module
    docstring); faces inside the body carry it too, so that advection near
    the body interpolates sensible values. A face between solid cells of two
    links takes the mean of both links' velocities there (no side is
    preferred, so a mirror-symmetric body stays symmetric).
    """
    box = _solid_box(voxels.owner)
    if box is None:
        return
    for axis, component in enumerate(velocity):
        index, lo, hi = _faces_touching_solid(voxels.owner, box, axis)
        offset = np.full(grid.dim, 0.5)
        offset[axis] = 0.0
        points = np.zeros((len(index), 3))
        points[:, : grid.dim] = np.asarray(grid.origin) + (index + offset) * grid.cell_size
        lo, hi = np.where(lo >= 0, lo, hi), np.where(hi >= 0, hi, lo)
        both = np.concatenate([lo, hi])
        speeds = point_velocity(np.concatenate([points, points]), both)[:, axis]
        component[tuple(index.T)] = 0.5 * (speeds[: len(lo)] + speeds[len(lo) :])


def _solid_box(owner: np.ndarray) -> tuple[slice, ...] | None:
    """The bounding box of the solid cells (the body is small beside the grid)."""
    box = []
    for axis in range(owner.ndim):
        occupied = np.flatnonzero(
            np.any(owner >= 0, axis=tuple(a for a in range(owner.ndim) if a != axis))
        )
        if len(occupied) == 0:
            return None
        box.append(slice(occupied[0], occupied[-1] + 1))
    return tuple(box)


def _faces_touching_solid(owner: np.ndarray, box: tuple[slice, ...], axis: int):
    """Faces normal to ``axis`` next to a solid cell of ``box``: indices (n, dim),
    and the owner links of the cells below and above each (-1: fluid or outside)."""
    inside = owner[box]
    widths = [(0, 0)] * owner.ndim
    widths[axis] = (1, 1)
    padded = np.pad(inside, widths, constant_values=-1)
    lo = np.take(padded, range(0, inside.shape[axis] + 1), axis=axis)
    hi = np.take(padded, range(1, inside.shape[axis] + 2), axis=axis)
    index = np.argwhere((lo >= 0) | (hi >= 0))
    first = np.array([b.start for b in box])
    return index + first, lo[tuple(index.T)], hi[tuple(index.T)]


def _per_cell(grid: Grid, voxels: Voxels, per_face: np.ndarray) -> np.ndarray:
    """Sum a value per coupled face into its fluid cell, ``grid.shape``."""
    out = grid.zeros_cells()
    np.add.at(out, tuple(voxels.face_cell.T), per_face)
    return out


# --- the slow reference ---------------------------------------------------------


def dense_coupled_system(problem: CoupledProblem) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The coupled system assembled from the physics, densely; for tests only.

    Every cell's net outflow after a step is an affine function of the
    pressure. Column c of the matrix is the outflow caused by a unit pressure
    in cell c alone, computed face by face: the gradient accelerates the
    fluid faces; the force ``-p A n_f`` on every coupled face accelerates the
    body through ``Mt``, and the body's surface velocity gives the outflow
    through the coupled faces. ``rho h / (dt A)`` times that is the matrix,
    and minus as much times the outflow at ``p = 0`` the right-hand side.

    Returns:
        ``(matrix, rhs, fluid_cells)``: (n, n), (n,) and (n, dim) cell indices.
    """
    grid, voxels, jacobians = problem.grid, problem.voxels, problem.jacobians
    dt, density, area, mass_t = problem.dt, problem.density, problem.area, problem.mass_t
    fluid_cells = np.argwhere(~voxels.solid)
    scale = problem.scale

    def outflow(p, u_star, qd_star):
        u = tuple(np.array(c, dtype=float) for c in u_star)
        set_solid_faces_(grid, u, voxels.solid)
        subtract_gradient_(grid, u, p, voxels.solid, dt / (density * grid.cell_size))
        force = np.zeros(len(qd_star))
        for f in range(len(voxels.face_axis)):
            normal = np.zeros(3)
            normal[voxels.face_axis[f]] = voxels.face_sign[f]
            p_cell = p[tuple(voxels.face_cell[f])]
            force += jacobians[f].T @ (-p_cell * area * normal)
        qd = qd_star + dt * np.linalg.solve(mass_t, force)
        total = area * net_outflow(grid, u)  # fluid faces (solid faces hold zero)
        for f in range(len(voxels.face_axis)):
            surface = jacobians[f] @ qd
            total[tuple(voxels.face_cell[f])] -= (
                area * voxels.face_sign[f] * surface[voxels.face_axis[f]]
            )
        return total[~voxels.solid]

    base = outflow(grid.zeros_cells(), problem.velocity_star, problem.qvel_star)
    still = grid.zeros_velocity()
    at_rest = np.zeros_like(problem.qvel_star)
    matrix = np.zeros((len(fluid_cells), len(fluid_cells)))
    for column, cell in enumerate(fluid_cells):
        unit = grid.zeros_cells()
        unit[tuple(cell)] = 1.0
        matrix[:, column] = scale * outflow(unit, still, at_rest)
    return matrix, -scale * base, fluid_cells
