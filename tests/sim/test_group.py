"""A group of creatures in one fluid: composed as one body, each swimming as it would alone
when far apart, mirror pairs staying mirrored, overlaps refused and touches stopped."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.body.group import GroupError, Pose, compose
from aquagait.control.group import GroupPolicy
from aquagait.sim import EulerFluid
from aquagait.sim.group import CreaturesTouched, group_grid, member_trajectory

H = 0.02
"""A coarse cell for eel2d (a quarter of its default resolution): a 1-s swim in a second."""


@pytest.fixture(scope="module")
def eel():
    return ag.creatures.get("eel2d")


def travel(trajectory):
    """x, y and heading gained by a 2D swimmer over a trajectory."""
    return trajectory.qpos[-1, :3] - trajectory.qpos[0, :3]


def test_the_group_model_is_each_creature_side_by_side(eel):
    fish = ag.creatures.get("fish").model
    group = compose([fish, fish], poses=[Pose(), Pose((0, 0.2, 0), np.pi / 2)])
    model, (a, b) = group.model, group.members
    assert (a.label, b.label) == ("fish-1", "fish-2") and model.source == "fish-1 + fish-2"
    assert (model.nq, model.nv, len(model.links)) == (2 * fish.nq, 2 * fish.nv, 2 * len(fish.links))
    assert model.dof_names[b.dofs][0] == "fish-2/root:x"
    mass = ag.body.Dynamics(model.mj).mass_matrix(model.qpos0)
    np.testing.assert_array_equal(mass[a.dofs, b.dofs], 0.0)  # nothing joins them
    alone = ag.body.Dynamics(fish.mj).mass_matrix(fish.qpos0)
    np.testing.assert_allclose(mass[b.dofs, b.dofs][6:, 6:], alone[6:, 6:], atol=1e-12)
    assert model.bounds[1, 1] > 0.2 - 0.1 * fish.body_length  # the box holds the second fish


def test_creatures_that_cannot_share_a_fluid_are_refused(eel):
    fish = ag.creatures.get("fish").model
    with pytest.raises(GroupError, match="2D and 3D creatures cannot share a fluid"):
        compose([eel.model, fish])
    with pytest.raises(GroupError, match="labels must be unique: 'a' repeated"):
        compose([eel.model, eel.model], labels=["a", "a"])
    with pytest.raises(GroupError, match="eel2d-2 is 2D: its offset's z must be 0"):
        compose([eel.model, eel.model], poses=[Pose(), Pose((0, 1, 1))])
    with pytest.raises(ValueError, match="2 creatures but 1 policies"):
        GroupPolicy(compose([eel.model, eel.model]), [None])


def test_creatures_far_apart_swim_as_each_swims_alone(eel):
    """Two eels 1.6 m (3.2 body lengths) apart, each exactly where the lone eel stands on
    its grid (a whole number of cells off): each gains what the lone eel gains in 1 s.

    What remains is the grid, not the other eel: the group's grid follows the pair's box,
    so it shifts at other steps and its walls stand elsewhere (``aquagait.sim.follow``,
    0.06-0.26 % for one eel), and doubling the distance changes nothing (measured with the
    straight gait of 2026-12-06 at 40, 80 and 160 cells: x within 0.10, 0.03, 0.06 %, y
    within 1.0, 1.3, 1.3 % of the x gained, heading within 0.005, 0.008, 0.008 rad).
    """
    alone = ag.make_scene(eel, (64, 32), H, fluid="euler")
    solo = travel(ag.rollout(alone, ag.init_state(alone), eel.policy(), 1.0))
    group = compose([eel.model, eel.model], poses=[Pose(), Pose((0, 80 * H, 0))])
    scene = ag.make_scene(group, (64, 32 + 80), H, fluid="euler", origin=alone.grid.origin)
    swim = ag.rollout(scene, ag.init_state(scene), GroupPolicy(group, [eel.policy()] * 2), 1.0)
    for member in group.members:
        gained = travel(member_trajectory(swim, member))
        assert abs(gained[0] / solo[0] - 1) < 0.01, member.label
        assert abs(gained[1] - solo[1]) < 0.02 * solo[0] and abs(gained[2] - solo[2]) < 0.02


def test_a_mirror_pair_side_by_side_stays_mirrored(eel):
    """Eels at y = -+0.15 m (0.6 body lengths apart), the second swimming the first's gait
    mirrored, on a grid symmetric about y = 0: their motions stay mirror images. What
    breaks the mirror is the solve's tolerance (the red-black smoother is not its own
    mirror image, ``aquagait.coupling.COUPLED_TOLERANCE``): at 1e-6, measured 5e-8 m and
    1.6e-7 rad over 1 s (at 1e-4: 2.5e-6 m, 5e-6 rad). They do feel each other: each turns
    0.31 rad where a lone eel turns 0.35. (At -+0.1 m the straight gait of 2026-12-06
    turns them into each other within the second.)"""
    gait = eel.spec().unpack(eel.default_gait)
    group = compose([eel.model, eel.model], poses=[Pose((0, -0.15, 0)), Pose((0, 0.15, 0))])
    fluid = EulerFluid(tolerance=1e-6)
    scene = ag.make_scene(group, (64, 48), H, fluid=fluid, origin=(-0.64, -0.48))
    policy = GroupPolicy(group, [eel.servo(gait), eel.servo(gait.mirrored())])
    swim = ag.rollout(scene, ag.init_state(scene), policy, 1.0)
    a, b = (member_trajectory(swim, m).qpos[:, :3] for m in group.members)
    np.testing.assert_allclose(b * [1, -1, -1], a, atol=1e-6)
    assert a[-1, 0] > 0.1  # they swam


def test_creatures_that_overlap_at_the_start_are_refused(eel):
    group = compose([eel.model, eel.model], poses=[Pose(), Pose((0.3, 0.0, 0))])
    with pytest.raises(GroupError, match=r"eel2d-1 and eel2d-2 overlap at their starting poses"
                       r" \(eel2d-\d's surface lies [\d.]+ mm inside eel2d-\d\)"):  # fmt: skip
        ag.make_scene(group, (96, 32), H, fluid="euler", origin=(-0.8, -0.32))


def test_creatures_that_touch_stop_the_swim_saying_which_and_when(eel):
    """Two eels in a vacuum 5 cm apart, the second drifting at 0.5 m/s into the first:
    they meet after 0.1 s, less the depth the check sees (one step's travel at most)."""
    group = compose([eel.model, eel.model], poses=[Pose(), Pose((0, 0.05, 0))])
    scene = ag.make_scene(group)
    qvel = np.zeros(group.model.nv)
    qvel[group.members[1].dofs.start + 1] = -0.5
    gap = 0.05 - 2 * eel.model.bounds[1, 1]  # the eels' widest half-widths face each other
    with pytest.raises(CreaturesTouched, match=r"at t = ([\d.]+) s eel2d-1 and eel2d-2 touched"
                       ) as err:  # fmt: skip
        ag.rollout(scene, ag.init_state(scene, qvel=qvel), None, 1.0, dt=1 / 300)
    when = float(err.value.args[0].split("t = ")[1].split(" s")[0])
    assert gap / 0.5 - 1e-9 <= when <= gap / 0.5 + 2 / 300


def test_in_a_vacuum_each_creature_keeps_its_own_momentum(eel):
    """Nothing passes between creatures in a vacuum: each one's internal torques keep its own
    centre of mass still, as alone (``tests/test_sim.py``), and its motion is its lone one."""
    group = compose([eel.model, eel.model], poses=[Pose(), Pose((0, 0.3, 0), 0.5)])
    scene = ag.make_scene(group)
    policy = GroupPolicy(group, [eel.policy(), eel.policy()])
    swim = ag.rollout(scene, ag.init_state(scene), policy, 1.0)
    alone = ag.make_scene(eel.model)
    solo = ag.rollout(alone, ag.init_state(alone), eel.policy(), 1.0)
    first = member_trajectory(swim, group.members[0])
    np.testing.assert_allclose(first.qpos, solo.qpos, atol=1e-12)
    np.testing.assert_allclose(first.energy, solo.energy, rtol=1e-12, atol=1e-15)


def test_the_group_grid_holds_each_creature_s_own_grid(eel):
    group = compose([eel.model, eel.model], poses=[Pose(), Pose((-0.75, 0.0, 0))])
    shape, h, origin = group_grid(group, [eel.resolution] * 2, [eel.cell_size] * 2)
    assert h == eel.cell_size and all(n % 8 == 0 for n in shape)
    width = eel.resolution[0] * h + 0.75
    assert width <= shape[0] * h < width + 8 * h and shape[1] == eel.resolution[1]
