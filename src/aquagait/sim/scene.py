"""A fixed ``Scene`` and a changing ``State``, and how to make them (docs/development.md).

The scene holds the creature, its dynamics, the water's density, a grid and
a fluid model (``aquagait.sim.fluids``): ``Vacuum()``, ``SimpleFluid()`` or
``EulerFluid()``; ``make_scene(..., fluid="euler")`` is a shorthand for the
default of each. The fluid model owns what differs between fluids: its
initial fields, its step and its largest stable time step. This module knows
the models only by their protocol and registry (``aquagait.sim.fluid_model``):
the models build on the scene, not the scene on them.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from aquagait.body.dynamics import Dynamics
from aquagait.body.group import Group, member_gaps, refuse_overlap
from aquagait.body.model import Model
from aquagait.body.shape import BodyShape, body_shape
from aquagait.body.surface import Surface, body_surface
from aquagait.grid import Grid
from aquagait.sim.fluid_model import FLUIDS, FluidModel, fluid_model
from aquagait.sim.memory import available_memory, check_memory


@dataclass(frozen=True, eq=False)
class Scene:
    """Everything that stays fixed during a simulation.

    Nothing in a scene changes while it is stepped (scratch space lives in the
    call or the thread), so threads may share one scene.

    Attributes:
        model: the creature.
        dynamics: its MuJoCo adapter.
        fluid: the fluid model, bound to this model and grid (``aquagait.sim.fluids``).
        grid: the fluid grid at the start, centred on the creature, or None
            when no resolution and cell size are known (a bare model in vacuum
            or the simple fluid; there it only frames pictures).
        density: fluid density rho [kg/m^3] (water).
        group: the creatures ``model`` is composed of, when it is a group
            (``aquagait.body.group``; ``aquagait.sim.group``); None for one creature.
    """

    model: Model
    dynamics: Dynamics
    fluid: FluidModel
    grid: Grid | None = None
    density: float = 1000.0
    group: Group | None = None

    @cached_property
    def shape(self) -> BodyShape | None:
        """The links' signed-distance geometry at the grid's cell size (None without a grid).

        Baked on first use (the fish's meshes take about half a second), so
        that the Euler fluid voxelizes and the collision term of the objective
        measures the same body in every fluid.
        """
        return None if self.grid is None else body_shape(self.model, self.grid.cell_size)

    @cached_property
    def gap_geometry(self) -> tuple[tuple[Surface, ...], BodyShape | None]:
        """What ``aquagait.sim.group`` measures the gaps between a group's members on: each
        member's surface patches, in its own links, and the group's shape (the grid's, else
        sampled at a twentieth of the shortest member); ``((), None)`` for one creature."""
        if self.group is None:
            return (), None
        members = self.group.members
        shape = self.shape or body_shape(self.model, min(m.model.body_length for m in members) / 20)
        return tuple(body_surface(m.model) for m in members), shape


@dataclass(frozen=True, eq=False)
class State:
    """Everything a step changes.

    Attributes:
        time: t [s].
        qpos: (nq,) generalized positions (MuJoCo order) [m, rad, quaternion].
        qvel: (nv,) generalized velocities [m/s, rad/s].
        torque: (nv,) generalized force applied during the last step [N, N m].
        energy: (nv,) actuator work so far, the integral of |tau_i qd_i| dt [J].
        steps: time steps taken so far.
        velocity: fluid face velocities (one array per axis) [m/s]; None without a flow.
        pressure: fluid pressure at cell centres [Pa]; None without a flow.
        grid: where the fluid grid is now (it follows the creature); None without a flow.
    """

    time: float
    qpos: np.ndarray
    qvel: np.ndarray
    torque: np.ndarray
    energy: np.ndarray
    steps: int = 0
    velocity: tuple | None = None
    pressure: np.ndarray | None = None
    grid: Grid | None = None


def make_scene(
    creature_or_model,
    resolution=None,
    cell_size=None,
    fluid: str | FluidModel = "none",
    origin=None,
    drag_coefficient: float | None = None,
    density: float = 1000.0,
) -> Scene:
    """Build a scene for a creature (or a bare model).

    Args:
        creature_or_model: a ``Model``, or a creature (anything with ``model``,
            ``resolution`` and ``cell_size`` attributes, e.g.
            ``aquagait.creatures.get("eel2d")``), or a ``Group`` of creatures
            (``aquagait.body.group.compose``; give its resolution and cell size,
            or ``aquagait.sim.group.group_grid`` for one that holds them).
        resolution: cells per axis, (nx, ny) in 2D or (nx, ny, nz) in 3D;
            default: the creature's.
        cell_size: h [m]; default: the creature's.
        fluid: a fluid model (``Vacuum()``, ``SimpleFluid(k)``,
            ``EulerFluid(...)``), or its name: 'none', 'simple' or 'euler'.
            The default is the vacuum, not the water the command line,
            ``prepare_swim`` and ``SwimEnv`` default to, because a bare ``Model``
            has no grid for the Euler fluid: give ``fluid="euler"`` to swim.
        origin: the grid's lower corner [m], one entry per axis; default: the
            grid is centred on the creature's centre of mass.
        drag_coefficient: shorthand for ``SimpleFluid(drag_coefficient)`` with
            ``fluid='simple'``.
        density: fluid density rho [kg/m^3], > 0.

    Returns:
        The scene; its grid is None when no resolution and cell size are known.
    Raises:
        ValueError: an unknown fluid, a grid of the wrong dimension, a fluid
            that needs a grid without one, a grid too small for the creature.
        GridTooLarge: a ValueError (``aquagait.sim.memory``): the fluid on
            this grid would take more memory than the machine has available
            (``FluidModel.memory``); checked before anything is allocated.
        GroupError: a ValueError (``aquagait.body.group``): creatures of a group
            that overlap at their starting poses (which two, how deep).
    """
    group = creature_or_model if isinstance(creature_or_model, Group) else None
    model, default_res, default_h = _unpack_creature(
        creature_or_model if group is None else group.model
    )
    if drag_coefficient is not None:
        if fluid != "simple":
            raise ValueError("drag_coefficient is the simple fluid's: give fluid='simple'")
        fluid = FLUIDS["simple"](drag_coefficient=drag_coefficient)
    fluid = fluid_model(fluid)
    if not (np.isfinite(density) and density > 0):
        raise ValueError(f"density must be a positive number of kg/m^3, got {density!r}")
    dynamics = Dynamics(model.mj)
    resolution = default_res if resolution is None else tuple(resolution)
    cell_size = default_h if cell_size is None else cell_size
    grid = None
    if resolution is not None and cell_size is not None:
        grid = _place_grid(model, dynamics, resolution, cell_size, origin)
        memory = getattr(fluid, "memory", None)  # optional in the protocol
        if memory is not None:
            check_memory(grid, memory(grid), available_memory())  # before any allocation
    scene = Scene(model, dynamics, fluid.bind(model, grid), grid, float(density), group)
    if group is not None:
        surfaces, shape = scene.gap_geometry
        refuse_overlap(
            group, member_gaps(group, shape, surfaces, *dynamics.link_poses(model.qpos0))
        )
    return scene


def _place_grid(model: Model, dynamics: Dynamics, resolution, cell_size, origin) -> Grid:
    if len(resolution) != model.dim:
        raise ValueError(
            f"resolution {resolution} has {len(resolution)} entries but {model.source} is "
            f"{model.dim}D: give (nx, ny{', nz' if model.dim == 3 else ''})"
        )
    if origin is None:
        centre = dynamics.center_of_mass(model.qpos0)[: model.dim]
        origin = centre - np.asarray(resolution) * cell_size / 2
    return Grid(shape=resolution, cell_size=cell_size, origin=tuple(origin))


def _unpack_creature(obj):
    if isinstance(obj, Model):
        return obj, None, None
    if hasattr(obj, "model") and isinstance(obj.model, Model):
        return obj.model, getattr(obj, "resolution", None), getattr(obj, "cell_size", None)
    raise TypeError(
        f"make_scene takes a Model or a creature, got {type(obj).__name__}; for a library "
        "creature use aquagait.creatures.get(name), for a file aquagait.load_model(path)"
    )


def init_state(scene: Scene, qpos=None, qvel=None) -> State:
    """The state at t = 0: the model's reference pose and rest unless given, still fluid.

    Args:
        scene: the scene.
        qpos: (nq,) positions; quaternions must have unit norm. Default ``qpos0``.
        qvel: (nv,) velocities. Default zero.
    """
    model = scene.model
    qpos = model.qpos0.copy() if qpos is None else np.array(qpos, dtype=float)
    qvel = np.zeros(model.nv) if qvel is None else np.array(qvel, dtype=float)
    if qpos.shape != (model.nq,) or qvel.shape != (model.nv,):
        raise ValueError(
            f"qpos {qpos.shape} and qvel {qvel.shape} must be ({model.nq},) and ({model.nv},)"
        )
    for joint in model.joints:
        if joint.kind in ("free", "ball"):
            start = joint.qpos + (3 if joint.kind == "free" else 0)
            norm = np.linalg.norm(qpos[start : start + 4])
            if abs(norm - 1) > 1e-6:
                raise ValueError(
                    f"qpos[{start}:{start + 4}] (quaternion of joint {joint.name!r}) has norm "
                    f"{norm:.6g}; it must be 1"
                )
    zeros = np.zeros(model.nv)
    state = State(time=0.0, qpos=qpos, qvel=qvel, torque=zeros, energy=zeros.copy())
    return scene.fluid.init(scene, state)
