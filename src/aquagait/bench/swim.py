"""``aquagait bench swim``: wall time per output frame of a coupled swim.

Each case swims a library creature with its shipped gait on its default
grid for half a second (the wake forms), then times whole frames (1/30 s simulated: the
CFL-limited coupled steps that make one frame). The baseline is the paper's
Table 1 (Tan et al. 2011, single core, C++, 2011) for the same grids: 0.64 s
per frame for the 2D eel at 128x64 and 1.45 s for the fish at 64x32x32.
The target is 30x faster than the paper.
"""

from __future__ import annotations

import statistics
import time
from typing import TextIO

PAPER_SECONDS_PER_FRAME = {"eel2d": 0.64, "fish": 1.45}
TARGET_RATIO = 30.0
WARMUP_FRAMES = 15


def run(repeats: int, out: TextIO) -> list[dict]:
    """Time ``repeats`` frames per creature and print the table; returns its rows."""
    import aquagait as ag
    from aquagait.sim import advance

    print(
        f"{'creature':<10}{'grid':>11}{'s_per_frame':>13}{'steps':>7}{'paper_s':>9}"
        f"{'ratio':>8}{'target':>8}",
        file=out,
    )
    rows = []
    for name, paper in PAPER_SECONDS_PER_FRAME.items():
        creature = ag.creatures.get(name)
        scene = ag.make_scene(creature, fluid="euler")
        policy = creature.policy()
        state = ag.init_state(scene)
        seconds, steps = [], []
        for frame in range(WARMUP_FRAMES + repeats):
            start, before = time.perf_counter(), state.steps
            state = advance(scene, state, policy, state.time + 1 / 30)
            elapsed = time.perf_counter() - start
            if frame >= WARMUP_FRAMES:
                seconds.append(elapsed)
                steps.append(state.steps - before)
        per_frame = statistics.median(seconds)
        row = dict(
            creature=name,
            grid="x".join(map(str, creature.resolution)),
            seconds_per_frame=per_frame,
            steps_per_frame=statistics.median(steps),
            paper=paper,
            ratio=paper / per_frame,
        )
        rows.append(row)
        print(
            f"{name:<10}{row['grid']:>11}{per_frame:>13.4f}{row['steps_per_frame']:>7.0f}"
            f"{paper:>9.2f}{row['ratio']:>7.1f}x{TARGET_RATIO:>7.0f}x",
            file=out,
            flush=True,
        )
    return rows
