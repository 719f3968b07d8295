"""The path follower: a planner that picks a learned manoeuvre, or a share of one, at every
cycle's start (paper §5, docs/follow.md).

    follower = Follower(scene, gaits, servo, path, period=1.0, dead_band=0.05)
    trajectory = rollout(scene, init_state(scene), None, seconds, plan=follower)
    follower.decisions       # one Decision per cycle: time, manoeuvre, offset, tangent

``gaits`` is the creature's manoeuvre library as sines (``straight`` and any
of ``turn-left``, ``turn-right``, ``pitch-up``, ``pitch-down``), ``servo``
turns a gait into the creature's PD servo. At the start of every cycle the
follower takes the root link's position, the nearest path point and the
path's tangent (read a cycle ahead, below) in the root's frame, and applies
``choose_maneuver``.
The root's frame is its heading now, free of the sway within a cycle: its
orientation averaged over the cycle just swum (the rotation nearest the
mean of its rotation matrices, frame by frame), carried on by half of the
turn between the last two such means (``LEAD``), since the mean lags the
present by half a cycle; at the first decision, the pose itself. The root of
an undulating swimmer (the eel's head) sways about ten degrees within every
cycle, always at the same phase at a cycle's start, which would bias every
decision the same way; and a turn goes on for a while after its cycle, so
a heading that lags makes the follower turn too far. Measured on eel2d
(its turn-left and that turn mirrored as turn-right; 12-15 cycles, mean and
max distance to the path in body lengths, circles of radius 0.6 and 1 m and
an S-curve 3 m long and 0.4 m high): the pose itself at the cycle's start
0.41/0.88 on the smaller circle; the mean heading 0.39/1.17, 0.51/1.68,
0.20/0.58; carried on by half a cycle 0.18/0.41, 0.29/0.85, 0.21/0.62 (by
a whole cycle 0.49/1.09, 0.28/0.75, 0.43/1.23).

The tangent is the path's one cycle's travel ahead of the nearest point
(``LOOK_AHEAD``: as far along the path as the root moved over the cycle
just swum), the rule's "is the path coming back towards the creature?"
asked of where the creature will be when it next decides. At the nearest
point itself, a path that curves away (the outside of a circle) looks as if
it came back as soon as the heading has passed its tangent there, and the
creature swims straight out of the bend: eel2d on the circle of radius 0.6
m, its turns learned from its straight gait of 2026-12-04 (47 degrees a
cycle), kept 0.81/1.39 body lengths from it with the nearest tangent, 0.23/
0.57 half a cycle ahead and 0.14/0.46 a cycle ahead.

Given the manoeuvres' ``rates`` (their turn a cycle), the follower steers
graded instead (``rule.graded_shares``): it mixes a share of a manoeuvre into
the straight gait (``control.mix``), chosen by the bearing of the path's
point ``AIM`` cycles' travel ahead of the nearest one; at the first decision,
with no travel yet to measure ahead by, it takes the paper's rule.

A manoeuvre it has no gait for is swum straight (and counted in
``Decision.unlearned``), so a creature that has learned only some turns
still follows as well as it can. A change of manoeuvre blends the reference
angles over ``blend`` of a cycle (``SwitchedGait``), so the joints are never
asked to jump.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial.transform import Rotation

from aquagait.control.gait import SineGait, SwitchedGait, mix
from aquagait.path.paths import Path
from aquagait.path.rule import GAIN, STRAIGHT, choose_maneuver, graded_shares, root_frame
from aquagait.sim import Scene, State

LOOK_AHEAD = 1.0
"""Cycles of travel (the root's over the cycle just swum) by which the tangent the rule reads
lies ahead of the path's nearest point (module docstring)."""

LEAD = 0.5
"""Cycles by which the root's mean heading over the last cycle is carried on (its turn over
that cycle continued): half a cycle brings the mean, which lags by half a cycle, to now."""

BLEND = 0.25
"""Share of a cycle over which one manoeuvre's references hand over to the next."""

AIM = 2.0
"""Graded steering: cycles of travel (the root's over the cycle just swum) by which the
point it steers towards lies ahead of the path's nearest point."""


@dataclass(frozen=True)
class Decision:
    """What the follower chose at a cycle's start.

    Attributes:
        time: [s].
        maneuver: the manoeuvre swum from here (straight where the wanted one
            is not learned); graded, the one of the largest share.
        wanted: the manoeuvre the rule asked for.
        offset: (dim,) from the root to the nearest path point, in the root's frame [m].
        tangent: (dim,) the path's unit tangent a cycle's travel ahead of that point
            (``LOOK_AHEAD``), in the root's frame.
        shares: ``{manoeuvre: share}`` mixed into the straight gait (the rest of
            it); by the paper's rule the one manoeuvre whole, straight none.
    """

    time: float
    maneuver: str
    wanted: str
    offset: np.ndarray
    tangent: np.ndarray
    shares: Mapping[str, float] = field(default_factory=dict)

    @property
    def unlearned(self) -> bool:
        """The rule asked for a manoeuvre the creature has not learned."""
        return self.wanted != self.maneuver


def root_pose(scene: Scene, qpos) -> tuple[np.ndarray, np.ndarray]:
    """The root link's world position (dim,) [m] and rotation (3, 3) at ``qpos``."""
    positions, rotations = scene.dynamics.link_poses(qpos)
    root = scene.model.joints[0].link
    return positions[root, : scene.model.dim], rotations[root]


def mean_rotation(rotations) -> np.ndarray:
    """The rotation (3, 3) nearest the mean of rotation matrices (the polar factor of their
    mean, by SVD): their average orientation."""
    u, _, vt = np.linalg.svd(np.mean(rotations, axis=0))
    return u @ np.diag([1.0, 1.0, np.linalg.det(u @ vt)]) @ vt


def lead(before, now, cycles: float) -> np.ndarray:
    """Rotation ``now`` (3, 3) turned on by ``cycles`` times the turn from ``before`` to it."""
    turn = Rotation.from_matrix(before.T @ now).as_rotvec()  # in the body's frame
    return now @ Rotation.from_rotvec(cycles * turn).as_matrix()


class Follower:
    """``plan(state) -> policy`` for ``rollout``: follow ``path`` with learned manoeuvres.

    One follower serves one run (it keeps the decisions it made and the gait
    it swims); make a new one for another.

    Args:
        scene: the scene swum in (its model and dynamics give the root's pose).
        gaits: the manoeuvre library, ``{name: SineGait}``; must hold ``straight``.
            Each is driven over every DOF any of them drives, holding at 0 rad
            those it does not (``SineGait.on``: a manoeuvre's rudder).
        servo: ``servo(gait) -> policy``, the creature's PD servo tracking a gait.
        path: the path, of the scene's dimension.
        period: the gait cycle T [s]; a decision every T.
        dead_band: ``eps`` of ``choose_maneuver`` [m].
        blend: share of a cycle over which a change of manoeuvre blends.
        lead: cycles by which the mean heading is carried on (``LEAD``).
        look_ahead: cycles of travel by which the tangent lies ahead of the nearest
            point (``LOOK_AHEAD``).
        rates: graded steering (module docstring): ``{manoeuvre: its turn a cycle}``
            [rad], > 0; None: the paper's rule.
        aim: graded steering's ``AIM``.
        gain: graded steering's ``rule.GAIN``.
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
        lead: float = LEAD,
        look_ahead: float = LOOK_AHEAD,
        rates: Mapping[str, float] | None = None,
        aim: float = AIM,
        gain: float = GAIN,
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
        if rates is not None and not all(rate > 0 for rate in rates.values()):
            raise ValueError(f"graded steering needs each manoeuvre's turn a cycle > 0 rad; "
                             f"got {dict(rates)}")  # fmt: skip
        dofs = tuple(dict.fromkeys(d for gait in gaits.values() for d in gait.dofs))
        gaits = {name: gait.on(dofs) for name, gait in gaits.items()}  # a rudder's DOFs too
        self.scene, self.gaits, self.servo, self.path = scene, gaits, servo, path
        self.period, self.dead_band, self.blend = float(period), float(dead_band), float(blend)
        self.decisions: list[Decision] = []
        self._policy = None
        self._next = None  # time of the next decision [s]
        self._rotations = []  # the root's rotation at every frame since the last decision
        self._last_mean = None  # the root's mean rotation over the cycle before
        self.lead, self.look_ahead = float(lead), float(look_ahead)
        self.rates = None if rates is None else dict(rates)
        self.aim, self.gain = float(aim), float(gain)
        self._last_position = None  # the root's at the last decision
        self._gait = None  # the gait swum since the last decision

    def __call__(self, state: State):
        """The policy for the frame starting at ``state`` (a new decision at a cycle's start)."""
        position, rotation = root_pose(self.scene, state.qpos)
        self._rotations.append(rotation)
        if self._next is None or state.time >= self._next - 1e-9 * self.period:
            mean = mean_rotation(self._rotations)
            ahead = mean if self._last_mean is None else lead(self._last_mean, mean, self.lead)
            self._decide(state, position, ahead)
            self._rotations, self._last_mean = [rotation], mean
        return self._policy

    def _decide(self, state: State, position, rotation) -> None:
        travelled = 0.0 if self._last_position is None else np.linalg.norm(
            position - self._last_position)  # fmt: skip
        progress = self.path.progress(position)  # of the nearest point
        point, _ = self.path.at(progress)
        _, tangent = self.path.at(progress + self.look_ahead * travelled)
        self._last_position = position
        offset = root_frame(point - position, rotation)
        along = root_frame(tangent, rotation)
        if self.rates is None or travelled == 0.0:
            wanted = choose_maneuver(offset, along, self.dead_band)
            asked = {} if wanted == STRAIGHT else {wanted: 1.0}
        else:
            aim, _ = self.path.at(progress + self.aim * travelled)
            asked = graded_shares(root_frame(aim - position, rotation), self.rates, self.gain)
            wanted = max(asked, key=asked.get) if asked else STRAIGHT
        shares = {name: share for name, share in asked.items() if name in self.gaits}
        chosen = max(shares, key=shares.get) if shares else STRAIGHT
        self.decisions.append(Decision(state.time, chosen, wanted, offset, along, shares))
        gait = mix([self.gaits[STRAIGHT], *(self.gaits[name] for name in shares)],
                   [1.0 - sum(shares.values()), *shares.values()])  # fmt: skip
        before = gait if self._gait is None else self._gait
        self._policy = self.servo(SwitchedGait(before, gait, state.time, self.blend * self.period))
        self._gait = gait
        start = 0.0 if self._next is None else self._next
        self._next = start + self.period * (1 + np.floor((state.time - start) / self.period))
