"""Swim benchmark: ``python benchmarks/bench_swim.py`` is ``aquagait bench swim``.

Wall time per output frame (1/30 s simulated) of eel2d at 128x64 and the fish
at 64x32x32, on one core, beside the paper's Table 1 (0.64 s and 1.45 s per
frame, C++, 2011). Target (issue 4): at least 30x faster than the paper.
"""

import argparse

from aquagait.bench import run_benchmark

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=15)
    run_benchmark("swim", repeats=parser.parse_args().repeats)
