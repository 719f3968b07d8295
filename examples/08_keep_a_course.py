"""08 - The manta keeps level by mixing, every cycle, some of a learned pitch into its gait.

Open loop, nothing rights a swimmer in this fluid (no gravity, no buoyancy),
and the manta's shipped flapping pitches it nose up a few degrees a cycle
until, by its twelfth, it loops. Kept on its course (``prepare_swim(...,
keep_course=True)``, ``aquagait.app.course``), at each cycle's start it
mixes into its gait a share of its learned pitch-up or pitch-down, by how
far the line two cycles ahead bears off its heading, as path following
does. Prints the pitch of every cycle both ways, the shares, and the
distances; writes both runs (their metrics and trajectories). The command
line does the same: ``aquagait swim manta --seconds 20 --keep-course``.

Run:  python examples/08_keep_a_course.py [--cycles 20] [--out runs/ex08]
(``--steps N`` swims N frames only, in the simple fluid, for a quick look.)
A few minutes on 2 cores: each manoeuvre's rate is measured first (two
cycles from rest each), then the two swims.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from aquagait.app import prepare_swim, run_swim, write_swim
from aquagait.metrics import Cycles


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cycles", type=int, default=20, help="gait cycles to swim")
    parser.add_argument("--out", default="runs/ex08", help="where the runs go")
    parser.add_argument("--steps", type=int, help="swim this many frames only")
    args = parser.parse_args(argv)

    quick = args.steps is not None
    fluid = "simple" if quick else "euler"
    seconds = args.steps / 30 if quick else float(args.cycles)
    runs = {}
    for label, keep in (("open loop", False), ("kept", True)):
        setup = prepare_swim("manta", seconds=seconds, fluid=fluid, keep_course=keep)
        if keep:
            rates = ", ".join(f"{m} {r:.3f} rad" for m, r in setup.course.rates.items())
            print(f"the manta's learned pitches turn it, a cycle: {rates}")
        run = runs[label] = run_swim(setup)
        out = write_swim(run, Path(args.out) / label.replace(" ", "-"))
        print(f"{label}: {run.metrics['distance']:.2f} m in {seconds:g} s; wrote {out}")

    for label, run in runs.items():
        cycles = Cycles(run.setup.creature.model, run.trajectory, run.setup.period)
        pitch = cycles.attitudes()[:, 1] if cycles.starts.size else np.zeros(0)
        print(f"{label:>9}: pitch per cycle [deg] {np.round(pitch, 1).tolist()}")
    shares = runs["kept"].metrics["course_shares"]
    print("kept with mean shares " + ", ".join(f"{m} {s:.2f}" for m, s in shares.items()))


if __name__ == "__main__":
    main()
