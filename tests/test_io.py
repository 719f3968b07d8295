"""Run directories, trajectories and gait files on disk; preparing and keeping a swim."""

import json

import numpy as np
import pytest

import aquagait as ag
from aquagait.io import (
    GaitFileError,
    SwimSetupError,
    load_trajectory,
    prepare_swim,
    read_gait,
    read_run,
    run_swim,
    save_trajectory,
    write_gait,
    write_run,
    write_swim,
)
from aquagait.sim import FluidFrames, Trajectory


@pytest.fixture(scope="module")
def eel():
    return ag.creatures.get("eel2d")


def random_trajectory(model, frames=5, plane=(6, 4), seed=0):
    rng = np.random.default_rng(seed)
    fluid = FluidFrames(
        cell_size=0.01,
        origin=rng.normal(size=(frames, 2)),
        velocity=rng.normal(size=(frames, 2, *plane)).astype(np.float32),
        solid=rng.random((frames, *plane)) < 0.3,
        plane_z=0.02,
    )
    per_dof = {k: rng.normal(size=(frames, model.nv)) for k in ("qvel", "torque", "energy")}
    qpos = np.tile(model.qpos0, (frames, 1)) + 0.01 * rng.normal(size=(frames, model.nq))
    time = np.arange(frames) / 30
    return Trajectory(time, qpos, **per_dof, dt=1 / 300, fps=30.0, fluid=fluid)


def assert_same(a: Trajectory, b: Trajectory):
    for name in ("time", "qpos", "qvel", "torque", "energy"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert (a.dt, a.fps) == (b.dt, b.fps)
    assert (a.fluid is None) == (b.fluid is None)
    if a.fluid is not None:
        for name in ("origin", "velocity", "solid"):
            x, y = getattr(a.fluid, name), getattr(b.fluid, name)
            np.testing.assert_array_equal(x, y)
            assert x.dtype == y.dtype
        assert (a.fluid.cell_size, a.fluid.plane_z) == (b.fluid.cell_size, b.fluid.plane_z)


# --- run directories ---------------------------------------------------------------


def test_a_run_directory_reads_back(tmp_path, eel):
    traj = random_trajectory(eel.model)
    metrics = {"distance": 0.3, "strouhal": float("inf"), "cost_of_transport": float("nan")}
    out = write_run(tmp_path / "run", traj, {"creature": "eel2d", "origin": np.zeros(2)}, metrics)
    run = read_run(out)
    assert_same(traj, run.trajectory)
    assert run.config["creature"] == "eel2d" and run.config["origin"] == [0.0, 0.0]
    assert set(run.config["versions"]) == {"aquagait", "numpy", "scipy", "numba", "mujoco"}
    assert run.config["versions"]["numpy"] == np.__version__
    # strict JSON: undefined numbers are null, units ride along
    assert run.metrics["strouhal"] is None and run.metrics["cost_of_transport"] is None
    assert run.metrics["units"]["distance"] == "m"
    json.loads((out / "metrics.json").read_text(), parse_constant=pytest.fail)


def test_a_vacuum_trajectory_round_trips_with_the_root_pose(tmp_path, eel):
    traj = random_trajectory(eel.model)
    traj = Trajectory(traj.time, traj.qpos, traj.qvel, traj.torque, traj.energy, 0.01, 30.0)
    path = save_trajectory(tmp_path / "vacuum.npz", traj, model=eel.model)
    assert_same(traj, load_trajectory(path))
    with np.load(path) as data:
        root = data["root_position"]
    np.testing.assert_allclose(root[:, :2] - traj.qpos[:, :2], [[0.2, 0]] * 5, atol=0.05)


def test_missing_and_foreign_files_are_named(tmp_path):
    with pytest.raises(FileNotFoundError, match="not a run directory: it has no config.json"):
        read_run(tmp_path)
    with pytest.raises(FileNotFoundError, match="no trajectory at"):
        load_trajectory(tmp_path / "nothing.npz")
    np.savez(tmp_path / "other.npz", x=np.zeros(3))
    with pytest.raises(ValueError, match=r"not an aquagait trajectory: it lacks \['time'"):
        load_trajectory(tmp_path / "other.npz")


# --- gait files ----------------------------------------------------------------------


def test_gait_files_round_trip(tmp_path, eel):
    params = eel.default_gait * 0.9
    path = write_gait(tmp_path / "gait.json", eel, params)
    gait = read_gait(path, eel)
    assert gait.creature == "eel2d" and gait.names == eel.gait.names
    np.testing.assert_array_equal(gait.params, params)
    assert read_gait(path).creature == "eel2d"  # without a creature: no checks


def test_gait_files_that_do_not_fit_are_refused(tmp_path, eel):
    def gait_file(**fields):
        data = {"creature": "eel2d", "names": list(eel.gait.names), "params": [0.1] * 8}
        path = tmp_path / "g.json"
        path.write_text(json.dumps({**data, **fields}))
        return path

    with pytest.raises(GaitFileError, match=r"has 3 gait parameters; eel2d has 8: amplitude\[j1\]"):
        read_gait(gait_file(names=["a", "b", "c"], params=[1, 2, 3]), eel)
    with pytest.raises(GaitFileError, match="is a gait for 'fish', not for 'eel2d'"):
        read_gait(gait_file(creature="fish"), eel)
    with pytest.raises(GaitFileError, match="expects amplitude"):
        read_gait(gait_file(names=list(reversed(eel.gait.names))), eel)
    with pytest.raises(GaitFileError, match="same length"):
        read_gait(gait_file(params=[0.1] * 7), eel)
    with pytest.raises(GaitFileError, match="finite numbers"):
        read_gait(gait_file(params=[0.1] * 7 + [float("nan")]), eel)
    with pytest.raises(GaitFileError, match="list of numbers"):
        read_gait(gait_file(params=["x"] * 8), eel)
    with pytest.raises(GaitFileError, match="'creature', 'names' and 'params'"):
        read_gait(_write(tmp_path / "h.json", "[1, 2]"), eel)
    with pytest.raises(GaitFileError, match="not valid JSON"):
        read_gait(_write(tmp_path / "h.json", "{creature"), eel)
    with pytest.raises(GaitFileError, match="does not exist"):
        read_gait(tmp_path / "none.json", eel)
    with pytest.raises(GaitFileError, match="has 2 gait parameters"):
        write_gait(tmp_path / "w.json", eel, [1.0, 2.0])


def _write(path, text):
    path.write_text(text)
    return path


# --- swims ---------------------------------------------------------------------------


def test_swim_settings_are_checked_before_simulating(tmp_path, eel):
    with pytest.raises(
        SwimSetupError, match="unknown creature 'eal'; known creatures: accordion2d, eel2d"
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
    assert run.notes == () and run.metrics["tail_amplitude"] > 0  # two cycles: steady figures
    out = write_swim(run, tmp_path / "runs" / "eel2d")
    names = {"config.json", "gait.json", "trajectory.npz", "metrics.json"}
    assert {p.name for p in out.iterdir()} == names
    back = read_run(out)
    assert_same(run.trajectory, back.trajectory)
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
