"""The CMA-ES loop: exact minima of analytic functions, feasibility, groups, failures."""

import dataclasses
import math

import numpy as np
import pytest
from optimize_cases import (
    Faulty,
    Recorder,
    RotatedEllipsoid,
    Sphere,
    never,
    sphere_problem,
    within,
)

from aquagait.optimize import Problem, Settings, optimize


def without_time(history):
    return [{k: v for k, v in row.items() if k != "elapsed"} for row in history]


def test_sphere_is_minimized_to_tolerance():
    result = optimize(sphere_problem(8), Settings(popsize=12, generations=400))
    # pycma stops on tolfun=1e-11: the spread of recent values, here f itself.
    assert result.best_f < 1e-10
    assert np.linalg.norm(result.best_x - 1) < 1e-5  # |x - x*| = sqrt(f)
    assert "tolfun" in result.stopped
    assert result.evaluations == 1 + 12 * result.generations  # the start, then the samples
    assert result.start_f == pytest.approx(8.0)  # |0 - 1|^2 x 8


def test_rotated_ellipsoid_is_minimized_to_tolerance():
    center = np.linspace(-2, 2, 6)
    objective = RotatedEllipsoid(center, cond=1e4)
    lower, upper = -5 * np.ones(6), 5 * np.ones(6)
    problem = Problem(objective, np.zeros(6), lower, upper)
    result = optimize(problem, Settings(popsize=12, generations=600))
    assert result.best_f < 1e-9
    # Every weight is at least 1 and R is a rotation: |x - x*|^2 <= f.
    assert np.linalg.norm(result.best_x - center) <= math.sqrt(result.best_f) + 1e-12
    assert result.generations < 600  # it converged rather than running out


def test_best_never_gets_worse_and_matches_the_log():
    result = optimize(sphere_problem(4), Settings(popsize=8, generations=30))
    best = [row["best"] for row in result.history]
    assert best == sorted(best, reverse=True)
    assert result.best_f == best[-1] == Sphere(np.ones(4))(result.best_x)
    assert [row["generation"] for row in result.history] == list(range(1, 31))


def test_infeasible_samples_are_never_evaluated():
    recorder = Recorder(Sphere(np.ones(4)))  # the optimum x0 = 1 is infeasible
    problem = sphere_problem(4, recorder, feasible=within)
    result = optimize(problem, Settings(popsize=8, generations=150))
    assert recorder.calls and all(within(x) for x in recorder.calls)
    assert sum(row["resamples"] for row in result.history) > 0
    assert len(recorder.calls) == result.evaluations
    # The constrained optimum sits on the constraint, x = (0.5, 1, 1, 1).
    assert result.best_x == pytest.approx([0.5, 1, 1, 1], abs=1e-4)
    assert result.best_f == pytest.approx(0.25, abs=1e-6)


def test_after_the_resampling_cap_a_sample_gets_the_penalty_unevaluated():
    recorder = Recorder(Sphere(np.ones(3)))
    problem = sphere_problem(3, recorder, feasible=never)
    settings = Settings(popsize=6, generations=5, max_resamples=3, penalty=1e5)
    result = optimize(problem, settings)
    assert recorder.calls == [] and result.evaluations == 0
    assert result.best_f == math.inf and np.array_equal(result.best_x, problem.x0)
    first = result.history[0]
    assert first["infeasible"] == 6 and first["resamples"] == 6 * 3
    assert math.isnan(first["mean"])


def test_a_zero_resampling_cap_penalizes_at_once():
    recorder = Recorder(Sphere(np.ones(3)))
    problem = sphere_problem(3, recorder, feasible=within, sigma0=2.0)
    result = optimize(problem, Settings(popsize=10, generations=3, max_resamples=0))
    assert sum(row["resamples"] for row in result.history) == 0
    infeasible = sum(row["infeasible"] for row in result.history)
    assert infeasible > 0 and len(recorder.calls) == 1 + 30 - infeasible  # the start too
    assert all(within(x) for x in recorder.calls)


def test_groups_are_optimized_in_turn_from_the_best_so_far():
    recorder = Recorder(Sphere(np.ones(5)))
    a, b = np.array([0, 1, 2]), np.array([3, 4])
    problem = sphere_problem(5, recorder, groups=(a, b, a), sigma0=0.05)
    result = optimize(problem, Settings(popsize=8, generations=40))
    groups = [row["group"] for row in result.history]
    assert groups == sorted(groups) and set(groups) == {0, 1, 2}
    assert result.stopped.count("group") == 3
    calls, ends = np.array(recorder.calls), {}
    for row in result.history:
        ends[row["group"]] = row  # the last generation of each group
    first_a, phase_b, second_a = np.split(calls, [ends[0]["evaluations"], ends[1]["evaluations"]])
    # Phase A moves only A; B stays at x0.
    assert np.all(first_a[:, b] == 0)
    # Phase B moves only B; A is frozen at the best of phase A.
    assert np.all(phase_b[:, a] == ends[0]["best_x"][:3])
    assert np.all(phase_b[:, a] != 0)
    # The second phase A starts at the best so far, not at x0: sigma0 = 0.05, far from 0.
    start = second_a[:8, a]
    assert np.abs(start - np.array(ends[1]["best_x"])[a]).max() < 0.5
    assert np.all(second_a[:, b] == np.array(ends[1]["best_x"])[b])
    assert result.best_f < 1e-6


def test_failed_samples_get_the_penalty_and_the_run_goes_on(caplog):
    problem = sphere_problem(4, Faulty(Sphere(np.ones(4))), sigma0=2.0)
    result = optimize(problem, Settings(popsize=10, generations=60, penalty=1e3))
    failures = sum(row["failures"] for row in result.history)
    assert failures > 0
    assert "FloatingPointError: simulation diverged" in caplog.text
    assert "returned nan" in caplog.text
    assert result.best_f < 1e-6 and result.generations > 10


def test_an_objective_that_always_fails_ends_without_a_best():
    def broken(x):
        raise RuntimeError("no")

    result = optimize(sphere_problem(3, broken), Settings(popsize=6, generations=4))
    assert result.best_f == math.inf and np.array_equal(result.best_x, np.zeros(3))
    assert all(row["failures"] == 6 for row in result.history)


def test_the_same_seed_gives_the_same_run_and_the_global_generator_is_irrelevant():
    problem = sphere_problem(4, feasible=within)
    settings = Settings(popsize=8, generations=15, seed=3)

    def disturb(report):
        # Moving NumPy's global generator changes nothing: pycma must not draw from it.
        np.random.seed(report.generation)  # noqa: NPY002
        np.random.standard_normal(10)  # noqa: NPY002

    a = optimize(problem, settings)
    b = optimize(problem, settings, progress=disturb)
    c = optimize(problem, Settings(popsize=8, generations=15, seed=4))
    assert without_time(a.history) == without_time(b.history)
    assert np.array_equal(a.best_x, b.best_x)
    assert not np.array_equal(a.best_x, c.best_x)


def test_progress_reports_every_generation():
    reports = []
    optimize(sphere_problem(3), Settings(popsize=6, generations=5), progress=reports.append)
    assert [r.generation for r in reports] == [1, 2, 3, 4, 5]
    assert all(r.planned == 5 and r.evaluations == 1 + 6 * r.generation for r in reports)
    assert reports[-1].remaining == 0 and reports[0].remaining >= 0


def test_paper_settings():
    assert Settings.for_dim(2).popsize == 16 and Settings.for_dim(3).popsize == 31
    assert Settings.for_dim(2).generations == 100 == Settings.paper(3).generations
    with pytest.raises(ValueError, match="dim must be 2 or 3"):
        Settings.for_dim(4)


@pytest.mark.parametrize(
    "fields, message",
    [
        ({"x0": np.zeros(3)}, "lower has 4 entries; x0 has 3"),
        ({"lower": np.ones(4)}, r"lower < upper; coordinates \[0, 1, 2, 3\]"),
        ({"x0": np.full(4, 9.0)}, "outside the bounds"),
        ({"sigma0": -1.0}, "sigma0 must be a positive number"),
        ({"groups": ([0, 7],)}, r"groups\[0\] = \[0, 7\] leaves 0..3"),
        ({"names": ("a",)}, "1 names for 4 parameters"),
        ({"objective": 3}, "objective must be callable"),
    ],
)
def test_problems_are_checked_where_they_are_built(fields, message):
    arguments = {
        "objective": Sphere(np.ones(4)),
        "x0": np.zeros(4),
        "lower": -np.ones(4),
        "upper": np.ones(4),
        **fields,
    }
    with pytest.raises((ValueError, TypeError), match=message):
        Problem(**arguments)


@pytest.mark.parametrize(
    "fields, message",
    [
        ({"popsize": 1}, "popsize must be an integer >= 2"),
        ({"generations": 0}, "generations must be an integer >= 1"),
        ({"penalty": math.inf}, "penalty must be finite"),
        ({"retries": -1}, "retries must be an integer >= 0"),
    ],
)
def test_settings_are_checked_where_they_are_built(fields, message):
    with pytest.raises(ValueError, match=message):
        Settings(**fields)


def test_default_sigma_scales_with_each_coordinates_range():
    problem = Problem(Sphere(np.zeros(2)), np.zeros(2), np.array([-1.0, -10.0]), np.array([1, 10]))
    assert problem.sigma0 == pytest.approx(0.25 * 11)
    recorder = Recorder(Sphere(np.zeros(2)))
    wide = Problem(recorder, problem.x0, problem.lower, problem.upper)
    optimize(wide, Settings(popsize=200, generations=1))
    spread = np.array(recorder.calls).std(axis=0)
    assert spread[1] / spread[0] == pytest.approx(10, rel=0.3)


def test_a_one_parameter_search_converges():
    """One number (the accordion's gait) is a search pycma's step-size cap once broke."""
    problem = Problem(lambda x: float((x[0] - 0.3) ** 2), [0.7], [0.0], [0.9])
    result = optimize(problem, Settings(popsize=8, generations=40))
    assert abs(result.best_x[0] - 0.3) < 1e-3


def test_the_answer_is_never_worse_than_the_start():
    """Started at the minimum with a wide spread, no draw of a short run comes as close: the
    start is evaluated first, so the run answers with it; the draws are those of a run that
    did not evaluate it (it takes no random numbers)."""
    recorder = Recorder(Sphere(np.ones(3)))
    problem = sphere_problem(3, recorder, sigma0=2.0)
    problem = dataclasses.replace(problem, x0=np.ones(3))
    result = optimize(problem, Settings(popsize=6, generations=2, seed=5))
    assert result.start_f == 0.0 and result.best_f == 0.0
    np.testing.assert_array_equal(result.best_x, np.ones(3))
    np.testing.assert_array_equal(recorder.calls[0], np.ones(3))
    assert min(float(np.sum((x - 1) ** 2)) for x in recorder.calls[1:]) > 0.1
