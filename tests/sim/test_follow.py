"""The grid that follows the swimmer: same swim as a fixed grid, clearance kept, clear refusals."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.body.voxelize import voxelize
from aquagait.sim import CLEARANCE, BodyOutsideGrid, EulerFluid, advance
from aquagait.sim.follow import GridGrew, _best_rotation, _weighted_points, body_bounds, widest_box


def swim(eel, scene, seconds):
    traj = ag.rollout(scene, ag.init_state(scene), eel.policy(), seconds, record_fluid=False)
    return traj.qpos[-1, 0] - traj.qpos[0, 0], traj.qpos[-1, 2] - traj.qpos[0, 2]


def test_a_following_grid_swims_like_a_fixed_grid_that_never_shifts(hand_set_eel):
    """The hand-set gait for 4 s on the default 128x64 grid (it shifts once, by about 30
    cells, when the snout comes within the clearance of the front wall) against a
    grid 2.8 m long placed so that the eel never nears a wall. With the clearance of
    8 cells the two agree to 0.2% in distance and 0.005 rad in heading with sub-cell
    boundaries (0.06% and 0.005 rad on the staircase; the COM-based rule they replace:
    1.6% and 0.016 rad); the issue's bound is 1% and 0.01 rad. The optimized shipped
    gait swims 1.64 m in the 4 s, so the grid shifts several times: 0.03% in distance
    and 0.012 rad in a heading that drifts 0.15 rad."""
    eel = hand_set_eel
    following = ag.make_scene(eel, fluid="euler")
    grid = following.grid
    fixed = ag.make_scene(eel, (280, grid.shape[1]), grid.cell_size, "euler", grid.origin)
    distance, heading = swim(eel, following, 4.0)
    distance_fixed, heading_fixed = swim(eel, fixed, 4.0)
    print(f"following {distance:.4f} m {heading:.4f} rad, fixed {distance_fixed:.4f} m "
          f"{heading_fixed:.4f} rad")  # fmt: skip
    assert distance > 0.3  # it swam several tens of cells: the grid must have shifted
    assert distance == pytest.approx(distance_fixed, rel=0.01)
    assert heading == pytest.approx(heading_fixed, abs=0.01)


def test_the_body_never_comes_nearer_a_wall_than_the_clearance(eel):
    """Every frame of a 4-s swim on a coarse grid that must shift several times: the
    solid cell nearest a wall has at least CLEARANCE fluid cells between it and the wall.
    (28 cells across: the shipped gait's body sweeps 0.18 m, 9 cells, plus 2 x 8 of water.)"""
    scene = ag.make_scene(eel, (48, 28), 0.02, fluid="euler")
    state, policy = ag.init_state(scene), eel.policy()
    origins = {scene.grid.origin}
    for k in range(1, 121):
        state = advance(scene, state, policy, k / 30)
        grid = state.grid
        solid = voxelize(scene.shape, grid, *scene.dynamics.link_poses(state.qpos)).solid
        cells = np.argwhere(solid)
        to_wall = np.minimum(cells, np.asarray(grid.shape) - 1 - cells).min()
        assert to_wall >= CLEARANCE, (
            f"at t = {state.time:.3f} s a solid cell is {to_wall} from a wall"
        )
        origins.add(grid.origin)
    assert len(origins) >= 3  # the grid shifted at least twice


def test_a_body_that_outgrows_the_grid_grows_it_and_swims_as_in_the_larger_grid(wide_eel):
    """The straight eel fits 16 cells of clearance plus its 2 cells of width; swimming (the
    gait of ``wide_eel``), its tail sweeps out more than that, and no shift can help: the
    grid grows (to 24, then 32 cells across) and says so. The 2-s swim then matches one
    on the 32-cell grid from the start to round-off in the cells that count: 0.4654
    against 0.4657 m (0.05%) and 0.338 against 0.320 rad of heading (the first 0.14 s near
    closer walls); the bounds are the clearance test's 1% and, for the heading turned
    through, 0.03 rad."""
    small = ag.make_scene(wide_eel, (64, 18), 0.02, fluid="euler")
    with pytest.warns(GridGrew, match=r"outgrew the 64x18 grid .* grew to 64x24") as grew:
        traj = ag.rollout(small, ag.init_state(small), wide_eel.policy(), 2.0)
    assert any("grew to 64x32" in str(w.message) for w in grew)
    assert traj.fluid.shape == (64, 32)  # frames before the growth padded with still water
    np.testing.assert_array_equal(traj.fluid.velocity[0][:, :, 24:], 0.0)
    large = ag.make_scene(wide_eel, (64, 32), 0.02, fluid="euler")
    distance, heading = swim(wide_eel, small, 2.0)
    distance_large, heading_large = swim(wide_eel, large, 2.0)
    assert distance == pytest.approx(distance_large, rel=0.01)
    assert heading == pytest.approx(heading_large, abs=0.03)


def test_a_grid_that_may_not_grow_stops_the_swim_with_the_size_it_needs(wide_eel):
    scene = ag.make_scene(wide_eel, (64, 18), 0.02, fluid=EulerFluid(grow=False))
    with pytest.raises(BodyOutsideGrid, match=r"no longer fits .* use at least 64x20 cells"):
        swim(wide_eel, scene, 2.0)


def test_a_grid_too_small_for_the_creature_is_refused_with_the_smallest_that_would_do(eel):
    with pytest.raises(ValueError, match=r"use at least (\d+)x(\d+) cells") as error:
        ag.make_scene(eel, (8, 4), 0.01, fluid="euler")
    nx, ny = (int(n) for n in error.value.args[0].split("use at least ")[1].split()[0].split("x"))
    ag.make_scene(eel, (nx, ny), 0.01, fluid="euler")  # just big enough
    for smaller in ((nx - 1, ny), (nx, ny - 1)):
        with pytest.raises(ValueError, match="cannot hold"):
            ag.make_scene(eel, smaller, 0.01, fluid="euler")


def test_a_grid_placed_off_the_creature_is_refused_and_so_is_a_start_near_a_wall(eel):
    with pytest.raises(ValueError, match="or another origin"):
        ag.make_scene(eel, (128, 64), 0.01, fluid="euler", origin=(0.0, 0.0))
    scene = ag.make_scene(eel, fluid="euler")
    qpos = eel.model.qpos0.copy()
    front_wall = scene.grid.origin[0] + scene.grid.extent[0]
    qpos[0] += front_wall - 4 * scene.grid.cell_size - eel.model.bounds[1, 0]  # snout 4 cells off
    with pytest.raises(ValueError, match="less than 8 cells from a wall"):
        ag.init_state(scene, qpos=qpos)


def test_a_still_gait_s_widest_box_is_the_body_s_box_at_rest(eel):
    scene = ag.make_scene(eel, fluid="euler")
    still = eel.spec("straight").unpack(np.zeros(eel.spec("straight").size))
    np.testing.assert_allclose(widest_box(scene, still), eel.model.extent[:2], atol=1e-9)


def test_the_widest_box_is_the_room_the_swimming_eel_takes_across(eel):
    """The eel's lateral room over three cycles of its gait, swum (the world box of its links
    every frame after the first cycle), against ``widest_box`` (its gait's poses, each turned
    back as a whole): 0.183 against 0.174 m. Held by the head instead, the same poses sweep
    0.28 m."""
    scene = ag.make_scene(eel, (64, 32), 0.02, fluid="euler")
    traj = ag.rollout(scene, ag.init_state(scene), eel.policy(), 3.0, record_fluid=False)
    swum = max(np.ptp(body_bounds(scene, q)[:, 1]) for q in traj.qpos[traj.time >= 1.0])
    predicted = widest_box(scene, eel.spec("straight").unpack(eel.default_gait))[1]
    assert predicted == pytest.approx(swum, rel=0.1)


def test_the_best_rotation_turns_a_turned_body_back(eel):
    scene = ag.make_scene(eel, fluid="euler")
    reference = _weighted_points(scene, eel.model.qpos0)
    points, mass = reference
    angle = 0.7  # about z: a turned body
    turn = np.array(
        [[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0], [0, 0, 1]]
    )
    back = _best_rotation((points @ turn.T, mass), reference)
    np.testing.assert_allclose(back, [0, 0, -angle], atol=1e-9)
