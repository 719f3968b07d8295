"""MJCF written for other MuJoCo projects: what the loader ignores (one note per kind), what
it refuses (every problem at once, each with its fix), and bad input (a clear error)."""

import pickle
from pathlib import Path

import mujoco
import numpy as np
import pytest

import aquagait
from aquagait.body import Dynamics, ModelError, load_model
from aquagait.body.dynamics import compile_mjcf, describe
from aquagait.body.geometry import link_volumes

MODELS = Path(__file__).parent / "models"
BAD = Path(__file__).parent / "bad_models"
CREATURES = Path(aquagait.__file__).resolve().parent / "creatures"
FLOAT32 = 1e-6  # MuJoCo stores mesh vertices in single precision

# The swimmer of models/swimmer.xml as aquagait's own files would write it: the body alone.
BARE_SWIMMER = """<mujoco><custom><numeric name="aquagait_depth" data="0.02"/></custom>
  <default><geom type="box" density="1000"/></default>
  <worldbody><body name="head">
    <joint type="slide" axis="1 0 0"/><joint type="slide" axis="0 1 0"/>
    <joint type="hinge" axis="0 0 1"/><geom size=".05 .015 .01"/>
    <body pos="-.05 0 0"><joint type="hinge" axis="0 0 1" range="-100 100"/>
      <geom pos="-.05 0 0" size=".05 .012 .01"/>
      <body pos="-.1 0 0"><joint type="hinge" axis="0 0 1" range="-100 100"/>
        <geom pos="-.05 0 0" size=".05 .008 .01"/></body></body>
  </body></worldbody></mujoco>"""


def heads(notes):
    """Each note up to its reason: what was ignored."""
    return [note.split(": ")[0] for note in notes]


def test_a_control_suite_swimmer_loads_with_one_note_per_kind_of_scenery():
    swimmer = load_model(MODELS / "swimmer.xml")
    assert heads(swimmer.notes) == [
        "ignored 2 geoms fixed to the world (plane 'ground', sphere 'target')",
        "ignored 2 lights ('target_light', 'light_1')",
        "ignored 1 camera ('tracking')",
        "ignored 2 textures (skybox 'skybox', 2d 'grid')",
        "ignored 3 materials ('grid', 'self', 'target')",
        "ignored 2 actuators ('motor_0', 'motor_1')",
        "ignored 2 sensors ('nose_pos', 'bend_0')",
        "ignored 1 contact pair or exclusion (unnamed)",
        "ignored 1 tendon ('bend')",
        "ignored 1 keyframe ('bent')",
        "ignored <visual>",
        "ignored <option> timestep, density, viscosity, <flag>",
        "ignored joint armature, damping (on default class 'swimmer')",  # the 'free' class's are 0
    ]
    assert (swimmer.dim, swimmer.depth) == (2, 0.02)
    assert swimmer.dof_names == ("rootx", "rooty", "rootz", "joint_0", "joint_1")
    # box prisms: density x area x depth, exactly
    np.testing.assert_allclose(
        swimmer.link_mass, 1000 * 0.02 * 0.1 * np.array([0.03, 0.024, 0.016])
    )
    np.testing.assert_allclose(swimmer.upper, np.deg2rad(100))


def test_what_is_ignored_leaves_the_same_body_as_the_bare_model():
    swimmer, bare = load_model(MODELS / "swimmer.xml"), load_model(BARE_SWIMMER)
    assert bare.notes == ()
    mj = swimmer.mj
    assert (mj.nu, mj.nsensor, mj.ntendon, mj.nkey, mj.nlight, mj.ncam, mj.nmat) == (0,) * 7
    assert mj.ngeom == 3 and not mj.dof_armature.any() and not mj.dof_damping.any()
    q = swimmer.qpos0 + np.array([0.1, -0.2, 0.3, 0.4, -0.5])
    np.testing.assert_array_equal(
        Dynamics(swimmer.mj).mass_matrix(q), Dynamics(bare.mj).mass_matrix(q)
    )  # armature would have added to the diagonal


def test_the_swimmer_as_written_for_another_project_swims_its_cut_by_the_plane():
    """Capsules, an ellipsoid head and no depth: each geom becomes its cross-section in the
    plane of motion, a prism whose depth keeps the body's 3D volume; masses stay MuJoCo's."""
    swimmer = load_model(MODELS / "swimmer_as_written.xml")
    r, length = 0.01, 0.1
    head = np.pi * 0.04 * 0.02  # the ellipsoid's cut: an ellipse
    segment = 2 * r * length + np.pi * r**2  # a capsule lying in the plane: a stadium
    volumes = np.array([4 / 3 * np.pi * 0.04 * 0.02 * 0.017,
                        *[np.pi * r**2 * (length + 4 / 3 * r)] * 2])  # fmt: skip
    depth = volumes.sum() / (head + 2 * segment)
    assert swimmer.dim == 2
    assert swimmer.depth == pytest.approx(depth, rel=2e-3)  # the outlines are 128-gons
    np.testing.assert_allclose(swimmer.link_mass, 1000 * volumes, rtol=1e-9)
    np.testing.assert_allclose(link_volumes(swimmer), swimmer.depth * np.array(
        [head, segment, segment]), rtol=2e-3)  # fmt: skip
    assert link_volumes(swimmer).sum() == pytest.approx(volumes.sum(), rel=FLOAT32)
    assert any(n.startswith("planar with 3D shapes") for n in swimmer.notes)


def test_a_3d_model_with_ball_joints_and_a_mesh_file_loads_from_any_directory(
    tmp_path, monkeypatch
):
    monkeypatch.chdir(tmp_path)  # the mesh resolves relative to the file, not the caller
    scene = load_model(MODELS / "turtle" / "scene.xml")
    alone = load_model(MODELS / "turtle" / "turtle.xml")
    assert scene.dim == 3 and scene.joint("left").kind == "ball"
    assert scene.dof_names[6:] == ("neck", "left:x", "left:y", "left:z", "right:x", "right:y",
                                   "right:z")  # fmt: skip
    np.testing.assert_allclose(scene.upper[1:], np.deg2rad(60))
    flipper = scene.link_mass[scene.links.index("left")]
    assert flipper == pytest.approx(1000 * 0.1 * 0.06 * 0.01, rel=FLOAT32)  # the OBJ's plate
    neck = 1000 * np.pi * 0.015**2 * (0.08 + 4 / 3 * 0.015)  # the fromto capsule
    assert scene.link_mass[scene.links.index("neck")] == pytest.approx(neck, rel=1e-9)
    np.testing.assert_array_equal(scene.link_mass, alone.link_mass)
    reference = mujoco.MjModel.from_xml_path(str(MODELS / "turtle" / "scene.xml"))
    np.testing.assert_array_equal(scene.link_mass, reference.body_mass[1:])
    assert heads(scene.notes) == [
        "ignored 1 geom fixed to the world (plane 'floor')",
        "ignored 1 light (unnamed)",
        "ignored 2 textures (skybox, 2d 'groundplane')",
        "ignored 1 material ('groundplane')",
        "ignored 1 actuator ('neck')",
        "ignored <statistic>",
        "ignored joint armature, damping (on default class 'turtle')",
    ]


def test_a_mesh_declared_in_a_nested_include_resolves_as_mujoco_resolves_it(tmp_path):
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "fin.obj").write_text(
        (MODELS / "turtle" / "assets" / "flipper.obj").read_text()
    )
    (tmp_path / "parts" / "fin.xml").write_text(
        '<mujoco><asset><mesh name="fin" file="fin.obj"/></asset></mujoco>'
    )
    main = tmp_path / "fish.xml"
    main.write_text(
        '<mujoco><include file="parts/fin.xml"/><worldbody><body><freejoint/>'
        '<geom type="mesh" mesh="fin" density="500"/></body></worldbody></mujoco>'
    )
    reference = mujoco.MjModel.from_xml_path(str(main))
    np.testing.assert_array_equal(load_model(main).link_mass, reference.body_mass[1:])


def test_a_body_fixed_beside_the_creature_is_scenery_but_a_fixed_creature_is_refused():
    target = "<body name='target' pos='1 0 0'><geom type='sphere' size='.1'/></body>"
    fish = "<body name='fish'><freejoint/><geom type='sphere' size='.05' density='1000'/></body>"
    model = load_model(f"<mujoco><worldbody>{target}{fish}</worldbody></mujoco>")
    assert heads(model.notes) == ["ignored 1 body fixed to the world ('target')"]
    fixed = fish.replace("<freejoint/>", "")
    with pytest.raises(ModelError, match="<string>: no root joint: link 'fish' is fixed"):
        load_model(f"<mujoco><worldbody>{fixed}</worldbody></mujoco>")


def test_a_model_with_five_problems_gets_all_five_in_one_message():
    path = MODELS / "five_problems.xml"
    with pytest.raises(ModelError) as err:
        load_model(path)
    expected = [
        "<equality> holds 1 constraint(s) (unnamed); aquagait solves no constraints between "
        "links: remove it (to move joints together, give them shared gait parameters)",
        "geom 'head' in body 'head' has density 'heavy'; it must be a number >= 0 [kg/m^3], "
        'e.g. density="1000" (water)',
        "geom 'keel' in body 'trunk' is a plane; allowed: capsule, box, sphere, ellipsoid, "
        "cylinder, mesh",
        "body 'spacer' has no <geom>; every link needs a shape for the water to push on (an "
        "<inertial> gives it mass, not a shape): give it a geom",
        "joint 'slider' in link 'tail' is a slide joint; below the root only hinge and ball "
        "joints are allowed: make it a hinge or a ball, or remove it",
    ]
    assert err.value.problems == expected
    assert str(err.value) == f"{path} has 5 problems:\n" + "\n".join(f"  - {p}" for p in expected)
    assert err.value.source == str(path)


@pytest.mark.parametrize(
    "name, write, expected",
    [
        ("missing.xml", None, "missing.xml: no such MJCF file"),
        ("folder", "dir", "folder: is not a file; give the path of an MJCF (.xml) file"),
        ("picture.png", b"\x89PNG\r\n\x1a\n\x00\xff", "picture.png: is not a text file"),
        ("mesh.obj", "v 0 0 0\nf 1 1 1\n", "mesh.obj: is not well-formed XML: syntax error"),
        ("robot.urdf", "<robot name='r'/>", "robot.urdf: the root element is <robot>; an MJCF"),
        ("empty.xml", "", "empty.xml: is not well-formed XML: no element found"),
    ],
    ids=["missing", "directory", "binary", "not-xml", "urdf", "empty"],
)
def test_bad_files_get_a_clear_error(tmp_path, name, write, expected):
    path = tmp_path / name
    if write == "dir":
        path.mkdir()
    elif isinstance(write, bytes):
        path.write_bytes(write)
    elif write is not None:
        path.write_text(write)
    with pytest.raises(ModelError) as err:
        load_model(path)
    assert str(err.value).startswith(str(tmp_path / expected))


@pytest.mark.parametrize(
    "included, expected",
    [
        (None, '<include file="part.xml">: no such file (looked in'),
        ("not xml <", "the included file {dir}/part.xml is not well-formed XML: syntax error"),
        ("<robot/>", "the included file {dir}/part.xml starts with <robot>, not <mujoco>"),
        (
            "<mujoco>\n<asset>\n<mesh name='m' file='nowhere.obj'/>\n</asset>\n</mujoco>",
            "MuJoCo cannot compile it: Error: Error opening file '{dir}/nowhere.obj'",
        ),
    ],
    ids=["missing", "not-xml", "not-mjcf", "mujoco-error"],
)
def test_bad_includes_get_a_clear_error(tmp_path, included, expected):
    if included is not None:
        (tmp_path / "part.xml").write_text(included)
    main = tmp_path / "main.xml"
    main.write_text(
        '<mujoco><include file="part.xml"/><worldbody><body><freejoint/>'
        "<geom size='.1' density='1000'/></body></worldbody></mujoco>"
    )
    with pytest.raises(ModelError) as err:
        load_model(main)
    assert str(err.value).startswith(f"{main}: " + expected.format(dir=tmp_path))


def test_mujocos_own_error_names_the_file_and_line_it_came_from(tmp_path):
    (tmp_path / "part.xml").write_text(
        "<mujoco>\n  <worldbody>\n    <body><freejoint/>\n"
        "      <geom size='.1' density='1000' wobble='3'/>\n    </body>\n  </worldbody>\n</mujoco>"
    )
    main = tmp_path / "main.xml"
    main.write_text('<mujoco>\n  <include file="part.xml"/>\n</mujoco>')
    with pytest.raises(ModelError) as err:
        load_model(main)
    assert str(err.value) == (
        f"{main}: MuJoCo cannot compile it: XML Error: Schema violation: unrecognized "
        f"attribute: 'wobble'; Element 'geom', line 4 of {tmp_path / 'part.xml'}"
    )


@pytest.mark.parametrize("path", sorted(CREATURES.glob("*.xml")), ids=lambda p: p.stem)
def test_library_creatures_load_as_mujoco_loads_their_files_with_no_notes(path):
    """No notes but the one that names a visual body's geoms (only drawn); the bounds
    are those of the geoms with mass, as MuJoCo places them."""
    model = load_model(path)
    facts = describe(compile_mjcf(path=path))  # MuJoCo reading the file itself
    drawn = {v.name for link in model.visuals for v in link}
    assert len(model.notes) == (1 if drawn else 0)
    assert all(n.startswith(f"{len(drawn)} geoms (") and "only drawn" in n for n in model.notes)
    np.testing.assert_array_equal(model.link_mass, facts.link_mass)
    np.testing.assert_array_equal(model.qpos0, facts.qpos0)
    massive = np.array([name not in drawn for name in facts.geom_names])
    np.testing.assert_array_equal(model.bounds[0], facts.geom_box[massive, 0].min(axis=0))
    np.testing.assert_array_equal(model.bounds[1], facts.geom_box[massive, 1].max(axis=0))


def test_model_errors_pickle_and_one_problem_reads_as_one_line():
    one = ModelError("fish.xml", ["no <worldbody>"])
    assert str(one) == "fish.xml: no <worldbody>" and one.problems == ["no <worldbody>"]
    two = pickle.loads(pickle.dumps(ModelError("fish.xml", ["a", "b"])))
    assert str(two) == "fish.xml has 2 problems:\n  - a\n  - b" and two.source == "fish.xml"
    assert isinstance(two, ValueError)


def test_gravity_passive_terms_on_named_joints_and_a_floor_in_a_frame_are_noted():
    xml = """<mujoco><option gravity="0 0 -9.81"/><worldbody>
      <frame pos="0 0 -1"><geom name="seabed" type="box" size="1 1 .1"/></frame>
      <body name="fish"><freejoint/><geom type="sphere" size=".05" density="1000"/>
        <body name="tail" pos="-.1 0 0">
          <joint name="j" type="hinge" axis="0 0 1" range="-30 30" frictionloss=".1"/>
          <geom type="box" size=".05 .005 .04" pos="-.05 0 0" density="1000"/></body>
      </body></worldbody></mujoco>"""
    assert heads(load_model(xml).notes) == [
        "ignored 1 geom fixed to the world (box 'seabed')",
        "ignored <option> gravity",
        "ignored joint frictionloss (on 'j')",
    ]
    still = xml.replace('-9.81"', '0"').replace(' frictionloss=".1"', "")
    assert heads(load_model(still).notes) == ["ignored 1 geom fixed to the world (box 'seabed')"]
