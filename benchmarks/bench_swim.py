"""Swim benchmark: ``python benchmarks/bench_swim.py`` is ``aquagait bench swim``.

Wall time per output frame (1/30 s simulated) of every library creature the
paper has, on its default grid, on one core, beside the paper's Table 1 (eel2d
0.64 s and the fish 1.45 s per frame, up to the frog's 12.79 s; C++, 2011).
Target (issue 4): at least 30x faster than the paper.
"""

import argparse

from aquagait.bench import run_benchmark

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=15)
    run_benchmark("swim", repeats=parser.parse_args().repeats)
