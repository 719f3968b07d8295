"""Environment benchmark: ``python benchmarks/bench_env.py`` is ``aquagait bench env``.

Control steps per second of the Gymnasium environment (``aquagait.envs``) for
eel2d and the fish, with and without the lateral line, beside a plain
``rollout`` of the same creature and length in the same run: their ratio is
the environment's own cost (issue 34: it should be small).
"""

import argparse

from aquagait.bench import run_benchmark

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=60, help="control steps timed per case")
    run_benchmark("env", repeats=parser.parse_args().repeats)
