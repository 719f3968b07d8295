"""The fluid as recorded once per frame of a rollout, for pictures and particle traces.

2D keeps the whole grid. 3D keeps the whole volume too (particle traces are
3D), block-averaged where the grid is large: the smallest ``stride`` whose
blocks of ``stride^3`` cells leave at most ``MAX_CELLS`` values per
component, in half precision. So a frame costs at most 3 x 2 x ``MAX_CELLS``
bytes before compression: a 10 s swim (300 frames) of the fish at 64x32x32
(65,536 cells, stride 1) holds 118 MB of velocity, the frog at 96x64x48
(stride 2) 66 MB. Half precision carries 3 significant digits, plenty for
particles that move a fraction of a cell per frame; what a picture is drawn
from in memory is what the run directory stores, so a re-rendered run
draws the same pictures.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from aquagait.body.voxelize import voxelize
from aquagait.fluid.operators import cell_centered

if TYPE_CHECKING:
    from aquagait.sim.scene import Scene, State

MAX_CELLS = 1 << 17
"""Most values per velocity component a 3D frame keeps (module docstring)."""


@dataclass(frozen=True, eq=False)
class FluidFrames:
    """The fluid as recorded once per frame, for pictures and particle traces.

    F frames of a lattice of cells (the grid's, or blocks of ``stride`` of
    them in 3D) whose lower corner moves with the grid.

    Attributes:
        cell_size: the lattice spacing [m] (the grid's h times the stride).
        origin: (F, dim) world position of the lattice's lower corner per
            frame (the grid follows the creature) [m].
        velocity: (F, dim, *shape) velocity at the lattice's cell centres
            [m/s]: float32 in 2D, float16 in 3D (module docstring).
        solid: (F, *shape) cells (or blocks, most of whose cells are) inside the body.
    """

    cell_size: float
    origin: np.ndarray
    velocity: np.ndarray
    solid: np.ndarray

    @property
    def dim(self) -> int:
        return self.velocity.shape[1]

    @property
    def shape(self) -> tuple[int, ...]:
        """The lattice's cells per axis."""
        return self.solid.shape[1:]


def fluid_frame(scene: Scene, state: State, blocks: int | None = None) -> tuple:
    """One frame's (origin, velocity, solid) as ``FluidFrames`` keeps it (module docstring),
    in 3D over blocks of ``blocks`` cells (default this grid's ``stride``; a rollout keeps
    its first grid's, should the grid grow)."""
    grid = state.grid
    blocks = stride(grid.shape) if blocks is None else blocks
    centred = cell_centered(grid, state.velocity)
    solid = voxelize(scene.shape, grid, *scene.dynamics.link_poses(state.qpos)).solid
    if grid.dim == 2:
        return np.asarray(grid.origin, float), centred.astype(np.float32), solid
    return (
        np.asarray(grid.origin, float),
        np.stack([_blocks(c, blocks) for c in centred]).astype(np.float16),
        _blocks(solid.astype(np.float32), blocks) > 0.5,
    )


def fluid_frames(cell_size: float, frames: list[tuple], blocks: int = 1) -> FluidFrames:
    """``FluidFrames`` from the ``fluid_frame`` records of a rollout on a grid of
    ``cell_size`` [m] cells, kept over ``blocks`` of them. A grid that grew during the swim
    (``aquagait.sim.follow``) left earlier frames on a smaller lattice: they are padded to
    the largest at their far side with still water, as the open boundary had it."""
    shape = np.max([solid.shape for _, _, solid in frames], axis=0)
    origin = np.stack([o for o, _, _ in frames])
    velocity = np.stack([_padded(v, (len(shape), *shape)) for _, v, _ in frames])
    solid = np.stack([_padded(solid, shape) for _, _, solid in frames])
    return FluidFrames(cell_size * blocks, origin, velocity, solid)


def _padded(field: np.ndarray, shape) -> np.ndarray:
    """``field`` in the lower corner of zeros of ``shape`` (itself when it has that shape)."""
    if field.shape == tuple(shape):
        return field
    out = np.zeros(shape, dtype=field.dtype)
    out[tuple(slice(0, n) for n in field.shape)] = field
    return out


def stride(shape) -> int:
    """The smallest block edge that leaves at most ``MAX_CELLS`` blocks of a 3D grid ``shape``."""
    s = 1
    while np.prod(-(-np.asarray(shape) // s)) > MAX_CELLS:
        s += 1
    return s


def _blocks(field: np.ndarray, s: int) -> np.ndarray:
    """Means over blocks of ``s^3`` cells (a partial block at the far border: of what it holds)."""
    if s == 1:
        return field
    out = field
    for axis in range(3):
        n = out.shape[axis]
        edges = np.arange(0, n, s)
        out = np.add.reduceat(out, edges, axis=axis) / np.diff(np.append(edges, n)).reshape(
            [-1 if a == axis else 1 for a in range(3)]
        )
    return out
