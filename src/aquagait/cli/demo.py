"""``aquagait demo``: optimize eel2d on a coarse grid, swim and film it; the fish in 3D."""

from __future__ import annotations

import sys

from aquagait.cli.errors import fail
from aquagait.cli.optimize import optimize_and_swim
from aquagait.cli.swim import swim_and_write


def add_parser(commands) -> None:
    demo = commands.add_parser(
        "demo", help="optimize eel2d on a coarse grid, swim and film it; the fish in 3D"
    )
    demo.add_argument("--generations", type=int, default=20, help="CMA-ES generations (default 20)")
    demo.add_argument("--workers", type=int, help="worker processes (default: all cores)")
    demo.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    demo.add_argument("--out", default="runs/demo", metavar="DIR",
                      help="run directory (default runs/demo)")  # fmt: skip
    demo.set_defaults(run=run)


def run(args) -> int:
    from aquagait import creatures
    from aquagait.app import SetupError, demo, output_directory

    try:
        setup = demo.prepare_demo(generations=args.generations, seed=args.seed)
        out = output_directory(args.out)
    except SetupError as err:
        return fail("demo", err, status=2)
    args.resume = args.scheduler = None
    (nx, ny), fine = demo.GRID[0], creatures.get(demo.CREATURE).resolution
    print(f"aquagait demo: CMA-ES finds {demo.CREATURE} a gait on a {nx}x{ny} grid, then it "
          f"swims at {fine[0]}x{fine[1]} into {out}/", file=sys.stderr)  # fmt: skip
    status = optimize_and_swim(setup, out, args, True, default_grid=True,
                               seconds=demo.SWIM_SECONDS)  # fmt: skip
    if status:
        return status
    print(f"aquagait demo: the {demo.CREATURE_3D} swims its shipped gait in 3D into "
          f"{out}/{demo.CREATURE_3D}/", file=sys.stderr)  # fmt: skip
    return swim_and_write(demo.prepare_demo_3d(), out / demo.CREATURE_3D, video=True)
