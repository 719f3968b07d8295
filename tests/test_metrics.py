"""Swim metrics on synthetic trajectories whose answers are known, and on a vacuum rollout."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.metrics import (
    UNITS,
    lateral_excursion,
    stroke_metrics,
    swim_metrics,
    travel_metrics,
)
from aquagait.sim import Trajectory

FPS = 40  # samples t = 0.25 and 0.75 s exactly: the peaks of a 1 s sine


@pytest.fixture(scope="module")
def eel():
    return ag.creatures.get("eel2d")


def synthetic(model, qpos_of_t, seconds=2.0, fps=FPS, power=0.5):
    """A trajectory with positions from ``qpos_of_t`` and energy spent at ``power`` [W]."""
    time = np.arange(round(seconds * fps) + 1) / fps
    qpos = np.stack([qpos_of_t(t) for t in time])
    energy = np.zeros((time.size, model.nv))
    energy[:, -1] = power * time
    zeros = np.zeros((time.size, model.nv))
    return Trajectory(time, qpos, zeros, zeros, energy, dt=1 / fps, fps=fps)


def eel_pose(eel, heading=0.0, speed=0.0, tail=0.0):
    """eel2d qpos(t): gliding at ``speed`` along ``heading``, the tail swinging ``tail`` rad."""

    def qpos(t):
        q = eel.model.qpos0.copy()
        q[:2] = speed * t * np.array([np.cos(heading), np.sin(heading)])
        q[2] = heading
        q[eel.model.joint("j4").qpos] = tail * np.sin(2 * np.pi * t)
        return q

    return qpos


def test_a_body_translated_at_constant_speed(eel):
    traj = synthetic(eel.model, eel_pose(eel, heading=0.3, speed=0.2), seconds=2.0, power=0.5)
    m = travel_metrics(eel.model, traj, period=1.0)
    assert m["distance"] == pytest.approx(0.4, rel=1e-12)
    assert m["speed"] == pytest.approx(0.2, rel=1e-12)
    assert m["body_lengths_per_cycle"] == pytest.approx(0.2 / eel.model.body_length, rel=1e-12)
    assert m["energy"] == pytest.approx(1.0, rel=1e-12)
    assert m["cost_of_transport"] == pytest.approx(1.0 / (eel.model.mass * 0.4), rel=1e-12)
    assert set(m) <= set(UNITS)


def test_a_tail_swinging_with_known_amplitude_gives_its_strouhal_number(eel):
    # The tail link's tip is 0.1 m behind its joint: it swings +-0.1 sin(0.4) across the heading.
    speed, swing, heading = 0.25, 0.4, np.deg2rad(30)
    traj = synthetic(eel.model, eel_pose(eel, heading=heading, speed=speed, tail=swing))
    m = swim_metrics(eel.model, traj, period=1.0)
    amplitude = 2 * 0.1 * np.sin(swing)
    assert m["tail_amplitude"] == pytest.approx(amplitude, rel=1e-6)  # float32 mesh vertices
    assert m["cycle_speed"] == pytest.approx(speed, rel=1e-9)
    assert m["strouhal"] == pytest.approx(amplitude / speed, rel=1e-6)
    assert set(m) == set(UNITS)


def test_strouhal_scales_with_frequency(eel):
    # The same stroke at twice the frequency: half the period, twice St.
    slow = synthetic(eel.model, eel_pose(eel, speed=0.25, tail=0.4))
    fast_pose = eel_pose(eel, speed=0.25, tail=0.4)
    fast = synthetic(eel.model, lambda t: fast_pose(2 * t) * 1.0)
    fast.qpos[:, 0] = 0.25 * fast.time  # keep the speed, double the stroke rate
    st_slow = stroke_metrics(eel.model, slow, period=1.0)["strouhal"]
    st_fast = stroke_metrics(eel.model, fast, period=0.5)["strouhal"]
    assert st_fast == pytest.approx(2 * st_slow, rel=1e-9)


def test_a_body_at_rest_has_undefined_ratios(eel):
    traj = synthetic(eel.model, eel_pose(eel, tail=0.2), power=0.0)
    m = swim_metrics(eel.model, traj)
    assert m["distance"] == 0 and m["speed"] == 0
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
    traj = ag.rollout(scene, ag.init_state(scene), eel.policy(), seconds=1.0)
    m = swim_metrics(eel.model, traj)
    assert m["distance"] < 0.01 * eel.model.body_length
    assert m["energy"] > 0 and m["tail_amplitude"] > 0.02


def test_errors_say_what_is_wrong(eel):
    short = synthetic(eel.model, eel_pose(eel), seconds=0.5)
    with pytest.raises(ValueError, match="less than one gait cycle of 1 s"):
        swim_metrics(eel.model, short)
    assert travel_metrics(eel.model, short)["duration"] == pytest.approx(0.5)
    one = synthetic(eel.model, eel_pose(eel), seconds=0.0)
    with pytest.raises(ValueError, match="two frames or more"):
        travel_metrics(eel.model, one)
    with pytest.raises(ValueError, match="period must be a positive"):
        travel_metrics(eel.model, short, period=0)
    fish = ag.creatures.get("fish")
    with pytest.raises(ValueError, match=r"must be \(21, 10\)"):
        travel_metrics(fish.model, short)
