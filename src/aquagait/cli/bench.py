"""``aquagait bench``: measure speed against in-run baselines."""

from __future__ import annotations

import sys

from aquagait.bench import BENCHMARKS
from aquagait.cli.errors import fail


def add_parser(commands) -> None:
    bench = commands.add_parser("bench", help="measure speed against in-run baselines")
    bench.add_argument("what", choices=BENCHMARKS, help="which benchmark to run")
    bench.add_argument("--repeats", type=int, default=10,
                       help="timed repetitions per case (default 10)")  # fmt: skip
    bench.add_argument("--profile", action="store_true", help="swim: time per phase of a step")
    bench.add_argument(
        "--compare-advection", action="store_true", help="swim: old and new advection, one run"
    )
    bench.add_argument(
        "--compare-still", action="store_true",
        help="swim: every departure point at second order beside still water traced by one "
        "Euler step (today's), one run",
    )  # fmt: skip
    bench.add_argument(
        "--compare-precision", action="store_true",
        help="swim: float64 and float32 face velocities, one run",
    )  # fmt: skip
    bench.add_argument(
        "--compare-boundary",
        action="store_true",
        help="swim: staircase and sub-cell boundaries, one run",
    )
    bench.add_argument(
        "--compare-start",
        action="store_true",
        help="swim: the step as the 3D-speed work found it beside today's, one run",
    )
    bench.add_argument(
        "--compare-thin",
        action="store_true",
        help="swim: the step before thin parts were closed beside today's, one run",
    )
    bench.add_argument(
        "--creature", metavar="NAME",
        help="optimize: the creature to time (default eel2d); swim --profile or --compare-*: "
        "that creature alone (default: every creature of the paper's Table 1)",
    )  # fmt: skip
    bench.add_argument("--seeds", type=int, metavar="K",
                       help="optimize: default searches run whole, seeds 1..K (default 3; 0: "
                       "time the samples only)")  # fmt: skip
    bench.set_defaults(run=run)


def run(args) -> int:
    from aquagait.bench import run_benchmark

    try:
        run_benchmark(args.what, repeats=args.repeats, out=sys.stdout, profile=args.profile,
                      compare_advection=args.compare_advection,
                      compare_still=args.compare_still,
                      compare_precision=args.compare_precision,
                      compare_boundary=args.compare_boundary,
                      compare_start=args.compare_start,
                      compare_thin=args.compare_thin,
                      creature=args.creature, seeds=args.seeds)  # fmt: skip
    except (ValueError, KeyError) as err:  # KeyError: an unknown creature
        return fail("bench", err, status=2)
    return 0
