"""Self-collision: the volume where non-adjacent links overlap (``E_collision``).

The objective charges it (docs/method-search.md, "The gait and the objective").

Links are sampled from their baked signed-distance grids (``aquagait.body.shape``)
at the points of a fine lattice over the body, with the same pose checks and
sampling kernels as ``voxelize``. Parent and child links overlap at their
joints by design; only links that are not adjacent count.
"""

from __future__ import annotations

import numba
import numpy as np

from aquagait.body.shape import BodyShape, turned_boxes
from aquagait.body.voxelize import baked_arrays, cell_range, checked_pose, link_distance

__all__ = ["MAX_OVERLAP_SAMPLES", "overlap_volume"]

MAX_OVERLAP_SAMPLES = 50_000_000
"""Most lattice points ``overlap_volume`` will count; ~100^3 is the usual budget."""


def overlap_volume(shape: BodyShape, link_pos, link_rot, spacing: float) -> float:
    """Volume where two or more non-adjacent links overlap [m^3] (``E_collision``).

    Counts the points of a lattice of the given spacing over the body's
    bounding box that lie inside two links that are not parent and child
    (adjacent links overlap at their joints by design). Error: about the
    overlap region's surface times ``spacing / 2`` at most, far less on average.

    Args:
        shape: the links' baked geometry.
        link_pos: (nl, 3) world link origins [m]; link_rot: (nl, 3, 3).
        spacing: lattice spacing [m], e.g. the body length / 100.
    Returns:
        the volume [m^3]; in 2D the overlapping area times the prism depth.
    Raises:
        ValueError: malformed poses or spacing, more than 63 links, or a
            lattice of more than ``MAX_OVERLAP_SAMPLES`` points.
    """
    if not np.isfinite(spacing) or spacing <= 0:
        raise ValueError(f"spacing must be a positive length in metres, got {spacing!r}")
    if shape.nlinks > 63:
        raise ValueError(f"overlap_volume handles up to 63 links, this body has {shape.nlinks}")
    pos, rot = checked_pose(shape, link_pos, link_rot)
    if not shape.dims[:, 0].any():
        return 0.0  # no geoms at all
    lo, hi = _bounds(shape, pos, rot)
    counts = np.maximum(np.ceil((hi - lo) / spacing).astype(np.int64), 1)
    if shape.dim == 2:
        lo[2], counts[2] = -spacing / 2, 1  # lattice points at z = 0
    if counts.prod() > MAX_OVERLAP_SAMPLES:
        raise ValueError(
            f"spacing {spacing:.3g} m needs {counts.prod()} lattice points over the body, more "
            f"than {MAX_OVERLAP_SAMPLES}; use a larger spacing"
        )
    inside = np.zeros(tuple(counts), dtype=np.int64)
    apart = _apart_masks(shape.parent)
    count = _overlap_count(*baked_arrays(shape), rot, pos, lo, float(spacing), inside, apart)
    if shape.dim == 2:
        return float(count * spacing**2 * shape.depth)
    return float(count * spacing**3)


def _bounds(shape: BodyShape, pos: np.ndarray, rot: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """World bounding box (lo, hi) of every link's baked grid [m]."""
    k = np.flatnonzero(shape.dims[:, 0] > 0)
    lower = shape.lower[k]
    box = turned_boxes(lower, lower + (shape.dims[k] - 1) * shape.spacing, pos[k], rot[k])
    return box[0], box[1]


def _apart_masks(parent: np.ndarray) -> np.ndarray:
    """Bit masks (nl,) int64: bit j of entry k is set when links k and j are not adjacent."""
    nl = parent.size
    everyone = (1 << nl) - 1
    masks = np.empty(nl, dtype=np.int64)
    for k in range(nl):
        near = 1 << k
        if parent[k] >= 0:
            near |= 1 << int(parent[k])
        for child in np.flatnonzero(parent == k):
            near |= 1 << int(child)
        masks[k] = everyone & ~near
    return masks


@numba.njit(cache=True)
def _overlap_count(sdf, offset, dims, lower, spacing, rot, pos, origin, step, inside, apart):
    """Lattice points inside two non-adjacent links; ``inside`` gets one bit per link."""
    span = np.empty((3, 2), dtype=np.int64)
    for k in range(dims.shape[0]):
        if dims[k, 0] == 0:
            continue
        bit = np.int64(1) << k
        cell_range(dims[k], lower[k], spacing, rot[k], pos[k], origin, step, inside.shape, span)
        for i in range(span[0, 0], span[0, 1] + 1):
            x = origin[0] + (i + 0.5) * step
            for j in range(span[1, 0], span[1, 1] + 1):
                y = origin[1] + (j + 0.5) * step
                for l in range(span[2, 0], span[2, 1] + 1):
                    z = origin[2] + (l + 0.5) * step
                    phi = link_distance(
                        sdf, offset[k], dims[k], lower[k], spacing, rot[k], pos[k], x, y, z
                    )
                    if phi < 0:
                        inside[i, j, l] |= bit
    count = 0
    flat = inside.ravel()
    for n in range(flat.size):
        links = flat[n]
        if links & (links - 1) == 0:  # at most one link here
            continue
        for k in range(apart.size):
            if (links >> k) & 1 and links & apart[k]:
                count += 1
                break
    return count
