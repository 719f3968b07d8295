"""Files in and out: run directories, gait files, and swims kept on disk (DESIGN.md §3, §5).

    from aquagait.io import prepare_swim, run_swim, write_swim, read_run, read_gait

See ``aquagait.io.run`` (the run directory's files), ``aquagait.io.gait``
(``gait.json``) and ``aquagait.io.swim`` (swim a creature and keep the run).
"""

from aquagait.io.gait import GaitFile, GaitFileError, read_gait, write_gait
from aquagait.io.run import (
    Run,
    library_versions,
    load_trajectory,
    read_run,
    save_trajectory,
    write_run,
)
from aquagait.io.swim import (
    SwimRun,
    SwimSetup,
    SwimSetupError,
    prepare_swim,
    run_swim,
    swim_config,
    swim_summary,
    write_swim,
)

__all__ = [
    "GaitFile",
    "GaitFileError",
    "Run",
    "SwimRun",
    "SwimSetup",
    "SwimSetupError",
    "library_versions",
    "load_trajectory",
    "prepare_swim",
    "read_gait",
    "read_run",
    "run_swim",
    "save_trajectory",
    "swim_config",
    "swim_summary",
    "write_gait",
    "write_run",
    "write_swim",
]
