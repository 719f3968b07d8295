"""``aquagait bench env``: control steps per second of the Gymnasium environment.

Each case swims a creature's shipped gait through the environment (residual
actions of zero: the same simulation as ``aquagait swim``, bit for bit) and,
as the baseline in the same run, through a plain ``rollout`` of the same
creature and length without recording the fluid. The two do the same
physics, so their ratio is the environment's own cost: the observation (the
root's motion, the joint angles, the task), the reward, the checks, and with
``sense_flow`` the lateral line. Both start from rest on the creature's
default grid; the first ``WARMUP`` seconds are not timed (the flow forms and
Numba's kernels load).
"""

from __future__ import annotations

import time
from typing import TextIO

import numpy as np

CASES = (("eel2d", False), ("eel2d", True), ("fish", False), ("fish", True))
"""(creature, lateral line) per row."""
WARMUP = 0.2
"""Seconds swum before the timing starts [s]."""


def run(repeats: int, out: TextIO) -> list[dict]:
    """Time ``repeats`` control steps (at least 10) per case through the environment and
    through ``rollout``; print the table and return its rows."""
    import aquagait as ag
    from aquagait.envs import SwimEnv
    from aquagait.sim import advance

    steps = max(repeats, 10)
    print(f"{'creature':<10}{'sensing':>9}{'env_steps/s':>13}{'rollout_steps/s':>17}"
          f"{'overhead':>10}", file=out)  # fmt: skip
    rows = []
    for name, sensing in CASES:
        env = SwimEnv(name, action="residual", sense_flow=sensing, seconds=WARMUP + steps / 30)
        env.reset(seed=0)
        zero = np.zeros(env.action_space.shape)
        warm = int(round(WARMUP / env.control_dt))
        for _ in range(warm):
            env.step(zero)
        began = time.perf_counter()
        for _ in range(steps):
            env.step(zero)
        env_rate = steps / (time.perf_counter() - began)

        creature = ag.creatures.get(name)
        scene = ag.make_scene(creature, fluid="euler")
        policy = creature.policy()
        state = advance(scene, ag.init_state(scene), policy, warm / 30)
        began = time.perf_counter()
        ag.rollout(scene, state, policy, steps / 30, record_fluid=False)
        rollout_rate = steps / (time.perf_counter() - began)
        row = dict(creature=name, sensing=sensing, env_steps_per_second=env_rate,
                   rollout_steps_per_second=rollout_rate,
                   overhead=rollout_rate / env_rate - 1)  # fmt: skip
        rows.append(row)
        print(f"{name:<10}{'yes' if sensing else 'no':>9}{env_rate:>13.1f}{rollout_rate:>17.1f}"
              f"{row['overhead']:>+10.1%}", file=out, flush=True)  # fmt: skip
    return rows
