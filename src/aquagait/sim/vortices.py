"""Where the wake's vortices are: the Q-criterion of the recorded flow (Hunt, Wray and Moin 1988).

A vortex is where the fluid rotates more than it is strained: with ``G`` the
velocity gradient, ``G_ij = d u_i / d x_j``, its antisymmetric part
``W = (G - G^T) / 2`` (rotation) and symmetric part ``S = (G + G^T) / 2``
(strain),

    Q = (|W|^2 - |S|^2) / 2 = -tr(G G) / 2        [1/s^2]

(``|.|`` the Frobenius norm) is positive inside a vortex core and negative
where strain dominates. For a planar swirl ``u_theta(r)`` it is
``(u_theta / r) du_theta/dr``: a solid-body rotation at rate ``w`` has
``Q = w^2`` everywhere; a Lamb-Oseen vortex has ``Q > 0`` inside the radius of
its fastest swirl and ``Q < 0`` outside.

The gradient is taken by central differences on the lattice of a recorded
frame (``aquagait.sim.FluidFrames``: cell-centred velocity; one-sided, second
order, at the lattice's edge). The body's cells and those within ``NEAR_BODY``
of them are set to ``Q = 0``: inside the solid the velocity is the body's
own, and the shear of the boundary layer beside it is not the wake.

The 3D pictures draw the surfaces ``Q = Q_FRACTION * peak`` (``q_level``),
the peak a high percentile of Q over the water of every frame, so that one
threshold holds for the whole swim and a vortex neither pops in nor out as
the flow grows.
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import binary_dilation

from aquagait.sim.frames import FluidFrames

Q_FRACTION = 0.5
"""The pictures' isosurface: this share of the swim's peak Q (``q_level``). Half: at a
twentieth the fish's wake is one cloud, at a quarter still blobs; at half its vortex
loops stand apart, a chain behind the tail."""

NEAR_BODY = 2
"""Cells beside the body (and the body's own) where Q is set to 0: the boundary layer."""

Q_PEAK_PERCENTILE = 99.9
"""The swim's peak Q: this percentile of Q over the water of every frame (not the
maximum, which one cell at a sharp edge may set)."""


def velocity_gradient(velocity: np.ndarray, cell_size: float) -> np.ndarray:
    """``G[i, j] = d u_i / d x_j`` at the cell centres, (dim, dim, *shape) [1/s].

    Args:
        velocity: (dim, *shape) velocity at the cell centres of a lattice [m/s].
        cell_size: the lattice spacing h [m].
    """
    velocity = np.asarray(velocity, dtype=float)
    dim = velocity.shape[0]
    if velocity.ndim != dim + 1 or min(velocity.shape[1:]) < 3:
        raise ValueError(
            f"velocity must be (dim, *shape) with dim axes of at least 3 cells; got "
            f"{velocity.shape}"
        )
    return np.stack(
        [np.stack(np.gradient(velocity[i], cell_size, edge_order=2), axis=0) for i in range(dim)]
    )


def q_criterion(velocity: np.ndarray, cell_size: float) -> np.ndarray:
    """``Q = -tr(G G) / 2`` at the cell centres, ``shape`` [1/s^2] (module docstring)."""
    gradient = velocity_gradient(velocity, cell_size)
    return -0.5 * np.einsum("ij...,ji...->...", gradient, gradient)


def frame_q(fluid: FluidFrames, frame: int) -> np.ndarray:
    """Q of one recorded frame, ``fluid.shape`` [1/s^2], 0 in and next to the body."""
    q = q_criterion(fluid.velocity[frame], fluid.cell_size)
    solid = fluid.solid[frame]
    cube = np.ones((3,) * solid.ndim, bool)  # a cell's 26 neighbours, corners too
    near_body = binary_dilation(solid, structure=cube, iterations=NEAR_BODY)
    q[near_body] = 0.0
    return q


def q_level(fluid: FluidFrames, fraction: float = Q_FRACTION) -> float:
    """The isosurface value for a whole swim: ``fraction`` of the ``Q_PEAK_PERCENTILE``-th
    percentile of Q over the water of every frame [1/s^2] (module docstring); inf for
    still water, which has no vortex to draw."""
    if not 0 < fraction < 1:
        raise ValueError(f"fraction must lie in (0, 1), got {fraction!r}")
    values = [frame_q(fluid, f)[~fluid.solid[f]] for f in range(len(fluid.origin))]
    values = np.concatenate(values) if values else np.zeros(1)
    peak = float(np.percentile(values, Q_PEAK_PERCENTILE)) if values.size else 0.0
    return fraction * peak if peak > 0 else np.inf
