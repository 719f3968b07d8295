"""NAME or PATH: a user's MJCF file works in swim, optimize and compare, end to end."""

import json

import pytest

from aquagait.cli import main

SWIMMER = """<mujoco model="three-link swimmer">
  <custom><numeric name="aquagait_depth" data="0.02"/></custom>
  <worldbody>
    <body name="head">
      <joint name="x" type="slide" axis="1 0 0"/><joint name="y" type="slide" axis="0 1 0"/>
      <joint name="yaw" type="hinge" axis="0 0 1"/>
      <geom type="box" size=".05 .012 .01" density="1000"/>
      <body name="middle" pos="-.05 0 0">
        <joint name="j1" type="hinge" axis="0 0 1" range="-60 60"/>
        <geom type="box" size=".05 .01 .01" pos="-.05 0 0" density="1000"/>
        <body name="tail" pos="-.1 0 0">
          <joint name="j2" type="hinge" axis="0 0 1" range="-60 60"/>
          <geom type="box" size=".05 .008 .01" pos="-.05 0 0" density="1000"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>"""

GRID = ["--resolution", "56", "24", "--cell-size", "0.01"]

EQUALITY = '<equality><joint joint1="j1" joint2="j2"/></equality>'
"""A constraint between joints: something aquagait cannot simulate."""


@pytest.fixture(scope="module")
def swimmer(tmp_path_factory):
    path = tmp_path_factory.mktemp("mine") / "swimmer.xml"
    path.write_text(SWIMMER)
    return path


def test_swim_takes_a_path(swimmer, tmp_path):
    out = tmp_path / "swim"
    argv = ["swim", str(swimmer), "--seconds", "0.2", *GRID, "--out", str(out), "--no-video"]
    assert main(argv) == 0
    config = json.loads((out / "config.json").read_text())
    assert config["creature"] == "swimmer"
    assert config["creature_source"] == str(swimmer.resolve())
    assert json.loads((out / "gait.json").read_text())["creature"] == "swimmer"


def test_optimize_takes_a_path_and_its_worker_processes_find_the_file(swimmer, tmp_path):
    out = tmp_path / "optimize"
    argv = ["optimize", str(swimmer), "--generations", "1", "--popsize", "2", "--workers", "2"]
    assert main([*argv, *GRID, "--out", str(out), "--no-video"]) == 0
    log = (out / "optimization.csv").read_text().splitlines()
    assert len(log) == 2 and (out / "gait.json").is_file()
    failures = (out / "failures.csv").read_text().splitlines()
    assert len(failures) == 1, failures  # the header only: every worker found the creature


def test_compare_takes_a_path(swimmer, tmp_path):
    out = tmp_path / "compare"
    argv = ["compare", str(swimmer), "--seconds", "0.2", *GRID, "--out", str(out), "--no-video"]
    assert main(argv) == 0
    assert set(json.loads((out / "compare.json").read_text())["swims"]) == {"euler", "simple"}


SEARCH = ["--optimize", "1", "--popsize", "2", "--workers", "1", "--seconds", "0.2"]
"""compare's smallest search: one generation of two in each fluid."""

WIDE = ["--resolution", "56", "32", "--cell-size", "0.01"]
"""A grid that holds a random gait's 0.07 m sweep (GRID's 24 cells hold the straight
swimmer's 2.4 cm)."""


def test_compare_optimizes_in_each_fluid_in_run_directories_a_resume_reads_back(
    swimmer, tmp_path, capsys
):
    out = tmp_path / "compare"
    argv = ["compare", str(swimmer), *SEARCH, *WIDE, "--seed", "3", "--out", str(out), "--no-video"]
    assert main(argv) == 0
    for fluid in ("euler", "simple"):
        run = out / f"optimize-{fluid}"
        assert (run / "checkpoint.pkl").is_file() and (run / "gait.json").is_file()
        header, row = (run / "optimization.csv").read_text().splitlines()  # one generation
        evaluations = row.split(",")[header.split(",").index("evaluations")]
        assert evaluations == "3"  # the start, and one generation of --popsize 2
    cross = json.loads((out / "compare.json").read_text())["cross"]
    assert (cross["seed"], cross["generations"]) == (3, 1)
    assert set(cross["objective"]) == {"euler", "simple"}
    err = capsys.readouterr().err
    assert "optimizing swimmer in the simple fluid" in err and "generation   1/1" in err

    assert main(argv) == 2  # the checkpoints are there: not overwritten
    assert "--resume" in capsys.readouterr().err
    assert main([*argv, "--resume"]) == 0  # finished searches are read back, not run again
    again = json.loads((out / "compare.json").read_text())["cross"]
    assert again["gaits"] == cross["gaits"] and again["distance"] == cross["distance"]


def test_a_trained_gait_that_outgrows_the_grid_swims_on_in_a_grown_grid(swimmer, tmp_path, capsys):
    """On GRID's 24 cells the seed-3 search's best gait in the simple fluid sweeps 0.07 m
    and leaves the grid in the Euler fluid: its swim grows the grid (the search's samples
    may not) and says so."""
    argv = ["compare", str(swimmer), *SEARCH, *GRID, "--seed", "3", "--out", str(tmp_path)]
    assert main([*argv, "--no-video"]) == 0
    out = capsys.readouterr().out
    assert "gait trained in simple, in euler: at t = " in out and "outgrew the 56x24 grid" in out
    cross = json.loads((tmp_path / "compare.json").read_text())["cross"]
    assert any("grew to 56x" in note for note in cross["notes"])


def test_search_flags_without_optimize_are_refused(swimmer, tmp_path, capsys):
    argv = ["compare", str(swimmer), "--resume", "--start", "x.json", "--out", str(tmp_path)]
    assert main(argv) == 2
    assert "--resume, --start: only with --optimize [G]" in capsys.readouterr().err


def test_compare_optimize_without_a_count_searches_until_converged():
    from aquagait.cli import CONVERGED, build_parser

    parser = build_parser()
    assert parser.parse_args(["compare", "eel2d", "--optimize"]).optimize == CONVERGED
    assert parser.parse_args(["compare", "eel2d", "--optimize", "8"]).optimize == 8
    assert parser.parse_args(["compare", "eel2d"]).optimize is None


def test_a_path_that_is_not_there_is_one_line_and_status_2(tmp_path, capsys):
    assert main(["swim", str(tmp_path / "nothing.xml"), "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("aquagait swim: error: ") and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1 and "nothing.xml" in err


@pytest.mark.parametrize(
    "files,message",
    [
        ({"swimmer.xml": "not xml at all"}, "swimmer.xml"),
        (
            {"swimmer.xml": SWIMMER.replace("</mujoco>", EQUALITY + "</mujoco>")},
            "aquagait solves no constraints between links",
        ),
        (
            {"swimmer.xml": SWIMMER, "swimmer.aquagait.json": '{"gait": {"dofs": "j1"}}'},
            "gait.dofs",
        ),
        ({"swimmer.xml": SWIMMER, "swimmer.aquagait.json": "{"}, "swimmer.aquagait.json"),
    ],
    ids=["not-xml", "equality", "metadata-shape", "metadata-not-json"],
)
def test_a_bad_file_is_a_message_and_status_2_in_every_command(tmp_path, capsys, files, message):
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    path = str(tmp_path / "swimmer.xml")
    for command in (["swim", path], ["optimize", path], ["compare", path], ["check", path]):
        assert main([*command, "--out", str(tmp_path / "out")]) == 2, command
        err = capsys.readouterr().err
        assert err.startswith(f"aquagait {command[0]}: error: ") and message in err, err
        assert "Traceback" not in err
