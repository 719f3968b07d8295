"""Recorded fluid frames: the whole 2D grid, the 3D volume block-averaged to a budget."""

import numpy as np

import aquagait as ag
from aquagait.sim.frames import MAX_CELLS, _blocks, stride


def test_the_stride_keeps_a_3d_frame_within_its_budget():
    assert stride((64, 32, 32)) == 1  # the fish: every cell
    assert stride((96, 64, 48)) == 2  # the frog: 2x2x2 blocks
    for shape in [(64, 32, 32), (96, 64, 48), (200, 100, 100), (129, 65, 17)]:
        s = stride(shape)
        assert np.prod(-(-np.array(shape) // s)) <= MAX_CELLS
        assert s == 1 or np.prod(-(-np.array(shape) // (s - 1))) > MAX_CELLS  # the smallest


def test_block_means_keep_a_linear_field_s_values_at_the_block_centres():
    shape = (6, 4, 5)  # the last axis has a partial block
    centres = np.indices(shape) + 0.5
    field = centres[0] + 2 * centres[1] - centres[2]
    means = _blocks(field, 2)
    assert means.shape == (3, 2, 3)
    block_centres = [np.array([1.0, 3.0, 5.0]), np.array([1.0, 3.0]), np.array([1.0, 3.0, 4.5])]
    expected = (block_centres[0][:, None, None] + 2 * block_centres[1][None, :, None]
                - block_centres[2][None, None, :])  # fmt: skip
    np.testing.assert_allclose(means, expected)


def test_a_3d_swim_records_its_whole_volume_in_half_precision():
    fish = ag.creatures.get("fish")
    scene = ag.make_scene(fish, (32, 20, 24), 0.008, fluid="euler")
    traj = ag.rollout(scene, ag.init_state(scene), fish.policy(), 2 / 30)
    fluid = traj.fluid
    assert fluid.velocity.shape == (3, 3, 32, 20, 24) and fluid.velocity.dtype == np.float16
    assert fluid.solid.shape == (3, 32, 20, 24) and fluid.solid[-1].any()
    assert fluid.origin.shape == (3, 3) and fluid.cell_size == 0.008
    assert np.abs(fluid.velocity[-1].astype(float)).max() > 1e-3  # the water moves
