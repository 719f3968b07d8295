"""lq-CMA-ES (Settings.surrogate): fewer real evaluations, and everything else as without it."""

import concurrent.futures as cf

import numpy as np
import pytest
from optimize_cases import (
    Faulty,
    Recorder,
    RotatedEllipsoid,
    Sphere,
    same_run,
    sphere_problem,
    within,
)

from aquagait.optimize import Problem, Settings, cmaes, local_executor, optimize
from aquagait.optimize.surrogate import TAU_TRUTH, Surrogate

SURROGATE = Settings(seed=3, surrogate=True)


def ellipsoid(n: int = 6, **fields) -> Problem:
    objective = RotatedEllipsoid(np.linspace(-1, 1, n), cond=1e2)
    return Problem(objective, np.zeros(n), -4 * np.ones(n), 4 * np.ones(n), sigma0=1.0, **fields)


def evaluations_to(result, target: float) -> int:
    return next(row["evaluations"] for row in result.history if row["best"] < target)


def test_on_a_quadratic_the_surrogate_finds_the_same_minimum_with_a_fraction_of_the_evaluations():
    """lq-CMA-ES's model is exact on a quadratic, so it vouches for most rankings: Hansen (2019)
    reports 3-10 times fewer evaluations on ellipsoids (here 3.6-4.7 to 1e-4); we ask for 3."""
    plain = optimize(ellipsoid(), Settings(seed=3, generations=120))
    modelled = optimize(ellipsoid(), Settings(seed=3, generations=120, surrogate=True))
    assert evaluations_to(modelled, 1e-4) < evaluations_to(plain, 1e-4) / 3
    assert modelled.best_f < 1e-8
    assert sum(row["modelled"] for row in modelled.history) > 0
    assert all(row["modelled"] == 0 for row in plain.history)


def test_evaluations_count_real_calls_and_max_evaluations_caps_them_exactly():
    recorder = Recorder(Sphere(np.ones(5)))
    for cap in (7, 23, 40):
        recorder.calls.clear()
        result = optimize(sphere_problem(5, recorder), Settings(seed=1, max_evaluations=cap,
                                                                 surrogate=True))  # fmt: skip
        assert len(recorder.calls) == result.evaluations == cap
        assert result.history[-1]["evaluations"] == cap
        assert result.stopped == f"max_evaluations ({cap})"


class MapRecorder:
    """A map-only executor that evaluates here and keeps the size of every batch."""

    def __init__(self):
        self.batches: list[int] = []

    def map(self, fn, *iterables):
        jobs = list(zip(*iterables, strict=True))
        self.batches.append(len(jobs))
        return [fn(*job) for job in jobs]


@pytest.mark.parametrize("batch", [2, 3, 4])
def test_real_evaluations_are_asked_for_in_batches_of_at_least_the_batch(batch):
    executor = MapRecorder()
    settings = Settings(popsize=12, seed=2, generations=15, surrogate=True, surrogate_batch=batch)
    result = optimize(ellipsoid(), settings, executor)
    popsize = result.history[0]["samples"]
    assert executor.batches[0] == 1  # the start, alone
    swum = np.diff([1] + [row["evaluations"] for row in result.history])
    assert all(size >= batch for size in executor.batches[1:])
    assert all(swum >= min(batch, popsize)) and sum(executor.batches) == result.evaluations
    assert any(swum < popsize)  # the model spared some swims


def test_serial_processes_and_threads_give_the_same_search():
    problem = sphere_problem(5, Faulty(Sphere(np.ones(5))), feasible=within)
    settings = Settings(seed=5, generations=12, surrogate=True, surrogate_batch=3)
    serial = optimize(problem, settings)
    with local_executor(2) as processes:
        in_processes = optimize(problem, settings, processes)
    with cf.ThreadPoolExecutor(2) as threads:
        in_threads = optimize(problem, settings, threads)
    same_run(serial, in_processes)
    same_run(serial, in_threads)
    assert sum(row["failures"] + row["infeasible"] for row in serial.history) > 0


class Abort(BaseException):
    """Stands for a kill: not an Exception, so no failure handler catches it."""


class AbortAt:
    def __init__(self, objective, at: int):
        self.objective, self.at, self.calls = objective, at, 0

    def __call__(self, x):
        self.calls += 1
        if self.calls == self.at:
            raise Abort
        return self.objective(x)


GROUPED = Settings(popsize=6, generations=8, seed=11, surrogate=True)
GROUPS = (np.array([0, 1, 2]), np.array([3, 4]))


@pytest.mark.parametrize("at", [9, 14, 30, 41])
def test_a_run_aborted_mid_generation_resumes_to_the_uninterrupted_result(tmp_path, at):
    def problem(objective):
        return sphere_problem(5, objective, groups=GROUPS)

    whole = optimize(problem(Sphere(np.ones(5))), GROUPED)
    assert whole.evaluations > at
    with pytest.raises(Abort):
        optimize(problem(AbortAt(Sphere(np.ones(5)), at)), GROUPED, run_dir=tmp_path)
    resumed = optimize(problem(Sphere(np.ones(5))), GROUPED, run_dir=tmp_path, resume=True)
    same_run(whole, resumed)


def test_a_checkpoint_with_and_one_without_the_surrogate_are_told_apart(tmp_path):
    problem = sphere_problem(3)
    optimize(problem, Settings(seed=1, generations=2), run_dir=tmp_path)
    with pytest.raises(ValueError, match="surrogate: None in the checkpoint, True now"):
        optimize(problem, Settings(seed=1, generations=2, surrogate=True), run_dir=tmp_path,
                 resume=True)  # fmt: skip


def test_each_group_gets_its_own_model_and_failed_samples_never_enter_it(monkeypatch):
    made = []

    class Watched(cmaes.Surrogate):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            made.append(self)

    monkeypatch.setattr(cmaes, "Surrogate", Watched)
    problem = sphere_problem(4, Faulty(Sphere(np.ones(4))), groups=(np.array([0, 1, 2]), [3]))
    result = optimize(problem, Settings(seed=4, generations=10, surrogate=True))
    assert [row["group"] for row in result.history] == [0] * 10 + [1] * 10
    assert sum(row["failures"] for row in result.history) > 0
    assert [np.shape(surrogate.model.X)[1] for surrogate in made] == [3, 1]
    assert all(np.isfinite(surrogate.model.F).all() for surrogate in made)  # no nan
    assert all(value < 1e6 for surrogate in made for value in surrogate.model.F)  # no penalty


def test_the_model_vouches_only_with_enough_agreeing_points():
    """Rank a population of a known quadratic: the first generation swims at least 5 (the
    model's minimum), and once the model has seen enough, it ranks a new population by
    swimming fewer than half of it, in the true order."""
    rng = np.random.default_rng(0)
    quadratic = Sphere([0.5, -0.5, 0.2])
    surrogate = Surrogate(popsize=12, batch=2)
    calls = []

    def swim(indices):
        calls.append(len(indices))
        return {i: quadratic(population[i]) for i in indices}

    for _ in range(6):
        population = dict(enumerate(rng.standard_normal((12, 3))))
        calls.clear()
        values = surrogate.rank(population, swim)
    assert calls[0] >= 2 and sum(calls) < 6 and surrogate.tau >= TAU_TRUTH
    order = sorted(population, key=lambda i: values[i])
    assert order == sorted(population, key=lambda i: quadratic(population[i]))


def test_settings_check_the_surrogate():
    with pytest.raises(ValueError, match="surrogate_batch must be an integer >= 1"):
        Settings(surrogate=True, surrogate_batch=0)
    with pytest.raises(ValueError, match="surrogate must be True or False"):
        Settings(surrogate="yes")
