"""The multi-agent environment: PettingZoo's own API test, a pair of eel2d in line by
default, zero actions swimming the formation exactly, determinism, station keeping's
reward, touching creatures ending the episode."""

import numpy as np
import pytest

pytest.importorskip("pettingzoo")

from pettingzoo.test import parallel_api_test  # noqa: E402

import aquagait as ag  # noqa: E402
from aquagait.control.group import GroupPolicy  # noqa: E402
from aquagait.envs.school import SchoolEnv  # noqa: E402
from aquagait.envs.swim import SwimEnv  # noqa: E402

COARSE = {"cell_size": 0.02, "seconds": 0.4}


@pytest.mark.parametrize("sense_flow", [False, True])
def test_it_passes_pettingzoo_s_parallel_api_test(sense_flow):
    parallel_api_test(SchoolEnv(sense_flow=sense_flow, **COARSE), num_cycles=15)


def test_by_default_it_is_a_pair_of_eels_in_line_keeping_station():
    env = SchoolEnv(**COARSE)
    assert env.possible_agents == ["eel2d-1", "eel2d-2"] and env.task == "station"
    second = env.group.members[1]
    assert second.pose.offset[0] == pytest.approx(-1.5 * 0.5)  # half a body length of water
    names = env.observation_names("eel2d-2")
    assert names[-4:] == ("eel2d-1:position:x", "eel2d-1:position:y", "eel2d-1:heading:cos",
                          "eel2d-1:heading:sin")  # fmt: skip
    observations, _ = env.reset(seed=0)
    ahead = observations["eel2d-2"][-4:]
    np.testing.assert_allclose(ahead, [0.75, 0.0, 1.0, 0.0], atol=1e-12)


def test_zero_actions_swim_the_formation_as_a_group_swim_does():
    env = SchoolEnv(phase=0.25, **COARSE)
    env.reset(seed=0)
    while env.agents:
        env.step({agent: np.zeros(4) for agent in env.agents})
    eel = ag.creatures.get("eel2d")
    gait = eel.spec().unpack(eel.default_gait)
    policy = GroupPolicy(env.group, [eel.servo(gait), eel.servo(gait.lagging(0.25))])
    swim = ag.rollout(env.scene, ag.init_state(env.scene), policy, COARSE["seconds"])
    np.testing.assert_allclose(env.state.qpos, swim.qpos[-1], atol=1e-12)


def test_the_same_seed_and_actions_give_the_same_episode():
    def episode():
        env = SchoolEnv(task="school", **COARSE)
        env.reset(seed=3)
        rewards = []
        while env.agents:
            actions = {a: env.action_space(a).sample() for a in env.agents}
            rewards.append(env.step(actions)[1])
        return env.state.qpos, rewards

    (q1, r1), (q2, r2) = episode(), episode()
    np.testing.assert_array_equal(q1, q2)
    assert r1 == r2
    assert all(len(set(step.values())) == 1 for step in r1)  # the school shares its reward


def test_the_follower_is_paid_for_closing_on_its_station():
    """Station keeping's reward is the rate at which the follower's distance from its place
    in the leader's frame shrinks: summed over an episode from that place, times the
    control step, it is minus the distance at the end."""
    env = SchoolEnv(power_weight=0.0, **COARSE)
    env.reset(seed=0)
    paid = 0.0
    while env.agents:
        paid += env.step({agent: np.zeros(4) for agent in env.agents})[1]["eel2d-2"]
    error = np.linalg.norm(env._relative(env.state.qpos, 0, 1) - env._station[1])
    assert error > 1e-3  # it drifted off its station
    assert paid * env.control_dt == pytest.approx(-error, rel=1e-9)


def test_creatures_that_touch_end_the_episode_for_all():
    env = SchoolEnv(kind="side-by-side", spacing=0.1, fluid="simple", seconds=2.0)
    env.reset(seed=0)
    turn = np.array([1.0, 1.0, 1.0, 1.0])
    done = None
    while env.agents:
        out = env.step({"eel2d-1": turn, "eel2d-2": -turn})
        done = out
    _, _, terminations, truncations, infos = done
    assert all(terminations.values()) and not any(truncations.values())
    assert "eel2d-1 and eel2d-2 touched" in infos["eel2d-1"]["error"]


def test_each_creature_has_its_own_lateral_line_and_a_mirror_pair_feels_the_mirror():
    """Side by side in anti-phase (for eel2d's pure sines, half a cycle's lag is the mirror
    image) on a grid symmetric about the pair's midline, after 10 steps: each sensor on
    eel2d-1's left flank reads what its twin on eel2d-2's right flank reads, the sideways
    flow reversed. Measured: pressure within 0.01 Pa of readings up to 200 Pa, flow within
    1e-5 m/s; what breaks the mirror is the solve's tolerance (tests/sim/test_group.py)."""
    env = SchoolEnv(kind="side-by-side", spacing=0.4, phase=0.5, cell_size=0.02, seconds=0.5,
                    sense_flow=True, sensors=8)  # fmt: skip
    lone = SwimEnv(cell_size=0.02, sense_flow=True, sensors=8)
    for line, member in zip(env.lateral_lines, env.group.members, strict=True):
        placed = line.world(env.scene, env.start.qpos) - np.array(member.pose.offset)
        alone = lone.lateral_line.world(lone.scene, lone.scene.model.qpos0)
        np.testing.assert_allclose(placed, alone, atol=1e-12)  # its own body's sensors
    env.reset(seed=0)
    for _ in range(10):
        observations, *_ = env.step({agent: np.zeros(4) for agent in env.agents})
    names = {name: k for k, name in enumerate(env.observation_names("eel2d-1"))}
    left, right = observations["eel2d-1"], observations["eel2d-2"]
    read = [
        (left[names[f"{kind}:left{s}{axis}"]], sign * right[names[f"{kind}:right{s}{axis}"]])
        for s in range(4)
        for kind, axis, sign in [("pressure", "", 1), ("flow", ":x", 1), ("flow", ":y", -1)]
    ]
    pressure = np.array(read[0::3])
    np.testing.assert_allclose(pressure[:, 0], pressure[:, 1], atol=1e-3 * np.abs(pressure).max())
    np.testing.assert_allclose(*np.array(read[1::3] + read[2::3]).T, atol=1e-4)
    assert np.abs(pressure).max() > 10.0  # the water moves: the mirror is not of nothing
