"""Pictures of a path following (paper §5, Figure 10).

    render_follow(trajectory, model, path_points, "runs/eel/swim.mp4")   # the path in red
    draw_follow(trajectory, model, path_points, "runs/eel/follow.png", every=30)

``render_follow`` is the swim's video (``aquagait.viz.swim``) with the path
drawn in red; ``draw_follow`` is one still picture of the whole run: the
path in red and the creature drawn every ``every`` frames along its way,
fainter the earlier it is (2D: matplotlib outlines in metres; 3D: the
shaded creature from one fixed camera over a faint ground grid, from the side
and above when the path climbs more than it turns, else from above).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from aquagait.body.dynamics import Dynamics
from aquagait.body.geometry import body_boxes
from aquagait.body.model import Model
from aquagait.sim import Trajectory
from aquagait.viz.style import ROUTE
from aquagait.viz.swim import render_swim
from aquagait.viz.volume import GROUND_SPAN, floor_height, ground_grid

SIZE = (800, 600)  # the 2D still's width and height [pixels]
SIZE_3D = (1280, 720)


def render_follow(trajectory: Trajectory, model: Model, route, path, progress=None, **look) -> Path:
    """The swim's video (or GIF, PNG) into ``path`` with ``route`` (n, dim) [m] drawn in red."""
    route = np.asarray(route, dtype=float)
    return render_swim(trajectory, model, path, progress=progress, route=route, **look)


def draw_follow(trajectory: Trajectory, model: Model, route, path, every: int = 30) -> Path:
    """A PNG of the path (red) and the creature every ``every`` frames along it.

    Args:
        trajectory: the swim.
        model: the creature.
        route: (n, dim) the path's points [m].
        path: the PNG to write (written whole or not at all).
        every: frames between snapshots (the last frame is always drawn).
    """
    if every < 1:
        raise ValueError(f"every must be a whole number of frames >= 1, got {every!r}")
    route = np.asarray(route, dtype=float)
    frames = np.unique(np.r_[np.arange(0, len(trajectory.time), every), len(trajectory.time) - 1])
    picture = (_still_2d if model.dim == 2 else _still_3d)(trajectory, model, route, frames)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = path.with_name(f".{path.stem}.partial.png")
    try:
        import imageio.v2 as imageio

        imageio.imwrite(partial, picture)
        partial.replace(path)
    finally:
        partial.unlink(missing_ok=True)
    return path


def _still_2d(trajectory, model, route, frames) -> np.ndarray:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.collections import PolyCollection
    from matplotlib.figure import Figure

    from aquagait.viz.plane import BODY, _Outlines

    outlines = _Outlines(model, trajectory)
    figure = Figure(figsize=(SIZE[0] / 100, SIZE[1] / 100), dpi=100)
    canvas = FigureCanvasAgg(figure)
    ax = figure.add_axes((0.1, 0.1, 0.85, 0.85))
    ax.plot(route[:, 0], route[:, 1], color=ROUTE, linewidth=1.5, label="path")
    for k, f in enumerate(frames):
        shade = 0.25 + 0.75 * (k + 1) / len(frames)
        ax.add_collection(PolyCollection(outlines.at(f), facecolors=BODY, alpha=shade,
                                         edgecolors="black", linewidths=0.5))  # fmt: skip
    low, high = outlines.bounds()
    low, high = np.minimum(low, route.min(0)), np.maximum(high, route.max(0))
    margin = 0.05 * (high - low).max()
    ax.set_xlim(low[0] - margin, high[0] + margin)
    ax.set_ylim(low[1] - margin, high[1] + margin)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"{len(frames)} snapshots, {trajectory.time[frames[1]] - trajectory.time[0]:.2g}"
                 " s apart" if len(frames) > 1 else "")  # fmt: skip
    canvas.draw()
    return np.asarray(canvas.buffer_rgba())[:, :, :3].copy()


def still_view(route) -> str:
    """The 3D still's view of a path (points, 3): from the side and above when it climbs more
    than it turns, else from above. The path's own extent decides, not the bodies': a
    manta's span is wider than the vertical S it keeps to is high."""
    climb = np.ptp(np.asarray(route, dtype=float), axis=0)
    return "side-above" if climb[2] >= climb[1] else "top"


def _still_3d(trajectory, model, route, frames) -> np.ndarray:
    from aquagait.body.meshes import link_meshes
    from aquagait.viz.camera import view_camera
    from aquagait.viz.gl import Renderer

    dynamics = Dynamics(model.mj)
    poses = [dynamics.link_poses(trajectory.qpos[f]) for f in frames]
    boxes = body_boxes(model, trajectory.qpos[frames])
    low = np.minimum(boxes[:, 0].min(0), route.min(0))
    high = np.maximum(boxes[:, 1].max(0), route.max(0))
    spread = high - low
    view = still_view(route)
    width, height = SIZE_3D
    centre = (low + high) / 2
    camera = view_camera(view, centre, spread, width / height, fill=0.9)
    floor = floor_height(model, trajectory.qpos[frames])
    reach = max(GROUND_SPAN, spread.max() / model.body_length)  # the grid reaches the path's ends
    with Renderer(link_meshes(model), width, height, line_width=1.5) as renderer:
        return renderer.draw(
            np.stack([p for p, _ in poses]), np.stack([r for _, r in poses]), camera,
            lines=((route, ROUTE), *ground_grid(centre, floor, model.body_length, reach)),
        )  # fmt: skip
