"""Steering with learned manoeuvres: what path following and a swim that keeps its course
share.

    course = prepare_course(creature, scene, straight, period)  # each manoeuvre's turn
    follower = course.follower(scene, straight, creature.servo, period)
    trajectory = rollout(scene, init_state(scene), None, seconds, plan=follower)

Graded steering (``aquagait.path.rule.graded_shares``) mixes a share of a
manoeuvre into the straight gait by how far the path ahead bears off the
heading and how fast the manoeuvre turns. Each manoeuvre's turn a cycle is
measured here under way, as steering uses it: ``UNDER_WAY_CYCLES`` cycles of
the straight gait from rest, then ``RATE_CYCLES`` of the manoeuvre
(``turn_rates``). Under way a manoeuvre turns other than from rest, where its
search measured it: eel2d's turn-left of 2026-12-06 turns 45-64 degrees a
cycle after two straight cycles and 69-89 after one of turn-right, against 47
from rest, and steering by its rate from rest over-steered round a circle
(docs/follow.md).

A swim that keeps its course follows the straight line ahead of its start
(+x, where every library creature faces). Open-loop gaits leave a 3D swimmer
neutral in pitch and roll and a 2D one in heading: nothing rights a body
that the wake or its own stroke has turned, and a gait searched over a few
cycles may pitch a few degrees a cycle (issue 32: the manta loops nose up by
its twelfth cycle). Real swimmers correct with their fins; the course keeper
corrects with the manoeuvres the creature has learned, as the path follower
does, a share at each cycle's start.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from aquagait.app.errors import SetupError
from aquagait.control.gait import SineGait
from aquagait.creatures import Creature
from aquagait.creatures.creature import STRAIGHT
from aquagait.objectives import MANEUVERS, cycle_frames, rotation_between
from aquagait.path import Follower, Path, root_pose
from aquagait.sim import Scene, init_state, rollout

UNDER_WAY_CYCLES = 2
"""Cycles of the straight gait from rest before a manoeuvre's turn is measured: as far as
a straight search's swim, to cruise or near it."""

RATE_CYCLES = 2
"""Cycles of a manoeuvre over which graded steering measures its turn (a manoeuvre's search
swims two)."""

DEAD_BAND = 0.1
"""The follower's dead band, in body lengths (the paper's rule; graded steering uses it at
its first decision only)."""

KEEP_GAIN = 0.5
"""Graded steering's gain for keeping a course: a quarter of the path follower's
(``rule.GAIN``), which anticipates bends. On a straight line there is no bend to meet, only
drift, and the correction a manoeuvre starts goes on turning after its cycle: eel2d in the
simple fluid (its turns of 2026-12-04, their rates from rest 0.48 rad a cycle) weaves with
a growing amplitude at gains 2 and 1 (33 and 24 degrees by cycle 8), alternates at 0.75
(within 2 degrees) and holds its heading within 1 degree at 0.5."""

AHEAD = 1000.0
"""Body lengths of the straight line a course keeper follows: more than any swim covers."""


class SteeringError(SetupError):
    """Steering cannot start: a manoeuvre that turns the wrong way, or none learned."""


def shipped_maneuvers(creature: Creature) -> dict:
    """``{manoeuvre: (spec, params, source)}`` of the creature's side-car, ``straight``
    included (``default`` where the side-car has none: the creature's default gait)."""
    return {
        name: (creature.spec(name), creature.maneuver_gait(name),
               "shipped" if name != STRAIGHT or STRAIGHT in creature.gaits else "default")
        for name in creature.maneuvers
    }  # fmt: skip


def sines(gaits: dict) -> dict:
    """``{manoeuvre: SineGait}`` of a manoeuvre library ``{name: (spec, params, source)}``."""
    return {name: spec.unpack(x) for name, (spec, x, _) in gaits.items()}


def turn_rates(
    creature: Creature,
    scene: Scene,
    straight: SineGait,
    maneuvers: Mapping[str, SineGait],
    period: float,
    progress=None,
) -> dict[str, float]:
    """Each manoeuvre's turn a cycle [rad] under way, for graded steering.

    The creature swims ``UNDER_WAY_CYCLES`` cycles of ``straight`` from rest in ``scene``,
    then ``RATE_CYCLES`` of the manoeuvre; its turn is the root's rotation about the
    manoeuvre's axis from its mean orientation over the last straight cycle to that over
    the last cycle (``aquagait.objectives.rotation_between``: free of the recoil within
    a beat), per cycle.

    Args:
        straight: the gait the manoeuvres are mixed into.
        maneuvers: ``{manoeuvre: SineGait}``; ``straight`` is skipped.
        period: the gait cycle [s].
        progress: ``progress(manoeuvre) -> progress(done, total)`` for each swim, or None.

    Raises:
        SteeringError: a manoeuvre that does not turn its way (learn it again).
    """
    cruise, switch = creature.servo(straight), UNDER_WAY_CYCLES * period
    seconds = (UNDER_WAY_CYCLES + RATE_CYCLES) * period
    rates = {}
    for name, gait in maneuvers.items():
        if name == STRAIGHT:
            continue
        report = None if progress is None else progress(name)
        turning = creature.servo(gait)

        def plan(state, turning=turning):
            return cruise if state.time < switch - 1e-9 * period else turning

        trajectory = rollout(scene, init_state(scene), None, seconds, progress=report,
                             record_fluid=False, plan=plan)  # fmt: skip
        under_way, last = (cycle_frames(trajectory, end, period) for end in (switch, seconds))
        axis = np.asarray(MANEUVERS[name][1], dtype=float)
        turn = float(axis @ rotation_between(creature.model, trajectory, under_way, last))
        if not turn > 0:
            fix = ("In a vacuum only the body's change of shape turns it: steer in a fluid"
                   if scene.fluid.name == "none" else "Learn it again")  # fmt: skip
            raise SteeringError(
                f"{creature.name}'s {name} turns {turn:.3g} rad its way over {RATE_CYCLES} "
                f"cycles under way (after {UNDER_WAY_CYCLES} of its straight gait): graded "
                f"steering needs each manoeuvre to turn its way. {fix}"
            )
        rates[name] = turn / RATE_CYCLES
    return rates


@dataclass(frozen=True, eq=False)
class Course:
    """The course straight ahead of the start, kept by graded steering.

    Attributes:
        maneuvers: ``{manoeuvre: SineGait}``, the learned ones it steers with (not
            ``straight``: the swim's own gait is that).
        rates: ``{manoeuvre: its turn a cycle}`` [rad] (``turn_rates``).
    """

    maneuvers: Mapping[str, SineGait]
    rates: Mapping[str, float]

    def follower(self, scene: Scene, straight: SineGait, servo, period: float) -> Follower:
        """A fresh ``Follower`` (one serves one run) of the line ahead of the start, with
        ``straight`` as the gait the manoeuvres are mixed into."""
        model = scene.model
        start, _ = root_pose(scene, init_state(scene).qpos)
        ahead = np.zeros(model.dim)
        ahead[0] = AHEAD * model.body_length
        line = Path(np.stack([start, start + ahead]))
        gaits = {STRAIGHT: straight, **self.maneuvers}
        return Follower(scene, gaits, servo, line, period, DEAD_BAND * model.body_length,
                        rates=self.rates, gain=KEEP_GAIN)  # fmt: skip


def prepare_course(
    creature: Creature, scene: Scene, straight: SineGait, period: float, progress=None
) -> Course:
    """The course keeper's manoeuvres (the creature's shipped ones) and their rates under way
    with ``straight``, the gait the swim keeps its course with.

    Raises:
        SteeringError: the creature has learned no manoeuvre to steer with (the message
            names the commands that learn them), or one turns the wrong way.
    """
    maneuvers = {name: gait for name, gait in sines(shipped_maneuvers(creature)).items()
                 if name != STRAIGHT}  # fmt: skip
    if not maneuvers:
        wanted = ("turn-left", "turn-right") + ("pitch-up", "pitch-down") * (creature.dim == 3)
        runs = [f"runs/{creature.name}-{m}" for m in wanted]
        learn = "; ".join(f"aquagait optimize {creature.name} --maneuver {m} --out {run}"
                          for m, run in zip(wanted, runs, strict=True))  # fmt: skip
        raise SteeringError(
            f"{creature.name} has learned no manoeuvre to keep its course with (it steers "
            f"with turns{' and pitches' * (creature.dim == 3)}). Learn them with: {learn}; "
            f"then follow the line ahead with them: aquagait follow {creature.name} --path "
            f"line --learned {' '.join(runs)}"
        )
    return Course(maneuvers, turn_rates(creature, scene, straight, maneuvers, period, progress))
