"""The swim video: vorticity, the body and particle traces, frame by frame (DESIGN.md §2.7).

Each video frame shows the recorded fluid plane (``Trajectory.fluid``: the
whole grid in 2D, the mid-plane slice in 3D) as the camera sees it, following
the grid as it moves with the creature:

- background: the vorticity dv/dx - du/dy of the plane, a pale diverging
  colour map (red counter-clockwise, blue clockwise), the same scale in every
  frame; cells inside the body in grey (what the fluid sees);
- the body: the outline of every geom at the frame's pose from the model
  (filled in 2D; in 3D the silhouette seen from +z over the slice);
- particle traces of the last 15 frames (``aquagait.viz.particles``), dark red
  where the particle sits in counter-clockwise vorticity, dark blue in
  clockwise, grey where the vorticity is below 5% of the colour scale.

A trajectory without fluid frames (``fluid="none"``) shows the body alone in a
fixed window around everything it swept.

matplotlib (Agg, no screen) and imageio-ffmpeg (its own ffmpeg binary) are
the ``viz`` extra, imported inside the functions that need them.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from aquagait.body.dynamics import Dynamics
from aquagait.body.geometry import geom_point_sets
from aquagait.body.model import Model
from aquagait.sim import Trajectory
from aquagait.viz.particles import particle_traces, sample, vorticity

CCW, CW, CALM = (0.7, 0.0, 0.05, 0.9), (0.0, 0.2, 0.75, 0.9), (0.35, 0.35, 0.35, 0.6)
BODY, SOLID = (0.22, 0.2, 0.12), np.array([0.6, 0.6, 0.6, 1.0])
CALM_FRACTION = 0.05
BACKGROUND_STRENGTH = 0.55  # 1: full colour map; less: blended towards white
WIDTH = 640  # pixels along the picture's long side, by default


@dataclass(frozen=True)
class Look:
    """How a swim is drawn.

    Attributes:
        pixels_per_cell: picture pixels per fluid cell; None: the plane's long
            side gets about ``WIDTH`` pixels.
        trace_frames: frames per particle trace (DESIGN.md §2.7: 15).
        particles_per_cell: particle density.
        substeps: RK2 steps per frame for the particles.
        vorticity_scale: |vorticity| [1/s] at full colour; None: the 99.5th
            percentile over the fluid cells of all frames.
        seed: particle placement.
    """

    pixels_per_cell: int | None = None
    trace_frames: int = 15
    particles_per_cell: float = 0.25
    substeps: int = 3
    vorticity_scale: float | None = None
    seed: int = 0


def render_swim(trajectory: Trajectory, model: Model | None, path, progress=None, **look) -> Path:
    """Write the swim video (H.264 MP4 at the trajectory's fps), one picture per frame.

    Args:
        trajectory: with ``fluid`` frames, or without (body only).
        model: the creature, for its outline; None draws the solid cells only.
        path: the video file, e.g. ``runs/eel2d/swim.mp4``.
        progress: optional ``progress(frames_done, frames_total)``.
        **look: fields of ``Look``.

    Returns:
        The video's path.

    Raises:
        ValueError: a trajectory with neither fluid frames nor a model.
    """
    import imageio.v2 as imageio

    pictures = swim_frames(trajectory, model, **look)  # checks its arguments first
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    writer = imageio.get_writer(
        path, fps=trajectory.fps, codec="libx264", macro_block_size=2, ffmpeg_log_level="error"
    )
    with writer:
        for f, picture in enumerate(pictures):
            writer.append_data(picture)
            if progress is not None:
                progress(f + 1, len(trajectory.time))
    return path


def swim_frames(trajectory: Trajectory, model: Model | None, **look) -> Iterator[np.ndarray]:
    """The swim's pictures, one per frame: (height, width, 3) uint8 RGB arrays.

    Arguments as for ``render_swim``. The arguments are checked at the call,
    the pictures drawn as they are asked for.
    """
    if trajectory.fluid is None and model is None:
        raise ValueError("a trajectory without fluid frames needs the model to draw the body")
    picture = _Picture(trajectory, model, Look(**look))
    return (picture.draw(f) for f in range(len(trajectory.time)))


class _Picture:
    """One matplotlib figure redrawn per frame: background image, traces, body outlines.

    ``draw`` must see the frames in order: the particle traces advance with it.
    """

    def __init__(self, trajectory: Trajectory, model: Model | None, look: Look):
        from matplotlib import colormaps
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.collections import LineCollection, PolyCollection
        from matplotlib.figure import Figure

        self.trajectory, self.fluid = trajectory, trajectory.fluid
        self.outlines = _Outlines(model, trajectory) if model is not None else None
        self.window, (width, height) = _window(self.fluid, self.outlines, look.pixels_per_cell)
        self.figure = Figure(figsize=(width / 100, height / 100), dpi=100)
        self.canvas = FigureCanvasAgg(self.figure)  # Agg, off screen; no global backend change
        ax = self.figure.add_axes((0, 0, 1, 1))
        ax.set_axis_off()
        self.ax = ax
        self.image = None
        if self.fluid is not None:
            self.scale = look.vorticity_scale or _vorticity_scale(self.fluid)
            self.image = ax.imshow(np.zeros((2, 2, 4)), origin="lower", interpolation="nearest")
            self.traces = particle_traces(
                self.fluid,
                trajectory.time,
                look.particles_per_cell,
                look.trace_frames,
                look.substeps,
                look.seed,
            )
            self.lines = ax.add_collection(LineCollection([], linewidths=0.8))
        filled = model is not None and model.dim == 2
        self.body = ax.add_collection(
            PolyCollection(
                [], facecolors=BODY if filled else "none", edgecolors="black", linewidths=0.8
            )
        )
        self.clock = ax.text(0.01, 0.98, "", transform=ax.transAxes, va="top", fontsize=9)
        self.colormap = colormaps["RdBu_r"]

    def draw(self, f: int) -> np.ndarray:
        ax = self.ax
        if self.fluid is not None:
            low = self.fluid.origin[f]
            high = low + np.array(self.fluid.solid.shape[1:]) * self.fluid.cell_size
            omega = vorticity(self.fluid, f)
            self.image.set_data(self._background(omega, self.fluid.solid[f]))
            self.image.set_extent((low[0], high[0], low[1], high[1]))
            traces = next(self.traces)
            self.lines.set_segments(traces)
            self.lines.set_color(self._trace_colours(omega, low, traces[:, -1]))
        else:
            low, high = self.window
        ax.set_xlim(low[0], high[0])
        ax.set_ylim(low[1], high[1])
        if self.outlines is not None:
            self.body.set_verts(self.outlines.at(f))
        self.clock.set_text(f"t = {self.trajectory.time[f]:.2f} s")
        self.canvas.draw()
        return np.asarray(self.canvas.buffer_rgba())[:, :, :3].copy()

    def _background(self, omega, solid):
        rgba = self.colormap(np.clip(0.5 + 0.5 * omega / self.scale, 0, 1))
        rgba[..., :3] = 1 - BACKGROUND_STRENGTH * (1 - rgba[..., :3])
        rgba[solid] = SOLID
        return rgba.transpose(1, 0, 2)  # imshow wants rows of y

    def _trace_colours(self, omega, origin, points):
        value = sample(omega, origin, self.fluid.cell_size, np.nan_to_num(points))
        colours = np.tile(np.array(CALM), (len(points), 1))
        colours[value > CALM_FRACTION * self.scale] = CCW
        colours[value < -CALM_FRACTION * self.scale] = CW
        return colours


def _window(fluid, outlines, pixels_per_cell):
    """The picture's (low, high) corners [m] (None: follow the fluid plane) and (width, height).

    Sizes are even, as H.264 wants. Without fluid: a fixed box around everything the body swept.
    """
    if fluid is not None:
        n = np.array(fluid.solid.shape[1:])
        ppc = pixels_per_cell or int(np.ceil(WIDTH / n.max()))
        return None, tuple(int(2 * np.ceil(k * ppc / 2)) for k in n)
    low, high = outlines.bounds()
    margin = 0.1 * (high - low).max()
    low, high = low - margin, high + margin
    per_metre = WIDTH / (high - low).max()
    return (low, high), tuple(int(2 * np.ceil(s * per_metre / 2)) for s in high - low)


class _Outlines:
    """Per frame, the xy outline (convex hull) of every geom at the trajectory's pose."""

    def __init__(self, model: Model, trajectory: Trajectory):
        self.sets = geom_point_sets(model)
        self.dynamics = Dynamics(model.mj)
        self.qpos = trajectory.qpos

    def world(self, f: int) -> list[np.ndarray]:
        pos, rot = self.dynamics.link_poses(self.qpos[f])
        return [(pos[link] + points @ rot[link].T)[:, :2] for link, points in self.sets]

    def at(self, f: int) -> list[np.ndarray]:
        return [_hull(points) for points in self.world(f)]

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        every = np.concatenate([np.concatenate(self.world(f)) for f in range(len(self.qpos))])
        return every.min(axis=0), every.max(axis=0)


def _hull(points: np.ndarray) -> np.ndarray:
    """Convex hull of 2D points, counter-clockwise (Andrew's monotone chain)."""
    pts = np.unique(np.round(points, 12), axis=0)
    if len(pts) < 3:
        return pts

    def half(seq):
        chain = []
        for p in seq:
            while len(chain) >= 2 and _cross(chain[-2], chain[-1], p) <= 0:
                chain.pop()
            chain.append(p)
        return chain[:-1]

    return np.array(half(pts) + half(pts[::-1]))


def _cross(o, a, b) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _vorticity_scale(fluid) -> float:
    values = [np.abs(vorticity(fluid, f))[~fluid.solid[f]] for f in range(len(fluid.origin))]
    values = np.concatenate(values) if values else np.zeros(1)
    scale = float(np.percentile(values, 99.5)) if values.size else 0.0
    return scale if scale > 0 else 1.0
