"""Where a search's samples are swum: the --workers and --scheduler flags and their executor."""

from __future__ import annotations

import contextlib


def add_evaluator_flags(parser) -> None:
    parser.add_argument("--workers", type=int, help="worker processes (default: all cores)")
    parser.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                        help="evaluate on a Dask cluster instead (extra: dist)")  # fmt: skip


def executor_for(args):
    """The evaluator the flags ask for: a Dask cluster, local processes, or this process."""
    from aquagait.optimize import dask_executor, local_executor

    if args.scheduler:
        return dask_executor(args.scheduler)
    if args.workers == 1:
        return contextlib.nullcontext(None)
    return local_executor(args.workers)
