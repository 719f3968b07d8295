"""Two-way coupling: fluid and articulated body in one SPD pressure solve (paper §3.3).

Derivation of the system in docs/method-coupling.md, "The coupled step", for
faces that may be partly solid (Batty, Bertails and Bridson 2007). Every face f near the
body has a water fraction ``w_f`` in [0, 1] (``Voxels.face_weight``; faces
away from the body have ``w = 1``): the share of its control volume, the box of one cell centred on
the face, that is water. The staircase (``aquagait.body.voxelize``) is the
special case ``w = 0`` on every coupled face, with a solid cell on one side;
``aquagait.body.subcell`` gives fractions between. Cells with no open face
are SOLID (no pressure unknown); ghost cells outside the grid hold ``p = 0``
(open boundary). A coupled face f, normal to axis a, cuts link k(f); ``J_f``
(3 x nv) is the Jacobian of its centre ``x_f`` moving with k(f), so the
body's velocity along the axis there is ``V_f = e_a . J_f qd``. ``A`` is a
face's area (``h^2`` in 3D; ``h * depth`` in 2D, where the fluid is a slab as
deep as the creature's prism).

Given ``u*`` (advected) and ``qd*`` (the body predicted without pressure,
``Mt qd* = Mt qd - dt (c + PD terms)``):

1. The water on a face with ``w_f > 0`` feels the pressure gradient:
   ``u_f = u*_f - dt / (rho h) (p_hi - p_lo)``.
2. The solid part of f's control volume, ``(1 - w_f) A h``, feels the same
   gradient: the force on it along ``e_a`` is ``(1 - w_f) A (p_lo - p_hi)``
   (the pressure integrated over the body's surface, written as the integral
   of ``-grad p`` over the body's volume with ``p = 0`` in solid cells). At a
   staircase face with water above, that is ``-p_c A n_f``, ``n_f = e_a``
   pointing into the water. Its generalized force is ``-B p`` with
   ``B = sum_f (1 - w_f) A J_f^T sum_c n_fc e_c^T``, where ``c`` runs over the
   one or two cells with water beside f and ``n_fc = +e_a`` for the cell
   above, ``-e_a`` below (the normal from f's solid part into c). So
   ``Mt qd = Mt qd* - dt B p``:  ``qd = qd* - dt Mt^-1 B p``.
3. Through f, water crosses at ``u_f`` over ``w_f A`` and the body at
   ``V_f`` over ``(1 - w_f) A``.
4. No cell with water gains or loses volume. Summed over its faces, cell c's
   outflow is ``A (D_w u*)_c + A dt / (rho h) (L_w p)_c - (B^T qd)_c`` where
   ``D_w`` sums ``w_f u_f`` over faces, ``L_w p = sum_f w_f (p_c - p_n)``
   (ghosts count) and ``(B^T qd)_c = sum_f (1 - w_f) A n_fc . J_f qd``. With
   step 2:

       A D_w u* + A dt / (rho h) L_w p - B^T qd* + dt B^T Mt^-1 B p = 0

   and multiplying by ``rho h / (dt A)``:

       (L_w + (rho h / A) B^T Mt^-1 B) p = (rho h / (dt A)) (B^T qd* - A D_w u*).

The same matrix is the Hessian of the kinetic energy of fluid plus body as a
function of the pressure impulse, so the pressure makes that energy least.
``L_w`` is SPD when every cell with water reaches the open boundary through
open faces (pockets are sealed), and ``B^T Mt^-1 B`` is PSD of rank at most
nv, so CG applies. ``L_w`` enters ``pcg`` as the unweighted Laplacian plus
``PartialFaces``; the body term as a ``LowRank`` with rows
``(1 - w_f) A n_fc^T J_f`` (one per coupled face and cell beside it) and core
``(rho h / A) Mt^-1``.

``dense_coupled_system`` assembles the same equations from the physics
(apply a unit pressure in one cell, measure every cell's outflow) rather than
from the formula above; tests hold the two against each other.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numba
import numpy as np

from aquagait.body.dynamics import rigid_velocity
from aquagait.body.voxelize import Voxels, marked
from aquagait.fluid.operators import net_outflow
from aquagait.fluid.pcg import LowRank, PartialFaces, PressureSystem, pcg, pressure_system
from aquagait.fluid.projection import (
    fluid_outflow,
    set_solid_faces_,
    subtract_gradient_,
)
from aquagait.grid import Grid, Velocity

COUPLED_TOLERANCE = 1e-4
"""Default tolerance of the coupled solve, relative to the fastest speed: every
cell's net outflow within 1e-4 of it. The solve starts from the last step's
pressure and the next step's solve removes what this one left, so errors do
not build up in the distance: the shipped eel2d and fish gaits swim the same
distance within 0.02% at 1e-5, 1e-4, 1e-3 and 1e-2 (2 s and 1 s, sub-cell
boundaries), while CG takes 7.4, 5.6, 3.7 and 1.8 iterations a step (eel2d;
fish 5.8, 4.2, 3.0, 1.6). What does build up is asymmetry: the red-black
smoother's colours are not mirror images, and the wake's mirror-asymmetric
modes grow from that error, so a mirror-symmetric 2D swimmer turns a little
(frog2d in its first second: 2.2e-3 rad at 1e-4, 1.3e-4 at 1e-6, 3.4e-6 at
1e-8; while faces under half water were held to the body once a step, which
damped those modes, 1.05e-5 at 1e-4). 1e-4 saves a quarter of the iterations
of 1e-5."""

MOSTLY_WATER = 0.0
"""A coupled face with at least this water fraction keeps the water's velocity after
the solve (for advection); below it, it takes the body's (``rigid_faces_``). 0,
the default: every face with water keeps the water's, and only faces with none
(inside the body, or closed across a thin part, ``aquagait.body.thin``) move with
the body, so nothing is held to the body once a step. Above 0 the body's velocity
re-enters the next solve as the water's on the faces below it, once a step: the
more steps a second, the more the water there is held to the body, a first-order
error in the step (0.5, the rule before thin parts were closed: eel2d +14 % from
1/90 to 1/540 s; docs/method-coupling.md, "Step and grid")."""


LinkMotion = tuple[np.ndarray, np.ndarray, np.ndarray]
"""``(origins, linear, angular)``, each (nlinks, 3): the links' world origins [m],
their velocities [m/s] and angular velocities [rad/s] (``Dynamics.link_motion``).
A point ``p`` moving with link k moves at ``linear[k] + angular[k] x (p - origins[k])``;
the seam from the body to the fluid."""


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


def coupled_rows(voxels: Voxels, jacobians: np.ndarray, area: float):
    """The nonzero rows of ``B^T``: ``(1 - w_f) A n_fc^T J_f`` per coupled face f and
    cell c with water beside it (module docstring); where links meet, each
    link's row carries its share of ``1 - w_f``.

    Args:
        voxels: the voxelized body.
        jacobians: (m, 3, nv) point Jacobians at the coupled face centres.
        area: ``A`` [m^2].
    Returns:
        ``(cells, rows)``: (e, dim) the cell of each row, and the rows (e, nv) [m^2].
    """
    face, cell, sign = voxels.sides()
    solid = area * voxels.face_share[face] * sign
    return cell, _axis_rows(jacobians, face, voxels.face_axis, solid)


@numba.njit(cache=True, nogil=True)
def _axis_rows(jacobians, face, axis, scale):
    """``scale[:, None] * jacobians[face, axis[face], :]``, (e, nv), without the gathered copy."""
    out = np.empty((face.size, jacobians.shape[2]))
    for r in range(face.size):
        f = face[r]
        for j in range(jacobians.shape[2]):
            out[r, j] = scale[r] * jacobians[f, axis[f], j]
    return out


def partial_faces(voxels: Voxels) -> PartialFaces:
    """The coupled faces with water on both sides (or water and the open border),
    which the Laplacian weights by their water fraction (module docstring)."""
    once = voxels.first_entries()
    below, above = (cells[once] for cells in voxels.face_cells())
    water = ~voxels.solid  # the open border counts as water
    both = marked(water, below, outside=True) & marked(water, above, outside=True)
    return PartialFaces(below[both], above[both], voxels.face_weight[once][both])


def coupled_system(
    voxels: Voxels,
    rows: tuple[np.ndarray, np.ndarray],
    mass_t: np.ndarray,
    grid: Grid,
    density: float,
    area: float,
) -> PressureSystem:
    """The operator ``L_w + (rho h / A) B^T Mt^-1 B`` for ``pcg``.

    Args:
        voxels: cells without water and coupled faces.
        rows: ``coupled_rows``: cells (e, dim) and rows (e, nv).
        mass_t: ``Mt = M + dt Kd``, (nv, nv).
        grid: the MAC grid.
        density: ``rho`` [kg/m^3].
        area: ``A`` [m^2].
    """
    core = (density * grid.cell_size / area) * np.linalg.inv(mass_t)
    core = 0.5 * (core + core.T)  # symmetric to round-off, as CG assumes
    low_rank = LowRank(*rows, core)
    partial = partial_faces(voxels)
    partial = partial if len(partial.weight) else None
    return pressure_system(voxels.solid, low_rank, sealed=True, partial=partial)


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

    @cached_property
    def rows(self) -> tuple[np.ndarray, np.ndarray]:
        """The nonzero rows of ``B^T`` and their cells: ``coupled_rows``."""
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
    set_solid_faces_(grid, u, voxels.solid)  # no water: no fluid velocity
    (cells, rows), scale = problem.rows, problem.scale
    system = coupled_system(voxels, (cells, rows), problem.mass_t, grid, problem.density, area)
    surface_outflow = rows @ problem.qvel_star
    body_outflow = _per_cell(grid, cells, surface_outflow)  # B^T qd*
    rhs = scale * (body_outflow - area * fluid_outflow(grid, water_flux(u, voxels), voxels.solid))
    speed = max(max(np.abs(c).max() for c in u), np.abs(surface_outflow).max(initial=0.0) / area)
    result = solve(system, rhs, atol=tol * max(speed, 1e-30) * scale * area, x0=pressure)
    subtract_gradient_(
        grid, u, result.x, voxels.solid, problem.dt / (problem.density * grid.cell_size)
    )
    force = -rows.T @ result.x[tuple(cells.T)]  # -B p
    qvel = problem.qvel_star + problem.dt * np.linalg.solve(problem.mass_t, force)
    return CoupledSolve(u, qvel, result.x, force, result.iterations)


def water_flux(velocity: Velocity, voxels: Voxels) -> Velocity:
    """A copy of the face velocities with each coupled face's times its water fraction:
    the fluid's share of the flow, whose ``fluid_outflow`` is ``D_w u``."""
    flux = tuple(np.array(c, dtype=float) for c in velocity)
    for axis, component in enumerate(flux):
        on = voxels.face_axis == axis
        component[tuple(voxels.face_index[on].T)] *= voxels.face_weight[on]
    return flux


def volume_change(problem: CoupledProblem, velocity: Velocity, qvel: np.ndarray) -> np.ndarray:
    """Every cell's net outflow of volume through the water and the body parts of its
    faces, ``grid.shape`` [m^3/s] (0 in solid cells): zero after a coupled solve."""
    grid, voxels = problem.grid, problem.voxels
    u = tuple(np.array(c, dtype=float) for c in velocity)
    set_solid_faces_(grid, u, voxels.solid)
    cells, rows = problem.rows
    fluid = problem.area * fluid_outflow(grid, water_flux(u, voxels), voxels.solid)
    return fluid - _per_cell(grid, cells, rows @ qvel)


def rigid_faces_(
    grid: Grid,
    velocity: Velocity,
    voxels: Voxels,
    motion: LinkMotion,
    mostly_water: float = MOSTLY_WATER,
) -> None:
    """Give every mostly solid face the rigid velocity of its link, in place.

    Mostly solid: a coupled face whose water fraction is below ``mostly_water``, or any
    other face that touches a cell the body owns. Coupled faces so get the
    body's velocity where the body is most of them (on the staircase, all of
    them: step 3 of the module docstring), and keep the water's where it is;
    faces inside the body carry the body's velocity too, so that advection
    near the body interpolates sensible values. A face between cells of two
    links takes the mean of both links' velocities there (no side is
    preferred, so a mirror-symmetric body stays symmetric).

    Args:
        grid: the MAC grid.
        velocity: face velocities [m/s], written in place.
        voxels: the voxelized body.
        motion: the links' rigid motion (``LinkMotion``).
        mostly_water: the water fraction from which a coupled face keeps the
            water's velocity (``MOSTLY_WATER``; 0: every face with water).
    """
    origins, linear, angular = (np.ascontiguousarray(a, dtype=float) for a in motion)
    owner = voxels.owner.reshape(voxels.owner.shape + (1,) * (3 - grid.dim))
    origin = np.zeros(3)
    origin[: grid.dim] = grid.origin
    box = _owned_box(owner)
    watery = (voxels.face_weight >= mostly_water) & (voxels.face_weight > 0)
    kept = [_coupled_values(velocity, voxels, watery, axis) for axis in range(grid.dim)]
    for axis, component in enumerate(velocity):
        face = component.reshape(component.shape + (1,) * (3 - grid.dim))
        _owned_faces_(owner, box, axis, origin, grid.cell_size, grid.dim == 3, origins, linear,
                      angular, face)  # fmt: skip
        at, values = kept[axis]
        component[at] = values
    loose = ~watery & ~_touches_owned(voxels)
    if loose.any():  # where links meet, the mean of theirs weighted by their shares
        speeds = rigid_velocity(motion, voxels.face_center[loose], voxels.face_link[loose])
        share = voxels.face_share[loose] / (1.0 - voxels.face_weight[loose])
        axes, index = voxels.face_axis[loose], voxels.face_index[loose]
        for axis, component in enumerate(velocity):
            at = tuple(index[axes == axis].T)
            component[at] = 0.0
            np.add.at(component, at, share[axes == axis] * speeds[axes == axis, axis])


def near_body(grid: Grid, voxels: Voxels, cells: int) -> Velocity:
    """Boolean face arrays: the faces within ``cells`` cells of the body.

    The body is every cell without water and every cell beside a coupled face;
    a face is near it when a cell on either side is at most ``cells`` steps
    along the axes from one of those (``cells = 0``: the faces of the body's
    own cells). Two Numba passes, a ball of ``cells`` steps about each body
    cell, then the faces beside the marked cells: 0.4 ms a step for the fish,
    where morphology and index arrays took 1.6.
    """
    flat = (1,) * (3 - grid.dim)  # a 2D grid is one cell deep
    near = np.zeros(grid.shape + flat, bool)
    index = np.zeros((voxels.face_count, 3), np.int64)
    index[:, : grid.dim] = voxels.face_index
    _mark_near_(voxels.solid.reshape(near.shape), index, voxels.face_axis, cells, near)
    faces = []
    for axis in range(grid.dim):
        out = np.empty(grid.face_shape(axis) + flat, bool)
        _faces_beside_(near, axis, out)
        faces.append(out.reshape(grid.face_shape(axis)))
    return tuple(faces)


@numba.njit(cache=True, nogil=True)
def _mark_near_(solid, face_index, face_axis, cells, near):
    """Mark in ``near`` (cells, 3D) every cell within ``cells`` steps along the axes of a
    solid cell or of a cell beside a coupled face (index and axis, 3 columns)."""
    body = solid.copy()
    nx, ny, nz = body.shape
    for f in range(face_axis.size):
        i, j, k = face_index[f, 0], face_index[f, 1], face_index[f, 2]
        if i < nx and j < ny and k < nz:
            body[i, j, k] = True  # the cell above the face
        a = face_axis[f]
        i, j, k = i - (a == 0), j - (a == 1), k - (a == 2)
        if i >= 0 and j >= 0 and k >= 0:
            body[i, j, k] = True  # and the one below
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if body[i, j, k]:
                    _ball_(near, i, j, k, cells)


@numba.njit(cache=True, nogil=True, inline="always")
def _ball_(near, i, j, k, cells):
    """Mark the cells within ``cells`` steps along the axes of cell ``(i, j, k)`` (only
    the ball's part inside the grid)."""
    nx, ny, nz = near.shape
    for di in range(-cells, cells + 1):
        x = i + di
        if not 0 <= x < nx:
            continue
        rest = cells - abs(di)
        for dj in range(-rest, rest + 1):
            y = j + dj
            if not 0 <= y < ny:
                continue
            last = rest - abs(dj)
            for z in range(max(k - last, 0), min(k + last + 1, nz)):
                near[x, y, z] = True


@numba.njit(cache=True, nogil=True)
def _faces_beside_(near, axis, out):
    """``out`` (faces normal to ``axis``, 3D): whether a cell on either side is marked."""
    nx, ny, nz = near.shape
    mx, my, mz = out.shape
    for i in range(mx):
        for j in range(my):
            for k in range(mz):
                p, q, r = i - (axis == 0), j - (axis == 1), k - (axis == 2)  # the cell below
                below = p >= 0 and q >= 0 and r >= 0 and near[p, q, r]
                out[i, j, k] = below or (i < nx and j < ny and k < nz and near[i, j, k])


def _beside_faces(padded: np.ndarray, axis: int) -> tuple[np.ndarray, np.ndarray]:
    """A cell field padded by one ghost cell a side, read at the cells below and above
    every face normal to ``axis``: two arrays of the faces' shape."""
    n = padded.shape[axis]
    inner = [slice(1, -1)] * padded.ndim
    inner[axis] = slice(None)
    below = np.take(padded, range(n - 1), axis=axis)[tuple(inner)]
    above = np.take(padded, range(1, n), axis=axis)[tuple(inner)]
    return below, above


def _coupled_values(velocity: Velocity, voxels: Voxels, chosen: np.ndarray, axis: int):
    """The chosen coupled faces normal to ``axis``: their index and current values."""
    at = tuple(voxels.face_index[chosen & (voxels.face_axis == axis)].T)
    return at, velocity[axis][at].copy()


def _touches_owned(voxels: Voxels) -> np.ndarray:
    """Whether each coupled face has a cell the body owns on either side."""
    owned = voxels.owner >= 0
    below, above = voxels.face_cells()
    return marked(owned, below, outside=False) | marked(owned, above, outside=False)


@numba.njit(cache=True, nogil=True)
def _owned_box(owner):
    """``(2, 3)``: the first and last index per axis of the owned cells (``owner >= 0``)
    of ``owner`` (nx, ny, nz); the last row is -1 when no cell is owned."""
    nx, ny, nz = owner.shape
    box = np.empty((2, 3), np.int64)
    box[0, 0], box[0, 1], box[0, 2] = nx, ny, nz
    box[1, :] = -1
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if owner[i, j, k] >= 0:
                    box[0, 0], box[1, 0] = min(box[0, 0], i), max(box[1, 0], i)
                    box[0, 1], box[1, 1] = min(box[0, 1], j), max(box[1, 1], j)
                    box[0, 2], box[1, 2] = min(box[0, 2], k), max(box[1, 2], k)
    return box


@numba.njit(cache=True, nogil=True)
def _owned_faces_(owner, box, axis, origin, h, three_d, origins, linear, angular, face):
    """Set each face normal to ``axis`` beside an owned cell to its links' velocity.

    ``owner`` (nx, ny, nz; nz = 1 in 2D) holds each cell's link or -1, ``box``
    the owned cells' bounds (``_owned_box``); ``face`` is the velocity
    component normal to ``axis`` in the same layout. A face with owned cells
    on both sides takes the mean of both links' velocities at its centre
    (written as ``0.5 (a + b)``, so one link's comes back exactly). Only the
    faces of the box are visited.
    """
    if box[1, 0] < 0:
        return
    lo, hi = box[0].copy(), box[1].copy()
    hi[axis] += 1  # the faces above the box's last cells
    step = np.zeros(3, np.int64)
    step[axis] = 1
    centre = np.array([0.5, 0.5, 0.5])
    centre[axis] = 0.0
    p = np.zeros(3)
    for i in range(lo[0], hi[0] + 1):
        for j in range(lo[1], hi[1] + 1):
            for k in range(lo[2], hi[2] + 1):
                below = _owner_at(owner, i - step[0], j - step[1], k - step[2])
                above = _owner_at(owner, i, j, k)
                if below < 0 and above < 0:
                    continue
                below, above = (below, above) if below >= 0 else (above, above)
                above = above if above >= 0 else below
                p[0] = origin[0] + (i + centre[0]) * h
                p[1] = origin[1] + (j + centre[1]) * h
                p[2] = origin[2] + (k + centre[2]) * h if three_d else 0.0
                a = _rigid_speed(origins, linear, angular, below, p, axis)
                b = _rigid_speed(origins, linear, angular, above, p, axis)
                face[i, j, k] = 0.5 * (a + b)


@numba.njit(cache=True, inline="always")
def _owner_at(owner, i, j, k):
    """``owner[i, j, k]``, or -1 outside the grid."""
    nx, ny, nz = owner.shape
    if 0 <= i < nx and 0 <= j < ny and 0 <= k < nz:
        return owner[i, j, k]
    return -1


@numba.njit(cache=True, inline="always")
def _rigid_speed(origins, linear, angular, link, p, axis):
    """Component ``axis`` of ``linear + angular x (p - origin)`` of ``link``, as ``np.cross``
    computes it (the same numbers as ``body.dynamics.rigid_velocity``)."""
    w = angular[link]
    r0, r1, r2 = p[0] - origins[link, 0], p[1] - origins[link, 1], p[2] - origins[link, 2]
    if axis == 0:
        return linear[link, 0] + (w[1] * r2 - w[2] * r1)
    if axis == 1:
        return linear[link, 1] + (w[2] * r0 - w[0] * r2)
    return linear[link, 2] + (w[0] * r1 - w[1] * r0)


def _per_cell(grid: Grid, cells: np.ndarray, per_row: np.ndarray) -> np.ndarray:
    """Sum a value per row of ``B^T`` into its cell, ``grid.shape``."""
    out = grid.zeros_cells()
    np.add.at(out, tuple(cells.T), per_row)
    return out


# --- the slow reference ---------------------------------------------------------


def dense_coupled_system(problem: CoupledProblem) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The coupled system assembled from the physics, densely; for tests only.

    Every cell's net outflow after a step is an affine function of the
    pressure. Column c of the matrix is the outflow caused by a unit pressure
    in cell c alone, computed face by face: the gradient accelerates the water
    on every face with some (``w > 0``); the pressure difference across each
    coupled face pushes its solid part, ``(1 - w) A (p_lo - p_hi)`` along the
    axis (``p = 0`` in solid and ghost cells; each link its share where links
    meet), which accelerates the body through ``Mt``; each face then passes
    ``w A u + (1 - w) A V`` (``V``: the body's velocity along the axis at the
    face). ``rho h / (dt A)`` times that is the matrix, and minus as much
    times the outflow at ``p = 0`` the right-hand side.

    Returns:
        ``(matrix, rhs, water_cells)``: (n, n), (n,) and (n, dim) cell indices.
    """
    grid, voxels, jacobians = problem.grid, problem.voxels, problem.jacobians
    dt, density, area, mass_t = problem.dt, problem.density, problem.area, problem.mass_t
    water_cells = np.argwhere(~voxels.solid)
    weight = water_fractions(grid, voxels)
    scale = problem.scale

    def outflow(p, u_star, qd_star):
        ghosted = np.pad(p, 1)
        u, force = [], np.zeros(len(qd_star))
        for axis in range(grid.dim):
            inner = [slice(1, -1)] * grid.dim
            inner[axis] = slice(None)
            gradient = np.diff(ghosted, axis=axis)[tuple(inner)]
            u.append(u_star[axis] - dt / (density * grid.cell_size) * gradient)
        for f in range(voxels.face_count):
            axis, index = voxels.face_axis[f], tuple(voxels.face_index[f])
            step = np.eye(grid.dim, dtype=int)[axis]
            lo = ghosted[tuple(np.add(index, 1) - step)]
            hi = ghosted[tuple(np.add(index, 1))]
            push = np.zeros(3)
            push[axis] = voxels.face_share[f] * area * (lo - hi)
            force += jacobians[f].T @ push
        qd = qd_star + dt * np.linalg.solve(mass_t, force)
        flux = [area * weight[axis] * u[axis] for axis in range(grid.dim)]
        for f in range(voxels.face_count):
            axis, index = voxels.face_axis[f], tuple(voxels.face_index[f])
            solid = voxels.face_share[f] * area * (jacobians[f] @ qd)[axis]
            flux[axis][index] += solid
        total = net_outflow(grid, tuple(flux))
        return total[~voxels.solid]

    base = outflow(grid.zeros_cells(), problem.velocity_star, problem.qvel_star)
    still = grid.zeros_velocity()
    at_rest = np.zeros_like(problem.qvel_star)
    matrix = np.zeros((len(water_cells), len(water_cells)))
    for column, cell in enumerate(water_cells):
        unit = grid.zeros_cells()
        unit[tuple(cell)] = 1.0
        matrix[:, column] = scale * outflow(unit, still, at_rest)
    return matrix, -scale * base, water_cells


def water_fractions(grid: Grid, voxels: Voxels) -> Velocity:
    """Every face's water fraction ``w``, as face arrays: 1 between two cells with
    water (or water and the open border), 0 next to a solid cell, the coupled
    faces' own fractions where listed."""
    water = np.pad(~voxels.solid, 1, constant_values=True)  # ghosts: open water
    fractions = [np.logical_and(*_beside_faces(water, axis)).astype(float)
                 for axis in range(grid.dim)]  # fmt: skip
    for axis, fraction in enumerate(fractions):
        on = voxels.face_axis == axis
        fraction[tuple(voxels.face_index[on].T)] = voxels.face_weight[on]
    return tuple(fractions)
