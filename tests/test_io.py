"""Run directories, trajectories and gait files on disk."""

import json

import numpy as np
import pytest

from aquagait.io import (
    GaitFileError,
    load_trajectory,
    prepare_directory,
    read_gait,
    read_run,
    save_trajectory,
    write_gait,
    write_run,
)
from aquagait.sim import FluidFrames, Trajectory


def random_trajectory(model, frames=5, plane=(6, 4), seed=0):
    rng = np.random.default_rng(seed)
    fluid = FluidFrames(
        cell_size=0.01,
        origin=rng.normal(size=(frames, 2)),
        velocity=rng.normal(size=(frames, 2, *plane)).astype(np.float32),
        solid=rng.random((frames, *plane)) < 0.3,
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
        assert a.fluid.cell_size == b.fluid.cell_size


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

    with pytest.raises(GaitFileError, match=r"has 3 gait parameters; eel2d's straight gait has 8"):
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
    with pytest.raises(GaitFileError, match="'maneuver' is 'loop'; manoeuvres are straight, "):
        read_gait(gait_file(maneuver="loop"), eel)
    # a turn's vector (offsets free: 12 numbers) under the straight gait's name is refused
    with pytest.raises(GaitFileError, match="turn-left gait has 12"):
        read_gait(gait_file(maneuver="turn-left"), eel)


def test_a_manoeuvre_s_gait_file_says_which_and_is_read_in_its_parameterization(tmp_path, eel):
    params = np.r_[eel.default_gait, [0.1, 0.2, 0.0, -0.1]]
    path = write_gait(tmp_path / "gait.json", eel, params, "turn-left")
    gait = read_gait(path, eel)
    assert gait.maneuver == "turn-left" and gait.names == eel.spec("turn-left").names
    np.testing.assert_array_equal(gait.params, params)
    data = json.loads(path.read_text())
    del data["maneuver"]  # a file without it is a straight gait
    data.update(params=[0.1] * 8, names=list(eel.gait.names))
    assert read_gait(_write(tmp_path / "old.json", json.dumps(data)), eel).maneuver == "straight"


def _write(path, text):
    path.write_text(text)
    return path


# --- swims ---------------------------------------------------------------------------


def test_a_directory_that_cannot_be_written_is_named_with_the_reason(tmp_path):
    assert prepare_directory(tmp_path / "a" / "b").is_dir()
    with pytest.raises(OSError, match="cannot write the run directory /proc/x"):
        prepare_directory("/proc/x")
    (tmp_path / "file").write_text("")
    with pytest.raises(OSError, match="Not a directory"):
        prepare_directory(tmp_path / "file" / "run")
