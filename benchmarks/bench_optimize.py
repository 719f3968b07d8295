"""Optimization benchmark: ``python benchmarks/bench_optimize.py`` is ``aquagait bench optimize``.

Candidate gaits evaluated per minute for eel2d at 64x32 and 128x64 with 1 and
2 worker processes, the scaling ratio, and the projected time of the paper's
whole 2D eel optimization (16 x 100 samples at 128x64; target: 30 minutes on
2 cores).
"""

import argparse

from aquagait.bench import run_benchmark

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=16)
    run_benchmark("optimize", repeats=parser.parse_args().repeats)
