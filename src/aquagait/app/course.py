"""Steering with learned manoeuvres: what path following and a swim that keeps its course
share.

    course = prepare_course(creature, scene, period)   # measures each manoeuvre's turn
    follower = course.follower(scene, straight, creature.servo, period)
    trajectory = rollout(scene, init_state(scene), None, seconds, plan=follower)

Graded steering (``aquagait.path.rule.graded_shares``) mixes a share of a
manoeuvre into the straight gait by how far the path ahead bears off the
heading and how fast the manoeuvre turns. Each manoeuvre's turn a cycle is
measured here, by swimming it ``RATE_CYCLES`` cycles from rest, as its
search did (``turn_rates``).

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
from aquagait.objectives import MANEUVERS, rotation_vector
from aquagait.path import Follower, Path, root_pose
from aquagait.sim import Scene, init_state, rollout

RATE_CYCLES = 2
"""Cycles from rest over which graded steering measures each manoeuvre's turn (a
manoeuvre's search swims two)."""

DEAD_BAND = 0.1
"""The follower's dead band, in body lengths (the paper's rule; graded steering uses it at
its first decision only)."""

KEEP_GAIN = 0.5
"""Graded steering's gain for keeping a course: a quarter of the path follower's
(``rule.GAIN``), which anticipates bends. On a straight line there is no bend to meet, only
drift, and the correction a manoeuvre starts goes on turning after its cycle: eel2d in the
simple fluid, its turns' measured rates 0.48 rad a cycle, weaves with a growing amplitude
at gains 2 and 1 (33 and 24 degrees by cycle 8), alternates at 0.75 (within 2 degrees)
and holds its heading within 1 degree at 0.5."""

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
    creature: Creature, scene: Scene, sines: dict, period: float, progress=None
) -> dict[str, float]:
    """Each manoeuvre's turn a cycle [rad], for graded steering: the root's rotation about
    the manoeuvre's axis over ``RATE_CYCLES`` cycles from rest in ``scene`` (to its mean
    orientation over the last, as the search measures it), per cycle.

    Args:
        sines: ``{manoeuvre: SineGait}``; ``straight`` is skipped.
        period: the gait cycle [s].
        progress: ``progress(manoeuvre) -> progress(done, total)`` for each swim, or None.

    Raises:
        SteeringError: a manoeuvre that does not turn its way (learn it again).
    """
    rates = {}
    for name, gait in sines.items():
        if name == STRAIGHT:
            continue
        report = None if progress is None else progress(name)
        trajectory = rollout(scene, init_state(scene), creature.servo(gait),
                             RATE_CYCLES * period, progress=report)  # fmt: skip
        axis = np.asarray(MANEUVERS[name][1], dtype=float)
        turn = float(axis @ rotation_vector(creature.model, trajectory, period))
        if not turn > 0:
            fix = ("In a vacuum only the body's change of shape turns it: steer in a fluid"
                   if scene.fluid.name == "none" else "Learn it again")  # fmt: skip
            raise SteeringError(
                f"{creature.name}'s {name} turns {turn:.3g} rad its way over {RATE_CYCLES} "
                f"cycles from rest: graded steering needs each manoeuvre to turn its way. {fix}"
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


def prepare_course(creature: Creature, scene: Scene, period: float, progress=None) -> Course:
    """The course keeper's manoeuvres (the creature's shipped ones) and their rates.

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
    return Course(maneuvers, turn_rates(creature, scene, maneuvers, period, progress))
