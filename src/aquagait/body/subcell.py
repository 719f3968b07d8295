"""Sub-cell solid boundaries: the fluid fraction of every face near the body.

The staircase (``aquagait.body.voxelize``) makes a cell solid when its centre
is inside a link, so a face is open water or wall and nothing between: a fin
thinner than a cell is there or not depending on where it falls, and a body
moving by a tenth of a cell changes nothing until a cell flips. Here, after
Batty, Bertails and Bridson (2007), every face gets the fraction ``w`` of its
*control volume* (the box of one cell's size centred on the face, half in
each neighbour cell) that is water. The coupled system weights the fluid's
velocity on the face by ``w`` and the body's by ``1 - w``
(``aquagait.coupling``), which keeps it symmetric positive definite and makes
the pressure the minimizer of the kinetic energy of fluid plus body.

Fractions from the links' signed distances (``aquagait.body.shape``), sampled
once per step on a lattice twice as fine as the cells and offset by a quarter
cell, ``x = (n / 2 + 1 / 4) h``: each cell holds 2^dim samples, each face's
control volume 2^dim too (half of them in each neighbour cell), so every face
of every axis reads the same samples. A sample stands for a box of ``h / 2``
a side and counts as solid by ``clip(1/2 - phi / (h / 2), 0, 1)``: exact for a
wall parallel to the box, second order in ``h`` for a curved one, and
continuous in the body's pose, so forces no longer jump as cells flip. A part
thinner than a cell blocks about the share of the face it covers.

Rules:

- A face whose water fraction is below ``WEIGHT_FLOOR`` is closed (``w = 0``):
  a film of water that thin would only slow the solver.
- A cell has water (a pressure unknown) when any of its faces is open; the
  others are ``solid``. Water that cannot reach the open boundary through open
  faces is sealed (solid, moving with the body), as on the staircase.
- A cell's owner is the deepest link of its samples when more than half of
  it is solid (a sealed cell always has one); the faces between solid cells
  carry the owner's velocity, for advection (``aquagait.coupling.rigid_faces_``).
- A coupled face is any face next to a cell with water whose fraction is
  below 1; its link is the link of its deepest sample.
"""

from __future__ import annotations

import numba
import numpy as np

from aquagait.body.shape import BodyShape
from aquagait.body.thin import close_thin_parts_
from aquagait.body.voxelize import (
    Voxels,
    as_3d,
    baked_arrays,
    cell_range,
    check_grid,
    checked_pose,
    link_distance,
    link_world_box,
    origin_3d,
    own_pockets_,
)
from aquagait.grid import Grid

WEIGHT_FLOOR = 0.01
"""Water fractions below this close the face."""

SEAM = 0.25
"""Where two links are within this many cells of the same depth at a sample, the
sample's solid share is split between them, linearly in the difference: a face
where links meet passes continuously from one to the other, and mirror-image
links get mirror-image shares."""

SLOTS = 4
"""Most links one face's solid part is split between (more is merged into the largest)."""

MARGIN = 2
"""Cells added around the links' boxes: a partly covered cell, and a layer of open water."""


def voxelize_subcell(
    shape: BodyShape, grid: Grid, link_pos, link_rot, close: bool = True
) -> Voxels:
    """Cells without water, owners and coupled faces with their water fractions (module docstring).

    Args:
        shape: the links' baked geometry (``body_shape(model, grid.cell_size)``).
        grid: the MAC grid, of the model's dimension.
        link_pos: (nl, 3) world origins of the links [m].
        link_rot: (nl, 3, 3) world rotations of the links.
        close: close the faces that water would cross a thin part by
            (``aquagait.body.thin``); False keeps the fractions alone
            (``voxelize_fractions``).
    Returns:
        the ``Voxels``, ``face_weight`` holding each coupled face's water fraction.
    Raises:
        ValueError: as ``voxelize``.
    """
    check_grid(shape, grid)
    pos, rot = checked_pose(shape, link_pos, link_rot)
    h, cells = grid.cell_size, as_3d(grid.shape)
    origin = origin_3d(grid.origin, h)
    baked = baked_arrays(shape)
    box = np.empty((3, 2), dtype=np.int64)
    owner = np.full(cells, -1, dtype=np.int32)
    if not _body_box(*baked, rot, pos, origin, h, np.array(cells), box):
        return _voxels(grid, owner, np.ones(cells, bool), [])
    first = box[:, 0]
    count = box[:, 1] - first + 1
    region = tuple(slice(f, f + n) for f, n in zip(first, count, strict=True))
    samples = tuple(2 * n + 2 if size > 1 else 1 for n, size in zip(count, cells, strict=True))
    phi = np.full((2,) + samples, np.inf)  # the deepest two links at each sample
    link = np.full((2,) + samples, -1, dtype=np.int32)
    _sample_(*baked, rot, pos, origin, h, first, phi, link)
    axes = range(grid.dim)
    step = np.eye(3, dtype=np.int64)
    weights = [np.empty(tuple(count + step[a])) for a in axes]
    links = [np.empty(tuple(count + step[a]) + (SLOTS,), dtype=np.int32) for a in axes]
    shares = [np.empty(tuple(count + step[a]) + (SLOTS,)) for a in axes]
    for a in axes:
        _face_fractions_(phi, link, h, a, weights[a], links[a], shares[a])
    if close:
        close_thin_parts_(baked, rot, pos, origin, h, first, phi, link, weights, links, shares)
    inside = owner[region]  # a view: the box's owners are written in place
    deepest = np.empty(tuple(count), dtype=np.int32)
    _cell_owners_(phi[0], link[0], h, inside, deepest)
    water = np.ones(cells, bool)
    local_water = _open_cells(weights, tuple(count))
    _seal_(local_water, weights, grid.dim)
    water[region] = local_water
    _own_sealed(owner, inside, deepest, local_water, first, count)
    faces = []
    for a in axes:
        faces.append(_coupled(weights[a], links[a], shares[a], water, first, a))
    return _voxels(grid, owner, water, faces)


def voxelize_fractions(shape: BodyShape, grid: Grid, link_pos, link_rot) -> Voxels:
    """``voxelize_subcell`` without closing thin parts: water fractions alone, which let
    water through a part thinner than a cell (the boundary before the closure,
    kept for comparison: ``EulerFluid(boundary=voxelize_fractions)``)."""
    return voxelize_subcell(shape, grid, link_pos, link_rot, close=False)


def _open_cells(weights, count) -> np.ndarray:
    """Cells of the box with at least one open face."""
    water = np.zeros(count, bool)
    for a, w in enumerate(weights):
        opened = w > 0
        water |= np.take(opened, range(count[a]), axis=a)
        water |= np.take(opened, range(1, count[a] + 1), axis=a)
    return water


def _own_sealed(owner, inside, deepest, water, first, count) -> None:
    """Give solid cells without an owner their deepest link, or the nearest owner's."""
    lonely = ~water & (inside < 0)
    inside[lonely] = deepest[lonely]
    inside[lonely & (deepest < 0)] = -2
    pockets = int(np.count_nonzero(inside == -2))
    if pockets:
        last = first + count - 1
        own_pockets_(owner, pockets, first[0], last[0], first[1], last[1], first[2], last[2])


def _coupled(weight, link, share, water, first, a):
    """The coupled faces normal to axis ``a``: partly solid, next to a cell with water;
    one entry per link with a share of the face, a face's entries next to each other."""
    rows, none, links = np.empty((0, 3), np.int64), np.empty(0), np.empty(0, np.int64)
    count = _coupled_sweep_(weight, link, share, water, first, a, rows, none, links, none)
    index = np.empty((count, 3), np.int64)
    at, links, shares = np.empty(count), np.empty(count, np.int64), np.empty(count)
    _coupled_sweep_(weight, link, share, water, first, a, index, at, links, shares)
    return np.full(count, a), index, at, links, shares


def _voxels(grid: Grid, owner, water, faces) -> Voxels:
    dim, h = grid.dim, grid.cell_size
    if faces:
        axis, index, weight, link, share = (
            np.concatenate(parts) for parts in zip(*faces, strict=True)
        )
    else:
        axis, index = np.zeros(0, np.int64), np.zeros((0, 3), np.int64)
        weight, link, share = np.zeros(0), np.zeros(0, np.int64), np.zeros(0)
    centre = origin_3d(grid.origin, h) + (index + 0.5) * h
    centre[np.arange(axis.size), axis] -= 0.5 * h
    if dim == 2:
        centre[:, 2] = 0.0
    return Voxels(
        solid=~water.reshape(grid.shape),
        owner=owner.reshape(grid.shape),
        face_axis=axis.astype(np.int64),
        face_index=index[:, :dim].astype(np.int64),
        face_weight=weight.astype(float),
        face_link=link.astype(np.int64),
        face_center=centre,
        face_share=share.astype(float),
    )


# --- kernels ------------------------------------------------------------------


@numba.njit(cache=True, nogil=True)
def _body_box(sdf, offset, dims, lower, spacing, rot, pos, origin, h, cells, box):
    """Cells (box[a] = first, last) near any link, with ``MARGIN`` around; False if none."""
    span = np.empty((3, 2), dtype=np.int64)
    box[:, 0], box[:, 1] = cells, -1
    for k in range(dims.shape[0]):
        if dims[k, 0] == 0:
            continue
        cell_range(dims[k], lower[k], spacing, rot[k], pos[k], origin, h, cells, span)
        for a in range(3):
            box[a, 0] = min(box[a, 0], span[a, 0] - MARGIN)
            box[a, 1] = max(box[a, 1], span[a, 1] + MARGIN)
    for a in range(3):
        box[a, 0] = max(box[a, 0], 0)
        box[a, 1] = min(box[a, 1], cells[a] - 1)
        if box[a, 0] > box[a, 1]:
            return False
    return True


@numba.njit(cache=True, nogil=True)
def _sample_(sdf, offset, dims, lower, spacing, rot, pos, origin, h, first, phi, link):
    """The two deepest signed distances and their links at every lattice point
    (``phi[0]``, ``link[0]`` the deepest), in place.

    Lattice point ``m`` along a real axis sits at ``(first + m / 2 - 1 / 4) h``
    from the origin (in grid index terms, ``n = 2 first - 1 + m``); a 2D
    grid's single layer is sampled at z = 0.
    """
    shape = phi.shape[1:]
    span = np.empty((3, 2), dtype=np.int64)
    for k in range(dims.shape[0]):
        if dims[k, 0] == 0:
            continue
        lo, hi = link_world_box(dims[k], lower[k], spacing, rot[k], pos[k])
        for a in range(3):
            if shape[a] == 1:
                span[a, 0], span[a, 1] = 0, 0
                continue
            start = np.ceil(2 * ((lo[a] - origin[a]) / h - first[a] + 0.25))
            stop = np.floor(2 * ((hi[a] - origin[a]) / h - first[a] + 0.25))
            span[a, 0] = int(min(max(start, 0.0), shape[a]))
            span[a, 1] = int(min(max(stop, -1.0), shape[a] - 1))
        for i in range(span[0, 0], span[0, 1] + 1):
            x = origin[0] + (first[0] + 0.5 * i - 0.25) * h
            for j in range(span[1, 0], span[1, 1] + 1):
                y = origin[1] + (first[1] + 0.5 * j - 0.25) * h
                for l in range(span[2, 0], span[2, 1] + 1):
                    z = 0.0 if shape[2] == 1 else origin[2] + (first[2] + 0.5 * l - 0.25) * h
                    d = link_distance(
                        sdf, offset[k], dims[k], lower[k], spacing, rot[k], pos[k], x, y, z
                    )
                    if d < phi[0, i, j, l]:
                        phi[1, i, j, l], link[1, i, j, l] = phi[0, i, j, l], link[0, i, j, l]
                        phi[0, i, j, l], link[0, i, j, l] = d, k
                    elif d < phi[1, i, j, l]:
                        phi[1, i, j, l], link[1, i, j, l] = d, k


@numba.njit(cache=True, nogil=True)
def _face_fractions_(phi, link, h, axis, weight, links, shares):
    """Every face normal to ``axis`` in the box, in place: its water fraction (0
    below ``WEIGHT_FLOOR``) and how its solid part splits between links
    (``links``, ``shares``: ``SLOTS`` per face, -1 and 0 where unused; the
    shares add up to one minus the water fraction)."""
    n0, n1, n2 = weight.shape
    base, count = np.empty(3, np.int64), np.empty(3, np.int64)
    for i in range(n0):
        for j in range(n1):
            for l in range(n2):
                links[i, j, l, :] = -1
                shares[i, j, l, :] = 0.0
                _volume(phi.shape[1:], axis, i, j, l, base, count)
                samples = count[0] * count[1] * count[2]
                for di in range(count[0]):
                    for dj in range(count[1]):
                        for dl in range(count[2]):
                            at = (base[0] + di, base[1] + dj, base[2] + dl)
                            solid = _ramp(phi[0][at], h) / samples
                            if solid == 0.0:
                                continue
                            split = _seam_split(phi[0][at], phi[1][at], link[1][at], h)
                            _add_share(links, shares, i, j, l, link[0][at], split * solid)
                            if split < 1.0:
                                _add_share(links, shares, i, j, l, link[1][at], (1 - split) * solid)
                solid = shares[i, j, l, :].sum()
                water = 1.0 - solid
                if water < WEIGHT_FLOOR:
                    water = 0.0
                    if solid > 0:
                        shares[i, j, l, :] /= solid
                weight[i, j, l] = water


@numba.njit(cache=True, nogil=True)
def _ramp(phi, h):
    """The solid share of a sample's box of ``h / 2`` a side, from its signed distance."""
    return min(max(0.5 - phi / (0.5 * h), 0.0), 1.0)


@numba.njit(cache=True, nogil=True)
def _seam_split(first, second, second_link, h):
    """The deepest link's part of a sample where the second is within ``SEAM`` cells."""
    gap = second - first
    if second_link < 0 or gap >= SEAM * h:
        return 1.0
    return 0.5 + 0.5 * gap / (SEAM * h)


@numba.njit(cache=True, nogil=True)
def _add_share(links, shares, i, j, l, k, amount):
    """Add ``amount`` of face (i, j, l)'s solid part to link ``k``."""
    largest = 0
    for slot in range(links.shape[3]):
        if links[i, j, l, slot] == k or links[i, j, l, slot] < 0:
            links[i, j, l, slot] = k
            shares[i, j, l, slot] += amount
            return
        if shares[i, j, l, slot] > shares[i, j, l, largest]:
            largest = slot
    shares[i, j, l, largest] += amount


@numba.njit(cache=True, nogil=True)
def _volume(samples, axis, i, j, l, base, count):
    """The samples of a control volume, in place: first index ``base`` and ``count`` per
    axis. Cell ``(i, j, l)`` of the box (``axis = -1``), or the face ``(i, j, l)``
    normal to ``axis``, whose volume starts half a cell lower along it."""
    index = (i, j, l)
    for b in range(3):
        flat = samples[b] == 1
        count[b] = 1 if flat else 2
        base[b] = 0 if flat else 2 * index[b] + (0 if b == axis else 1)


@numba.njit(cache=True, nogil=True)
def _cell_owners_(phi, link, h, owner, deepest):
    """Every cell's deepest link, and its owner: that link where more than half
    the cell is solid, else -1; in place (``phi``, ``link``: the deepest per sample)."""
    n0, n1, n2 = owner.shape
    base, count = np.empty(3, np.int64), np.empty(3, np.int64)
    for i in range(n0):
        for j in range(n1):
            for l in range(n2):
                _volume(phi.shape, -1, i, j, l, base, count)
                total, lowest, who = 0.0, np.inf, -1
                for di in range(count[0]):
                    for dj in range(count[1]):
                        for dl in range(count[2]):
                            at = (base[0] + di, base[1] + dj, base[2] + dl)
                            total += _ramp(phi[at], h)
                            if phi[at] < lowest:
                                lowest, who = phi[at], link[at]
                owner[i, j, l] = who if total > 0.5 * count[0] * count[1] * count[2] else -1
                deepest[i, j, l] = who


@numba.njit(cache=True, nogil=True)
def _coupled_sweep_(weight, link, share, water, first, a, index, at, links, shares):
    """Count the coupled faces' entries (face and link) normal to axis ``a``; fill the
    arrays too when they are long enough (``at``: the face's water fraction)."""
    fill = at.size > 0
    n0, n1, n2 = weight.shape
    count = 0
    for i in range(n0):
        for j in range(n1):
            for l in range(n2):
                if weight[i, j, l] >= 1.0:
                    continue
                above = (first[0] + i, first[1] + j, first[2] + l)
                below = (above[0] - int(a == 0), above[1] - int(a == 1), above[2] - int(a == 2))
                if not (_has_water(water, above) or _has_water(water, below)):
                    continue
                for slot in range(share.shape[3]):
                    if share[i, j, l, slot] <= 0.0:
                        continue
                    if fill:
                        index[count, 0], index[count, 1], index[count, 2] = above
                        at[count] = weight[i, j, l]
                        links[count] = link[i, j, l, slot]
                        shares[count] = share[i, j, l, slot]
                    count += 1
    return count


@numba.njit(cache=True, nogil=True)
def _has_water(water, cell):
    for b in range(3):
        if cell[b] < 0 or cell[b] >= water.shape[b]:
            return False
    return water[cell[0], cell[1], cell[2]]


def _seal_(water, weights, dim) -> None:
    """Close off water that cannot reach the box's border through open faces, in place."""
    reached = np.zeros(water.shape, bool)
    w = tuple(weights) + (np.zeros((1, 1, 1)),) * (3 - dim)
    _flood_open_(water, w[0], w[1], w[2], dim, reached)
    sealed = water & ~reached
    if not sealed.any():
        return
    water[sealed] = False
    for a in range(dim):  # faces of sealed cells close
        pad = [(0, 0)] * 3
        pad[a] = (0, 1)
        weights[a][np.pad(sealed, pad)] = 0.0
        pad[a] = (1, 0)
        weights[a][np.pad(sealed, pad)] = 0.0


@numba.njit(cache=True, nogil=True)
def _flood_open_(water, wx, wy, wz, dim, reached):
    """Mark the cells with water joined to the box's border through open faces."""
    nx, ny, nz = water.shape
    stack = np.empty((water.size, 3), dtype=np.int64)
    top = 0
    for i in range(nx):
        for j in range(ny):
            for l in range(nz):
                if not water[i, j, l]:
                    continue
                out = (i == 0 and wx[0, j, l] > 0) or (i == nx - 1 and wx[nx, j, l] > 0)
                out = out or (j == 0 and wy[i, 0, l] > 0) or (j == ny - 1 and wy[i, ny, l] > 0)
                if dim == 3:
                    out = out or (l == 0 and wz[i, j, 0] > 0) or (l == nz - 1 and wz[i, j, nz] > 0)
                if out:
                    reached[i, j, l] = True
                    stack[top, 0], stack[top, 1], stack[top, 2] = i, j, l
                    top += 1
    while top > 0:
        top -= 1
        i, j, l = stack[top, 0], stack[top, 1], stack[top, 2]
        for a in range(dim):
            for side in (0, 1):
                d = 2 * side - 1
                p, q, r = i + d * (a == 0), j + d * (a == 1), l + d * (a == 2)
                if not (0 <= p < nx and 0 <= q < ny and 0 <= r < nz):
                    continue
                if a == 0:
                    w = wx[i + side, j, l]
                elif a == 1:
                    w = wy[i, j + side, l]
                else:
                    w = wz[i, j, l + side]
                if w > 0 and water[p, q, r] and not reached[p, q, r]:
                    reached[p, q, r] = True
                    stack[top, 0], stack[top, 1], stack[top, 2] = p, q, r
                    top += 1
