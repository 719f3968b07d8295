"""Checkpoints: a run killed at any moment, SIGKILL included, resumes to exactly its result."""

import csv
import os
import pickle
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from optimize_cases import (
    KILLED_SETTINGS,
    Recorder,
    Sphere,
    killed_problem,
    same_run,
    sphere_problem,
    within,
)

from aquagait.optimize import CHECKPOINT, LOG, CorruptCheckpoint, Settings, checkpoint, optimize

HERE = Path(__file__).resolve().parent


def log_without_time(run_dir: Path) -> list[dict]:
    with (run_dir / LOG).open() as file:
        return [{k: v for k, v in row.items() if k != "elapsed"} for row in csv.DictReader(file)]


def saved_progress(run_dir: Path) -> tuple[int, int]:
    """(generations, evaluations) in run_dir's checkpoint; (0, 0) before the first."""
    try:
        run = checkpoint.load(run_dir)["run"]
    except FileNotFoundError:
        return 0, 0
    return len(run["history"]), run["evaluations"]


def test_a_run_killed_with_sigkill_mid_generation_resumes_to_the_same_result(tmp_path):
    run_dir, calls = tmp_path / "killed", tmp_path / "calls.txt"
    # The start is the first call, then generations evaluate 8 samples each (no sample hits
    # the resampling cap), so the 20th call is the 3rd of generation 3: the objective hangs
    # there until killed.
    hang_at = 1 + 2 * KILLED_SETTINGS.popsize + 3
    output = (tmp_path / "output.txt").open("w")
    script = [sys.executable, str(HERE / "optimize_cases.py"), str(run_dir), str(calls)]
    process = subprocess.Popen([*script, str(hang_at)], stdout=output, stderr=subprocess.STDOUT)
    try:
        deadline = time.monotonic() + 60
        while not (calls.exists() and len(calls.read_text().splitlines()) >= hang_at):
            assert process.poll() is None, (tmp_path / "output.txt").read_text()
            assert time.monotonic() < deadline, "the run never reached the call to kill it in"
            time.sleep(0.01)
        os.kill(process.pid, signal.SIGKILL)
        assert process.wait(timeout=10) == -signal.SIGKILL
    finally:
        if process.poll() is None:
            process.kill()
            process.wait(timeout=10)
        output.close()
    assert saved_progress(run_dir) == (2, 1 + 2 * KILLED_SETTINGS.popsize)  # died in gen. 3

    resumed = optimize(killed_problem(), KILLED_SETTINGS, run_dir=run_dir, resume=True)
    whole = optimize(killed_problem(), KILLED_SETTINGS, run_dir=tmp_path / "whole")
    same_run(resumed, whole)
    assert resumed.generations == KILLED_SETTINGS.generations
    assert sum(row["resamples"] for row in whole.history) > 0  # the redraws were replayed too
    assert log_without_time(run_dir) == log_without_time(tmp_path / "whole")


class Abort(BaseException):
    """Stands for a kill: not an Exception, so no failure handler catches it."""


class AbortAt:
    """The objective, except that call number `at` aborts the run."""

    def __init__(self, objective, at: int):
        self.objective, self.at, self.calls = objective, at, 0

    def __call__(self, x):
        self.calls += 1
        if self.calls == self.at:
            raise Abort
        return self.objective(x)


GROUPS = (np.array([0, 1]), np.array([2, 3]))
GROUPED = Settings(popsize=6, generations=5, seed=11)


def grouped(objective=None):
    objective = Sphere(np.ones(4)) if objective is None else objective
    return sphere_problem(4, objective, feasible=within, groups=GROUPS)


# Evaluation 1 is the start, 2-31 group 0's five generations, 32-61 group 1's.
@pytest.mark.parametrize("at", [8, 13, 14, 31, 32, 37, 60])
def test_a_run_aborted_mid_generation_resumes_to_the_same_result(tmp_path, at):
    whole = optimize(grouped(), GROUPED)
    with pytest.raises(Abort):
        optimize(grouped(AbortAt(Sphere(np.ones(4)), at)), GROUPED, run_dir=tmp_path)
    same_run(whole, optimize(grouped(), GROUPED, run_dir=tmp_path, resume=True))


@pytest.mark.parametrize("after", [1, 5, 6, 9])
def test_a_run_aborted_between_generations_resumes_to_the_same_result(tmp_path, after):
    def abort_after(report):
        if report.generation == after:
            raise Abort

    whole = optimize(grouped(), GROUPED)
    with pytest.raises(Abort):
        optimize(grouped(), GROUPED, run_dir=tmp_path, progress=abort_after)
    assert saved_progress(tmp_path)[0] == after
    same_run(whole, optimize(grouped(), GROUPED, run_dir=tmp_path, resume=True))


def test_a_run_resumed_twice_still_matches(tmp_path):
    whole = optimize(grouped(), GROUPED)
    for at in (20, 25):  # the second abort is 25 calls into the first resumed session
        with pytest.raises(Abort):
            problem = grouped(AbortAt(Sphere(np.ones(4)), at))
            optimize(problem, GROUPED, run_dir=tmp_path, resume=(tmp_path / CHECKPOINT).exists())
    same_run(whole, optimize(grouped(), GROUPED, run_dir=tmp_path, resume=True))


def test_a_finished_run_resumes_to_its_result_without_evaluating(tmp_path):
    first = optimize(grouped(), GROUPED, run_dir=tmp_path)
    recorder = Recorder(Sphere(np.ones(4)))
    again = optimize(grouped(recorder), GROUPED, run_dir=tmp_path, resume=True)
    same_run(first, again)
    assert recorder.calls == []


def test_a_checkpoint_with_other_settings_is_refused(tmp_path):
    optimize(grouped(), GROUPED, run_dir=tmp_path)
    other = Settings(popsize=8, generations=5, seed=11)
    with pytest.raises(ValueError, match="popsize: 6 in the checkpoint, 8 now"):
        optimize(grouped(), other, run_dir=tmp_path, resume=True)
    with pytest.raises(ValueError, match="seed: 11 in the checkpoint, 12 now"):
        optimize(
            grouped(), Settings(popsize=6, generations=5, seed=12), run_dir=tmp_path, resume=True
        )
    with pytest.raises(ValueError, match="parameters: 4 in the checkpoint, 5 now"):
        optimize(sphere_problem(5, groups=GROUPS), GROUPED, run_dir=tmp_path, resume=True)


class Scaled(Sphere):
    """A sphere times a weight, which its fingerprint names (as a swim's objective does)."""

    def __init__(self, center, weight: float):
        super().__init__(center)
        self.weight = weight

    def __call__(self, x):
        return self.weight * super().__call__(x)

    def fingerprint(self) -> dict:
        return {"kind": "scaled sphere", "terms": {"weight": self.weight}}


def test_a_checkpoint_of_another_objective_is_refused_and_an_older_one_resumes(tmp_path):
    def scaled(weight: float):
        return sphere_problem(4, Scaled(np.ones(4), weight), groups=GROUPS)

    first = optimize(scaled(2.0), GROUPED, run_dir=tmp_path)
    with pytest.raises(ValueError, match=r"objective\.terms\.weight: 2\.0 in the checkpoint, 3\.0"):
        optimize(scaled(3.0), GROUPED, run_dir=tmp_path, resume=True)
    same_run(first, optimize(scaled(2.0), GROUPED, run_dir=tmp_path, resume=True))
    # a checkpoint from before objectives were fingerprinted resumes
    state = checkpoint.load(tmp_path)
    del state["fingerprint"]["objective"]
    checkpoint.save(tmp_path, state)
    same_run(first, optimize(scaled(3.0), GROUPED, run_dir=tmp_path, resume=True))


def test_resume_needs_a_checkpoint_and_a_new_run_never_overwrites_one(tmp_path):
    with pytest.raises(FileNotFoundError, match="nothing to resume"):
        optimize(grouped(), GROUPED, run_dir=tmp_path, resume=True)
    with pytest.raises(ValueError, match="needs the run_dir"):
        optimize(grouped(), GROUPED, resume=True)
    optimize(grouped(), Settings(popsize=6, generations=1), run_dir=tmp_path)
    with pytest.raises(FileExistsError, match="already holds an optimization checkpoint"):
        optimize(grouped(), GROUPED, run_dir=tmp_path)


@pytest.mark.parametrize(
    "damage", [b"garbage", b"", pickle.dumps([1, 2]), b"\x80\x05\x95 truncated"]
)
def test_a_damaged_checkpoint_is_refused_by_name_and_nothing_else_is_touched(tmp_path, damage):
    optimize(grouped(), GROUPED, run_dir=tmp_path)
    (tmp_path / CHECKPOINT).write_bytes(damage)
    before = {path.name: path.read_bytes() for path in tmp_path.iterdir()}
    with pytest.raises(CorruptCheckpoint) as refused:
        optimize(grouped(), GROUPED, run_dir=tmp_path, resume=True)
    message = str(refused.value)
    assert f"the checkpoint {tmp_path / CHECKPOINT} cannot be read" in message
    assert f"Nothing else in {tmp_path} was touched" in message and "Restore" in message
    assert {path.name: path.read_bytes() for path in tmp_path.iterdir()} == before


def test_the_log_has_a_row_per_generation_and_the_best_parameters(tmp_path):
    problem = sphere_problem(3, names=("amplitude", "phase", "period"))
    result = optimize(problem, Settings(popsize=6, generations=4), run_dir=tmp_path)
    with (tmp_path / LOG).open() as file:
        rows = list(csv.DictReader(file))
    assert list(rows[0])[:7] == [
        "generation",
        "group",
        "evaluations",
        "best",
        "mean",
        "sigma",
        "elapsed",
    ]
    assert list(rows[0])[-3:] == ["amplitude", "phase", "period"]
    assert [int(row["generation"]) for row in rows] == [1, 2, 3, 4]
    assert [float(row["best"]) for row in rows] == [row["best"] for row in result.history]
    assert [float(rows[-1][name]) for name in problem.names] == result.best_x.tolist()


def test_writes_are_atomic_and_half_written_files_are_swept(tmp_path, monkeypatch):
    optimize(grouped(), Settings(popsize=6, generations=1), run_dir=tmp_path)
    before = (tmp_path / CHECKPOINT).read_bytes()

    def killed_before_rename(source, target):
        raise Abort  # as if the process died between writing and renaming

    monkeypatch.setattr(os, "replace", killed_before_rename)
    with pytest.raises(Abort):
        checkpoint.save(tmp_path, {"run": "torn"})
    monkeypatch.undo()
    assert (tmp_path / CHECKPOINT).read_bytes() == before
    assert list(tmp_path.glob(".checkpoint.pkl.*")) == []  # cleaned up on the way out
    (tmp_path / ".checkpoint.pkl.abc123").write_bytes(b"half a pickle")  # a SIGKILL's leftover
    optimize(grouped(), Settings(popsize=6, generations=1), run_dir=tmp_path, resume=True)
    assert list(tmp_path.glob(".checkpoint.pkl.*")) == []
    assert pickle.loads(before)["run"]["finished"]
