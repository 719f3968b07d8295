"""Fluid benchmark: ``python benchmarks/bench_fluid.py`` is ``aquagait bench fluid``.

One fluid step (BFECC advection + projection) around a static disc or sphere
at 128x64, 64x32x32 and 96x64x48, on one core, with the pressure solve timed
beside SciPy's unpreconditioned CG on the same system in the same run.
Targets (issue 2): 3 / 30 / 120 ms per step; solve >= 10x SciPy at 64x32x32.
"""

import argparse

from aquagait.bench import run_benchmark

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=10)
    run_benchmark("fluid", repeats=parser.parse_args().repeats)
