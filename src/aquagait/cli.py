"""The ``aquagait`` command line: thin, each flag maps to a library argument."""

from __future__ import annotations

import argparse
import sys

import aquagait


def _cmd_bench(args) -> int:
    from aquagait.bench import run_benchmark

    run_benchmark(args.what, repeats=args.repeats, out=sys.stdout)
    return 0


def _cmd_creatures(args) -> int:
    from aquagait import creatures

    print(creatures.format_table())
    return 0


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
    bench.add_argument("what", choices=["fluid"], help="which benchmark to run")
    bench.add_argument("--repeats", type=int, default=10, help="timed repetitions per case")
    bench.set_defaults(run=_cmd_bench)

    creatures = commands.add_parser("creatures", help="list the creature library")
    creatures.set_defaults(run=_cmd_creatures)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``aquagait`` console script; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 0
    return args.run(args)
