"""Evaluate a generation's samples, serially or through any executor (docs/optimize.md).

An executor is anything with `submit(fn, *args) -> concurrent.futures.Future`
(`ProcessPoolExecutor`, Dask's `Client.get_executor()`, the helpers in
`optimize.executors`), a Dask `Client` itself, or, failing `submit`, anything
with `map(fn, *iterables)`. None evaluates in this process, in order.

Values are placed by sample index, never by completion order, so the result is
the same whichever worker finishes first. Two kinds of failure are told apart:
the objective itself failing (it raised, or returned nan/inf) is caught inside
the worker and reported as a value, never retried (the simulation is
deterministic); the worker dying or the task being lost (an exception out of
`Future.result()`) is retried `retries` times. Either kind ends in the penalty.

A third kind is no sample's fault: the executor itself is gone (a Dask
scheduler died, no worker has been connected for too long, a pool refuses new
work). Nothing evaluated then says anything about the samples, so no penalty
is given: `ExecutorLost` is raised and the generation is left unfinished, to be
redone, unchanged, by a resumed run. An executor may say when it is gone with a
method `lost() -> str` (why, or "" while it can still evaluate), which is asked
after every wait of at most `POLL` seconds (see `DaskExecutor.lost`); a `submit`
that raises, or a `map`-only executor losing its whole batch `retries + 1`
times, means the same.
"""

from __future__ import annotations

import concurrent.futures as cf
import logging
import math
from dataclasses import dataclass

import numpy as np

from aquagait.optimize.executors import DaskExecutor

log = logging.getLogger(__name__)

OK, FAILED, LOST = "ok", "failed", "lost"

POLL = 0.5
"""Seconds between looks at a waiting executor's `lost()`: how late a loss may be seen."""


class ExecutorLost(RuntimeError):
    """The executor can no longer evaluate samples; the generation it was on is not finished.

    Raised by `evaluate` when the executor is gone (see the module docstring), and
    passed on by `optimize` with the generation and checkpoint filled in. Its
    message is one line: what was lost, when, and how to go on.

    Attributes:
        reason: what was lost, in words (e.g. "lost the Dask scheduler at
            tcp://127.0.0.1:8786 (its client is connecting)").
        outstanding: samples of the generation without a value when it was lost.
        samples: samples the generation was evaluating.
        generation: the generation cut off (1-based, over all groups); None
            outside `optimize`.
        saved: complete generations in the run's checkpoint; None without a
            run directory.
        run_dir: the run directory, or None.
    """

    def __init__(self, reason: str, outstanding: int, samples: int):
        reason = " ".join(reason.split())  # one line, whatever the executor's error said
        super().__init__(reason)
        self.reason, self.outstanding, self.samples = reason, outstanding, samples
        self.generation: int | None = None
        self.saved: int | None = None
        self.run_dir = None

    def __str__(self) -> str:
        where = "" if self.generation is None else f" in generation {self.generation}"
        text = (
            f"{self.reason}{where}, with {self.outstanding} of {self.samples} samples "
            "outstanding; no sample was given a penalty for it"
        )
        if self.generation is None:
            return text
        if self.run_dir is None:
            return f"{text}. This run keeps no checkpoint (no run directory): start it again"
        if not self.saved:
            return (
                f"{text}. No generation was complete, so {self.run_dir} holds no checkpoint: "
                "start the run again"
            )
        saved = "generation 1" if self.saved == 1 else f"generations 1-{self.saved}"
        return (
            f"{text}. The checkpoint in {self.run_dir} holds {saved}: resume with --resume "
            "and the same --out (resume=True), on any executor, to redraw the same samples "
            "and reach the uninterrupted result"
        )


@dataclass(frozen=True)
class Outcome:
    """One sample's evaluation.

    Attributes:
        value: the objective value, or the penalty when `status` is not "ok".
        status: "ok"; "failed" (the objective raised or returned nan/inf);
            "lost" (its worker died `retries + 1` times).
        message: what went wrong, empty when "ok".
    """

    value: float
    status: str
    message: str = ""


def evaluate_sample(objective, x: np.ndarray) -> tuple[float, str]:
    """Run `objective(x)` where the worker is; return (value, "") or (nan, why).

    A module-level function so that process pools and Dask can ship it.
    """
    try:
        value = float(objective(x))
    except Exception as error:  # any failure of the simulation, e.g. a divergence
        return math.nan, f"{type(error).__name__}: {error}"
    if not math.isfinite(value):
        return math.nan, f"the objective returned {value}"
    return value, ""


def evaluate(
    objective, xs: list[np.ndarray], executor=None, retries: int = 1, penalty: float = 1e6
) -> list[Outcome]:
    """Evaluate every sample of `xs` (each of shape (n,)), one Outcome per sample, in order.

    Args:
        objective: `f(x) -> float`, picklable for executors in other processes.
        xs: the samples, each (n,).
        executor: None (serially, here), anything with `submit` or `map`, or a
            Dask `Client`; see the module docstring.
        retries: re-submissions of a sample whose task was lost.
        penalty: the value of a failed or lost sample.

    Returns:
        One Outcome per sample, in the order of `xs`.

    Raises:
        ExecutorLost: the executor is gone; no outcome is returned for any sample.
    """
    if not xs:
        return []
    if executor is None:
        raw = [evaluate_sample(objective, x) for x in xs]
        return [_outcome(value, message, penalty) for value, message in raw]
    if hasattr(executor, "get_executor"):  # a Dask Client: watched like our own DaskExecutor
        executor = DaskExecutor(executor)
    if hasattr(executor, "submit"):
        return _evaluate_submitted(objective, xs, executor, retries, penalty)
    if hasattr(executor, "map"):
        return _evaluate_mapped(objective, xs, executor, retries, penalty)
    raise TypeError(f"an executor needs a submit or map method; got {executor!r}")


def _outcome(value: float, message: str, penalty: float) -> Outcome:
    if message:
        return Outcome(penalty, FAILED, message)
    return Outcome(value, OK)


def _submit(executor, objective, x, outcomes):
    """Submit one sample; a submit that raises means the executor takes no more work."""
    try:
        return executor.submit(evaluate_sample, objective, x)
    except Exception as error:  # a broken pool, a closed client
        why = f"the executor refused new work ({type(error).__name__}: {error})"
        raise _lost(why, outcomes) from error


def _lost(why: str, outcomes: list) -> ExecutorLost:
    return ExecutorLost(why, sum(o is None for o in outcomes), len(outcomes))


def _check_alive(executor, outcomes: list) -> None:
    """Raise ExecutorLost if the executor says it can no longer evaluate anything."""
    lost = getattr(executor, "lost", None)
    why = lost() if callable(lost) else ""
    if why:
        raise _lost(why, outcomes)


def _evaluate_submitted(objective, xs, executor, retries, penalty) -> list[Outcome]:
    # Tasks still out when the executor is lost are left to its shutdown: cancelling
    # a Dask future asks the scheduler, which may be the thing that is gone.
    outcomes: list[Outcome | None] = [None] * len(xs)
    attempts, pending = [0] * len(xs), {}
    for i, x in enumerate(xs):
        pending[_submit(executor, objective, x, outcomes)] = i
    while pending:
        done, _ = cf.wait(list(pending), timeout=POLL, return_when=cf.FIRST_COMPLETED)
        _check_alive(executor, outcomes)  # before a lost task is taken for a dead worker
        for future in done:
            i = pending.pop(future)
            try:
                value, message = future.result()
            except Exception as error:  # the worker died or the task was lost
                why = f"{type(error).__name__}: {error}"
                if attempts[i] < retries:
                    attempts[i] += 1
                    log.warning("sample %d lost (%s); resubmitting", i, why)
                    pending[_submit(executor, objective, xs[i], outcomes)] = i
                else:
                    outcomes[i] = Outcome(penalty, LOST, why)
                continue
            outcomes[i] = _outcome(value, message, penalty)
    return outcomes


def _evaluate_mapped(objective, xs, executor, retries, penalty) -> list[Outcome]:
    """An executor with only `map`: one lost task loses the batch, retried as a whole.

    A batch lost `retries + 1` times is ExecutorLost, not a generation of
    penalties: it cannot tell the sample that killed its worker from the others.
    """
    for attempt in range(retries + 1):
        try:
            raw = list(executor.map(evaluate_sample, [objective] * len(xs), xs))
        except Exception as error:
            why = f"{type(error).__name__}: {error}"
            log.warning("batch lost (%s), attempt %d of %d", why, attempt + 1, retries + 1)
            continue
        return [_outcome(value, message, penalty) for value, message in raw]
    why = f"the executor lost the whole batch {retries + 1} times ({why})"
    raise ExecutorLost(why, outstanding=len(xs), samples=len(xs))
