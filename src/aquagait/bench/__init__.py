"""Benchmarks behind ``aquagait bench``: each prints its figures beside a baseline
measured in the same run, because shared machines are noisy (docs/benchmarks.md)."""

from __future__ import annotations

import os
import sys
from typing import TextIO

BENCHMARKS = ("fluid", "swim", "optimize", "render", "env")


def run_benchmark(
    what: str,
    repeats: int = 10,
    out: TextIO = sys.stdout,
    profile: bool = False,
    compare_advection: bool = False,
    compare_still: bool = False,
    compare_precision: bool = False,
    compare_boundary: bool = False,
    compare_start: bool = False,
    compare_thin: bool = False,
    creature: str | None = None,
    seeds: int | None = None,
) -> list[dict]:
    """Run one benchmark on one core and print its table.

    Args:
        what: the benchmark's name, one of ``BENCHMARKS``.
        repeats: timed repetitions per case (the median is reported).
        out: where the table goes.
        profile: swim only: time per phase of the coupled step (``swim.profile``).
        compare_advection: swim only: each advection scheme beside the other
            (``swim.compare_advection``).
        compare_still: swim only: every departure point traced at second order
            beside still water traced by one Euler step (``swim.compare_still``).
        compare_precision: swim only: float64 beside float32 face velocities
            (``swim.compare_precision``).
        compare_boundary: swim only: the staircase beside sub-cell boundaries
            (``swim.compare_boundary``).
        compare_start: swim only: the step as the 3D-speed work found it beside
            today's (``swim.compare_start``).
        compare_thin: swim only: the step before thin parts were closed beside
            today's (``swim.compare_thin``).
        creature: optimize: the creature whose optimization is timed (default
            eel2d); swim's profile and comparisons: that creature alone (default:
            every creature of the paper's Table 1).
        seeds: optimize only: default searches run whole, one per seed (default 3;
            0 times the samples alone).
    Returns:
        one dict per row of the table.
    """
    if what not in BENCHMARKS:
        raise ValueError(f"unknown benchmark {what!r}; choose one of {', '.join(BENCHMARKS)}")
    if repeats < 1:
        raise ValueError(f"repeats must be at least 1, got {repeats}")
    chosen = {"profile": profile, "compare_advection": compare_advection,
              "compare_still": compare_still, "compare_precision": compare_precision,
              "compare_boundary": compare_boundary, "compare_start": compare_start,
              "compare_thin": compare_thin}  # fmt: skip
    if any(chosen.values()) and what != "swim":
        raise ValueError(f"--profile and --compare-* are for 'swim', not {what!r}")
    if seeds is not None and what != "optimize":
        raise ValueError(f"--seeds is for 'optimize', not {what!r}")
    if creature is not None and what != "optimize" and not any(chosen.values()):
        raise ValueError(
            f"--creature is for 'optimize' and for 'swim' with --profile or "
            f"--compare-*, not {what!r} alone"
        )
    if seeds is not None and seeds < 0:
        raise ValueError(f"seeds must be at least 0, got {seeds}")
    from aquagait.bench import env, fluid, optimize, render, swim

    if creature is not None:
        from aquagait.creatures import get

        get(creature)  # an unknown name is refused before anything runs
    if what != "optimize":  # the optimize benchmark measures two worker processes
        _pin_to_one_core(out)
    if any(chosen.values()):
        creatures = (creature,) if creature else swim.TABLE_1
        return [row for name, on in chosen.items() if on
                for row in getattr(swim, name)(repeats, out, creatures)]  # fmt: skip
    if what == "optimize":
        return optimize.run(repeats, out, creature or "eel2d", 3 if seeds is None else seeds)
    modules = {"fluid": fluid, "swim": swim, "optimize": optimize, "render": render, "env": env}
    return modules[what].run(repeats=repeats, out=out)


def _pin_to_one_core(out: TextIO) -> None:
    """The targets are per core: keep this process (and its BLAS threads) on one CPU."""
    if hasattr(os, "sched_setaffinity"):
        cpu = min(os.sched_getaffinity(0))
        os.sched_setaffinity(0, {cpu})
        print(f"# pinned to one core (cpu {cpu})", file=out)
