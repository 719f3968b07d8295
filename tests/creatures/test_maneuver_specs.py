"""A creature's manoeuvres (paper §5): the parameterization each is learned in, its shipped
gaits in the side-car, and what a creature that has not learned one is told."""

import numpy as np
import pytest
from tests.creatures.test_metadata import SWIMMER, write

import aquagait as ag
from aquagait.creatures import CreatureError, load
from aquagait.creatures.creature import UnlearnedManeuver, maneuver_start

TIMES = np.linspace(0.0, 1.0, 21)


def test_a_turn_frees_every_offset_within_the_joint_limits_and_half_a_radian():
    eel = ag.creatures.get("eel2d")
    spec = eel.spec("turn-left")
    assert spec.names == eel.gait.names + tuple(f"offset[j{k}]" for k in range(1, 5))
    lower, upper = eel.gait_limits()
    offsets = slice(eel.gait.size, spec.size)
    assert np.all(spec.lower[offsets] == np.maximum(lower, -0.5))
    assert np.all(spec.upper[offsets] == np.minimum(upper, 0.5))
    np.testing.assert_array_equal(spec.lower[: eel.gait.size], eel.gait.lower)  # the rest kept
    assert eel.spec("straight") is eel.gait


def test_a_turn_drops_the_mirror_and_a_pitch_keeps_it():
    turtle = ag.creatures.get("turtle3d")  # right flippers mirror the left ones
    assert turtle.gait.mirror
    turn, pitch = turtle.spec("turn-right"), turtle.spec("pitch-up")
    assert not turn.mirror and pitch.mirror == turtle.gait.mirror
    assert turn.size == 3 * len(turtle.gait.dofs)  # amplitude, phase, offset for every DOF
    assert pitch.size == 3 * len(turtle.gait.independent)
    # a right flipper's bounds are its left twin's
    left, right = turn.names.index("amplitude[wrist_l]"), turn.names.index("amplitude[wrist_r]")
    assert (turn.lower[right], turn.upper[right]) == (turn.lower[left], turn.upper[left])


def test_a_gait_whose_offsets_are_free_keeps_their_bounds():
    manta = ag.creatures.get("manta")  # offsets free already (21 dims)
    pitch = manta.spec("pitch-down")
    assert pitch.names == manta.gait.names
    np.testing.assert_array_equal(pitch.lower, manta.gait.lower)


STARTS = [("eel2d", "turn-left"), ("turtle3d", "turn-right"), ("frog", "pitch-up"),
          ("manta", "turn-left")]  # fmt: skip


@pytest.mark.parametrize("name, maneuver", STARTS)
def test_a_manoeuvre_s_search_starts_from_the_straight_gait(name, maneuver):
    creature = ag.creatures.get(name)
    x0 = maneuver_start(creature, maneuver)
    spec = creature.spec(maneuver)
    assert np.all((spec.lower <= x0) & (x0 <= spec.upper))
    straight, start = creature.gait.unpack(creature.default_gait), spec.unpack(x0)
    np.testing.assert_allclose([start.angles(t) for t in TIMES],
                               [straight.angles(t) for t in TIMES], atol=1e-12)  # fmt: skip


def test_unknown_manoeuvres_are_refused():
    with pytest.raises(ValueError, match="manoeuvres: straight, turn-left"):
        ag.creatures.get("eel2d").spec("loop")


def _swimmer_with(tmp_path, gaits):
    return load(write(tmp_path, "swimmer3", SWIMMER, {"gaits": gaits}))


def test_shipped_manoeuvres_are_read_in_their_own_parameterization(tmp_path):
    left = {"params": [0.5, 0.6, 0.0, -1.0, 0.2, 0.3], "provenance": {"method": "hand-set"}}
    swimmer = _swimmer_with(tmp_path, {"turn-left": left})
    assert swimmer.maneuvers == ("straight", "turn-left")
    np.testing.assert_array_equal(swimmer.maneuver_gait("turn-left"), left["params"])
    policy = swimmer.policy(maneuver="turn-left")
    np.testing.assert_allclose(policy.gait.offset, [0.2, 0.3])
    np.testing.assert_array_equal(swimmer.maneuver_gait("straight"), swimmer.default_gait)


def test_a_shipped_manoeuvre_of_the_straight_gait_s_length_is_refused(tmp_path):
    with pytest.raises(CreatureError, match=r"gaits\.turn-left\.params: 4 numbers; the gait has "
                                            r"6: .*offset\[joint_1\]"):  # fmt: skip
        _swimmer_with(tmp_path, {"turn-left": {"params": [0.5, 0.6, 0.0, -1.0]}})


def test_a_shipped_manoeuvre_outside_the_joint_limits_is_refused(tmp_path):
    # offset 0.5 plus amplitude 1.7 swings past the 100 degree limit
    with pytest.raises(CreatureError, match="joint_1: swings over"):
        _swimmer_with(tmp_path, {"turn-left": {"params": [1.7, 0.6, 0.0, 0.0, 0.5, 0.0]}})


def test_an_unlearned_manoeuvre_says_what_is_learned_and_how_to_learn_it():
    eel = ag.creatures.get("accordion2d")
    with pytest.raises(UnlearnedManeuver) as err:
        eel.maneuver_gait("turn-right")
    assert "accordion2d has not learned 'turn-right'; it has learned straight" in str(err.value)
    assert "aquagait optimize accordion2d --maneuver turn-right" in str(err.value)


def test_a_dof_the_straight_gait_holds_at_rest_becomes_a_rudder():
    """The 2D turtle's rear flipper trails when it swims straight (not in its gait); a
    manoeuvre may set it at an angle, as a turtle steers with its rear flippers."""
    turtle = ag.creatures.get("turtle2d")
    assert "rear_hip" not in turtle.gait.dofs
    spec = turtle.spec("turn-left")
    assert spec.held == ("rear_hip", "rear_knee")
    assert spec.names[-2:] == ("offset[rear_hip]", "offset[rear_knee]")
    assert "amplitude[rear_hip]" not in spec.names
    lower, upper = turtle.gait_limits("turn-left")
    assert len(lower) == 4 and spec.upper[-1] == min(upper[-1], 0.5)
