"""Convergence pictures read from real optimization logs."""

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from aquagait.optimize import Problem, Settings, optimize  # noqa: E402
from aquagait.viz import plot_budgets, plot_convergence  # noqa: E402
from aquagait.viz.convergence import read_log  # noqa: E402


def sphere(x):
    return float(np.sum((x - 1) ** 2))


def logged_run(run_dir, settings):
    problem = Problem(sphere, np.zeros(3), -5 * np.ones(3), 5 * np.ones(3))
    optimize(problem, settings, run_dir=run_dir)
    return run_dir / "optimization.csv"


def test_the_log_reads_back_as_the_run_and_both_pictures_are_drawn(tmp_path):
    small = logged_run(tmp_path / "small", Settings(seed=1, max_evaluations=40))
    paper = logged_run(tmp_path / "paper", Settings.paper(2, generations=4, seed=1))
    log = read_log(paper)
    assert log["generation"] == [1, 2, 3, 4]
    assert log["evaluations"] == [1 + 16 * g for g in (1, 2, 3, 4)]  # the start, then 16 each
    assert read_log(small)["evaluations"][-1] == 40
    budgets = plot_budgets({"default": [small], "paper": [paper]}, tmp_path / "b.png", "sphere")
    single = plot_convergence(small, tmp_path / "c.png")
    for picture in (budgets, single):
        assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
