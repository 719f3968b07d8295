"""Simulation: a fixed ``Scene``, a changing ``State``, ``step`` and ``rollout``.

    scene   = make_scene(creature, fluid=EulerFluid())   # or fluid="euler" | "simple" | "none"
    state   = init_state(scene)
    state   = step(scene, state, dt, policy)
    traj    = rollout(scene, state, policy, seconds)

Modules, one concept each: ``scene`` (Scene, State, make_scene, init_state),
``fluid_model`` (what a fluid model is, and the registry ``FLUIDS``),
``memory`` (a grid whose fluid would not fit in memory is refused),
``fluids`` (the fluid models Vacuum, SimpleFluid and EulerFluid, each owning
its fields, its step and its largest stable step), ``servo`` (the body's half
of every step: the policy seam and the stable PD), ``follow`` (the grid that
follows the swimmer), ``rollout`` (step, advance, rollout, Trajectory),
``inertia`` (each DOF's inertia in its fluid, added mass included),
``frames`` (the fluid recorded per frame) and ``particles`` (traces through
the recorded flow, for pictures and exports). Where ``sim`` sits among the
layers, and why a fixed scene and a changing state: docs/development.md.
"""

from aquagait.sim.fluids import (
    FLUIDS,
    BodyNotOnGrid,
    EulerFluid,
    FluidModel,
    SimpleFluid,
    Vacuum,
    fluid_model,
)
from aquagait.sim.follow import CLEARANCE, BodyOutsideGrid, GridGrew, growth_notes
from aquagait.sim.frames import FluidFrames
from aquagait.sim.inertia import inertia_in_fluid
from aquagait.sim.memory import GridTooLarge
from aquagait.sim.rollout import FRAMES_PER_SECOND, Trajectory, advance, rollout, step
from aquagait.sim.scene import Scene, State, init_state, make_scene
from aquagait.sim.servo import SimulationDiverged, SimulationError

__all__ = [
    "CLEARANCE",
    "FLUIDS",
    "FRAMES_PER_SECOND",
    "BodyNotOnGrid",
    "BodyOutsideGrid",
    "EulerFluid",
    "FluidFrames",
    "FluidModel",
    "GridGrew",
    "GridTooLarge",
    "Scene",
    "SimpleFluid",
    "SimulationDiverged",
    "SimulationError",
    "State",
    "Trajectory",
    "Vacuum",
    "advance",
    "fluid_model",
    "growth_notes",
    "inertia_in_fluid",
    "init_state",
    "make_scene",
    "rollout",
    "step",
]
