"""Fluid models as objects: the shorthand, a scheme passed in, their settings, bad input,
a body the grid does not see."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.fluid.advection import semi_lagrangian
from aquagait.sim import FLUIDS


def swim(scene, eel, seconds=0.2):
    return ag.rollout(scene, ag.init_state(scene), eel.policy(), seconds, record_fluid=False)


def test_the_name_is_a_shorthand_for_the_default_model(eel):
    grid = ((48, 24), 0.025)
    by_name = swim(ag.make_scene(eel, *grid, fluid="euler"), eel)
    by_object = swim(ag.make_scene(eel, *grid, fluid=ag.EulerFluid()), eel)
    np.testing.assert_array_equal(by_name.qpos, by_object.qpos)
    assert {name: FLUIDS[name]().name for name in FLUIDS} == {n: n for n in FLUIDS}
    assert by_name.dt == ag.EulerFluid().max_dt


def test_a_scheme_is_a_function_passed_in(eel):
    """Plain semi-Lagrangian advection diffuses more than BFECC: the same swim, not the
    same numbers; the scene's settings name the scheme."""
    grid = ((48, 24), 0.025)
    plain = ag.make_scene(eel, *grid, fluid=ag.EulerFluid(advect=semi_lagrangian))
    assert plain.fluid.settings()["advect"] == "semi_lagrangian"
    a, b = swim(plain, eel).qpos, swim(ag.make_scene(eel, *grid, fluid="euler"), eel).qpos
    assert not np.array_equal(a, b)
    np.testing.assert_allclose(a, b, atol=0.01)  # a fifth of a second from rest: close


def test_simple_and_vacuum_models_carry_their_settings(eel):
    scene = ag.make_scene(eel, fluid=ag.SimpleFluid(drag_coefficient=0.6))
    assert scene.fluid.settings() == {"drag_coefficient": 0.6}
    assert scene.fluid.surface is not None  # baked for this creature by make_scene
    assert ag.make_scene(eel, fluid=ag.Vacuum()).fluid.settings() == {}


def test_an_unknown_fluid_is_refused_with_the_known_ones(eel):
    with pytest.raises(ValueError, match="unknown fluid 'water'; fluids: none, simple, euler"):
        ag.make_scene(eel, fluid="water")
    with pytest.raises(TypeError, match="must be a fluid model"):
        ag.make_scene(eel, fluid=42)
    with pytest.raises(ValueError, match="drag_coefficient must be >= 0"):
        ag.SimpleFluid(drag_coefficient=float("nan"))


@pytest.mark.parametrize(
    "name, grid, seconds",
    [("eel2d", ((48, 28), 0.025), 1.0), ("fish", ((40, 28, 28), 0.006), 0.5)],
)
def test_float32_face_velocities_swim_as_float64_does(name, grid, seconds):
    """The fluid's faces in float32, the coupled solve in float64: the swim is the same to
    far inside the 0.5 % a gait's ranking could notice (measured: the roots end 1e-8 of
    the distance apart), and the fields stay float32 from step to step."""
    creature = ag.creatures.get(name)
    swims = {}
    for dtype in (np.float64, np.float32):
        scene = ag.make_scene(creature, *grid, fluid=ag.EulerFluid(dtype=dtype))
        state = ag.init_state(scene)
        assert all(c.dtype == dtype for c in state.velocity)
        traj = ag.rollout(scene, state, creature.policy(), seconds, record_fluid=False)
        swims[dtype] = traj.qpos[-1, :2] - traj.qpos[0, :2]
    distance = np.linalg.norm(swims[np.float64])
    apart = np.linalg.norm(swims[np.float32] - swims[np.float64])
    print(f"{name}: {distance:.4f} m in {seconds} s, float32 {apart / distance:.1e} of it apart")
    assert apart <= 0.005 * distance


def test_the_precision_is_a_setting_and_checked(eel):
    assert ag.EulerFluid().settings()["dtype"] == "float64"
    assert ag.EulerFluid(dtype=np.float32).settings()["dtype"] == "float32"
    with pytest.raises(ValueError, match="near_body must be a whole number of cells >= -1"):
        ag.EulerFluid(near_body=1.5)
    with pytest.raises(ValueError, match=r"mostly_water must be a water fraction in \[0, 1\]"):
        ag.EulerFluid(mostly_water=2)
    with pytest.raises(ValueError, match="must be np.float64 or np.float32, got"):
        ag.EulerFluid(dtype=np.int32)


PLATE = """<mujoco><worldbody><body name="plate"><freejoint/>
  <geom name="blade" type="box" size="0.05 0.05 0.0015" density="1000"/>
</body></worldbody></mujoco>"""
"""A 10 cm square plate 3 mm thick: on 1 cm cells centred on it, the cell centres lie
5 mm either side of its mid-plane, none inside it."""


def plate_scene(boundary=None, origin=None):
    fluid = ag.EulerFluid() if boundary is None else ag.EulerFluid(boundary=boundary)
    return ag.make_scene(ag.load_model(PLATE), (32, 32, 20), 0.01, fluid=fluid, origin=origin)


def test_a_body_no_cell_centre_falls_in_is_refused_by_name_on_the_staircase():
    from aquagait.body.voxelize import voxelize

    with pytest.raises(ag.sim.BodyNotOnGrid) as refused:
        ag.init_state(plate_scene(voxelize))
    message = str(refused.value)
    for fact in ("t = 0 s", "'voxelize'", "0.01 m grid", "plate (3 mm thick, 0.3 cells)",
                 "at most 1.5 mm", "boundary=voxelize_subcell"):  # fmt: skip
        assert fact in message
    # a simulation error, as the command line reports one
    assert isinstance(refused.value, ag.sim.SimulationError)


def test_the_same_plate_is_seen_by_a_cell_centre_or_the_sub_cell_boundary():
    """Moved half a cell across, the centres' plane lies in the plate and the staircase has
    cells to couple; the default boundary sees it through its faces where it lies. Either
    way the water slows a plate started broadside: any added mass takes speed away."""
    from aquagait.body.voxelize import voxelize

    shifted = (-0.16, -0.16, -0.095)  # the centres at z = 0: the plate's mid-plane
    for scene in (plate_scene(voxelize, origin=shifted), plate_scene()):
        state = ag.init_state(scene, qvel=[0, 0, 0.1, 0, 0, 0])
        after = ag.step(scene, state, 1 / 90)
        assert 0 < after.qvel[2] < 0.1
