"""The benchmarks' arithmetic and tables, on searches small enough for the test suite."""

import io
from functools import partial

import aquagait.app.optimize as app_optimize
from aquagait.bench import optimize as bench_optimize


def test_bench_optimize_runs_the_default_search_per_seed_beside_the_papers_budget(monkeypatch):
    """Each seed's search is a real one (eel2d from its hand-set gait, two workers), capped
    here at 6 swims on a coarse grid; the summary's ratios follow from its rows."""
    small = partial(app_optimize.prepare_optimization, resolution=(48, 28), cell_size=0.025,
                    max_evaluations=6)  # fmt: skip
    monkeypatch.setattr(app_optimize, "prepare_optimization", small)
    out = io.StringIO()
    rows = bench_optimize._default_searches("eel2d", 2, {"target": 80.0}, out)
    assert [(row["seed"], row["samples"], row["stopped"]) for row in rows] == [
        (1, 6, "max_evaluations (6)"), (2, 6, "max_evaluations (6)")]  # fmt: skip
    text = out.getvalue()
    assert "optimize eel2d --start hand-set --seed S, 2 workers" in text
    minutes = sorted(row["minutes"] for row in rows)
    summary = text.strip().splitlines()[-1]
    assert summary.startswith("default search: median 6 samples to its stop")
    assert f"{(minutes[0] + minutes[1]) / 2:.1f} min whole (target 5 min: met)" in summary
    assert "the paper's budget (1600 samples) 20.0 min at this run's rate" in summary
    assert "266.7x the samples" in summary


def test_bench_env_times_the_environment_beside_a_rollout(monkeypatch):
    """Both sides swim the same physics; the overhead column is their ratio less one."""
    from aquagait.bench import env as bench_env

    monkeypatch.setattr(bench_env, "CASES", (("eel2d", True),))
    out = io.StringIO()
    (row,) = bench_env.run(10, out)
    assert row["env_steps_per_second"] > 0 and row["rollout_steps_per_second"] > 0
    ratio = row["rollout_steps_per_second"] / row["env_steps_per_second"]
    assert row["overhead"] == ratio - 1
    assert out.getvalue().splitlines()[1].startswith("eel2d")
