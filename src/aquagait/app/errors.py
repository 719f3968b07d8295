"""What every job checks before it runs: its settings, and where it will write."""

from __future__ import annotations

from pathlib import Path

from aquagait.io.run import prepare_directory


class SetupError(ValueError):
    """A job cannot start: the message says which setting is wrong and what would be right."""


def output_directory(out) -> Path:
    """The run directory ``out``, created and proven writable before anything is simulated.

    Raises:
        SetupError: it cannot be created or written (names the directory and why).
    """
    try:
        return prepare_directory(out)
    except OSError as err:
        raise SetupError(f"{err}; choose another directory with --out") from None
