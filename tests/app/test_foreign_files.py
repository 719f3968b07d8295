"""Files written for other MuJoCo projects, end to end: check, swim (it moves head first) and
a one-generation search, without edits (issue 31).

Two small models in the control suites' styles, written for these tests: a 3D fish modelled
head along +y with its mass on a hidden box, massless shape geoms, ranges switched off, a
joint bounded only by its position servo and 2 mm fins; and a planar swimmer of capsules
and an ellipsoid head, 5 cm above a floor, its nose at -y, swum in the 2D fluid (its cut by
the plane) and, by its side-car, in the 3D fluid held to its plane.
"""

import json

import pytest

from aquagait.cli import main

FISH = """<mujoco model="suite fish">
  <option timestep="0.004" density="5000"><flag gravity="disable"/></option>
  <default>
    <default class="fish">
      <joint type="hinge" limited="false" range="-40 40" damping="2e-5"/>
      <geom rgba=".8 .5 .3 1"/>
    </default>
  </default>
  <worldbody>
    <geom name="ground" type="plane" size=".5 .5 .1"/>
    <body name="torso" pos="0 0 .1" childclass="fish">
      <freejoint name="root"/>
      <geom name="torso" type="ellipsoid" size=".01 .04 .015" mass="0"/>
      <geom name="ballast" type="box" size=".002 .03 .01" group="4" mass=".01"/>
      <body name="tail1" pos="0 -.04 0">
        <joint name="tail1" axis="0 0 1"/>
        <geom name="tail1" type="ellipsoid" pos="0 -.015 0" size=".002 .015 .012"/>
        <body name="tail2" pos="0 -.03 0">
          <joint name="tail2" axis="0 0 1" limited="auto" range="0 0"/>
          <geom name="tail2" type="ellipsoid" pos="0 -.02 0" size=".001 .02 .02"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator>
    <position name="tail1" joint="tail1" ctrlrange="-1 1" kp="1e-3"/>
    <position name="tail2" joint="tail2" ctrlrange="-.8 .8" kp="1e-3"/>
  </actuator>
</mujoco>"""

SWIMMER = """<mujoco model="suite swimmer">
  <option timestep="0.002" density="3000"><flag contact="disable"/></option>
  <default>
    <default class="swimmer">
      <joint type="hinge" pos="0 -.05 0" axis="0 0 1" limited="true" range="-60 60"/>
      <default class="inertial">
        <geom type="box" size=".001 .05 .01" rgba="0 0 0 0" mass=".01"/>
      </default>
      <default class="visual">
        <geom type="capsule" size=".01" fromto="0 -.05 0 0 .05 0" mass="0"/>
      </default>
    </default>
    <default class="free"><joint limited="false" armature="0"/></default>
  </default>
  <worldbody>
    <geom name="ground" type="plane" size="2 2 0.1"/>
    <body name="head" pos="0 0 .05" childclass="swimmer">
      <geom name="head" type="ellipsoid" size=".02 .04 .017" pos="0 -.022 0" mass="0"/>
      <joint name="rootx" class="free" type="slide" axis="1 0 0" pos="0 -.05 0"/>
      <joint name="rooty" class="free" type="slide" axis="0 1 0" pos="0 -.05 0"/>
      <joint name="rootz" class="free" type="hinge" axis="0 0 1" pos="0 -.05 0"/>
      <geom name="inertial" class="inertial"/>
      <geom name="visual" class="visual"/>
      <body name="segment_0" pos="0 .1 0">
        <geom class="visual"/><geom class="inertial"/><joint name="joint_0"/>
        <body name="segment_1" pos="0 .1 0">
          <geom class="visual"/><geom class="inertial"/><joint name="joint_1"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="joint_0" gear="5e-4"/><motor joint="joint_1" gear="5e-4"/></actuator>
</mujoco>"""

CASES = {
    "fish": (FISH, ["--resolution", "56", "28", "32", "--cell-size", "0.005"], None),
    "swimmer": (SWIMMER, ["--resolution", "80", "40", "--cell-size", "0.008"], None),
    # the same swimmer in the 3D fluid, its root held to its plane
    "swimmer3d": (SWIMMER, ["--resolution", "48", "24", "24", "--cell-size", "0.012"],
                  '{"planar_fluid": "3d"}'),
}  # fmt: skip


@pytest.fixture(params=list(CASES))
def written_elsewhere(request, tmp_path):
    text, grid, sidecar = CASES[request.param]
    path = tmp_path / f"{request.param}.xml"
    path.write_text(text)
    if sidecar:
        path.with_name(f"{request.param}.aquagait.json").write_text(sidecar)
    return path, grid


def test_check_reads_it_as_mujoco_does(written_elsewhere, tmp_path, capsys):
    path, _ = written_elsewhere
    assert main(["check", str(path), "--no-picture", "--out", str(tmp_path / "check")]) == 0
    out = capsys.readouterr().out
    assert "only gives mass" in out or "only give mass" in out  # the hidden geoms
    assert "turned to face +x" in out  # head along +y (fish), nose at -y (swimmer)
    if path.stem == "fish":
        assert "switched off" in out and "'tail2' -0.8 to 0.8 rad" in out
        assert "thickened for the fluid" in out
    elif path.stem == "swimmer":
        assert "planar with 3D shapes" in out and "moved to z = 0" in out
    else:
        assert "held to its plane in the 3D fluid" in out and "3D;" in out


def test_it_swims_head_first(written_elsewhere, tmp_path):
    path, grid = written_elsewhere
    out = tmp_path / "swim"
    argv = ["swim", str(path), "--seconds", "2", *grid, "--out", str(out), "--no-video"]
    assert main(argv) == 0
    metrics = json.loads((out / "metrics.json").read_text())
    # forward along its own head's direction: the travelling wave pushes it head first
    assert metrics["distance"] > 0.01 * metrics["body_length"]


def test_a_one_generation_search_runs(written_elsewhere, tmp_path):
    path, grid = written_elsewhere
    out = tmp_path / "optimize"
    argv = ["optimize", str(path), "--generations", "1", "--popsize", "2", "--workers", "1"]
    assert main([*argv, *grid, "--out", str(out), "--no-video"]) == 0
    assert len((out / "optimization.csv").read_text().splitlines()) == 2
    failures = (out / "failures.csv").read_text().splitlines()
    assert len(failures) == 1, failures  # the header only
