"""Objectives and problems shared by the optimize tests, importable by worker processes.

Run as a script, it is the optimization that test_checkpoint.py kills with SIGKILL:

    python optimize_cases.py RUN_DIR CALLS_FILE HANG_AT
"""

from __future__ import annotations

import importlib.util
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from aquagait.optimize import Problem, Settings, optimize

needs_dask = pytest.mark.skipif(
    importlib.util.find_spec("distributed") is None,
    reason="Dask's distributed is not installed (pip install 'aquagait[dist]')",
)


def same_run(a, b):
    """Two optimization Results are the same run, to the bit, apart from the clock."""

    def without_time(history):
        return [{k: v for k, v in row.items() if k != "elapsed"} for row in history]

    np.testing.assert_equal(without_time(a.history), without_time(b.history))  # nan == nan
    assert np.array_equal(a.best_x, b.best_x) and a.best_f == b.best_f
    assert a.evaluations == b.evaluations and a.stopped == b.stopped


class Sphere:
    """f(x) = |x - center|^2, minimum 0 at `center`."""

    def __init__(self, center):
        self.center = np.asarray(center, dtype=float)

    def __call__(self, x):
        return float(np.sum((x - self.center) ** 2))


class RotatedEllipsoid:
    """f(x) = sum_i cond^(i/(n-1)) y_i^2 with y = R (x - center), R a fixed random rotation.

    The smallest weight is 1, so |x - center| <= sqrt(f(x)).
    """

    def __init__(self, center, cond: float, seed: int = 1):
        self.center = np.asarray(center, dtype=float)
        n = self.center.size
        q, r = np.linalg.qr(np.random.default_rng(seed).standard_normal((n, n)))
        self.rotation = q * np.sign(np.diag(r))
        self.weights = cond ** (np.arange(n) / (n - 1))

    def __call__(self, x):
        y = self.rotation @ (x - self.center)
        return float(np.sum(self.weights * y**2))


class Recorder:
    """Wraps an objective and keeps every x it was called with (serial runs only)."""

    def __init__(self, objective):
        self.objective = objective
        self.calls: list[np.ndarray] = []

    def __call__(self, x):
        self.calls.append(np.array(x))
        return self.objective(x)


class Slow:
    """Sleeps, then evaluates; optionally appends its process id to the file `calls`
    as each call starts, and hangs on call number `hang_at` (to be killed there)."""

    def __init__(self, objective, seconds: float, calls: str | None = None, hang_at: int = 0):
        self.objective, self.seconds, self.calls, self.hang_at = objective, seconds, calls, hang_at
        self.count = 0

    def __call__(self, x):
        self.count += 1
        if self.calls:
            with open(self.calls, "a") as file:
                file.write(f"{os.getpid()}\n")
        time.sleep(600 if self.count == self.hang_at else self.seconds)
        return self.objective(x)


class Faulty:
    """Raises where x[0] < -1, returns nan where x[1] < -1, else the wrapped value."""

    def __init__(self, objective):
        self.objective = objective

    def __call__(self, x):
        if x[0] < -1:
            raise FloatingPointError("simulation diverged (test)")
        if x[1] < -1:
            return math.nan
        return self.objective(x)


class DiesOnce:
    """Kills its worker process the first time any worker calls it after the start (the
    run's first call, evaluated alone); marker files say which calls have been."""

    def __init__(self, objective, marker: str):
        self.objective, self.marker = objective, marker

    def __call__(self, x):
        for marker in (self.marker + ".start", self.marker):
            try:
                descriptor = os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
            except FileExistsError:
                continue
            os.close(descriptor)
            if marker == self.marker:
                os._exit(3)  # the worker dies mid-task, as if killed
            return self.objective(x)  # the start
        return self.objective(x)


class DiesWhenTaken:
    """A task that marks that a worker has taken it, then kills that worker."""

    def __init__(self, marker: str):
        self.marker = marker

    def __call__(self):
        open(self.marker, "w").close()
        time.sleep(0.2)
        os._exit(3)


def _stat(pid: int) -> list[str] | None:
    """The fields of ``/proc/PID/stat`` after the command's name (state, parent, ...),
    or None once the process is gone."""
    try:
        with open(f"/proc/{pid}/stat") as stat:
            return stat.read().rsplit(")", 1)[1].split()
    except (FileNotFoundError, ProcessLookupError):
        return None


def gone(pid: int) -> bool:
    """The process has exited (a zombie not yet reaped by its parent counts as exited)."""
    fields = _stat(pid)
    return fields is None or fields[0] == "Z"


def descendants(pid: int) -> list[int]:
    """The processes descended from ``pid`` (Linux's /proc)."""
    parents = {}
    for entry in os.listdir("/proc"):
        fields = _stat(int(entry)) if entry.isdigit() else None
        if fields is not None:
            parents[int(entry)] = int(fields[1])
    found, frontier = [], [pid]
    while frontier:
        frontier = [child for child, parent in parents.items() if parent in frontier]
        found += frontier
    return found


def within(x, limit: float = 0.5) -> bool:
    """Feasible when x[0] <= limit (a stand-in for joint limits)."""
    return bool(x[0] <= limit)


def never(x) -> bool:
    return False


def sphere_problem(n: int = 4, objective=None, **fields) -> Problem:
    """A sphere centred at 1 in [-5, 5]^n, started at 0."""
    objective = Sphere(np.ones(n)) if objective is None else objective
    return Problem(objective, np.zeros(n), -5 * np.ones(n), 5 * np.ones(n), **fields)


# The run that test_checkpoint.py kills: small enough to finish in seconds.
KILLED_SETTINGS = Settings(popsize=8, generations=12, seed=7)


def killed_problem(calls: str | None = None, seconds: float = 0.0, hang_at: int = 0) -> Problem:
    objective = RotatedEllipsoid(np.linspace(-1, 1, 5), cond=1e3)
    if seconds or calls:
        objective = Slow(objective, seconds, calls, hang_at)
    lower, upper = -4 * np.ones(5), 4 * np.ones(5)
    return Problem(objective, np.zeros(5), lower, upper, sigma0=1.0, feasible=within)


if __name__ == "__main__":
    run_dir, calls, hang_at = Path(sys.argv[1]), sys.argv[2], int(sys.argv[3])
    optimize(killed_problem(calls, 0.01, hang_at), KILLED_SETTINGS, run_dir=run_dir)
