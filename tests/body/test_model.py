"""Loading and checking MJCF creatures: masses from geometry, metadata, and clear errors."""

import pickle
import re
from pathlib import Path

import numpy as np
import pytest

import aquagait
from aquagait.body import ModelError, load_model
from aquagait.body.geometry import link_volumes

CREATURES = Path(aquagait.__file__).resolve().parent / "creatures"
BAD = sorted((Path(__file__).parent / "bad_models").glob("*.xml"))
RHO = 1000.0
FLOAT32 = 1e-6  # MuJoCo stores mesh vertices in single precision
PLANAR_ROOT = (
    '<joint name="x" type="slide" axis="1 0 0"/><joint name="y" type="slide" axis="0 1 0"/>'
    '<joint name="theta" type="hinge" axis="0 0 1"/>'
)


def rigid(geom: str, root="<freejoint/>", custom="", asset="") -> str:
    return (
        f"<mujoco>{custom}<asset>{asset}</asset><worldbody><body name='b'>{root}"
        f"<geom {geom} density='{RHO}'/></body></worldbody></mujoco>"
    )


def planar(geom: str, depth=0.04, asset="") -> str:
    custom = f"<custom><numeric name='aquagait_depth' data='{depth}'/></custom>"
    return rigid(geom, PLANAR_ROOT, custom, asset)


@pytest.mark.parametrize("path", BAD, ids=lambda p: p.stem)
def test_each_bad_model_gets_its_clear_error(path):
    expected = re.search(r"<!-- expect: (.*?) -->", path.read_text()).group(1)
    with pytest.raises(ModelError) as err:
        load_model(path)
    message = str(err.value)
    assert message.startswith(str(path)), "the message names the file"
    assert expected in message


def test_the_bad_corpus_covers_every_check():
    assert len(BAD) >= 25  # what MuJoCo reads (masses, ranges, 3D shapes in a plane) loads now


CUT = Path(__file__).parent / "models" / "planar_cut"


@pytest.mark.parametrize(
    "name, area",
    [
        ("planar_box_wrong_depth", 0.2 * 0.04),  # a slab 10 cm thick in a 4 cm prism
        ("planar_capsule", 0.2 * 0.04 + np.pi * 0.02**2),  # a stadium
        ("planar_mesh_not_prism", 0.2 * 0.1 / 2),  # the wedge's cut at z = 0: a triangle
        ("planar_tilted_cylinder", 0.04 * 0.04),  # lying in the plane: a square
        ("planar_no_depth", 0.2 * 0.04),  # a box prism already: its thickness is the depth
    ],
)
def test_a_planar_model_of_3d_shapes_swims_their_cut_by_its_plane(name, area):
    model = load_model(CUT / f"{name}.xml")
    assert (model.dim, model.depth) == (2, pytest.approx(0.04))
    assert link_volumes(model)[0] == pytest.approx(area * 0.04, rel=2e-3)  # 128-gon outlines
    said = "planar with 3D shapes" if name != "planar_no_depth" else "prism depth 40 mm"
    assert any(note.startswith(said) for note in model.notes)


def test_missing_file_is_named():
    with pytest.raises(ModelError, match=r"nowhere\.xml: no such MJCF file"):
        load_model("nowhere.xml")


@pytest.mark.parametrize(
    "geom, mass",
    [
        ("type='sphere' size='.05'", RHO * 4 / 3 * np.pi * 0.05**3),
        ("type='box' size='.1 .02 .03'", RHO * 8 * 0.1 * 0.02 * 0.03),
        ("type='ellipsoid' size='.1 .02 .03'", RHO * 4 / 3 * np.pi * 0.1 * 0.02 * 0.03),
        ("type='cylinder' size='.02 .1'", RHO * np.pi * 0.02**2 * 0.2),
        ("type='capsule' size='.02 .1'", RHO * (np.pi * 0.02**2 * 0.2 + 4 / 3 * np.pi * 0.02**3)),
    ],
    ids=["sphere", "box", "ellipsoid", "cylinder", "capsule"],
)
def test_3d_mass_is_density_times_volume(geom, mass):
    model = load_model(rigid(geom))
    assert model.dim == 3 and model.depth is None
    assert model.mass == pytest.approx(mass, rel=1e-9)


def test_3d_mesh_mass_is_density_times_hull_volume():
    tetra = "<mesh name='t' vertex='0 0 0  .1 0 0  0 .1 0  0 0 .1'/>"
    model = load_model(rigid("type='mesh' mesh='t'", asset=tetra))
    assert model.mass == pytest.approx(RHO * 0.1**3 / 6, rel=FLOAT32)


@pytest.mark.parametrize(
    "geom, area",
    [
        ("type='box' size='.1 .02 .02' euler='0 0 30'", 4 * 0.1 * 0.02),
        ("type='cylinder' size='.03 .02'", np.pi * 0.03**2),
        ("type='mesh' mesh='tri'", 0.5 * 0.2 * 0.1),
    ],
    ids=["box", "cylinder", "mesh"],
)
def test_2d_mass_is_density_times_area_times_depth(geom, area):
    tri = "<mesh name='tri' vertex='0 0 -.02  0 0 .02  .2 0 -.02  .2 0 .02  0 .1 -.02  0 .1 .02'/>"
    model = load_model(planar(geom, asset=tri))
    assert model.dim == 2 and model.depth == 0.04
    assert model.mass == pytest.approx(RHO * area * 0.04, rel=FLOAT32 if "mesh" in geom else 1e-9)


def test_eel2d_is_planar_with_four_limited_yaw_joints():
    eel = load_model(CREATURES / "eel2d.xml")
    assert (eel.dim, eel.depth, eel.nq, eel.nv) == (2, 0.04, 7, 7)
    assert eel.dof_names == ("root_x", "root_y", "root_theta", "j1", "j2", "j3", "j4")
    np.testing.assert_array_equal(eel.root_dofs, [0, 1, 2])
    np.testing.assert_array_equal(eel.actuated_dofs, [3, 4, 5, 6])
    np.testing.assert_allclose(eel.upper, np.deg2rad(45))
    np.testing.assert_allclose(eel.lower, -np.deg2rad(45))
    assert eel.body_length == pytest.approx(0.5, rel=1e-6)
    # a trunk link is a 0.1 m x 3.5 cm x 4 cm prism: its mass is exact
    assert eel.link_mass[eel.links.index("trunk1")] == pytest.approx(RHO * 0.1 * 0.035 * 0.04)


def test_ball_joint_dofs_and_limits(snake):
    assert snake.dim == 3
    assert snake.dof_names[:9] == ("root:x", "root:y", "root:z", "root:rx", "root:ry", "root:rz",
                                   "ball:x", "ball:y", "ball:z")  # fmt: skip
    assert snake.joint("ball").kind == "ball" and snake.joint("ball").nq == 4
    np.testing.assert_allclose(snake.upper[:3], np.deg2rad(60))
    assert snake.dof("h2") == 10


def test_unknown_joint_and_dof_list_the_known_ones(snake):
    with pytest.raises(KeyError, match="joints: ball, h1, h2"):
        snake.joint("elbow")
    with pytest.raises(KeyError, match="DOFs: root:x"):
        snake.dof("elbow")


def test_path_and_string_give_the_same_model_and_models_pickle():
    path = CREATURES / "fish.xml"
    from_path, from_text = load_model(path), load_model(path.read_text())
    assert from_text.source == "<string>" and from_path.source == str(path)
    assert from_path.mass == from_text.mass and from_path.dof_names == from_text.dof_names
    copy = pickle.loads(pickle.dumps(from_path))
    assert copy.mass == from_path.mass and copy.mj.nbody == from_path.mj.nbody


def test_extent_and_body_length_of_a_box():
    model = load_model(rigid("type='box' size='.3 .1 .05'"))
    np.testing.assert_allclose(model.extent, [0.6, 0.2, 0.1])
    assert model.body_length == pytest.approx(0.6)
