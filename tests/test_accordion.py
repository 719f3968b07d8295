"""The paper's §7 comparison: the accordion swims in the Euler fluid, hardly in the simple one."""

import numpy as np

import aquagait as ag


def swim(fluid: str, seconds: float = 3.0) -> float:
    accordion = ag.creatures.get("accordion2d")
    scene = ag.make_scene(accordion, fluid=fluid)
    traj = ag.rollout(scene, ag.init_state(scene), accordion.policy(), seconds)
    # mirror-symmetric, so it swims straight; in the Euler fluid its symmetric
    # wake is unstable and round-off grows into a slight turn (measured 4 mm, 0.013 rad)
    assert np.abs(traj.qpos[:, 1]).max() < 0.01 and np.abs(traj.qpos[:, 2]).max() < 0.05
    return traj.qpos[-1, 0] - traj.qpos[0, 0]


def test_accordion_swims_in_the_euler_fluid_and_barely_in_the_simple_one():
    euler, simple = swim("euler"), swim("simple")
    print(f"accordion2d 3 s from rest: Euler {euler:+.4f} m, simple {simple:+.4f} m")
    # measured +0.373 m and +0.037 m (10.0%); in the sixth cycle 0.235 m against 0.024 m
    # (10.3%); the hand-set gait (amplitude 0.7 against the searched 0.86) 8.7% and 9.2%:
    # an order of magnitude, whichever the gait
    assert euler > 1.0 * ag.creatures.get("accordion2d").model.body_length
    assert abs(simple) < euler / 8


def test_one_number_drives_all_ten_joints_in_phase():
    accordion = ag.creatures.get("accordion2d")
    assert accordion.gait.names == ("amplitude",)
    gait = accordion.gait.unpack([0.4])
    np.testing.assert_allclose(np.abs(gait.amplitude), 0.4)
    assert np.all(gait.phase == gait.phase[0])
    # the upper arm alternates its folds; the lower arm mirrors it
    np.testing.assert_array_equal(np.sign(gait.amplitude[:5]), [1, -1, 1, -1, 1])
    np.testing.assert_array_equal(gait.amplitude[5:], -gait.amplitude[:5])
