"""Models written for other MuJoCo projects load as MuJoCo reads them (issue 31).

Each small model carries one trait of the swimmers of control suites and RL
benchmarks: masses from ``mass=`` or ``<inertial>``, a link's mass on a hidden
geom, ranges switched off or missing.
"""

import mujoco
import numpy as np
import pytest

import aquagait as ag
from aquagait.body import ModelError, load_model
from aquagait.body.dynamics import Dynamics, compile_mjcf, describe
from aquagait.body.geometry import link_volumes
from aquagait.body.mjcf import prepare_mjcf
from aquagait.body.model import DEFAULT_RANGE

TAIL = (
    "<body name='tail' pos='-.1 0 0'><joint name='j' type='hinge' axis='0 0 1' {joint}/>"
    "<geom name='fin' type='box' size='.05 .005 .03' pos='-.05 0 0' {fin}/></body>"
)


def fish(head="", joint="range='-30 30'", fin="", extra="", compiler=""):
    """A two-link 3D swimmer: an ellipsoid head and a box tail, with the given attributes."""
    tail = TAIL.format(joint=joint, fin=fin)
    return (
        f"<mujoco>{compiler}<worldbody><body name='head'><freejoint/>"
        f"<geom name='head' type='ellipsoid' size='.1 .03 .05' {head}/>{tail}</body>"
        f"</worldbody>{extra}</mujoco>"
    )


def mujoco_model(xml: str):
    """MuJoCo's own compile of the text aquagait reads (scenery set aside)."""
    return compile_mjcf(xml=prepare_mjcf(xml, None, "<string>").xml)


def test_geom_masses_and_inertials_are_mujocos():
    head_volume = 4 / 3 * np.pi * 0.1 * 0.03 * 0.05
    model = load_model(fish(head="mass='0.5'", fin="density='500'"))
    assert model.link_mass == pytest.approx([0.5, 500 * 8 * 0.05 * 0.005 * 0.03], rel=1e-12)
    inertial = "<inertial pos='-.05 0 0' mass='.02' diaginertia='1e-5 2e-5 3e-5'/>"
    model = load_model(fish().replace("<geom name='fin'", inertial + "<geom name='fin'"))
    assert model.link_mass == pytest.approx([1000 * head_volume, 0.02], rel=1e-12)
    # the shape is still the geoms': the tail's box, though its mass comes from <inertial>
    assert link_volumes(model)[1] == pytest.approx(8 * 0.05 * 0.005 * 0.03, rel=1e-12)


def test_inertia_from_an_inertial_everywhere_is_accepted():
    inertial = "<inertial pos='0 0 0' mass='{m}' diaginertia='1e-4 1e-4 1e-4'/>"
    xml = fish(compiler="<compiler inertiafromgeom='false'/>")
    xml = xml.replace("<freejoint/>", "<freejoint/>" + inertial.format(m=0.3))
    xml = xml.replace("<geom name='fin'", inertial.format(m=0.01) + "<geom name='fin'")
    assert load_model(xml).link_mass == pytest.approx([0.3, 0.01])


def test_a_geom_without_density_has_waters_as_in_mujoco():
    model = load_model(fish())
    volumes = link_volumes(model)
    assert model.link_mass == pytest.approx(1000 * volumes, rel=1e-12)


@pytest.mark.parametrize("hidden", ["group='4'", "rgba='0 0 0 0'"], ids=["group", "alpha"])
def test_a_hidden_geom_gives_mass_but_no_shape(hidden):
    """The control suites' style: the mass on a hidden box, the shape on massless geoms."""
    ballast = f"<geom name='ballast' type='box' size='.002 .06 .03' mass='0.03' {hidden}/>"
    xml = fish(head="mass='0'").replace("<body name='tail'", ballast + "<body name='tail'")
    model, original = load_model(xml), mujoco_model(xml)
    names = describe(model.mj).geom_names
    assert "ballast" not in names and "head" in names
    assert any("'ballast'" in note and "only gives mass" in note for note in model.notes)
    # the motion is MuJoCo's: same masses, same mass matrix at any pose
    np.testing.assert_allclose(model.link_mass, original.body_mass[1:], rtol=1e-12)
    rng = np.random.default_rng(1)
    q = original.qpos0.copy()
    q[3:7] = rng.normal(size=4)
    q[3:7] /= np.linalg.norm(q[3:7])
    q[7] = 0.3
    data = mujoco.MjData(original)
    data.qpos[:] = q
    mujoco.mj_forward(original, data)
    expected = np.zeros((original.nv, original.nv))
    mujoco.mj_fullM(original, data, expected)
    ours = Dynamics(model.mj).mass_matrix(q)
    np.testing.assert_allclose(ours, expected, rtol=1e-10, atol=1e-14)


def test_a_link_whose_geoms_are_all_hidden_keeps_them_as_its_shape():
    model = load_model(fish(fin="group='3'"))
    assert "fin" in describe(model.mj).geom_names
    assert not any("only give" in note for note in model.notes)


def gait_range(xml, joint="j"):
    model = load_model(xml)
    return model.joint(joint).range, model.notes


def test_a_range_switched_off_bounds_the_gait_with_a_note():
    bounds, notes = gait_range(fish(joint="limited='false' range='-30 30'"))
    assert bounds == pytest.approx(np.radians([-30, 30]))
    assert any("joint 'j' has a range that is switched off" in n for n in notes)
    radian = "<compiler angle='radian'/>"
    bounds, _ = gait_range(fish(joint="limited='false' range='-.4 .5'", compiler=radian))
    assert bounds == pytest.approx([-0.4, 0.5])


def test_a_joint_without_range_takes_its_position_servos_targets():
    servo = "<actuator><position joint='j' ctrlrange='-0.5 0.8' gear='2' kp='1'/></actuator>"
    bounds, notes = gait_range(fish(joint="", extra=servo))
    assert bounds == pytest.approx([-0.25, 0.4])  # MuJoCo's servo holds q = ctrl / gear
    assert any("position servo" in n and "'j' -0.25 to 0.4 rad" in n for n in notes)
    motor = "<actuator><motor joint='j' ctrlrange='-1 1'/></actuator>"
    bounds, notes = gait_range(fish(joint="", extra=motor))  # a motor bounds no angle
    assert bounds == pytest.approx([-DEFAULT_RANGE, DEFAULT_RANGE])
    assert any("no range and no position servo" in n and "60 degrees" in n for n in notes)


def test_a_ball_without_range_gets_the_default_cone():
    xml = fish(joint="").replace("type='hinge' axis='0 0 1'", "type='ball'")
    model = load_model(xml)
    assert model.joint("j").range == pytest.approx((0.0, DEFAULT_RANGE))
    assert model.upper == pytest.approx([DEFAULT_RANGE] * 3)


def test_thin_geoms_are_thickened_for_the_fluid_and_the_motion_is_unchanged():
    """A 2 mm fin (a control-suite fish's) widened to 6 mm: its other sides, its frame and
    the link's mass and inertia are MuJoCo's as written."""
    xml = fish(fin="").replace("size='.05 .005 .03'", "size='.05 .001 .03' euler='0 0 20'")
    model, original = load_model(xml, thicken_to=0.006), mujoco_model(xml)
    facts, written = describe(model.mj), describe(original)
    np.testing.assert_allclose(facts.geom_size[1], [0.05, 0.003, 0.03])
    np.testing.assert_allclose(facts.geom_box[0], written.geom_box[0])  # the head as it was
    np.testing.assert_allclose(facts.geom_pos, written.geom_pos, atol=1e-15)
    np.testing.assert_allclose(facts.geom_rot, written.geom_rot, atol=1e-15)
    np.testing.assert_allclose(model.link_mass, original.body_mass[1:], rtol=1e-12)
    np.testing.assert_allclose(facts.link_inertia, written.link_inertia, rtol=1e-12)
    assert any("thickened for the fluid to 6 mm: 'fin' 2 -> 6 mm" in n for n in model.notes)
    assert load_model(xml, thicken_to=0.002).notes == load_model(xml).notes  # not thin: as is


PLANAR = """<mujoco><custom><numeric name="aquagait_depth" data="0.04"/></custom><worldbody>
  <body name="head"><joint type="slide" axis="1 0 0"/><joint type="slide" axis="0 1 0"/>
    <joint type="hinge" axis="0 0 1"/><geom type="box" size=".05 .01 .02"/>
    <body name="tail" pos="-.05 0 0"><joint name="j" type="hinge" axis="0 0 1" range="-30 30"/>
      <geom name="fin" type="box" size=".05 .001 .02" pos="-.05 0 0"/></body>
  </body></worldbody></mujoco>"""


def test_a_planar_prism_is_thickened_in_its_plane_only():
    model = load_model(PLANAR, thicken_to=0.004)
    assert model.dim == 2
    np.testing.assert_allclose(describe(model.mj).geom_size[1], [0.05, 0.002, 0.02])


def test_the_ellipsoids_thickness_is_its_least_axis():
    """Deep inside a flat ellipsoid the first-order distance estimate reached its longest
    semi-axis: a 2 mm fin measured 32 mm thick, and the default grid would not see it."""
    from aquagait.body.shape import body_shape, link_thickness

    xml = fish(fin="").replace("type='box' size='.05 .005 .03'", "type='ellipsoid' "
                               "size='.02 .001 .016'")  # fmt: skip
    shape = body_shape(load_model(xml), 0.002, refine=4)
    assert link_thickness(shape)[1] == pytest.approx(0.002, abs=shape.spacing)


ALONG_Y = """<mujoco><worldbody>
  <body name="head" pos="0 0 .1"><freejoint/>
    <geom name="head" type="ellipsoid" size=".01 .04 .015"/>
    <body name="tail" pos="0 -.04 0"><joint name="j" axis="0 0 1" range="-30 30"/>
      <geom name="fin" type="box" size=".003 .02 .012" pos="0 -.02 0"/></body>
  </body></worldbody></mujoco>"""


def test_a_fish_modelled_head_along_y_is_turned_to_swim_along_x():
    model, written = load_model(ALONG_Y), describe(mujoco_model(ALONG_Y))
    assert model.forward == (0.0, 1.0, 0.0)
    assert any("forward is the model's +y" in note for note in model.notes)
    facts = describe(model.mj)
    turn = np.array([[0.0, 1, 0], [-1, 0, 0], [0, 0, 1]])  # +y -> +x about z
    np.testing.assert_allclose(facts.link_pos, written.link_pos @ turn.T, atol=1e-15)
    np.testing.assert_allclose(facts.link_rot, turn @ written.link_rot, atol=1e-15)
    assert model.extent[0] == pytest.approx(written.geom_box[:, 1, 1].max()
                                            - written.geom_box[:, 0, 1].min())  # fmt: skip
    np.testing.assert_allclose(model.link_mass, mujoco_model(ALONG_Y).body_mass[1:], rtol=1e-12)


def test_a_planar_swimmer_facing_minus_y_stays_planar_when_turned():
    """The control suites' swimmer: nose at -y, links along +y, slides along x and y."""
    xml = PLANAR.replace('pos="-.05 0 0"><joint', 'pos="0 .05 0"><joint')
    xml = xml.replace('size=".05 .01 .02"/>', 'size=".01 .05 .02"/>').replace(
        'size=".05 .001 .02" pos="-.05 0 0"', 'size=".001 .05 .02" pos="0 .05 0"'
    )
    model = load_model(xml)
    assert model.dim == 2 and model.forward == (0.0, -1.0, 0.0)
    facts = describe(model.mj)
    root = [j for j in model.joints if j.link == 0]
    np.testing.assert_allclose([j.axis for j in root], np.eye(3), atol=1e-12)
    assert facts.link_pos[1, 0] < facts.link_pos[0, 0]  # the tail now trails along -x


def test_the_side_car_can_say_which_way_is_forward():
    assert load_model(PLANAR, forward=(0.0, 1.0)).forward == (0.0, 1.0, 0.0)
    with pytest.raises(ModelError, match=r"forward \[0.0, 1.0, 1.0\] leaves the plane"):
        load_model(PLANAR, forward=(0.0, 1.0, 1.0))


@pytest.mark.parametrize("name", ag.creatures.names())
def test_the_library_faces_plus_x_as_written(name):
    model = ag.creatures.get(name).model
    assert model.forward == (1.0, 0.0, 0.0)
    assert not any(note.startswith("forward") for note in model.notes)


def test_a_planar_model_can_swim_in_3d_held_to_its_plane():
    from aquagait import objectives
    from aquagait.sim import Trajectory

    held, flat = load_model(PLANAR, planar_fluid="3d"), load_model(PLANAR)
    assert (held.dim, held.planar, held.depth, len(held.root_dofs)) == (3, True, None, 3)
    assert (flat.dim, flat.planar) == (2, True)
    np.testing.assert_allclose(held.link_mass, flat.link_mass, rtol=1e-12)
    assert any("held to the plane" in note for note in held.notes)
    with pytest.raises(ValueError, match="held to its plane turns in its plane"):
        objectives.maneuver_goal("pitch-up", 3, planar=True)
    qpos = np.tile(held.qpos0, (2, 1))
    qpos[1, :3] = [0.1, -0.02, 0.3]  # x, y and the heading
    zeros = np.zeros((2, held.nv))
    traj = Trajectory(np.array([0.0, 1.0]), qpos, zeros, zeros, zeros, dt=0.01, fps=1.0)
    np.testing.assert_allclose(objectives.root_displacement(held, traj), [0.1, -0.02, 0.0])
    np.testing.assert_allclose(objectives.rotation_vector(held, traj), [0.0, 0.0, 0.3])


def test_a_tilted_plate_in_a_planar_model_is_thickened_across_the_plane():
    """A box stood on its edge: its thin side lies in the plane (widened), its 2 cm side
    along the depth (left alone); the cut then is 10 cm x 4 mm."""
    plate = 'size=".05 .02 .001" euler="90 0 0"'
    model = load_model(PLANAR.replace('size=".05 .001 .02"', plate), thicken_to=0.004)
    assert any("'fin' 2 -> 4 mm" in note for note in model.notes)
    assert link_volumes(model)[1] == pytest.approx(0.1 * 0.004 * model.depth, rel=2e-3)
