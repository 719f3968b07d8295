"""The search's budget: CMA-ES's own population, the convergence rule, the evaluation cap."""

import concurrent.futures as cf
import math

import numpy as np
import pytest
from optimize_cases import Recorder, Sphere, same_run, sphere_problem, within

from aquagait.optimize import (
    Problem,
    Settings,
    default_patience,
    default_popsize,
    finished_run,
    local_executor,
    optimize,
)


class Bowl:
    """f(x) = 1 + |x - centre|^2: a minimum of 1 that a search reaches and then polishes by
    amounts far below 1 % of it (a converged problem for the relative patience rule)."""

    def __init__(self, center):
        self.center = np.asarray(center, dtype=float)

    def __call__(self, x):
        return 1.0 + float(np.sum((x - self.center) ** 2))


def test_the_default_population_is_cma_es_own_for_each_groups_size():
    import cma

    for n in (2, 6, 8, 21, 24):
        recommended = cma.CMAEvolutionStrategy(np.zeros(n), 1.0, {"verbose": -9}).popsize
        assert default_popsize(n) == recommended
        assert Settings().for_group(n) == (recommended, 10 + math.ceil(30 * n / recommended))
    groups = (np.array([0, 1]), np.arange(2, 8))  # 2 then 6 parameters: 6 then 9 samples
    result = optimize(sphere_problem(8, groups=groups), Settings(generations=4))
    assert [row["samples"] for row in result.history] == [6] * 4 + [9] * 4


def test_a_converged_problem_stops_by_the_patience_rule_where_the_rule_first_holds():
    center = np.array([0.5, -0.5, 1.0])
    result = optimize(sphere_problem(3, Bowl(center)), Settings(seed=2))
    patience = default_patience(3, default_popsize(3))
    assert result.stopped.startswith("converged: best improved")
    assert result.stopped.endswith(f"in {patience} generations")
    assert result.best_f < 1.01  # within the rule's 1 % of the minimum
    best = [result.start_f] + [row["best"] for row in result.history]

    def stalled(k):  # after generation k: best[k - patience] -> best[k] gained <= 1 %
        return k >= patience and best[k - patience] - best[k] <= 0.01 * abs(best[k])

    assert stalled(result.generations)
    assert not any(stalled(k) for k in range(result.generations))


def test_a_moving_problem_is_not_stopped_by_the_patience_rule():
    # a minimum 2,000 initial steps away: the search walks to it, gaining every generation
    far = Bowl(np.full(4, 100.0))
    problem = Problem(far, np.zeros(4), -200 * np.ones(4), 200 * np.ones(4), sigma0=0.1)
    result = optimize(problem, Settings(generations=40, patience=10, seed=1))
    assert result.stopped == "generations (40)"
    assert result.best_f < 0.5 * result.start_f  # still far from the minimum, and moving


def test_a_generation_count_alone_is_the_papers_fixed_budget():
    assert Settings(generations=100).for_group(8) == (10, None)  # no patience rule
    paper = Settings.paper(2)
    assert (paper.popsize, paper.generations, paper.patience) == (16, 100, None)
    assert Settings.paper(3).for_group(24) == (31, None)
    result = optimize(sphere_problem(3, Bowl(np.ones(3))), Settings(popsize=6, generations=40))
    assert result.generations == 40 and result.stopped == "generations (40)"


@pytest.mark.parametrize("cap", [1, 9, 30, 31])
def test_max_evaluations_is_honoured_exactly(cap):
    recorder = Recorder(Sphere(np.ones(4)))
    problem = sphere_problem(4, recorder, feasible=within)
    result = optimize(problem, Settings(popsize=6, max_evaluations=cap, seed=4))
    assert result.evaluations == len(recorder.calls) == cap
    assert result.stopped == f"max_evaluations ({cap})"
    # the start, then 6 a generation; the last one cut short to the cap
    evaluated = np.diff([1] + [row["evaluations"] for row in result.history]).tolist()
    assert evaluated == [6] * ((cap - 1) // 6) + ([(cap - 1) % 6] if (cap - 1) % 6 else [])
    assert result.best_f == min([result.start_f] + [Sphere(np.ones(4))(x) for x in recorder.calls])


def test_a_cut_generation_is_not_told_to_cma_es():
    """The capped run is the uncapped run's prefix: same samples, same best so far."""
    whole = optimize(sphere_problem(4), Settings(popsize=6, generations=5, seed=8))
    capped = optimize(sphere_problem(4), Settings(popsize=6, generations=5, seed=8,
                                                  max_evaluations=22))  # fmt: skip
    assert capped.history[-1]["evaluations"] - capped.history[-2]["evaluations"] == 3
    for a, b in zip(capped.history[:-1], whole.history[:3], strict=True):
        assert a["best_x"] == b["best_x"] and a["best"] == b["best"]


def test_a_run_stopped_by_the_rule_resumes_as_a_no_op_that_says_so(tmp_path):
    problem = sphere_problem(3, Bowl(np.ones(3)))
    assert finished_run(tmp_path) is None
    first = optimize(problem, Settings(seed=2), run_dir=tmp_path)
    assert finished_run(tmp_path) == first.stopped and first.stopped.startswith("converged")
    recorder = Recorder(Bowl(np.ones(3)))
    again = optimize(sphere_problem(3, recorder), Settings(seed=2), run_dir=tmp_path, resume=True)
    same_run(first, again)
    assert recorder.calls == []


def test_a_default_search_resumed_after_an_interruption_ends_where_it_would_have(tmp_path):
    problem, settings = sphere_problem(3, Bowl(np.ones(3))), Settings(seed=2)
    whole = optimize(problem, settings)

    def stop_after_ten(report):
        if report.generation == 10:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        optimize(problem, settings, run_dir=tmp_path, progress=stop_after_ten)
    assert finished_run(tmp_path) is None
    same_run(whole, optimize(problem, settings, run_dir=tmp_path, resume=True))


def test_serial_processes_and_threads_give_the_same_default_search():
    problem = sphere_problem(4, Bowl(np.ones(4)), feasible=within)
    settings = Settings(seed=3, max_evaluations=150)
    serial = optimize(problem, settings)
    with local_executor(2) as processes:
        same_run(serial, optimize(problem, settings, processes))
    with cf.ThreadPoolExecutor(2) as threads:
        same_run(serial, optimize(problem, settings, threads))


def test_reports_without_a_generation_count_plan_by_the_evaluation_cap():
    reports = []
    optimize(sphere_problem(3), Settings(max_evaluations=50, seed=1), progress=reports.append)
    assert all(r.planned is None for r in reports)
    assert reports[-1].remaining == 0 and all(r.remaining >= 0 for r in reports)
    reports.clear()
    optimize(sphere_problem(3, Bowl(np.ones(3))), Settings(seed=1), progress=reports.append)
    assert all(math.isnan(r.remaining) for r in reports)  # nothing bounds an open search


@pytest.mark.parametrize(
    "fields, message",
    [
        ({"max_evaluations": 0}, "max_evaluations must be an integer >= 1 or None"),
        ({"patience": 0}, "patience must be an integer >= 1 or None"),
        ({"popsize": 1}, "popsize must be an integer >= 2 or None"),
        ({"tolerance": -0.1}, "tolerance must be >= 0"),
    ],
)
def test_budget_settings_are_checked_where_they_are_built(fields, message):
    with pytest.raises(ValueError, match=message):
        Settings(**fields)
