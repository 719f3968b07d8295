"""``aquagait bench optimize``: the default search's whole cost beside the paper's budget.

For one creature (eel2d by default; ``--creature NAME`` for any), two parts,
every figure from this one run:

1. **Seconds a sample.** On each grid, its target grid and the coarse grid a
   coarse-to-fine search would rank on (``aquagait.app.coarse``, factor 2),
   the same seeded set of admissible gaits (two cycles each, as the
   optimizer swims them) is evaluated serially in this process and then on a
   pool of two worker processes, after a warm-up that builds every process's
   scene. The baseline is the serial rate (the scaling ratio). A sample whose
   swim fails (the body outgrows the grid, say) is timed as far as it got and
   counts as a penalty, as in an optimization; a note says how many did.
2. **The default search and the surrogate's, whole.** ``aquagait optimize
   NAME --start hand-set`` (the creature's hand-set gait where it ships one,
   else its default) with the default budget (``aquagait.optimize.Settings``:
   CMA-ES's population, stop when converged), and the same with
   ``--surrogate`` (lq-CMA-ES, two swims at a time), on two worker processes,
   the two in turn for each seed (``--seeds``): samples to its stop, wall time
   and best objective each, and their medians; the surrogate's ratios to the
   default's, and whether its median best is within 0.5 % of it. Beside them,
   the paper's budget (population 16 in 2D and 31 in 3D, 100 generations)
   projected at the two-worker rate measured in part 1: the ratio is the
   speed-up of the fitted budget. The runs are kept in
   ``runs/bench/optimize-NAME/`` (each replaced when the benchmark runs again),
   with ``convergence.png``: the best objective against real swims, both searches.

Targets, whole search on 2 workers: eel2d 5 min, the fish 20 min, eel3d, the
manta and turtle3d 45 min, the alien 1 h, the frog 2 h; the surrogate's median
best within 0.5 % of the default's.
"""

from __future__ import annotations

import math
import shutil
import statistics
import time
from functools import partial
from pathlib import Path
from typing import TextIO

import numpy as np

from aquagait.optimize.checkpoint import LOG

GENERATIONS = 100
COARSE_FACTOR = 2.0
REFINE_TOP = 2
TARGET_MINUTES = {
    "eel2d": 5.0, "fish": 20.0, "eel3d": 45.0, "manta": 45.0, "turtle3d": 45.0, "alien": 60.0,
    "frog": 120.0,
}  # fmt: skip
"""The targets for the whole search on 2 workers [min]."""


def run(repeats: int, out: TextIO, creature: str = "eel2d", seeds: int = 3) -> list[dict]:
    """Time ``repeats`` samples per worker count and grid, then ``seeds`` default searches;
    print the tables. Returns the rows of both."""
    rows, rate = _sample_rates(repeats, out, creature)
    if seeds:
        rows += _default_searches(creature, seeds, rate, out)
    return rows


def _sample_rates(repeats: int, out: TextIO, creature: str) -> tuple[list[dict], dict]:
    """Part 1: samples a minute per grid and worker count; the two-worker rate per grid."""
    import aquagait as ag
    from aquagait.app.coarse import coarse_grid
    from aquagait.app.optimize import POPULATION, SwimObjective
    from aquagait.optimize import local_executor
    from aquagait.optimize.evaluate import evaluate_sample

    model = ag.creatures.get(creature)
    target = (model.resolution, model.cell_size)
    coarse = coarse_grid(model, *target, COARSE_FACTOR)
    grids = {"target": (*target, None), "coarse": (coarse.resolution, coarse.cell_size,
                                                 coarse.clearance)}  # fmt: skip
    samples = _admissible_gaits(model, max(repeats, 4))
    print(f"{'creature':<10}{'grid':>8}{'cells':>11}{'workers':>8}{'evals_per_min':>15}"
          f"{'scaling':>9}", file=out, flush=True)  # fmt: skip
    rows, notes = [], list(coarse.notes)
    for name, (resolution, cell_size, clearance) in grids.items():
        direction = (1.0,) + (0.0,) * (model.dim - 1)
        objective = SwimObjective(creature, tuple(resolution), cell_size, direction=direction,
                                  clearance=clearance)  # fmt: skip
        sample = partial(evaluate_sample, objective)  # a failure is timed, as a penalty
        sample(samples[0])  # warm: the scene and the kernels
        serial, outcomes = _rate(lambda xs, f=sample: [f(x) for x in xs], samples)
        with local_executor(2) as pool:
            list(pool.map(sample, samples[:2]))  # warm both workers
            parallel, _ = _rate(lambda xs, f=sample, p=pool: list(p.map(f, xs)), samples)
        failed = [why for _, why in outcomes if why]
        if failed:
            notes.append(f"{len(failed)} of {len(samples)} samples failed on the {name} grid "
                         f"and count as penalties, as in an optimization: {failed[0]}")  # fmt: skip
        cells = "x".join(map(str, resolution))
        for workers, rate in ((1, serial), (2, parallel)):
            rows.append(dict(creature=creature, grid=name, cells=cells, workers=workers,
                             evals_per_minute=rate))  # fmt: skip
            scaling = f"{rate / serial:>8.2f}x" if workers == 2 else f"{'1.00x':>9}"
            print(f"{creature:<10}{name:>8}{cells:>11}{workers:>8}{rate:>15.1f}{scaling}",
                  file=out, flush=True)  # fmt: skip
    population = POPULATION[model.dim]
    rate = {row["grid"]: row["evals_per_minute"] for row in rows if row["workers"] == 2}
    full = population * GENERATIONS / rate["target"]
    staged = GENERATIONS * (population / rate["coarse"] + REFINE_TOP / rate["target"])
    print(f"{creature}'s paper-budget optimization ({population} x {GENERATIONS} samples) on 2 "
          f"workers: {full:.1f} min on the target grid; coarse-to-fine (x{COARSE_FACTOR:g}, best "
          f"{REFINE_TOP} refined): {staged:.1f} min", file=out)  # fmt: skip
    for note in notes:
        print(f"note: {note}", file=out)
    return rows, rate


SEARCHES = {"default": {}, "surrogate": {"surrogate": True, "surrogate_batch": 2}}
"""The searches run whole, by label: the default and lq-CMA-ES swimming two at a time
(one sample for each of the two workers)."""


def _default_searches(creature: str, seeds: int, rate: dict, out: TextIO) -> list[dict]:
    """Part 2: the default search and the surrogate's, whole, seed by seed in turn, beside
    the paper's budget; their convergence drawn in one picture."""
    from aquagait.app.optimize import POPULATION, prepare_optimization, run_optimization
    from aquagait.optimize import local_executor

    start = "hand-set" if "hand-set" in _gaits(creature) else None
    runs = Path("runs") / "bench" / f"optimize-{creature}"
    print(f"\n{'seed':>4}  {'search':<10}{'samples':>8}{'generations':>13}{'minutes':>9}"
          f"{'best':>10}  stopped (optimize {creature} --start {start or 'default'} --seed S "
          f"[--surrogate], 2 workers)", file=out, flush=True)  # fmt: skip
    rows = []
    for seed in range(1, seeds + 1):
        for search, flags in SEARCHES.items():
            setup = prepare_optimization(creature, seed=seed, start=start, **flags)
            run_dir = runs / f"{search}-seed{seed}"
            shutil.rmtree(run_dir, ignore_errors=True)  # this benchmark's own, of a run before
            run_dir.mkdir(parents=True)
            with local_executor(2) as pool:
                began = time.perf_counter()
                result = run_optimization(setup, run_dir, pool)
                minutes = (time.perf_counter() - began) / 60
            rows.append(dict(creature=creature, seed=seed, search=search,
                             samples=result.evaluations, generations=result.generations,
                             minutes=minutes, best=result.best_f, stopped=result.stopped,
                             log=run_dir / LOG))  # fmt: skip
            print(f"{seed:>4}  {search:<10}{result.evaluations:>8}{result.generations:>13}"
                  f"{minutes:>9.1f}{result.best_f:>10.4g}  {result.stopped}", file=out,
                  flush=True)  # fmt: skip
    plain, modelled = ([row for row in rows if row["search"] == s] for s in SEARCHES)
    samples, minutes, best = _medians(plain)
    paper_samples = POPULATION[setup.creature.dim] * GENERATIONS
    paper = paper_samples / rate["target"]
    goal = TARGET_MINUTES.get(creature)
    print(f"default search: median {samples:.0f} samples to its stop, {60 * minutes / samples:.2f} "
          f"s a sample on 2 workers, {minutes:.1f} min whole{_verdict(minutes, goal)}; the "
          f"paper's budget ({paper_samples} samples) {paper:.1f} min at this run's rate: "
          f"{paper / minutes:.1f}x the time, {paper_samples / samples:.1f}x the samples",
          file=out)  # fmt: skip
    m_samples, m_minutes, m_best = _medians(modelled)
    worse = (m_best - best) / abs(best) if best else math.nan  # > 0: a worse (higher) best
    quality = "met" if worse <= QUALITY else "missed"
    print(f"surrogate search: median {m_samples:.0f} samples ({samples / m_samples:.2f}x "
          f"fewer), {m_minutes:.1f} min whole ({minutes / m_minutes:.2f}x faster)"
          f"{_verdict(m_minutes, goal)}; median best {m_best:.4g} against {best:.4g}, "
          f"{100 * worse:+.2f} % (target within +{100 * QUALITY:g} %: {quality})",
          file=out)  # fmt: skip
    logs = {search: [row["log"] for row in runs_of] for search, runs_of in
            zip(SEARCHES, (plain, modelled), strict=True)}  # fmt: skip
    _draw(creature, logs, runs / "convergence.png", out)
    return rows


def _medians(rows: list[dict]) -> tuple[float, float, float]:
    """Median samples, minutes and best objective of the searches in ``rows``."""
    return tuple(statistics.median(row[k] for row in rows) for k in ("samples", "minutes", "best"))


QUALITY = 0.005
"""The surrogate's median best may be this much worse than the default's (a share of it)."""


def _verdict(minutes: float, goal: float | None) -> str:
    return f" (target {goal:.0f} min: {'met' if minutes <= goal else 'missed'})" if goal else ""


def _draw(creature: str, logs: dict[str, list[Path]], path: Path, out: TextIO) -> None:
    """Best objective against real swims, one colour per search (needs the viz extra)."""
    try:
        from aquagait.viz import plot_budgets
    except ImportError as err:
        print(f"note: no convergence picture ({err}; pip install aquagait[viz])", file=out)
        return
    print(f"wrote {plot_budgets(logs, path, title=creature)}", file=out)


def _gaits(creature: str) -> dict:
    import aquagait as ag

    return ag.creatures.get(creature).gaits


def _rate(evaluate, samples) -> tuple[float, list]:
    """Samples per minute of ``evaluate(samples)``, and what it returned."""
    start = time.perf_counter()
    outcomes = evaluate(samples)
    return 60.0 * len(samples) / (time.perf_counter() - start), outcomes


def _admissible_gaits(creature, count: int) -> list[np.ndarray]:
    """``count`` gaits drawn around the default one, inside bounds and joint limits."""
    gait, rng = creature.gait, np.random.default_rng(0)
    lower, upper = creature.gait_limits()
    gaits = []
    while len(gaits) < count:
        x = creature.default_gait + rng.normal(0, 0.2, gait.size) * (gait.upper - gait.lower)
        x = np.clip(x, gait.lower, gait.upper)
        if not gait.limit_violations(x, lower, upper):
            gaits.append(x)
    return gaits
