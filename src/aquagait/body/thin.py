"""Thin parts closed to water: faces whose cell centres lie on opposite sides of a part.

Water fractions (``aquagait.body.subcell``) let a face pass water over the
share of its control volume that is not body. For a part thinner than a cell
that share is most of the face, so water flows *through* the part: a plate a
third of a cell thick felt 1 % of its added mass. The pressure unknowns sit at
cell centres, so what decides whether water can cross a part is whether two
centres joined by an open face lie on opposite sides of it. Here, after
Guendelman, Selle, Losasso and Fedkiw (2005) and Robinson-Mosher et al.
(2008), such faces are closed inside the coupled system:

- **Crossed faces.** A face whose two cell centres face a part from opposite
  sides is closed (``w = 0``): its whole control volume moves with the part
  (its links' shares, scaled up to one), so the full pressure difference
  across it pushes the body and no water crosses it. The side a centre faces
  is the normal of the surface it meets: outside the body, where the segment
  towards the other centre first comes within ``NEAR`` of the body; inside,
  the nearest surface's. Opposite sides (normals more than ``OPPOSED``
  apart) are a plate's two faces; a segment clipping a thick body's curved
  side or corner meets surfaces that face the same way and is left alone.
- **Thin cells.** A cell whose centre is inside a part that is thin there
  joins both sides through its own pressure. It is thin when two of its
  neighbours outside the body face the part from opposite sides: the two
  neighbours along one axis (the part is thinner than two cells along it),
  or two along different axes (a tilted part). Every face of a thin cell
  closes, so the cell has no water and the sides share no pressure.

Everywhere else the fractions stay as they are, so thick parts keep their
second-order boundary (a disc, a sphere and a turned box get the same faces
with and without the closure). Because the closure is part of the fractions,
it is part of the one SPD solve: nothing is reset once a step.

Where a segment comes near a part is found by sphere tracing the union of the
links' signed distances (``aquagait.body.shape``): a step as long as the
distance to the nearest surface cannot pass through a part. The candidate
links are those deepest or second deepest at the lattice samples of the
cells involved (``subcell``'s half-cell lattice), since a link that a
segment meets comes within half a cell of some sample there. Normals are
central differences half a sample long, so a mirror-symmetric body gets
mirror-symmetric closures.
"""

from __future__ import annotations

import numba
import numpy as np

from aquagait.body.shape import PAD
from aquagait.body.voxelize import link_distance

NEAR = 0.5
"""How near a part, in signed-distance samples, counts as on it. Interpolated
between samples, the distance of a part thinner than about two samples can stay
above zero where it is tilted against the samples' axes (a plate a fifth of a
cell thick, a quarter cell a sample: its interpolated distance came within
0.01 cells of zero); within half a sample of the surface, such a part is met."""

OPPOSED = -0.5
"""Two surfaces whose normals' cosine is below this face away from each other."""

SMALLEST_STEP = 1 / 16
"""The shortest step of a trace, in signed-distance samples."""


def close_thin_parts_(baked, rot, pos, origin, h, first, phi, link, weights, links, shares):
    """Close crossed faces and the faces of thin cells, in place (module docstring).

    Args:
        baked: the shape's arrays (``voxelize.baked_arrays``).
        rot, pos: (nl, 3, 3) rest-frame-to-world rotations, (nl, 3) origins.
        origin: (3,) the grid's origin [m]; h: the cell size [m].
        first: (3,) the box's first cell.
        phi, link: the two deepest distances and links at the box's lattice samples.
        weights, links, shares: per axis, the box's faces' water fractions and
            their links' shares (``subcell._face_fractions_``), changed in place.
    """
    dim = len(weights)
    count = np.array(weights[0].shape) - np.eye(3, dtype=np.int64)[0]
    centre = np.empty(tuple(count))
    _centre_distances_(*baked, rot, pos, origin, h, first, link, centre)
    for a in range(dim):
        _close_crossed_(*baked, rot, pos, origin, h, first, link, centre, a, weights[a],
                        links[a], shares[a])  # fmt: skip
    thin = np.full(tuple(count), -1, np.int64)
    _thin_cells_(*baked, rot, pos, origin, h, first, link, centre, dim, thin)
    if (thin >= 0).any():
        for a in range(dim):
            _close_cell_faces_(thin, a, weights[a], links[a], shares[a])


@numba.njit(cache=True, nogil=True)
def _centre_distances_(sdf, offset, dims, lower, spacing, rot, pos, origin, h, first, link, out):
    """The body's signed distance at every box cell's centre, in place [m]."""
    cand = np.empty(64, np.int64)
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            for l in range(out.shape[2]):
                n = _cell_candidates(link, i, j, l, cand, 0)
                x = _centre(origin, h, first, i, j, l, out.shape[2] == 1)
                out[i, j, l] = _union(sdf, offset, dims, lower, spacing, rot, pos, cand, n, x)[0]


@numba.njit(cache=True, nogil=True)
def _close_crossed_(sdf, offset, dims, lower, spacing, rot, pos, origin, h, first, link, centre,
                    a, weight, links, shares):  # fmt: skip
    """Close the faces normal to ``a`` whose cell centres face a part from opposite
    sides, in place."""
    cand = np.empty(64, np.int64)
    step = np.zeros(3, np.int64)
    step[a] = 1
    flat = centre.shape[2] == 1
    clear = h + 2 * NEAR * spacing
    for i in range(step[0], weight.shape[0] - step[0]):
        for j in range(step[1], weight.shape[1] - step[1]):
            for l in range(step[2], weight.shape[2] - step[2]):
                if weight[i, j, l] >= 1.0 or weight[i, j, l] == 0.0:
                    continue
                p, q, r = i - step[0], j - step[1], l - step[2]
                below, above = centre[p, q, r], centre[i, j, l]
                if 0.0 < below < np.inf and 0.0 < above < np.inf and below + above >= clear:
                    continue  # balls free of the body cover the segment, with room to spare
                # (off every link's grid the distance is unknown: +inf, no ball)
                n = _cell_candidates(link, p, q, r, cand, 0)
                n = _cell_candidates(link, i, j, l, cand, n)
                lo = _centre(origin, h, first, p, q, r, flat)
                hi = _centre(origin, h, first, i, j, l, flat)
                hit = _straddled(sdf, offset, dims, lower, spacing, rot, pos, cand, n, lo, hi)
                if hit >= 0:
                    _close_(weight, links, shares, i, j, l, hit)


@numba.njit(cache=True, nogil=True)
def _thin_cells_(sdf, offset, dims, lower, spacing, rot, pos, origin, h, first, link, centre,
                 dim, thin):  # fmt: skip
    """Mark the box's cells whose centre is on a part thin there with that part's link,
    in place: two of their neighbours outside the body straddle it (the
    neighbours along one axis, or two along different axes)."""
    cand = np.empty(64, np.int64)
    shape = centre.shape
    flat = shape[2] == 1
    for i in range(shape[0]):
        for j in range(shape[1]):
            for l in range(shape[2]):
                if centre[i, j, l] > 0.0 or centre[i, j, l] <= -h:
                    continue  # deeper than a cell: no neighbour is outside
                n = _cell_candidates(link, i, j, l, cand, 0)
                cell = (i, j, l)
                for pair in range(4 * dim * dim):
                    a, sa, b, sb = (
                        pair // (4 * dim),
                        pair // (2 * dim) % 2,
                        pair // 2 % dim,
                        pair % 2,
                    )
                    if thin[i, j, l] >= 0 or b < a or (b == a and sb <= sa):
                        continue
                    na, nb = _neighbour(cell, a, 2 * sa - 1), _neighbour(cell, b, 2 * sb - 1)
                    if not (_outside(centre, na) and _outside(centre, nb)):
                        continue
                    pa = _centre(origin, h, first, na[0], na[1], na[2], flat)
                    pb = _centre(origin, h, first, nb[0], nb[1], nb[2], flat)
                    thin[i, j, l] = _straddled(sdf, offset, dims, lower, spacing, rot, pos, cand,
                                               n, pa, pb)  # fmt: skip


@numba.njit(cache=True, nogil=True)
def _close_cell_faces_(thin, a, weight, links, shares):
    """Close both faces normal to ``a`` of every thin cell, in place; a face whose
    control volume held none of the body becomes the thin cell's link's."""
    step = np.zeros(3, np.int64)
    step[a] = 1
    for i in range(thin.shape[0]):
        for j in range(thin.shape[1]):
            for l in range(thin.shape[2]):
                if thin[i, j, l] < 0:
                    continue
                for f in ((i, j, l), (i + step[0], j + step[1], l + step[2])):
                    if weight[f] > 0.0:
                        _close_(weight, links, shares, f[0], f[1], f[2], thin[i, j, l])


@numba.njit(cache=True, nogil=True)
def _close_(weight, links, shares, i, j, l, hit):
    """Close face (i, j, l): no water, its links' shares scaled up to the whole face."""
    weight[i, j, l] = 0.0
    if not _scale_to_one_(shares, i, j, l):
        links[i, j, l, 0], shares[i, j, l, 0] = hit, 1.0


@numba.njit(cache=True, nogil=True)
def _scale_to_one_(shares, i, j, l):
    total = shares[i, j, l, :].sum()
    if total <= 0.0:
        return False
    shares[i, j, l, :] /= total
    return True


@numba.njit(cache=True, nogil=True)
def _straddled(sdf, offset, dims, lower, spacing, rot, pos, cand, n, lo, hi):
    """The link of a part that the points ``lo`` and ``hi`` (3-tuples) lie on opposite
    sides of, or -1: the sides they face it from (``_side``) point away from
    each other by more than ``OPPOSED``, as a plate's two faces do. A segment
    that clips a thick body's curved side or corner meets surfaces facing the
    same way, and is left to the fractions."""
    k, a = _side(sdf, offset, dims, lower, spacing, rot, pos, cand, n, lo, hi)
    if k < 0:
        return -1
    m, b = _side(sdf, offset, dims, lower, spacing, rot, pos, cand, n, hi, lo)
    if m < 0:
        return -1
    return k if a[0] * b[0] + a[1] * b[1] + a[2] * b[2] < OPPOSED else -1


@numba.njit(cache=True, nogil=True)
def _side(sdf, offset, dims, lower, spacing, rot, pos, cand, n, start, end):
    """Which way the body's surface faces ``start``, looking towards ``end``: the link
    and the unit normal there (a 3-tuple), or -1. Inside the body, the normal at
    ``start`` (towards its nearest surface); outside, the normal where the
    segment to ``end`` first comes within ``NEAR`` samples of the body."""
    phi, k = _union(sdf, offset, dims, lower, spacing, rot, pos, cand, n, start)
    at = start
    if phi > 0.0:
        k, at = _trace(sdf, offset, dims, lower, spacing, rot, pos, cand, n, start, end)
    if k < 0:
        return -1, (0.0, 0.0, 0.0)
    normal = _normal(sdf, offset, dims, lower, spacing, rot, pos, cand, n, at)
    flat = normal[0] == 0.0 and normal[1] == 0.0 and normal[2] == 0.0
    return (-1 if flat else k), normal


@numba.njit(cache=True, nogil=True)
def _trace(sdf, offset, dims, lower, spacing, rot, pos, cand, n, start, end):
    """Where the segment from ``start`` to ``end`` first comes within ``NEAR`` samples of
    a candidate link, and that link (-1 if it never does): sphere tracing the
    union of their signed distances, less ``NEAR``. Off every candidate's grid
    the distance is unknown but at least the grids' margin (``shape.PAD``
    samples), so that is the step there."""
    dx, dy, dz = end[0] - start[0], end[1] - start[1], end[2] - start[2]
    length = np.sqrt(dx * dx + dy * dy + dz * dz)
    near = NEAR * spacing
    s = 0.0
    while s <= length:
        t = s / length
        x = (start[0] + t * dx, start[1] + t * dy, start[2] + t * dz)
        phi, k = _union(sdf, offset, dims, lower, spacing, rot, pos, cand, n, x)
        if phi <= near:
            return k, x
        s += max(min(phi - near, PAD * spacing), SMALLEST_STEP * spacing)
    return -1, end


@numba.njit(cache=True, nogil=True)
def _normal(sdf, offset, dims, lower, spacing, rot, pos, cand, n, x):
    """The unit gradient of the union's signed distance at ``x`` (central differences,
    half a sample apart; zero where it is flat), a 3-tuple."""
    e = 0.5 * spacing
    g = [0.0, 0.0, 0.0]
    for a in range(3):  # a 2D shape's distance does not change along z
        up = (x[0] + e * (a == 0), x[1] + e * (a == 1), x[2] + e * (a == 2))
        down = (x[0] - e * (a == 0), x[1] - e * (a == 1), x[2] - e * (a == 2))
        above = _union(sdf, offset, dims, lower, spacing, rot, pos, cand, n, up)[0]
        below = _union(sdf, offset, dims, lower, spacing, rot, pos, cand, n, down)[0]
        g[a] = above - below
    size = np.sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2])
    if not (np.isfinite(size) and size > 0):
        return (0.0, 0.0, 0.0)
    return (g[0] / size, g[1] / size, g[2] / size)


@numba.njit(cache=True, nogil=True)
def _union(sdf, offset, dims, lower, spacing, rot, pos, cand, n, x):
    """The least signed distance of the candidate links at a point ``x`` (a 3-tuple),
    and its link."""
    best, who = np.inf, -1
    for c in range(n):
        k = cand[c]
        d = link_distance(sdf, offset[k], dims[k], lower[k], spacing, rot[k], pos[k], x[0], x[1],
                          x[2])  # fmt: skip
        if d < best:
            best, who = d, k
    return best, who


@numba.njit(cache=True, nogil=True)
def _cell_candidates(link, i, j, l, cand, n):
    """Append the distinct links deepest or second deepest at cell (i, j, l)'s lattice
    samples to ``cand[:n]``; the new count."""
    s0, s1, s2 = link.shape[1], link.shape[2], link.shape[3]
    for di in range(2 if s0 > 1 else 1):
        for dj in range(2 if s1 > 1 else 1):
            for dl in range(2 if s2 > 1 else 1):
                a = 2 * i + 1 + di if s0 > 1 else 0
                b = 2 * j + 1 + dj if s1 > 1 else 0
                c = 2 * l + 1 + dl if s2 > 1 else 0
                for rank in range(2):
                    k = link[rank, a, b, c]
                    if k < 0:
                        continue
                    known = False
                    for m in range(n):
                        known = known or cand[m] == k
                    if not known and n < cand.size:
                        cand[n] = k
                        n += 1
    return n


@numba.njit(cache=True, inline="always")
def _centre(origin, h, first, i, j, l, flat):
    """World centre of box cell (i, j, l), a 3-tuple [m] (z = 0 on a 2D grid)."""
    z = 0.0 if flat else origin[2] + (first[2] + l + 0.5) * h
    return (origin[0] + (first[0] + i + 0.5) * h, origin[1] + (first[1] + j + 0.5) * h, z)


@numba.njit(cache=True, inline="always")
def _neighbour(cell, a, side):
    out = [cell[0], cell[1], cell[2]]
    out[a] += side
    return (out[0], out[1], out[2])


@numba.njit(cache=True, inline="always")
def _outside(centre, cell):
    """Whether a cell's centre is outside the body; cells beyond the box are."""
    for b in range(3):
        if cell[b] < 0 or cell[b] >= centre.shape[b]:
            return True
    return centre[cell[0], cell[1], cell[2]] > 0.0
