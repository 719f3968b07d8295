"""The grid that follows the swimmer, and never lets it near the open boundary (paper §6).

The Euler fluid's grid ends in ``p = 0`` ghost cells: open water, but only
far from the body is that the same as the ocean. The grid therefore keeps
``clearance`` cells of water between every wall and the body's bounding box
(the box of every link's geoms, turned with the link): when a step leaves
the box nearer a wall than that, the grid shifts by whole cells
(``aquagait.fluid.shift``: no value moves between sample points) to centre
the box along that axis. A body that grew too large to fit even then (it
turned out of its plane, spread its fins) grows the grid instead, with a
``GridGrew`` warning: the cells added hold still water, which the open
boundary already assumed there, so the swim goes on as it would have in the
larger grid from the start, only slower a step (an optimization's samples
raise ``BodyOutsideGrid`` instead, and are penalized). ``check_room`` refuses
a grid too small for the body at rest before anything is simulated, naming
the smallest resolution that would do.

Whichever happens, the step sets the faces that touch the body from its pose
at the start of the step, in the grid it was solved on, and only then shifts
the fields: the same rule whether or not the grid moves.
"""

from __future__ import annotations

import math
import warnings
from contextlib import contextmanager
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
from scipy.spatial.transform import Rotation

from aquagait.body.shape import link_box_corners, world_bounds
from aquagait.fluid.shift import regrid
from aquagait.grid import Grid
from aquagait.sim.servo import SimulationDiverged, SimulationError

if TYPE_CHECKING:
    from aquagait.body.model import Model
    from aquagait.sim.scene import Scene, State

CLEARANCE = 8
"""Cells of water kept between the body's bounding box and every wall of the grid.

Measured with the shipped eel2d gait, 4 s on its default 128x64 grid of 1 cm
(one shift of about 30 cells), against a grid 2.8 m long that never shifts:
distance 0.5620 against 0.5623 m (0.06%), heading 0.144 against 0.149 rad;
with 4 cells 0.02% and 0.008 rad, with 16 cells 0.26% and 0.004 rad. The rule
it replaces (recentre when the centre of mass came within a quarter of the
grid of a wall, which let the eel's snout reach the last cells) was measured
at 1.6% and 0.016 rad (issue 9)."""


GROWTH_MULTIPLE = 8
"""A grid that grows grows to a multiple of this many cells along each axis it grows on:
some room for the next turn of the body, and halvings for the multigrid."""


class BodyOutsideGrid(SimulationError):
    """The body came nearer a wall than the clearance, no shift could make room, and the
    grid may not grow (``EulerFluid(grow=False)``, as an optimization's samples swim)."""


class GridGrew(UserWarning):
    """The body outgrew its grid, which grew (``follow``): the swim goes on, slower a step."""


def body_bounds(scene: Scene, q) -> np.ndarray:
    """The body's world bounding box at ``q``: (2, dim) lower and upper corners [m]."""
    return world_bounds(scene.shape, *scene.dynamics.link_poses(q))[:, : scene.model.dim]


def widest_box(scene: Scene, gait, poses: int = 16) -> np.ndarray:
    """The body's largest bounding-box side along each axis over one cycle of ``gait``,
    (dim,) [m]: the driven joints at the gait's angles at ``poses`` moments of its
    period, the body turned as a whole to its reference orientation.

    A free swimmer does not hold its head still while it bends: it recoils
    so that its links, on the whole, keep their orientation. Each pose is
    therefore turned by the rotation that best maps its links, weighted by
    mass (their origins and their boxes' corners), back onto the reference
    pose's (Kabsch's), before its box is measured. What a following grid
    must hold besides its clearance; a swim's turns come on top.
    """
    model, dynamics = scene.model, scene.dynamics
    index = [model.dof(d) for d in gait.dofs]
    turn = model.root_dofs[2:] if model.planar else model.root_dofs[3:]
    reference = _weighted_points(scene, model.qpos0)
    root_rot = dynamics.link_poses(model.qpos0)[1][0]  # a free root turns in its own frame
    period = float(np.max(gait.period))
    displacement = np.zeros(model.nv)
    sides = np.zeros(model.dim)
    for t in np.arange(poses) * period / poses:
        displacement[:] = 0.0
        displacement[index] = gait.angles(t)
        bent = _weighted_points(scene, dynamics.integrate(model.qpos0, displacement, 1.0))
        back = _best_rotation(bent, reference)
        displacement[turn] = back[2:] if model.planar else root_rot.T @ back
        bounds = body_bounds(scene, dynamics.integrate(model.qpos0, displacement, 1.0))
        sides = np.maximum(sides, bounds[1] - bounds[0])
    return sides


CORNER_SHARE = 0.1
"""The share of each link's weight ``widest_box`` puts on its box's corners, the rest on its
origin. The origins alone match a swim best (the eel2d's lateral room 0.178 m against 0.183 m
swum, 0.174 m with this share, 0.152 m on the corners alone; eel3d's hand-set gait 0.082,
0.081, 0.073 against 0.094 m), but a straight chain's origins lie on a line, about which no
rotation could be told from another: the corners decide that."""


def _weighted_points(scene: Scene, q) -> tuple[np.ndarray, np.ndarray]:
    """The links' origins and the corners of their boxes of geoms at ``q``, about their
    weighted centre, (m, 3) [m], and their weights (m,), summing to 1: each link's mass,
    ``CORNER_SHARE`` of it shared among its box's 8 corners."""
    origins, rot = scene.dynamics.link_poses(q)
    corners, links = link_box_corners(scene.shape, origins, rot)
    mass = scene.model.link_mass
    points = np.concatenate([origins, corners.reshape(-1, 3)])
    weight = np.concatenate(
        [(1 - CORNER_SHARE) * mass, np.repeat(CORNER_SHARE * mass[links] / 8, 8)]
    )
    weight = weight / weight.sum()
    return points - weight @ points, weight


def _best_rotation(moved, reference) -> np.ndarray:
    """The rotation vector (3,) [rad] of the rotation that best maps the points ``moved``
    onto ``reference`` in the weighted least-squares sense (Kabsch); both as returned by
    ``_weighted_points``."""
    (a, mass), (b, _) = moved, reference
    u, _, vt = np.linalg.svd((mass[:, None] * a).T @ b)
    flip = np.sign(np.linalg.det(u @ vt))  # a rotation, not a reflection
    return Rotation.from_matrix((u @ np.diag([1.0, 1.0, flip]) @ vt).T).as_rotvec()


def room(grid: Grid, bounds: np.ndarray) -> np.ndarray:
    """Cells of water between the box and the nearer wall, per axis, (dim,) (may be < 0)."""
    lo = np.asarray(grid.origin)
    hi = lo + np.asarray(grid.extent)
    return np.minimum(bounds[0] - lo, hi - bounds[1]) / grid.cell_size


def follow(scene: Scene, state: State, clearance: float, grow: bool = True) -> State:
    """Shift the grid by whole cells to centre the body along every axis where it came
    nearer a wall than ``clearance`` cells; fields move with the grid. Where no shift
    makes room, the grid grows (``grow``, ``GridGrew``) to ``smallest_resolution``
    rounded up to ``GROWTH_MULTIPLE`` cells along those axes, centred on the body.

    Raises:
        BodyOutsideGrid: the body is too large for the grid along some axis, and
            ``grow`` is off.
    """
    grid = state.grid
    bounds = body_bounds(scene, state.qpos)
    space = room(grid, bounds)
    if not np.all(space >= 0):  # at the step's start it was `clearance` cells inside
        raise SimulationDiverged(
            f"simulation diverged at t = {state.time:.4g} s: in one step the body crossed "
            f"{clearance:g} cells of water and a wall of the grid, far beyond the CFL limit; "
            "lower the torques (the gait's amplitudes or the PD gains), or check the model's masses"
        )
    near = space < clearance
    if not near.any():
        return state
    needed = np.asarray(smallest_resolution(bounds, grid.cell_size, clearance))
    shape = np.asarray(grid.shape)
    small = near & (needed > shape)
    if small.any():
        if not grow:
            raise BodyOutsideGrid(
                f"at t = {state.time:.4g} s the body ({_sides(bounds)} m) no longer fits in "
                f"the {_cells(grid.shape)} grid of {grid.cell_size:g} m cells with "
                f"{clearance:g} cells of water on every side; use at least "
                f"{_cells(np.maximum(needed, shape))} cells (--resolution), "
                "or larger cells (--cell-size)"
            )
        shape = np.where(small, -(-needed // GROWTH_MULTIPLE) * GROWTH_MULTIPLE, shape)
        near = near | small
    centre = 0.5 * (bounds[0] + bounds[1])
    corner = centre - 0.5 * shape * grid.cell_size  # the lower corner that centres the body
    offset = np.round((corner - np.asarray(grid.origin)) / grid.cell_size)
    cells = tuple(int(c) for c in np.where(near, offset, 0))
    moved, velocity, pressure = regrid(grid, state.velocity, cells, shape, state.pressure)
    if small.any():
        warnings.warn(
            GridGrew(
                f"at t = {state.time:.4g} s the body ({_sides(bounds)} m) outgrew the "
                f"{_cells(grid.shape)} grid of {grid.cell_size:g} m cells: it grew to "
                f"{_cells(moved.shape)}, still water added where the open boundary assumed it "
                f"({moved.cell_count / grid.cell_count:.2f}x the cells, and the time a step)"
            ),
            stacklevel=2,
        )
    return replace(state, grid=moved, velocity=velocity, pressure=pressure)


@contextmanager
def growth_notes():
    """Collect the ``GridGrew`` warnings of the swims within: yields the list their messages
    go into, for a run's notes; other warnings pass on as before."""
    notes = []
    with warnings.catch_warnings():
        warnings.simplefilter("always", GridGrew)
        previous = warnings.showwarning

        def note(message, category, *where, **more):
            if issubclass(category, GridGrew):
                notes.append(str(message))
            else:
                previous(message, category, *where, **more)

        warnings.showwarning = note
        yield notes


def check_room(model: Model, grid: Grid, clearance: float) -> None:
    """Refuse a grid that cannot hold the creature at its reference pose with the clearance.

    Raises:
        ValueError: naming the smallest resolution around the same centre that
            would do (``make_scene`` centres the grid on the creature's centre
            of mass unless given an origin).
    """
    bounds = model.bounds[:, : model.dim]
    if np.all(room(grid, bounds) >= clearance):
        return
    centre = np.asarray(grid.origin) + 0.5 * np.asarray(grid.extent)
    around = cells_around(bounds, centre, grid.cell_size, clearance)
    needed = tuple(max(n, m) for n, m in zip(grid.shape, around, strict=True))
    raise ValueError(
        f"the {_cells(grid.shape)} grid of {grid.cell_size:g} m cells cannot hold "
        f"{model.source} ({_sides(bounds)} m) with {clearance:g} cells of water on every "
        f"side: use at least {_cells(needed)} cells around the same centre (--resolution), "
        "larger cells (--cell-size), or another origin"
    )


def cells_around(bounds: np.ndarray, centre, cell_size: float, clearance: float) -> tuple:
    """Cells per axis of the smallest grid centred on ``centre`` that holds a box of these
    bounds, (2, dim) [m], with ``clearance`` cells of water on either side."""
    half = np.maximum(np.asarray(centre) - bounds[0], bounds[1] - np.asarray(centre))
    return tuple(math.ceil(2 * x / cell_size + 2 * clearance - 1e-9) for x in half)


def cells_for(sides, cell_size: float, clearance: float) -> tuple:
    """Cells per axis of the smallest grid that holds a box with these sides (dim,) [m],
    centred, with ``clearance`` cells of water on either side."""
    sides = np.asarray(sides, dtype=float)
    return cells_around(np.stack([0 * sides, sides]), sides / 2, cell_size, clearance)


def smallest_resolution(bounds: np.ndarray, cell_size: float, clearance: float) -> tuple:
    """Cells per axis that hold a box of these bounds with ``clearance`` cells on each side,
    wherever the whole-cell shifts leave it (one cell more than the box and clearances)."""
    centred = cells_around(bounds, bounds.mean(axis=0), cell_size, clearance)
    return tuple(n + 1 for n in centred)


def _cells(shape) -> str:
    return "x".join(str(int(n)) for n in shape)


def _sides(bounds: np.ndarray) -> str:
    return " x ".join(f"{s:.3g}" for s in bounds[1] - bounds[0])
