"""What moves a gait's figures at cruise: the same gait swum with one setting changed.

Run from the repository root::

    python tools/cruise_study.py eel2d --gait efficient --seconds 12
    python tools/cruise_study.py eel2d --gait straight --cases default step/3 grid*2 period*2

Each case swims the gait from rest for ``--seconds`` (stretched with the period:
the same number of cycles) and prints its figures at cruise (``aquagait.metrics``):
the cycle it settled from, body lengths per cycle, the tail's peak-to-peak
amplitude, the Strouhal number and the cost of transport. The cases:

- ``default``: the creature's grid and step;
- ``step/K``: the largest time step K times smaller;
- ``grid*K``: cells K times smaller over the same domain;
- ``period*K``: the gait's period K times longer (and the step with it, so a cycle
  has as many steps);
- ``amplitude*K``: every joint's amplitude K times larger, clipped to its limits;
- ``simple``: the drag-only fluid instead of the Euler one.

It answers issue 32's question of which cause keeps a gait's Strouhal number
outside 0.2-0.4 (grid, time step, the inviscid model, the period, the stroke).
``--json FILE`` writes the rows too.
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace

import numpy as np

from aquagait.app import prepare_swim, run_swim
from aquagait.app.swim import SwimSetup
from aquagait.sim import make_scene

CASES = ("default", "step/3", "grid*2", "period*2", "period*0.5")
FIGURES = ("settled_cycle", "cruise_body_lengths_per_cycle", "cruise_tail_amplitude",
           "cruise_strouhal", "cruise_cost_of_transport")  # fmt: skip


def case_setup(base: SwimSetup, case: str) -> SwimSetup:
    """The swim of ``base`` with ``case``'s one change (module docstring)."""
    creature = base.creature
    kind, _, factor = case.replace("/", "*").partition("*")
    k = float(factor) if factor else 1.0
    setup, dt = base, base.scene.fluid.max_dt
    if kind == "step":
        setup = replace(base, dt=dt / k)
    elif kind == "grid":
        resolution = tuple(int(round(n * k)) for n in creature.resolution)
        scene = make_scene(creature, resolution, creature.cell_size / k, fluid="euler")
        setup = replace(base, scene=scene)
    elif kind in ("period", "amplitude"):
        spec = creature.spec(base.maneuver, free_period=True)
        gait = base.gait
        x = spec.vector(gait)
        if kind == "period":
            x[list(spec.names).index("period")] *= k
            setup = replace(base, dt=dt * k, seconds=base.seconds * k)
        else:
            amplitudes = [i for i, n in enumerate(spec.names) if n.startswith("amplitude")]
            x[amplitudes] *= k
            x = np.minimum(x, spec.upper)
        setup = replace(setup, params=x, free_period=True)
        problems = spec.limit_violations(x, *creature.gait_limits(base.maneuver))
        if problems:
            raise SystemExit(f"{case}: the gait leaves the joint limits: {problems}")
    elif kind == "simple":
        setup = replace(base, scene=make_scene(creature, fluid="simple"))
    elif kind != "default":
        raise SystemExit(f"unknown case {case!r}; cases: {', '.join(CASES)}, amplitude*K, simple")
    return setup


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("creature")
    parser.add_argument("--gait", default=None, help="a shipped gait's name or a gait.json")
    parser.add_argument("--seconds", type=float, default=12.0)
    parser.add_argument("--cases", nargs="+", default=list(CASES))
    parser.add_argument("--json", help="also write the rows to this file")
    args = parser.parse_args()
    base = prepare_swim(args.creature, gait=args.gait, seconds=args.seconds)
    print(f"{args.creature} {args.gait or 'straight'}: " + " | ".join(("case",) + FIGURES + ("s",)))
    rows = []
    for case in args.cases:
        start = time.perf_counter()
        metrics = run_swim(case_setup(base, case)).metrics
        row = {"case": case, **{f: metrics.get(f) for f in FIGURES}}
        row["wall_time"] = time.perf_counter() - start
        rows.append(row)
        cells = [f"{row[f]:.3g}" if row[f] is not None else "-" for f in FIGURES]
        print(" | ".join([case, *cells, f"{row['wall_time']:.0f}"]), flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
