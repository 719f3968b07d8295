"""Files in and out: run directories and gait files (docs/run-directory.md). Files only.

    from aquagait.io import read_run, read_gait, write_gait

See ``aquagait.io.run`` (the run directory's files) and ``aquagait.io.gait``
(``gait.json``). The jobs that write them (swim, optimize, compare, demo)
are ``aquagait.app``'s.
"""

from aquagait.io.gait import GaitFile, GaitFileError, read_gait, write_gait
from aquagait.io.run import (
    Run,
    library_versions,
    load_trajectory,
    prepare_directory,
    read_run,
    save_trajectory,
    write_run,
)

__all__ = [
    "GaitFile",
    "GaitFileError",
    "Run",
    "library_versions",
    "load_trajectory",
    "prepare_directory",
    "read_gait",
    "read_run",
    "save_trajectory",
    "write_gait",
    "write_run",
]
