"""Optimization benchmark: ``python benchmarks/bench_optimize.py`` is ``aquagait bench optimize``.

Samples a minute for a creature (eel2d by default) on its target and coarse
grids with 1 and 2 worker processes, then the default search run whole once
per seed (samples to its stop, minutes) beside the paper's budget (16 or 31 x
100 samples) projected at the two-worker rate of the same run
(``aquagait.bench.optimize``).
"""

import argparse

from aquagait.bench import run_benchmark

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=16)
    parser.add_argument("--creature", default="eel2d")
    parser.add_argument("--seeds", type=int, default=3)
    args = parser.parse_args()
    run_benchmark("optimize", repeats=args.repeats, creature=args.creature, seeds=args.seeds)
