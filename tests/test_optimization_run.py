"""Optimizing a creature's gait end to end: the swim objective, the command, the demo."""

import dataclasses
import json
import pickle
import re
import shlex
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from tests.optimize.optimize_cases import descendants, gone

import aquagait as ag
from aquagait import cli
from aquagait.app.optimize import (
    JointLimits,
    OptimizationSetupError,
    SwimObjective,
    prepare_optimization,
    run_optimization,
)
from aquagait.creatures.creature import maneuver_start
from aquagait.io import write_gait
from aquagait.optimize import checkpoint

COARSE = dict(resolution=(48, 28), cell_size=0.025)
"""A coarse eel2d grid: 28 cells across hold the shipped gait's 0.19 m sweep and 8 of water
either side."""


def test_swim_objective_is_picklable_and_deterministic():
    objective = SwimObjective("eel2d", COARSE["resolution"], COARSE["cell_size"], seconds=0.5)
    eel = ag.creatures.get("eel2d")
    clone = pickle.loads(pickle.dumps(objective))
    assert objective(eel.default_gait) == clone(eel.default_gait)


def test_swim_objective_gives_the_same_value_in_a_worker_process():
    """What makes serial, process and Dask optimization agree: the simulation
    itself is deterministic across processes, to the last bit."""
    from aquagait.optimize import local_executor

    objective = SwimObjective("eel2d", COARSE["resolution"], COARSE["cell_size"], seconds=0.5)
    eel = ag.creatures.get("eel2d")
    gaits = [eel.default_gait, np.clip(eel.default_gait * 1.1, eel.gait.lower, eel.gait.upper)]
    with local_executor(2) as pool:
        remote = list(pool.map(objective, gaits))
    assert remote == [objective(g) for g in gaits]


def test_joint_limits_are_checked_before_swimming():
    eel = ag.creatures.get("eel2d")
    feasible = JointLimits("eel2d")
    assert feasible(eel.default_gait)
    too_wide = eel.default_gait.copy()
    too_wide[0] = 1.2  # amplitude of j1 beyond its 45 degree limit
    assert not feasible(too_wide)


def test_an_optimized_eel_swims_farther_than_the_hand_set_gait(tmp_path):
    setup = prepare_optimization("eel2d", generations=4, popsize=8, seed=3, **COARSE)
    eel = setup.creature
    start = dataclasses.replace(setup.problem, x0=eel.gaits["hand-set"].params)
    setup = dataclasses.replace(setup, problem=start)
    result = run_optimization(setup, run_dir=tmp_path)
    scene = ag.make_scene(eel, fluid="euler", **COARSE)

    def distance(params):
        traj = ag.rollout(scene, ag.init_state(scene), eel.policy(params), 2.0)
        return traj.qpos[-1, 0] - traj.qpos[0, 0]

    hand_set, optimized = distance(eel.gaits["hand-set"].params), distance(result.best_x)
    print(f"eel2d 2 s on 48x28: hand-set {hand_set:.3f} m, optimized {optimized:.3f} m")
    assert optimized > hand_set
    assert result.best_f < setup.problem.objective(eel.gaits["hand-set"].params)


def test_bad_settings_are_refused_before_anything_runs():
    with pytest.raises(OptimizationSetupError, match="known creatures"):
        prepare_optimization("shark")
    with pytest.raises(OptimizationSetupError, match="give 2 numbers"):
        prepare_optimization("eel2d", resolution=(32, 16, 8))
    with pytest.raises(OptimizationSetupError, match="generations must be at least 1"):
        prepare_optimization("eel2d", generations=0)


def test_the_energy_weight_is_the_creature_s_unless_given(tmp_path, capsys):
    """The frog's side-car weighs a joule above its bound 20 times the paper's default."""
    assert prepare_optimization("eel2d", **COARSE).objective.weights.energy == 1.0
    frog = prepare_optimization("frog", fluid="none")
    assert frog.objective.weights.energy == 20.0 == frog.creature.energy_weight
    setup = prepare_optimization("eel2d", resolution=(64, 32), cell_size=0.02, energy_weight=5.0,
                                 coarse=2)  # fmt: skip
    assert setup.objective.weights.energy == setup.target.weights.energy == 5.0
    assert setup.config()["weights"]["energy"] == 5.0
    with pytest.raises(OptimizationSetupError, match="energy weight must be a number >= 0"):
        prepare_optimization("eel2d", energy_weight=-1.0, **COARSE)
    argv = ["optimize", "eel2d", "--energy-weight", "-1", "--out", str(tmp_path / "eel")]
    assert cli.main(argv) == 2  # the flag reaches the setup, which refuses it
    assert "energy weight must be a number >= 0" in capsys.readouterr().err


def test_the_deviation_weight_scales_the_drift_and_turning_term(tmp_path, capsys):
    """The objective is linear in the weight of ``E_deviation``: the same swim (the simple
    fluid, its start) scores ``w E_deviation`` more at weight ``w`` than at 0, with
    ``E_deviation > 0`` (a swim drifts and turns a little); 0.2 is the paper's default. The
    command line and a shipped gait's command carry it."""
    values = {}
    for weight in (None, 0.0, 1.2):
        setup = prepare_optimization("eel2d", fluid="simple", deviation_weight=weight)
        values[weight] = setup.objective(setup.problem.x0)
    assert setup.config()["weights"]["deviation"] == 1.2
    e_deviation = (values[1.2] - values[0.0]) / 1.2
    assert e_deviation > 0
    assert values[None] - values[0.0] == pytest.approx(0.2 * e_deviation, rel=1e-9)
    with pytest.raises(OptimizationSetupError, match="deviation weight must be a number >= 0"):
        prepare_optimization("eel2d", deviation_weight=float("nan"), **COARSE)

    out = tmp_path / "eel"
    argv = ["optimize", "eel2d", "--generations", "1", "--popsize", "4", "--workers", "1",
            "--deviation-weight", "1", "--resolution", "48", "28", "--cell-size", "0.025",
            "--out", str(out), "--no-video"]  # fmt: skip
    assert cli.main(argv) == 0
    command, again = _shipped_command(out)
    assert "--deviation-weight 1" in command
    assert again.objective.weights.deviation == 1.0


def _shipped_command(run: Path):
    """The command a gait shipped from ``run`` records (``tools/ship_gait.py``), and the
    search it sets up when parsed again."""
    from ship_gait import provenance

    command = provenance(run)["command"]
    return command, cli.optimization_setup(cli.build_parser().parse_args(shlex.split(command)[1:]))


def test_a_turn_limit_reaches_the_manoeuvre_objective_and_the_gaits_command(tmp_path, capsys):
    """``--turn-limit`` caps the rotation a manoeuvre's samples are rewarded for: recorded in
    config.json and in a shipped gait's command (with the paper's objective's ``--cycles``
    when not its 2), a different one refused on resume, and refused for straight swimming
    or as no angle."""
    setup = prepare_optimization("eel2d", maneuver="turn-left", turn_limit=0.3, **COARSE)
    assert setup.objective.turn_limit == 0.3 and setup.config()["turn_limit"] == 0.3
    assert prepare_optimization("eel2d", **COARSE).config()["turn_limit"] is None
    # by default the creature's: 90 degrees, or what its side-car says (the manta's 0.25)
    turn = prepare_optimization("eel2d", maneuver="turn-left", **COARSE).objective.turn_limit
    assert turn == ag.objectives.TURN == ag.creatures.get("eel2d").turn_limit
    manta = prepare_optimization("manta", maneuver="pitch-up", fluid="none")
    assert manta.objective.turn_limit == 0.25 == manta.config()["turn_limit"]
    with pytest.raises(OptimizationSetupError, match="--turn-limit is for a manoeuvre"):
        prepare_optimization("eel2d", turn_limit=0.3, **COARSE)
    with pytest.raises(OptimizationSetupError, match="turn limit must be an angle > 0"):
        prepare_optimization("eel2d", maneuver="turn-left", turn_limit=0.0, **COARSE)

    out = tmp_path / "eel"
    argv = ["optimize", "eel2d", "--maneuver", "turn-left", "--turn-limit", "0.3",
            "--cycles", "1.5", "--generations", "1", "--popsize", "4", "--workers", "1",
            "--resolution", "48", "28", "--cell-size", "0.025", "--out", str(out),
            "--no-video"]  # fmt: skip
    assert cli.main(argv) == 0
    command, again = _shipped_command(out)
    assert "--turn-limit 0.3" in command and "--cycles 1.5" in command
    assert again.objective.turn_limit == 0.3
    assert again.objective.seconds == setup.objective.seconds * 1.5 / 2
    capsys.readouterr()
    assert cli.main([*argv[:5], "0.4", *argv[6:], "--resume"]) == 2
    assert "objective.turn_limit: 0.3 in the checkpoint, 0.4 now" in capsys.readouterr().err


def test_optimize_command_writes_the_run_directory_and_resumes(tmp_path, capsys):
    out = tmp_path / "eel"
    argv = ["optimize", "eel2d", "--generations", "2", "--popsize", "4", "--workers", "1"]
    argv += ["--resolution", "48", "28", "--cell-size", "0.025", "--out", str(out), "--no-video"]
    assert cli.main(argv) == 0
    for name in ("gait.json", "optimization.csv", "checkpoint.pkl", "metrics.json", "config.json"):
        assert (out / name).exists(), name
    config = json.loads((out / "config.json").read_text())
    assert config["optimization"]["popsize"] == 4 and config["optimization"]["creature"] == "eel2d"
    gait = json.loads((out / "gait.json").read_text())
    assert len(gait["params"]) == 8
    assert "generation   2/2" in capsys.readouterr().err
    # a second run into the same directory must say --resume; with it, the finished run returns
    assert cli.main(argv) == 2
    assert "resume" in capsys.readouterr().err
    assert cli.main(argv + ["--resume"]) == 0
    assert json.loads((out / "gait.json").read_text())["params"] == gait["params"]


def test_sigterm_stops_a_search_with_its_workers_and_it_resumes(tmp_path):
    """A batch system's SIGTERM (or a user's ``kill``) unwinds the command: its worker
    processes, the forkserver and the resource tracker all exit with it (killed by
    default, they outlived it for ever), one line says how to go on, and ``--resume``
    goes on from the checkpoint."""
    out = tmp_path / "eel"
    argv = [sys.executable, "-m", "aquagait", "optimize", "eel2d", "--generations", "400",
            "--popsize", "4", "--workers", "2", "--resolution", "48", "28", "--cell-size",
            "0.025", "--out", str(out), "--no-video"]  # fmt: skip
    search = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 120
        while not (out / "checkpoint.pkl").exists():  # a whole generation, on two workers
            assert search.poll() is None and time.monotonic() < deadline
            time.sleep(0.2)
        family = descendants(search.pid)
        assert len(family) >= 3  # the forkserver, the resource tracker, a worker
        search.send_signal(signal.SIGTERM)
        _, err = search.communicate(timeout=60)
    finally:
        if search.poll() is None:
            search.kill()
            search.communicate()
    assert search.returncode == 143
    assert "optimize: terminated (SIGTERM)" in err and "with --resume goes on" in err
    deadline = time.monotonic() + 10
    while not all(gone(pid) for pid in family):
        assert time.monotonic() < deadline, f"left running: {[p for p in family if not gone(p)]}"
        time.sleep(0.1)
    last = int(np.loadtxt(out / "optimization.csv", delimiter=",", skiprows=1, ndmin=2)[-1, 0])
    resumed = subprocess.Popen([*argv, "--resume"], stderr=subprocess.PIPE, text=True)
    try:
        lines = (line for line in resumed.stderr if line.startswith("generation"))
        assert int(next(lines).split()[1].split("/")[0]) == last + 1
    finally:
        resumed.send_signal(signal.SIGTERM)
        resumed.communicate(timeout=60)


def test_the_default_search_stops_by_itself_and_a_resume_after_it_says_so(tmp_path, capsys):
    """No generation count: CMA-ES's own population for eel2d's 8 parameters (10), the
    patience rule on, and here the evaluation cap, met exactly, stops it."""
    out = tmp_path / "eel"
    argv = ["optimize", "eel2d", "--max-evaluations", "13", "--workers", "1", "--out", str(out),
            "--resolution", "48", "28", "--cell-size", "0.025", "--no-video"]  # fmt: skip
    assert cli.main(argv) == 0
    streams = capsys.readouterr()
    assert "population 10, until the best improves less than 1 % in 34 generations, " \
        "at most 13 evaluations" in streams.err  # fmt: skip
    assert "after 13 samples (max_evaluations (13)" in streams.out
    config = json.loads((out / "config.json").read_text())["optimization"]
    assert (config["populations"], config["max_evaluations"], config["generations"]) == (
        [10], 13, None)  # fmt: skip
    assert cli.main(argv + ["--resume"]) == 0
    assert (
        "has already stopped (max_evaluations (13)): nothing to resume" in capsys.readouterr().err
    )
    assert cli.main(argv[:3] + ["14"] + argv[4:] + ["--resume"]) == 2  # another cap: refused
    assert "max_evaluations: 13 in the checkpoint, 14 now" in capsys.readouterr().err
    assert cli.main(argv + ["--deviation-weight", "1", "--resume"]) == 2  # another objective
    assert "objective.weights.deviation: 0.2 in the checkpoint, 1.0 now" in capsys.readouterr().err


def test_a_damaged_checkpoint_is_refused_with_its_name_and_what_to_do(tmp_path, capsys):
    (tmp_path / "checkpoint.pkl").write_text("garbage")
    (tmp_path / "optimization.csv").write_text("generation\n1\n")
    argv = ["optimize", "eel2d", "--workers", "1", "--out", str(tmp_path), "--resume",
            "--resolution", "48", "28", "--cell-size", "0.025", "--no-video"]  # fmt: skip
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    assert f"error: the checkpoint {tmp_path / 'checkpoint.pkl'} cannot be read (" in err
    assert "Nothing else in" in err and "start the search again in another directory" in err
    assert sorted(path.name for path in tmp_path.iterdir()) == ["checkpoint.pkl",
                                                                 "optimization.csv"]  # fmt: skip
    assert (tmp_path / "optimization.csv").read_text() == "generation\n1\n"


def test_a_generation_count_alone_keeps_the_papers_fixed_budget():
    setup = prepare_optimization("eel2d", generations=100, popsize=16, **COARSE)
    assert setup.settings.for_group(8) == (16, None)
    assert setup.budget() == "population 16, at most 100 generations"
    both = prepare_optimization("eel2d", generations=50, patience=5, **COARSE)
    assert both.budget() == (
        "population 10, at most 50 generations, until the best improves less than 1 % in 5 "
        "generations"
    )
    frog = prepare_optimization("frog", fluid="none")  # hind legs (12 parameters), fore (6)
    assert frog.populations() == [11, 9]
    with pytest.raises(OptimizationSetupError, match="max evaluations must be at least 1"):
        prepare_optimization("eel2d", max_evaluations=0, **COARSE)


@pytest.mark.slow
def test_demo_finds_a_gait_that_swims_a_third_of_a_body_length_per_cycle(tmp_path):
    """The README's main job: in at most 10 minutes on 2 cores (measured about 1 minute)."""
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-m", "aquagait", "demo", "--out", str(tmp_path)],
        capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    metrics = json.loads((tmp_path / "metrics.json").read_text())
    print(f"demo: {metrics['body_lengths_per_cycle_from_rest']:.2f} BL/cycle from rest in "
          f"{time.perf_counter() - start:.0f} s")  # fmt: skip
    assert metrics["body_lengths_per_cycle_from_rest"] >= 0.3
    assert (tmp_path / "swim.mp4").stat().st_size > 0
    assert np.isfinite(metrics["strouhal"])


def test_a_manoeuvre_is_searched_in_its_own_parameters_towards_its_own_goal(tmp_path):
    """Paper §5: offsets freed, the desired direction half way to the turn, its axis
    rewarded; the search starts from the straight gait and its gait file says which."""
    setup = prepare_optimization("eel2d", generations=1, popsize=4, seed=1, fluid="none",
                                 maneuver="turn-right", **COARSE)  # fmt: skip
    eel, objective = setup.creature, setup.objective
    assert setup.problem.names == eel.spec("turn-right").names
    np.testing.assert_array_equal(setup.problem.x0[: eel.gait.size], eel.default_gait)
    np.testing.assert_array_equal(setup.problem.x0[eel.gait.size :], 0.0)
    np.testing.assert_allclose(objective.direction, np.array([1.0, -1.0]) / np.sqrt(2))
    assert objective.axis == (0.0, 0.0, -1.0) and objective.maneuver == "turn-right"
    assert setup.config()["maneuver"] == "turn-right"
    bent = setup.problem.x0.copy()
    bent[eel.gait.size] = 0.6  # j1 bent 0.6 rad plus its 0.25 rad swing: past its 45 degrees
    assert setup.problem.feasible(setup.problem.x0) and not setup.problem.feasible(bent)
    result = run_optimization(setup, run_dir=tmp_path)
    from aquagait.app.optimize import best_swim, write_optimization

    write_optimization(setup, result, tmp_path, plot=False)
    assert json.loads((tmp_path / "gait.json").read_text())["maneuver"] == "turn-right"
    assert best_swim(setup, tmp_path).maneuver == "turn-right"


def test_a_2d_creature_cannot_learn_a_pitch():
    with pytest.raises(OptimizationSetupError, match="'pitch-up' is for 3D creatures"):
        prepare_optimization("eel2d", maneuver="pitch-up", fluid="none", **COARSE)


def test_a_search_starts_from_a_given_gait_with_a_given_spread(tmp_path):
    eel = ag.creatures.get("eel2d")
    setup = prepare_optimization("eel2d", start="hand-set", step=0.05, **COARSE)
    np.testing.assert_array_equal(setup.problem.x0, eel.gaits["hand-set"].params)
    width = eel.gait.upper - eel.gait.lower  # each parameter's spread: 5% of its range
    assert setup.problem.sigma0 * width / width.mean() == pytest.approx(0.05 * width)
    assert setup.config()["start"] == "hand-set" and setup.config()["step"] == 0.05
    turn = prepare_optimization("eel2d", maneuver="turn-left", start="hand-set", **COARSE)
    hand_set = eel.gait.unpack(eel.gaits["hand-set"].params)
    np.testing.assert_array_equal(turn.problem.x0, maneuver_start(eel, "turn-left", hand_set))
    with pytest.raises(OptimizationSetupError, match="shipped gaits: straight, hand-set"):
        prepare_optimization("eel2d", start="handset", **COARSE)
    with pytest.raises(OptimizationSetupError, match=r"step must be in \(0, 1\]"):
        prepare_optimization("eel2d", step=0.0, **COARSE)
    wide = write_gait(tmp_path / "wide.json", eel, np.r_[1.0, eel.default_gait[1:]])
    with pytest.raises(OptimizationSetupError, match=r"wide.json is outside its bounds: ampl"):
        prepare_optimization("eel2d", start=wide, **COARSE)


def test_a_grid_too_narrow_for_the_search_s_gaits_is_named_with_one_that_holds_them():
    """48x20 cells of 25 mm hold the straight eel (3.5 cm across and 8 cells of water either
    side), not its gaits: the shipped one takes 0.17 m across, 7 cells. The note counts the
    gaits drawn around the start that would not fit and names a resolution that holds nine
    in ten of them, where no note is given."""
    narrow = prepare_optimization("eel2d", resolution=(48, 20), cell_size=0.025)
    (note,) = narrow.notes
    found = re.search(r"(\d+) of 64 gaits drawn .* --resolution (\d+) (\d+) would hold", note)
    assert int(found[1]) > 16 and int(found[3]) > 20
    wider = (int(found[2]), int(found[3]))
    assert prepare_optimization("eel2d", resolution=wider, cell_size=0.025).notes == ()
    assert prepare_optimization("eel2d", **COARSE).notes == ()


def test_the_efficiency_objective_is_measured_in_the_starting_gaits_cost():
    setup = prepare_optimization("eel2d", objective="efficiency", cycles=3, **COARSE)
    objective = setup.objective
    speed, cost, _ = objective.cruise(setup.problem.x0)
    assert objective.reference_cost == cost and objective.seconds == 3.0
    assert objective.min_speed == pytest.approx(0.75 * speed)  # the default: 75 % of it
    # the start: its own cost (1), fast enough, plus its small drift and turn
    assert 1.0 < objective(setup.problem.x0) < 1.0 + 0.2 * 0.5
    config = setup.config()
    assert config["objective"] == "efficiency" and config["cruise_cycles"] == 2
    assert config["reference_cost_of_transport"] == cost and "efficiency" in setup.notes[0]
    # three cycles from rest are too few to cruise in (the third swims twice the first)
    assert "swum as a sample, is not yet at cruising speed after 3 cycle(s)" in setup.notes[1]
    settled = prepare_optimization("eel2d", objective="efficiency", cycles=7, **COARSE)
    assert not any("settled" in note for note in settled.notes)  # settled from cycle 4
    asked = prepare_optimization("eel2d", objective="efficiency", cycles=3, min_speed=10 * speed,
                                 **COARSE)  # fmt: skip
    assert asked.objective(setup.problem.x0) > 1 + 0.8 * 10  # 90 % short of its speed


def test_an_efficiency_search_whose_best_gait_has_not_settled_says_so(tmp_path, capsys):
    """Three cycles from rest are too few for eel2d to cruise in, for its start and so for
    the gaits drawn about it: the swim of the best gait after the search, as long as a
    sample, says the search ranked them before their cruise, on the terminal and in its
    config.json, and how to search again from it."""
    out = tmp_path / "eel"
    argv = ["optimize", "eel2d", "--objective", "efficiency", "--cycles", "3", "--generations",
            "1", "--popsize", "2", "--workers", "1", "--resolution", "48", "28", "--cell-size",
            "0.025", "--out", str(out), "--no-video"]  # fmt: skip
    assert cli.main(argv) == 0
    printed = capsys.readouterr().out
    assert "not yet at cruising speed after 3 cycle(s)" in printed  # the swim's own note
    said = re.search(r"the best gait has not settled within a sample's 3 cycles .* search "
                     r"again with more --cycles, from it \(--start (\S+) ", printed)  # fmt: skip
    assert said and Path(said[1]) == out / "gait.json"
    notes = json.loads((out / "config.json").read_text())["notes"]
    assert any(note.startswith("an efficiency search: the best gait") for note in notes)


@pytest.mark.parametrize(
    "flags, message",
    [
        ({"objective": "speed"}, "unknown objective 'speed'; objectives: distance, efficiency"),
        ({"objective": "efficiency", "maneuver": "turn-left"}, "efficiency objective is for"),
        ({"min_speed": 0.2}, "--min-speed is for --objective efficiency"),
        ({"objective": "efficiency", "min_speed": -1.0}, "min speed must be a speed > 0"),
        ({"objective": "efficiency", "cycles": 2}, "give at least 3 cycles, got 2"),
    ],
)
def test_bad_efficiency_settings_say_what_would_be_right(flags, message):
    with pytest.raises(OptimizationSetupError, match=message):
        prepare_optimization("eel2d", **COARSE, **flags)


def test_a_search_carried_to_the_next_session_goes_on_where_it_stopped(tmp_path, monkeypatch):
    """``tools/carry_searches.py``: a run's best so far becomes a leg (a gait file that
    swims); a search continued from it starts at that gait with the spread reached, so its
    start scores the leg's objective again (the swim is deterministic); while it runs, it
    resumes against the leg it started from; its leg follows that one and names it, and is
    replaced when carried again; a leg that finished its search stops the lane."""
    import carry_searches as carry

    monkeypatch.setattr(carry, "ROOT", tmp_path)
    monkeypatch.setattr(carry, "CARRIED", tmp_path / "carried")
    lane = ["optimize", "eel2d", "--generations", "2", "--popsize", "4", "--workers", "1",
            "--resolution", "48", "28", "--cell-size", "0.025", "--no-video"]  # fmt: skip
    first = tmp_path / "runs" / "eel"
    assert carry.continuation("eel") == []  # nothing yet: the lane's own start
    assert cli.main([*lane, "--out", str(first)]) == 0
    leg = carry.carry(first)
    gait = json.loads(leg.read_text())
    assert leg.name == "eel.leg1.json" and gait["carried"]["from"] == "the search's own start"
    assert gait["params"] == json.loads((first / "gait.json").read_text())["params"]
    assert gait["carried"]["finished"] and gait["carried"]["generations"] == 2
    first.rename(tmp_path / "lost")  # the next session's machine: runs/ is gone
    with pytest.raises(SystemExit) as finished:
        carry.continuation("eel")
    assert finished.value.code == 3

    # as if carried before it finished: the next session goes on from the leg
    gait["carried"]["finished"] = False
    leg.write_text(json.dumps(gait))
    more = carry.continuation("eel")
    assert more == ["--start", "carried/eel.leg1.json", "--step", f"{gait['carried']['step']:.4g}"]
    more[1] = str(tmp_path / more[1])
    second = tmp_path / "runs" / "eel"
    assert cli.main([*lane, "--out", str(second), *more]) == 0
    config = json.loads((second / "config.json").read_text())["optimization"]
    assert config["step"] == pytest.approx(gait["carried"]["step"], rel=1e-3)
    start_f = checkpoint.load(second)["run"]["start_f"]
    assert start_f == pytest.approx(gait["carried"]["objective"], rel=1e-6)
    assert carry.continuation("eel")[:3] == ["--resume", "--start", "carried/eel.leg1.json"]
    later = carry.carry(second)
    assert later.name == "eel.leg2.json"
    assert json.loads(later.read_text())["carried"]["from"] == "eel.leg1.json"
    assert carry.carry(second) == later  # carried again: the same leg, not a third
    assert carry.summary()[2].startswith("| `eel` | 2 | 4 |")  # two legs of 2 generations


def test_a_carried_grouped_search_keeps_the_spread_of_the_group_it_was_in():
    """The frog's search runs its groups in turn, each with a CMA-ES over its own
    parameters: the spread carried is the group's, each standard deviation a share of its
    own parameter's range (``--step``'s unit)."""
    import carry_searches as carry

    width = np.array([1.0, 2.0, 4.0, 8.0])
    es = type("Group", (), {"stds": np.array([0.4, 0.8])})()  # 10 % of widths 4 and 8
    progress = {"es": es, "group": 1, "history": []}
    assert carry._spread(progress, width, [[0, 1], [2, 3]]) == pytest.approx(0.1)
    ungrouped = {"es": type("All", (), {"stds": 0.05 * width})(), "group": 0, "history": []}
    assert carry._spread(ungrouped, width, []) == pytest.approx(0.05)
