"""``aquagait follow``: what it refuses and why, and the run directory it writes.

The runs here are in a vacuum (fluid 'none': the eel hardly moves), so they
test the machinery fast; following in water is the slow tests' business
(``tests/path/test_following_swims.py``).
"""

import csv
import json

import numpy as np
import pytest

import aquagait as ag
from aquagait.app.follow import FollowSetupError, prepare_follow, run_follow, write_follow
from aquagait.cli import main
from aquagait.io import write_gait

EEL = ag.creatures.get("eel2d")


@pytest.fixture(scope="module")
def learned(tmp_path_factory):
    """Hand-set turns for the eel: its straight gait bent 0.2 rad to one side."""
    folder = tmp_path_factory.mktemp("learned")
    files = []
    for maneuver, offset in (("turn-left", 0.2), ("turn-right", -0.2)):
        params = np.r_[EEL.default_gait, [offset] * 4]
        files.append(write_gait(folder / f"{maneuver}.json", EEL, params, maneuver))
    return files


def _follow(path, learned, steer="paper", **options):
    """In a vacuum the hand-set turns hardly turn (turn-left even turns right a little): the
    paper's rule, which needs no measure of them."""
    return prepare_follow("eel2d", path, cycles=2, learned=learned, fluid="none", steer=steer,
                          **options)  # fmt: skip


def test_a_shape_starts_at_the_root_and_the_run_records_the_way(tmp_path, learned):
    setup = _follow("s-curve:length=2,amplitude=0.3", learned)
    start, _ = ag.path.root_pose(setup.scene, ag.init_state(setup.scene).qpos)
    np.testing.assert_allclose(setup.path.points[0], start)
    assert setup.scene.grid is None or setup.scene.grid.shape[0] == setup.scene.grid.shape[1]
    assert setup.dead_band == pytest.approx(0.1 * EEL.model.body_length)
    run = run_follow(setup)
    out = write_follow(run, tmp_path / "run", video=True)
    written = {p.name for p in out.iterdir()}
    assert {"config.json", "trajectory.npz", "metrics.json", "path.csv", "maneuvers.csv",
            "path_distance.csv", "swim.mp4", "follow.png"} <= written  # fmt: skip
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["units"]["path_distance_mean"] == "m"
    assert metrics["units"]["path_progress_body_lengths"] == "1"
    length = EEL.model.body_length
    assert metrics["path_distance_mean_body_lengths"] == pytest.approx(
        metrics["path_distance_mean"] / length)  # fmt: skip
    rows = list(csv.DictReader((out / "path_distance.csv").open()))
    assert len(rows) == len(run.trajectory.time) == 61
    assert float(rows[0]["distance_m"]) == pytest.approx(0.0, abs=1e-9)  # starts on the path
    distances = [float(r["distance_m"]) for r in rows]
    assert max(distances) == pytest.approx(metrics["path_distance_max"])
    cycles = list(csv.DictReader((out / "maneuvers.csv").open()))
    assert [float(c["time_s"]) for c in cycles] == [0.0, 1.0]
    config = json.loads((out / "config.json").read_text())
    assert set(config["maneuvers"]) == {"straight", "turn-left", "turn-right"}
    assert config["maneuvers"]["turn-left"]["source"].endswith("turn-left.json")


def test_open_loop_swims_straight_only(learned):
    run = run_follow(_follow("circle:radius=0.3", learned, open_loop=True))
    assert {d.maneuver for d in run.decisions} == {"straight"}


def _write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize(
    "path, message",
    [
        ("one.csv:0.2,0", "at least two points"),
        ("nan.csv:0.2,0\n0.5,nan", "path point 1 is not a number"),
        ("flat.csv:0.2,0,0\n0.5,0,0", "holds 3D points but the creature swims in 2D"),
        (
            "far.csv:5,5\n6,5",
            r"passes 6\.\d+ m \(1\d\.\d body lengths\) from the creature's "
            r"start .* move the path by \[-",
        ),  # fmt: skip
        ("blob", "neither a path file nor a shape; shapes .*: line:length=5.0; circle:"),
        ("circl:radius=0.6", "neither a path file nor a shape; shapes .*: line:length=5.0;"),
        ("circle:radius=big", "give parameters as key=value"),
        ("circle:radus=0.6", "path shape 'circle' takes radius, turns, not radus"),
        ("missing.csv", "does not exist"),
    ],
)
def test_bad_paths_say_what_is_wrong(tmp_path, learned, path, message):
    if ".csv:" in path:
        name, _, rows = path.partition(":")
        path = _write(tmp_path, name, rows.replace("\\n", "\n"))
    with pytest.raises(FollowSetupError, match=message):
        _follow(path, learned)


def test_a_path_needs_the_turns_the_creature_has_learned():
    with pytest.raises(FollowSetupError) as err:
        prepare_follow("accordion2d", "line", fluid="none")
    text = str(err.value)
    assert "needs turn-left, turn-right, which accordion2d has not learned" in text
    assert "(it has learned: straight)" in text
    assert "aquagait optimize accordion2d --maneuver turn-right" in text
    assert "--learned" in text


def test_another_creature_s_manoeuvre_is_refused(tmp_path):
    fish = ag.creatures.get("fish")
    other = write_gait(tmp_path / "gait.json", fish, None)
    with pytest.raises(FollowSetupError, match="a gait for 'fish', not for 'eel2d'"):
        _follow("line", [other])


@pytest.mark.parametrize("options, message", [({"cycles": 0}, "cycles must be a whole number"),
                                              ({"blend": 2}, "blend is a share"),
                                              ({"dead_band": -1}, "dead band")])  # fmt: skip
def test_bad_settings_are_refused(learned, options, message):
    with pytest.raises(FollowSetupError, match=message):
        prepare_follow("eel2d", "line", learned=learned, fluid="none", **options)


def test_the_command_line_fails_with_status_2_and_the_reason(tmp_path, capsys):
    assert main(["follow", "accordion2d", "--path", "circle", "--out", str(tmp_path / "x")]) == 2
    assert "has not learned" in capsys.readouterr().err


def test_follow_snapshots_are_whole_cycles_apart_and_a_slow_swimmer_is_not_drawn_over_itself():
    from types import SimpleNamespace

    from aquagait.app.follow import SNAPSHOT_SPACING, SNAPSHOTS, snapshot_every

    def run(cycles, body_lengths):
        return SimpleNamespace(setup=SimpleNamespace(cycles=cycles, period=0.5),
                               metrics={"path_progress_body_lengths": body_lengths},
                               trajectory=SimpleNamespace(fps=30))  # fmt: skip

    assert snapshot_every(run(12, 12 * SNAPSHOT_SPACING)) == 15  # a cycle apart
    assert snapshot_every(run(3 * SNAPSHOTS, 100.0)) == 3 * 15  # no more than SNAPSHOTS
    assert snapshot_every(run(20, 2.8)) == 6 * 15  # 0.14 BL a cycle: 0.84 BL apart
    assert snapshot_every(run(4, 0.0)) == 4 * 15  # nowhere: the first and last frames


def test_the_following_ends_where_the_root_first_reaches_the_paths_end():
    """Distances count until then: past a line's end, or round a circle's lap and on, there
    is nothing left to follow."""
    from aquagait.app.follow import _end_frame, _progress

    line = ag.path.shape("line", dim=2, length=1.0)
    along = np.linspace(0.0, 1.5, 16)  # 0.1 m a frame
    positions = np.stack([along, np.full_like(along, 0.05)], axis=1)
    progress = _progress(line, positions, body_length=0.5)
    assert _end_frame(line, progress) == 10  # x = 1.0 m
    short = positions[:8]
    assert _end_frame(line, _progress(line, short, body_length=0.5)) == 7  # not reached

    circle = ag.path.shape("circle", dim=2, radius=1.0)
    angle = np.linspace(0.0, 2.4 * np.pi, 49)  # 1.2 laps, 0.05 of a lap a frame
    centre = circle.points[0] + [0.0, 1.0]  # it starts at the root, turning left
    positions = centre + 1.02 * np.stack([np.sin(angle), -np.cos(angle)], axis=1)
    progress = _progress(circle, positions, body_length=0.5)
    assert _end_frame(circle, progress) == 40  # one lap, not the start read as its end


def test_graded_steering_measures_each_turn_and_refuses_one_that_turns_the_wrong_way(learned):
    """In a vacuum, with nothing to push against, only the body's change of shape turns it,
    and the eel's hand-set turn-left (its straight gait bent 0.2 rad left) turns it 0.42 rad
    to the right over two cycles under way (in the simple fluid 1.14): graded steering
    cannot steer with it. The shipped turns, learned in water, turn their ways in the
    simple fluid too (0.59-0.62 rad a cycle under way), and the setup records both rates."""
    wrong_way = r"turn-left turns -0.42\d* rad its way.*under way.*In a vacuum.*in a fluid.*--steer"
    with pytest.raises(FollowSetupError, match=wrong_way):
        _follow("line", learned, steer="graded")
    setup = prepare_follow("eel2d", "line", cycles=1, fluid="simple")
    assert setup.steer == "graded"
    assert set(setup.rates) == {"turn-left", "turn-right"}
    assert all(0.1 < rate < 1.5 for rate in setup.rates.values())  # radians a cycle
    assert prepare_follow("eel2d", "line", cycles=1, fluid="simple",
                          open_loop=True).rates is None  # fmt: skip
