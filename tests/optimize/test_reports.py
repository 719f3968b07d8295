"""Failures are never silent: counts per generation, a warning past a share, every reason kept."""

from __future__ import annotations

import csv
import io
import math

import numpy as np
from optimize_cases import DiesOnce, Faulty, Sphere, never, sphere_problem, within

from aquagait.cli import GenerationLine
from aquagait.optimize import FAILURES, GenerationReport, ProcessExecutor, Settings, optimize
from aquagait.optimize.problem import LOSS_WARNING


def report(**fields) -> GenerationReport:
    base = dict(generation=3, planned=10, group=0, best=-1.0, mean=0.5, sigma=0.2)
    base.update(evaluations=48, failures=0, elapsed=12.0, remaining=30.0, samples=16)
    return GenerationReport(**{**base, **fields})


def test_history_and_reports_count_failed_and_infeasible_samples_with_their_reasons(tmp_path):
    # Faulty raises where x0 < -1 and returns nan where x1 < -1; `within` (x0 <= 0.5) with
    # one redraw leaves some samples infeasible. sigma0 = 2 makes all three common.
    problem = sphere_problem(4, Faulty(Sphere(np.ones(4))), feasible=within, sigma0=2.0)
    settings = Settings(popsize=10, generations=6, seed=1, max_resamples=1, penalty=1e3)
    reports = []
    result = optimize(problem, settings, run_dir=tmp_path, progress=reports.append)
    for row, seen in zip(result.history, reports, strict=True):
        statuses = [p["status"] for p in row["penalized"]]
        assert (row["failed"], row["lost"], row["infeasible"]) == (
            statuses.count("failed"),
            0,
            statuses.count("infeasible"),
        )
        assert row["failures"] == row["failed"] + row["lost"]
        assert (seen.failed, seen.lost, seen.infeasible) == (row["failed"], 0, row["infeasible"])
        assert seen.samples == 10 and len(seen.reasons) == seen.failed
        for penalized in row["penalized"]:
            x = np.array(penalized["x"])
            if penalized["status"] == "infeasible":
                assert not within(x)
                assert penalized["reason"] == "infeasible after max_resamples = 1 redraws"
            elif x[0] < -1:
                assert penalized["reason"] == "FloatingPointError: simulation diverged (test)"
            else:
                assert x[1] < -1 and penalized["reason"] == "the objective returned nan"
    assert sum(r.failed for r in reports) > 0 and sum(r.infeasible for r in reports) > 0

    with (tmp_path / FAILURES).open() as file:
        rows = list(csv.DictReader(file))
    kept = [
        (row["generation"], p["sample"], p["status"], p["reason"], p["x"])
        for row in result.history
        for p in row["penalized"]
    ]
    assert [
        (int(r["generation"]), int(r["sample"]), r["status"], r["reason"])
        + ([float(r[name]) for name in problem.names],)
        for r in rows
    ] == kept  # every reason, and the x to rerun it with
    with (tmp_path / "optimization.csv").open() as file:
        log = list(csv.DictReader(file))
    assert [int(r["failed"]) for r in log] == [row["failed"] for row in result.history]
    assert [int(r["infeasible"]) for r in log] == [row["infeasible"] for row in result.history]


def test_a_run_without_penalties_writes_a_failures_log_of_just_its_header(tmp_path):
    problem = sphere_problem(3, names=("a", "b", "c"))
    optimize(problem, Settings(popsize=6, generations=2), run_dir=tmp_path)
    assert (tmp_path / FAILURES).read_text() == "generation,group,sample,status,reason,a,b,c\n"


def test_lost_samples_are_counted_apart_from_failed_ones(tmp_path):
    dies = sphere_problem(4, DiesOnce(Sphere(np.ones(4)), str(tmp_path / "died")), feasible=within)
    settings = Settings(popsize=8, generations=2, seed=5, retries=0, penalty=1e3)
    reports = []
    with ProcessExecutor(2) as executor:
        optimize(dies, settings, executor, progress=reports.append)
    first = reports[0]
    assert first.lost >= 1 and first.failed == 0 and first.failures == first.lost
    assert all("lost: BrokenProcessPool" in reason for reason in first.reasons)
    assert reports[1].lost == 0


def test_a_generation_warns_when_more_than_an_eighth_of_its_samples_is_lost():
    assert LOSS_WARNING == 1 / 8
    assert not report(failed=2, failures=2).lossy  # 2 of 16 is an eighth: no warning
    assert report(failed=2, lost=1, failures=3).lossy
    assert not report(infeasible=16).lossy  # infeasible samples are the search, not losses


def test_the_generation_line_shows_the_counts_and_warns_with_the_first_reason():
    stream = io.StringIO()
    line = GenerationLine(stream)
    line(report(failed=1, infeasible=2, failures=1, reasons=("sample 4 failed: boom",)))
    quiet = stream.getvalue()
    assert quiet.startswith("generation   3/10  best -1  mean 0.5  sigma 0.2  ")
    assert "failed 1  lost 0  infeasible 2" in quiet and "warning" not in quiet
    reasons = ("sample 2 failed: FloatingPointError:\n diverged at t=0.4 s", "sample 5 lost: x")
    line(report(failed=2, lost=1, failures=3, reasons=reasons))
    warning = stream.getvalue().splitlines()[-1]
    assert warning == (
        "warning: generation 3 lost 3 of 16 samples (2 failed, 1 lost); first: sample 2 "
        "failed: FloatingPointError: diverged at t=0.4 s (all reasons: failures.csv)"
    )


def test_a_generation_of_infeasible_samples_only_has_no_mean_and_no_reasons():
    reports = []
    settings = Settings(popsize=6, generations=1, max_resamples=0)
    optimize(sphere_problem(3, feasible=never), settings, progress=reports.append)
    assert reports[0].infeasible == 6 and reports[0].reasons == () and math.isnan(reports[0].mean)
