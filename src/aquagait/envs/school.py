"""``SchoolEnv``: several creatures in one coupled fluid, one agent each, through PettingZoo's
parallel API (docs/schools.md).

    from aquagait.envs.school import SchoolEnv

    env = SchoolEnv()                     # a pair of eel2d in line, station keeping
    observations, infos = env.reset(seed=0)
    actions = {agent: env.action_space(agent).sample() for agent in env.agents}
    observations, rewards, terminations, truncations, infos = env.step(actions)

The creatures stand in a formation (``aquagait.body.group.formation``) and
swim as one composed body (``aquagait.body.group``). Every control step
(``control_dt``, one frame by default) each agent sets a residual on its
creature's shipped straight gait, lagged by its place's phase, exactly as
``aquagait.envs.swim.SwimEnv(action="residual")`` does for one creature: all-zero
actions swim the formation as ``aquagait swim --formation`` does.

Each agent's observation is a single creature's (``SwimEnv``'s, without task:
joint angles and rates, the root's velocity and spin in its own frame, its
heading (2D) or forward and up axes (3D), the clock; with ``sense_flow``, its
own lateral line, ``aquagait.envs.sensing``, which feels the others' wakes),
then, for each other creature in order, where it is in this one's frame [m] and
which way it heads (2D: the cosine and sine of the heading difference; 3D:
its forward axis in this one's frame). ``observation_names(agent)`` names
every entry.

Rewards, per control step, in m/s:

- ``task="station"``: the leader (the first creature) is paid its speed
  along its heading; every other creature is paid for keeping the place it
  started at in the leader's frame: the rate at which its distance from that
  place shrinks, ``-(|e1| - |e0|) / control_dt``, so that holding station
  earns 0 and closing on it earns;
each less ``power_weight * P / (m g)`` for its own power ``P`` and mass (as
``SwimEnv``'s);
- ``task="school"``: every agent is paid the same, the group's mean speed
  along the headings less ``power_weight * P / (M g)`` for the group's power
  and mass: the group's cost of transport.
 Two creatures that touch end the episode for all
(``terminations``, with ``infos[agent]["error"]`` saying which and when).

Determinism: nothing is random; ``reset(seed=...)`` seeds the action spaces
only. The same actions give the same episode, bit for bit.
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv

from aquagait.body.group import compose, formation
from aquagait.control.group import GroupPolicy
from aquagait.creatures.creature import actuated_dof_names
from aquagait.envs.sensing import DEFAULT_SENSORS, LateralLine
from aquagait.envs.swim import (
    CONTROL_DT,
    GRAVITY,
    POWER_WEIGHT,
    RESIDUAL_SCALE,
    Targets,
    _creature,
    creature_names,
    creature_observation,
)
from aquagait.sim import SimulationError, advance, growth_notes, init_state, make_scene
from aquagait.sim.group import group_grid

TASKS = ("station", "school")


class SchoolEnv(ParallelEnv):
    """Creatures in one fluid, one agent each (module docstring).

    Args:
        creature: a library creature's name, an MJCF path or a ``Creature``.
        kind: the formation, ``in-line``, ``side-by-side`` or ``diamond``.
        count: creatures (default 2; a diamond has 4).
        spacing: in body lengths (``aquagait.body.group.formation``).
        phase: each place's gait lags the one before by this many cycles.
        task: 'station' or 'school' (module docstring).
        seconds: episode length [s].
        control_dt: the control step [s].
        residual_scale: a unit action's share of each joint's half range.
        power_weight: the reward's weight on ``P / (m g)``.
        fluid: 'euler' or 'simple'.
        resolution: cells per axis; default a grid that holds each creature's own.
        cell_size: h [m]; default the creature's.
        sense_flow: add each creature's own lateral line (Euler fluid).
        sensors: its sensors, even (half on each flank).

    Raises:
        ValueError: a setting that cannot be used; the message says what would be right.
    """

    metadata = {"name": "aquagait_school_v0", "render_modes": []}

    def __init__(
        self,
        creature="eel2d",
        kind: str = "in-line",
        count: int = 2,
        spacing: float = 0.5,
        phase: float = 0.0,
        task: str = "station",
        seconds: float = 10.0,
        control_dt: float = CONTROL_DT,
        residual_scale: float = RESIDUAL_SCALE,
        power_weight: float = POWER_WEIGHT,
        fluid: str = "euler",
        resolution=None,
        cell_size: float | None = None,
        sense_flow: bool = False,
        sensors: int = DEFAULT_SENSORS,
    ):
        self.creature = _creature(creature)
        model = self.creature.model
        if task not in TASKS:
            raise ValueError(f"unknown task {task!r}; tasks: {', '.join(TASKS)}")
        for value, what in ((seconds, "seconds"), (control_dt, "control_dt")):
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"{what} must be a positive number of seconds, got {value!r}")
        if fluid not in ("euler", "simple"):
            raise ValueError(f"fluid must be 'euler' or 'simple', got {fluid!r}")
        if sense_flow and fluid != "euler":
            raise ValueError("flow sensing reads the coupled fluid: give fluid='euler'")
        places = formation(kind, count, spacing, model.body_length)
        self.group = compose([model] * count, poses=[pose for pose, _ in places])
        h = cell_size or self.creature.cell_size
        shape, h, origin = group_grid(self.group, [self.creature.resolution] * count, [h] * count)
        self.scene = make_scene(self.group, resolution or shape, h, fluid=fluid,
                                origin=None if resolution else origin)  # fmt: skip
        self.lateral_lines = (
            [LateralLine(self.scene, sensors, member) for member in self.group.members]
            if sense_flow else None
        )  # fmt: skip
        self.task, self.seconds, self.control_dt = task, float(seconds), float(control_dt)
        self.power_weight = float(power_weight)

        dofs = actuated_dof_names(model)
        spec = self.creature.gait
        gait = spec.unpack(self.creature.default_gait).on(dofs)
        self.period = float(np.max(gait.period))
        self.scale = residual_scale * (model.upper - model.lower) / 2
        self.targets = [Targets(dofs, model.lower, model.upper, gait.lagging(rank * phase))
                        for _, rank in places]  # fmt: skip
        self.policy = GroupPolicy(self.group, [self.creature.servo(t) for t in self.targets])
        self.possible_agents = [m.label for m in self.group.members]
        self.agents = []
        self.start = init_state(self.scene)
        self._rest = [self._root(self.start.qpos, k)[1] for k in range(count)]
        self._names = {agent: self._observation_names(k, dofs)
                       for k, agent in enumerate(self.possible_agents)}  # fmt: skip
        self._spaces = {
            agent: spaces.Box(-np.inf, np.inf, (len(names),), np.float64)
            for agent, names in self._names.items()
        }
        self._actions = {
            agent: spaces.Box(-1.0, 1.0, (len(dofs),), np.float32) for agent in self.possible_agents
        }
        self._station = [self._relative(self.start.qpos, 0, k) for k in range(count)]
        self.state, self.steps = self.start, 0

    # --- PettingZoo ---------------------------------------------------------
    def observation_space(self, agent):
        return self._spaces[agent]

    def action_space(self, agent):
        return self._actions[agent]

    def observation_names(self, agent) -> tuple[str, ...]:
        """What each entry of ``agent``'s observation is (module docstring)."""
        return self._names[agent]

    def reset(self, seed: int | None = None, options: dict | None = None):
        """Back to the formation at rest in still water; ``seed`` seeds the action spaces.
        Returns ``(observations, infos)``, dicts by agent."""
        if seed is not None:
            for k, agent in enumerate(self.possible_agents):
                self._actions[agent].seed(seed + k)
        self.agents = list(self.possible_agents)
        self.state, self.steps = self.start, 0
        for targets in self.targets:
            targets.set(np.zeros(len(targets.dofs)))
        return self._observe(), {agent: {"time": 0.0} for agent in self.agents}

    def step(self, actions):
        """Hold every agent's residual for ``control_dt`` and advance the group; returns
        ``(observations, rewards, terminations, truncations, infos)``, dicts by agent."""
        if not self.agents:
            raise RuntimeError("the episode is over (or has not begun): call reset() before step()")
        for k, agent in enumerate(self.possible_agents):
            a = np.asarray(actions.get(agent, np.zeros(self._actions[agent].shape)), dtype=float)
            if a.shape != self._actions[agent].shape or not np.isfinite(a).all():
                raise ValueError(
                    f"{agent}'s action must be {self._actions[agent].shape[0]} finite numbers in "
                    f"[-1, 1] (one per actuated DOF); got {actions.get(agent)!r}"
                )
            self.targets[k].set(np.clip(a, -1.0, 1.0) * self.scale)
        before = self.state
        end = min((self.steps + 1) * self.control_dt, self.seconds)
        try:
            with growth_notes():
                state = advance(self.scene, before, self.policy, end)
        except SimulationError as err:
            agents, self.agents = self.agents, []
            return (self._observe(), dict.fromkeys(agents, 0.0), dict.fromkeys(agents, True),
                    dict.fromkeys(agents, False),
                    {a: {"time": before.time, "error": str(err)} for a in agents})  # fmt: skip
        self.state, self.steps = state, self.steps + 1
        rewards = self._rewards(before, state)
        truncated = state.time >= self.seconds - 1e-9
        agents = self.agents
        if truncated:
            self.agents = []
        observations = self._observe()
        infos = {agent: {"time": state.time} for agent in agents}
        return (observations, rewards, dict.fromkeys(agents, False),
                dict.fromkeys(agents, truncated), infos)  # fmt: skip

    # --- the pieces ---------------------------------------------------------
    def _root(self, q, k: int) -> tuple[np.ndarray, np.ndarray]:
        member = self.group.members[k]
        positions, rotations = self.scene.dynamics.link_poses(q)
        root = member.links.start + member.model.joints[0].link
        return positions[root], rotations[root]

    def _frame(self, q, k: int) -> tuple[np.ndarray, np.ndarray]:
        """Creature ``k``'s root position and its frame (rotation from rest)."""
        position, rotation = self._root(q, k)
        return position, rotation @ self._rest[k].T

    def _relative(self, q, k: int, other: int) -> np.ndarray:
        """Where creature ``other`` is in creature ``k``'s frame [m], (dim,)."""
        position, frame = self._frame(q, k)
        return (frame.T @ (self._root(q, other)[0] - position))[: self.group.model.dim]

    def _rewards(self, before, after) -> dict:
        dt = after.time - before.time
        dim, members = self.group.model.dim, self.group.members
        speeds = []
        for k in range(len(members)):
            (p0, _), (p1, frame) = self._frame(before.qpos, k), self._frame(after.qpos, k)
            speeds.append(float(frame[:dim, 0] @ (p1 - p0)[:dim] / dt))
        if self.task == "school":
            power = (after.energy.sum() - before.energy.sum()) / dt
            shared = np.mean(speeds) - self.power_weight * power / (self.group.model.mass * GRAVITY)
            return dict.fromkeys(self.possible_agents, float(shared))
        rewards = {}
        for k, (agent, member) in enumerate(zip(self.possible_agents, members, strict=True)):
            energy = after.energy[member.dofs].sum() - before.energy[member.dofs].sum()
            cost = self.power_weight * energy / dt / (member.model.mass * GRAVITY)
            if k == 0:
                progress = speeds[0]
            else:
                errors = [np.linalg.norm(self._relative(q, 0, k) - self._station[k])
                          for q in (before.qpos, after.qpos)]  # fmt: skip
                progress = -(errors[1] - errors[0]) / dt
            rewards[agent] = progress - cost
        return rewards

    def _observe(self) -> dict:
        q, qd = self.state.qpos, self.state.qvel
        _, velocity, spin = self.scene.dynamics.link_motion(q, qd)
        dim, observations = self.group.model.dim, {}
        for k, (agent, member) in enumerate(zip(self.possible_agents, self.group.members,
                                                strict=True)):  # fmt: skip
            _, frame = self._frame(q, k)
            root = member.links.start + member.model.joints[0].link
            parts = [creature_observation(member.model, q[member.qpos], qd[member.dofs], frame,
                                          velocity[root], spin[root],
                                          self.state.time / self.period)]  # fmt: skip
            if self.lateral_lines is not None:
                parts.append(self.lateral_lines[k].read(self.scene, self.state, frame))
            for other in range(len(self.group.members)):
                if other == k:
                    continue
                parts.append(self._relative(q, k, other))
                other_frame = self._frame(q, other)[1]
                turned = frame.T @ other_frame[:, 0]
                parts.append(turned[:2] if dim == 2 else turned)
            observations[agent] = np.concatenate(parts).astype(np.float64)
        return observations

    def _observation_names(self, k: int, dofs) -> tuple[str, ...]:
        dim = self.group.model.dim
        axes = "xyz"[:dim]
        names = creature_names(dofs, dim)
        if self.lateral_lines is not None:
            names += list(self.lateral_lines[k].names)
        for other, label in enumerate(self.possible_agents):
            if other != k:
                names += [f"{label}:position:{a}" for a in axes]
                names += ([f"{label}:heading:cos", f"{label}:heading:sin"] if dim == 2
                          else [f"{label}:forward:{a}" for a in "xyz"])  # fmt: skip
        return tuple(names)
