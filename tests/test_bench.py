"""The benchmarks' arithmetic and tables, on searches small enough for the test suite."""

import io
from functools import partial

import aquagait.app.optimize as app_optimize
from aquagait.bench import optimize as bench_optimize


def test_bench_optimize_runs_the_default_search_per_seed_beside_the_papers_budget(
    monkeypatch, tmp_path
):
    """Each seed's searches are real ones (eel2d from its hand-set gait, two workers, plain
    and with the surrogate), capped here at 6 swims on a coarse grid; the summary's ratios
    follow from its rows, and the picture draws both."""
    monkeypatch.chdir(tmp_path)
    small = partial(app_optimize.prepare_optimization, resolution=(48, 28), cell_size=0.025,
                    max_evaluations=6)  # fmt: skip
    monkeypatch.setattr(app_optimize, "prepare_optimization", small)
    out = io.StringIO()
    rows = bench_optimize._default_searches("eel2d", 2, {"target": 80.0}, out)
    assert [(row["seed"], row["search"], row["samples"], row["stopped"]) for row in rows] == [
        (seed, search, 6, "max_evaluations (6)") for seed in (1, 2)
        for search in ("default", "surrogate")]  # fmt: skip
    text = out.getvalue()
    assert "optimize eel2d --start hand-set --seed S [--surrogate], 2 workers" in text
    plain, modelled = ([row for row in rows if row["search"] == s]
                       for s in ("default", "surrogate"))  # fmt: skip
    minutes = sorted(row["minutes"] for row in plain)
    default, surrogate, picture = text.strip().splitlines()[-3:]
    assert default.startswith("default search: median 6 samples to its stop")
    assert f"{(minutes[0] + minutes[1]) / 2:.1f} min whole (target 5 min: met)" in default
    assert "the paper's budget (1600 samples) 20.0 min at this run's rate" in default
    assert "266.7x the samples" in default
    best = [sum(row["best"] for row in rows) / 2 for rows in (plain, modelled)]
    worse = 100 * (best[1] - best[0]) / abs(best[0])
    assert surrogate.startswith("surrogate search: median 6 samples (1.00x fewer)")
    assert f"median best {best[1]:.4g} against {best[0]:.4g}, {worse:+.2f} %" in surrogate
    assert picture == "wrote runs/bench/optimize-eel2d/convergence.png"
    assert (tmp_path / "runs/bench/optimize-eel2d/convergence.png").stat().st_size > 10_000


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
