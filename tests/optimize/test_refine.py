"""Coarse-to-fine search: a cheap model ranks the samples, the target objective picks the best."""

import concurrent.futures as cf

import numpy as np
import pytest
from optimize_cases import Recorder, Sphere, same_run, sphere_problem, within
from test_checkpoint import Abort, AbortAt

from aquagait.optimize import Settings, checkpoint, optimize

TARGET = Sphere(np.ones(4))
COARSE = Sphere(np.ones(4) + 0.2)  # a model of the target with its optimum a little off
SETTINGS = Settings(popsize=8, generations=6, seed=3, refine_top=2)


def refined(objective=COARSE, refine=TARGET):
    return sphere_problem(4, objective, feasible=within, refine=refine)


def test_the_answer_is_the_best_sample_by_the_target_objective():
    """The start is scored by the target; every generation refines its two best samples by
    the coarse objective; the answer is the best of those by the target, and its value is
    the target's."""
    target = Recorder(TARGET)
    result = optimize(refined(refine=target), SETTINGS)
    assert result.refinements == len(target.calls) == 1 + SETTINGS.generations * 2
    np.testing.assert_array_equal(target.calls[0], np.zeros(4))
    assert result.start_f == TARGET(np.zeros(4))
    best_x = min(target.calls, key=TARGET)
    np.testing.assert_array_equal(result.best_x, best_x)
    assert result.best_f == TARGET(result.best_x)
    assert [row["refinements"] for row in result.history] == [3, 5, 7, 9, 11, 13]


def test_ranking_comes_from_the_coarse_objective_only():
    """CMA-ES sees the coarse values: the same samples are drawn whatever the target says."""
    upside_down = refined(refine=lambda x: -TARGET(x))
    a, b = optimize(refined(), SETTINGS), optimize(upside_down, SETTINGS)
    assert [r["mean"] for r in a.history] == [r["mean"] for r in b.history]
    assert [r["sigma"] for r in a.history] == [r["sigma"] for r in b.history]


def test_a_coarse_model_with_an_offset_optimum_still_ends_at_the_targets_best_sample():
    """Against the coarse-only search, the refined one answers closer to the target's optimum."""
    coarse_only = optimize(sphere_problem(4, COARSE, feasible=within), SETTINGS)
    both = optimize(refined(), SETTINGS)
    assert TARGET(both.best_x) <= TARGET(coarse_only.best_x)


@pytest.mark.parametrize("at", [4, 9, 10, 13])  # call 1 of the target scores the start
def test_a_coarse_to_fine_run_aborted_anywhere_resumes_to_the_same_result(tmp_path, at):
    """Aborted inside a refinement (call `at` of the target) or between: the checkpoint
    holds the last whole generation, and the resumed run is the uninterrupted one."""
    whole = optimize(refined(), SETTINGS)
    with pytest.raises(Abort):
        optimize(refined(refine=AbortAt(TARGET, at)), SETTINGS, run_dir=tmp_path)
    resumed = optimize(refined(), SETTINGS, run_dir=tmp_path, resume=True)
    same_run(whole, resumed)
    assert resumed.refinements == whole.refinements


def test_serial_and_threads_give_the_same_coarse_to_fine_run():
    with cf.ThreadPoolExecutor(2) as pool:
        same_run(optimize(refined(), SETTINGS), optimize(refined(), SETTINGS, executor=pool))


def test_a_plain_checkpoint_does_not_resume_as_a_coarse_to_fine_run(tmp_path):
    optimize(sphere_problem(4, TARGET, feasible=within), SETTINGS, run_dir=tmp_path)
    with pytest.raises(ValueError, match="refine"):
        optimize(refined(), SETTINGS, run_dir=tmp_path, resume=True)
    plain = checkpoint.fingerprint(sphere_problem(4, TARGET), SETTINGS)
    assert "refine_top" not in plain  # checkpoints from before coarse-to-fine still resume
