"""The swim's pictures and the files they go to (docs/pictures.md).

    from aquagait.viz import render_swim
    render_swim(trajectory, creature.model, "runs/fish/swim.mp4", view="side")

A 2D creature is drawn by ``aquagait.viz.plane`` (matplotlib: vorticity,
body, traces coloured by the sign of vorticity), a 3D one by
``aquagait.viz.volume`` (OpenGL: the shaded creature, traces in 3D whose
opacity follows the vorticity). The file's suffix says what is written:

- ``.mp4``: H.264 at the trajectory's frame rate (imageio-ffmpeg);
- ``.gif``: an animated GIF at the same rate (every other frame over 15 fps:
  GIF delays are whole hundredths of a second and big GIFs are slow);
- ``.png``: one picture: the frame itself if one frame is selected, else a
  contact sheet of six frames spread over the selection (``contact_sheet``).
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np

from aquagait.body.model import Model
from aquagait.sim import Trajectory

FORMATS = ("mp4", "gif", "png")
SHEET = (3, 2)  # a contact sheet's columns and rows
GIF_MAX_FPS = 15


def swim_frames(
    trajectory: Trajectory, model: Model | None, frames=None, view: str = "follow", **look
) -> Iterator[np.ndarray]:
    """The swim's pictures, (height, width, 3) uint8 RGB, one per selected frame.

    Args:
        trajectory: the swim.
        model: the creature (None in 2D draws the solid cells only).
        frames: increasing frame indices to draw (default all).
        view: 3D only: 'side', 'top' or 'follow' (``aquagait.viz.volume``).
        **look: fields of ``aquagait.viz.plane.Look`` (2D) or
            ``aquagait.viz.volume.Look3D`` (3D).

    Raises:
        aquagait.viz.gl.RenderUnavailable: a 3D swim and no OpenGL.
    """
    if _dim(trajectory, model) == 3:
        from aquagait.viz.volume import volume_pictures

        return volume_pictures(trajectory, model, frames, view=view, **look)
    from aquagait.viz.plane import plane_pictures

    return plane_pictures(trajectory, model, frames, **look)


def render_swim(
    trajectory: Trajectory, model: Model | None, path, frames=None, progress=None, **look
) -> Path:
    """Draw the swim into ``path`` (.mp4, .gif or .png: module docstring).

    Args:
        trajectory, model, frames: as for ``swim_frames``.
        path: the file; its parent is created. Written whole or not at all.
        progress: optional ``progress(pictures_done, pictures_total)``.
        **look: ``view`` and the fields of the look (``swim_frames``).

    Returns:
        The file's path.
    """
    path = Path(path)
    kind = path.suffix.lstrip(".").lower()
    if kind not in FORMATS:
        raise ValueError(f"cannot write pictures to {path}: give a .mp4, .gif or .png file")
    frames = list(range(len(trajectory.time)) if frames is None else frames)
    if kind == "gif":
        frames = frames[:: int(np.ceil(trajectory.fps / GIF_MAX_FPS))]
    if kind == "png" and len(frames) > 1:
        picks = np.linspace(0, len(frames) - 1, SHEET[0] * SHEET[1]).round().astype(int)
        frames = sorted({frames[i] for i in picks})
    pictures = swim_frames(trajectory, model, frames, **look)  # checks its arguments first
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = path.with_name(f".{path.stem}.partial{path.suffix}")
    try:
        _write(kind, partial, _counted(pictures, len(frames), progress), trajectory.fps, frames)
        partial.replace(path)
    finally:
        partial.unlink(missing_ok=True)
    return path


def contact_sheet(pictures: list[np.ndarray], columns: int = SHEET[0]) -> np.ndarray:
    """Pictures of one size tiled in rows of ``columns``, white where a row is short."""
    height, width, _ = pictures[0].shape
    rows = -(-len(pictures) // columns)
    sheet = np.full((rows * height, columns * width, 3), 255, np.uint8)
    for k, picture in enumerate(pictures):
        r, c = divmod(k, columns)
        sheet[r * height : (r + 1) * height, c * width : (c + 1) * width] = picture
    return sheet


def _write(kind: str, path: Path, pictures, fps: float, frames: list[int]) -> None:
    import imageio.v2 as imageio

    if kind == "png":
        pictures = list(pictures)
        imageio.imwrite(path, pictures[0] if len(pictures) == 1 else contact_sheet(pictures))
        return
    if kind == "gif":
        step = frames[1] - frames[0] if len(frames) > 1 else 1
        writer = imageio.get_writer(path, format="GIF", duration=1000 * step / fps, loop=0)
    else:
        writer = imageio.get_writer(
            path, fps=fps, codec="libx264", macro_block_size=2, ffmpeg_log_level="error"
        )
    with writer:
        for picture in pictures:
            writer.append_data(picture)


def _counted(pictures, total: int, progress):
    for k, picture in enumerate(pictures):
        yield picture
        if progress is not None:
            progress(k + 1, total)


def _dim(trajectory: Trajectory, model: Model | None) -> int:
    if model is not None:
        return model.dim
    return trajectory.fluid.dim if trajectory.fluid is not None else 2
