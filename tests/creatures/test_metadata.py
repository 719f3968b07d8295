"""Creature metadata as data: a user's MJCF with and without a side-car, defaults, errors."""

import json
import os

import numpy as np
import pytest

import aquagait as ag
from aquagait.body.mjcf import ModelError
from aquagait.creatures import CreatureError, UnknownCreatureError, defaults, load, resolve, schema
from aquagait.creatures.metadata import parse_metadata
from aquagait.creatures.schema import KEYS
from aquagait.sim.follow import CLEARANCE, room

# A planar three-link swimmer in the style of the reinforcement-learning suites
# (links 0.1 m long; the tail 8 mm wide, the thinnest), limits +-100 deg.
SWIMMER = """<mujoco model="swimmer3">
  <compiler angle="degree"/>
  <custom><numeric name="aquagait_depth" data="0.04"/></custom>
  <default><geom density="1000" contype="0" conaffinity="0"/></default>
  <worldbody>
    <body name="head">
      <joint name="slide_x" type="slide" axis="1 0 0"/>
      <joint name="slide_y" type="slide" axis="0 1 0"/>
      <joint name="rot_z" type="hinge" axis="0 0 1"/>
      <geom type="box" size="0.05 0.01 0.02" pos="-0.05 0 0"/>
      <body name="mid" pos="-0.1 0 0">
        <joint name="joint_1" type="hinge" axis="0 0 1" range="-100 100"/>
        <geom type="box" size="0.05 0.01 0.02" pos="-0.05 0 0"/>
        <body name="tail" pos="-0.1 0 0">
          <joint name="joint_2" type="hinge" axis="0 0 1" range="-100 100"/>
          <geom type="box" size="0.05 0.004 0.02" pos="-0.05 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>"""

# A 3D body: a free torso, a ball-jointed head (30 deg) and a tail whose
# hinge bends further one way than the other (-20..40 deg).
NEWT = """<mujoco model="newt">
  <compiler angle="degree"/>
  <default><geom density="1000" contype="0" conaffinity="0"/></default>
  <worldbody>
    <body name="torso">
      <freejoint name="root"/>
      <geom type="ellipsoid" size="0.04 0.015 0.012"/>
      <body name="head" pos="0.04 0 0">
        <joint name="neck" type="ball" range="0 30"/>
        <geom type="sphere" size="0.012" pos="0.012 0 0"/>
      </body>
      <body name="tail" pos="-0.04 0 0">
        <joint name="tail" type="hinge" axis="0 0 1" range="-20 40"/>
        <geom type="box" size="0.03 0.005 0.012" pos="-0.03 0 0"/>
      </body>
    </body>
  </worldbody>
</mujoco>"""


def write(folder, name, mjcf, sidecar=None):
    """Write ``name.xml`` (and ``name.aquagait.json``: a dict as JSON, a str as is)."""
    path = folder / f"{name}.xml"
    path.write_text(mjcf)
    if sidecar is not None:
        text = sidecar if isinstance(sidecar, str) else json.dumps(sidecar)
        (folder / f"{name}.aquagait.json").write_text(text)
    return path


def assert_default_grid_fits(creature):
    """The default grid: multiples of 16, a few body lengths, and make_scene's clearance."""
    length, h = creature.model.body_length, creature.cell_size
    span = np.asarray(creature.resolution) * h
    assert all(n % 16 == 0 for n in creature.resolution)
    assert span.max() >= 2.5 * length and span.min() >= 1.25 * length
    scene = ag.make_scene(creature, fluid="euler")  # refuses a grid without the clearance
    assert np.all(room(scene.grid, creature.model.bounds[:, : creature.dim]) >= CLEARANCE)


def test_a_planar_swimmer_without_metadata_gets_defaults_from_its_model(tmp_path):
    swimmer = load(write(tmp_path, "swimmer3", SWIMMER))
    assert swimmer.name == "swimmer3" and swimmer.metadata_path is None and swimmer.gaits == {}
    spec = swimmer.gait
    assert spec.dofs == ("joint_1", "joint_2") and spec.free == ("amplitude", "phase")
    assert (spec.period, spec.offset) == (1.0, 0.0)
    assert spec.bounds == {"amplitude": (0.0, np.deg2rad(100)), "phase": (-np.pi, np.pi)}
    # a travelling wave: 0.3 rad, 1 rad of lag from joint to joint
    np.testing.assert_allclose(swimmer.default_gait, [0.3, 0.3, 0.0, -1.0])
    # the tail (8 mm, measured 8 mm: the sampling lattice has a sample on its mid-plane) is
    # two cells of 8 / 2 = 4 mm thick, a mantissa the cell size is rounded down to
    assert swimmer.cell_size == 0.004
    assert_default_grid_fits(swimmer)
    assert swimmer.energy_bound == pytest.approx(5 * swimmer.model.mass * 0.3**2)
    assert swimmer.energy_weight == 1.0  # paper §4
    assert swimmer.turn_limit == pytest.approx(np.pi / 2)  # a manoeuvre rewards up to 90 degrees
    assert (swimmer.natural_frequency, swimmer.damping_ratio) == (100.0, 1.5)
    notes = "\n".join(swimmer.notes)
    for words in ("no metadata", "2 hinges", "thinnest link (tail", "travelling wave", "energy"):
        assert words in notes
    scene = ag.make_scene(swimmer)
    traj = ag.rollout(scene, ag.init_state(scene), swimmer.policy(), 1.0)
    swing = np.ptp(traj.qpos[:, swimmer.model.actuated_dofs], axis=0)
    assert np.all(swing > 0.4) and np.all(swing < 2 * 0.3 + 0.1)  # it follows the 0.3 rad sines


def test_a_ball_joint_gets_three_axes_and_an_asymmetric_limit_its_smaller_side(tmp_path):
    newt = load(write(tmp_path, "newt", NEWT))
    spec = newt.gait
    assert spec.dofs == ("neck:x", "neck:y", "neck:z", "tail")
    assert spec.bounds["amplitude[neck:y]"] == pytest.approx((0.0, np.deg2rad(30)))
    # -20..40 deg about an offset of 0: a sine swings as far down as up, so 20 deg
    assert spec.bounds["amplitude[tail]"] == pytest.approx((0.0, np.deg2rad(20)))
    assert newt.gait.limit_violations(newt.default_gait, *newt.gait_limits()) == []
    phase = spec.unpack(newt.default_gait).phase
    np.testing.assert_allclose(phase, [0, 0, 0, -1.0])  # the ball's axes in phase
    assert "1 hinge and 1 ball joint" in "\n".join(newt.notes)
    assert_default_grid_fits(newt)
    traj = ag.rollout(ag.make_scene(newt), ag.init_state(ag.make_scene(newt)), newt.policy(), 0.5)
    assert np.all(np.isfinite(traj.qpos))


def test_a_free_offset_widens_the_amplitude_to_the_half_range():
    """With the offset free, (amplitude, offset) may use the whole range: the box around it."""
    newt = ag.load_model(NEWT)
    bounds = defaults.amplitude_bounds(newt, ("tail",), free=("amplitude", "offset"))
    assert bounds["amplitude"] == pytest.approx((0.0, np.deg2rad(30)))
    assert bounds["offset"] == pytest.approx((np.deg2rad(-20), np.deg2rad(40)))
    with pytest.raises(ValueError, match="do not contain the offset 1 rad, so no sine"):
        defaults.amplitude_bounds(newt, ("tail",), offset=1.0)  # 57 deg: beyond 40


def test_a_sidecar_fills_what_it_states_and_defaults_the_rest(tmp_path):
    sidecar = {
        "description": "a swimmer that folds",
        "gait": {
            "free": ["amplitude", "phase", "period"],
            "shared": ["amplitude", "period"],
            "mirror": [["joint_2", "joint_1", -1]],
            "bounds": {"amplitude": [0, 0.5], "period": [0.5, 1.5]},
        },
        "grid": {"cell_size": 0.004},
        "energy_bound": 0.2,
        "energy_weight": 20,
        "turn_limit": 0.4,
        "gaits": {
            "straight": {
                "params": {"amplitude": 0.4, "phase[joint_1]": 0.5, "period": 0.8},
                "provenance": {"method": "optimized", "seed": 3, "wall_time": 120.0},
            },
            "slow": {"params": [0.2, 0.0, 1.2]},
        },
    }
    folder = write(tmp_path, "swimmer3", SWIMMER, sidecar)
    swimmer = load(folder)
    assert swimmer.metadata_path == tmp_path / "swimmer3.aquagait.json"
    assert swimmer.description == "a swimmer that folds"
    assert swimmer.gait.names == ("amplitude", "phase[joint_1]", "period")
    # a kind's bound replaces the per-DOF defaults from the limits; phase keeps its default
    assert swimmer.gait.bounds == {
        "amplitude": (0.0, 0.5),
        "phase": (-np.pi, np.pi),
        "period": (0.5, 1.5),
    }
    np.testing.assert_array_equal(swimmer.default_gait, [0.4, 0.5, 0.8])
    np.testing.assert_array_equal(swimmer.gaits["slow"].params, [0.2, 0.0, 1.2])
    assert swimmer.gaits["straight"].provenance["seed"] == 3
    assert swimmer.cell_size == 0.004 and swimmer.energy_bound == 0.2
    assert swimmer.energy_weight == 20.0 and swimmer.turn_limit == 0.4
    assert_default_grid_fits(swimmer)  # the resolution from the stated cell size
    assert any(n.startswith("grid ") for n in swimmer.notes)
    assert not any("energy bound" in n for n in swimmer.notes)


def test_loads_are_cached_by_path_and_modification_time(tmp_path):
    path = write(tmp_path, "swimmer3", SWIMMER)
    first = load(path)
    assert load(str(path)) is first and resolve(path) is first
    sidecar = tmp_path / "swimmer3.aquagait.json"
    sidecar.write_text(json.dumps({"energy_bound": 0.3}))
    os.utime(sidecar, ns=(path.stat().st_mtime_ns + 10**9,) * 2)
    again = load(path)
    assert again is not first and again.energy_bound == 0.3
    assert load(sidecar) is again  # the side-car's path finds its MJCF


SHAPES = [
    ("{", "not JSON: Expecting property name"),
    ("[1, 2]", "the top level: must be a JSON object"),
    ({"descripton": "x"}, "unknown key(s) 'descripton'; known: description, gait, pd, grid"),
    ({"gait": {"speed": 2}}, "gait: unknown key(s) 'speed'; known: dofs, free, shared"),
    ({"gait": {"free": ["amplitude", "speed"]}}, "gait.free[1]: 'speed' is not one of amplitude"),
    ({"gait": {"mirror": [["joint_2", "joint_1", 2]]}}, "gait.mirror[0][2]: the sign must be +1"),
    ({"gait": {"mirror": [["joint_2"]]}}, "gait.mirror[0]: must be a list [dof, source dof, sign"),
    ({"gait": {"bounds": {"amplitude": [1, 0]}}}, "gait.bounds.amplitude: lower 1 must be below"),
    ({"gait": {"bounds": {"wobble": [0, 1]}}}, "gait.bounds.wobble: bounds are named 'kind' or"),
    ({"gait": {"period": 0}}, "gait.period: must be > 0 s, got 0"),
    ({"pd": {"natural_frequency": -3}}, "pd.natural_frequency: must be > 0 rad/s, got -3"),
    ({"pd": {"damping_ratio": True}}, "pd.damping_ratio: must be a number, got a boolean"),
    ({"grid": {"resolution": [64, 32.5]}}, "grid.resolution: must be 2 or 3 whole numbers"),
    ({"grid": {"cell_size": "1 cm"}}, 'grid.cell_size: must be a number [m], got a string "1 cm"'),
    ({"energy_bound": float("nan")}, "energy_bound: must be a finite number [J], got nan"),
    ({"energy_weight": -1}, "energy_weight: must be >= 0, got -1"),
    ({"turn_limit": 0}, "turn_limit: must be > 0 rad, got 0"),
    ({"gaits": {"straight": {"params": [0.1, "a"]}}}, "gaits.straight.params[1]: must be a number"),
    ({"gaits": {"turn left": 3}}, 'gaits["turn left"]: must be a JSON object'),
    ({"gaits": {"straight": {}}}, "gaits.straight: needs 'params'"),
    ({"view": "below"}, "view: must be one of 'follow', 'side', 'top', 'side-above'"),
]


@pytest.mark.parametrize("sidecar, message", SHAPES, ids=[m.split(":")[0] for _, m in SHAPES])
def test_metadata_of_the_wrong_shape_names_the_entry(tmp_path, sidecar, message):
    path = write(tmp_path, "swimmer3", SWIMMER, sidecar)
    with pytest.raises(CreatureError) as err:
        load(path)
    assert str(err.value).startswith(str(tmp_path / "swimmer3.aquagait.json"))
    assert message in str(err.value)


MISFITS = [
    ({"gait": {"dofs": ["joint_1", "j9"]}}, "gait.dofs: j9 is not an actuated DOF of"),
    ({"gait": {"mirror": [["joint_2", "j9", 1]]}}, "gait.mirror[0][1]: 'j9' is not a gait DOF"),
    ({"gait": {"bounds": {"amplitude[j9]": [0, 1]}}}, "gait.bounds[\"amplitude[j9]\"]: 'j9' is"),
    ({"gait": {"groups": [["joint_1"]]}}, "gait: gait groups (('joint_1',),) must list every"),
    ({"grid": {"resolution": [64, 32, 32]}}, "grid.resolution: [64, 32, 32] for a 2D model"),
    # the centre of mass is 12.5 cm behind the snout (masses 2 : 2 : 0.8), so the grid
    # centred on it spans 2 x 17.5 cm + 2 x 8 cells along x, 2 x 1 cm + 2 x 8 across
    ({"grid": {"resolution": [32, 16], "cell_size": 0.01}}, "use at least [51, 18], or a"),
    ({"gaits": {"straight": {"params": [0.1, 0.2, 0.3]}}}, "params: 3 numbers; the gait has 4"),
    (
        {"gaits": {"straight": {"params": {"amplitude[joint_1]": 0.1, "amp[joint_2]": 0.1}}}},
        "missing amplitude[joint_2], phase[joint_1], phase[joint_2]; unknown amp[joint_2]",
    ),
    (
        {"gaits": {"straight": {"params": [2.0, 0.1, 0.0, 0.0]}}},
        "the gait is outside its bounds: amplitude[joint_1] = 2 outside [0, 1.74533]",
    ),
    (
        {
            "gait": {"bounds": {"amplitude": [0, 2]}},
            "gaits": {"straight": {"params": [1.8, 0.1, 0.0, 0.0]}},
        },
        "the gait leaves the joint limits: joint_1: swings over [-1.8, 1.8] rad",
    ),
]


@pytest.mark.parametrize("sidecar, message", MISFITS, ids=[m[:24] for _, m in MISFITS])
def test_metadata_that_does_not_fit_the_model_says_what_would(tmp_path, sidecar, message):
    with pytest.raises(CreatureError, match="swimmer3.aquagait.json: ") as err:
        load(write(tmp_path, "swimmer3", SWIMMER, sidecar))
    assert message in str(err.value)


def test_the_eels_metadata_on_another_model_is_refused_with_its_dofs(tmp_path):
    eel = (ag.creatures.get("eel2d").metadata_path).read_text()
    with pytest.raises(CreatureError) as err:
        load(write(tmp_path, "swimmer3", SWIMMER, eel))
    assert "gait.dofs: j1, j2, j3, j4 are not actuated DOFs of" in str(err.value)
    assert "its actuated DOFs are joint_1, joint_2" in str(err.value)


def test_every_problem_is_listed_at_once(tmp_path):
    sidecar = {"descripton": 1, "pd": {"natural_frequency": 0}, "grid": {"cell_size": -1}}
    with pytest.raises(CreatureError) as err:
        load(write(tmp_path, "swimmer3", SWIMMER, sidecar))
    lines = str(err.value).splitlines()
    assert lines[0].endswith("swimmer3.aquagait.json: 3 problems:")
    assert [line.split(":")[0].strip() for line in lines[1:]] == [
        "the top level",
        "pd.natural_frequency",
        "grid.cell_size",
    ]


def test_files_that_are_not_creatures(tmp_path):
    with pytest.raises(CreatureError, match="nothing.xml does not exist: give the path of an"):
        load(tmp_path / "nothing.xml")
    with pytest.raises(CreatureError, match="is a directory"):
        load(tmp_path)
    notxml = tmp_path / "notes.xml"
    notxml.write_text("swimmer, three links")
    with pytest.raises(ModelError):  # the loader's own error, passed through
        load(notxml)
    with pytest.raises(UnknownCreatureError, match="or give the path of an MJCF file"):
        resolve("swimmer3")


def test_a_metadata_object_can_be_checked_without_a_file():
    with pytest.raises(CreatureError, match=r"^metadata: gait.free\[0\]: 'size' is not one of"):
        parse_metadata({"gait": {"free": ["size"]}})
    assert parse_metadata({}).gait == {}


def test_the_formats_documented_example_is_valid_metadata():
    doc = ag.creatures.metadata.__doc__
    start = doc.index("\n    {\n") + 1
    example = json.loads(doc[start : doc.index("\n    }\n", start) + 6])
    meta = parse_metadata(example)
    assert meta.gait["mirror"] == (("leg_r", "leg_l", -1.0),)
    assert meta.gaits["straight"]["provenance"]["seed"] == 3
    assert set(example) == set(KEYS[""])  # every entry shown
    assert set(example["gait"]) | {"amplitude", "phase"} == set(KEYS["gait"])  # these are free


def test_a_free_offset_gets_its_bounds_from_the_limits_whatever_the_amplitudes(tmp_path):
    sidecar = {"gait": {"free": ["amplitude", "offset"], "bounds": {"amplitude": [0, 0.2]}}}
    newt = load(write(tmp_path, "newt", NEWT, sidecar))
    assert newt.gait.names[-1] == "offset[tail]"
    assert newt.gait.bounds["offset[tail]"] == pytest.approx((np.deg2rad(-20), np.deg2rad(40)))
    assert newt.gait.bounds["amplitude"] == (0.0, 0.2)
    fixed = load(write(tmp_path, "fixed", NEWT, {"gait": {"free": ["phase"], "amplitude": 0.1}}))
    assert fixed.gait.bounds == {"phase": (-np.pi, np.pi)}  # nothing for a fixed amplitude


def test_the_sidecars_views_are_the_ones_the_pictures_draw(tmp_path):
    from aquagait.viz.camera import VIEWS

    assert set(VIEWS) == set(schema.VIEWS)
    assert load(write(tmp_path, "swimmer3", SWIMMER, {"view": "top"})).view == "top"
    assert load(write(tmp_path, "swimmer3", SWIMMER, {})).view == "follow"
    assert ag.creatures.get("manta").view == "front-above"
