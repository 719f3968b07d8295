"""A swim that keeps its course: shares of the learned manoeuvres mixed into its gait, to hold
the line ahead of its start (``aquagait.app.course``)."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.app import SwimSetupError, prepare_swim, run_swim
from aquagait.cli import main
from aquagait.control import mix
from aquagait.io import write_gait
from aquagait.metrics import Cycles
from aquagait.sim import init_state, rollout


@pytest.fixture(scope="module")
def kept():
    """eel2d set up to keep its course in the simple fluid (its turns' rates measured)."""
    return prepare_swim("eel2d", seconds=3.0, fluid="simple", keep_course=True)


def test_a_kept_course_holds_a_drifting_gait_to_its_heading(kept):
    """The straight gait with a tenth of turn-left mixed in turns left about 5 degrees a
    cycle, open loop: 59 degrees after 12 cycles (the turns of 2026-12-06). Kept, it is at
    most 6.1 degrees off, in its second cycle (the first is the open loop's: the first
    correction acts from the second), and 2.6 at the end: never more than a cycle and a
    half of the open loop's drift off, and at the end within one cycle's."""
    creature, scene = kept.creature, kept.scene
    straight = kept.gait
    drifting = mix([straight, kept.course.maneuvers["turn-left"]], [0.9, 0.1])
    seconds = 12 * kept.period
    open_loop = rollout(scene, init_state(scene), creature.servo(drifting), seconds)
    follower = kept.course.follower(scene, drifting, creature.servo, kept.period)
    steered = rollout(scene, init_state(scene), None, seconds, plan=follower)
    drift = Cycles(creature.model, open_loop, kept.period).attitudes()[:, 0]
    heading = Cycles(creature.model, steered, kept.period).attitudes()[:, 0]
    assert drift[-1] > 10 * drift[0] > 0
    assert np.all(np.abs(heading) < 1.5 * drift[0]) and abs(heading[-1]) < drift[0]
    assert abs(steered.qpos[-1, 1]) < 0.05 * creature.model.body_length * 12  # on the line


def test_a_swim_that_keeps_its_course_says_how_it_steered(kept):
    assert set(kept.course.rates) == {"turn-left", "turn-right"}
    assert all(0.1 < rate < 1.5 for rate in kept.course.rates.values())  # radians a cycle
    run = run_swim(kept)
    shares = run.metrics["course_shares"]
    assert set(shares) == {"turn-left", "turn-right"}
    assert all(0.0 <= share <= 1.0 for share in shares.values())
    assert run.config["keep_course"]["rates"] == kept.course.rates
    assert any("kept its course" in note for note in run.notes)
    assert prepare_swim("eel2d", fluid="simple").course is None
    assert run_swim(prepare_swim("eel2d", seconds=1.0, fluid="none")).config["keep_course"] is None


def test_keeping_a_course_needs_learned_manoeuvres_and_a_straight_gait(tmp_path):
    needs = r"fish has learned no manoeuvre .* turns and pitches.*--maneuver pitch-up.*--learned"
    with pytest.raises(SwimSetupError, match=needs):
        prepare_swim("fish", fluid="none", keep_course=True)
    with pytest.raises(SwimSetupError, match="this gait is turn-left: swim a straight gait"):
        prepare_swim("eel2d", maneuver="turn-left", fluid="none", keep_course=True)
    eel = ag.creatures.get("eel2d")
    free = write_gait(tmp_path / "free.json", eel, np.append(eel.default_gait, 1.2),
                      "straight", free_period=True)  # fmt: skip
    with pytest.raises(SwimSetupError, match=r"sets its own period \(--free-period\)"):
        prepare_swim("eel2d", gait=free, fluid="none", keep_course=True)


def test_the_command_keeps_a_course(tmp_path, capsys):
    out = tmp_path / "kept"
    status = main(["swim", "eel2d", "--fluid", "simple", "--seconds", "2",
                          "--keep-course", "--no-video", "--out", str(out)])  # fmt: skip
    assert status == 0
    assert "kept its course with its manoeuvres" in capsys.readouterr().out
    assert (out / "metrics.json").exists()
