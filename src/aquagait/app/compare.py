"""The same creature and gait in the Euler fluid and in the simple drag fluid (paper §7).

    runs = swim_both("accordion2d", gait=None, seconds=3.0)        # {fluid: SwimRun}
    table = cross_optimize("accordion2d", generations=8)           # gait per fluid, swum in each
    write_compare(runs, "runs/accordion2d-compare", cross=table)   # runs, compare.json, pictures

The paper's point: a simplified fluid misleads. The accordion swims in the
Euler fluid and stays nearly in place in the simple one, and gaits trained in
each differ. ``swim_both`` swims one gait in both fluids; ``cross_optimize``
optimizes a gait in each fluid and swims each gait in each fluid.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from aquagait.app.optimize import prepare_optimization, run_optimization, write_optimization
from aquagait.app.swim import SwimRun, prepare_swim, run_swim, write_swim
from aquagait.io.run import write_json
from aquagait.optimize import CHECKPOINT

FLUIDS = ("euler", "simple")


def swim_both(name: str, gait=None, seconds: float = 3.0, progress=None, **grid) -> dict:
    """Swim one gait in both fluids.

    Args:
        name: library creature.
        gait: a gait.json path, a parameter vector, or None for the shipped gait.
        seconds: simulated time [s].
        progress: optional ``progress(fluid, frames_done, frames_total)``.
        **grid: ``resolution`` and ``cell_size`` for the Euler fluid.
    Returns:
        ``{fluid: SwimRun}``.
    """
    runs = {}
    for fluid in FLUIDS:
        setup = prepare_swim(name, gait=gait, seconds=seconds, fluid=fluid, **grid)
        report = None if progress is None else (lambda d, t, f=fluid: progress(f, d, t))
        runs[fluid] = run_swim(setup, progress=report)
    return runs


def forward_distance(run: SwimRun) -> float:
    """How far the root swam along +x [m]."""
    x = run.trajectory.qpos[:, 0]
    return float(x[-1] - x[0])


def cross_optimize(
    name: str,
    generations: int | None = None,
    seconds: float = 3.0,
    seed: int = 0,
    executor=None,
    out=None,
    resume: bool = False,
    start=None,
    popsize: int | None = None,
    progress=None,
    **grid,
) -> dict:
    """Optimize a gait in each fluid, then swim each gait in each fluid.

    Args:
        name: library creature or MJCF path.
        generations: the most CMA-ES generations in each fluid; None: each search
            stops when converged (``prepare_optimization``).
        seconds: how long each gait swims in each fluid afterwards [s].
        seed: the searches' seed (the same in both fluids).
        executor: evaluates the samples (``aquagait.optimize``); None: this process.
        out: if given, each fluid's search keeps its run directory in
            ``out/optimize-<fluid>/`` (checkpoint after every generation,
            ``optimization.csv``, and ``gait.json`` once done).
        resume: continue the searches whose checkpoints are there (a finished
            one is read back, not run again).
        start: where both searches start (``prepare_optimization``); None: the
            shipped gait.
        popsize: samples per generation; None: CMA-ES's for the number of parameters.
        progress: optional ``progress(fluid)`` returning the per-generation
            callback of that fluid's search (``GenerationLine``).
        **grid: ``resolution`` and ``cell_size`` for the Euler fluid.

    Returns:
        ``{"gaits": {trained_in: params}, "distance": {trained_in: {swum_in: metres}},
        "body_lengths_per_cycle_from_rest": {...}, "objective": {trained_in: value},
        "seed": seed, "generations": generations, "start": start}``.
    """
    setups = {
        fluid: prepare_optimization(
            name,
            generations=generations,
            popsize=popsize,
            seed=seed,
            fluid=fluid,
            start=start,
            **_grid_for(fluid, grid),
        )
        for fluid in FLUIDS
    }  # both checked before either runs
    gaits, objective = {}, {}
    for fluid, setup in setups.items():
        run_dir = None if out is None else Path(out) / f"optimize-{fluid}"
        report = None if progress is None else progress(fluid)
        result = run_optimization(setup, run_dir, executor, resume and _started(run_dir), report)
        if run_dir is not None:
            write_optimization(setup, result, run_dir, plot=False)
        gaits[fluid], objective[fluid] = result.best_x, float(result.best_f)
    distance, per_cycle, notes = {}, {}, []
    for trained, params in gaits.items():
        runs = swim_both(name, gait=params, seconds=seconds, **grid)
        notes += [f"gait trained in {trained}, in {f}: {n}" for f, r in runs.items()
                  for n in r.grid_notes]  # fmt: skip
        distance[trained] = {f: forward_distance(r) for f, r in runs.items()}
        per_cycle[trained] = {
            f: r.metrics["body_lengths_per_cycle_from_rest"] for f, r in runs.items()
        }
    return {
        "gaits": {f: np.asarray(p).tolist() for f, p in gaits.items()},
        "distance": distance,
        "body_lengths_per_cycle_from_rest": per_cycle,
        "objective": objective,
        "seed": seed,
        "generations": generations,
        "start": None if start is None else str(start),
        "notes": notes,
    }


def _started(run_dir) -> bool:
    """Whether a search left a checkpoint in ``run_dir``: a resumed comparison resumes the
    searches that began and starts those that did not (stopped during the first search,
    the second has no checkpoint yet)."""
    return run_dir is not None and (Path(run_dir) / CHECKPOINT).exists()


def _grid_for(fluid: str, grid: dict) -> dict:
    return grid if fluid == "euler" else {}


def write_compare(
    runs: dict, out, gait=None, cross=None, video: bool = False, progress=None
) -> dict:
    """Write each fluid's run directory, ``compare.json`` and, if ``video``, the pictures.

    Args:
        runs: ``swim_both``'s ``{fluid: SwimRun}``.
        out: the directory; each swim goes into ``out/<fluid>/``.
        gait: where the gait came from (for the summary), None for the shipped gait.
        cross: ``cross_optimize``'s table, if one was made.
        video: also write ``displacement.png`` and ``compare.mp4`` (the ``viz`` extra).
        progress: optional ``progress(frames_done, frames_total)`` while rendering.
    Returns:
        The summary written to ``compare.json``.
    """
    out = Path(out)
    seconds = next(iter(runs.values())).setup.seconds
    summary = {"gait": str(gait or "default"), "seconds": seconds, "swims": {}}
    for fluid, run in runs.items():
        write_swim(run, out / fluid)
        summary["swims"][fluid] = {"distance": forward_distance(run), **run.metrics}
    if cross is not None:
        summary["cross"] = cross
    write_json(out / "compare.json", summary)  # before the pictures, which may be skipped
    if video:
        from aquagait.viz import plot_displacement, render_side_by_side

        creature = next(iter(runs.values())).setup.creature
        plot_displacement(runs, out / "displacement.png", title=creature.name)
        render_side_by_side(runs, creature.model, out / "compare.mp4", progress=progress)
    return summary
