"""turtle2d: a side-view green sea turtle (paper Table 1: 2D, 4 DOFs, 4 dims, 64 x 64)."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.app.check import prepare_check, resolving_shape
from aquagait.app.swim import prepare_swim, run_swim
from aquagait.body.shape import link_thickness


@pytest.fixture(scope="module")
def turtle():
    return ag.creatures.get("turtle2d")


def test_table1_numbers(turtle):
    assert turtle.dim == 2
    assert len(turtle.model.actuated_dofs) == 4
    assert turtle.gait.size == 4
    assert tuple(turtle.resolution) == (64, 64)


def test_gait_drives_the_front_flipper_and_the_rear_one_trails(turtle):
    # 4 dims from 4 DOFs: amplitude and phase of the front shoulder and wrist;
    # the rear hip and knee are actuated but servoed to rest (rudders).
    assert turtle.gait.dofs == ("front_shoulder", "front_wrist")
    assert turtle.gait.free == ("amplitude", "phase")
    assert turtle.gait.mirror == () and turtle.gait.groups == ()
    names = [turtle.model.dof_names[i] for i in turtle.model.actuated_dofs]
    assert sorted(names) == ["front_shoulder", "front_wrist", "rear_hip", "rear_knee"]


def test_every_link_is_at_least_one_and_a_half_cells_thick(turtle):
    scene = prepare_check(turtle).scene
    thickness = link_thickness(resolving_shape(turtle.model, scene.shape))
    assert np.all(thickness / turtle.cell_size >= 1.5), dict(
        zip(turtle.model.links, np.round(thickness / turtle.cell_size, 2), strict=True)
    )


def test_masses_are_a_water_density_prism_of_the_turtle(turtle):
    model = turtle.model
    mass = dict(zip(model.links, model.link_mass, strict=True))
    # the shell's side outline (about 0.14 m^2 with the head) times the 0.55 m depth
    assert model.depth == pytest.approx(0.55)
    assert 70 < mass["shell"] < 90
    # a flipper plate: length x 50 mm x 0.55 m of water
    assert mass["front_blade"] == pytest.approx(0.20 * 0.05 * 0.55 * 1000, rel=0.01)
    assert mass["front_arm"] + mass["front_blade"] > mass["rear_leg"] + mass["rear_blade"]


def test_shipped_gait_swims_forward():
    # One cycle from rest at the default grid (about 3 s of wall time): the
    # front flipper's heave and pitch thrust the turtle forward (+x). The
    # shipped gait travels 0.08 m in its first second, 3 cells; this asks only
    # for more than one cell forward, and for a pitch that stays small in one
    # cycle (it drifts nose down over several, as the paper's 2D turtle does).
    run = run_swim(prepare_swim("turtle2d", seconds=1.0))
    x, _, theta = run.trajectory.qpos[-1, :3]
    assert x > run.setup.creature.cell_size
    assert abs(theta) < np.radians(10)
    assert run.metrics["energy"] < run.setup.creature.energy_bound
