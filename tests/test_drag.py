"""The simple fluid: quadratic drag on plates against the formula, coasting against the
quadratic law, and the library creatures swimming in it."""

import time
from dataclasses import replace

import numpy as np
import pytest

import aquagait as ag
from aquagait.app.optimize import SwimObjective
from aquagait.body import Dynamics, load_model
from aquagait.body.surface import body_surface
from aquagait.drag import DRAG_COEFFICIENT, drag_force, patch_forces

RHO = 1000.0
K = DRAG_COEFFICIENT
DEPTH = 0.04


def plate(a: float, b: float, t: float, euler: str = "0 0 0"):
    """A free box of half sizes a (x), b (y), t (z), density 1000, turned by ``euler``."""
    return load_model(f"""<mujoco><worldbody><body name="plate" pos=".1 .2 .3" euler="{euler}">
        <freejoint/><geom type="box" size="{a} {b} {t}" density="1000"/></body></worldbody>
        </mujoco>""")


def planar_plate(a: float, b: float):
    return load_model(f"""<mujoco><custom><numeric name="aquagait_depth" data="{DEPTH}"/>
        </custom><worldbody><body name="plate"><joint type="slide" axis="1 0 0"/>
        <joint type="slide" axis="0 1 0"/><joint type="hinge" axis="0 0 1"/>
        <geom type="box" size="{a} {b} {DEPTH / 2}" density="1000"/></body></worldbody>
        </mujoco>""")


def force_at(model, qd, resolution=0.01):
    return drag_force(body_surface(model, resolution), Dynamics(model.mj), model.qpos0, qd, RHO)


# --- a plate at one instant ----------------------------------------------------------


@pytest.mark.parametrize("v", [0.3, -0.7])
def test_plate_moving_along_its_normal_feels_the_quadratic_drag(v):
    """Only the face moving into the water counts: f = -k rho A v |v| along the normal."""
    a, b, t = 0.05, 0.04, 0.002
    model = plate(a, b, t)
    force = force_at(model, np.array([0, 0, v, 0, 0, 0.0]))
    expected = np.array([0, 0, -K * RHO * (2 * a) * (2 * b) * v * abs(v), 0, 0, 0])
    np.testing.assert_allclose(force, expected, rtol=1e-12, atol=1e-15)


def test_a_turned_plate_is_pushed_back_along_its_own_normal():
    a, b, t = 0.05, 0.04, 0.002
    model = plate(a, b, t, euler="30 -20 60")
    dynamics = Dynamics(model.mj)
    normal = dynamics.link_poses(model.qpos0)[1][0][:, 2]  # the plate's z axis in the world
    v = 0.4
    force = force_at(model, np.concatenate([v * normal, np.zeros(3)]))
    np.testing.assert_allclose(force[:3], -K * RHO * 4 * a * b * v**2 * normal, rtol=1e-12)
    np.testing.assert_allclose(force[3:], 0, atol=1e-15)


def test_plate_moving_along_itself_feels_only_its_edge():
    """The broad faces feel nothing; the thin front edge (area 2b x 2t) is all that drags."""
    a, b, t = 0.05, 0.04, 0.002
    model = plate(a, b, t)
    surface = body_surface(model, 0.01)
    v = 0.5
    qd = np.array([v, 0, 0, 0, 0, 0.0])
    _, forces = patch_forces(surface, Dynamics(model.mj), model.qpos0, qd, RHO)
    broad = np.abs(surface.normal[:, 2]) == 1
    assert not forces[broad].any()
    force = drag_force(surface, Dynamics(model.mj), model.qpos0, qd, RHO)
    np.testing.assert_allclose(force, [-K * RHO * 4 * b * t * v**2, 0, 0, 0, 0, 0], atol=1e-15)


def test_planar_plate_moving_along_its_normal():
    a, b = 0.002, 0.05  # thin along x
    model = planar_plate(a, b)
    v = 0.3
    force = force_at(model, np.array([v, 0, 0.0]), resolution=0.005)
    np.testing.assert_allclose(
        force, [-K * RHO * 2 * b * DEPTH * v**2, 0, 0], rtol=1e-12, atol=1e-15
    )


def test_a_body_at_rest_feels_nothing():
    for model in (plate(0.05, 0.04, 0.002), planar_plate(0.01, 0.05)):
        assert not force_at(model, np.zeros(model.nv)).any()
    creature = ag.creatures.get("fish")
    scene = ag.make_scene(creature, fluid="simple")
    assert not drag_force(scene.fluid.surface, scene.dynamics, creature.model.qpos0,
                          np.zeros(creature.model.nv), RHO).any()  # fmt: skip


def test_spinning_plate_feels_the_integrated_torque():
    """Spin w about y: each face pushes back on its leading half; T = k rho w^2 b (a^4 + t^4)."""
    a, b, t = 0.05, 0.04, 0.005
    model = plate(a, b, t)
    w = 3.0
    force = force_at(model, np.array([0, 0, 0, 0, w, 0.0]), resolution=0.001)
    torque = K * RHO * w**2 * b * (a**4 + t**4)
    np.testing.assert_allclose(force[:3], 0, atol=1e-12)  # the two faces push opposite ways
    np.testing.assert_allclose(force[3:], [0, -torque, 0], rtol=2e-3, atol=1e-12)


# --- coasting: the quadratic law ------------------------------------------------------


def coast(model, qvel, seconds, dt, resolution=0.005):
    scene = ag.make_scene(model, fluid="simple")
    scene = replace(scene, fluid=replace(scene.fluid, surface=body_surface(model, resolution)))
    state = ag.init_state(scene, qvel=qvel)
    return ag.rollout(scene, state, None, seconds, dt=dt)


def test_a_plate_coasting_broadside_slows_as_the_quadratic_law_predicts():
    """m v' = -c v^2 with c = k rho A: v(t) = v0 / (1 + c v0 t / m); explicit steps: O(dt)."""
    a, b, t = 0.05, 0.04, 0.02
    model = plate(a, b, t)
    m, c, v0 = model.mass, K * RHO * 4 * a * b, 0.5
    errors = []
    for dt in (1 / 300, 1 / 600):
        traj = coast(model, [0, 0, v0, 0, 0, 0], 0.3, dt)
        exact = v0 / (1 + c * v0 * traj.time / m)
        errors.append(np.abs(traj.qvel[:, 2] - exact).max() / v0)
        np.testing.assert_allclose(traj.qvel[:, [0, 1, 3, 4, 5]], 0, atol=1e-14)
        assert not traj.energy.any()  # drag does no actuator work
        travelled = traj.qpos[-1, 2] - traj.qpos[0, 2]
        law = m / c * np.log(1 + c * v0 * traj.time[-1] / m)
        print(f"dt {dt:.4f}: v(0.3 s) {traj.qvel[-1, 2]:.5f} vs {exact[-1]:.5f} m/s, distance "
              f"{travelled:.5f} vs {law:.5f} m, max error {errors[-1]:.2%} of v0")  # fmt: skip
        assert abs(travelled - law) < 12 * dt * law  # first order: 4% at dt = 1/300
    assert errors[0] < 0.01
    assert 0.4 < errors[1] / errors[0] < 0.6  # first order in dt


def test_a_spinning_plate_slows_as_the_quadratic_law_predicts():
    """I w' = -C w^2 with C = k rho b (a^4 + t^4), I = m (a^2 + t^2) / 3."""
    a, b, t = 0.05, 0.04, 0.005
    model = plate(a, b, t)
    inertia = model.mass * (a**2 + t**2) / 3
    drag, w0 = K * RHO * b * (a**4 + t**4), 2.0
    traj = coast(model, [0, 0, 0, 0, w0, 0], 0.3, 1 / 600, resolution=0.002)
    exact = w0 / (1 + drag * w0 * traj.time / inertia)
    print(f"spin: w(0.3 s) {traj.qvel[-1, 4]:.4f} vs {exact[-1]:.4f} rad/s")
    np.testing.assert_allclose(traj.qvel[:, 4], exact, rtol=0.01)
    np.testing.assert_allclose(traj.qvel[:, :3], 0, atol=1e-12)


# --- the creatures ----------------------------------------------------------------------


@pytest.mark.parametrize("name", ["eel2d", "fish"])
def test_creatures_swim_in_the_simple_fluid_much_faster_than_in_euler(name):
    creature = ag.creatures.get(name)
    seconds = {}
    for fluid, span in (("simple", 1.0), ("euler", 0.2)):
        scene = ag.make_scene(creature, fluid=fluid)
        start = time.perf_counter()
        traj = ag.rollout(scene, ag.init_state(scene), creature.policy(), span)
        seconds[fluid] = (time.perf_counter() - start) / span
        assert np.all(np.isfinite(traj.qpos))
        assert (traj.fluid is None) == (fluid == "simple")
    ratio = seconds["euler"] / seconds["simple"]
    print(f"{name}: {seconds['simple']:.2f} s per simulated second in the simple fluid, "
          f"{seconds['euler']:.2f} in the Euler fluid ({ratio:.0f}x)")  # fmt: skip


def test_the_eel_swims_forward_in_the_simple_fluid():
    """The eel is a drag-based swimmer: its travelling wave pushes it head first."""
    creature = ag.creatures.get("eel2d")
    scene = ag.make_scene(creature, fluid="simple")
    traj = ag.rollout(scene, ag.init_state(scene), creature.policy(), 2.0, record_fluid=False)
    start, end = (scene.dynamics.center_of_mass(traj.qpos[i]) for i in (0, -1))
    print(f"eel2d, default gait, simple fluid: {end[0] - start[0]:.3f} m forward in 2 s")
    assert end[0] - start[0] > 0.1 * creature.model.body_length
    assert abs(end[1] - start[1]) < 0.2 * (end[0] - start[0])
    objective = SwimObjective("eel2d", None, None, fluid="simple")  # the optimizer's seam
    assert objective(creature.default_gait) < 0  # forward is rewarded


def test_simple_scene_needs_no_grid_and_keeps_one_if_given():
    model = plate(0.05, 0.04, 0.002)
    bare = ag.make_scene(model, fluid="simple")
    assert bare.grid is None and bare.fluid.surface is not None and bare.fluid.drag_coefficient == K
    state = ag.init_state(bare)
    assert state.velocity is None and state.grid is None
    creature = ag.creatures.get("eel2d")
    assert ag.make_scene(creature, fluid="simple").grid.shape == creature.resolution
    halved = ag.make_scene(model, fluid="simple", drag_coefficient=0.5)
    qd = np.array([0, 0, 0.3, 0, 0, 0.0])
    np.testing.assert_allclose(
        drag_force(halved.fluid.surface, halved.dynamics, model.qpos0, qd, RHO, 0.5),
        0.5 * drag_force(bare.fluid.surface, bare.dynamics, model.qpos0, qd, RHO),
    )
