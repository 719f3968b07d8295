"""How a creature's attitude goes under a fixed sequence of its manoeuvres, cycle by cycle:
the open-loop swim a path follower's decisions are made of, on a grid and solve of your
choosing.

Run from the repository root::

    python tools/maneuver_under_way.py manta straight*2 pitch-down*3 pitch-up*10
    python tools/maneuver_under_way.py manta straight*2 pitch-down*3 pitch-up*10 \\
        --resolution 96 48 48 --tolerance 1e-5
    python tools/maneuver_under_way.py manta straight*2 pitch-up*8 --learned runs/manta-pitch-up

Each ``NAME*K`` swims K cycles of the shipped (or ``--learned``) manoeuvre NAME, switching
at cycle boundaries, from rest on the follower's grid (``aquagait follow``'s default:
``roomy_grid``) unless ``--resolution`` says otherwise. It prints the heading, pitch and
roll of every cycle (``aquagait.metrics.Cycles.attitudes``, degrees), its travel (the
centre of mass's displacement over the cycle, body lengths) and the grid's shifts.
docs/follow.md ("How far ahead a manoeuvre's turn can be trusted") used it for the
manta's pitches on five grids and three tolerances.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import aquagait as ag
from aquagait.app.course import sines
from aquagait.app.follow import FollowSetupError, maneuver_library, roomy_grid
from aquagait.metrics import Cycles
from aquagait.sim import EulerFluid, growth_notes, init_state, make_scene
from aquagait.sim.rollout import rollout


def schedule(steps: list[str]) -> list[str]:
    """``["straight*2", "pitch-up"]`` -> ``["straight", "straight", "pitch-up"]``."""
    cycles = []
    for step in steps:
        name, _, count = step.partition("*")
        cycles += [name] * (int(count) if count else 1)
    return cycles


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("creature")
    parser.add_argument("steps", nargs="+", help="NAME*K: K cycles of manoeuvre NAME")
    parser.add_argument("--learned", nargs="*", default=(),
                        help="learned manoeuvres: gait.json files or run directories")  # fmt: skip
    parser.add_argument("--resolution", type=int, nargs="+")
    parser.add_argument("--cell-size", type=float)
    parser.add_argument("--tolerance", type=float, default=EulerFluid().tolerance)
    args = parser.parse_args()
    creature = ag.creatures.get(args.creature)
    try:
        gaits = sines(maneuver_library(creature, args.learned))
    except FollowSetupError as err:
        parser.error(str(err))
    cycles = schedule(args.steps)
    unknown = sorted(set(cycles) - set(gaits))
    if unknown:
        parser.error(f"{creature.name} has no {', '.join(unknown)}; it has {', '.join(gaits)}")
    period = float(np.max(gaits["straight"].period))
    resolution = args.resolution or roomy_grid(creature.resolution)
    scene = make_scene(creature, resolution, args.cell_size,
                       fluid=EulerFluid(tolerance=args.tolerance))  # fmt: skip
    policies = {name: creature.servo(gait) for name, gait in gaits.items()}
    shifts, origin = [], [scene.grid.origin]

    def plan(state):
        if state.grid.origin != origin[0]:
            moved = np.subtract(state.grid.origin, origin[0]) / state.grid.cell_size
            shifts.append(f"{state.time:.2f} s: {np.round(moved).astype(int).tolist()}")
            origin[0] = state.grid.origin
        return policies[cycles[min(int(state.time / period + 1e-9), len(cycles) - 1)]]

    start = time.perf_counter()
    with growth_notes() as grew:
        trajectory = rollout(scene, init_state(scene), None, len(cycles) * period,
                             plan=plan, record_fluid=False)  # fmt: skip
    cycled = Cycles(creature.model, trajectory, period)
    attitudes, travel = cycled.attitudes(), cycled.distances() / creature.model.body_length
    print(f"{creature.name} on {'x'.join(map(str, resolution))}, tolerance {args.tolerance:g}: "
          f"{time.perf_counter() - start:.0f} s")  # fmt: skip
    print("cycle  manoeuvre      heading   pitch    roll  travel")
    for k, (name, angles, moved) in enumerate(zip(cycles, attitudes, travel, strict=False), 1):
        print(f"{k:5d}  {name:12s}" + "".join(f"{a:8.1f}" for a in angles) + f"{moved:8.3f}")
    print("grid shifts (cells):", "; ".join(shifts) or "none")
    for note in grew:
        print(note)


if __name__ == "__main__":
    main()
