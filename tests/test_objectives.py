"""The objective's terms on trajectories whose answers are known."""

import numpy as np
import pytest

import aquagait as ag
from aquagait import objectives as obj
from aquagait.sim import Trajectory

# three boxes in a chain whose middle hinge folds the tail back over the head
FOLDING = """<mujoco><custom><numeric name="aquagait_depth" data="0.02"/></custom>
  <worldbody><body name="head">
    <joint type="slide" axis="1 0 0"/><joint type="slide" axis="0 1 0"/>
    <joint type="hinge" axis="0 0 1"/>
    <geom type="box" size=".05 .01 .01" density="1000"/>
    <body name="mid" pos="-.05 0 0"><joint name="a" type="hinge" axis="0 0 1" range="-179 179"/>
      <geom type="box" size=".005 .01 .01" pos="-.005 0 0" density="1000"/>
      <body name="tail" pos="-.01 0 0"><joint name="b" type="hinge" axis="0 0 1" range="-179 179"/>
        <geom type="box" size=".05 .01 .01" pos="-.05 0 0" density="1000"/></body>
    </body>
  </body></worldbody></mujoco>"""


def trajectory(qpos, energy=None, fps=30.0):
    qpos = np.asarray(qpos, dtype=float)
    frames, nq = qpos.shape
    nv = nq if energy is None else np.shape(energy)[1]
    energy = np.zeros((frames, nv)) if energy is None else np.asarray(energy, dtype=float)
    zeros = np.zeros((frames, nv))
    time = np.arange(frames) / fps
    return Trajectory(time, qpos, zeros, zeros, energy, 1 / 300, fps)


def test_distance_is_the_displacement_along_the_direction(eel):
    path = np.zeros((31, eel.model.nq))
    path[:, 0] = np.linspace(0, 0.3, 31)  # 0.3 m along x
    path[:, 1] = np.linspace(0, 0.1, 31)  # 0.1 m along y
    traj = trajectory(path)
    assert obj.distance(eel.model, traj, (1, 0)) == pytest.approx(-0.3)
    assert obj.distance(eel.model, traj, (0, 2)) == pytest.approx(-0.1)  # direction is normalized
    assert obj.deviation(eel.model, traj, (1, 0)) == pytest.approx(0.1)


def test_deviation_adds_the_turn_in_2d_and_3d(eel):
    path = np.zeros((2, eel.model.nq))
    path[1, 2] = -0.25  # the eel turned 0.25 rad clockwise
    assert obj.deviation(eel.model, trajectory(path), (1, 0)) == pytest.approx(0.25)
    fish = ag.creatures.get("fish").model
    path = np.tile(fish.qpos0, (2, 1))
    angle = 0.4
    path[1, 3:7] = [np.cos(angle / 2), 0, np.sin(angle / 2), 0]  # 0.4 rad about y
    assert obj.root_rotation(fish, trajectory(path)) == pytest.approx(angle)


def test_energy_counts_only_above_the_bound():
    energy = np.outer(np.linspace(0, 1, 11), [0.0, 0.2, 0.3])  # 0.5 J spent in all
    traj = trajectory(np.zeros((11, 3)), energy)
    assert obj.work(traj) == pytest.approx(0.5)
    assert obj.energy(traj, bound=0.6) == 0.0
    assert obj.energy(traj, bound=0.4) == pytest.approx(0.5)


@pytest.fixture(scope="module")
def folding():
    """The folding chain's model, a scene for it, and its pose folded flat (tail under head).

    No fluid: the collision term bakes the links' shape itself, the same as an
    Euler scene's (the same volumes to the last digit).
    """
    model = ag.load_model(FOLDING)
    scene = ag.make_scene(model, fluid="none")
    folded = model.qpos0.copy()
    folded[3:5] = [np.pi / 2, np.pi / 2]  # the tail folds back along the head, 1 cm lower
    return model, scene, folded


def test_collision_integrates_the_overlap_of_non_adjacent_links(folding):
    model, scene, folded = folding
    straight = trajectory(np.tile(model.qpos0, (31, 1)))
    assert obj.collision(scene, straight) == 0.0
    # head: x in [-0.05, 0.05], y in [-0.01, 0.01]; tail: the same x, y in [-0.02, 0]
    exact = 0.1 * 0.01 * 0.02  # overlap: length x width x depth [m^3]
    one_second = obj.collision(scene, trajectory(np.tile(folded, (31, 1))))
    # the time integral of a constant is exact (next test), so the error is the
    # lattice's (body length / 100 = 2.1 mm), which puts 4.8 spacings across the 1 cm
    # overlap: four or five points fall in it, -16% or +5% as the lattice lies, so within
    # 20% (measured -15.3% with each link's lattice centred on its box, +5.8% from its
    # corner; +13% when the sum counted one sample interval too many)
    assert one_second == pytest.approx(exact * 1.0, rel=0.2)


def test_collision_of_a_constant_overlap_is_the_overlap_times_the_duration(folding):
    # The trapezoid rule over the sampled frames' times, the last frame always
    # among them, integrates a constant exactly: V T for any frame count and stride.
    _, scene, folded = folding
    volume = obj.collision(scene, trajectory(np.tile(folded, (2, 1)))) * 30  # V [m^3]: 1/30 s
    assert volume > 0
    for frames, stride in ((31, 2), (32, 2), (32, 3), (5, 1), (5, 8)):
        duration = (frames - 1) / 30  # [s]
        traj = trajectory(np.tile(folded, (frames, 1)))
        assert obj.collision(scene, traj, stride) == pytest.approx(volume * duration, rel=1e-12)
    assert obj.collision(scene, trajectory(folded[None])) == 0.0  # one frame: no time passes


def test_total_weighs_the_terms(eel):
    scene = ag.make_scene(eel, fluid="euler")
    path = np.tile(eel.model.qpos0, (31, 1))
    path[:, 0] += np.linspace(0, 0.2, 31)
    path[:, 1] += np.linspace(0, 0.05, 31)
    energy = np.zeros((31, eel.model.nv))
    energy[:, 3] = np.linspace(0, 2.0, 31)
    traj = trajectory(path, energy)
    value = obj.total(scene, traj, (1, 0), energy_bound=1.0)
    assert value == pytest.approx(-0.2 + 0.2 * 0.05 + 2.0)
    quiet = obj.total(scene, traj, (1, 0), energy_bound=5.0, weights=obj.Weights(deviation=0))
    assert quiet == pytest.approx(-0.2)


def test_direction_must_fit_the_dimension(eel):
    with pytest.raises(ValueError, match="nonzero vector of 2 numbers"):
        obj.distance(eel.model, trajectory(np.zeros((2, 7))), (1, 0, 0))


def test_a_turn_is_rewarded_about_its_axis_and_not_counted_as_deviation(eel):
    path = np.zeros((2, eel.model.nq))
    path[1, 2] = 0.3  # the eel turned 0.3 rad to the left (counter-clockwise)
    left, right = obj.maneuver_goal("turn-left", 2), obj.maneuver_goal("turn-right", 2)
    np.testing.assert_allclose(left[0], [np.sqrt(0.5), np.sqrt(0.5)])  # half way to +y
    traj = trajectory(path)
    assert obj.turning(eel.model, traj, left[1]) == pytest.approx(-0.3)
    assert obj.turning(eel.model, traj, right[1]) == pytest.approx(0.3)
    assert obj.deviation(eel.model, traj, left[0], left[1]) == pytest.approx(0.0)
    assert obj.deviation(eel.model, traj, (1, 0)) == pytest.approx(0.3)  # straight: all of it


def test_a_turn_is_rewarded_up_to_a_quarter_turn_and_no_further(eel):
    """Spinning on the spot earns no more than turning 90 degrees (``TURN``)."""
    path = np.zeros((2, eel.model.nq))
    left = obj.maneuver_goal("turn-left", 2)[1]
    for turned, reward in ((1.0, -1.0), (np.pi / 2, -np.pi / 2), (4.1, -np.pi / 2)):
        path[1, 2] = turned
        assert obj.turning(eel.model, trajectory(path), left) == pytest.approx(reward)
    path[1, 2] = -4.1  # the other way round: no cap on the penalty
    assert obj.turning(eel.model, trajectory(path), left) == pytest.approx(4.1)


def test_a_turn_limit_caps_the_rotation_the_objective_rewards(eel):
    """``total``'s ``turn_limit``: past it more rotation earns nothing, so travel is what a
    search can still buy; below it the reward is the rotation, as with the default cap."""
    scene = ag.make_scene(eel, fluid="euler")
    d, r = obj.maneuver_goal("turn-left", 2)
    path = np.tile(eel.model.qpos0, (2, 1))
    path[1, 2] += 1.0  # a radian to the left, on the spot

    def value(limit):
        return obj.total(scene, trajectory(path), d, 1.0, axis=r, turn_limit=limit)

    assert value(obj.TURN) == pytest.approx(-1.0)  # the default cap is not reached
    assert value(0.25) == pytest.approx(-0.25)
    assert value(2.0) == pytest.approx(-1.0)


def test_pitching_up_turns_the_nose_up_and_only_unwanted_rotation_deviates():
    fish = ag.creatures.get("fish").model
    path = np.tile(fish.qpos0, (2, 1))
    up, roll = 0.2, 0.1
    about_minus_y = np.array([np.cos(up / 2), 0, -np.sin(up / 2), 0])  # nose (+x) towards +z
    roll_q = np.array([np.cos(roll / 2), np.sin(roll / 2), 0, 0])
    path[1, 3:7] = about_minus_y
    nose = obj.rotation_vector(fish, trajectory(path))
    np.testing.assert_allclose(nose, [0, -up, 0], atol=1e-12)
    d, r = obj.maneuver_goal("pitch-up", 3)
    assert obj.turning(fish, trajectory(path), r) == pytest.approx(-up)
    assert obj.turning(fish, trajectory(path), obj.maneuver_goal("pitch-down", 3)[1]) > 0
    path[1, 3:7] = obj.quat_mul(roll_q, about_minus_y)  # pitched up, then rolled a little
    assert obj.deviation(fish, trajectory(path), d, r) == pytest.approx(roll, rel=0.05)
    with pytest.raises(ValueError, match="'pitch-up' is for 3D creatures"):
        obj.maneuver_goal("pitch-up", 2)
    with pytest.raises(ValueError, match="unknown manoeuvre 'loop'; manoeuvres: straight, "):
        obj.maneuver_goal("loop", 3)


def test_with_the_gait_period_the_rotation_is_free_of_the_recoil_within_a_cycle(eel):
    """A heading that turned by 0.1 rad, plus a yaw of +-0.3 rad at the gait frequency that
    grows from rest over the first cycle (a fish's head recoiling every tail beat): the
    last frame sees the yaw at whatever moment of its beat the run ends; the mean over the
    last cycle sees only the turn."""
    time = np.arange(61) / 30  # two cycles of 1 s
    for phase in (0.0, 1.0, 2.0):
        recoil = np.minimum(time, 1.0) * np.sin(2 * np.pi * time + phase)
        yaw = 0.1 * time / 2 + 0.3 * recoil
        path = np.zeros((61, eel.model.nq))
        path[:, 2] = yaw
        planar = trajectory(path)
        assert obj.rotation_vector(eel.model, planar)[2] == pytest.approx(0.1 + 0.3 * np.sin(phase))
        # the mean over the last cycle's 30 frames (1/30 s to 2 s): the turn at their mean time
        turn = 0.1 * time[31:].mean() / 2
        assert obj.rotation_vector(eel.model, planar, period=1.0)[2] == pytest.approx(turn)
        fish = ag.creatures.get("fish").model
        spatial = np.tile(fish.qpos0, (61, 1))
        spatial[:, 3:7] = np.c_[np.cos(yaw / 2), 0 * yaw, 0 * yaw, np.sin(yaw / 2)]  # about z
        turned = obj.rotation_vector(fish, trajectory(spatial), period=1.0)
        np.testing.assert_allclose(turned, [0, 0, turn], atol=0.002)  # a chordal mean
        assert obj.deviation(fish, trajectory(spatial), (1, 0, 0), period=1.0) == pytest.approx(
            np.linalg.norm(turned)
        )


def test_the_rotation_between_two_cycles_is_free_of_the_recoil_in_either(eel):
    """Graded steering's rate under way: a heading turning 0.2 rad a second under a yaw of
    +-0.3 rad at the gait frequency. From the mean over the second of three 1-s cycles to
    the mean over the third, the turn is 0.2 rad (both means lag their cycle's end by the
    same half cycle), whatever the beat's phase; one frame at the start would see the yaw."""
    time = np.arange(91) / 30  # three cycles of 1 s
    fish = ag.creatures.get("fish").model
    for phase in (0.0, 1.0, 2.0):
        yaw = 0.2 * time + 0.3 * np.sin(2 * np.pi * time + phase)
        planar = np.zeros((91, eel.model.nq))
        planar[:, 2] = yaw
        spatial = np.tile(fish.qpos0, (91, 1))
        spatial[:, 3:7] = np.c_[np.cos(yaw / 2), 0 * yaw, 0 * yaw, np.sin(yaw / 2)]  # about z
        second, third = (obj.cycle_frames(trajectory(planar), end, 1.0) for end in (2.0, 3.0))
        np.testing.assert_array_equal(second, np.arange(31, 61))  # each phase of it once
        turn = obj.rotation_between(eel.model, trajectory(planar), second, third)
        np.testing.assert_allclose(turn, [0, 0, 0.2], atol=1e-12)
        turned = obj.rotation_between(fish, trajectory(spatial), second, third)
        np.testing.assert_allclose(turned, [0, 0, 0.2], atol=1e-12)  # the recoils cancel
        from_a_frame = obj.rotation_between(eel.model, trajectory(planar), [60], third)[2]
        assert from_a_frame == pytest.approx(0.2 * time[61:].mean() - yaw[60])  # yaw and all


# --- the efficiency objective ----------------------------------------------------------


def cruising(eel, speed=0.3, power=0.2, seconds=4.0, fps=30.0):
    """The eel's root moving along x at ``speed`` [m/s] while its joints spend ``power`` [W]."""
    frames = int(seconds * fps) + 1
    time = np.arange(frames) / fps
    path = np.zeros((frames, eel.model.nq))
    path[:, 0] = speed * time
    energy = np.zeros((frames, eel.model.nv))
    energy[:, -1] = power * time
    return trajectory(path, energy, fps)


def test_cruise_is_the_speed_and_the_cost_of_transport_over_the_last_cycles(eel):
    traj = cruising(eel, speed=0.3, power=0.2)
    speed, cost = obj.cruise(eel.model, traj, (1, 0), period=1.0, cycles=2)
    assert speed == pytest.approx(0.3)
    assert cost == pytest.approx(0.2 * 2 / (eel.model.mass * 0.3 * 2))  # work / (m d)
    start = cruising(eel, speed=0.3, power=0.2)
    start.qpos[:60, 0] = 0.0  # idle for two seconds, then a jump: outside the window
    assert obj.cruise(eel.model, start, (1, 0), 1.0, 2)[0] == pytest.approx(0.3)
    with pytest.raises(ValueError, match="less than the 5 cycles"):
        obj.cruise(eel.model, traj, (1, 0), period=1.0, cycles=5)


def test_the_efficiency_term_is_the_cost_in_the_references_unit_plus_the_speed_shortfall(eel):
    traj = cruising(eel, speed=0.3, power=0.2)
    _, cost = obj.cruise(eel.model, traj, (1, 0), 1.0)
    fast_enough = obj.efficiency(eel.model, traj, (1, 0), 1.0, min_speed=0.25,
                                 reference_cost=2 * cost)  # fmt: skip
    assert fast_enough == pytest.approx(0.5)  # half the reference's cost, no shortfall
    too_slow = obj.efficiency(eel.model, traj, (1, 0), 1.0, min_speed=0.4, reference_cost=cost)
    assert too_slow == pytest.approx(1 + obj.SPEED_WEIGHT * (1 - 0.3 / 0.4))
    backwards = obj.efficiency(eel.model, cruising(eel, speed=-0.1), (1, 0), 1.0, 0.4, cost)
    assert backwards == pytest.approx(obj.COST_CAP + obj.SPEED_WEIGHT * (1 + 0.1 / 0.4))
