"""The swim job: settings checked before simulating, the run kept in its directory."""

import numpy as np
import pytest

from aquagait.app import (
    SetupError,
    SwimSetupError,
    output_directory,
    prepare_swim,
    run_swim,
    write_swim,
)
from aquagait.io import read_gait, read_run, write_gait


def test_swim_settings_are_checked_before_simulating(tmp_path, eel):
    with pytest.raises(
        SwimSetupError, match="unknown creature 'eal'; known creatures: accordion2d, alien, eel2d"
    ):
        prepare_swim("eal")
    with pytest.raises(SwimSetupError, match="has 3 entries but .* is 2D"):
        prepare_swim("eel2d", fluid="none", resolution=(8, 8, 8))
    with pytest.raises(SwimSetupError, match="unknown fluid 'air'"):
        prepare_swim("eel2d", fluid="air")
    with pytest.raises(SwimSetupError, match="seconds must be a positive number"):
        prepare_swim("eel2d", fluid="none", seconds=0)
    with pytest.raises(SwimSetupError, match="does not exist"):
        prepare_swim("eel2d", gait=tmp_path / "none.json", fluid="none")
    with pytest.raises(SwimSetupError, match="has 8 gait parameters"):
        prepare_swim("eel2d", gait=[0.1, 0.2], fluid="none")


def test_a_swim_is_kept_in_its_run_directory(tmp_path, eel):
    gait = write_gait(tmp_path / "mine.json", eel, eel.default_gait * 0.5)
    setup = prepare_swim("eel2d", gait=gait, seconds=2.0, fluid="none", resolution=(64, 32))
    calls = []
    run = run_swim(setup, progress=lambda done, total: calls.append((done, total)))
    assert calls[0] == (1, 60) and calls[-1] == (60, 60)
    assert run.metrics["tail_amplitude"] > 0  # two cycles: steady figures
    (note,) = run.notes  # but too few to tell a cruise
    assert note.startswith("not yet at cruising speed after 2 cycle(s) (settled: within 2%)")
    assert not run.metrics["settled"] and run.grid_notes == ()
    out = write_swim(run, tmp_path / "runs" / "eel2d")
    names = {"config.json", "gait.json", "trajectory.npz", "metrics.json"}
    assert {p.name for p in out.iterdir()} == names
    back = read_run(out)
    for name in ("time", "qpos", "qvel", "torque", "energy"):
        np.testing.assert_array_equal(getattr(run.trajectory, name), getattr(back.trajectory, name))
    config = back.config
    assert config["resolution"] == [64, 32] and config["cell_size"] == eel.cell_size
    assert config["fluid"] == "none" and config["fps"] == 30 and config["frames"] == 61
    assert config["gait"]["source"] == str(gait) and config["dt"] == pytest.approx(1 / 300)
    np.testing.assert_allclose(read_gait(out / "gait.json", eel).params, eel.default_gait * 0.5)


def test_a_swim_shorter_than_two_cycles_says_what_it_cannot_measure(eel):
    run = run_swim(prepare_swim("eel2d", seconds=0.2, fluid="none"))
    assert "strouhal" not in run.metrics and "steady_speed" not in run.metrics
    assert "distance" in run.metrics and "speed_from_rest" in run.metrics
    assert "less than two gait cycles of 1 s: no steady figures" in run.notes[0]


def test_an_output_directory_that_cannot_be_written_is_a_setup_error():
    with pytest.raises(SetupError, match="cannot write the run directory /proc/x: .* --out"):
        output_directory("/proc/x")


def test_a_learned_manoeuvre_swims_its_shipped_gait(tmp_path):
    setup = prepare_swim("eel2d", maneuver="turn-left", seconds=0.2, fluid="none")
    eel = setup.creature
    assert setup.maneuver == "turn-left" and setup.spec is eel.spec("turn-left")
    np.testing.assert_array_equal(setup.params, eel.maneuver_gait("turn-left"))
    out = write_swim(run_swim(setup), tmp_path / "run")
    assert read_gait(out / "gait.json", eel).maneuver == "turn-left"
    with pytest.raises(SwimSetupError, match="accordion2d has not learned 'turn-left'"):
        prepare_swim("accordion2d", maneuver="turn-left", fluid="none")
    with pytest.raises(SwimSetupError, match="a gait or a manoeuvre, not both"):
        prepare_swim("eel2d", gait=out / "gait.json", maneuver="turn-left", fluid="none")


def test_a_shipped_gait_swims_by_its_name(eel):
    hand_set = prepare_swim("eel2d", gait="hand-set", seconds=0.2, fluid="none")
    np.testing.assert_array_equal(hand_set.params, eel.gaits["hand-set"].params)
    assert hand_set.maneuver == "straight" and hand_set.gait_source == "shipped hand-set"
    turn = prepare_swim("eel2d", gait="turn-left", seconds=0.2, fluid="none")
    assert turn.maneuver == "turn-left" and turn.spec is eel.spec("turn-left")
    np.testing.assert_array_equal(turn.params, eel.maneuver_gait("turn-left"))
    with pytest.raises(SwimSetupError, match="eel2d's shipped gaits: straight, hand-set, turn"):
        prepare_swim("eel2d", gait="optimised", fluid="none")
