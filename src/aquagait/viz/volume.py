"""3D swim pictures: the creature shaded, its wake as particle traces in 3D (DESIGN.md §2.7, §7).

Each picture is drawn by ``aquagait.viz.gl`` (OpenGL through EGL, Mesa's
software renderer, no screen):

- the creature's geoms at the frame's pose, shaded in their MJCF colours;
- particle traces of the last 15 frames (``aquagait.sim.particles.wake``),
  seeded in a box around the body and living ``lifetime`` frames; a trace
  vertex is as opaque as the vorticity magnitude where the particle was at
  that frame, fading towards the trace's old end, so still water draws
  nothing and the wake's vortices stand out;
- a camera that follows the swimmer: it aims at the body's centre averaged
  over half a second (the tail beat does not shake the picture), from the
  side (-y), the top (+z) or three-quarters behind and above (``follow``),
  framing the body with room for its wake.

The pictures depend only on the trajectory and the look, so a run directory
re-renders to the same pictures (``aquagait render``).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from aquagait.body.dynamics import Dynamics
from aquagait.body.geometry import body_boxes
from aquagait.body.meshes import link_meshes
from aquagait.body.model import Model
from aquagait.sim import Trajectory
from aquagait.sim.particles import Replay, wake
from aquagait.viz.camera import VIEWS, view_camera
from aquagait.viz.style import ROUTE

SMOOTHING = 0.5  # [s] the camera's aim is the body's centre averaged over this long
FRAMING = 1.6  # the view spans this many body lengths along the body's long side


@dataclass(frozen=True)
class Look3D:
    """How a 3D swim is drawn.

    Attributes:
        view: 'side', 'top' or 'follow' (three-quarter, behind and above).
        width, height: picture size [pixels] (even, as H.264 wants).
        trace_frames: frames per particle trace (DESIGN.md §2.7: 15).
        particles: how many particles.
        lifetime: frames a particle lives before it is seeded again near the body.
        substeps: RK2 steps per frame for the particles.
        vorticity_scale: |vorticity| [1/s] at full opacity; None: the 99th
            percentile over the fluid cells of all frames.
        seed: particle placement.
        route: (n, 3) world points [m] of a path to follow, drawn as a red
            line; None: no path.
    """

    view: str = "follow"
    width: int = 640
    height: int = 480
    trace_frames: int = 15
    particles: int = 3000
    lifetime: int = 60
    substeps: int = 3
    vorticity_scale: float | None = None
    seed: int = 0
    route: np.ndarray | None = None

    def __post_init__(self):
        if self.view not in VIEWS:
            raise ValueError(f"unknown view {self.view!r}; views: {', '.join(VIEWS)}")
        if self.width % 2 or self.height % 2 or min(self.width, self.height) < 16:
            raise ValueError(
                f"picture size {self.width}x{self.height}: give even sizes of 16 pixels or more"
            )


def volume_pictures(
    trajectory: Trajectory, model: Model, frames=None, **look
) -> Iterator[np.ndarray]:
    """The 3D swim's pictures, (height, width, 3) uint8 RGB, one per selected frame.

    Args:
        trajectory: a 3D swim, with or without fluid frames (without: the body alone).
        model: the creature.
        frames: the frame indices to draw, increasing (default all); the
            particles still travel from the first frame, so a frame looks the
            same whichever others are drawn.
        **look: fields of ``Look3D``.

    Raises:
        aquagait.viz.gl.RenderUnavailable: no OpenGL (it names what to install).
        ValueError: a bad look, or fluid frames that are not 3D.
    """
    look = Look3D(**look)
    fluid = trajectory.fluid
    if fluid is not None and fluid.dim != 3:
        raise ValueError(
            "the trajectory's fluid frames are a 2D plane, not a 3D volume: it was recorded "
            "by an older aquagait; swim it again to draw its wake in 3D"
        )
    frames = range(len(trajectory.time)) if frames is None else list(frames)
    return _pictures(trajectory, model, frames, look)


def _pictures(trajectory: Trajectory, model: Model, frames, look: Look3D):
    from aquagait.viz.gl import Renderer

    dynamics = Dynamics(model.mj)
    cameras = _cameras(model, trajectory, look)
    traces = _wake(trajectory, model, look)
    route = () if look.route is None else ((look.route, ROUTE),)
    with Renderer(link_meshes(model), look.width, look.height, line_width=1.5) as renderer:
        for f in frames:
            lines, alpha = traces.at(f) if traces is not None else (None, None)
            pos, rot = dynamics.link_poses(trajectory.qpos[f])
            yield renderer.draw(pos, rot, cameras[f], traces=lines, trace_alpha=alpha,
                                lines=route)  # fmt: skip


def _cameras(model: Model, trajectory: Trajectory, look: Look3D) -> list:
    """One camera a frame: aimed at the body's smoothed centre, framing a fixed box."""
    boxes = body_boxes(model, trajectory.qpos)
    centres = boxes.mean(axis=1)
    half = max(1, int(round(0.5 * SMOOTHING * trajectory.fps)))
    padded = np.pad(centres, ((half, half), (0, 0)), mode="edge")
    kernel = np.ones(2 * half + 1) / (2 * half + 1)
    smooth = np.stack([np.convolve(padded[:, a], kernel, mode="valid") for a in range(3)], 1)
    size = (boxes[:, 1] - boxes[:, 0]).max(axis=0)
    length = model.body_length
    extent = np.maximum(size, 0.4 * length)
    extent = extent * FRAMING * length / max(extent.max(), 1e-9)
    aspect = look.width / look.height
    return [view_camera(look.view, centre, extent, aspect) for centre in smooth]


def _wake(trajectory: Trajectory, model: Model, look: Look3D) -> Replay | None:
    if trajectory.fluid is None:
        return None
    return Replay(wake(
        trajectory, model, count=look.particles, length=look.trace_frames,
        lifetime=look.lifetime, substeps=look.substeps, seed=look.seed,
        vorticity_scale=look.vorticity_scale,
    ))  # fmt: skip
