"""Fluid models as objects: the shorthand, a scheme passed in, their settings, bad input."""

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
