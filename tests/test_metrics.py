"""Swim metrics on synthetic trajectories whose answers are known, and on a vacuum rollout."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import aquagait as ag
from aquagait.metrics import (
    UNITS,
    NoSteadyWindow,
    attitude_metrics,
    course,
    cruise_metrics,
    lateral_excursion,
    settled_cycle,
    steady_metrics,
    swim_metrics,
    travel_metrics,
)
from aquagait.sim import Trajectory

FPS = 40  # samples t = 0.25 and 0.75 s exactly: the peaks of a 1 s sine


def synthetic(model, qpos_of_t, seconds=2.0, fps=FPS, power=0.5):
    """A trajectory with positions from ``qpos_of_t`` and energy spent at ``power`` [W]."""
    time = np.arange(round(seconds * fps) + 1) / fps
    qpos = np.stack([qpos_of_t(t) for t in time])
    energy = np.zeros((time.size, model.nv))
    energy[:, -1] = power * time
    zeros = np.zeros((time.size, model.nv))
    return Trajectory(time, qpos, zeros, zeros, energy, dt=1 / fps, fps=fps)


def eel_pose(eel, heading=0.0, speed=0.0, tail=0.0, travelled=None):
    """eel2d qpos(t): gliding along ``heading``, the tail swinging ``tail`` rad at 1 Hz.

    The eel covers ``travelled(t)`` metres, by default ``speed * t``; ``tail``
    may be a function of time too.
    """

    def qpos(t):
        q = eel.model.qpos0.copy()
        along = speed * t if travelled is None else travelled(t)
        q[:2] = along * np.array([np.cos(heading), np.sin(heading)])
        q[2] = heading
        swing = tail(t) if callable(tail) else tail
        q[eel.model.joint("j4").qpos] = swing * np.sin(2 * np.pi * t)
        return q

    return qpos


def starting(speed, period=1.0):
    """travelled(t) [m] of a swimmer that speeds up evenly from rest to ``speed`` in one cycle."""

    def travelled(t):
        if t < period:
            return speed * t**2 / (2 * period)
        return speed * (t - period / 2)

    return travelled


def test_a_body_translated_at_constant_speed(eel):
    traj = synthetic(eel.model, eel_pose(eel, heading=0.3, speed=0.2), seconds=2.0, power=0.5)
    m = travel_metrics(eel.model, traj, period=1.0)
    assert m["distance"] == pytest.approx(0.4, rel=1e-12)
    assert m["speed_from_rest"] == pytest.approx(0.2, rel=1e-12)
    per_cycle = 0.2 / eel.model.body_length
    assert m["body_lengths_per_cycle_from_rest"] == pytest.approx(per_cycle, rel=1e-12)
    assert m["energy"] == pytest.approx(1.0, rel=1e-12)
    assert m["cost_of_transport"] == pytest.approx(1.0 / (eel.model.mass * 0.4), rel=1e-12)
    assert set(m) <= set(UNITS)
    steady = steady_metrics(eel.model, traj, period=1.0)  # no start-up: the same speed
    assert steady["steady_speed"] == pytest.approx(0.2, rel=1e-12)
    assert steady["steady_body_lengths_per_cycle"] == pytest.approx(per_cycle, rel=1e-12)


def test_steady_speed_leaves_out_the_acceleration_from_rest(eel):
    # Even acceleration to 0.3 m/s over the first cycle, then 0.3 m/s, the tail
    # beating throughout (the centre of mass sways with the same 1 s period, so
    # its displacement over whole cycles is the root's).
    speed = 0.3
    pose = eel_pose(eel, heading=0.5, tail=0.3, travelled=starting(speed))
    traj = synthetic(eel.model, pose, seconds=3.0)
    m = swim_metrics(eel.model, traj, period=1.0)
    assert (m["steady_start"], m["steady_end"], m["steady_cycles"]) == (1.0, 3.0, 2.0)
    assert m["steady_speed"] == pytest.approx(speed, rel=1e-9)
    per_cycle = speed / eel.model.body_length
    assert m["steady_body_lengths_per_cycle"] == pytest.approx(per_cycle, rel=1e-9)
    # from rest: 0.15 m over the first second, 0.6 m over the next two
    assert m["speed_from_rest"] == pytest.approx(0.75 / 3.0, rel=1e-9)
    assert m["body_lengths_per_cycle_from_rest"] == pytest.approx(0.25 / eel.model.body_length)
    # a swim of 2.5 cycles: two whole ones, the steady window is the last second
    m = steady_metrics(eel.model, synthetic(eel.model, pose, seconds=2.5), period=1.0)
    assert (m["steady_start"], m["steady_end"], m["steady_cycles"]) == (1.5, 2.5, 1.0)
    assert m["steady_speed"] == pytest.approx(speed, rel=1e-9)


def test_a_tail_swinging_with_known_amplitude_gives_its_strouhal_number(eel):
    # The tail link's tip is 0.1 m behind its joint: it swings +-0.1 sin(0.4) across the heading
    # in steady swimming, twice as far while the eel gets going (left out: the first cycle).
    speed, swing, heading = 0.25, 0.4, np.deg2rad(30)

    def tail(t):
        return 2 * swing if t < 1 else swing  # the angle is 0 at t = 1 either way

    pose = eel_pose(eel, heading=heading, tail=tail, travelled=starting(speed))
    traj = synthetic(eel.model, pose, seconds=3.0)
    m = swim_metrics(eel.model, traj, period=1.0)
    amplitude = 2 * 0.1 * np.sin(swing)
    assert m["tail_amplitude"] == pytest.approx(amplitude, rel=1e-6)  # float32 mesh vertices
    assert m["steady_speed"] == pytest.approx(speed, rel=1e-9)
    assert m["strouhal"] == pytest.approx(1.0 * amplitude / speed, rel=1e-6)  # f A / U, f = 1 Hz
    assert set(m) == set(UNITS) - {"pitch", "roll", "max_pitch", "max_roll"}  # 3D only


def test_strouhal_scales_with_frequency(eel):
    # The same stroke at twice the frequency: half the period, twice St.
    slow = synthetic(eel.model, eel_pose(eel, speed=0.25, tail=0.4))
    fast_pose = eel_pose(eel, speed=0.25, tail=0.4)
    fast = synthetic(eel.model, lambda t: fast_pose(2 * t) * 1.0)
    fast.qpos[:, 0] = 0.25 * fast.time  # keep the speed, double the stroke rate
    st_slow = steady_metrics(eel.model, slow, period=1.0)["strouhal"]
    st_fast = steady_metrics(eel.model, fast, period=0.5)["strouhal"]
    assert st_fast == pytest.approx(2 * st_slow, rel=1e-9)


def test_a_body_at_rest_has_undefined_ratios(eel):
    traj = synthetic(eel.model, eel_pose(eel, tail=0.2), power=0.0)
    m = swim_metrics(eel.model, traj)
    assert m["distance"] == 0 and m["speed_from_rest"] == 0 and m["steady_speed"] == 0
    assert np.isnan(m["cost_of_transport"])  # no energy over no distance
    assert m["strouhal"] == np.inf  # a beating tail that goes nowhere


def test_a_swim_settles_when_its_distance_per_cycle_stops_changing(eel):
    """Speed rising as U (1 - exp(-t / 2 s)): cycle k covers U (1 - 0.787 e^{-(k-1)/2}) of
    U T, so 0.961, 0.976, 0.986 and 0.991 U T in cycles 7-10: cycle 7 and 9 differ by 2.5 %,
    8 and 10 by 1.6 %, the first pair within 2 %. Over cycles 8-14 the mean speed is within
    1.5 % of U; the steady window (cycles 2-14) is 8 % slow."""
    speed, tau = 0.3, 2.0

    def travelled(t):
        return speed * (t - tau * (1 - np.exp(-t / tau)))

    traj = synthetic(eel.model, eel_pose(eel, tail=0.4, travelled=travelled), seconds=14.0)
    m = swim_metrics(eel.model, traj, period=1.0)
    assert m["settled"] and m["settled_cycle"] == 8
    assert (m["cruise_start"], m["cruise_end"], m["cruise_cycles"]) == (7.0, 14.0, 7.0)
    assert m["cruise_speed"] == pytest.approx(speed, rel=0.015)
    assert m["steady_speed"] < 0.93 * speed
    assert m["cycle_distances"][0] == pytest.approx(travelled(1.0), rel=1e-9)
    assert m["cruise_tail_amplitude"] == pytest.approx(2 * 0.1 * np.sin(0.4), rel=1e-6)
    energy = 0.5 * 7.0  # 0.5 W over the window
    assert m["cruise_cost_of_transport"] == pytest.approx(
        energy / (eel.model.mass * (travelled(14.0) - travelled(7.0))), rel=1e-9
    )


def test_a_swim_still_speeding_up_has_not_settled_and_no_cruise_figures(eel):
    traj = synthetic(eel.model, eel_pose(eel, tail=0.4, travelled=lambda t: 0.05 * t**2), 6.0)
    m = cruise_metrics(eel.model, traj, period=1.0)
    assert not m["settled"] and np.isnan(m["settled_cycle"])
    assert np.isnan(m["cruise_speed"]) and np.isnan(m["cruise_strouhal"])
    assert m["cycles"] == 6 and len(m["cycle_distances"]) == 6
    assert settled_cycle([0.1, 0.2]) is None  # too few cycles to tell
    assert settled_cycle([0.1, 0.2, 0.3, 0.3, 0.3]) == 3


def test_the_tail_amplitude_is_taken_per_cycle_so_a_slow_turn_is_not_beat(eel):
    """The eel swims a circle of 2 m radius at 0.25 m/s, its tail beating +-0.4 rad: over
    10 cycles its path bends 72 degrees, so the tip's excursion across the window's chord
    is more than a metre, while each cycle's, across that cycle's own chord, is the beat
    (the path's sagitta over a cycle, 4 mm, comes on top)."""
    radius, speed, swing = 2.0, 0.25, 0.4
    base = eel_pose(eel, tail=swing)

    def pose(t):
        q = base(t)
        angle = speed * t / radius
        q[:3] = radius * np.sin(angle), radius * (1 - np.cos(angle)), angle
        return q

    m = swim_metrics(eel.model, synthetic(eel.model, pose, seconds=10.0), period=1.0)
    beat = 2 * 0.1 * np.sin(swing)
    assert m["tail_amplitude"] == pytest.approx(beat, abs=0.006)
    assert m["cruise_tail_amplitude"] == pytest.approx(beat, abs=0.006)
    assert m["settled_cycle"] == 1
    # measured along the path, cycle by cycle (each chord 0.06% short of its arc, on a
    # circle a little wider than the root's: the centre of mass trails it; measured +0.24%);
    # the steady speed, from where the eel ended up 9 cycles later, is 5% short
    assert m["cruise_speed"] == pytest.approx(speed, rel=0.005)
    assert m["steady_speed"] < 0.96 * speed
    assert m["heading"] == pytest.approx(np.degrees(speed * 9.5 / radius), abs=0.5)
    # the course over the last two cycles: the chord of the arc from 8 to 10 s, its direction
    # the arc's middle (9 s), a cycle's turn short of where it faces at the end
    traj = synthetic(eel.model, pose, seconds=10.0)
    assert course(traj, 2, seconds=2.0) == pytest.approx(np.degrees(speed * 9 / radius), abs=1e-9)


def test_the_attitude_is_the_root_s_mean_turn_from_rest_over_a_cycle():
    """The fish turned by heading 5, nose up 10 and roll 20 degrees (z-y-x) for its last
    cycle, its root rocking +-8 degrees of yaw within the stroke; upright before."""
    fish = ag.creatures.get("fish")
    rest = fish.model.qpos0.copy()
    turn = Rotation.from_euler("ZYX", [5.0, -10.0, 20.0], degrees=True)

    def pose(t):
        q = rest.copy()
        rock = Rotation.from_euler("z", 8 * np.sin(2 * np.pi * t), degrees=True)
        root = (turn if t >= 2 else Rotation.identity()) * rock
        q[3:7] = np.roll(root.as_quat(), 1)  # MuJoCo's w, x, y, z
        q[0] = 0.05 * t
        return q

    m = attitude_metrics(fish.model, synthetic(fish.model, pose, seconds=3.0), period=1.0)
    assert m["heading"] == pytest.approx(5.0, abs=0.1)
    assert m["pitch"] == pytest.approx(10.0, abs=0.1)
    assert m["roll"] == pytest.approx(20.0, abs=0.1)
    assert m["max_roll"] == pytest.approx(20.0, abs=0.1)


def test_lateral_excursion_ignores_motion_along_the_direction():
    t = np.linspace(0, 1, 41)
    points = np.stack([3 * t, 0.05 * np.sin(2 * np.pi * t), 0.0 * t], axis=1)
    assert lateral_excursion(points, [1, 0, 0]) == pytest.approx(0.1)
    assert lateral_excursion(points[:, :2], [0, 0]) == pytest.approx(3.0, rel=1e-3)
    assert lateral_excursion(np.zeros((5, 2)), [1, 0]) == 0.0


def test_in_vacuum_the_centre_of_mass_stays_put(eel):
    scene = ag.make_scene(eel, fluid="none")
    traj = ag.rollout(scene, ag.init_state(scene), eel.policy(), seconds=2.0)
    m = swim_metrics(eel.model, traj)
    assert m["distance"] < 0.01 * eel.model.body_length
    assert m["steady_speed"] * m["period"] < 0.01 * eel.model.body_length
    assert m["energy"] > 0 and m["tail_amplitude"] > 0.02


def test_errors_say_what_is_wrong(eel):
    short = synthetic(eel.model, eel_pose(eel), seconds=0.5)
    with pytest.raises(NoSteadyWindow, match="less than two gait cycles of 1 s"):
        swim_metrics(eel.model, short)
    almost = synthetic(eel.model, eel_pose(eel), seconds=1.9)
    with pytest.raises(NoSteadyWindow, match="simulate at least 2 s"):
        steady_metrics(eel.model, almost)
    sparse = synthetic(eel.model, eel_pose(eel), seconds=2.0, fps=0.5)
    with pytest.raises(NoSteadyWindow, match="holds one frame"):
        steady_metrics(eel.model, sparse)
    assert travel_metrics(eel.model, short)["duration"] == pytest.approx(0.5)
    one = synthetic(eel.model, eel_pose(eel), seconds=0.0)
    with pytest.raises(ValueError, match="two frames or more"):
        travel_metrics(eel.model, one)
    with pytest.raises(ValueError, match="period must be a positive"):
        travel_metrics(eel.model, short, period=0)
    with pytest.raises(ValueError, match="needs a swim longer than that"):
        course(short, 2, seconds=1.0)
    fish = ag.creatures.get("fish")
    with pytest.raises(ValueError, match=r"must be \(21, 10\)"):
        travel_metrics(fish.model, short)
