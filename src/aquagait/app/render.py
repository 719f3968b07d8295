"""Draw a run directory's swim again, without simulating it (DESIGN.md §1 step 5, §5).

    setup = prepare_render("runs/fish", format="gif", view="top", frames="0:90")
    path = run_render(setup)                # runs/fish/swim-top.gif

The trajectory keeps what the pictures need (the body's pose per frame and
the fluid near it, ``aquagait.sim.FluidFrames``), so the pictures are the
ones ``aquagait swim`` drew: the same frames, drawn by the same code from
the same arrays. ``aquagait swim`` writes ``swim.mp4`` through ``draw_swim``
too; where OpenGL is missing a 3D swim's video is skipped with one message
that says what to install, and the run directory is kept.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from aquagait.app.errors import SetupError, output_directory
from aquagait.app.resolve import run_creature
from aquagait.body.model import Model
from aquagait.io.run import Run
from aquagait.viz.gl import RenderUnavailable

FORMATS = ("mp4", "gif", "png")
VIEWS = ("side", "top", "follow")
DEFAULT_VIEW = "follow"


__all__ = ["RenderSetup", "RenderSetupError", "RenderUnavailable", "draw_swim", "prepare_render",
           "run_render"]  # fmt: skip


class RenderSetupError(SetupError):
    """A render cannot start: no run directory, a bad frame range, view or format."""


@dataclass(frozen=True, eq=False)
class RenderSetup:
    """A checked render: the run, its creature's model, the frames and the file to write.

    Attributes:
        run: the run directory read back.
        model: the creature (from the run's ``config.json``).
        frames: the frame indices to draw, increasing.
        view: 'side', 'top' or 'follow' (3D; 2D has one view).
        path: the picture file.
    """

    run: Run
    model: Model
    frames: list[int]
    view: str
    path: Path


def prepare_render(
    run_dir, format: str = "mp4", view: str | None = None, frames=None, out=None
) -> RenderSetup:
    """Check a render's settings before drawing anything.

    Args:
        run_dir: a run directory written by ``aquagait swim`` (or optimize, compare).
        format: 'mp4', 'gif' or 'png' (``aquagait.viz.render_swim``).
        view: 3D: 'side', 'top' or 'follow' (default); 2D: None.
        frames: 'A:B' (Python slice, either end optional), a ``range``, or None for all.
        out: the file to write; default ``RUN_DIR/swim[-VIEW].FORMAT``.

    Raises:
        RenderSetupError: the message says what is wrong and what would be right.
    """
    if format not in FORMATS:
        raise RenderSetupError(f"unknown format {format!r}; formats: {', '.join(FORMATS)}")
    if view is not None and view not in VIEWS:
        raise RenderSetupError(f"unknown view {view!r}; views: {', '.join(VIEWS)}")
    try:
        run, creature = run_creature(run_dir)
    except SetupError as err:
        raise RenderSetupError(str(err)) from None
    model = creature.model
    count = len(run.trajectory.time)
    chosen = _frames(frames, count)
    if model.dim == 2 and view not in (None, "side"):
        raise RenderSetupError(f"a 2D swim has one view; --view {view} is for 3D creatures")
    view = view or DEFAULT_VIEW
    suffix = "" if model.dim == 2 or view == DEFAULT_VIEW else f"-{view}"
    path = Path(out) if out is not None else Path(run_dir) / f"swim{suffix}.{format}"
    try:
        output_directory(path.parent)
    except SetupError as err:
        raise RenderSetupError(str(err)) from None
    return RenderSetup(run, model, chosen, view, path)


def run_render(setup: RenderSetup, progress=None) -> Path:
    """Draw the pictures and write the file; returns its path (``draw_swim``)."""
    return draw_swim(setup.run.trajectory, setup.model, setup.path, setup.frames, setup.view,
                     progress)  # fmt: skip


def draw_swim(trajectory, model: Model, path, frames=None, view=DEFAULT_VIEW, progress=None):
    """``aquagait.viz.render_swim`` for the jobs: 3D picks the ``view``; returns the path.

    Raises:
        aquagait.viz.gl.RenderUnavailable: a 3D swim and no OpenGL (what to install).
    """
    from aquagait.viz import render_swim

    look = {"view": view} if model.dim == 3 else {}
    return render_swim(trajectory, model, path, frames, progress=progress, **look)


def _frames(frames, count: int) -> list[int]:
    """Frame indices from 'A:B', a range or None; checked against the ``count`` frames."""
    if frames is None:
        return list(range(count))
    asked = frames
    if isinstance(frames, str):
        try:
            parts = [int(p) if p.strip() else None for p in frames.split(":")]
        except ValueError:
            parts = []
        if len(parts) != 2:
            raise RenderSetupError(f"frames {frames!r}: give A:B, e.g. 0:90 (either end optional)")
        frames = range(count)[slice(*parts)]
    chosen = list(frames)
    if not chosen or min(chosen) < 0 or max(chosen) >= count:
        raise RenderSetupError(
            f"frames {asked!r} select nothing of this run's {count} frames (0 to {count - 1})"
        )
    return sorted(set(chosen))
