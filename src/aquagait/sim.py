"""Simulation: a fixed ``Scene``, a changing ``State``, ``step`` and ``rollout`` (DESIGN.md §3, §4).

Only ``fluid="none"`` (vacuum) exists so far: the body moves under its own
joint forces alone, which is enough to test the body half on its own. The
Euler fluid and the simple drag model come later and will add phases to
``step`` (voxelize, advect, coupled solve); a new scheme is a new function.

The controller seam (STYLE.md §6). A *policy* is any callable

    policy(t, q, qd) -> tau    # (nv,) generalized force [N or N m]

applied over the step. Plain callables are explicit: ``tau`` is evaluated at
the start of the step. A policy may also carry ``damping``, (nv,) diagonal
gains Kd [N m s/rad]; the step then treats it as a servo evaluated at the end
of the step (the stable PD of Tan et al. 2011, paper §3.2): it calls
``policy(t + dt, q + dt qd, qd)`` and solves

    (M + dt Kd) qdd = tau - c

so that with ``tau = -Kp (q - qbar) - Kd qd`` it is exactly DESIGN.md §2.2.
The force actually applied is ``tau - dt Kd qdd``; the step records it and
adds ``|tau_i qd_i| dt`` per DOF to the energy. ``policy=None`` applies
nothing. ``aquagait.control`` provides such policies; this module never
imports it.

Time integration is semi-implicit Euler: ``qd += dt qdd``, then ``q`` moves
with the new ``qd`` (quaternions on the unit sphere).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from aquagait.body.dynamics import Dynamics
from aquagait.body.model import Model
from aquagait.grid import Grid

FLUIDS_NOW = ("none",)
FLUIDS_LATER = ("euler", "simple")
FRAMES_PER_SECOND = 30


class SimulationDiverged(RuntimeError):
    """The state stopped being finite; the message says when and where."""


@dataclass(frozen=True, eq=False)
class Scene:
    """Everything that stays fixed during a simulation.

    Attributes:
        model: the creature.
        dynamics: its MuJoCo adapter.
        fluid: 'none' (vacuum) for now.
        grid: the fluid grid centred on the creature, or None when no
            resolution and cell size are known (a bare model in vacuum).
        density: fluid density rho [kg/m^3] (water).
    """

    model: Model
    dynamics: Dynamics
    fluid: str = "none"
    grid: Grid | None = None
    density: float = 1000.0


@dataclass(frozen=True, eq=False)
class State:
    """Everything a step changes.

    Attributes:
        time: t [s].
        qpos: (nq,) generalized positions (MuJoCo order) [m, rad, quaternion].
        qvel: (nv,) generalized velocities [m/s, rad/s].
        torque: (nv,) generalized force applied during the last step [N, N m].
        energy: (nv,) actuator work so far, the integral of |tau_i qd_i| dt [J].
        velocity: fluid face velocities (one array per axis) [m/s]; None in vacuum.
        pressure: fluid pressure at cell centres [Pa]; None in vacuum.
    """

    time: float
    qpos: np.ndarray
    qvel: np.ndarray
    torque: np.ndarray
    energy: np.ndarray
    velocity: tuple | None = None
    pressure: np.ndarray | None = None


@dataclass(frozen=True, eq=False)
class FluidFrames:
    """The fluid as recorded once per frame, for pictures and particle traces.

    Always a plane: the whole grid in 2D, the mid-plane z = const through the
    grid's centre in 3D (x-y plane, cell-centred values). F frames, a plane of
    ``nx x ny`` cells.

    Attributes:
        cell_size: h [m].
        origin: (F, 2) world position of the plane's lower corner per frame
            (the grid follows the creature) [m].
        velocity: (F, 2, nx, ny) in-plane velocity at cell centres [m/s].
        solid: (F, nx, ny) cells inside the body.
        plane_z: the plane's world z [m] (0 in 2D).
    """

    cell_size: float
    origin: np.ndarray
    velocity: np.ndarray
    solid: np.ndarray
    plane_z: float = 0.0


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A rollout sampled at ``fps`` frames per second; F frames, the first at the start.

    Attributes:
        time: (F,) [s].
        qpos: (F, nq), qvel: (F, nv), torque: (F, nv) [N m], energy: (F, nv) [J]
            cumulative actuator work per DOF.
        dt: the simulation step used [s].
        fps: frames per second.
        fluid: the fluid per frame, or None in vacuum.
    """

    time: np.ndarray
    qpos: np.ndarray
    qvel: np.ndarray
    torque: np.ndarray
    energy: np.ndarray
    dt: float
    fps: float
    fluid: FluidFrames | None = None


def make_scene(
    creature_or_model, resolution=None, cell_size=None, fluid: str = "none", origin=None
) -> Scene:
    """Build a scene for a creature (or a bare model).

    Args:
        creature_or_model: a ``Model``, or a creature (anything with ``model``,
            ``resolution`` and ``cell_size`` attributes, e.g.
            ``aquagait.creatures.get("eel2d")``).
        resolution: cells per axis, (nx, ny) in 2D or (nx, ny, nz) in 3D;
            default: the creature's.
        cell_size: h [m]; default: the creature's.
        fluid: 'none' (vacuum). 'euler' and 'simple' are planned.
        origin: the grid's lower corner [m], one entry per axis; default: the
            grid is centred on the creature's centre of mass.

    Returns:
        The scene; its grid is None when no resolution and cell size are known.
    """
    model, default_res, default_h = _unpack_creature(creature_or_model)
    if fluid in FLUIDS_LATER:
        raise ValueError(
            f"fluid {fluid!r} is not implemented yet; available now: {', '.join(FLUIDS_NOW)}"
        )
    if fluid not in FLUIDS_NOW:
        raise ValueError(f"unknown fluid {fluid!r}; fluids: {', '.join(FLUIDS_NOW + FLUIDS_LATER)}")
    dynamics = Dynamics(model.mj)
    resolution = default_res if resolution is None else tuple(resolution)
    cell_size = default_h if cell_size is None else cell_size
    grid = None
    if resolution is not None and cell_size is not None:
        if len(resolution) != model.dim:
            raise ValueError(
                f"resolution {resolution} has {len(resolution)} entries but {model.source} is "
                f"{model.dim}D: give (nx, ny{', nz' if model.dim == 3 else ''})"
            )
        if origin is None:
            centre = dynamics.center_of_mass(model.qpos0)[: model.dim]
            origin = centre - np.asarray(resolution) * cell_size / 2
        grid = Grid(shape=resolution, cell_size=cell_size, origin=tuple(origin))
    return Scene(model=model, dynamics=dynamics, fluid=fluid, grid=grid)


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
    return State(time=0.0, qpos=qpos, qvel=qvel, torque=zeros, energy=zeros.copy())


def step(scene: Scene, state: State, dt: float, policy=None) -> State:
    """Advance the scene by one step of ``dt`` [s] (paper Figure 2, vacuum so far).

    Args:
        scene: the fixed scene.
        state: the state at time t.
        dt: time step [s].
        policy: the controller (see the module docstring); None for no actuation.

    Returns:
        The state at t + dt.
    """
    _check_dt(dt)
    tau, damping = servo_forces(scene, state, dt, policy)  # the stable PD: at t + dt
    qdd = predict_body(scene, state, dt, tau, damping)  # (M + dt Kd) qdd = tau - c
    # (later: voxelize, advect, coupled pressure solve correct qvel here)
    qvel = state.qvel + dt * qdd
    qpos = scene.dynamics.integrate(state.qpos, qvel, dt)
    torque, energy = account_work(state, dt, tau, damping, qdd, qvel)
    new = replace(state, time=state.time + dt, qpos=qpos, qvel=qvel, torque=torque, energy=energy)
    return _check_finite(scene, new)


def servo_forces(scene: Scene, state: State, dt: float, policy) -> tuple[np.ndarray, np.ndarray]:
    """The policy's force and implicit damping for this step, each (nv,).

    A policy with ``damping`` is evaluated at the predicted end of the step,
    ``(t + dt, q + dt qd, qd)``; any other at ``(t, q, qd)``.
    """
    nv = scene.model.nv
    if policy is None:
        return np.zeros(nv), np.zeros(nv)
    damping = getattr(policy, "damping", None)
    if damping is None:
        tau, damping = policy(state.time, state.qpos, state.qvel), np.zeros(nv)
    else:
        ahead = scene.dynamics.integrate(state.qpos, state.qvel, dt)
        tau = policy(state.time + dt, ahead, state.qvel)
    tau = np.asarray(tau, dtype=float)
    damping = np.asarray(damping, dtype=float)
    if tau.shape != (nv,) or damping.shape != (nv,):
        raise ValueError(
            f"policy returned tau {tau.shape} and damping {damping.shape}; both must be ({nv},)"
        )
    return tau, damping


def predict_body(scene: Scene, state: State, dt: float, tau, damping) -> np.ndarray:
    """Accelerations qdd (nv,) from ``(M + dt Kd) qdd = tau - c`` (DESIGN.md §2.2, step 2)."""
    dynamics = scene.dynamics
    mass = dynamics.mass_matrix(state.qpos)
    mass[np.diag_indices_from(mass)] += dt * damping
    force = tau - dynamics.bias(state.qpos, state.qvel)
    try:
        qdd = np.linalg.solve(mass, force)
    except np.linalg.LinAlgError:
        qdd = np.full(len(force), np.nan)
    if not np.all(np.isfinite(qdd)):
        raise SimulationDiverged(
            f"simulation diverged at t = {state.time:.4g} s: no finite acceleration "
            f"(|q| up to {np.abs(state.qpos).max():.3g}, |tau| up to {np.abs(tau).max():.3g}); "
            "gains too stiff for dt?"
        )
    return qdd


def account_work(state: State, dt: float, tau, damping, qdd, qvel):
    """The force applied over the step and the energy so far, each (nv,).

    The implicit damping adds ``-dt Kd qdd`` to the policy's force; the work
    is counted as ``|tau_i qd_i| dt`` with the velocity that moves the
    positions, so spending and braking both cost (DESIGN.md §2.4, E_energy).
    """
    applied = tau - dt * damping * qdd
    return applied, state.energy + dt * np.abs(applied * qvel)


def rollout(
    scene: Scene, state: State, policy, seconds: float, dt: float = 1 / 300, fps=FRAMES_PER_SECOND
) -> Trajectory:
    """Simulate ``seconds`` [s] from ``state`` and sample frames.

    Args:
        scene, state, policy: as for ``step``.
        seconds: duration [s].
        dt: largest time step [s]; the step used is the largest that is <= dt
            and divides one frame, so frames fall exactly on k / fps.
        fps: frames per second recorded (DESIGN.md: 30).

    Returns:
        The trajectory, ``round(seconds * fps) + 1`` frames including the start.
    """
    _check_dt(dt)
    if not seconds >= 0:
        raise ValueError(f"seconds must be >= 0, got {seconds}")
    substeps = int(np.ceil((1.0 / fps) / dt - 1e-9))
    dt = 1.0 / fps / substeps
    frames = [state]
    for _ in range(int(round(seconds * fps))):
        for _ in range(substeps):
            state = step(scene, state, dt, policy)
        frames.append(state)
    return Trajectory(
        time=np.array([s.time for s in frames]),
        qpos=np.stack([s.qpos for s in frames]),
        qvel=np.stack([s.qvel for s in frames]),
        torque=np.stack([s.torque for s in frames]),
        energy=np.stack([s.energy for s in frames]),
        dt=dt,
        fps=float(fps),
    )


def _check_dt(dt) -> None:
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"time step dt must be a positive number of seconds, got {dt!r}")


def _check_finite(scene: Scene, state: State) -> State:
    if np.all(np.isfinite(state.qvel)) and np.all(np.isfinite(state.qpos)):
        return state
    bad = np.flatnonzero(~np.isfinite(state.qvel))
    where = ", ".join(scene.model.dof_names[i] for i in bad[:3]) if bad.size else "qpos"
    raise SimulationDiverged(
        f"simulation diverged at t = {state.time:.4g} s: non-finite state at {where} "
        "(gains too stiff for dt? use a stable PD or a smaller dt)"
    )
