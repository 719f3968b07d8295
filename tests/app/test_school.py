"""A group swim from the command line and from Python: formations, scene files, the run
directory with every creature's files, pictures and exports of the group, clear refusals."""

import json

import numpy as np
import pytest

from aquagait.app.school import (
    SchoolSetupError,
    formation_members,
    prepare_school,
    read_scene_file,
)
from aquagait.cli import main
from aquagait.io.run import read_run

COARSE = ["--cell-size", "0.02", "--seconds", "0.2", "--no-video"]


def test_a_formation_swims_from_the_command_line_into_one_run(tmp_path, capsys):
    out = tmp_path / "pair"
    assert main(["swim", "eel2d", "--formation", "in-line", "--spacing", "0.5", "--phase",
                 "0.25", *COARSE, "--out", str(out)]) == 0  # fmt: skip
    printed = capsys.readouterr().out
    assert "eel2d-2 (eel2d, phase 0.25)" in printed and "the group (euler fluid)" in printed
    run = read_run(out)
    members = run.config["school"]["members"]
    assert [m["label"] for m in members] == ["eel2d-1", "eel2d-2"]
    assert members[1]["offset"][0] == pytest.approx(-1.5 * 0.5, rel=1e-6)  # 1.5 body lengths
    for member in members:
        own = read_run(out / "members" / member["label"])
        assert own.trajectory.qpos.shape[1] == 7 and own.metrics["distance"] > 0
        assert (out / "members" / member["label"] / "gait.json").exists()
    assert run.trajectory.qpos.shape[1] == 14
    np.testing.assert_array_equal(run.trajectory.qpos[:, 7:], read_run(
        out / "members" / "eel2d-2").trajectory.qpos)  # fmt: skip


def test_a_scene_file_names_each_creature_and_the_pictures_draw_them_all(tmp_path):
    scene = tmp_path / "pair.json"
    scene.write_text(json.dumps({"creatures": [
        {"name": "eel2d", "label": "leader"},
        {"name": "eel2d", "label": "follower", "offset": [-0.75, 0.05], "gait": "hand-set",
         "phase": 0.5},
    ], "cell_size": 0.02}))  # fmt: skip
    out = tmp_path / "run"
    assert main(["swim", str(scene), "--seconds", "0.2", "--no-video", "--out", str(out)]) == 0
    config = read_run(out).config
    assert config["cell_size"] == 0.02 and config["school"]["members"][1]["phase"] == 0.5
    assert config["school"]["members"][1]["gait"]["source"] == "shipped hand-set"
    assert main(["render", str(out), "--format", "png", "--frames", "3:4"]) == 0
    assert (out / "swim.png").stat().st_size > 0


def test_formations_place_their_creatures_as_their_spacing_says():
    inline = formation_members("eel2d", "in-line:3", spacing=1.0, phase=0.1)
    assert [m.offset[0] for m in inline] == pytest.approx([0.0, -1.0, -2.0])  # 2 BL of 0.5 m
    assert [m.phase for m in inline] == pytest.approx([0.0, 0.1, 0.2])
    beside = formation_members("eel2d", "side-by-side", spacing=0.4)
    assert [m.offset[1] for m in beside] == pytest.approx([-0.1, 0.1])
    diamond = formation_members("eel2d", "diamond", spacing=0.5, phase=0.25)
    assert [m.phase for m in diamond] == [0.0, 0.25, 0.25, 0.5]


@pytest.mark.parametrize("formation, message", [
    ("v-shape", "unknown formation 'v-shape'; formations: in-line, side-by-side, diamond"),
    ("in-line:0", "a whole number of creatures >= 1"),
    ("diamond:3", "a diamond has 4"),
])  # fmt: skip
def test_a_bad_formation_says_what_would_do(formation, message):
    with pytest.raises(SchoolSetupError, match=message):
        formation_members("eel2d", formation)


def test_creatures_placed_too_close_are_refused_with_their_depth(capsys):
    assert main(["swim", "eel2d", "--formation", "side-by-side", "--spacing", "0.01",
                 *COARSE]) == 2  # fmt: skip
    assert "eel2d-1 and eel2d-2 overlap at their starting poses" in capsys.readouterr().err


def test_a_scene_file_s_mistakes_are_named(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"creatures": [{"name": "eel2d", "pose": [0, 0]}]}))
    with pytest.raises(SchoolSetupError, match="creature 1: unknown keys pose; known: gait, "):
        read_scene_file(bad)
    bad.write_text("{")
    with pytest.raises(SchoolSetupError, match="is not JSON"):
        read_scene_file(bad)
    mixed = [*formation_members("eel2d", "in-line:1"), *formation_members("fish", "in-line:1")]
    with pytest.raises(SchoolSetupError, match="2D and 3D creatures cannot share a fluid"):
        prepare_school(mixed)
