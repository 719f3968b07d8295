"""The ``aquagait`` command line: thin, each flag maps to a library argument."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import aquagait
from aquagait.bench import BENCHMARKS
from aquagait.sim import FLUIDS_NOW


def _cmd_bench(args) -> int:
    from aquagait.bench import run_benchmark

    run_benchmark(args.what, repeats=args.repeats, out=sys.stdout)
    return 0


def _cmd_creatures(args) -> int:
    from aquagait import creatures

    print(creatures.format_table())
    return 0


def _cmd_swim(args) -> int:
    from aquagait.io import SwimSetupError, prepare_swim, run_swim, swim_summary, write_swim
    from aquagait.sim import SimulationDiverged

    try:
        setup = prepare_swim(
            args.name,
            gait=args.gait,
            seconds=args.seconds,
            fluid=args.fluid,
            resolution=args.resolution,
            cell_size=args.cell_size,
        )
    except SwimSetupError as err:
        return _fail("swim", err, status=2)
    try:
        run = run_swim(setup, progress=ProgressBar("swimming"))
    except SimulationDiverged as err:
        return _fail("swim", err, status=1)
    out = write_swim(run, args.out or Path("runs") / args.name)
    if not args.no_video:
        from aquagait.viz import render_swim

        render_swim(
            run.trajectory,
            setup.creature.model,
            out / "swim.mp4",
            progress=ProgressBar("rendering"),
        )
    print(swim_summary(run, out))
    return 0


class ProgressBar:
    """``progress(done, total)`` drawn as a one-line text bar on stderr.

    On a terminal the bar is redrawn in place every call; into a file or a
    pipe (logs, CI) it is written as a new line at every tenth of the work.
    """

    def __init__(self, label: str, width: int = 30, stream=None):
        self.label, self.width, self.stream = label, width, stream or sys.stderr
        self.start = time.perf_counter()
        self.live = getattr(self.stream, "isatty", lambda: False)()
        self.shown = -1

    def __call__(self, done: int, total: int) -> None:
        tenth = 10 * done // max(total, 1)
        if not self.live and tenth == self.shown:
            return
        self.shown = tenth
        filled = self.width * done // max(total, 1)
        elapsed = time.perf_counter() - self.start
        bar = "#" * filled + "-" * (self.width - filled)
        line = f"{self.label} [{bar}] {done}/{total} frames {elapsed:.1f} s"
        if self.live:
            end = "\n" if done >= total else ""
            print(f"\r{line}", end=end, file=self.stream, flush=True)
        else:
            print(line, file=self.stream, flush=True)


def _fail(command: str, err: Exception, status: int) -> int:
    print(f"aquagait {command}: error: {err}", file=sys.stderr)
    return status


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``aquagait`` command."""
    parser = argparse.ArgumentParser(
        prog="aquagait",
        description="Discover and simulate swimming gaits for articulated creatures "
        "in an incompressible fluid (Tan et al. 2011).",
    )
    parser.add_argument("--version", action="version", version=f"aquagait {aquagait.__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")

    bench = commands.add_parser("bench", help="measure speed against in-run baselines")
    bench.add_argument("what", choices=BENCHMARKS, help="which benchmark to run")
    bench.add_argument("--repeats", type=int, default=10, help="timed repetitions per case")
    bench.set_defaults(run=_cmd_bench)

    creatures = commands.add_parser("creatures", help="list the creature library")
    creatures.set_defaults(run=_cmd_creatures)

    swim = commands.add_parser(
        "swim", help="swim a creature with a gait; write trajectory, metrics and video"
    )
    swim.add_argument("name", metavar="NAME", help="library creature (see: aquagait creatures)")
    swim.add_argument("--gait", metavar="FILE", help="gait.json (default: the shipped gait)")
    swim.add_argument("--seconds", type=float, default=2.0, help="simulated time [s]")
    swim.add_argument("--fluid", choices=FLUIDS_NOW, default="euler")
    swim.add_argument(
        "--resolution",
        type=int,
        nargs="+",
        metavar="N",
        help="cells per axis: NX NY (2D) or NX NY NZ (3D)",
    )
    swim.add_argument("--cell-size", type=float, metavar="H", help="cell size [m]")
    swim.add_argument("--out", metavar="DIR", help="run directory (default: runs/NAME)")
    swim.add_argument("--no-video", action="store_true", help="skip swim.mp4")
    swim.set_defaults(run=_cmd_swim)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``aquagait`` console script; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 0
    return args.run(args)
