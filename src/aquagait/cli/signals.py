"""Ctrl-C and SIGTERM: a command stops by unwinding, and says so in one line."""

from __future__ import annotations

import contextlib
import signal
import sys
import threading


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread: a command stops as on Ctrl-C, unwinding, so a
    search's worker processes are killed (``ProcessExecutor.__exit__``) and not left
    behind, and its checkpoint keeps the last whole generation."""


def _terminate(signum, frame):
    raise Terminated


@contextlib.contextmanager
def sigterm_unwinds():
    """Within the block, SIGTERM raises ``Terminated`` (in the main thread only: a signal
    handler cannot be set elsewhere), and the handler before is restored after it."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    before = signal.signal(signal.SIGTERM, _terminate)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, before)


def stopped(args, stop: KeyboardInterrupt) -> int:
    """A command stopped by Ctrl-C (exit status 130) or SIGTERM (143), in one line."""
    status, how = (
        (143, "terminated (SIGTERM)") if isinstance(stop, Terminated) else (130, "interrupted")
    )
    resume = ""
    if args.command == "optimize" or getattr(args, "optimize", None) is not None:  # compare's
        resume = ("; a search's checkpoint keeps its last whole generation: the same command "
                  "with --resume goes on from it")  # fmt: skip
    print(f"aquagait {args.command}: {how}{resume}", file=sys.stderr)
    return status
