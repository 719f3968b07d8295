"""3D swim pictures: the creature shaded, its wake as vortex surfaces and particle traces
(docs/pictures.md).

Each picture is drawn by ``aquagait.viz.gl`` (OpenGL through EGL, Mesa's
software renderer, no screen):

- the creature's geoms at the frame's pose, shaded in their MJCF colours;
- the wake (``wake``): ``"q"`` the vortex surfaces, ``"traces"`` the particle
  traces, ``"both"`` (the default) the one over the other.
  - Vortex surfaces: the isosurface ``Q = q_fraction * peak`` of the
    Q-criterion (``aquagait.sim.vortices``: the fluid rotating more than it is
    strained; the peak, a high percentile over the whole swim, so one threshold
    holds for every frame), by marching cubes (scikit-image) on Q interpolated
    onto a lattice ``SURFACE_REFINE`` times finer (a vortex three cells across
    comes out round, not ribbed), see-through (the nearest layer), each vertex
    coloured by the direction of the vorticity there along the
    spanwise axis (``spin_axis``): red where it turns counter-clockwise seen
    from the axis' tip, blue clockwise, grey across.
  - Particle traces of the last 15 frames (``aquagait.sim.particles.wake``),
    seeded in a box around the body and living ``lifetime`` frames; a trace
    vertex is as opaque as the vorticity magnitude where the particle was,
    fading towards the trace's old end, and coloured by the vorticity's
    spanwise component on the same red-grey-blue scale, with a legend.
- a faint ground grid below the swimmer (half a body length apart, fixed in
  the world, so the picture shows the body's motion), and the path to follow.
- a camera that follows the swimmer: it aims behind the body's centre
  averaged over half a second (the tail beat does not shake the picture, and
  the near wake is in view), from one of ``VIEWS``: the creature's own view
  by default (its side-car's ``view``: the manta from in front and above, the
  frog from above, the turtle from the side and above), from the distance at
  which the body's box spans ``BODY_SHARE`` (40 %) of the picture's width,
  with ``WAKE_LENGTHS`` body lengths of wake behind it in view.

The spanwise axis is the world axis across the stroke: of y and z, the one
along which the swim's vorticity is strongest (z for a fish beating its tail
side to side, whose wake turns about vertical axes; y for a ray flapping its
wings up and down). The pictures depend only on the trajectory and the look,
so a run directory re-renders to the same pictures (``aquagait render``).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, replace
from itertools import product

import numpy as np
from scipy.ndimage import zoom

from aquagait.body.dynamics import Dynamics
from aquagait.body.geometry import body_boxes
from aquagait.body.meshes import link_meshes
from aquagait.body.model import Model
from aquagait.sim import Trajectory
from aquagait.sim.particles import Replay, sample, vorticity, vorticity_percentile, wake
from aquagait.sim.vortices import Q_FRACTION, frame_q, q_level
from aquagait.viz.camera import VIEWS, project, view_camera
from aquagait.viz.style import ROUTE

SMOOTHING = 0.5  # [s] the camera's aim is the body's centre averaged over this long
WAKE_LENGTHS = 0.6
"""Body lengths of wake behind the body that the camera frames with it."""
BODY_SHARE = 0.4
"""The share of the picture's width the body's box spans (its projection, the swim's median)."""
WAKES = ("both", "q", "traces")
SPIN = {1: (0.75, 0.08, 0.05), 0: (0.5, 0.5, 0.52), -1: (0.05, 0.22, 0.75)}
"""Colours of the spin scale: counter-clockwise (+1), across (0), clockwise (-1)."""
SURFACE_ALPHA = 0.55
SURFACE_REFINE = 2
"""Q is interpolated (cubic splines) onto a lattice this many times finer before marching
cubes: on the coarse lattice a vortex tube three cells across comes out ribbed, a kink at
every cell."""
LEGEND_WIDTH = 3.6
"""The legend's width [inches]; its height grows with its lines."""
LEGEND_DPI = 100
LEGEND_SHARE = 0.5
"""The most of the picture's width the legend may cover; narrower pictures go without."""
GROUND = (0.35, 0.38, 0.42, 0.12)
"""RGBA of the ground grid's lines."""
GROUND_SPACING = 0.5
"""The ground grid's spacing [body lengths]."""
GROUND_SPAN = 4
"""How far the ground grid reaches from the camera's aim [body lengths]."""


@dataclass(frozen=True)
class Look3D:
    """How a 3D swim is drawn.

    Attributes:
        view: one of ``VIEWS`` ('side', 'top', 'follow', 'side-above', 'front-above').
        width, height: picture size [pixels] (even, as H.264 wants).
        wake: 'both', 'q' (vortex surfaces) or 'traces' (module docstring).
        q_fraction: the vortex surfaces' threshold, a share of the swim's peak Q.
        trace_frames: frames per particle trace (docs/pictures.md: 15).
        particles: how many particles.
        lifetime: frames a particle lives before it is seeded again near the body.
        substeps: RK2 steps per frame for the particles.
        vorticity_scale: |vorticity| [1/s] at full opacity and colour; None:
            the 99th percentile over the fluid cells of all frames.
        seed: particle placement.
        route: (n, 3) world points [m] of a path to follow, drawn as a red
            line; None: no path.
        ground: draw the ground grid.
        legend: draw the colour scale's legend (needs matplotlib, the ``viz`` extra).
    """

    view: str = "follow"
    width: int = 1280
    height: int = 720
    wake: str = "both"
    q_fraction: float = Q_FRACTION
    trace_frames: int = 15
    particles: int = 3000
    lifetime: int = 60
    substeps: int = 3
    vorticity_scale: float | None = None
    seed: int = 0
    route: np.ndarray | None = None
    ground: bool = True
    legend: bool = True

    def __post_init__(self):
        if self.view not in VIEWS:
            raise ValueError(f"unknown view {self.view!r}; views: {', '.join(VIEWS)}")
        if self.wake not in WAKES:
            raise ValueError(f"unknown wake {self.wake!r}; wakes: {', '.join(WAKES)}")
        if not 0 < self.q_fraction < 1:
            raise ValueError(f"q_fraction must lie in (0, 1), got {self.q_fraction!r}")
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
    cameras, aims = _cameras(model, trajectory, look)
    fluid = trajectory.fluid
    axis = spin_axis(fluid) if fluid is not None else 2
    scale = look.vorticity_scale or (vorticity_percentile(fluid) if fluid is not None else 1.0)
    traces = _wake(trajectory, model, look, axis, scale) if look.wake != "q" else None
    level = None
    if fluid is not None and look.wake != "traces":
        _need_marching_cubes()
        level = q_level(fluid, look.q_fraction)
    route = () if look.route is None else ((look.route, ROUTE),)
    floor = floor_height(model, trajectory.qpos) if look.ground else None
    legend = _legend(look, axis, scale, level) if look.legend and fluid is not None else None
    with Renderer(link_meshes(model), look.width, look.height, line_width=1.5) as renderer:
        for f in frames:
            lines, alpha, spin = traces.at(f) if traces is not None else (None, None, None)
            surfaces = () if level is None else vortex_surfaces(fluid, f, level, axis)
            grid = () if floor is None else ground_grid(aims[f], floor, model.body_length)
            pos, rot = dynamics.link_poses(trajectory.qpos[f])
            picture = renderer.draw(
                pos, rot, cameras[f], traces=lines, trace_alpha=alpha,
                trace_colours=None if spin is None else spin_colours(spin),
                lines=grid + route, surfaces=surfaces,
            )  # fmt: skip
            yield picture if legend is None else _overlay(picture, legend)


def spin_axis(fluid) -> int:
    """The spanwise axis of a 3D swim's wake: 1 (y) or 2 (z), the one along which its
    vorticity is strongest over (up to 10 of) its frames."""
    picks = np.unique(np.linspace(0, len(fluid.origin) - 1, 10).round().astype(int))
    total = np.zeros(3)
    for f in picks:
        omega = np.abs(vorticity(fluid, f))
        total += omega.reshape(3, -1).sum(axis=1)
    return 1 if total[1] > total[2] else 2


def spin_colours(spin) -> np.ndarray:
    """RGB (..., 3) of spins in [-1, 1]: blue through grey to red (``SPIN``)."""
    spin = np.clip(np.asarray(spin, dtype=float), -1.0, 1.0)[..., None]
    calm, up, down = (np.array(SPIN[k]) for k in (0, 1, -1))
    return np.where(spin >= 0, calm + spin * (up - calm), calm - spin * (down - calm))


def vortex_surfaces(fluid, frame: int, level: float, axis: int) -> tuple:
    """The frame's vortex surfaces ``Q = level`` as one ``SurfaceMesh`` (none where Q stays
    below the level): world vertices, their normals, and colours by the vorticity's
    direction along ``axis`` there (module docstring)."""
    from skimage.measure import marching_cubes

    from aquagait.viz.gl import SurfaceMesh

    q = frame_q(fluid, frame)
    if not np.isfinite(level) or q.max() <= level:
        return ()
    low, high = _around(q > level, margin=2)
    fine = zoom(q[tuple(slice(a, b) for a, b in zip(low, high, strict=True))], SURFACE_REFINE,
                order=3, mode="nearest", grid_mode=False)  # fmt: skip
    vertices, triangles, normals, _ = marching_cubes(fine, level)
    steps = (high - low - 1) / (np.array(fine.shape) - 1)  # fine points to coarse cells
    origin, h = fluid.origin[frame], fluid.cell_size
    world = origin + (low + vertices * steps + 0.5) * h  # lattice indices are cell centres
    omega = sample(vorticity(fluid, frame), origin, h, world)  # (3, n)
    direction = omega[axis] / np.maximum(np.linalg.norm(omega, axis=0), 1e-12)
    spin = np.sign(direction) * np.sqrt(np.abs(direction))  # a vortex leg tilted 45 deg: 84 %
    colours = np.hstack([spin_colours(spin), np.full((len(world), 1), SURFACE_ALPHA)])
    return (SurfaceMesh(world, normals, colours, triangles),)


def _around(inside: np.ndarray, margin: int) -> tuple[np.ndarray, np.ndarray]:
    """The lattice box (low, high: index ranges) holding the True cells, ``margin`` cells
    larger on every side where the lattice allows."""
    where = np.argwhere(inside)
    low = np.maximum(where.min(axis=0) - margin, 0)
    high = np.minimum(where.max(axis=0) + margin + 1, inside.shape)
    return low, high


def _need_marching_cubes() -> None:
    """Raise ``RenderUnavailable`` naming what to install when scikit-image is missing."""
    from aquagait.viz.gl import INSTALL_MODERNGL, RenderUnavailable

    try:
        import skimage.measure  # noqa: F401
    except ImportError as err:
        raise RenderUnavailable(
            f"the vortex surfaces (wake 'q' or 'both') need scikit-image, which cannot be "
            f"imported ({err}); install it with: {INSTALL_MODERNGL}, "
            f"or draw the particle traces alone (wake 'traces', --wake traces)"
        ) from err


def _cameras(model: Model, trajectory: Trajectory, look: Look3D) -> tuple[list, np.ndarray]:
    """One camera a frame, and where each aims: behind the body's smoothed centre, at the
    distance (one for the whole swim) at which the body's box spans ``BODY_SHARE`` of the
    picture's width, so that ``WAKE_LENGTHS`` of wake behind it are in view."""
    boxes = body_boxes(model, trajectory.qpos)
    centres = boxes.mean(axis=1)
    half = max(1, int(round(0.5 * SMOOTHING * trajectory.fps)))
    smooth = _smoothed(centres, half)
    heading = _smoothed(np.gradient(centres, axis=0), 3 * half) if len(centres) > 1 else None
    wake = WAKE_LENGTHS * model.body_length
    aspect = look.width / look.height
    looking = VIEWS[look.view][0]
    aims, cameras, shares, corners = [], [], [], []
    for k, centre in enumerate(smooth):
        ahead = np.array([1.0, 0.0, 0.0])
        if heading is not None and np.linalg.norm(heading[k]) > 1e-9:
            ahead = heading[k] / np.linalg.norm(heading[k])
        behind = -0.5 * wake * ahead
        aim = centre + behind - (behind @ looking) * looking  # across the view, not into it
        size = boxes[k, 1] - boxes[k, 0]
        camera = view_camera(look.view, aim, size + wake * np.abs(ahead), aspect)
        corners.append(centres[k] + np.array(list(product((-0.5, 0.5), repeat=3))) * size)
        shares.append(np.ptp(project(camera, corners[k], look.width, look.height)[:, 0]))
        aims.append(aim)
        cameras.append(camera)
    scale = float(np.median(shares)) / look.width / BODY_SHARE
    for _ in range(20):  # back off until the body stays in the picture in every frame
        moved = [replace(c, eye=c.target + scale * (c.eye - c.target)) for c in cameras]
        if all(_within(c, box, look) for c, box in zip(moved, corners, strict=True)):
            break
        scale *= 1.05
    return moved, np.array(aims)


def _within(camera, points, look: Look3D, margin: float = 0.02) -> bool:
    """Every point projects inside the picture, ``margin`` of its sides from the edges."""
    p = project(camera, points, look.width, look.height) / [look.width, look.height]
    return bool(np.all((p >= margin) & (p <= 1 - margin)))


def _smoothed(values: np.ndarray, half: int) -> np.ndarray:
    """Means over a window of ``2 half + 1`` frames (the ends held), (F, 3)."""
    padded = np.pad(values, ((half, half), (0, 0)), mode="edge")
    kernel = np.ones(2 * half + 1) / (2 * half + 1)
    return np.stack([np.convolve(padded[:, a], kernel, mode="valid") for a in range(3)], 1)


def floor_height(model: Model, qpos) -> float:
    """The ground grid's height [m]: half a body length below the lowest the body reaches
    over the poses ``qpos`` (F, nq)."""
    boxes = body_boxes(model, qpos)
    return float(boxes[:, 0, 2].min() - 0.5 * model.body_length)


def ground_grid(aim, floor: float, length: float, span: float = GROUND_SPAN) -> tuple:
    """``(points, rgba)`` lines of the faint ground grid at height ``floor`` [m] around
    ``aim``, ``span`` body lengths ``length`` [m] each way, fixed in the world (at multiples
    of the spacing, so it stays put as the camera moves)."""
    spacing = GROUND_SPACING * length
    reach = span * length
    lines = []
    for axis in (0, 1):
        other = 1 - axis
        low = np.floor((aim[other] - reach) / spacing) * spacing
        for at in np.arange(low, aim[other] + reach + spacing / 2, spacing):
            ends = np.zeros((2, 3))
            ends[:, axis] = aim[axis] - reach, aim[axis] + reach
            ends[:, other], ends[:, 2] = at, floor
            lines.append((ends, GROUND))
    return tuple(lines)


def _wake(trajectory: Trajectory, model: Model, look: Look3D, axis: int,
          scale: float) -> Replay | None:  # fmt: skip
    if trajectory.fluid is None:
        return None
    return Replay(wake(
        trajectory, model, count=look.particles, length=look.trace_frames,
        lifetime=look.lifetime, substeps=look.substeps, seed=look.seed,
        vorticity_scale=scale, axis=axis,
    ))  # fmt: skip


def _legend(look: Look3D, axis: int, scale: float, level: float | None) -> np.ndarray | None:
    """The colour scale's legend, (h, w, 4) uint8 RGBA; None without matplotlib, or when it
    would cover more than ``LEGEND_SHARE`` of the picture's width (a thumbnail).

    It is drawn at ``LEGEND_DPI`` up to 1280 pixels wide and grows with wider pictures."""
    dpi = LEGEND_DPI * max(1.0, look.width / 1280)
    if LEGEND_WIDTH * dpi > LEGEND_SHARE * look.width:
        return None
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.colors import ListedColormap
        from matplotlib.figure import Figure
    except ImportError:
        return None
    name = "xyz"[axis]
    traces = look.wake != "q"
    lines = [f"colour: the sign of \u03c9{name}, red turning counter-clockwise seen from +{name}"]
    if look.wake != "traces" and level is not None and np.isfinite(level):
        lines.insert(0, f"vortex surfaces: Q = {look.q_fraction:.0%} of the swim's peak "
                        f"({level:.3g} 1/s\u00b2)")  # fmt: skip
    if traces:
        lines.insert(0, f"traces: spanwise vorticity \u03c9{name} [1/s]")
    line, bar_at, bar_height = 0.14, 0.22, 0.15  # [inches]
    height = bar_at + bar_height + 0.06 + line * len(lines)
    figure = Figure(figsize=(LEGEND_WIDTH, height), dpi=dpi)
    figure.patch.set_facecolor((1.0, 1.0, 1.0, 0.75))  # readable over the wake
    canvas = FigureCanvasAgg(figure)
    bar = figure.add_axes((0.04, bar_at / height, 0.92, bar_height / height))
    ramp = np.linspace(-1, 1, 256)
    bar.imshow(ramp[None], aspect="auto", cmap=ListedColormap(spin_colours(ramp)),
               extent=(-scale, scale, 0, 1))  # fmt: skip
    bar.set_yticks([])
    bar.tick_params(labelsize=7, length=2, pad=1)
    if not traces:  # the surfaces' colour is a direction, not a rate
        bar.set_xticks([])
        for x, words, side in ((0, "clockwise", "left"), (1, "counter-clockwise", "right")):
            bar.text(x, -0.15, words, transform=bar.transAxes, fontsize=7, ha=side, va="top")
    figure.text(0.04, 1 - 0.04 / height, "\n".join(lines), fontsize=7, va="top",
                linespacing=1.35, color=(0.15, 0.15, 0.15))  # fmt: skip
    canvas.draw()
    return np.asarray(canvas.buffer_rgba()).copy()


def _overlay(picture: np.ndarray, legend: np.ndarray, margin: int = 12) -> np.ndarray:
    """``legend`` alpha-composited into the picture's lower left corner."""
    h, w = legend.shape[:2]
    h, w = min(h, picture.shape[0] - margin), min(w, picture.shape[1] - margin)
    region = picture[-h - margin : -margin, margin : margin + w].astype(float)
    alpha = legend[:h, :w, 3:4] / 255.0
    blended = region * (1 - alpha) + legend[:h, :w, :3] * alpha
    out = picture.copy()
    out[-h - margin : -margin, margin : margin + w] = blended.round().astype(np.uint8)
    return out
