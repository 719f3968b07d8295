"""CMA-ES on pycma's ask/tell, with feasibility, groups and checkpoints (paper §4).

One generation: ask pycma for `popsize` samples (by default CMA-ES's own
population for the group's size, `problem.default_popsize`); redraw each
infeasible one up to `max_resamples` times, checking `feasible` here before
anything runs; give the ones still infeasible the penalty; evaluate the rest
(serially or through an executor), placing each value by its sample index;
tell pycma; write the checkpoint and the log. Groups (paper §4, frog) run one after another, each a
fresh CMA-ES over its coordinates, started from the best point so far.

When it stops. A group ends at the first of: its `Settings.generations`
(when set), convergence (its best improved by no more than
`Settings.tolerance` of itself over the last `patience` generations), or one
of pycma's own criteria; the whole run ends early at `max_evaluations`,
whose last generation is cut short to meet the cap exactly. `Result.stopped`
and the log say which.

Determinism and resume. Every random number comes from one
`numpy.random.Generator` seeded with `Settings.seed`, handed to pycma as its
`randn` option (pycma otherwise draws from NumPy's global generator). That
generator lives inside the pycma object and both are in the checkpoint, which
is written after `tell`, so a run resumed from the checkpoint of generation k
draws exactly the samples the uninterrupted run drew in generation k + 1. A
generation cut off half way is redone from its start: its samples are drawn
again from the saved generator, so they are the same ones. Nothing depends on
the order in which workers finish.

A lost executor (`ExecutorLost`: the Dask scheduler died, no worker came for
too long) stops the run inside a generation. That generation is never told to
pycma nor saved, so no sample carries a penalty it did not earn, and the
checkpoint keeps the last complete generation: a resume, on any executor,
redraws the same samples and ends where the uninterrupted run ends.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from aquagait.optimize import checkpoint
from aquagait.optimize.evaluate import FAILED, LOST, OK, ExecutorLost, evaluate
from aquagait.optimize.executors import check_picklable
from aquagait.optimize.problem import GenerationReport, Problem, Result, Settings
from aquagait.optimize.surrogate import Surrogate

if TYPE_CHECKING:
    import cma

log = logging.getLogger(__name__)

INFEASIBLE = "infeasible"
"""The status of a sample penalized without evaluation (beside evaluate's "failed", "lost")."""


class GaussianDraws:
    """pycma's `randn` option: `draws(lam, n)` -> (lam, n) standard normals from our generator.

    Picklable with its generator state, so the checkpoint carries it.
    """

    def __init__(self, seed: int):
        self.rng = np.random.default_rng(seed)

    def __call__(self, *shape: int) -> np.ndarray:
        return self.rng.standard_normal(shape)


@dataclass
class _Run:
    """Everything a run changes; saved whole in the checkpoint."""

    draws: GaussianDraws
    best_x: np.ndarray  # (n,) best evaluated parameters, x0 before any success
    best_f: float = math.inf
    group: int = 0  # the group being optimized
    es: cma.CMAEvolutionStrategy | None = None  # its CMA-ES; None before it starts
    surrogate: Surrogate | None = None  # its model, with Settings.surrogate
    group_generations: int = 0
    evaluations: int = 0
    refinements: int = 0  # evaluations of Problem.refine
    elapsed: float = 0.0  # seconds, over every session
    history: list[dict] = field(default_factory=list)
    stopped: list[str] = field(default_factory=list)
    finished: bool = False
    start_f: float | None = None  # the start's value (refine's, if any); None: not scored
    group_start_f: float = math.inf  # the best when the group began (the patience rule's base)


def optimize(
    problem: Problem,
    settings: Settings | None = None,
    executor=None,
    run_dir: str | Path | None = None,
    resume: bool = False,
    progress: Callable[[GenerationReport], None] | None = None,
) -> Result:
    """Minimize `problem.objective` with CMA-ES (paper §4).

    Args:
        problem: objective, start, bounds, feasibility and groups.
        settings: population, generations, seed, penalties; None: `Settings()`.
        executor: None evaluates serially here; else a `concurrent.futures`
            executor (`local_executor()`, `dask_executor(address)`, a
            `ProcessPoolExecutor`, a Dask `Client`). Same seed, same result.
        run_dir: where to write `checkpoint.pkl`, `optimization.csv` and
            `failures.csv` after every generation; None writes nothing.
        resume: continue the run whose checkpoint is in `run_dir`. Refused
            (ValueError) if its problem or settings differ from these. A
            finished run returns its result at once.
        progress: called after every generation with a `GenerationReport`.

    Returns:
        The Result; `history[i]` is generation i + 1.

    Raises:
        FileExistsError: `run_dir` holds a checkpoint and `resume` is False.
        FileNotFoundError: `resume` and `run_dir` holds no checkpoint.
        ExecutorLost: the executor is gone (a Dask scheduler died, no worker for
            too long); the checkpoint holds the last complete generation, and
            the message says how to resume.
    """
    settings = Settings() if settings is None else settings
    if not isinstance(problem, Problem) or not isinstance(settings, Settings):
        raise TypeError("optimize(problem, settings) takes a Problem and a Settings")
    check_picklable(problem.objective, executor)
    run = _begin(problem, settings, run_dir, resume)
    phases = problem.phases()
    planned = None if settings.generations is None else settings.generations * len(phases)
    clock = _Clock(run)
    if run.evaluations == 0 and not run.history:
        _score_start(problem, settings, run, executor)
        run.group_start_f = run.best_f
    while not run.finished:
        if _budget_spent(run, settings):
            _end_run(run, f"max_evaluations ({settings.max_evaluations})", len(phases))
            continue
        if run.es is None:
            run.es = _strategy(problem, settings, phases[run.group], run)
            if settings.surrogate:
                popsize = settings.for_group(len(phases[run.group]))[0]
                run.surrogate = Surrogate(popsize, settings.surrogate_batch)
        reason = _stop_reason(run, settings, len(phases[run.group]))
        if reason:
            _end_group(run, reason, len(phases))
            continue
        try:
            _generation(problem, settings, phases[run.group], run, executor)
        except ExecutorLost as lost:  # nothing of this generation is kept
            lost.generation = len(run.history) + 1
            lost.run_dir = run_dir
            lost.saved = None if run_dir is None else len(run.history)
            raise
        run.elapsed = run.history[-1]["elapsed"] = clock.elapsed()
        if run_dir is not None:
            _save(Path(run_dir), problem, settings, run)
        if progress is not None:
            progress(_report(run, planned, settings.max_evaluations, clock))
    if run_dir is not None:
        _save(Path(run_dir), problem, settings, run)
    return Result(
        best_x=run.best_x.copy(),
        best_f=run.best_f,
        history=run.history,
        evaluations=run.evaluations,
        stopped="; ".join(run.stopped),
        refinements=run.refinements,
        start_f=run.start_f,
    )


def finished_run(run_dir: str | Path) -> str | None:
    """Why the run whose checkpoint is in ``run_dir`` stopped, if it has (its
    ``Result.stopped``); None if it has not, or there is no checkpoint.

    Resuming a finished run searches nothing more: ``optimize`` returns its result at once.
    """
    if not (Path(run_dir) / checkpoint.CHECKPOINT).is_file():
        return None
    run = checkpoint.load(Path(run_dir))["run"]
    return "; ".join(run["stopped"]) if run["finished"] else None


def _score_start(problem: Problem, settings: Settings, run: _Run, executor) -> None:
    """Evaluate the start ``x0`` (by ``refine`` when there is one), so that the answer is
    never worse than the gait the search began from: CMA-ES draws around its mean without
    evaluating it, and a good start (a hand-set gait) can beat every draw of a short run.

    It draws no random numbers, so the samples are those of a run without it.
    """
    if problem.feasible is not None and not problem.feasible(problem.x0):
        return
    scorer = problem.objective if problem.refine is None else problem.refine
    (outcome,) = evaluate(scorer, [problem.x0], executor, settings.retries, settings.penalty)
    run.evaluations += 1
    run.refinements += problem.refine is not None
    if outcome.status == OK:
        run.start_f = run.best_f = float(outcome.value)
    else:
        log.warning("the start %s (%s)", outcome.status, outcome.message)


def _begin(problem: Problem, settings: Settings, run_dir, resume: bool) -> _Run:
    """A fresh run, or the one saved in run_dir's checkpoint."""
    fresh = _Run(draws=GaussianDraws(settings.seed), best_x=problem.x0.copy())
    if run_dir is None:
        if resume:
            raise ValueError("resume=True needs the run_dir of the run to continue")
        return fresh
    run_dir = Path(run_dir)
    checkpoint.remove_leftovers(run_dir)
    if not resume:
        if (run_dir / checkpoint.CHECKPOINT).exists():
            raise FileExistsError(
                f"{run_dir} already holds an optimization checkpoint; resume it "
                "(resume=True, --resume) or write the new run to another directory"
            )
        return fresh
    state = checkpoint.load(run_dir)
    differences = checkpoint.mismatch(
        state["fingerprint"], checkpoint.fingerprint(problem, settings)
    )
    if differences:
        raise ValueError(
            f"the checkpoint in {run_dir} was written by a different run, so it cannot be "
            "resumed with this problem and these settings:\n  "
            + "\n  ".join(differences)
            + "\nResume with the run's own settings, or start a new run in another directory."
        )
    return _Run(**state["run"])


def _strategy(problem: Problem, settings: Settings, group: np.ndarray, run: _Run):
    """A CMA-ES over `group`'s coordinates, started at the best point so far."""
    import cma  # here, not at the top: workers import this package and need no pycma (1 s)

    width = problem.upper - problem.lower
    popsize, _ = settings.for_group(len(group))
    options = {
        "popsize": popsize,
        "tolfun": settings.tolfun,
        "tolx": settings.tolx,
        "bounds": [problem.lower[group].tolist(), problem.upper[group].tolist()],
        "BoundaryHandler": cma.BoundTransform,
        "CMA_stds": (width[group] / width.mean()).tolist(),
        "randn": run.draws,
        "seed": math.nan,  # pycma seeds only its default global generator, which we do not use
        "verbose": -9,
        "verb_disp": 0,
        "verb_log": 0,
    }
    if settings.generations is not None:
        options["maxiter"] = settings.generations
    if len(group) == 1:
        # pycma 4.5 fails ("not yet initialized") whenever it caps the step size of a
        # one-coordinate search; uncapped, BoundTransform still keeps samples in the box
        options.update(maxstd_boundrange=math.inf, maxstd=math.inf)
    return cma.CMAEvolutionStrategy(run.best_x[group].tolist(), problem.sigma0, options)


# pycma's criteria that read a flat fitness as convergence. Penalties are all
# equal, so a generation whose samples were penalized (a worker died, every
# sample infeasible) would otherwise end the run; it goes on instead.
FLAT_FITNESS = {"tolfun", "tolfunhist", "tolflatfitness", "tolfunrel"}


def _stop_reason(run: _Run, settings: Settings, n: int) -> str:
    """Why the group should stop now ("" if it should go on)."""
    if settings.generations is not None and run.group_generations >= settings.generations:
        return f"generations ({settings.generations})"
    converged = _converged(run, settings.for_group(n)[1], settings.tolerance)
    if converged:
        return converged
    reasons = run.es.stop()
    last = run.history[-1] if run.group_generations else None
    if last is not None and last["failures"] + last["infeasible"] > 0:
        reasons = {key: value for key, value in reasons.items() if key not in FLAT_FITNESS}
    return ", ".join(f"{key}={value}" for key, value in reasons.items())


def _converged(run: _Run, patience: int | None, tolerance: float) -> str:
    """The patience rule: "converged: ..." when the group's best improved by no more than
    ``tolerance`` of itself over its last ``patience`` generations, else ""."""
    if patience is None or run.group_generations < patience:
        return ""
    bests = [row["best"] for row in run.history[-run.group_generations :]]
    before = bests[-patience - 1] if len(bests) > patience else run.group_start_f
    gain = before - bests[-1]
    if not gain <= tolerance * abs(bests[-1]):  # inf - x (nothing scored yet) goes on
        return ""
    share = 100 * gain / abs(bests[-1]) if bests[-1] else 0.0
    return f"converged: best improved {share:.2g} % in {patience} generations"


def _budget_spent(run: _Run, settings: Settings) -> bool:
    return settings.max_evaluations is not None and run.evaluations >= settings.max_evaluations


def _end_group(run: _Run, reason: str, groups: int) -> None:
    run.stopped.append(f"group {run.group}: {reason}" if groups > 1 else reason)
    run.group, run.es, run.surrogate, run.group_generations = run.group + 1, None, None, 0
    run.group_start_f = run.best_f
    run.finished = run.group == groups


def _end_run(run: _Run, reason: str, groups: int) -> None:
    """End the run in its current group, whatever is left (the evaluation budget is spent)."""
    _end_group(run, reason, groups)
    run.finished = True


def _generation(problem: Problem, settings: Settings, group, run: _Run, executor) -> None:
    """Ask, reject infeasible samples, evaluate (all, or those the surrogate asks for), tell;
    record the generation."""
    base = run.best_x  # the coordinates outside the group stay at the best so far

    def full(z) -> np.ndarray:
        x = base.copy()
        x[group] = z
        return x

    samples = run.es.ask()
    infeasible, resamples = _reject_infeasible(run.es, samples, full, problem.feasible, settings)
    todo = [i for i in range(len(samples)) if i not in infeasible]
    cap = settings.max_evaluations
    budget = None if cap is None else cap - run.evaluations
    values = np.full(len(samples), float(settings.penalty))
    reason = f"infeasible after max_resamples = {settings.max_resamples} redraws"
    penalized = {i: (INFEASIBLE, reason) for i in infeasible}
    swum: list[int] = []

    def swim(indices: list[int]) -> dict[int, float]:
        """Evaluate one batch; the values of the samples that succeeded."""
        outcomes = evaluate(
            problem.objective, [full(samples[i]) for i in indices], executor, settings.retries,
            settings.penalty,
        )  # fmt: skip
        for i, outcome in zip(indices, outcomes, strict=True):
            values[i] = outcome.value
            if outcome.status != OK:
                penalized[i] = (outcome.status, outcome.message)
                log.warning(
                    "generation %d, sample %d %s (%s): penalty %g",
                    len(run.history) + 1, i, outcome.status, outcome.message, settings.penalty,
                )  # fmt: skip
        swum.extend(indices)
        return {i: float(values[i]) for i in indices if i not in penalized}

    if run.surrogate is None:
        swim(todo[:budget])
        told = values
    else:
        ranking = run.surrogate.rank({i: samples[i] for i in todo}, swim, budget)
        told = np.full(len(samples), float(settings.penalty))
        told[list(ranking)] = list(ranking.values())
    cut = len(swum) < len(todo) and len(swum) == budget  # the budget's last generation
    if not cut:  # (cut short: evaluated up to the cap, and CMA-ES is told nothing)
        run.es.tell(samples, told.tolist())
    succeeded = [i for i in swum if i not in penalized]
    ranked = sorted(succeeded, key=lambda i: values[i])  # stable: the first of equals first
    if problem.refine is None:
        scored = [(i, values[i]) for i in ranked[:1]]
    else:
        scored = _refined(problem, settings, ranked, full, samples, executor)
        run.refinements += len(scored)
    run.evaluations += len(swum)
    run.group_generations += 1
    for i, value in scored:
        if value < run.best_f:
            run.best_f, run.best_x = float(value), full(samples[i])
    penalties = [
        {"sample": i, "status": status, "reason": why, "x": full(samples[i]).tolist()}
        for i, (status, why) in sorted(penalized.items())
    ]
    modelled = len(todo) - len(swum)
    run.history.append(
        _record(run, values[succeeded], penalties, resamples, len(samples), modelled)
    )


def _refined(problem: Problem, settings: Settings, ranked, full, samples, executor) -> list:
    """``(sample, refine value)`` of the generation's best ``refine_top`` samples that
    ``refine`` scored (a refinement that fails scores nothing)."""
    top = ranked[: settings.refine_top]
    outcomes = evaluate(
        problem.refine, [full(samples[i]) for i in top], executor, settings.retries,
        settings.penalty,
    )  # fmt: skip
    for i, outcome in zip(top, outcomes, strict=True):
        if outcome.status != OK:
            log.warning("refining sample %d %s (%s)", i, outcome.status, outcome.message)
    return [(i, o.value) for i, o in zip(top, outcomes, strict=True) if o.status == OK]


def _record(run: _Run, succeeded: np.ndarray, penalized: list[dict], resamples: int,
            samples: int, modelled: int) -> dict:  # fmt: skip
    """One row of the history: the run after a generation of ``samples`` drawn samples
    (CMA-ES's population) whose good values are `succeeded`, ``modelled`` of them ranked by
    the surrogate without a swim."""
    statuses = [p["status"] for p in penalized]
    failed, lost, infeasible = (statuses.count(s) for s in (FAILED, LOST, INFEASIBLE))
    return {
        "generation": len(run.history) + 1,
        "group": run.group,
        "evaluations": run.evaluations,
        "best": run.best_f,
        "mean": float(np.mean(succeeded)) if succeeded.size else math.nan,
        "generation_best": float(np.min(succeeded)) if succeeded.size else math.nan,
        "sigma": float(run.es.sigma),
        "failures": failed + lost,
        "failed": failed,
        "lost": lost,
        "infeasible": infeasible,
        "resamples": resamples,
        "samples": samples,
        "elapsed": run.elapsed,
        "refinements": run.refinements,
        "modelled": modelled,
        "tau": math.nan if run.surrogate is None else float(run.surrogate.tau),
        "best_x": run.best_x.tolist(),
        "penalized": penalized,
    }


def _reject_infeasible(es, samples, full, feasible, settings: Settings) -> tuple[set[int], int]:
    """Redraw infeasible samples in place; return those still infeasible and the redraws."""
    if feasible is None:
        return set(), 0
    still_infeasible, resamples = set(), 0
    for i in range(len(samples)):
        tries = 0
        while not feasible(full(samples[i])):
            if tries == settings.max_resamples:
                still_infeasible.add(i)
                break
            samples[i] = es.ask(1)[0]
            tries += 1
        resamples += tries
    return still_infeasible, resamples


def _save(run_dir: Path, problem: Problem, settings: Settings, run: _Run) -> None:
    """Checkpoint first, then the logs: they never run ahead of the checkpoint."""
    state = {"fingerprint": checkpoint.fingerprint(problem, settings), "run": vars(run)}
    checkpoint.save(run_dir, state)
    checkpoint.write_log(run_dir, run.history, problem.names)
    checkpoint.write_failures(run_dir, run.history, problem.names)


class _Clock:
    """Seconds spent, continuing a resumed run's count; generations and evaluations done in
    this session."""

    def __init__(self, run: _Run):
        self.start, self.before = time.perf_counter(), run.elapsed
        self.done_before, self.evaluated_before = len(run.history), run.evaluations
        self.run = run

    def elapsed(self) -> float:
        return self.before + time.perf_counter() - self.start

    def per_generation(self) -> float:
        return self._per(len(self.run.history) - self.done_before)

    def per_evaluation(self) -> float:
        return self._per(self.run.evaluations - self.evaluated_before)

    def _per(self, done: int) -> float:
        return (self.elapsed() - self.before) / done if done else math.nan


def _report(run: _Run, planned: int | None, cap: int | None, clock: _Clock) -> GenerationReport:
    row = run.history[-1]
    if planned is not None:
        remaining = clock.per_generation() * max(planned - row["generation"], 0)
    elif cap is not None:
        remaining = clock.per_evaluation() * max(cap - row["evaluations"], 0)
    else:
        remaining = math.nan
    reasons = tuple(
        f"sample {p['sample']} {p['status']}: {p['reason']}"
        for p in row["penalized"]
        if p["status"] != INFEASIBLE
    )
    return GenerationReport(
        generation=row["generation"],
        planned=planned,
        group=row["group"],
        best=row["best"],
        mean=row["mean"],
        sigma=row["sigma"],
        evaluations=row["evaluations"],
        failures=row["failures"],
        elapsed=run.elapsed,
        remaining=remaining,
        samples=row["samples"],
        failed=row["failed"],
        lost=row["lost"],
        infeasible=row["infeasible"],
        reasons=reasons,
    )
