"""Evaluate a generation's samples, serially or through any executor (STYLE.md §7).

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
"""

from __future__ import annotations

import concurrent.futures as cf
import logging
import math
from dataclasses import dataclass

import numpy as np

log = logging.getLogger(__name__)

OK, FAILED, LOST = "ok", "failed", "lost"


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
    """Evaluate every sample of `xs` (each of shape (n,)), one Outcome per sample, in order."""
    if not xs:
        return []
    if executor is None:
        raw = [evaluate_sample(objective, x) for x in xs]
        return [_outcome(value, message, penalty) for value, message in raw]
    if hasattr(executor, "get_executor"):  # a Dask Client: resubmitted tasks need fresh keys
        executor = executor.get_executor(pure=False)
    if hasattr(executor, "submit"):
        return _evaluate_submitted(objective, xs, executor, retries, penalty)
    if hasattr(executor, "map"):
        return _evaluate_mapped(objective, xs, executor, retries, penalty)
    raise TypeError(f"an executor needs a submit or map method; got {executor!r}")


def _outcome(value: float, message: str, penalty: float) -> Outcome:
    if message:
        return Outcome(penalty, FAILED, message)
    return Outcome(value, OK)


def _submit(executor, objective, x):
    """Submit one sample; a submit that raises (a broken pool) yields a failed future."""
    try:
        return executor.submit(evaluate_sample, objective, x)
    except Exception as error:
        future = cf.Future()
        future.set_exception(error)
        return future


def _evaluate_submitted(objective, xs, executor, retries, penalty) -> list[Outcome]:
    pending = {_submit(executor, objective, x): i for i, x in enumerate(xs)}
    attempts = [0] * len(xs)
    outcomes: list[Outcome | None] = [None] * len(xs)
    while pending:
        done, _ = cf.wait(list(pending), return_when=cf.FIRST_COMPLETED)
        for future in done:
            i = pending.pop(future)
            try:
                value, message = future.result()
            except Exception as error:  # the worker died or the task was lost
                why = f"{type(error).__name__}: {error}"
                if attempts[i] < retries:
                    attempts[i] += 1
                    log.warning("sample %d lost (%s); resubmitting", i, why)
                    pending[_submit(executor, objective, xs[i])] = i
                else:
                    outcomes[i] = Outcome(penalty, LOST, why)
                continue
            outcomes[i] = _outcome(value, message, penalty)
    return outcomes


def _evaluate_mapped(objective, xs, executor, retries, penalty) -> list[Outcome]:
    """An executor with only `map`: one lost task loses the batch, retried as a whole."""
    for attempt in range(retries + 1):
        try:
            raw = list(executor.map(evaluate_sample, [objective] * len(xs), xs))
        except Exception as error:
            why = f"{type(error).__name__}: {error}"
            log.warning("batch lost (%s), attempt %d of %d", why, attempt + 1, retries + 1)
            continue
        return [_outcome(value, message, penalty) for value, message in raw]
    return [Outcome(penalty, LOST, why) for _ in xs]
