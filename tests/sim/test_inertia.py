"""A DOF's inertia in its fluid, ``1/((M + M_a)^-1)_ii``: vacuum, potential flow, a swimmer."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.control import apparent_inertia
from aquagait.sim.inertia import inertia_in_fluid

DEPTH = 0.1
RADIUS = 0.1
DISC = f"""<mujoco><custom><numeric name="aquagait_depth" data="{DEPTH}"/></custom>
  <worldbody><body name="disc">
    <joint type="slide" axis="1 0 0"/><joint type="slide" axis="0 1 0"/>
    <joint type="hinge" axis="0 0 1"/>
    <geom type="cylinder" size="{RADIUS} {DEPTH / 2}" density="1000"/>
  </body></worldbody></mujoco>"""


def test_in_a_vacuum_it_is_the_apparent_inertia(eel):
    scene = ag.make_scene(eel, fluid="none")
    np.testing.assert_allclose(inertia_in_fluid(scene), apparent_inertia(eel.model), rtol=1e-12)


@pytest.mark.parametrize("offset", [(0.0, 0.0), (0.64, 0.27), (0.81, 0.91)])
def test_a_disc_in_water_carries_its_potential_flow_added_mass(offset):
    """A neutrally buoyant disc: ``m_a = rho pi a^2 depth = m`` moving, none spinning.

    At 4 cells a radius in a box 20 radii wide, placed at a fraction of a cell:
    surge and sway within 3% of 2 m (the open boundary 10 radii away, p = 0
    there, takes about (a / R)^2 = 1% off; the sub-cell disc about 1% more;
    measured -1.4% to -1.8%), spin within 0.5% of the disc's own inertia
    (measured +0.2%: the sub-cell rim)."""
    model = ag.load_model(DISC)
    h = RADIUS / 4
    cells = 80
    origin = tuple(-cells * h / 2 + o * h for o in offset)
    scene = ag.make_scene(model, (cells, cells), h, fluid="euler", origin=origin)
    inertia = inertia_in_fluid(scene)
    mass = scene.dynamics.mass_matrix(model.qpos0)
    np.testing.assert_allclose(inertia[:2], 2 * mass[0, 0], rtol=0.03)
    assert inertia[2] == pytest.approx(mass[2, 2], rel=0.005)


def test_a_swimmers_joints_are_heavier_in_water(eel):
    """``M_a`` is positive semi-definite, so ``(M + M_a)^-1 <= M^-1`` and every DOF's
    inertia grows; eel2d's joints move water of about their own mass or more (their
    links are as dense as the water, flat, and beat broadside): measured 2.2x to 4x."""
    water = inertia_in_fluid(ag.make_scene(eel, fluid="euler"))
    vacuum = apparent_inertia(eel.model)
    joints = eel.model.actuated_dofs
    assert np.all(water[joints] > 2 * vacuum[joints])
    np.testing.assert_array_equal(inertia_in_fluid(ag.make_scene(eel, fluid="euler"), dofs=joints),
                                  water[joints])  # fmt: skip
