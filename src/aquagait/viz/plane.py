"""2D swim pictures: vorticity, the body and particle traces, frame by frame (docs/pictures.md).

Each picture shows the recorded fluid (``Trajectory.fluid``, the whole grid)
as the camera sees it, following the grid as it moves with the creature:

- background: the vorticity dv/dx - du/dy, a pale diverging colour map (red
  counter-clockwise, blue clockwise), the same scale in every frame,
  interpolated bilinearly between the cell centres (smooth, not blocky);
  zero inside the body's cells, so the body's own spin does not bleed out;
- the body: every geom at the frame's pose from the model, filled (without
  a model: the cells inside the body, in grey);
- particle traces of the last 15 frames (``aquagait.sim.particles``), dark red
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

import numpy as np

from aquagait.body.dynamics import Dynamics
from aquagait.body.geometry import geom_point_sets
from aquagait.body.model import Model
from aquagait.sim import Trajectory
from aquagait.sim.particles import (
    Replay,
    particle_traces,
    sample,
    vorticity,
    vorticity_percentile,
)
from aquagait.viz.style import ROUTE

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
        trace_frames: frames per particle trace (docs/pictures.md: 15).
        particles_per_cell: particle density.
        substeps: RK2 steps per frame for the particles.
        vorticity_scale: |vorticity| [1/s] at full colour; None: the 99.5th
            percentile over the fluid cells of all frames.
        seed: particle placement.
        route: (n, 2) world points [m] of a path to follow, drawn as a red
            line; None: no path.
    """

    pixels_per_cell: int | None = None
    trace_frames: int = 15
    particles_per_cell: float = 0.25
    substeps: int = 3
    vorticity_scale: float | None = None
    seed: int = 0
    route: np.ndarray | None = None


def plane_pictures(
    trajectory: Trajectory, model: Model | None, frames=None, **look
) -> Iterator[np.ndarray]:
    """The 2D swim's pictures, (height, width, 3) uint8 RGB, one per selected frame.

    Args:
        trajectory: with ``fluid`` frames, or without (body only).
        model: the creature, for its outline; None draws the solid cells only.
        frames: the frame indices to draw, increasing (default all); the
            particles still travel from the first frame.
        **look: fields of ``Look``.

    The arguments are checked at the call, the pictures drawn as they are asked for.

    Raises:
        ValueError: a trajectory with neither fluid frames nor a model.
    """
    if trajectory.fluid is None and model is None:
        raise ValueError("a trajectory without fluid frames needs the model to draw the body")
    picture = _Picture(trajectory, model, Look(**look))
    frames = range(len(trajectory.time)) if frames is None else list(frames)
    return (picture.draw(f) for f in frames)


class _Picture:
    """One matplotlib figure redrawn per frame: vorticity, traces, body.

    ``draw`` must see the frames in increasing order: the particle traces advance with it.
    """

    def __init__(self, trajectory: Trajectory, model: Model | None, look: Look):
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
        if self.fluid is not None:
            self.scale = look.vorticity_scale or vorticity_percentile(self.fluid, 99.5)
            self.image = ax.imshow(
                np.zeros((2, 2)), origin="lower", cmap=_pale_colormap(), vmin=-self.scale,
                vmax=self.scale, interpolation="bilinear", interpolation_stage="data",
            )  # fmt: skip
            self.solid = None
            if model is None:
                self.solid = ax.imshow(np.zeros((2, 2, 4)), origin="lower", interpolation="nearest")
            self.traces = Replay(particle_traces(
                self.fluid,
                trajectory.time,
                look.particles_per_cell,
                look.trace_frames,
                look.substeps,
                look.seed,
            ))  # fmt: skip
            self.lines = ax.add_collection(LineCollection([], linewidths=0.8))
        if look.route is not None:
            route = np.asarray(look.route, dtype=float)
            ax.plot(route[:, 0], route[:, 1], color=ROUTE, linewidth=2.0, linestyle=(0, (6, 3)),
                    zorder=1.5)  # fmt: skip
        filled = model is not None and model.dim == 2
        self.body = ax.add_collection(
            PolyCollection(
                [],
                facecolors=BODY if filled else "none",
                edgecolors="black",
                linewidths=0.8,
                zorder=2,
            )
        )
        self.clock = ax.text(0.01, 0.98, "", transform=ax.transAxes, va="top", fontsize=9)

    def draw(self, f: int) -> np.ndarray:
        ax = self.ax
        if self.fluid is not None:
            low = self.fluid.origin[f]
            high = low + np.array(self.fluid.shape) * self.fluid.cell_size
            extent = (low[0], high[0], low[1], high[1])
            omega = vorticity(self.fluid, f)
            solid = self.fluid.solid[f]
            self.image.set_data(np.where(solid, 0.0, omega).T)  # imshow wants rows of y
            self.image.set_extent(extent)
            if self.solid is not None:
                self.solid.set_data((solid[..., None] * SOLID).transpose(1, 0, 2))
                self.solid.set_extent(extent)
            traces = self.traces.at(f)
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

    def _trace_colours(self, omega, origin, points):
        value = sample(omega, origin, self.fluid.cell_size, np.nan_to_num(points))
        colours = np.tile(np.array(CALM), (len(points), 1))
        colours[value > CALM_FRACTION * self.scale] = CCW
        colours[value < -CALM_FRACTION * self.scale] = CW
        return colours


def _pale_colormap():
    """RdBu_r blended towards white by ``BACKGROUND_STRENGTH``: the wake, not a poster."""
    from matplotlib import colormaps
    from matplotlib.colors import ListedColormap

    rgba = colormaps["RdBu_r"](np.linspace(0, 1, 256))
    rgba[:, :3] = 1 - BACKGROUND_STRENGTH * (1 - rgba[:, :3])
    return ListedColormap(rgba)


def _window(fluid, outlines, pixels_per_cell):
    """The picture's (low, high) corners [m] (None: follow the fluid plane) and (width, height).

    Sizes are even, as H.264 wants. Without fluid: a fixed box around everything the body swept.
    """
    if fluid is not None:
        n = np.array(fluid.shape)
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
