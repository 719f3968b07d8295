"""Benchmarks behind ``aquagait bench``: each prints its figures beside a baseline
measured in the same run, because shared machines are noisy (DEVELOPERS.md)."""

from __future__ import annotations

import os
import sys
from typing import TextIO

BENCHMARKS = ("fluid", "swim", "optimize")


def run_benchmark(
    what: str,
    repeats: int = 10,
    out: TextIO = sys.stdout,
    profile: bool = False,
    compare_advection: bool = False,
) -> list[dict]:
    """Run one benchmark on one core and print its table.

    Args:
        what: the benchmark's name, one of ``BENCHMARKS``.
        repeats: timed repetitions per case (the median is reported).
        out: where the table goes.
        profile: swim only: time per phase of the coupled step (``swim.profile``).
        compare_advection: swim only: each advection scheme beside the other
            (``swim.compare_advection``).
    Returns:
        one dict per row of the table.
    """
    if what not in BENCHMARKS:
        raise ValueError(f"unknown benchmark {what!r}; choose one of {', '.join(BENCHMARKS)}")
    if repeats < 1:
        raise ValueError(f"repeats must be at least 1, got {repeats}")
    if (profile or compare_advection) and what != "swim":
        raise ValueError(f"--profile and --compare-advection are for 'swim', not {what!r}")
    from aquagait.bench import fluid, optimize, swim

    if what != "optimize":  # the optimize benchmark measures two worker processes
        _pin_to_one_core(out)
    if profile or compare_advection:
        rows = swim.profile(repeats, out) if profile else []
        return rows + (swim.compare_advection(repeats, out) if compare_advection else [])
    return {"fluid": fluid, "swim": swim, "optimize": optimize}[what].run(repeats=repeats, out=out)


def _pin_to_one_core(out: TextIO) -> None:
    """The targets are per core: keep this process (and its BLAS threads) on one CPU."""
    if hasattr(os, "sched_setaffinity"):
        cpu = min(os.sched_getaffinity(0))
        os.sched_setaffinity(0, {cpu})
        print(f"# pinned to one core (cpu {cpu})", file=out)
