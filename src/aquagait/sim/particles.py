"""Massless particles carried by the recorded flow, for traces (docs/pictures.md, paper §7).

The flow is a ``FluidFrames``: per frame f, velocity at the cell centres of a
lattice (2D or 3D) whose lower corner sits at ``origin[f]`` (the grid follows
the creature by whole cells, so the origin changes). Particles live in world
coordinates, so a moving grid needs no special care: the velocity at a world
point and time t in [t_f, t_f+1] is

    u(x, t) = (1 - s) U_f(x) + s U_f+1(x),    s = (t - t_f) / (t_f+1 - t_f)

with ``U_f(x)`` multilinear between the cell centres of frame f (clamped at
the lattice's edge). Between two frames a particle takes ``substeps``
midpoint (RK2) steps. A particle that leaves the lattice or ends up inside
the body is re-seeded where particles are scarcest (blocks of cells below
their share), and its trace starts afresh.

In 3D a few thousand particles cannot fill the whole volume densely, so they
are seeded in a box around the body (``region``) and live a limited number of
frames (``lifetime``, staggered), after which they are seeded again: the
particles stay where the body makes a wake. ``wake`` gives such traces with
an opacity per position, for the 3D pictures and the exports alike.
"""

from __future__ import annotations

from collections.abc import Iterator
from itertools import product

import numpy as np

from aquagait.body.geometry import body_boxes
from aquagait.body.model import Model
from aquagait.fluid.operators import curl
from aquagait.sim.frames import FluidFrames


def sample(field: np.ndarray, origin, cell_size: float, points: np.ndarray) -> np.ndarray:
    """Multilinear interpolation of a cell-centred field at world points.

    Args:
        field: (..., n_1, ..., n_d) values at cell centres ``origin + (i + 1/2) h``.
        origin: (d,) the lattice's lower corner [m].
        cell_size: h [m].
        points: (N, d) world positions [m]; outside the lattice the nearest edge value.

    Returns:
        (..., N) values.
    """
    dim = points.shape[1]
    shape = np.array(field.shape[-dim:])
    x = np.clip((points - origin) / cell_size - 0.5, 0, shape - 1)
    i0 = np.minimum(x.astype(int), np.maximum(shape - 2, 0))
    t = x - i0
    total = 0.0
    for corner in product((0, 1), repeat=dim):
        weight = np.prod([t[:, a] if c else 1 - t[:, a] for a, c in enumerate(corner)], axis=0)
        index = tuple(np.minimum(i0[:, a] + c, shape[a] - 1) for a, c in enumerate(corner))
        total = total + field[(..., *index)] * weight
    return total


def vorticity(fluid: FluidFrames, frame: int) -> np.ndarray:
    """Vorticity of a frame at cell centres [1/s]: ``operators.curl``.

    2D: the scalar dv/dx - du/dy, (nx, ny). 3D: the vector, (3, nx, ny, nz).
    """
    return curl(fluid.velocity[frame], fluid.cell_size)


def vorticity_magnitude(fluid: FluidFrames, frame: int) -> np.ndarray:
    """|vorticity| of a frame at cell centres, ``fluid.shape`` [1/s]."""
    omega = vorticity(fluid, frame)
    return np.abs(omega) if fluid.dim == 2 else np.sqrt((omega**2).sum(axis=0))


def inside(fluid: FluidFrames, frame: int, points: np.ndarray) -> np.ndarray:
    """(N,) True where a world point lies in the lattice of ``frame`` and not in a solid cell."""
    cell = np.floor((points - fluid.origin[frame]) / fluid.cell_size).astype(int)
    n = np.array(fluid.shape)
    ok = np.all((cell >= 0) & (cell < n), axis=1)
    ok[ok] = ~fluid.solid[frame][tuple(cell[ok].T)]
    return ok


def advect(fluid: FluidFrames, time, frame: int, points: np.ndarray, substeps: int = 3):
    """Carry world points from frame ``frame`` to ``frame + 1`` through the flow (RK2)."""
    h, v = fluid.cell_size, fluid.velocity
    o = fluid.origin

    def velocity(p, s):
        now = sample(v[frame], o[frame], h, p)
        nxt = sample(v[frame + 1], o[frame + 1], h, p)
        return ((1 - s) * now + s * nxt).T

    dt = (time[frame + 1] - time[frame]) / substeps
    for k in range(substeps):
        s = k / substeps
        mid = points + 0.5 * dt * velocity(points, s)
        points = points + dt * velocity(mid, s + 0.5 / substeps)
    return points


def particle_traces(
    fluid: FluidFrames,
    time,
    per_cell: float = 0.25,
    length: int = 15,
    substeps: int = 3,
    seed: int = 0,
    count: int | None = None,
    region: np.ndarray | None = None,
    lifetime: int | None = None,
) -> Iterator[np.ndarray]:
    """Particle traces frame by frame.

    Args:
        fluid: the recorded flow, F frames.
        time: (F,) frame times [s].
        per_cell: particles per cell of the lattice (when ``count`` is None).
        length: frames per trace (docs/pictures.md: 15).
        substeps: RK2 steps between two frames.
        seed: seeds the particles' random placement.
        count: the number of particles, instead of ``per_cell``.
        region: (F, 2, dim) per frame the [low, high] corners of the box
            where particles are seeded [m]; None: the whole lattice.
        lifetime: frames a particle lives before it is seeded again (each
            particle's first life is cut short at random, so they do not all
            go at once); None: until it leaves the fluid.

    Yields:
        For each frame, traces (N, length, dim) of world positions [m], oldest
        first, the current position last; NaN where a trace is younger than
        ``length`` frames.
    """
    rng = np.random.default_rng(seed)
    n = count if count is not None else max(1, round(per_cell * fluid.solid[0].size))
    density = n / fluid.solid[0].size if region is None else n / _cells_in(fluid, region[0])
    traces = np.full((n, length, fluid.dim), np.nan)
    traces[:, -1] = _seed(fluid, 0, n, density, rng, None, _box(region, 0))
    age = rng.integers(0, lifetime, n) if lifetime else np.zeros(n, int)
    yield traces.copy()
    for f in range(len(time) - 1):
        moved = advect(fluid, time, f, traces[:, -1], substeps)
        traces = np.roll(traces, -1, axis=1)
        traces[:, -1] = moved
        age += 1
        lost = ~inside(fluid, f + 1, moved)
        if lifetime:
            lost |= age >= lifetime
        if lost.any():
            traces[lost] = np.nan
            box = _box(region, f + 1)
            traces[lost, -1] = _seed(fluid, f + 1, int(lost.sum()), density, rng, moved[~lost], box)
            age[lost] = 0
        yield traces.copy()


def wake(
    trajectory,
    model: Model,
    count: int = 3000,
    length: int = 15,
    lifetime: int = 60,
    substeps: int = 3,
    seed: int = 0,
    vorticity_scale: float | None = None,
    margin: float = 0.5,
    axis: int = 2,
) -> Iterator[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """A swim's wake: particle traces, their opacity and spin, frame by frame (docs/pictures.md).

    ``count`` particles are seeded in the body's bounding box grown by
    ``margin`` body lengths on every side and live ``lifetime`` frames. A
    trace position is as opaque as the vorticity magnitude where the particle
    was at that frame, ``sqrt(|omega| / vorticity_scale)`` clipped to 1 (the
    square root keeps weak vortices in sight), fading to 15% at the trace's
    old end; still water is transparent. Its spin is the vorticity's component
    along the world ``axis`` there, over ``vorticity_scale``, clipped to [-1, 1]
    (in 2D the vorticity is a scalar, about z, whatever the axis): positive
    turns counter-clockwise seen from the axis' tip.

    Args:
        trajectory: a ``Trajectory`` with fluid frames (2D or 3D).
        model: the creature (its bounding box places the seeds).
        count, length, lifetime, substeps, seed: as for ``particle_traces``.
        vorticity_scale: |vorticity| [1/s] at full opacity; None: the 99th
            percentile over the fluid cells of all frames (``vorticity_percentile``).
        margin: the seeding box's margin [body lengths].
        axis: 3D: the world axis (0, 1, 2: x, y, z) whose vorticity component is the spin.

    Yields:
        per frame: traces (N, length, dim) [m] as ``particle_traces`` yields
        them, opacity (N, length) in [0, 1] and spin (N, length) in [-1, 1].
    """
    fluid, time = trajectory.fluid, trajectory.time
    region = body_boxes(model, trajectory.qpos)[:, :, : fluid.dim]
    region += np.array([-1.0, 1.0])[None, :, None] * margin * model.body_length
    scale = vorticity_scale or vorticity_percentile(fluid)
    fade = np.linspace(0.15, 1.0, length)
    strength, spin = np.zeros((count, length)), np.zeros((count, length))
    traces = particle_traces(fluid, time, length=length, substeps=substeps, seed=seed,
                             count=count, region=region, lifetime=lifetime)  # fmt: skip
    for f, now in enumerate(traces):
        omega = vorticity(fluid, f)
        magnitude = np.abs(omega) if fluid.dim == 2 else np.sqrt((omega**2).sum(axis=0))
        along = omega if fluid.dim == 2 else omega[axis]
        head = np.nan_to_num(now[:, -1])
        value = sample(np.stack([magnitude, along]), fluid.origin[f], fluid.cell_size, head)
        strength, spin = np.roll(strength, -1, axis=1), np.roll(spin, -1, axis=1)
        strength[:, -1] = np.sqrt(np.clip(value[0] / scale, 0.0, 1.0))
        spin[:, -1] = np.clip(value[1] / scale, -1.0, 1.0)
        young = np.isnan(now[..., 0])  # a re-seeded particle's old trace
        strength[young], spin[young] = 0.0, 0.0
        yield now, strength * fade, spin


def vorticity_percentile(fluid: FluidFrames, percentile: float = 99.0) -> float:
    """A percentile of |vorticity| over the fluid cells of every frame [1/s] (1 if none):
    the colour or opacity scale of the pictures."""
    values = [vorticity_magnitude(fluid, f)[~fluid.solid[f]] for f in range(len(fluid.origin))]
    values = np.concatenate(values) if values else np.zeros(1)
    scale = float(np.percentile(values, percentile)) if values.size else 0.0
    return scale if scale > 0 else 1.0


class Replay:
    """Items of an iterator asked for by increasing frame index, some skipped: ``at(f)``
    advances the iterator to item ``f`` (the traces of frame ``f`` depend on every frame
    before it)."""

    def __init__(self, items):
        self.items, self.frame, self.last = iter(items), -1, None

    def at(self, f: int):
        while self.frame < f:
            self.last = next(self.items)
            self.frame += 1
        return self.last


def _box(region, frame):
    return None if region is None else region[frame]


def _cells_in(fluid: FluidFrames, box) -> float:
    return max(1.0, float(np.prod((box[1] - box[0]) / fluid.cell_size)))


def _seed(fluid: FluidFrames, frame: int, count: int, per_cell: float, rng, others, box=None):
    """``count`` new world points in the fluid of ``frame`` (within ``box``), where
    particles are scarcest."""
    h, shape, origin = fluid.cell_size, np.array(fluid.shape), fluid.origin[frame]
    lo, hi = np.zeros(fluid.dim, int), shape
    if box is not None:  # the lattice's cells the box covers, at least one
        lo = np.clip(np.floor((box[0] - origin) / h).astype(int), 0, shape - 1)
        hi = np.clip(np.ceil((box[1] - origin) / h).astype(int), lo + 1, shape)
    span = hi - lo
    block = max(1, int(np.ceil((4 / per_cell) ** (1 / fluid.dim))))  # about 4 particles a block
    blocks = -(-span // block)
    weight = np.ones(blocks)
    if others is not None and len(others):
        cell = (np.floor((others - origin) / h).astype(int) - lo) // block
        within = np.all((cell >= 0) & (cell < blocks), axis=1)
        count_in = np.zeros(blocks)
        np.add.at(count_in, tuple(cell[within].T), 1)
        weight = np.maximum(per_cell * block**fluid.dim - count_in, 0) + 1e-3
    chosen = rng.choice(weight.size, size=count, p=(weight / weight.sum()).ravel())
    corner = lo + np.stack(np.unravel_index(chosen, blocks), axis=1) * block
    points = origin + (corner + rng.random((count, fluid.dim)) * block) * h
    points = np.minimum(points, origin + hi * h * (1 - 1e-9))
    for _ in range(4):  # move those that fell into the body
        bad = ~inside(fluid, frame, points)
        if not bad.any():
            break
        points[bad] = origin + (lo + rng.random((int(bad.sum()), fluid.dim)) * span) * h
    return points
