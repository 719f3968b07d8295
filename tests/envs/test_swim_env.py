"""The Gymnasium environment: Gymnasium's own checks, the shipped gait through it, determinism,
every task to its time limit, the lateral line, processes, and clear errors."""

import warnings

import numpy as np
import pytest

gym = pytest.importorskip("gymnasium")

import aquagait as ag  # noqa: E402
from aquagait.body.surface import PATCHES_PER_LENGTH  # noqa: E402
from aquagait.envs import ENV_ID, SwimEnv  # noqa: E402
from aquagait.path import shape  # noqa: E402
from aquagait.sim.frames import fluid_frame, fluid_frames  # noqa: E402
from aquagait.sim.particles import inside  # noqa: E402


def _check(env):
    from gymnasium.utils.env_checker import check_env

    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*infinity.*")  # unbounded by design
        warnings.filterwarnings("ignore", message=".*render modes.*")
        check_env(env, skip_render_check=True)


@pytest.mark.parametrize("creature", ["eel2d", "fish"])
def test_gymnasium_check_env_passes(creature):
    _check(SwimEnv(creature, seconds=0.2, sense_flow=True, task="target"))


def test_registered_and_made_by_id():
    env = gym.make(ENV_ID, creature="eel2d", seconds=0.1)
    obs, _ = env.reset(seed=0)
    assert obs.shape == env.observation_space.shape
    assert len(env.unwrapped.observation_names) == obs.size
    env.close()


def test_zero_residual_swims_the_shipped_gait_bit_for_bit():
    """The environment steps the same simulation as ``aquagait swim``: a residual of zero
    is the creature's straight gait, frame by frame, exactly."""
    env = SwimEnv("eel2d", seconds=0.5, action="residual")
    env.reset(seed=0)
    positions = [env.state.qpos]
    for _ in range(15):
        env.step(np.zeros(env.action_space.shape))
        positions.append(env.state.qpos)
    creature = ag.creatures.get("eel2d")
    scene = ag.make_scene(creature, fluid="euler")
    swim = ag.rollout(scene, ag.init_state(scene), creature.policy(), 0.5, record_fluid=False)
    assert np.array_equal(np.stack(positions), swim.qpos)


def test_forward_reward_is_speed_less_the_power_term():
    """The rewards add up to the distance swum along the heading less the weighted work
    over m g: sum(power dt) is the actuators' work, as the energy counts it."""
    env = SwimEnv("eel2d", seconds=1.0, action="residual", power_weight=2.0)
    env.reset(seed=0)
    dt, rewards, progress, work, start = env.control_dt, [], [], 0.0, env.pose.position
    while True:
        _, reward, terminated, truncated, info = env.step(np.zeros(4))
        rewards.append(reward)
        progress.append(info["progress"])
        work += info["power"] * dt
        if terminated or truncated:
            break
    mg = env.creature.model.mass * 9.81
    assert np.sum(rewards) * dt == pytest.approx(np.sum(progress) * dt - 2.0 * work / mg)
    assert work == pytest.approx(info["energy"], rel=1e-9)
    assert np.linalg.norm(env.pose.position - start) > 0.2  # about 0.26 m in its first second


def test_same_seed_and_actions_give_the_same_episode():
    def episode(seed):
        env = SwimEnv("eel2d", seconds=0.3, task="target")
        obs, _ = env.reset(seed=seed)
        rng = np.random.default_rng(1)
        record = [obs]
        for _ in range(9):
            obs, reward, *_ = env.step(rng.uniform(-1, 1, env.action_space.shape))
            record += [obs, [reward]]
        return np.concatenate(record)

    assert np.array_equal(episode(7), episode(7))
    assert not np.array_equal(episode(7), episode(8))  # the target is drawn from the seed


@pytest.mark.parametrize(
    "task,options",
    [("forward", {}), ("target", {}), ("follow", {"path": "circle:radius=0.6"})],
)
def test_random_actions_run_each_task_to_its_time_limit(task, options):
    env = SwimEnv("eel2d", seconds=0.3, task=task, **options)
    env.reset(seed=0)
    env.action_space.seed(0)
    steps = 0
    while True:
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        steps += 1
        assert np.isfinite(obs).all() and np.isfinite(reward)
        if terminated or truncated:
            break
    assert truncated and not terminated and "error" not in info
    assert steps == 9 and info["time"] == pytest.approx(0.3)
    with pytest.raises(RuntimeError, match="reset"):
        env.step(env.action_space.sample())


def test_target_task_observes_the_target_in_the_creatures_frame():
    """A point straight ahead reads as +x; one to the left as +y."""
    env = SwimEnv("eel2d", seconds=0.1, task="target", target=[0.0, 0.0])
    names = env.unwrapped.observation_names
    start = env.pose if env.pose is not None else None
    assert start is None
    env.reset(seed=0)
    at = env.pose.position
    for offset, expected in (([1.0, 0.0], [1.0, 0.0]), ([0.0, 0.5], [0.0, 0.5])):
        env.task.point = at + np.array(offset)
        obs = env._observe()
        got = [obs[names.index("target:x")], obs[names.index("target:y")]]
        assert np.allclose(got, expected, atol=1e-9)


def test_follow_task_knows_a_closed_path_has_just_begun():
    """A circle ends where it starts: the creature at the start has all of it ahead."""
    env = SwimEnv("eel2d", seconds=0.2, task="follow", path="circle:radius=0.6")
    env.reset(seed=0)
    assert env.task.arc == pytest.approx(0.0, abs=1e-9)
    _, reward, terminated, *_ = env.step(np.zeros(4))
    assert not terminated and abs(reward) < 1.0  # no jump of a whole lap


def test_lateral_line_sits_in_the_water_on_both_flanks():
    """The fish is mirror-symmetric: its sensors pair up across its plane of symmetry (to
    within a surface patch: a mesh's triangles are not split symmetrically), lie outside
    the body, and read nothing in still water at rest; swimming, the flanks feel
    pressures of opposite sign as the body bends one way."""
    env = SwimEnv("fish", seconds=0.5, sense_flow=True, sensors=8, action="residual")
    env.reset(seed=0)
    line = env.lateral_line
    points = line.world(env.scene, env.state.qpos)
    left, right = points[:4], points[4:]
    patch = env.creature.model.body_length / PATCHES_PER_LENGTH
    assert np.abs(left - right * [1, -1, 1]).max() < patch
    assert np.all(left[:, 1] > 0)
    record = fluid_frame(env.scene, env.state, 1)
    assert inside(fluid_frames(env.scene.grid.cell_size, [record]), 0, points).all()
    names = env.observation_names
    first = names.index("pressure:left0")
    obs = env._observe()
    assert np.all(obs[first:] == 0)
    for _ in range(8):
        obs, *_ = env.step(np.zeros(3))
    pressure = obs[first : first + 8]
    assert np.abs(pressure).max() > 0.1  # Pa: the beating tail pushes the water
    assert np.sign(pressure[3]) == -np.sign(pressure[7])  # mid-body: one flank pushed


def test_position_actions_span_the_joint_limits():
    env = SwimEnv("eel2d", seconds=0.1)
    env.reset(seed=0)
    env.step(np.ones(4))
    assert np.allclose(env.targets.angles(0.0), env.creature.model.upper)
    env.reset(seed=0)
    env.step(-np.ones(4))
    assert np.allclose(env.targets.angles(0.0), env.creature.model.lower)


@pytest.mark.parametrize(
    "options,message",
    [
        ({"task": "race"}, "tasks: forward, target, follow"),
        ({"task": "follow"}, "needs a path"),
        ({"task": "target", "target": [1.0, 2.0, 3.0]}, "2 numbers"),
        ({"fluid": "simple", "sense_flow": True}, "fluid='euler'"),
        ({"gait": "optimized"}, "action='residual'"),
        ({"action": "torque"}, "actions: position, residual"),
        ({"creature": "narwhal"}, "narwhal"),
        ({"seconds": 0}, "seconds"),
    ],
)
def test_bad_settings_say_what_would_be_right(options, message):
    with pytest.raises(ValueError, match=message):
        SwimEnv(**{"creature": "eel2d", **options})


def test_a_bad_action_or_a_step_before_reset_is_refused():
    env = SwimEnv("eel2d", seconds=0.1)
    with pytest.raises(RuntimeError, match="reset"):
        env.step(np.zeros(4))
    env.reset(seed=0)
    with pytest.raises(ValueError, match="4 finite numbers"):
        env.step(np.zeros(3))


def test_render_draws_the_swim_with_the_path():
    pytest.importorskip("matplotlib")
    env = SwimEnv("eel2d", seconds=0.2, task="follow", path=shape("line", length=1.0),
                  render_mode="rgb_array")  # fmt: skip
    env.reset(seed=0)
    for _ in range(3):
        env.step(np.zeros(4))
    picture = env.render()
    assert picture.dtype == np.uint8 and picture.ndim == 3 and picture.shape[2] == 3
    red = (picture[..., 0] > 200) & (picture[..., 1] < 80) & (picture[..., 2] < 80)
    assert red.sum() > 100  # the path, a red line across the picture
    assert SwimEnv("eel2d", seconds=0.1).render() is None


def test_render_in_3d():
    pytest.importorskip("moderngl")
    from aquagait.viz.gl import RenderUnavailable

    env = SwimEnv("fish", seconds=0.2, render_mode="rgb_array")
    env.reset(seed=0)
    env.step(np.zeros(3))
    try:
        picture = env.render()
    except RenderUnavailable as err:
        pytest.skip(f"no headless OpenGL here: {err}")
    assert picture.shape[2] == 3 and (picture < 250).any()


def test_vector_environment_on_processes():
    envs = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="async", creature="eel2d",
                        seconds=0.1, task="target")  # fmt: skip
    try:
        obs, _ = envs.reset(seed=[1, 2])
        assert obs.shape == (2, envs.single_observation_space.shape[0])
        assert not np.array_equal(obs[0], obs[1])  # two seeds, two targets
        obs, reward, terminated, truncated, _ = envs.step(np.zeros((2, 4)))
        assert np.isfinite(reward).all()
    finally:
        envs.close(terminate=True)


def test_made_by_module_prefix_in_a_fresh_interpreter():
    """Gymnasium imports the module named before the colon, which registers the id."""
    import subprocess
    import sys

    code = (
        "import gymnasium as gym; "
        "env = gym.make('aquagait.envs:aquagait/Swim-v0', creature='eel2d', seconds=0.1); "
        "print(env.reset(seed=0)[0].shape)"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            timeout=120)  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "(15,)"
