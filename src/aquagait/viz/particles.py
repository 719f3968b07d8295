"""Massless particles carried by the recorded flow, for traces (DESIGN.md §2.7, paper §7).

The flow is a ``FluidFrames``: per frame f, in-plane velocity at the cell
centres of a plane whose lower corner sits at ``origin[f]`` (the grid follows
the creature by whole cells, so the origin changes). Particles live in world
coordinates, so a moving grid needs no special care: the velocity at a world
point and time t in [t_f, t_f+1] is

    u(x, t) = (1 - s) U_f(x) + s U_f+1(x),    s = (t - t_f) / (t_f+1 - t_f)

with ``U_f(x)`` bilinear between the cell centres of frame f (clamped at the
plane's edge). Between two frames a particle takes ``substeps`` midpoint (RK2)
steps. A particle that leaves the plane or ends up inside the body is
re-seeded where particles are scarcest (blocks of cells below their share),
and its trace starts afresh.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from aquagait.fluid.operators import curl
from aquagait.sim import FluidFrames


def sample(field: np.ndarray, origin, cell_size: float, points: np.ndarray) -> np.ndarray:
    """Bilinear interpolation of a cell-centred field at world points.

    Args:
        field: (..., nx, ny) values at cell centres ``origin + (i + 1/2, j + 1/2) h``.
        origin: (2,) the plane's lower corner [m].
        cell_size: h [m].
        points: (N, 2) world positions [m]; outside the plane the nearest edge value.

    Returns:
        (..., N) values.
    """
    shape = np.array(field.shape[-2:])
    x = np.clip((points - origin) / cell_size - 0.5, 0, shape - 1)
    i0 = np.minimum(x.astype(int), shape - 2)
    t = x - i0
    i, j = i0[:, 0], i0[:, 1]
    tx, ty = t[:, 0], t[:, 1]
    return (
        field[..., i, j] * (1 - tx) * (1 - ty)
        + field[..., i + 1, j] * tx * (1 - ty)
        + field[..., i, j + 1] * (1 - tx) * ty
        + field[..., i + 1, j + 1] * tx * ty
    )


def vorticity(fluid: FluidFrames, frame: int) -> np.ndarray:
    """Vorticity dv/dx - du/dy of a frame at cell centres, (nx, ny) [1/s]: ``operators.curl``."""
    return curl(fluid.velocity[frame], fluid.cell_size)


def inside(fluid: FluidFrames, frame: int, points: np.ndarray) -> np.ndarray:
    """(N,) True where a world point lies in the plane of ``frame`` and not in a solid cell."""
    cell = np.floor((points - fluid.origin[frame]) / fluid.cell_size).astype(int)
    n = np.array(fluid.solid.shape[1:])
    ok = np.all((cell >= 0) & (cell < n), axis=1)
    ok[ok] = ~fluid.solid[frame][cell[ok, 0], cell[ok, 1]]
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
) -> Iterator[np.ndarray]:
    """Particle traces frame by frame.

    Args:
        fluid: the recorded flow, F frames.
        time: (F,) frame times [s].
        per_cell: particles per cell of the plane.
        length: frames per trace (DESIGN.md §2.7: 15).
        substeps: RK2 steps between two frames.
        seed: seeds the particles' random placement.

    Yields:
        For each frame, traces (N, length, 2) of world positions [m], oldest
        first, the current position last; NaN where a trace is younger than
        ``length`` frames.
    """
    rng = np.random.default_rng(seed)
    n = max(1, round(per_cell * fluid.solid[0].size))
    traces = np.full((n, length, 2), np.nan)
    traces[:, -1] = _seed(fluid, 0, n, per_cell, rng, None)
    yield traces.copy()
    for f in range(len(time) - 1):
        moved = advect(fluid, time, f, traces[:, -1], substeps)
        traces = np.roll(traces, -1, axis=1)
        traces[:, -1] = moved
        lost = ~inside(fluid, f + 1, moved)
        if lost.any():
            traces[lost] = np.nan
            traces[lost, -1] = _seed(fluid, f + 1, int(lost.sum()), per_cell, rng, moved[~lost])
        yield traces.copy()


def _seed(fluid: FluidFrames, frame: int, count: int, per_cell: float, rng, others):
    """``count`` new world points in the fluid of ``frame``, where particles are scarcest."""
    h, shape = fluid.cell_size, np.array(fluid.solid.shape[1:])
    block = max(1, int(np.ceil(np.sqrt(4 / per_cell))))  # about 4 particles per block
    blocks = -(-shape // block)
    weight = np.ones(blocks)
    if others is not None and len(others):
        cell = np.floor((others - fluid.origin[frame]) / h).astype(int) // block
        cell = np.clip(cell, 0, blocks - 1)
        count_in = np.zeros(blocks)
        np.add.at(count_in, (cell[:, 0], cell[:, 1]), 1)
        weight = np.maximum(per_cell * block**2 - count_in, 0) + 1e-3
    chosen = rng.choice(weight.size, size=count, p=(weight / weight.sum()).ravel())
    corner = np.stack(np.unravel_index(chosen, blocks), axis=1) * block
    points = fluid.origin[frame] + (corner + rng.random((count, 2)) * block) * h
    points = np.minimum(points, fluid.origin[frame] + shape * h * (1 - 1e-9))
    for _ in range(4):  # move those that fell into the body
        bad = ~inside(fluid, frame, points)
        if not bad.any():
            break
        points[bad] = fluid.origin[frame] + rng.random((int(bad.sum()), 2)) * shape * h
    return points
