"""The follower as a planner: when it decides, what it hands the servo, what it records.

In a vacuum (fluid 'none') the eel hardly moves, so the path's place alone
decides: these are the rule's answers seen through a real rollout.
"""

from dataclasses import replace

import numpy as np
import pytest

import aquagait as ag
from aquagait.control import GaitSpec, mix
from aquagait.path import Follower, Path, root_pose
from aquagait.path.follower import LEAD, lead, mean_rotation
from aquagait.path.rule import GAIN

EEL = ag.creatures.get("eel2d")


@pytest.fixture(scope="module")
def scene():
    return ag.make_scene(EEL, fluid="none")


def _library(maneuvers=("straight", "turn-left", "turn-right")):
    straight = EEL.gait.unpack(EEL.default_gait)
    offsets = {"straight": 0.0, "turn-left": 0.2, "turn-right": -0.2}
    return {
        m: EEL.spec("turn-left").unpack(np.r_[EEL.default_gait, [offsets[m]] * 4])
        if m != "straight" else straight
        for m in maneuvers
    }  # fmt: skip


def _follow(scene, path, seconds=3.0, maneuvers=("straight", "turn-left", "turn-right")):
    handed = []

    def servo(gait):
        handed.append(gait)
        return EEL.servo(gait)

    follower = Follower(scene, _library(maneuvers), servo, path, period=1.0, dead_band=0.05)
    ag.rollout(scene, ag.init_state(scene), None, seconds, plan=follower)
    return follower, handed


def _line(scene, side):
    """A line parallel to the eel's axis, ``side`` metres to its left."""
    start, _ = root_pose(scene, ag.init_state(scene).qpos)
    return Path(np.array([[-1.0, side], [5.0, side]]) + [0.0, start[1]])


@pytest.mark.parametrize("side, expected", [(0.3, "turn-left"), (-0.3, "turn-right"),
                                            (0.0, "straight"), (0.03, "straight")])  # fmt: skip
def test_it_decides_once_a_cycle_by_the_rule(scene, side, expected):
    follower, handed = _follow(scene, _line(scene, side))
    assert [d.time for d in follower.decisions] == [0.0, 1.0, 2.0]
    assert {d.maneuver for d in follower.decisions} == {expected}
    assert len(handed) == 3
    first = follower.decisions[0]
    np.testing.assert_allclose(first.offset[1], side, atol=1e-9)  # the path, in the root frame
    np.testing.assert_allclose(first.tangent, [1.0, 0.0], atol=1e-9)


def test_a_change_of_manoeuvre_blends_from_the_last_one_over_a_quarter_cycle(scene):
    handed = []
    servo = lambda gait: handed.append(gait) or EEL.servo(gait)  # noqa: E731
    lib = _library()
    follower = Follower(scene, lib, servo, _line(scene, 0.3), period=1.0, dead_band=0.05)
    state = ag.init_state(scene)
    first = follower(state)
    assert follower(replace(state, time=0.5)) is first  # no decision within a cycle
    follower.path = _line(scene, -0.3)  # the path jumps to the right
    follower(replace(state, time=1.0))
    assert [d.maneuver for d in follower.decisions] == ["turn-left", "turn-right"]
    left, right = lib["turn-left"].offset, lib["turn-right"].offset
    assert np.all(handed[0].before.offset == left) and np.all(handed[0].after.offset == left)
    switch = handed[1]
    assert np.all(switch.before.offset == left) and np.all(switch.after.offset == right)
    assert (switch.start, switch.duration) == (1.0, 0.25)


def test_an_unlearned_manoeuvre_is_swum_straight_and_recorded(scene):
    follower, _ = _follow(scene, _line(scene, 0.3), seconds=1.0, maneuvers=("straight",))
    (decision,) = follower.decisions
    assert (decision.maneuver, decision.wanted, decision.unlearned) == (
        "straight", "turn-left", True)  # fmt: skip


def test_a_follower_needs_a_straight_gait_and_a_path_of_its_dimension(scene):
    with pytest.raises(ValueError, match="straight gait"):
        Follower(scene, {"turn-left": _library()["turn-left"]}, EEL.servo,
                 _line(scene, 0.0), 1.0, 0.05)  # fmt: skip
    with pytest.raises(ValueError, match="3D path for a 2D creature"):
        Follower(scene, _library(), EEL.servo, Path(np.eye(3)), 1.0, 0.05)


def _about_z(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def test_the_heading_is_the_cycle_s_mean_carried_on_by_half_its_turn():
    """A head swaying +-10 degrees about a heading of 30 averages to 30; a heading that
    went from 20 to 30 degrees over a cycle is carried on to 35 (``LEAD``: half a cycle)."""
    sway = [_about_z(np.radians(30 + 10 * np.sin(a))) for a in np.linspace(0, 2 * np.pi, 31)]
    np.testing.assert_allclose(mean_rotation(sway), _about_z(np.radians(30)), atol=1e-12)
    ahead = lead(_about_z(np.radians(20)), _about_z(np.radians(30)), LEAD)
    np.testing.assert_allclose(ahead, _about_z(np.radians(35)), atol=1e-12)
    tilted = _about_z(0.3) @ np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0.0]])  # about x too
    np.testing.assert_allclose(lead(tilted, tilted, 0.5), tilted, atol=1e-12)


def test_gaits_over_different_dofs_are_all_driven_over_every_one(scene):
    """A manoeuvre with a rudder drives DOFs the straight gait leaves at rest."""
    lib = _library()
    straight = GaitSpec(dofs=("j1", "j2")).unpack([0.2, 0.3, 0.0, -1.0])  # the rest held at 0
    handed = []
    servo = lambda gait: handed.append(gait) or EEL.servo(gait)  # noqa: E731
    follower = Follower(scene, {**lib, "straight": straight}, servo, _line(scene, 0.0), 1.0, 0.05)
    follower(ag.init_state(scene))
    (switch,) = handed
    assert switch.dofs == ("j1", "j2", "j3", "j4")
    np.testing.assert_allclose(switch.angles(0.3), [*straight.angles(0.3), 0.0, 0.0])


@pytest.mark.parametrize("look_ahead, expected", [(1.0, "turn-left"), (0.0, "straight")])
def test_on_the_outside_of_a_bend_it_reads_the_path_a_cycle_ahead(scene, look_ahead, expected):
    """The eel outside a left circle of radius 0.6 m, 0.4 m on and 45 degrees left of its
    start after one cycle: its heading has passed the tangent at the nearest point (32
    degrees), so the nearest tangent says the path is coming back and the rule would swim
    straight; but the circle bends away from it, and 0.4 m further on (as far as it swam
    that cycle) the path heads 70 degrees left: keep turning."""
    start, _ = root_pose(scene, ag.init_state(scene).qpos)
    theta = np.linspace(-np.pi / 2, 3 * np.pi / 2, 721)  # from the start, turning left
    circle = Path(start + 0.6 * np.c_[np.cos(theta), 1.0 + np.sin(theta)])
    follower = Follower(scene, _library(), EEL.servo, circle, period=1.0, dead_band=0.05,
                        lead=0.0, look_ahead=look_ahead)  # fmt: skip
    state = ag.init_state(scene)
    qpos = state.qpos.copy()
    qpos[:2] = [0.0, -0.1]  # 0.1 m outside the circle, heading along it
    follower(replace(state, qpos=qpos.copy()))
    assert follower.decisions[0].maneuver == "turn-left"
    qpos[:3] = [0.4, -0.05, np.pi / 4]  # where a cycle's turn took it
    for time in np.arange(1, 31) / 30:  # its heading over the cycle, held: no lead to add
        follower(replace(state, qpos=qpos.copy(), time=time))
    decision = follower.decisions[1]
    assert decision.offset[1] > 0.05  # the circle still lies to its left
    assert decision.maneuver == expected


def test_graded_it_mixes_a_share_of_the_turn_the_bearing_asks_for(scene):
    """Its first cycle by the paper's rule (no travel to aim ahead by); then, with the eel
    moved 0.3 m along a line that lies 0.1 m to its left, the aim point two cycles' travel
    further on bears atan(0.1 / 0.6) off its heading: the share GAIN times that over the
    turn's rate, and the gait handed over is that mix of straight and turn."""
    handed = []

    def servo(gait):
        handed.append(gait)
        return EEL.servo(gait)

    start, _ = root_pose(scene, ag.init_state(scene).qpos)
    line = Path(np.array([[-1.0, 0.1], [5.0, 0.1]]) + [0.0, start[1]])
    library = _library()
    follower = Follower(scene, library, servo, line, period=1.0, dead_band=0.05, lead=0.0,
                        rates={"turn-left": 1.0, "turn-right": 1.0})  # fmt: skip
    state = ag.init_state(scene)
    follower(state)
    assert follower.decisions[0].shares == {"turn-left": 1.0}  # the paper's rule: 0.1 > eps
    qpos = state.qpos.copy()
    qpos[0] += 0.3  # a cycle's travel, heading held along +x
    for time in np.arange(1, 31) / 30:
        follower(replace(state, qpos=qpos.copy(), time=time))
    decision = follower.decisions[1]
    share = GAIN * np.arctan2(0.1, 0.6) / 1.0
    assert decision.maneuver == "turn-left"
    assert decision.shares["turn-left"] == pytest.approx(share, rel=1e-6)
    expected = mix([library["straight"], library["turn-left"]], [1 - share, share])
    np.testing.assert_allclose(handed[-1].after.angles(1.6), expected.angles(1.6))


def test_graded_steering_needs_positive_rates(scene):
    with pytest.raises(ValueError, match="> 0 rad"):
        Follower(scene, _library(), EEL.servo, _line(scene, 0.0), 1.0, 0.05,
                 rates={"turn-left": 0.0})  # fmt: skip
