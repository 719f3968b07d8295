"""A search inside a group: one creature's gait or phase searched while the others swim
theirs, scored on that creature's own part of the group's swim; the same serially and in
parallel; the command line end to end, with its refusals."""

import csv
import json
from dataclasses import replace

import numpy as np
import pytest

from aquagait import objectives
from aquagait.app import SetupError
from aquagait.app.school import (
    formation_members,
    prepare_school,
    read_scene_file,
    run_school,
)
from aquagait.app.school_search import prepare_school_search
from aquagait.cli import main
from aquagait.io.run import read_run
from aquagait.optimize import local_executor, optimize
from aquagait.sim.group import member_trajectory

COARSE = dict(cell_size=0.02, cycles=0.5)  # a 0.5-s sample on 2-cm cells: a second a swim


def pair(phase=0.0):
    return formation_members("eel2d", "in-line", spacing=0.5, phase=phase)


def test_the_objective_is_the_searched_creature_s_part_of_the_group_s_swim():
    """The search's number for a gait is the paper's objective of the follower's own part
    of the group's swim (``run_school``), for its gait and, searched, for its phase."""
    setup = prepare_school_search(pair(), **COARSE)
    gait, bound = setup.search_setup.problem.x0, setup.school.creatures[1].energy_bound
    objective = setup.search_setup.objective
    for search, params, phase in [("gait", gait, 0.0), ("phase", [0.3], 0.3)]:
        school = prepare_school(pair(phase), seconds=0.5, cell_size=0.02)
        run = run_school(school)
        own = member_trajectory(run.trajectory, school.group.members[1])
        searched = replace(objective, search=search)
        lone = searched._swim(params)[1]  # the follower's own scene
        expected = objectives.total(lone, own, objective.direction, bound, objective.weights,
                                    period=school.period(1))  # fmt: skip
        assert searched(params) == pytest.approx(expected, rel=1e-9, abs=1e-12)
    # and the follower is scored, not the leader: the leader's part scores otherwise
    leader = member_trajectory(run.trajectory, school.group.members[0])
    assert objectives.distance(lone.model, leader, objective.direction) != pytest.approx(
        objectives.distance(lone.model, own, objective.direction), rel=1e-3
    )


def test_a_search_inside_a_group_is_the_same_serially_and_in_processes():
    setup = prepare_school_search(pair(), generations=2, popsize=4, seed=3, **COARSE)
    search = setup.search_setup
    serial = optimize(search.problem, search.settings)
    with local_executor(2) as executor:
        parallel = optimize(search.problem, search.settings, executor)
    np.testing.assert_array_equal(serial.best_x, parallel.best_x)
    assert serial.best_f == parallel.best_f and serial.evaluations == parallel.evaluations == 9


def test_a_phase_search_varies_the_lag_alone_within_a_cycle():
    setup = prepare_school_search(pair(0.25), search="phase", **COARSE)
    problem = setup.search_setup.problem
    assert problem.names == ("phase",) and problem.x0.tolist() == [0.25]
    assert (problem.lower.tolist(), problem.upper.tolist()) == ([0.0], [1.0])
    objective = setup.search_setup.objective
    assert objective([0.25]) != pytest.approx(objective([0.75]), rel=1e-3)
    # a group spreads as the wake pushes its followers aside: its grid grows (a lone
    # creature's search penalizes a sample that leaves its grid)
    assert setup.search_setup.config()["fluid_settings"]["grow"] is True


def test_the_efficiency_objective_s_unit_is_the_member_s_cost_in_the_group():
    setup = prepare_school_search(pair(), objective="efficiency", cell_size=0.02, cycles=3)
    objective = setup.search_setup.objective
    speed, cost, _ = objective.cruise(setup.search_setup.problem.x0)
    assert objective.reference_cost == pytest.approx(cost, rel=1e-12)
    assert objective.min_speed == pytest.approx(0.75 * speed, rel=1e-12)
    assert any(note.startswith("eel2d-2 in the group") for note in setup.search_setup.notes)
    # its start scores exactly the cost term's unit, 1, at the speed it keeps
    assert objective(setup.search_setup.problem.x0) == pytest.approx(
        1.0 + objective.weights.deviation * objectives.deviation(
            *_member(objective, setup.search_setup.problem.x0)), rel=1e-9)  # fmt: skip


def _member(objective, params):
    _, scene, traj, period = objective._swim(params)
    return scene.model, traj, objective.direction, None, period


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (dict(searched="eel2d-9"), "no creature labelled 'eel2d-9'"),
        (dict(search="spacing"), "unknown search 'spacing'"),
        (dict(min_speed=0.2), "--min-speed is for --objective efficiency"),
    ],
)
def test_a_bad_search_inside_a_group_says_what_would_do(options, message):
    with pytest.raises(SetupError, match=message):
        prepare_school_search(pair(), cell_size=0.02, **options)


def test_the_command_line_searches_a_follower_and_swims_the_group_with_its_best(tmp_path, capsys):
    out = tmp_path / "follower"
    assert main(["optimize", "eel2d", "--formation", "in-line", "--cell-size", "0.02",
                 "--cycles", "0.5", "--generations", "1", "--popsize", "4", "--workers", "1",
                 "--search", "phase", "--no-video", "--out", str(out)]) == 0  # fmt: skip
    printed = capsys.readouterr()
    assert "optimizing eel2d-2's phase in eel2d-in-line" in printed.err
    config = read_run(out).config
    assert config["optimization"]["school"]["searched"] == "eel2d-2"
    assert config["optimization"]["parameters"] == ["phase"]
    with (out / "optimization.csv").open() as log:
        best = float(list(csv.DictReader(log))[-1]["phase"])
    members, grid = read_scene_file(out / "scene.json")
    assert [m.phase for m in members] == pytest.approx([0.0, best], rel=1e-12)
    assert grid == {"cell_size": 0.02}
    # the group swum with the best is the scene file's: its follower is the searched one
    assert config["school"]["members"][1]["phase"] == pytest.approx(best, rel=1e-12)


@pytest.mark.parametrize(
    ("flags", "message"),
    [
        (["--formation", "in-line", "--maneuver", "turn-left"], "--maneuver is refused in a group"),
        (["--formation", "in-line", "--free-period"], "--free-period is refused in a group"),
        (["--member", "eel2d-2"], "--member: for a group"),
        (["--phase", "0.25"], "--phase: for a group"),
        (["--formation", "in-line", "--member", "leader"], "no creature labelled 'leader'"),
    ],
)
def test_the_command_line_refuses_what_a_group_s_search_cannot_do(flags, message, capsys):
    assert main(["optimize", "eel2d", "--cell-size", "0.02", *flags]) == 2
    assert message in capsys.readouterr().err


def test_a_formation_s_flags_without_a_formation_are_refused(capsys):
    assert main(["swim", "eel2d", "--spacing", "1.0", "--no-video"]) == 2
    assert "--spacing: for a group: give --formation" in capsys.readouterr().err


def test_a_scene_file_s_creature_is_searched_by_its_label(tmp_path, capsys):
    scene = tmp_path / "pair.json"
    scene.write_text(json.dumps({"creatures": [
        {"name": "eel2d", "label": "leader"},
        {"name": "eel2d", "label": "follower", "offset": [-0.75, 0.0], "phase": 0.25},
    ], "cell_size": 0.02}))  # fmt: skip
    out = tmp_path / "run"
    assert main(["optimize", str(scene), "--member", "follower", "--cycles", "0.5",
                 "--generations", "1", "--popsize", "2", "--workers", "1", "--no-video",
                 "--out", str(out)]) == 0  # fmt: skip
    assert "optimizing follower's gait in pair" in capsys.readouterr().err
    members, grid = read_scene_file(out / "scene.json")
    assert [m.label for m in members] == ["leader", "follower"] and grid == {"cell_size": 0.02}
    assert members[0].gait is None and members[1].gait == str((out / "gait.json").resolve())
    assert members[1].phase == 0.25  # a gait search keeps the phase
    swum = read_run(out).config["school"]["members"][1]["gait"]["params"]
    searched = json.loads((out / "gait.json").read_text())["params"]
    np.testing.assert_array_equal(swum, searched)  # the group swum with the best found
