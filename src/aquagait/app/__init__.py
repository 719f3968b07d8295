"""The jobs users run, each prepare -> run -> write (docs/development.md).

    setup = prepare_swim("eel2d", seconds=4.0)     # resolve and check everything; SetupError
    out = output_directory("runs/eel2d")           # created and writable, or SetupError
    run = run_swim(setup, progress=...)            # simulate and measure
    write_swim(run, out, video=True)               # the run directory and its video

``swim``, ``optimize`` (CMA-ES and the best gait's swim), ``compare`` (the
Euler and the simple fluid), ``check`` (a creature's table and its voxels on
the default grid), ``render`` (a run directory's pictures again) and
``demo``. This is the one layer that joins simulation, optimizer, files and
pictures; the command line only maps flags
to its arguments. A mistake in a setting raises a ``SetupError`` whose
message says what was wrong and what would be right, before anything runs.
"""

from aquagait.app.check import (
    CheckReport,
    CheckSetup,
    CheckSetupError,
    format_check,
    prepare_check,
    run_check,
    write_check,
)
from aquagait.app.errors import SetupError, output_directory
from aquagait.app.optimize import (
    OptimizationSetup,
    OptimizationSetupError,
    SwimObjective,
    prepare_optimization,
    run_optimization,
    write_optimization,
)
from aquagait.app.render import (
    RenderSetup,
    RenderSetupError,
    RenderUnavailable,
    draw_swim,
    picture_look,
    prepare_render,
    run_render,
)
from aquagait.app.swim import (
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
    "CheckReport",
    "CheckSetup",
    "CheckSetupError",
    "OptimizationSetup",
    "OptimizationSetupError",
    "RenderSetup",
    "RenderSetupError",
    "RenderUnavailable",
    "SetupError",
    "SwimObjective",
    "SwimRun",
    "SwimSetup",
    "SwimSetupError",
    "draw_swim",
    "format_check",
    "output_directory",
    "picture_look",
    "prepare_check",
    "prepare_optimization",
    "prepare_render",
    "prepare_swim",
    "run_check",
    "run_optimization",
    "run_render",
    "run_swim",
    "swim_config",
    "swim_summary",
    "write_check",
    "write_optimization",
    "write_swim",
]
