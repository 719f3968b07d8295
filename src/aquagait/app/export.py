"""Take a run elsewhere: ``aquagait export RUN_DIR --format usd|gltf|vtk|html`` (docs/export.md).

    setup = prepare_export("runs/fish", "gltf")      # checks the run, the format, the path
    path = run_export(setup)                          # runs/fish/swim.glb

The run directory keeps what an export needs (``aquagait.io.export``): the
poses per frame and the flow, from which the creature's meshes and the
particle traces are drawn again, the same way the video draws them.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from aquagait.app.errors import SetupError, output_directory
from aquagait.app.resolve import run_creature
from aquagait.creatures import Creature
from aquagait.io.export import (
    FORMATS,
    TRACES,
    ExportUnavailable,
    check_format,
    export_swim,
    swim_export,
)
from aquagait.io.run import Run

__all__ = ["ExportSetup", "ExportSetupError", "ExportUnavailable", "prepare_export", "run_export"]


class ExportSetupError(SetupError):
    """An export cannot start: no run directory, a damaged one, a bad format or path."""


SUFFIXES = {"usd": (".usd",), "gltf": (".glb",), "html": (".html", ".htm"), "vtk": ()}
"""The file suffixes each format's readers open it by (vtk writes a folder: none)."""


@dataclass(frozen=True, eq=False)
class ExportSetup:
    """A checked export: the run, its creature, the format, the file (or folder) to write,
    and ``notes`` on what was changed on the way (an extension added)."""

    run: Run
    creature: Creature
    format: str
    path: Path
    traces: int = TRACES
    notes: tuple[str, ...] = ()


def prepare_export(run_dir, format: str, out=None, traces: int = TRACES) -> ExportSetup:
    """Check an export's settings before gathering anything.

    Args:
        run_dir: a run directory written by ``aquagait swim`` (or optimize, compare).
        format: 'usd', 'gltf', 'vtk' or 'html'.
        out: the file (a folder for vtk) to write; default ``RUN_DIR/`` and
            the format's name (``aquagait.io.export.FORMATS``). Without the
            format's extension (``SUFFIXES``), it is added (and said in ``notes``):
            USD tools and Blender open a file by its extension.
        traces: particle traces exported (0: none).

    Raises:
        ExportSetupError: the message says what is wrong and what would be right
            (a missing library: what to install).
    """
    if format not in FORMATS:
        raise ExportSetupError(f"unknown format {format!r}; formats: {', '.join(FORMATS)}")
    if not (isinstance(traces, int) and traces >= 0):
        raise ExportSetupError(f"traces must be a whole number >= 0, got {traces!r}")
    notes = ()
    path = Path(out) if out is not None else Path(run_dir) / FORMATS[format]
    suffixes = SUFFIXES[format]
    if suffixes and path.suffix.lower() not in suffixes:
        if path.suffix.lower() in {s for known in SUFFIXES.values() for s in known}:
            raise ExportSetupError(
                f"{path}: a {format} export is a {suffixes[0]} file, not {path.suffix}; "
                f"give --out {path.with_suffix(suffixes[0])}"
            )
        path = path.with_name(path.name + suffixes[0])
        notes = (f"added the {suffixes[0]} extension, by which {format} readers open it",)
    try:
        run, creature = run_creature(run_dir)
        output_directory(path.parent)
    except SetupError as err:
        raise ExportSetupError(str(err)) from None
    try:
        check_format(format)
    except ExportUnavailable as err:
        raise ExportSetupError(str(err)) from None
    if path.is_dir() != (format == "vtk") and path.exists():
        kind = "a folder" if format == "vtk" else "a file"
        raise ExportSetupError(f"{path} exists and is not {kind}: {format} writes {kind}")
    return ExportSetup(run, creature, format, path, traces, notes)


def run_export(setup: ExportSetup) -> Path:
    """Gather the swim and write it; returns the path written."""
    run = setup.run
    data = swim_export(run.trajectory, setup.creature.model, setup.creature.name, setup.traces)
    return export_swim(data, setup.format, setup.path)
