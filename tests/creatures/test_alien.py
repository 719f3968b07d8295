"""The alien (paper Figure 13, Table 1): an 8-hinge tail, two pairs of mirrored two-hinge wings."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.app.swim import prepare_swim, run_swim
from aquagait.body.shape import body_shape, link_thickness
from aquagait.creatures import get

TAIL = tuple(f"t{k}" for k in range(1, 9))
WINGS = ("wing1_flap", "wing1_pitch", "wing2_flap", "wing2_pitch")
RHO = 1000.0


@pytest.fixture(scope="module")
def alien():
    return get("alien")


def test_alien_matches_table_1(alien):
    assert alien.dim == 3
    assert len(alien.model.actuated_dofs) == 16
    assert alien.gait.size == 24  # 8 tail DOFs + 4 left wing DOFs, x (amplitude, phase)
    assert alien.resolution == (96, 40, 28)  # the paper: 96x36x24; ours holds its gait
    assert alien.gait.period == 1.0 and alien.gait.offset == 0.0
    assert alien.gait.free == ("amplitude", "phase")


def test_right_wings_mirror_the_left_and_the_tail_is_optimized_first(alien):
    mirror = {dof: (source, sign) for dof, source, sign in alien.gait.mirror}
    assert mirror == {f"{n}_r": (f"{n}_l", -1) for n in WINGS}
    tail, wings = alien.gait.groups
    assert tail == TAIL
    assert set(wings) == {f"{n}_{s}" for n in WINGS for s in "lr"}
    assert len(alien.gait.group_indices(0)) == 16 and len(alien.gait.group_indices(1)) == 8


def test_wings_are_reflections(alien):
    model = alien.model
    pos, _ = ag.make_scene(alien, fluid="none").dynamics.link_poses(model.qpos0)
    for left in ("wing1_l", "wing2_l"):
        i, j = model.links.index(left), model.links.index(left[:-1] + "r")
        assert model.link_mass[i] == pytest.approx(model.link_mass[j], rel=1e-6)
        assert pos[j] == pytest.approx(pos[i] * [1, -1, 1], abs=1e-9)


def test_every_link_is_about_two_cells_thick_at_the_default_grid(alien):
    """Wings, fin and tail tip are 8 mm at 4 mm cells (thicker than a fin would be, so the
    fluid sees them); the tail's 16-sided sections measure a little less: 1.75 cells."""
    shape = body_shape(alien.model, alien.cell_size, refine=4)
    assert link_thickness(shape).min() / alien.cell_size > 1.75


def test_alien_masses(alien):
    model = alien.model
    mass = dict(zip(model.links, model.link_mass, strict=True))
    assert 0.04 < model.mass < 0.08
    assert model.body_length == pytest.approx(0.255, rel=0.01)
    # a wing: a trapezoid 22 mm span, 26 -> 16 mm chord, 8 mm thick, of water
    assert mass["wing1_l"] == pytest.approx(RHO * 0.022 * (0.026 + 0.016) / 2 * 0.008, rel=1e-3)
    tail = [mass[f"tail{k}"] for k in range(1, 8)]
    assert np.all(np.diff(tail) < 0)  # the tail tapers


def test_shipped_gait_swims_forward_and_straight():
    """Two cycles on a coarse grid (6 mm cells, 72x30x22: the body with 8 cells of water).
    The hand-set gait is slow (11 mm in 2 s on the default grid, 0.02 body lengths per
    cycle): it must end ahead by half of that, neither climb nor sink off its course by
    more than 5 degrees, and not turn off it (yaw < 10 deg). Measured: 35.6 mm ahead,
    2.0 mm down (3.2 degrees; with water fractions alone and the per-step hold, 41.7
    and 0.4 mm)."""
    setup = prepare_swim("alien", seconds=2.0, resolution=(72, 30, 22), cell_size=0.006)
    q = run_swim(setup).trajectory.qpos
    assert q[-1, 0] > 0.005
    assert abs(q[-1, 2]) < np.tan(np.radians(5)) * q[-1, 0]
    w, x, y, z = q[-1, 3:7]
    yaw = np.degrees(np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)))
    assert abs(yaw) < 10
