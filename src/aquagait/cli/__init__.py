"""The ``aquagait`` command line: thin, each flag maps to a library argument.

One module per command (``swim``, ``optimize``, ...), each with its ``add_parser(commands)``
and ``run(args) -> int``; the flags, progress lines and signal handling they share sit
beside them.
"""

from __future__ import annotations

import argparse

import aquagait
from aquagait.cli import (
    bench,
    check,
    compare,
    creatures,
    demo,
    export,
    follow,
    optimize,
    render,
    swim,
)
from aquagait.cli.compare import CONVERGED
from aquagait.cli.optimize import optimization_setup
from aquagait.cli.progress import GenerationLine, ProgressBar
from aquagait.cli.signals import Terminated, sigterm_unwinds, stopped

__all__ = [
    "CONVERGED",
    "GenerationLine",
    "ProgressBar",
    "Terminated",
    "build_parser",
    "main",
    "optimization_setup",
]

COMMANDS = (bench, creatures, check, swim, optimize, follow, compare, render, export, demo)
"""The command modules, in the order ``aquagait --help`` lists them."""


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``aquagait`` command."""
    parser = argparse.ArgumentParser(
        prog="aquagait",
        description="Discover and simulate swimming gaits for articulated creatures "
        "in an incompressible fluid (Tan et al. 2011).",
    )
    parser.add_argument("--version", action="version", version=f"aquagait {aquagait.__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    for command in COMMANDS:
        command.add_parser(commands)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``aquagait`` console script; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 0
    if getattr(args, "no_thicken", False):
        from aquagait.creatures import as_written

        args.name = as_written(args.name)
    with sigterm_unwinds():
        try:
            return args.run(args)
        except KeyboardInterrupt as stop:
            return stopped(args, stop)
