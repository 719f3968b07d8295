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

MARGIN = 2
"""Cells added around the links' boxes: a partly covered cell, and a layer of open water."""


def voxelize_subcell(shape: BodyShape, grid: Grid, link_pos, link_rot) -> Voxels:
    """Cells without water, owners and coupled faces with their water fractions (module docstring).

    Args:
        shape: the links' baked geometry (``body_shape(model, grid.cell_size)``).
        grid: the MAC grid, of the model's dimension.
        link_pos: (nl, 3) world origins of the links [m].
        link_rot: (nl, 3, 3) world rotations of the links.
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
    samples = tuple(2 * n + 2 if size > 1 else 1 for n, size in zip(count, cells, strict=True))
    phi = np.full(samples, np.inf)
    link = np.full(samples, -1, dtype=np.int32)
    _sample_(*baked, rot, pos, origin, h, first, phi, link)
    axes = range(grid.dim)
    step = np.eye(3, dtype=np.int64)
    weights = [np.empty(tuple(count + step[a])) for a in axes]
    links = [np.empty(tuple(count + step[a]), dtype=np.int32) for a in axes]
    for a in axes:
        _face_fractions_(phi, link, h, a, weights[a], links[a])
    inside = owner[tuple(slice(f, f + n) for f, n in zip(first, count, strict=True))]
    deepest = np.empty(tuple(count), dtype=np.int32)
    _cell_owners_(phi, link, h, inside, deepest)
    water = np.ones(cells, bool)
    local_water = _open_cells(weights, tuple(count))
    _seal_(local_water, weights, grid.dim)
    water[tuple(slice(f, f + n) for f, n in zip(first, count, strict=True))] = local_water
    _own_sealed(owner, inside, deepest, local_water, first, count)
    faces = []
    for a in axes:
        faces.append(_coupled(weights[a], links[a], water, first, a))
    return _voxels(grid, owner, water, faces)


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


def _coupled(weight, link, water, first, a):
    """The coupled faces normal to axis ``a``: partly solid, next to a cell with water."""
    local = np.argwhere(weight < 1)
    index = local + first
    below, above = index - np.eye(3, dtype=np.int64)[a], index
    touches = np.zeros(len(index), bool)
    for cell in (below, above):
        inside = np.all((cell >= 0) & (cell < water.shape), axis=1)
        touches[inside] |= water[tuple(cell[inside].T)]
    local, index = local[touches], index[touches]
    return (np.full(len(index), a), index, weight[tuple(local.T)], link[tuple(local.T)])


def _voxels(grid: Grid, owner, water, faces) -> Voxels:
    dim, h = grid.dim, grid.cell_size
    if faces:
        axis, index, weight, link = (np.concatenate(parts) for parts in zip(*faces, strict=True))
    else:
        axis, index = np.zeros(0, np.int64), np.zeros((0, 3), np.int64)
        weight, link = np.zeros(0), np.zeros(0, np.int64)
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
    """Deepest signed distance and its link at every lattice point, in place.

    Lattice point ``m`` along a real axis sits at ``(first + m / 2 - 1 / 4) h``
    from the origin (in grid index terms, ``n = 2 first - 1 + m``); a 2D
    grid's single layer is sampled at z = 0.
    """
    shape = phi.shape
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
                    if d < phi[i, j, l]:
                        phi[i, j, l] = d
                        link[i, j, l] = k


@numba.njit(cache=True, nogil=True)
def _face_fractions_(phi, link, h, axis, weight, deepest):
    """Water fraction (0 below ``WEIGHT_FLOOR``) and deepest link of every face
    normal to ``axis`` in the box, in place."""
    n0, n1, n2 = weight.shape
    for i in range(n0):
        for j in range(n1):
            for l in range(n2):
                solid, who = _solid_share(phi, link, h, axis, i, j, l)
                water = 1.0 - solid
                weight[i, j, l] = water if water >= WEIGHT_FLOOR else 0.0
                deepest[i, j, l] = who


@numba.njit(cache=True, nogil=True)
def _cell_owners_(phi, link, h, owner, deepest):
    """Every cell's deepest link, and its owner: that link where more than half
    the cell is solid, else -1; in place."""
    n0, n1, n2 = owner.shape
    for i in range(n0):
        for j in range(n1):
            for l in range(n2):
                solid, who = _solid_share(phi, link, h, -1, i, j, l)
                owner[i, j, l] = who if solid > 0.5 else -1
                deepest[i, j, l] = who


@numba.njit(cache=True, nogil=True)
def _solid_share(phi, link, h, axis, i, j, l):
    """Solid share of a control volume and the link of its deepest sample.

    The volume is cell ``(i, j, l)`` of the box (``axis = -1``) or the face
    ``(i, j, l)`` normal to ``axis``, whose volume starts half a cell lower
    along it. Each of its 2^dim samples counts ``clip(1/2 - phi / (h/2), 0, 1)``.
    """
    index = (i, j, l)
    base = np.empty(3, dtype=np.int64)
    count = np.empty(3, dtype=np.int64)
    for b in range(3):
        flat = phi.shape[b] == 1
        count[b] = 1 if flat else 2
        base[b] = 0 if flat else 2 * index[b] + (0 if b == axis else 1)
    total, lowest, who = 0.0, np.inf, -1
    for di in range(count[0]):
        for dj in range(count[1]):
            for dl in range(count[2]):
                p = phi[base[0] + di, base[1] + dj, base[2] + dl]
                total += min(max(0.5 - p / (0.5 * h), 0.0), 1.0)
                if p < lowest:
                    lowest, who = p, link[base[0] + di, base[1] + dj, base[2] + dl]
    return total / (count[0] * count[1] * count[2]), who


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
