"""Simulation: a fixed ``Scene``, a changing ``State``, ``step`` and ``rollout`` (DESIGN.md §3, §4).

Three fluids. ``fluid="none"`` (vacuum): the body moves under its own
joint forces alone. ``fluid="simple"`` (paper §7, DESIGN.md §2.6): no grid;
every surface patch that moves into the still water feels the quadratic drag
``-k rho A v_n^2 n`` (``aquagait.drag``), added explicitly to the joint forces
of a vacuum step (``simple_step``). ``fluid="euler"``: the body swims in the
inviscid fluid of ``aquagait.fluid``, two-way coupled through one pressure
solve (``aquagait.coupling``, paper §3.3). One coupled step reads like the
paper's algorithm box (``euler_step``):

    voxelize the links at q^n            solid cells, coupled faces
    advect the fluid                      u* (faces in the body carry its velocity)
    predict the body                      Mt qd* = Mt qd^n + dt (tau - c)
    coupled pressure solve                p, u^{n+1}, qd^{n+1}
    move the body (and the grid)          q^{n+1}; whole-cell shifts follow the swimmer

The controller seam (STYLE.md §6). A *policy* is any callable

    policy(t, q, qd) -> tau    # (nv,) generalized force [N or N m]

applied over the step. Plain callables are explicit: ``tau`` is evaluated at
the start of the step. A policy may also carry ``damping``, (nv,) diagonal
gains Kd [N m s/rad]; the step then treats it as a servo evaluated at the end
of the step (the stable PD of Tan et al. 2011, paper §3.2): it calls
``policy(t + dt, q + dt qd, qd)`` and solves

    (M + dt Kd) qdd = tau - c

so that with ``tau = -Kp (q - qbar) - Kd qd`` it is exactly DESIGN.md §2.2.
The force actually applied is ``tau - Kd (qd^{n+1} - qd^n)``; the step records
it and adds ``|tau_i qd_i| dt`` per DOF to the energy. ``policy=None`` applies
nothing. ``aquagait.control`` provides such policies; this module never
imports it.

Time integration is semi-implicit Euler: ``qd += dt qdd``, then ``q`` moves
with the new ``qd`` (quaternions on the unit sphere). ``rollout`` takes the
largest steps the CFL condition allows (at most ``dt``) and lands exactly on
its frames.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from aquagait.body.dynamics import Dynamics
from aquagait.body.model import Model
from aquagait.body.surface import Surface, body_surface
from aquagait.body.voxelize import BodyShape, Voxels, body_shape, voxelize
from aquagait.coupling import face_area, rigid_faces_, solve_coupled
from aquagait.drag import DRAG_COEFFICIENT, drag_force
from aquagait.fluid.advection import advect_velocity
from aquagait.fluid.operators import cell_centered
from aquagait.fluid.shift import recentre_offset, shift
from aquagait.grid import Grid, max_speed

FLUIDS_NOW = ("none", "euler", "simple")
FLUIDS_LATER = ()
FRAMES_PER_SECOND = 30
CFL = 1.0
"""Courant number of the coupled steps ``rollout`` takes."""

MAX_DT = {"none": 1 / 300, "euler": 1 / 90, "simple": 1 / 300}
"""Default longest step [s]. In the fluid, three steps a frame: against steps of
1/300 s, the eel's and the fish's distance over 1.5-2 s differ by 0.9% and
1.3%, their energy by 4% and 9% (first order in dt); the stable PD allows up
to about 1/45 s (``aquagait.control.pd``). The simple fluid's drag is
explicit: a patch of area A on a link of mass m moving at v loses the fraction
``dt k rho A v / m`` of its speed a step, which must stay well below 1 (for a
neutrally buoyant plate of thickness t, ``dt k v / t``: at 1/300 s, 0.1 for the
fish's 3 mm tail fin at 1 m/s). At 1/300 s the eel's and the fish's distance
over 2 s are 1.5% and 2.6% short of their dt -> 0 limit, their energy 2%
(first order in dt); at 1/90 s they still swim, 7% and 11% short."""

SMALLEST_STEP = 1e-3
"""A CFL step below this fraction of ``dt`` means the flow has blown up."""


class SimulationDiverged(RuntimeError):
    """The state stopped being finite; the message says when and where."""


@dataclass(frozen=True, eq=False)
class Scene:
    """Everything that stays fixed during a simulation.

    Attributes:
        model: the creature.
        dynamics: its MuJoCo adapter.
        fluid: 'none' (vacuum), 'euler' or 'simple' (module docstring).
        grid: the fluid grid at the start, centred on the creature, or None
            when no resolution and cell size are known (a bare model in vacuum
            or the simple fluid; there it only frames pictures).
        density: fluid density rho [kg/m^3] (water).
        shape: the links' geometry for voxelizing (Euler fluid; the simple
            fluid keeps it when it has a grid, so that the objective's
            collision term sees the same shape in both fluids).
        area: a coupled face's area A [m^2] (Euler fluid only).
        surface: the links' surface patches (simple fluid only).
        drag_coefficient: k of the simple fluid's drag ``-k rho A v_n^2 n``.
    """

    model: Model
    dynamics: Dynamics
    fluid: str = "none"
    grid: Grid | None = None
    density: float = 1000.0
    shape: BodyShape | None = None
    area: float | None = None
    surface: Surface | None = None
    drag_coefficient: float = DRAG_COEFFICIENT


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
        velocity: fluid face velocities (one array per axis) [m/s]; None in vacuum.
        pressure: fluid pressure at cell centres [Pa]; None in vacuum.
        grid: where the fluid grid is now (it follows the creature); None in vacuum.
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
        dt: the largest simulation step allowed [s] (fluid steps may be shorter).
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
    creature_or_model,
    resolution=None,
    cell_size=None,
    fluid: str = "none",
    origin=None,
    drag_coefficient: float = DRAG_COEFFICIENT,
) -> Scene:
    """Build a scene for a creature (or a bare model).

    Args:
        creature_or_model: a ``Model``, or a creature (anything with ``model``,
            ``resolution`` and ``cell_size`` attributes, e.g.
            ``aquagait.creatures.get("eel2d")``).
        resolution: cells per axis, (nx, ny) in 2D or (nx, ny, nz) in 3D;
            default: the creature's.
        cell_size: h [m]; default: the creature's.
        fluid: 'none' (vacuum), 'euler' (the coupled inviscid fluid) or
            'simple' (surface drag only; needs no grid).
        origin: the grid's lower corner [m], one entry per axis; default: the
            grid is centred on the creature's centre of mass.
        drag_coefficient: k of the simple fluid (``aquagait.drag``), >= 0.

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
    if fluid == "none":
        return Scene(model=model, dynamics=dynamics, fluid=fluid, grid=grid)
    if fluid == "simple":
        if not (np.isfinite(drag_coefficient) and drag_coefficient >= 0):
            raise ValueError(f"drag_coefficient must be >= 0, got {drag_coefficient!r}")
        shape = None if grid is None else body_shape(model, grid.cell_size)
        return Scene(
            model, dynamics, fluid, grid, shape=shape, surface=body_surface(model),
            drag_coefficient=float(drag_coefficient),
        )  # fmt: skip
    if grid is None:
        raise ValueError(
            f"fluid {fluid!r} needs a grid: give resolution and cell_size for {model.source}"
        )
    shape = body_shape(model, grid.cell_size)
    area = face_area(grid, model.depth)
    return Scene(model, dynamics, fluid, grid, shape=shape, area=area)


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
    if scene.fluid != "euler":
        return state  # no fluid fields to hold
    grid = scene.grid
    velocity = grid.zeros_velocity()
    rigid_faces_(grid, velocity, _voxels(scene, grid, qpos), _point_velocity(scene, qpos, qvel))
    return replace(state, velocity=velocity, pressure=grid.zeros_cells(), grid=grid)


def step(scene: Scene, state: State, dt: float, policy=None) -> State:
    """Advance the scene by one step of ``dt`` [s] (paper Figure 2).

    Args:
        scene: the fixed scene.
        state: the state at time t.
        dt: time step [s]; in a fluid it must respect the CFL limit (see
            ``rollout``, which picks it).
        policy: the controller (see the module docstring); None for no actuation.

    Returns:
        The state at t + dt.
    """
    _check_dt(dt)
    return _STEPPERS[scene.fluid](scene, state, dt, policy)


def vacuum_step(scene: Scene, state: State, dt: float, policy=None) -> State:
    """One step with no fluid: the body under its own joint forces."""
    tau, damping = servo_forces(scene, state, dt, policy)  # the stable PD: at t + dt
    qdd = predict_body(scene, state, dt, tau, damping)  # (M + dt Kd) qdd = tau - c
    qvel = state.qvel + dt * qdd
    return _move_body(scene, state, dt, tau, damping, qvel)


def simple_step(scene: Scene, state: State, dt: float, policy=None) -> State:
    """One step in the simple fluid: a vacuum step with the surface drag added (DESIGN.md §2.6).

    The drag is evaluated at the start of the step (explicit; see ``MAX_DT``)
    and joins the policy's force in ``predict_body``; the energy counts only
    the actuators' work, as in the other fluids.
    """
    tau, damping = servo_forces(scene, state, dt, policy)
    drag = drag_force(scene.surface, scene.dynamics, state.qpos, state.qvel, scene.density,
                      scene.drag_coefficient)  # fmt: skip
    qdd = predict_body(scene, state, dt, tau + drag, damping)
    qvel = state.qvel + dt * qdd
    return _move_body(scene, state, dt, tau, damping, qvel)


def euler_step(scene: Scene, state: State, dt: float, policy=None) -> State:
    """One two-way coupled step in the inviscid fluid (module docstring, DESIGN.md §2.3)."""
    grid, q = state.grid, state.qpos
    grid.check_dt(state.velocity, dt)
    voxels = _voxels(scene, grid, q)
    advected = advect_velocity(grid, state.velocity, dt)
    tau, damping = servo_forces(scene, state, dt, policy)
    qvel_star = state.qvel + dt * predict_body(scene, state, dt, tau, damping)
    solved = _coupled_solve(scene, state, voxels, advected, qvel_star, dt, damping)
    rigid_faces_(grid, solved.velocity, voxels, _point_velocity(scene, q, solved.qvel))
    moved = _move_body(scene, state, dt, tau, damping, solved.qvel)
    return _follow(scene, replace(moved, velocity=solved.velocity, pressure=solved.pressure))


_STEPPERS = {"none": vacuum_step, "euler": euler_step, "simple": simple_step}


def _coupled_solve(scene, state, voxels, advected, qvel_star, dt, damping):
    q = state.qpos
    jacobians = scene.dynamics.point_jacobians(q, voxels.face_center, voxels.face_link)
    return solve_coupled(
        state.grid, voxels, advected, qvel_star, servo_mass(scene, q, dt, damping), jacobians,
        dt, scene.density, scene.area, pressure=state.pressure,
    )  # fmt: skip


def _move_body(scene: Scene, state: State, dt: float, tau, damping, qvel) -> State:
    """``q^{n+1}`` from ``qd^{n+1}``, the force applied and the work done."""
    qpos = scene.dynamics.integrate(state.qpos, qvel, dt)
    torque, energy = account_work(state, dt, tau, damping, qvel)
    new = replace(
        state, time=state.time + dt, qpos=qpos, qvel=qvel, torque=torque, energy=energy,
        steps=state.steps + 1,
    )  # fmt: skip
    return _check_finite(scene, new)


def _voxels(scene: Scene, grid: Grid, q) -> Voxels:
    return voxelize(scene.shape, grid, *scene.dynamics.link_poses(q))


def _point_velocity(scene: Scene, q, qd):
    """The rigid velocity of points moving with links: the body-to-fluid seam."""
    return lambda points, links: scene.dynamics.point_velocities(q, qd, points, links)


def _follow(scene: Scene, state: State) -> State:
    """Shift the grid by whole cells when the creature nears a wall (paper §6)."""
    grid = state.grid
    centre = scene.dynamics.center_of_mass(state.qpos)[: grid.dim]
    cells = recentre_offset(grid, centre, margin=min(grid.extent) / 4)
    if not any(cells):
        return state
    moved, velocity, pressure = shift(grid, state.velocity, cells, state.pressure)
    rigid_faces_(moved, velocity, _voxels(scene, moved, state.qpos),
                 _point_velocity(scene, state.qpos, state.qvel))  # fmt: skip
    return replace(state, grid=moved, velocity=velocity, pressure=pressure)


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


def servo_mass(scene: Scene, q, dt: float, damping) -> np.ndarray:
    """``Mt = M(q) + dt Kd``, (nv, nv): the mass the stable PD's implicit damping adds to."""
    mass = scene.dynamics.mass_matrix(q)
    mass[np.diag_indices_from(mass)] += dt * damping
    return mass


def predict_body(scene: Scene, state: State, dt: float, tau, damping) -> np.ndarray:
    """Accelerations qdd (nv,) from ``(M + dt Kd) qdd = tau - c`` (DESIGN.md §2.2, step 2)."""
    mass = servo_mass(scene, state.qpos, dt, damping)
    force = tau - scene.dynamics.bias(state.qpos, state.qvel)
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


def account_work(state: State, dt: float, tau, damping, qvel):
    """The force applied over the step and the energy so far, each (nv,).

    The implicit damping adds ``-Kd (qd^{n+1} - qd^n)`` to the policy's force
    (``-dt Kd qdd``); the work is counted as ``|tau_i qd_i| dt`` with the
    velocity that moves the positions, so spending and braking both cost
    (DESIGN.md §2.4, E_energy).
    """
    applied = tau - damping * (qvel - state.qvel)
    return applied, state.energy + dt * np.abs(applied * qvel)


def rollout(
    scene: Scene,
    state: State,
    policy,
    seconds: float,
    dt: float | None = None,
    fps=FRAMES_PER_SECOND,
    progress=None,
    record_fluid: bool = True,
) -> Trajectory:
    """Simulate ``seconds`` [s] from ``state`` and sample frames.

    Args:
        scene, state, policy: as for ``step``.
        seconds: duration [s].
        dt: largest time step [s]; default ``MAX_DT[scene.fluid]``. In a
            fluid, steps also keep to the CFL limit (the fastest fluid or body
            surface moves at most one cell). Steps are shortened so that frames
            fall exactly on k / fps.
        fps: frames per second recorded (DESIGN.md: 30).
        progress: optional ``progress(frames_done, frames_total)``, called
            after every frame (for progress bars).
        record_fluid: keep the fluid plane of every frame (for pictures);
            off when only the body matters, as in optimization.

    Returns:
        The trajectory, ``round(seconds * fps) + 1`` frames including the start;
        in the Euler fluid it carries the fluid plane of every frame (the
        simple fluid has no flow to record).
    Raises:
        SimulationDiverged: the state stopped being finite, or the flow grew so
            fast that the CFL step fell below ``SMALLEST_STEP * dt``.
    """
    dt = MAX_DT[scene.fluid] if dt is None else dt
    _check_dt(dt)
    if not seconds >= 0:
        raise ValueError(f"seconds must be >= 0, got {seconds}")
    total = int(round(seconds * fps))
    start = state.time
    frames = [state]
    for k in range(1, total + 1):
        state = advance(scene, state, policy, start + k / fps, dt)
        frames.append(state)
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
        fluid=_fluid_frames(scene, frames) if record_fluid and scene.fluid == "euler" else None,
    )


def advance(scene: Scene, state: State, policy, end: float, dt: float | None = None) -> State:
    """Step until time ``end`` [s] with steps no longer than ``dt`` or the CFL limit.

    The steps before each re-evaluation of the CFL limit are equal, so the
    last one lands exactly on ``end``. ``dt`` defaults to ``MAX_DT[scene.fluid]``.
    Raises ``SimulationDiverged`` as ``rollout``.
    """
    dt = MAX_DT[scene.fluid] if dt is None else dt
    _check_dt(dt)
    while end - state.time > 1e-12 * max(1.0, end):
        longest = dt
        if state.velocity is not None:
            longest = state.grid.cfl_dt(state.velocity, cfl=CFL, max_dt=dt)
            if longest < SMALLEST_STEP * dt:
                raise SimulationDiverged(
                    f"simulation diverged at t = {state.time:.4g} s: the fluid reached "
                    f"{max_speed(state.velocity):.3g} m/s, which would need steps of "
                    f"{longest:.2g} s; lower the torques (the gait's amplitudes or the "
                    "PD gains), or check the model's masses"
                )
        count = int(np.ceil((end - state.time) / longest - 1e-9))
        state = step(scene, state, (end - state.time) / count, policy)
    return replace(state, time=end)  # no round-off drift between frames


def _fluid_frames(scene: Scene, frames: list[State]) -> FluidFrames:
    """The fluid plane of every frame: the whole grid in 2D, the mid-plane z in 3D."""
    origins, velocities, solids = [], [], []
    for state in frames:
        grid = state.grid
        centred = cell_centered(grid, state.velocity)
        solid = _voxels(scene, grid, state.qpos).solid
        if grid.dim == 3:
            k = grid.shape[2] // 2
            centred, solid = centred[:2, :, :, k], solid[:, :, k]
        origins.append(grid.origin[:2])
        velocities.append(centred)
        solids.append(solid)
    grid = frames[-1].grid
    plane_z = grid.origin[2] + (grid.shape[2] // 2 + 0.5) * grid.cell_size if grid.dim == 3 else 0
    return FluidFrames(
        cell_size=grid.cell_size,
        origin=np.array(origins),
        velocity=np.stack(velocities).astype(np.float32),
        solid=np.stack(solids),
        plane_z=float(plane_z),
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
