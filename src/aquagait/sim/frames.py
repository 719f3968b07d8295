"""The fluid as recorded once per frame of a rollout, for pictures and particle traces."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from aquagait.body.voxelize import voxelize
from aquagait.fluid.operators import cell_centered

if TYPE_CHECKING:
    from aquagait.sim.scene import Scene, State


@dataclass(frozen=True, eq=False)
class FluidFrames:
    """The fluid as recorded once per frame, for pictures and particle traces.

    Always a plane: the whole grid in 2D, the mid-plane z = const through the
    grid's centre in 3D (x-y plane, cell-centred values). F frames, a plane of
    ``nx x ny`` cells.

    Attributes:
        cell_size: h [m].
        origin: (F, 2) world position of the plane's lower corner per frame
            (the grid follows the creature) [m].
        velocity: (F, 2, nx, ny) in-plane velocity at cell centres [m/s].
        solid: (F, nx, ny) cells inside the body.
        plane_z: the plane's world z [m] (0 in 2D).
    """

    cell_size: float
    origin: np.ndarray
    velocity: np.ndarray
    solid: np.ndarray
    plane_z: float = 0.0


def fluid_frames(scene: Scene, frames: list[State]) -> FluidFrames:
    """The fluid plane of every frame: the whole grid in 2D, the mid-plane z in 3D."""
    origins, velocities, solids = [], [], []
    for state in frames:
        grid = state.grid
        centred = cell_centered(grid, state.velocity)
        solid = voxelize(scene.shape, grid, *scene.dynamics.link_poses(state.qpos)).solid
        if grid.dim == 3:
            k = grid.shape[2] // 2
            centred, solid = centred[:2, :, :, k], solid[:, :, k]
        origins.append(grid.origin[:2])
        velocities.append(centred)
        solids.append(solid)
    grid = frames[-1].grid
    plane_z = grid.origin[2] + (grid.shape[2] // 2 + 0.5) * grid.cell_size if grid.dim == 3 else 0
    return FluidFrames(
        cell_size=grid.cell_size,
        origin=np.array(origins),
        velocity=np.stack(velocities).astype(np.float32),
        solid=np.stack(solids),
        plane_z=float(plane_z),
    )
