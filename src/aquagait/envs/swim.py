"""``SwimEnv``: closed-loop swimming in the coupled fluid, through Gymnasium's API.

    import gymnasium as gym
    import aquagait.envs  # registers aquagait/Swim-v0

    env = gym.make("aquagait/Swim-v0", creature="eel2d", task="forward", seconds=4.0)
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

Every control step (``control_dt``, by default one frame, 1/30 s) the agent
sets the joints' target angles, held for the step, and the creature's stable
PD servo tracks them while the body and the fluid advance together
(``aquagait.sim.advance``, the same steps as ``aquagait swim``). The episode
starts from the rest pose in still water and ends when the task is done
(``terminated``), after ``seconds`` (``truncated``), or, rarely, when the
simulation cannot go on (``terminated``, with ``info["error"]`` saying why).

Actions, (na,) in [-1, 1] (``na`` the actuated DOFs, in ``model.actuated_dofs``
order; a ball joint's three rotation-vector components):

- ``action="position"``: the target angle of each DOF, ``a = -1`` its lower
  joint limit and ``+1`` its upper, linearly between.
- ``action="residual"``: a correction on top of a gait (``gait``: a shipped
  gait's name, a ``gait.json`` path or a parameter vector; default the
  creature's straight gait): the target is ``qbar(t) + a * residual_scale *
  half_range``, clipped to the limits, ``half_range`` half the joint's range.
  All-zero actions swim the gait exactly as ``aquagait swim`` does.

Observation: one float64 vector; ``env.unwrapped.observation_names`` names
every entry. In order:

==================  ======================  ==========================================
names               size (2D / 3D)          what, units
==================  ======================  ==========================================
``angle:DOF``       na                      joint angles [rad] (``control.joint_angles``)
``rate:DOF``        na                      joint rates [rad/s]
``velocity:x|y|z``  2 / 3                   the root's velocity in the creature's frame [m/s]
``spin:z|x,y,z``    1 / 3                   the root's angular velocity, same frame [rad/s]
``heading:cos|sin`` 2 / -                   2D: the heading relative to rest
``forward:x,y,z``   - / 3                   3D: the creature's forward axis in the world
``up:x,y,z``        - / 3                   3D: its up axis in the world
``clock:sin|cos``   2                       the gait's phase, 2 pi t / T (T: the gait's period)
task entries        0, dim or 2 dim         ``aquagait.envs.tasks``
sensor entries      count (1 + dim)         ``sense_flow``: ``aquagait.envs.sensing``
==================  ======================  ==========================================

The creature's frame is the root's orientation relative to its rest pose:
+x forward, +y left, +z up at rest (``aquagait.envs.tasks``). The space's
bounds are infinite but for the clock's [-1, 1] (a joint may overshoot its
limit a little under load).

Reward, per control step, in m/s::

    reward = progress - power_weight * P / (m g)

``progress`` is the task's (forward: speed along the heading); ``P`` the
actuators' mean power over the step, ``sum_i |tau_i qd_i|`` [W], as the
objective counts energy; ``m`` the creature's mass [kg] (2D: per its prism's
depth); ``g = 9.81 m/s^2``. ``P / (m g)`` is the speed at which that power
would lift the body; ``power_weight`` (default 1) weighs it against the
speed, so that for ``forward`` the reward is the speed times ``1 - power_weight
* COT``, ``COT = P / (m g v)`` the dimensionless cost of transport. The shipped
eel2d gait pays about 7 % of its speed.

Determinism: the simulation has no randomness; ``reset(seed=...)`` seeds the
generator the ``target`` task draws its point from. The same seed and actions
give the same episode, bit for bit.
"""

from __future__ import annotations

from collections import deque
from dataclasses import replace
from pathlib import Path as FilePath

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from aquagait.control.gait import SineGait
from aquagait.control.pd import joint_angles
from aquagait.creatures import Creature, resolve
from aquagait.creatures.creature import actuated_dof_names
from aquagait.envs.sensing import DEFAULT_SENSORS, LateralLine
from aquagait.envs.tasks import DISTANCE_WEIGHT, Pose, make_task
from aquagait.io.gait import GaitFileError, read_gait
from aquagait.sim import (
    FRAMES_PER_SECOND,
    SimulationError,
    Trajectory,
    advance,
    growth_notes,
    init_state,
    make_scene,
)
from aquagait.sim.frames import fluid_frame, fluid_frames, stride

CONTROL_DT = 1.0 / FRAMES_PER_SECOND
DEFAULT_SECONDS = 10.0
POWER_WEIGHT = 1.0
GRAVITY = 9.81
RESIDUAL_SCALE = 0.25
"""A residual action of 1 moves the target by this share of the joint's half range."""
ACTIONS = ("position", "residual")
RENDER_FRAMES = 16
"""Control steps kept for ``render``: the particle traces' length (15 frames) and one more."""


class Targets:
    """The joints' reference angles as the servo asks for them: ``angles(t)``, (na,) [rad].

    Held by the environment and changed at every control step (the servo keeps
    this object): ``set`` the held targets (position) or the residual on top of
    a gait (residual), clipped to the limits.
    """

    def __init__(self, dofs, lower, upper, gait: SineGait | None):
        self.dofs = tuple(dofs)
        self.lower, self.upper, self.gait = lower, upper, gait
        self.held = np.zeros(len(self.dofs))

    def set(self, held: np.ndarray) -> None:
        self.held = held

    def angles(self, t: float) -> np.ndarray:
        base = self.held if self.gait is None else self.gait.angles(t) + self.held
        return np.clip(base, self.lower, self.upper)


class SwimEnv(gym.Env):
    """A creature swimming in the coupled fluid, driven step by step (module docstring).

    Args:
        creature: a library creature's name, the path of an MJCF file (with its
            side-car, if any), or a ``Creature``.
        fluid: 'euler' (the coupled fluid) or 'simple' (drag only).
        task: 'forward', 'target' or 'follow' (``aquagait.envs.tasks``).
        seconds: episode length [s].
        control_dt: the control step [s]; default one frame, 1/30 s.
        action: 'position' or 'residual' (module docstring).
        gait: residual only: the gait corrected (a shipped gait's name, a
            ``gait.json`` path, a parameter vector); default the straight gait.
        residual_scale: residual only: a unit action's share of the half range.
        power_weight: the reward's weight on ``P / (m g)`` (module docstring).
        target: task 'target': the point [m], (dim,); default drawn per episode.
        path: task 'follow': a shape (``circle:radius=0.6``), a file or a ``Path``.
        radius: task 'target' and 'follow': how near counts as reached [m];
            default half a body length.
        distance_weight: task 'follow': the weight on the distance from the path [1/s].
        sense_flow: add the lateral line (``aquagait.envs.sensing``; Euler fluid).
        sensors: how many flow sensors, half a flank.
        resolution: the fluid grid's cells per axis; default the creature's.
        cell_size: the fluid grid's cell size [m]; default the creature's.
        render_mode: None or 'rgb_array' (the 2D and 3D pictures of ``aquagait swim``;
            the ``viz`` extra, 3D also ``render``).

    Raises:
        ValueError: a setting that cannot be used; the message says what would be right.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": FRAMES_PER_SECOND}

    def __init__(
        self,
        creature="eel2d",
        fluid: str = "euler",
        task: str = "forward",
        seconds: float = DEFAULT_SECONDS,
        control_dt: float = CONTROL_DT,
        action: str = "position",
        gait=None,
        residual_scale: float = RESIDUAL_SCALE,
        power_weight: float = POWER_WEIGHT,
        target=None,
        path=None,
        radius: float | None = None,
        distance_weight: float = DISTANCE_WEIGHT,
        sense_flow: bool = False,
        sensors: int = DEFAULT_SENSORS,
        resolution=None,
        cell_size: float | None = None,
        render_mode: str | None = None,
    ):
        self.creature = _creature(creature)
        model = self.creature.model
        for value, what in ((seconds, "seconds"), (control_dt, "control_dt")):
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"{what} must be a positive number of seconds, got {value!r}")
        if action not in ACTIONS:
            raise ValueError(f"unknown action {action!r}; actions: {', '.join(ACTIONS)}")
        if gait is not None and action != "residual":
            raise ValueError("gait= is the gait a residual corrects: give action='residual'")
        if fluid not in ("euler", "simple"):
            raise ValueError(f"fluid must be 'euler' or 'simple', got {fluid!r}")
        if sense_flow and fluid != "euler":
            raise ValueError("flow sensing reads the coupled fluid: give fluid='euler'")
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        if not power_weight >= 0 or not residual_scale > 0:
            raise ValueError(
                f"power_weight must be >= 0 and residual_scale > 0; got {power_weight!r}, "
                f"{residual_scale!r}"
            )
        self.scene = make_scene(self.creature, resolution=resolution, cell_size=cell_size,
                                fluid=fluid)  # fmt: skip
        self.seconds, self.control_dt = float(seconds), float(control_dt)
        self.action_kind, self.power_weight = action, float(power_weight)
        self.render_mode = render_mode

        dofs = actuated_dof_names(model)
        self.lower, self.upper = model.lower.copy(), model.upper.copy()
        self.half_range = (self.upper - self.lower) / 2
        sine = self._gait(gait)
        self.period = float(np.max(sine.period))
        residual = action == "residual"
        self.targets = Targets(dofs, self.lower, self.upper, sine if residual else None)
        self.scale = residual_scale * self.half_range if residual else self.half_range
        self.servo = self.creature.servo(self.targets)

        self.start = init_state(self.scene)
        self._rest_rotation = self._root(self.start.qpos)[1]
        self.task = make_task(task, model.dim, model.body_length, self._root(self.start.qpos)[0],
                              target, path, radius, distance_weight)  # fmt: skip
        self.lateral_line = LateralLine(self.scene, sensors) if sense_flow else None
        self.observation_names = self._names(dofs)
        self.action_space = spaces.Box(-1.0, 1.0, (len(dofs),), np.float32)
        self.observation_space = self._observation_space()
        self.state, self.pose, self.running, self.steps = self.start, None, False, 0
        self._frames: deque = deque(maxlen=RENDER_FRAMES)

    # --- Gymnasium ----------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Back to the rest pose in still water; ``seed`` seeds ``np_random`` (the target task
        draws its point from it). Returns ``(observation, info)``."""
        super().reset(seed=seed)
        self.state, self.steps = self.start, 0
        self.targets.set(np.zeros(len(self.targets.dofs)))
        self.pose = self._pose(self.state)
        self.task.reset(self.pose, self.np_random)
        self._frames.clear()
        self._record()
        self.running = True
        return self._observe(), {"time": 0.0, **self.task.describe()}

    def step(self, action):
        """Hold the action's targets for ``control_dt`` and advance; returns ``(observation,
        reward, terminated, truncated, info)`` (module docstring)."""
        if not self.running:
            raise RuntimeError("the episode is over (or has not begun): call reset() before step()")
        a = np.asarray(action, dtype=float)
        if a.shape != self.action_space.shape or not np.isfinite(a).all():
            raise ValueError(
                f"action must be {self.action_space.shape[0]} finite numbers in [-1, 1] (one "
                f"per actuated DOF: {', '.join(self.targets.dofs)}); got {action!r}"
            )
        a = np.clip(a, -1.0, 1.0)
        centre = 0.0 if self.action_kind == "residual" else (self.upper + self.lower) / 2
        self.targets.set(centre + a * self.scale)
        before, state = self.pose, self.state
        end = min((self.steps + 1) * self.control_dt, self.seconds)  # k dt: no drift
        info = {}
        try:
            with growth_notes() as grew:
                state = advance(self.scene, state, self.servo, end)
        except SimulationError as err:
            info["error"] = str(err)
            self.running = False
            return self._observe(), 0.0, True, False, {"time": state.time, **info}
        if grew:
            info["grid_notes"] = list(grew)
        power = (state.energy.sum() - self.state.energy.sum()) / (state.time - self.state.time)
        self.state, self.pose, self.steps = state, self._pose(state), self.steps + 1
        progress = self.task.progress(before, self.pose)
        reward = progress - self.power_weight * power / (self.creature.model.mass * GRAVITY)
        self._record()
        terminated = self.task.reached(self.pose)
        truncated = not terminated and state.time >= self.seconds - 1e-9
        self.running = not (terminated or truncated)
        info.update(
            time=state.time, progress=progress, power=power, energy=float(state.energy.sum()),
            position=self.pose.position.copy(),
        )  # fmt: skip
        return self._observe(), float(reward), terminated, truncated, info

    def render(self):
        """The picture of the present control step, (height, width, 3) uint8 RGB, as ``aquagait
        swim`` draws it (2D: vorticity and particle traces; 3D: the shaded creature and its
        wake), with traces over the last ``RENDER_FRAMES`` steps and the path of ``follow`` in
        red; None without ``render_mode='rgb_array'``.

        Raises:
            aquagait.viz.gl.RenderUnavailable: a 3D creature and no OpenGL (what to install).
        """
        if self.render_mode != "rgb_array":
            return None
        from aquagait.viz.swim import swim_frames

        states = [s for s, _ in self._frames]
        records = [r for _, r in self._frames]
        fluid = None
        if records[0] is not None:
            fluid = fluid_frames(self.scene.grid.cell_size, records, self._blocks)
        trajectory = Trajectory(
            time=np.array([s.time for s in states]),
            qpos=np.stack([s.qpos for s in states]),
            qvel=np.stack([s.qvel for s in states]),
            torque=np.stack([s.torque for s in states]),
            energy=np.stack([s.energy for s in states]),
            dt=self.scene.fluid.max_dt,
            fps=1.0 / self.control_dt,
            fluid=fluid,
        )
        look = {"route": self.task.path.points} if self.task.name == "follow" else {}
        pictures = swim_frames(trajectory, self.creature.model, [len(states) - 1], **look)
        return next(iter(pictures))

    # --- the pieces ---------------------------------------------------------
    def _gait(self, gait) -> SineGait:
        """The gait a residual corrects, over every actuated DOF (``SineGait.on``)."""
        creature = self.creature
        spec, params = creature.gait, creature.default_gait
        if isinstance(gait, str | FilePath) and str(gait) in creature.gaits:
            spec, params = creature.shipped_spec(str(gait)), creature.gaits[str(gait)].params
        elif isinstance(gait, str | FilePath):
            try:
                found = read_gait(gait, creature)
            except GaitFileError as err:
                shipped = ", ".join(creature.gaits) or "none"
                raise ValueError(f"{err}; {creature.name}'s shipped gaits: {shipped}") from None
            spec, params = creature.spec(found.maneuver, found.free_period), found.params
        elif gait is not None:
            params = np.asarray(gait, dtype=float)
            if params.shape != (spec.size,):
                raise ValueError(
                    f"{creature.name}'s gait has {spec.size} parameters ({', '.join(spec.names)}); "
                    f"got {params.size}"
                )
        return spec.unpack(params).on(actuated_dof_names(creature.model))

    def _root(self, q) -> tuple[np.ndarray, np.ndarray]:
        positions, rotations = self.scene.dynamics.link_poses(q)
        root = self.creature.model.joints[0].link
        return positions[root, : self.creature.dim], rotations[root]

    def _pose(self, state) -> Pose:
        position, rotation = self._root(state.qpos)
        return Pose(state.time, position, rotation @ self._rest_rotation.T)

    def _observe(self) -> np.ndarray:
        model, state, pose = self.creature.model, self.state, self.pose
        _, velocity, spin = self.scene.dynamics.link_motion(state.qpos, state.qvel)
        root = model.joints[0].link
        own = creature_observation(model, state.qpos, state.qvel, pose.frame, velocity[root],
                                   spin[root], state.time / self.period)  # fmt: skip
        parts = [own, self.task.observe(pose)]
        if self.lateral_line is not None:
            parts.append(self.lateral_line.read(self.scene, state, pose.frame))
        return np.concatenate(parts).astype(np.float64)

    def _names(self, dofs) -> tuple[str, ...]:
        names = [*creature_names(dofs, self.creature.dim), *self.task.names]
        if self.lateral_line is not None:
            names += list(self.lateral_line.names)
        return tuple(names)

    def _observation_space(self) -> spaces.Box:
        """Unbounded but for the clock: a joint may overshoot its limit a little, and a
        unit vector's entries round past 1."""
        low = np.full(len(self.observation_names), -np.inf)
        high = np.full(len(self.observation_names), np.inf)
        clock = [k for k, name in enumerate(self.observation_names) if name.startswith("clock:")]
        low[clock], high[clock] = -1.0, 1.0
        return spaces.Box(low, high, dtype=np.float64)

    def _record(self) -> None:
        """Keep the step for ``render`` (only with a render mode: the fluid costs memory)."""
        if self.render_mode is None:
            return
        state = self.state
        record = None
        if state.velocity is not None:
            if not self._frames:
                self._blocks = 1 if state.grid.dim == 2 else stride(state.grid.shape)
            record = fluid_frame(self.scene, state, self._blocks)
        self._frames.append((replace(state, velocity=None, pressure=None), record))


def creature_observation(model, q, qd, frame, velocity, spin, cycles: float) -> np.ndarray:
    """A creature's own observation entries (module docstring: angles to clock, in order).

    Args:
        model: the creature's ``Model``.
        q: (nq,) its positions; qd: (nv,) its velocities.
        frame: (3, 3) its root's rotation from the rest pose.
        velocity: (3,) its root's world velocity [m/s]; spin: (3,) its angular velocity
            [rad/s] (``Dynamics.link_motion``).
        cycles: the time in gait cycles, t / T.
    """
    local_spin = frame.T @ spin
    if model.dim == 2:
        turn = frame[:2, 0]
        attitude, local_spin = turn / np.linalg.norm(turn), local_spin[2:]
    else:
        attitude = np.concatenate([frame[:, 0], frame[:, 2]])
    phase = 2 * np.pi * cycles
    return np.concatenate([
        joint_angles(model, q), qd[model.actuated_dofs], (frame.T @ velocity)[: model.dim],
        local_spin, attitude, [np.sin(phase), np.cos(phase)],
    ])  # fmt: skip


def creature_names(dofs, dim: int) -> list[str]:
    """The names of ``creature_observation``'s entries for the actuated ``dofs``."""
    axes = "xyz"[:dim]
    names = [f"angle:{d}" for d in dofs] + [f"rate:{d}" for d in dofs]
    names += [f"velocity:{a}" for a in axes]
    names += ["spin:z"] if dim == 2 else [f"spin:{a}" for a in "xyz"]
    if dim == 2:
        names += ["heading:cos", "heading:sin"]
    else:
        names += [f"forward:{a}" for a in "xyz"] + [f"up:{a}" for a in "xyz"]
    return [*names, "clock:sin", "clock:cos"]


def _creature(creature) -> Creature:
    if isinstance(creature, Creature):
        return creature
    try:
        return resolve(creature)
    except KeyError as err:
        raise ValueError(err.args[0] if err.args else str(err)) from None
