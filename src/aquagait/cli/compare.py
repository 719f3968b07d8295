"""``aquagait compare``: one gait in the Euler and the simple fluid, and on request a gait
optimized in each and swum in both."""

from __future__ import annotations

import math
import sys
from pathlib import Path

from aquagait.cli.errors import fail
from aquagait.cli.flags import GAIT_HELP, NAME_HELP, thicken_flag
from aquagait.cli.progress import GenerationLine, ProgressBar, fluid_bar
from aquagait.cli.workers import add_evaluator_flags, executor_for

CONVERGED = math.inf
"""``compare --optimize`` with no count: no generation count, each search runs until it has
converged (not a string: argparse would pass it through ``int``)."""


def add_parser(commands) -> None:
    compare = commands.add_parser(
        "compare", help="one gait in the Euler and the simple fluid: distances, plot, video"
    )
    compare.add_argument("name", metavar="NAME", help=NAME_HELP)
    thicken_flag(compare)
    compare.add_argument("--gait", metavar="FILE|NAME", help=GAIT_HELP)
    compare.add_argument("--seconds", type=float, default=3.0,
                         help="simulated time [s] (default 3)")  # fmt: skip
    compare.add_argument("--optimize", type=int, nargs="?", const=CONVERGED, metavar="G",
                         help="also optimize a gait in each fluid (G generations; without G, "
                         "until converged) and swim each in both")  # fmt: skip
    compare.add_argument("--popsize", type=int, metavar="N",
                         help="--optimize: samples per generation (default: CMA-ES's "
                         "for the number of parameters)")  # fmt: skip
    compare.add_argument("--seed", type=int, default=0, help="--optimize: random seed (default 0)")
    compare.add_argument("--start", metavar="FILE|NAME",
                         help="--optimize: the gait both searches start from "
                         "(default: the shipped gait)")  # fmt: skip
    compare.add_argument("--resume", action="store_true",
                         help="--optimize: continue the searches in --out")  # fmt: skip
    add_evaluator_flags(compare)
    compare.add_argument("--resolution", type=int, nargs="+", metavar="N",
                         help="Euler grid cells per axis")  # fmt: skip
    compare.add_argument("--cell-size", type=float, metavar="H", help="Euler cell size [m]")
    compare.add_argument("--out", metavar="DIR", help="directory (default: runs/NAME-compare)")
    compare.add_argument("--no-video", action="store_true", help="skip the plot and video")
    compare.set_defaults(run=run)


def run(args) -> int:
    from aquagait.app import SetupError, output_directory
    from aquagait.app.compare import cross_optimize, forward_distance, swim_both, write_compare
    from aquagait.app.resolve import find_creature
    from aquagait.sim import SimulationError

    grid = dict(resolution=args.resolution, cell_size=args.cell_size)
    given = {"--resume": args.resume, "--start": args.start, "--popsize": args.popsize}
    alone = [flag for flag, value in given.items() if value]
    if alone and args.optimize is None:
        return fail("compare", f"{', '.join(alone)}: only with --optimize [G]", status=2)
    try:
        name = find_creature(args.name).name
        out = output_directory(args.out or Path("runs") / f"{name}-compare")
        runs = swim_both(args.name, args.gait, args.seconds, progress=fluid_bar(), **grid)
    except SetupError as err:
        return fail("compare", err, status=2)
    except SimulationError as err:
        return fail("compare", err, status=1)
    for fluid, run in runs.items():
        m = run.metrics
        steady = f", {m['steady_body_lengths_per_cycle']:.3f} steady" if "steady_speed" in m else ""
        print(f"{fluid:>7} fluid: {forward_distance(run):+.4f} m along x, "
              f"{m['body_lengths_per_cycle_from_rest']:.3f} body lengths per cycle from rest"
              f"{steady}")  # fmt: skip
        for note in run.grid_notes:
            print(f"        {note}")
    cross = None
    if args.optimize is not None:
        from aquagait.optimize import ExecutorLost

        budget = "until converged" if args.optimize == CONVERGED else f"{args.optimize} generations"
        generations_given = None if args.optimize == CONVERGED else args.optimize

        def generations(fluid):
            print(f"optimizing {name} in the {fluid} fluid ({budget}, "
                  f"run directory {out / f'optimize-{fluid}'})", file=sys.stderr)  # fmt: skip
            return GenerationLine()

        try:
            with executor_for(args) as executor:
                cross = cross_optimize(
                    args.name, generations_given, args.seconds, seed=args.seed, executor=executor,
                    out=out, resume=args.resume, start=args.start, popsize=args.popsize,
                    progress=generations, **grid,
                )  # fmt: skip
        except SetupError as err:
            return fail("compare", err, status=2)
        except (ExecutorLost, SimulationError) as err:  # a trained gait's swim may fail too
            return fail("compare", err, status=1)
        except (FileExistsError, FileNotFoundError, ValueError, OSError) as err:
            return fail("compare", err, status=2)
        for trained, swum in cross["distance"].items():
            row = ", ".join(f"in {fluid} {metres:+.4f} m" for fluid, metres in swum.items())
            print(f"gait trained in the {trained} fluid swims {row}")
        for note in cross["notes"]:
            print(f"        {note}")
    from aquagait.app import RenderUnavailable

    try:
        write_compare(runs, out, args.gait, cross, video=not args.no_video,
                      progress=ProgressBar("rendering"))  # fmt: skip
    except RenderUnavailable as err:
        print(f"aquagait: the video is skipped, the runs are kept: {err}", file=sys.stderr)
    print(f"wrote {out}/")
    return 0
