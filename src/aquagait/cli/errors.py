"""How a command reports a mistake or a failure: one line on stderr and an exit status."""

from __future__ import annotations

import sys


def fail(command: str, err: Exception | str, status: int) -> int:
    print(f"aquagait {command}: error: {err}", file=sys.stderr)
    return status
