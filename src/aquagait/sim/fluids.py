"""Fluid models: what the water does to the body, each owning its fields, step and time step.

A fluid model is an object passed to ``make_scene`` that keeps the protocol
of ``aquagait.sim.fluid_model`` (its fields at rest, its step, its largest
stable step); this module builds on ``scene``, never the other way.

Three are here, each registered in ``FLUIDS`` by its name. ``Vacuum``: the
body moves under its own joint forces alone. ``SimpleFluid`` (paper §7,
docs/compare-fluids.md): no grid; every surface patch that moves into the still
water feels the quadratic drag ``-k rho A v_n^2 n`` (``aquagait.drag``),
added explicitly to the joint forces of a vacuum step. ``EulerFluid``: the
inviscid fluid of ``aquagait.fluid``, two-way coupled through one pressure
solve (``aquagait.coupling``, paper §3.3); its step reads like the paper's
algorithm box:

    voxelize the links at q^n            solid cells, coupled faces
    advect the fluid                      u* (faces in the body carry its velocity)
    predict the body                      Mt qd* = Mt qd^n + dt (tau - c)
    coupled pressure solve                p, u^{n+1}, qd^{n+1}
    move the body, then the grid          q^{n+1}; whole-cell shifts follow the swimmer
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from numbers import Real
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from aquagait.body.shape import link_thickness
from aquagait.body.subcell import voxelize_subcell
from aquagait.body.surface import Surface, body_surface
from aquagait.body.voxelize import Voxels
from aquagait.coupling import (
    COUPLED_TOLERANCE,
    MOSTLY_WATER,
    CoupledProblem,
    face_area,
    near_body,
    rigid_faces_,
    solve_coupled,
)
from aquagait.drag import DRAG_COEFFICIENT, drag_force
from aquagait.fluid.advection import advect_velocity, bfecc
from aquagait.fluid.pcg import pcg
from aquagait.grid import Grid, max_speed
from aquagait.sim.fluid_model import FLUIDS, FluidModel, fluid_model, register
from aquagait.sim.follow import CLEARANCE, body_bounds, check_room, follow, room
from aquagait.sim.servo import (
    SimulationDiverged,
    SimulationError,
    move_body,
    predict_body,
    servo_forces,
    servo_mass,
)

if TYPE_CHECKING:
    from aquagait.body.model import Model
    from aquagait.sim.scene import Scene, State

__all__ = [
    "FLUIDS",
    "BodyNotOnGrid",
    "EulerFluid",
    "FluidModel",
    "SimpleFluid",
    "Vacuum",
    "fluid_model",
]

NEAR_BODY = 2
"""Faces within this many cells of the body are advected at first order
(``EulerFluid.near_body``). The fish's 2-s swim from rest at 1/270 and 1/540 s
against 1/90 s: -14.1% and -14.4% with BFECC up to the body; -0.3% and -6.5%
with two cells; -4.7% at 1/540 s with one."""

SMALLEST_STEP = 1e-3
"""A CFL step below this fraction of ``dt`` means the flow has blown up."""


@register
@dataclass(frozen=True)
class Vacuum:
    """No fluid: the body under its own joint forces.

    Attributes:
        max_dt: default longest step [s]; the stable PD allows up to about
            1/45 s (``aquagait.control.pd``).
    """

    name: ClassVar[str] = "none"
    max_dt: float = 1 / 300

    def bind(self, model: Model, grid: Grid | None) -> Vacuum:
        """Itself: a vacuum bakes nothing (``FluidModel.bind``)."""
        return self

    def init(self, scene: Scene, state: State) -> State:
        """``state`` unchanged: a vacuum has no fields (``FluidModel.init``)."""
        return state

    def step(self, scene: Scene, state: State, dt: float, policy=None) -> State:
        """The body ``dt`` [s] later under its servo's torques alone (``FluidModel.step``)."""
        tau, damping = servo_forces(scene, state, dt, policy)  # the stable PD: at t + dt
        qdd = predict_body(scene, state, dt, tau, damping)  # (M + dt Kd) qdd = tau - c
        return move_body(scene, state, dt, tau, damping, state.qvel + dt * qdd)

    def longest_step(self, state: State, dt: float) -> float:
        """``dt``: a vacuum sets no stability limit of its own (``FluidModel.longest_step``)."""
        return dt

    def memory(self, grid: Grid) -> int:
        """0 bytes: a vacuum keeps no fields (``FluidModel.memory``)."""
        return 0

    def settings(self) -> dict:
        """No parameters: ``{}`` (``FluidModel.settings``)."""
        return {}


@register
@dataclass(frozen=True)
class SimpleFluid:
    """The paper's simple fluid (§7): quadratic drag on every surface patch, no flow.

    The drag is evaluated at the start of the step (explicit) and joins the
    policy's force; the energy counts only the actuators' work, as in the
    other fluids.

    Attributes:
        drag_coefficient: k of ``-k rho A v_n^2 n`` (``aquagait.drag``), >= 0.
        max_dt: default longest step [s]. The drag is explicit: a patch of
            area A on a link of mass m moving at v loses the fraction
            ``dt k rho A v / m`` of its speed a step, which must stay well
            below 1 (for a neutrally buoyant plate of thickness t,
            ``dt k v / t``: at 1/300 s, 0.1 for the fish's 3 mm tail fin at
            1 m/s). At 1/300 s the eel's and the fish's distance over 2 s are
            1.5% and 2.6% short of their dt -> 0 limit, their energy 2% (first
            order in dt); at 1/90 s they still swim, 7% and 11% short.
        surface: the links' surface patches, baked by ``bind``.
    """

    name: ClassVar[str] = "simple"
    drag_coefficient: float = DRAG_COEFFICIENT
    max_dt: float = 1 / 300
    surface: Surface | None = field(default=None, repr=False, compare=False)

    def __post_init__(self):
        k = self.drag_coefficient
        if not (isinstance(k, Real) and math.isfinite(k) and k >= 0):
            raise ValueError(f"drag_coefficient must be >= 0 and finite, got {k!r}")

    def bind(self, model: Model, grid: Grid | None) -> SimpleFluid:
        """This fluid with the creature's surface patches baked in (``FluidModel.bind``)."""
        return replace(self, surface=body_surface(model))

    def init(self, scene: Scene, state: State) -> State:
        """``state`` unchanged: drag has no fields (``FluidModel.init``)."""
        return state

    def step(self, scene: Scene, state: State, dt: float, policy=None) -> State:
        """The body ``dt`` [s] later under its servo's torques and the drag on every patch
        (``FluidModel.step``)."""
        tau, damping = servo_forces(scene, state, dt, policy)
        drag = drag_force(self.surface, scene.dynamics, state.qpos, state.qvel, scene.density,
                          self.drag_coefficient)  # fmt: skip
        qdd = predict_body(scene, state, dt, tau + drag, damping)
        return move_body(scene, state, dt, tau, damping, state.qvel + dt * qdd)

    def longest_step(self, state: State, dt: float) -> float:
        """``dt``: drag sets no stability limit of its own (``FluidModel.longest_step``)."""
        return dt

    def memory(self, grid: Grid) -> int:
        """0 bytes: drag keeps no fields; its grid only frames pictures (``FluidModel.memory``)."""
        return 0

    def settings(self) -> dict:
        """``{"drag_coefficient": ...}`` (``FluidModel.settings``)."""
        return {"drag_coefficient": self.drag_coefficient}


@register
@dataclass(frozen=True)
class EulerFluid:
    """The inviscid incompressible fluid, two-way coupled with the body (paper §3).

    Attributes:
        advect: the advection scheme (``aquagait.fluid.advection``: ``bfecc``
            or ``semi_lagrangian``).
        solve: the linear solver of the coupled system (``pcg``).
        boundary: how the body meets the grid, ``boundary(shape, grid,
            link_pos, link_rot) -> Voxels``: ``voxelize_subcell`` (faces
            weighted by their water fraction) or ``voxelize`` (the staircase).
        tolerance: the coupled solve's, relative to the fastest speed
            (``aquagait.coupling.COUPLED_TOLERANCE``).
        clearance: cells of water kept between the body and every wall
            (``aquagait.sim.follow``).
        cfl: Courant number: the fastest fluid or body surface moves at most
            this many cells a step.
        max_dt: default longest step [s]: three steps a 1/30 s frame. Gaits
            are ranked, and the library's figures measured, at this step;
            how far a swim moves when it is shortened: docs/method-coupling.md,
            "Step and grid", and ``aquagait check NAME --convergence``.
        dtype: the precision of the fluid's face velocities between steps and in
            advection, ``np.float64`` or ``np.float32``; the coupled pressure
            solve runs in float64 either way (``benchmarks/precision.py`` and
            docs/method-coupling.md, "Single precision", for what float32 buys).
        near_body: faces within this many cells of the body are advected at
            first order (BFECC's own first pass, ``bfecc(first_order=...)``):
            there the field holds the body's velocity, not an advected one, and
            BFECC's correction across it made the fish's swim depend on the
            step (``NEAR_BODY``); -1 corrects everywhere. The scheme is then
            passed ``first_order=`` masks (``bfecc`` and ``semi_lagrangian``
            take them; give -1 with a scheme of your own that does not).
        mostly_water: coupled faces with less water take the body's velocity
            after every solve (``aquagait.coupling.MOSTLY_WATER``; 0: the water
            keeps its own on every face with water).
        grow: a body that outgrows the grid grows it (``aquagait.sim.follow``,
            with a ``GridGrew`` warning); False raises ``BodyOutsideGrid``, as
            an optimization's samples do (a gait that leaves its grid within
            the sample is penalized, not paid for with a larger grid).
        area: a coupled face's area A [m^2], set by ``bind``.
    """

    name: ClassVar[str] = "euler"
    advect: Callable = bfecc
    solve: Callable = pcg
    boundary: Callable = voxelize_subcell
    tolerance: float = COUPLED_TOLERANCE
    clearance: float = CLEARANCE
    cfl: float = 1.0
    max_dt: float = 1 / 90
    dtype: type = np.float64
    near_body: int = NEAR_BODY
    mostly_water: float = MOSTLY_WATER
    grow: bool = True
    area: float | None = field(default=None, repr=False, compare=False)

    def __post_init__(self):
        if not (isinstance(self.near_body, int) and self.near_body >= -1):
            raise ValueError(
                f"near_body must be a whole number of cells >= -1, got {self.near_body!r}"
            )
        if not (isinstance(self.mostly_water, Real) and 0 <= self.mostly_water <= 1):
            raise ValueError(
                f"mostly_water must be a water fraction in [0, 1], got {self.mostly_water!r}"
            )
        if np.dtype(self.dtype) not in PRECISIONS:
            raise ValueError(
                f"EulerFluid(dtype=...) must be np.float64 or np.float32, got {self.dtype!r}"
            )

    def bind(self, model: Model, grid: Grid | None) -> EulerFluid:
        """This fluid with the faces' wetted area for the creature's depth baked in
        (``FluidModel.bind``).

        Raises:
            ValueError: no grid, or one too small to hold the creature with
                ``clearance`` cells of water on every side.
        """
        if grid is None:
            raise ValueError(
                f"fluid 'euler' needs a grid: give resolution and cell_size for {model.source}"
            )
        check_room(model, grid, self.clearance)
        return replace(self, area=face_area(grid, model.depth))

    def init(self, scene: Scene, state: State) -> State:
        """``state`` with still water, the body's faces moving with it, and zero pressure
        (``FluidModel.init``).

        Raises:
            ValueError: the body lies within ``clearance`` cells of the grid's walls.
            BodyNotOnGrid: the boundary finds no cell or face of the grid in the body.
        """
        grid = scene.grid
        if (room(grid, body_bounds(scene, state.qpos)) < self.clearance).any():
            raise ValueError(
                f"the body at the given qpos is less than {self.clearance:g} cells from a wall "
                "of the grid: start it nearer the grid's centre"
            )
        velocity = grid.zeros_velocity(self.dtype)
        voxels = self._voxels(scene, grid, state)
        motion = scene.dynamics.link_motion(state.qpos, state.qvel)
        rigid_faces_(grid, velocity, voxels, motion, self.mostly_water)
        return replace(state, velocity=velocity, pressure=grid.zeros_cells(), grid=grid)

    def step(self, scene: Scene, state: State, dt: float, policy=None) -> State:
        """One two-way coupled step (module docstring; docs/method-coupling.md).

        Raises:
            BodyNotOnGrid: the boundary finds no cell or face of the grid in the body.
        """
        grid, q = state.grid, state.qpos
        grid.check_dt(state.velocity, dt)
        voxels = self._voxels(scene, grid, state)
        first_order = near_body(grid, voxels, self.near_body) if self.near_body >= 0 else None
        advected = advect_velocity(grid, state.velocity, dt, self.advect, first_order)
        tau, damping = servo_forces(scene, state, dt, policy)
        qvel_star = state.qvel + dt * predict_body(scene, state, dt, tau, damping)
        solved = self._coupled_solve(scene, state, voxels, advected, qvel_star, dt, damping)
        motion = scene.dynamics.link_motion(q, solved.qvel)
        rigid_faces_(grid, solved.velocity, voxels, motion, self.mostly_water)
        velocity = tuple(c.astype(self.dtype, copy=False) for c in solved.velocity)
        moved = move_body(scene, state, dt, tau, damping, solved.qvel)
        moved = replace(moved, velocity=velocity, pressure=solved.pressure)
        return follow(scene, moved, self.clearance, self.grow)

    def _voxels(self, scene: Scene, grid: Grid, state: State) -> Voxels:
        voxels = self.boundary(scene.shape, grid, *scene.dynamics.link_poses(state.qpos))
        if voxels.face_count == 0:  # nothing to couple: the water would not see the body
            raise BodyNotOnGrid(_unseen_body(scene, grid, self.boundary, state.time))
        return voxels

    def _coupled_solve(self, scene, state, voxels, advected, qvel_star, dt, damping):
        q = state.qpos
        problem = CoupledProblem(
            grid=state.grid, voxels=voxels, velocity_star=advected, qvel_star=qvel_star,
            mass_t=servo_mass(scene, q, dt, damping),
            jacobians=scene.dynamics.point_jacobians(q, voxels.face_center, voxels.face_link),
            dt=dt, density=scene.density, area=self.area,
        )  # fmt: skip
        return solve_coupled(problem, pressure=state.pressure, tol=self.tolerance, solve=self.solve)

    def longest_step(self, state: State, dt: float) -> float:
        """The CFL step, at most ``dt``.

        Raises:
            SimulationDiverged: the flow grew so fast that the step fell below
                ``SMALLEST_STEP * dt``.
        """
        longest = state.grid.cfl_dt(state.velocity, cfl=self.cfl, max_dt=dt)
        if longest < SMALLEST_STEP * dt:
            raise SimulationDiverged(
                f"simulation diverged at t = {state.time:.4g} s: the fluid reached "
                f"{max_speed(state.velocity):.3g} m/s, which would need steps of "
                f"{longest:.2g} s; lower the torques (the gait's amplitudes or the "
                "PD gains), or check the model's masses"
            )
        return longest

    def memory(self, grid: Grid) -> int:
        """The bytes a swim on ``grid`` holds at its peak: ``BYTES_PER_CELL`` a cell for the
        grid's dimension and this fluid's ``dtype`` (``FluidModel.memory``)."""
        per_cell = BYTES_PER_CELL[grid.dim, np.dtype(self.dtype).itemsize]
        return per_cell * math.prod(grid.shape)

    def settings(self) -> dict:
        """The schemes by name and the numerical parameters (``FluidModel.settings``)."""
        return {
            "advect": getattr(self.advect, "__name__", repr(self.advect)),
            "solve": getattr(self.solve, "__name__", repr(self.solve)),
            "boundary": getattr(self.boundary, "__name__", repr(self.boundary)),
            "tolerance": self.tolerance,
            "clearance": self.clearance,
            "cfl": self.cfl,
            "dtype": np.dtype(self.dtype).name,
            "near_body": self.near_body,
            "mostly_water": self.mostly_water,
            "grow": self.grow,
        }


PRECISIONS = (np.dtype(np.float64), np.dtype(np.float32))
"""The precisions ``EulerFluid`` keeps its face velocities in."""

BYTES_PER_CELL = {(2, 8): 340, (2, 4): 285, (3, 8): 380, (3, 4): 320}
"""The memory a grid cell takes at the peak of an Euler swim [bytes], by (dimension, bytes
of the face velocities' dtype): the fields, the coupled solve's vectors, the multigrid's
levels, the advection's scratch, the voxels. Measured over 2-s swims of the default gait
from rest (tracemalloc's peak, and the rise of the process's peak RSS after a warm-up:
the larger): fish in float64 376 a cell on 128x64x64 and 370 on 192x96x96 (367 a cell
between them), in float32 316 on 128x64x64; eel2d in float64 329 on 1024x512 and 328 on
2048x1024 (327 between; 335 on 1024x512 with thin parts closed), in float32 281 on
1024x512. The first five steps peak 8-10 % lower. Not counted: the frames a rollout
records, and a grid that grows."""


class BodyNotOnGrid(SimulationError):
    """The fluid's boundary found no cell or face of the grid inside the body: the water
    would not see it. The staircase (``voxelize``) makes a cell solid only where its centre
    lies in a part, so a body thinner than a cell can fall between the centres."""


def _unseen_body(scene: Scene, grid: Grid, boundary, time: float) -> str:
    """What ``BodyNotOnGrid`` says: the parts and their thickness, the cell, what would work."""
    h, shape = grid.cell_size, scene.shape
    thickness = link_thickness(shape)
    parts = sorted(np.flatnonzero(shape.dims[:, 0] > 0), key=lambda k: thickness[k])
    listed = ", ".join(
        f"{shape.links[k]} ({1e3 * thickness[k]:.3g} mm thick, {thickness[k] / h:.2g} cells)"
        for k in parts[:4]
    ) + (f" and {len(parts) - 4} more" if len(parts) > 4 else "")
    thinnest = thickness[parts[0]] if parts else 0.0
    return (
        f"at t = {time:.4g} s the fluid boundary {getattr(boundary, '__name__', boundary)!r} "
        f"puts no cell or face of the {h:g} m grid inside {scene.model.source}, so the water "
        f"would not feel it: {listed}. The staircase (voxelize) makes a cell solid only "
        f"where its centre lies in a part; give cells of at most {1e3 * thinnest / 2:.3g} mm "
        "(two across the thinnest part, --cell-size), or the default sub-cell boundary "
        "(EulerFluid(), boundary=voxelize_subcell), which sees a part thinner than a cell in "
        "its faces"
    )
