"""``aquagait bench optimize``: candidate gaits evaluated per minute, 1 and 2 workers.

For one creature (eel2d by default; ``--creature NAME`` for any), each grid,
its target grid and the coarse grid a coarse-to-fine search would rank on
(``aquagait.app.coarse``, factor 2), evaluates the same seeded set of
admissible gaits (two cycles each, as the optimizer does) serially in this
process and then on a pool of two worker processes, after a warm-up that
builds every process's scene. The baseline is the serial rate measured in the
same run (the scaling ratio). A sample whose swim fails (the body outgrows
the grid, say) is timed as far as it got and counts as a penalty, as in an
optimization; a note says how many did. Printed last: the projected wall
time of the paper's whole optimization (population x 100 generations) on 2
workers, on the target grid alone and coarse-to-fine (every sample on the
coarse grid, the best ``refine_top`` of each generation again on the target
grid). Targets (issues 4 and 10): the 2D eel in 30 minutes, the fish in 15,
the frog in an hour.
"""

from __future__ import annotations

import time
from functools import partial
from typing import TextIO

import numpy as np

GENERATIONS = 100
COARSE_FACTOR = 2.0
REFINE_TOP = 2
TARGET_MINUTES = {"eel2d": 30.0, "fish": 15.0, "frog": 60.0}


def run(repeats: int, out: TextIO, creature: str = "eel2d") -> list[dict]:
    """Time ``repeats`` samples per worker count and grid; print the table."""
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
    goal = TARGET_MINUTES.get(creature)
    verdict = f" (target {goal:.0f} min, {goal / full:.1f}x inside)" if goal else ""
    print(f"{creature}'s whole optimization ({population} x {GENERATIONS} samples) on 2 workers: "
          f"{full:.1f} min on the target grid{verdict}; coarse-to-fine (x{COARSE_FACTOR:g}, "
          f"best {REFINE_TOP} refined): {staged:.1f} min", file=out)  # fmt: skip
    for note in notes:
        print(f"note: {note}", file=out)
    return rows


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
