"""The path follower: a planner that picks a learned manoeuvre at every cycle's start
(paper §5, DESIGN.md §2.5).

    follower = Follower(scene, gaits, servo, path, period=1.0, dead_band=0.05)
    trajectory = rollout(scene, init_state(scene), None, seconds, plan=follower)
    follower.decisions       # one Decision per cycle: time, manoeuvre, offset, tangent

``gaits`` is the creature's manoeuvre library as sines (``straight`` and any
of ``turn-left``, ``turn-right``, ``pitch-up``, ``pitch-down``), ``servo``
turns a gait into the creature's PD servo. At the start of every cycle the
follower takes the root link's pose, the nearest path point and the path's
tangent there in the root's frame, and applies ``choose_maneuver``. A
manoeuvre it has no gait for is swum straight (and counted in
``Decision.unlearned``), so a creature that has learned only some turns
still follows as well as it can. A change of manoeuvre blends the reference
angles over ``blend`` of a cycle (``SwitchedGait``), so the joints are never
asked to jump.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from aquagait.control.gait import SineGait, SwitchedGait
from aquagait.path.paths import Path
from aquagait.path.rule import STRAIGHT, choose_maneuver, root_frame
from aquagait.sim import Scene, State

BLEND = 0.25
"""Share of a cycle over which one manoeuvre's references hand over to the next."""


@dataclass(frozen=True)
class Decision:
    """What the follower chose at a cycle's start.

    Attributes:
        time: [s].
        maneuver: the manoeuvre swum from here (straight where the wanted one
            is not learned).
        wanted: the manoeuvre the rule asked for.
        offset: (dim,) from the root to the nearest path point, in the root's frame [m].
        tangent: (dim,) the path's unit tangent there, in the root's frame.
    """

    time: float
    maneuver: str
    wanted: str
    offset: np.ndarray
    tangent: np.ndarray

    @property
    def unlearned(self) -> bool:
        """The rule asked for a manoeuvre the creature has not learned."""
        return self.wanted != self.maneuver


def root_pose(scene: Scene, qpos) -> tuple[np.ndarray, np.ndarray]:
    """The root link's world position (dim,) [m] and rotation (3, 3) at ``qpos``."""
    positions, rotations = scene.dynamics.link_poses(qpos)
    root = scene.model.joints[0].link
    return positions[root, : scene.model.dim], rotations[root]


class Follower:
    """``plan(state) -> policy`` for ``rollout``: follow ``path`` with learned manoeuvres.

    One follower serves one run (it keeps the decisions it made and the gait
    it swims); make a new one for another.

    Args:
        scene: the scene swum in (its model and dynamics give the root's pose).
        gaits: the manoeuvre library, ``{name: SineGait}``; must hold ``straight``;
            all drive the same DOFs.
        servo: ``servo(gait) -> policy``, the creature's PD servo tracking a gait.
        path: the path, of the scene's dimension.
        period: the gait cycle T [s]; a decision every T.
        dead_band: ``eps`` of ``choose_maneuver`` [m].
        blend: share of a cycle over which a change of manoeuvre blends.
    """

    def __init__(
        self,
        scene: Scene,
        gaits: Mapping[str, SineGait],
        servo: Callable[[object], object],
        path: Path,
        period: float,
        dead_band: float,
        blend: float = BLEND,
    ):
        if STRAIGHT not in gaits:
            raise ValueError(f"the manoeuvre library needs a straight gait; has {sorted(gaits)}")
        if path.dim != scene.model.dim:
            raise ValueError(f"a {path.dim}D path for a {scene.model.dim}D creature")
        if not (period > 0 and dead_band >= 0 and 0 <= blend <= 1):
            raise ValueError(
                f"need period > 0 s, dead_band >= 0 m and blend in [0, 1]; got {period}, "
                f"{dead_band}, {blend}"
            )
        self.scene, self.gaits, self.servo, self.path = scene, dict(gaits), servo, path
        self.period, self.dead_band, self.blend = float(period), float(dead_band), float(blend)
        self.decisions: list[Decision] = []
        self._policy = None
        self._next = None  # time of the next decision [s]

    def __call__(self, state: State):
        """The policy for the frame starting at ``state`` (a new decision at a cycle's start)."""
        if self._next is None or state.time >= self._next - 1e-9 * self.period:
            self._decide(state)
        return self._policy

    def _decide(self, state: State) -> None:
        position, rotation = root_pose(self.scene, state.qpos)
        point, tangent = self.path.nearest(position)
        offset = root_frame(point - position, rotation)
        along = root_frame(tangent, rotation)
        wanted = choose_maneuver(offset, along, self.dead_band)
        chosen = wanted if wanted in self.gaits else STRAIGHT
        previous = self.decisions[-1].maneuver if self.decisions else chosen
        self.decisions.append(Decision(state.time, chosen, wanted, offset, along))
        gait = SwitchedGait(
            self.gaits[previous], self.gaits[chosen], state.time, self.blend * self.period
        )
        self._policy = self.servo(gait)
        start = 0.0 if self._next is None else self._next
        self._next = start + self.period * (1 + np.floor((state.time - start) / self.period))
