"""Draw a run directory's swim again, without simulating it (docs/pictures.md).

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
from aquagait.viz.camera import VIEWS as CAMERA_VIEWS
from aquagait.viz.gl import RenderUnavailable
from aquagait.viz.volume import WAKES

FORMATS = ("mp4", "gif", "png")
VIEWS = tuple(CAMERA_VIEWS)


__all__ = ["RenderSetup", "RenderSetupError", "RenderUnavailable", "draw_swim", "picture_look",
           "prepare_render", "run_render"]  # fmt: skip


class RenderSetupError(SetupError):
    """A render cannot start: no run directory, a bad frame range, view or format."""


@dataclass(frozen=True, eq=False)
class RenderSetup:
    """A checked render: the run, its creature's model, the frames and the file to write.

    Attributes:
        run: the run directory read back.
        model: the creature's model (from the run's ``config.json``).
        frames: the frame indices to draw, increasing.
        look: how to draw it (``picture_look``; empty for a 2D swim, which has one look).
        path: the picture file.
    """

    run: Run
    model: Model
    frames: list[int]
    look: dict
    path: Path


def prepare_render(
    run_dir, format: str = "mp4", view: str | None = None, frames=None, out=None,
    wake: str | None = None, size=None,
) -> RenderSetup:  # fmt: skip
    """Check a render's settings before drawing anything.

    Args:
        run_dir: a run directory written by ``aquagait swim`` (or optimize, compare).
        format: 'mp4', 'gif' or 'png' (``aquagait.viz.render_swim``).
        view: 3D only (``picture_look``): the camera; default the creature's view.
        wake: 3D only: the wake drawn, 'both' (default), 'q' (vortex surfaces) or
            'traces'.
        size: 3D only: the picture's width and height; default 1280x720.
        frames: 'A:B' (Python slice, either end optional), a ``range``, or None for all.
        out: the file to write; default ``RUN_DIR/swim[-VIEW].FORMAT`` (the view's
            name when it is not the creature's own).

    Raises:
        RenderSetupError: the message says what is wrong and what would be right.
    """
    if format not in FORMATS:
        raise RenderSetupError(f"unknown format {format!r}; formats: {', '.join(FORMATS)}")
    try:
        run, creature = run_creature(run_dir)
    except SetupError as err:
        raise RenderSetupError(str(err)) from None
    model = creature.model
    chosen = _frames(frames, len(run.trajectory.time))
    look = picture_look(model, view, wake, size, creature.view)
    own = model.dim == 2 or look["view"] == creature.view
    path = (
        Path(out)
        if out is not None
        else Path(run_dir) / (f"swim{'' if own else '-' + look['view']}.{format}")
    )
    try:
        output_directory(path.parent)
    except SetupError as err:
        raise RenderSetupError(str(err)) from None
    return RenderSetup(run, model, chosen, look if model.dim == 3 else {}, path)


def picture_look(model: Model, view=None, wake=None, size=None, default_view="follow") -> dict:
    """How the jobs draw a swim: for a 3D creature the ``view`` (default ``default_view``,
    the creature's own), the ``wake`` ('both', 'q' vortex surfaces, 'traces') and the
    picture's ``size`` (width, height) in pixels (default the renderer's, 1280x720); a 2D
    swim has one look, ``{"view": "side"}`` in name only.

    Raises:
        RenderSetupError: an unknown view or wake, a bad size, or 3D options for a 2D swim.
    """
    if model.dim == 2:
        if view not in (None, "side") or wake is not None or size is not None:
            raise RenderSetupError(
                "a 2D swim has one picture: --view, --wake and --size are for 3D creatures"
            )
        return {"view": "side"}
    view = view or default_view
    if view not in VIEWS:
        raise RenderSetupError(f"unknown view {view!r}; views: {', '.join(VIEWS)}")
    if wake is not None and wake not in WAKES:
        raise RenderSetupError(f"unknown wake {wake!r}; wakes: {', '.join(WAKES)}")
    look = {"view": view} | ({"wake": wake} if wake is not None else {})
    if size is not None:
        width, height = (int(v) for v in size)
        if width % 2 or height % 2 or min(width, height) < 16 or tuple(size) != (width, height):
            raise RenderSetupError(
                f"size {list(size)}: give an even width and height of 16 pixels or more"
            )
        look |= {"width": width, "height": height}
    return look


def run_render(setup: RenderSetup, progress=None) -> Path:
    """Draw the pictures and write the file; returns its path (``draw_swim``)."""
    return draw_swim(setup.run.trajectory, setup.model, setup.path, setup.frames, progress,
                     **setup.look)  # fmt: skip


def draw_swim(trajectory, model: Model, path, frames=None, progress=None, **look):
    """``aquagait.viz.render_swim`` for the jobs, with a look from ``picture_look``; returns
    the path.

    Raises:
        aquagait.viz.gl.RenderUnavailable: a 3D swim and no OpenGL (what to install).
    """
    from aquagait.viz import render_swim

    look = look if model.dim == 3 else {}
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
