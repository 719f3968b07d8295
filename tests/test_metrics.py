"""Swim metrics on synthetic trajectories whose answers are known, and on a vacuum rollout."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.metrics import (
    UNITS,
    NoSteadyWindow,
    lateral_excursion,
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
    assert set(m) == set(UNITS)


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
    fish = ag.creatures.get("fish")
    with pytest.raises(ValueError, match=r"must be \(21, 10\)"):
        travel_metrics(fish.model, short)
