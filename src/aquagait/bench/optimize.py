"""``aquagait bench optimize``: candidate gaits evaluated per minute, 1 and 2 workers.

Each case evaluates the same seeded set of admissible eel2d gaits (two cycles
each, as the optimizer does) serially in this process and then on a pool of
two worker processes, after a warm-up that builds every process's scene. The
baseline is the serial rate measured in the same run (the scaling ratio); the
target is the paper's whole 2D eel optimization, 16 x 100 samples at 128x64,
in under 30 minutes on 2 cores.
"""

from __future__ import annotations

import time
from typing import TextIO

import numpy as np

CASES = {"64x32": ((64, 32), 0.02), "128x64": ((128, 64), 0.01)}
PAPER_SAMPLES = 16 * 100
TARGET_MINUTES = 30.0


def run(repeats: int, out: TextIO) -> list[dict]:
    """Time ``repeats`` samples per worker count and grid; print the table."""
    from aquagait.app.optimize import SwimObjective
    from aquagait.optimize import local_executor

    samples = _admissible_gaits(max(repeats, 4))
    print(f"{'grid':<8}{'workers':>8}{'evals_per_min':>15}{'scaling':>9}", file=out, flush=True)
    rows = []
    for name, (resolution, cell_size) in CASES.items():
        objective = SwimObjective("eel2d", resolution, cell_size)
        objective(samples[0])  # warm: the scene and the kernels
        serial = _rate(lambda xs, f=objective: [f(x) for x in xs], samples)
        with local_executor(2) as pool:
            list(pool.map(objective, samples[:2]))  # warm both workers
            parallel = _rate(lambda xs, f=objective, p=pool: list(p.map(f, xs)), samples)
        for workers, rate in ((1, serial), (2, parallel)):
            rows.append(dict(grid=name, workers=workers, evals_per_minute=rate))
            scaling = f"{rate / serial:>8.2f}x" if workers == 2 else f"{'1.00x':>9}"
            print(f"{name:<8}{workers:>8}{rate:>15.1f}{scaling}", file=out, flush=True)
    minutes = PAPER_SAMPLES / rows[-1]["evals_per_minute"]
    margin = TARGET_MINUTES / minutes
    print(
        f"paper's eel optimization ({PAPER_SAMPLES} samples at 128x64) on 2 workers: "
        f"{minutes:.1f} min (target {TARGET_MINUTES:.0f} min, {margin:.1f}x inside)",
        file=out,
    )
    return rows


def _rate(evaluate, samples) -> float:
    start = time.perf_counter()
    evaluate(samples)
    return 60.0 * len(samples) / (time.perf_counter() - start)


def _admissible_gaits(count: int) -> list[np.ndarray]:
    """``count`` gaits drawn around the shipped one, inside bounds and joint limits."""
    import aquagait as ag

    eel = ag.creatures.get("eel2d")
    rng = np.random.default_rng(0)
    lower, upper = eel.gait_limits()
    gaits = []
    while len(gaits) < count:
        x = eel.default_gait + rng.normal(0, 0.2, eel.gait.size) * (eel.gait.upper - eel.gait.lower)
        x = np.clip(x, eel.gait.lower, eel.gait.upper)
        if not eel.gait.limit_violations(x, lower, upper):
            gaits.append(x)
    return gaits
