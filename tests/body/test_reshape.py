"""Visual-only geoms: massless and visible beside a massive visible geom, drawn but never simulated.

The loader (``aquagait.body.reshape``) takes them out of the physics model, so
every measure of the body (mass, inertia, voxels, surface patches, bounds,
thickening) is that of the same file without them; a link whose visible
geoms are all massless (the control suites' fish) keeps them as its shape.
"""

import pickle

import numpy as np
import pytest

from aquagait.body import Dynamics, load_model
from aquagait.body.dynamics import compile_mjcf, describe, massless_geoms
from aquagait.body.mjcf import prepare_mjcf
from aquagait.body.overlap import overlap_volume
from aquagait.body.shape import body_shape
from aquagait.body.surface import body_surface
from aquagait.body.voxelize import voxelize
from aquagait.grid import Grid

BOX = (0.05, 0.03, 0.02)  # the body's half-sides [m]
BALL = 0.04  # the look's radius [m], centred BALL_X ahead: mostly outside the box
BALL_X = 0.08


def creature(look: str = "", tail_look: str = "") -> str:
    """A two-link swimmer: a massive box body and a massive box tail, each with an
    optional extra geom ``look`` / ``tail_look`` beside its box."""
    return f"""<mujoco><worldbody>
      <body name="body"><freejoint/>
        <geom name="box" type="box" size="{" ".join(map(str, BOX))}"/>
        {look}
        <body name="tail" pos="-.05 0 0"><joint name="j" type="hinge" axis="0 0 1" range="-30 30"/>
          <geom name="fin" type="box" size=".03 .004 .015" pos="-.03 0 0"/>
          {tail_look}
        </body>
      </body></worldbody></mujoco>"""


BALL_LOOK = (
    f'<geom name="ball" type="sphere" size="{BALL}" pos="{BALL_X} 0 0" density="0" rgba="1 0 0 1"/>'
)


@pytest.fixture(scope="module")
def pair():
    """The swimmer with a massless red ball on its body, and without it."""
    return load_model(creature(BALL_LOOK)), load_model(creature())


def grid_around(model, h=0.005) -> Grid:
    return Grid((48, 24, 16), h, (-0.16, -0.06, -0.04))


def test_a_massless_visible_geom_beside_a_massive_one_is_only_drawn(pair):
    drawn, bare = pair
    assert "ball" not in describe(drawn.mj).geom_names
    (ball,) = drawn.visuals[0]
    assert drawn.visuals[1] == ()
    assert (ball.name, ball.kind) == ("ball", "sphere") and ball.size[0] == BALL
    np.testing.assert_allclose(ball.pos, [BALL_X, 0, 0], atol=1e-15)
    np.testing.assert_allclose(ball.rgba, [1, 0, 0, 1])
    assert any("'ball'" in note and "only drawn" in note for note in drawn.notes)
    assert not any("only drawn" in note for note in bare.notes)


def test_it_changes_no_mass_inertia_or_motion(pair):
    drawn, bare = pair
    np.testing.assert_array_equal(drawn.link_mass, bare.link_mass)
    np.testing.assert_allclose(drawn.mj.body_inertia, bare.mj.body_inertia, rtol=1e-12)
    np.testing.assert_allclose(drawn.mj.body_ipos, bare.mj.body_ipos, atol=1e-15)
    q = drawn.qpos0.copy()
    q[7] = 0.4
    np.testing.assert_allclose(Dynamics(drawn.mj).mass_matrix(q), Dynamics(bare.mj).mass_matrix(q),
                               rtol=1e-12, atol=1e-16)  # fmt: skip


def test_it_gives_no_shape_to_the_fluid_the_surface_or_the_bounds(pair):
    drawn, bare = pair
    np.testing.assert_array_equal(drawn.bounds, bare.bounds)
    assert drawn.body_length == bare.body_length == 2 * BOX[0] + 0.06
    h = 0.005
    shapes = body_shape(drawn, h), body_shape(bare, h)
    np.testing.assert_array_equal(shapes[0].sdf, shapes[1].sdf)
    pos, rot = Dynamics(drawn.mj).link_poses(drawn.qpos0)
    grid = grid_around(drawn, h)
    cells = [voxelize(shape, grid, pos, rot) for shape in shapes]
    np.testing.assert_array_equal(cells[0].owner, cells[1].owner)
    # the ball's cells ahead of the box are water: nothing of it reaches the grid
    centres = np.stack(grid.cell_centers(), -1)
    ahead = (np.linalg.norm(centres - [BALL_X, 0, 0], axis=-1) < BALL - h) & (
        centres[..., 0] > BOX[0] + h)  # fmt: skip
    assert ahead.sum() > 100 and not cells[0].solid[ahead].any()
    patches = body_surface(drawn), body_surface(bare)
    np.testing.assert_array_equal(patches[0].centre, patches[1].centre)
    np.testing.assert_array_equal(patches[0].area, patches[1].area)


def test_a_look_reaching_into_another_link_is_no_self_collision():
    """A look on a tail tip that reaches back into the body (links not adjacent, so
    their overlap would count): no overlap, as though it were not there."""
    tip = """<body name="tip" pos="-.06 0 0"><joint name="k" type="hinge" axis="0 0 1"/>
      <geom name="tip" type="box" size=".02 .004 .01" pos="-.02 0 0"/>{look}</body>"""
    reach = '<geom name="reach" type="box" size=".1 .01 .01" pos=".1 0 0" {mass}/>'
    volumes = []
    for mass in ('mass="0"', 'mass="0.001"'):
        look = tip.format(look=reach.format(mass=mass))
        model = load_model(creature(tail_look=look))
        pos, rot = Dynamics(model.mj).link_poses(model.qpos0)
        volumes.append(overlap_volume(body_shape(model, 0.005), pos, rot, 0.002))
        assert [v.name for v in model.visuals[2]] == (["reach"] if mass == 'mass="0"' else [])
    # with mass, the reach is shape: x from -0.11 to 0.09 m, it crosses the body's box
    # (x within +-0.05 m) for 0.1 x 0.02 x 0.02 m; the 2 mm lattice errs by at most its
    # surface (0.0088 m^2) times half its spacing, 22 % of that
    assert volumes[0] == 0.0 and volumes[1] == pytest.approx(0.1 * 0.02 * 0.02, rel=0.22)


def test_thin_looks_are_not_thickened():
    """A 1 mm massless plate beside the fin: no note names it, and the fin alone shapes
    the tail, widened to the minimum as without it."""
    plate = '<geom name="web" type="box" size=".03 .0005 .02" pos="-.03 0 0" density="0"/>'
    drawn = load_model(creature(tail_look=plate), thicken_to=0.01)
    bare = load_model(creature(), thicken_to=0.01)
    thick = [n for n in drawn.notes if "thickened" in n]
    assert thick and "'web'" not in thick[0] and "'fin'" in thick[0]
    np.testing.assert_array_equal(drawn.mj.geom_size, bare.mj.geom_size)
    assert drawn.visuals[1][0].size[1] == 0.0005  # drawn as written


@pytest.mark.parametrize(
    "attributes",
    ['mass="0"', 'density="0"', 'mass="0" density="500"', 'density="0" group="2"'],
)
def test_massless_means_mujoco_gives_it_no_mass(attributes):
    look = f'<geom name="look" type="sphere" size=".01" pos=".06 0 0" {attributes}/>'
    model = load_model(creature(look))
    assert [v.name for v in model.visuals[0]] == ["look"]


@pytest.mark.parametrize(
    "attributes",
    ['density="0" mass="0.01"', 'density="10"', 'mass="1e-6"'],
    ids=["mass wins over density", "light", "tiny mass"],
)
def test_a_geom_with_any_mass_is_shape(attributes):
    look = f'<geom name="look" type="sphere" size=".01" pos=".06 0 0" {attributes}/>'
    model = load_model(creature(look))
    assert model.visuals[0] == () and "look" in describe(model.mj).geom_names


def test_massless_geoms_follow_defaults_frames_and_the_inertia_group_range():
    xml = """<mujoco><compiler inertiagrouprange="0 1"/>
      <default><default class="look"><geom density="0"/></default></default>
      <worldbody><body><freejoint/>
        <geom type="box" size=".05 .03 .02"/>
        <frame childclass="look"><geom type="sphere" size=".01"/></frame>
        <geom type="sphere" size=".01" group="2"/>
        <geom type="sphere" size=".01" mass="0.2" density="0"/>
      </body></worldbody></mujoco>"""
    np.testing.assert_array_equal(massless_geoms(xml), [False, True, True, False])
    compiled = compile_mjcf(xml=xml)
    assert compiled.body_mass[1] == pytest.approx(1000 * 8 * 0.05 * 0.03 * 0.02 + 0.2)


def test_the_control_suites_fish_keeps_its_massless_visible_geoms_as_shape():
    """Mass on a hidden geom, looks on massless visible ones: no visible geom has mass,
    so the visible ones are the shape (and the hidden one only gives mass), as before."""
    xml = creature().replace(
        '<geom name="box" type="box"',
        '<geom name="ballast" type="box" size=".01 .01 .01" mass=".5" group="3"/>'
        '<geom name="skin" type="ellipsoid" size=".06 .03 .02" density="0"/>'
        '<geom name="box" density="0" type="box"',
    )
    model = load_model(xml)
    names = describe(model.mj).geom_names
    assert "skin" in names and "box" in names and "ballast" not in names
    assert all(link == () for link in model.visuals)
    assert model.link_mass[0] == pytest.approx(0.5, rel=1e-12)
    assert not any("only drawn" in note for note in model.notes)


def test_a_link_with_an_inertial_and_massless_geoms_keeps_them_as_shape():
    inertial = '<inertial pos="0 0 0" mass=".3" diaginertia="1e-4 1e-4 1e-4"/>'
    xml = creature().replace(
        '<geom name="box" type="box"', inertial + '<geom name="box" density="0" type="box"'
    )
    model = load_model(xml)
    assert "box" in describe(model.mj).geom_names and model.visuals[0] == ()


def test_visuals_survive_pickling_and_a_turn_to_face_x():
    """Records are in the link frame: turning the creature to face +x moves none."""
    model = load_model(creature(BALL_LOOK), forward=(0, 1, 0))
    assert any("turned to face +x" in note for note in model.notes)
    (ball,) = model.visuals[0]
    np.testing.assert_allclose(ball.pos, [BALL_X, 0, 0], atol=1e-15)
    again = pickle.loads(pickle.dumps(model))
    np.testing.assert_array_equal(again.visuals[0][0].pos, ball.pos)
    assert again.visuals[0][0].kind == "sphere"


def test_the_text_mujoco_compiles_still_has_the_look():
    """Only the loader sets it aside: MuJoCo reading the file itself gives it no mass."""
    text = prepare_mjcf(creature(BALL_LOOK), None, "<string>").xml
    facts = describe(compile_mjcf(xml=text))
    assert "ball" in facts.geom_names
    np.testing.assert_array_equal(load_model(creature(BALL_LOOK)).link_mass, facts.link_mass)
