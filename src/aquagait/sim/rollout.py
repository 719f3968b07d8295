"""Stepping through time: one ``step``, ``advance`` to a time, ``rollout`` into a ``Trajectory``.

``rollout`` takes the largest steps the fluid model allows (at most ``dt``;
in the Euler fluid also the CFL limit) and lands exactly on its frames.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from aquagait.sim.frames import FluidFrames, fluid_frame, fluid_frames, stride
from aquagait.sim.group import check_apart
from aquagait.sim.scene import Scene, State

FRAMES_PER_SECOND = 30
"""Frames a ``rollout`` records per second unless told (``fps``)."""


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A rollout sampled at ``fps`` frames per second; F frames, the first at the start.

    Attributes:
        time: (F,) [s].
        qpos: (F, nq), qvel: (F, nv), torque: (F, nv) [N m], energy: (F, nv) [J]
            cumulative actuator work per DOF.
        dt: the largest simulation step allowed [s] (fluid steps may be shorter).
        fps: frames per second.
        fluid: the fluid per frame, or None without a flow.
    """

    time: np.ndarray
    qpos: np.ndarray
    qvel: np.ndarray
    torque: np.ndarray
    energy: np.ndarray
    dt: float
    fps: float
    fluid: FluidFrames | None = None


def step(scene: Scene, state: State, dt: float, policy=None) -> State:
    """Advance the scene by one step of ``dt`` [s] (paper Figure 2).

    Args:
        scene: the fixed scene.
        state: the state at time t.
        dt: time step [s]; in the Euler fluid it must respect the CFL limit
            (see ``rollout``, which picks it).
        policy: the controller (``aquagait.sim.servo``); None for no actuation.

    Returns:
        The state at t + dt.
    Raises:
        aquagait.sim.SimulationError: the simulation cannot go on (it diverged,
            the body outgrew the grid, or two creatures of a group touched:
            ``aquagait.sim.group.CreaturesTouched``); the message says when and why.
    """
    _check_dt(dt)
    state = scene.fluid.step(scene, state, dt, policy)
    check_apart(scene, state)
    return state


def rollout(
    scene: Scene,
    state: State,
    policy,
    seconds: float,
    dt: float | None = None,
    fps=FRAMES_PER_SECOND,
    progress=None,
    record_fluid: bool = True,
    plan=None,
) -> Trajectory:
    """Simulate ``seconds`` [s] from ``state`` and sample frames.

    Args:
        scene: the fixed scene, as for ``step``.
        state: the state to start from.
        policy: the controller, as for ``step`` (``aquagait.sim.servo``).
        seconds: duration [s].
        dt: largest time step [s]; default the fluid model's ``max_dt``. In
            the Euler fluid, steps also keep to the CFL limit (the fastest
            fluid or body surface moves at most one cell). Steps are shortened
            so that frames fall exactly on k / fps.
        fps: frames per second recorded (30 by default, as docs/swim.md says).
        progress: optional ``progress(frames_done, frames_total)``, called
            after every frame (for progress bars).
        record_fluid: keep the fluid of every frame (for pictures);
            off when only the body matters, as in optimization.
        plan: optional ``plan(state) -> policy``, asked at the start of every
            frame; the policy it returns drives the steps to the next frame
            (a path follower chooses its manoeuvre this way; ``policy`` is
            then unused).

    Returns:
        The trajectory, ``round(seconds * fps) + 1`` frames including the start;
        in the Euler fluid it carries the fluid of every frame (the
        simple fluid has no flow to record).
    Raises:
        aquagait.sim.SimulationError: as ``step``; also when the flow grew so
            fast that the CFL step fell below a thousandth of ``dt``.
    """
    dt = scene.fluid.max_dt if dt is None else dt
    _check_dt(dt)
    if not seconds >= 0:
        raise ValueError(f"seconds must be >= 0, got {seconds}")
    total = int(round(seconds * fps))
    start = state.time
    has_flow = record_fluid and state.velocity is not None
    blocks = 1 if not has_flow or state.grid.dim == 2 else stride(state.grid.shape)
    frames = [_small(state)]  # a frame's fluid is recorded as it comes, not kept whole
    fluid = [fluid_frame(scene, state, blocks)] if has_flow else None
    for k in range(1, total + 1):
        if plan is not None:
            policy = plan(state)
        state = advance(scene, state, policy, start + k / fps, dt)
        frames.append(_small(state))
        if has_flow:
            fluid.append(fluid_frame(scene, state, blocks))
        if progress is not None:
            progress(k, total)
    return Trajectory(
        time=np.array([s.time for s in frames]),
        qpos=np.stack([s.qpos for s in frames]),
        qvel=np.stack([s.qvel for s in frames]),
        torque=np.stack([s.torque for s in frames]),
        energy=np.stack([s.energy for s in frames]),
        dt=dt,
        fps=float(fps),
        fluid=fluid_frames(state.grid.cell_size, fluid, blocks) if has_flow else None,
    )


def _small(state: State) -> State:
    """The state without its fields: what a trajectory keeps of a frame."""
    return replace(state, velocity=None, pressure=None)


def advance(scene: Scene, state: State, policy, end: float, dt: float | None = None) -> State:
    """Step until time ``end`` [s] with steps no longer than ``dt`` or the fluid's limit.

    The steps before each re-evaluation of the limit are equal, so the last
    one lands exactly on ``end``. ``dt`` defaults to the fluid model's
    ``max_dt``. Raises as ``rollout``.
    """
    dt = scene.fluid.max_dt if dt is None else dt
    _check_dt(dt)
    while end - state.time > 1e-12 * max(1.0, end):
        longest = scene.fluid.longest_step(state, dt)
        count = int(np.ceil((end - state.time) / longest - 1e-9))
        state = step(scene, state, (end - state.time) / count, policy)
    return replace(state, time=end)  # no round-off drift between frames


def _check_dt(dt) -> None:
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"time step dt must be a positive number of seconds, got {dt!r}")
