"""Voxelize the links at a pose: solid cells, their owner links, the coupled faces (paper §3.3).

As docs/method-coupling.md, "The coupled step", says: a cell whose centre
lies inside a link is SOLID and remembers that link; a face between a FLUID
and a SOLID cell is a *coupled face*, with outward normal ``n_f = sign *
e_axis`` (from the solid cell into the fluid cell) and the solid cell's
owner. This runs every fluid step, so each link
tests only the cells inside its own world bounding box, against its
signed-distance grid baked once in its rest frame (``aquagait.body.shape``),
in serial Numba kernels.

Rules:

- Owner: a cell inside several links belongs to the one it is deepest in (the
  most negative sampled signed distance); an exact tie goes to the lowest link
  index.
- Pockets: fluid cells that cannot reach the grid border through fluid would
  make the pressure system singular (docs/method-coupling.md). They become
  solid and move with the body: each takes the owner of the nearest solid
  cell (a breadth-first search from the solid; ties in scan order).
- The grid border is open water: faces on it are never coupled faces.
- 2D: the planar body is cut at z = 0; its links turn about z only.

This is the *staircase* boundary: a face is open water or wall, nothing
between. ``aquagait.body.subcell`` gives the same ``Voxels`` with fractional
faces; the fluid model takes either function (``EulerFluid.boundary``).

The pose checks and the two sampling kernels (``cell_range``,
``link_distance``) serve ``aquagait.body.overlap`` and ``subcell`` too.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from aquagait.body.shape import BodyShape, body_shape
from aquagait.grid import Grid, flood_from_border_

__all__ = ["BodyShape", "Voxels", "body_shape", "voxelize"]


@dataclass(frozen=True, eq=False)
class Voxels:
    """The body on the grid at one pose: cells without water, and the coupled faces.

    A *coupled face* is a face, next to at least one cell with water, that is
    partly or wholly inside the body: its *fluid fraction* ``w`` is below 1.
    The staircase (``voxelize``) has ``w = 0`` on every coupled face, the faces
    between a solid and a fluid cell; the sub-cell boundary
    (``aquagait.body.subcell``) has fractions between. ``m`` is the number of
    coupled faces, ``dim`` the grid's dimension.

    Attributes:
        solid: ``grid.shape`` bool, a cell with no water (no pressure
            unknown): inside the body, or a sealed fluid pocket.
        owner: ``grid.shape`` int32, the link a cell mostly belongs to (its
            centre is inside it), -1 for water. Every solid cell has one.
        face_axis: (m,) int64, the axis ``a`` a coupled face is normal to.
        face_index: (m, dim) int64, its index into ``velocity[a]`` (shape
            ``grid.face_shape(a)``), between cells ``index - e_a`` and ``index``.
        face_weight: (m,) float64, its fluid fraction ``w`` in [0, 1).
        face_link: (m,) int64, the link whose surface the face cuts.
        face_center: (m, 3) world position of the face centre [m] (z = 0 in 2D).
        face_share: (m,) float64, the share of the face's control volume that
            is this link. A face where links meet is listed once per link,
            in rows next to each other; its shares add up to ``1 - w``
            (staircase: one link, share 1).
    """

    solid: np.ndarray
    owner: np.ndarray
    face_axis: np.ndarray
    face_index: np.ndarray
    face_weight: np.ndarray
    face_link: np.ndarray
    face_center: np.ndarray
    face_share: np.ndarray

    @property
    def face_count(self) -> int:
        """``m``, the number of coupled faces (a face counts once per link it cuts)."""
        return int(self.face_axis.shape[0])

    def first_entries(self) -> np.ndarray:
        """The rows that list each coupled face first: one row per face (none without faces)."""
        key = np.column_stack([self.face_axis, self.face_index])
        first = np.r_[True, np.any(key[1:] != key[:-1], axis=1)][: len(key)]
        return np.flatnonzero(first)

    def sides(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The cells with water on either side of every coupled face.

        Returns:
            ``(face, cell, sign)``, one entry per coupled face and neighbour
            cell that is in the grid and not solid (the cells below every
            face first, then those above): the face's row (e,), the
            cell (e, dim), and the sign of the normal ``n = sign * e_a`` that
            points from the face's solid part into that cell (+1: the cell
            above the face, ``index``; -1: the cell below, ``index - e_a``).
        """
        water = ~self.solid
        faces, cells, signs = [], [], []
        for sign, cell in zip((-1.0, 1.0), self.face_cells(), strict=True):
            keep = np.flatnonzero(marked(water, cell, outside=False))
            faces.append(keep)
            cells.append(cell[keep])
            signs.append(np.full(len(keep), sign))
        return np.concatenate(faces), np.concatenate(cells), np.concatenate(signs)

    def face_cells(self) -> tuple[np.ndarray, np.ndarray]:
        """The cells below (``index - e_a``) and above (``index``) every coupled face,
        (m, dim) each; either may lie outside the grid (the open border)."""
        step = np.eye(self.solid.ndim, dtype=np.int64)[self.face_axis]
        return self.face_index - step, self.face_index


def marked(mask: np.ndarray, cells: np.ndarray, outside: bool) -> np.ndarray:
    """Whether each of ``cells`` (n, dim) is True in ``mask``; a cell outside the grid
    counts as ``outside``."""
    inside = np.all((cells >= 0) & (cells < mask.shape), axis=1)
    out = np.full(len(cells), outside)
    out[inside] = mask[tuple(cells[inside].T)]
    return out


def voxelize(shape: BodyShape, grid: Grid, link_pos, link_rot) -> Voxels:
    """Solid cells, owners and coupled faces of the links at one pose (paper §3.3).

    Args:
        shape: the links' baked geometry (``body_shape(model, grid.cell_size)``).
        grid: the MAC grid, of the model's dimension.
        link_pos: (nl, 3) world origins of the links [m].
        link_rot: (nl, 3, 3) world rotations of the links (both from
            ``Dynamics.link_poses(q)``).
    Returns:
        the ``Voxels``.
    Raises:
        ValueError: malformed poses, a 2D pose that leaves the x-y plane, a grid
            of the wrong dimension or finer than the shape resolves.
    """
    check_grid(shape, grid)
    pos, rot = checked_pose(shape, link_pos, link_rot)
    owner = np.full(as_3d(grid.shape), -1, dtype=np.int32)
    box = np.empty(6, dtype=np.int64)
    origin, h = origin_3d(grid.origin, grid.cell_size), grid.cell_size
    best = np.full(owner.shape, np.inf, dtype=np.float32)
    _paint_owners_(*baked_arrays(shape), rot, pos, origin, h, owner, best, box)
    _seal_pockets_(owner, box)
    axis, index, link = _coupled_faces(owner, box)
    dim = grid.dim
    centre = origin + (index + 0.5) * h
    centre[np.arange(axis.size), axis] -= 0.5 * h
    if dim == 2:
        centre[:, 2] = 0.0
    owner = owner.reshape(grid.shape)
    return Voxels(
        solid=owner >= 0,
        owner=owner,
        face_axis=axis,
        face_index=index[:, :dim],
        face_weight=np.zeros(axis.size),
        face_link=link,
        face_center=centre,
        face_share=np.ones(axis.size),
    )


# --- checks and small geometry --------------------------------------------------


def check_grid(shape: BodyShape, grid: Grid) -> None:
    """Refuse a grid of the wrong dimension, or finer than the shape's samples resolve."""
    if grid.dim != shape.dim:
        raise ValueError(
            f"the grid is {grid.dim}D but the body is {shape.dim}D: give a grid of {shape.dim} axes"
        )
    if grid.cell_size < 2 * shape.spacing:
        raise ValueError(
            f"the body shape samples every {shape.spacing:.3g} m, too coarse for cells of "
            f"{grid.cell_size:.3g} m: rebuild it with body_shape(model, grid.cell_size)"
        )


def checked_pose(shape: BodyShape, link_pos, link_rot) -> tuple[np.ndarray, np.ndarray]:
    """Checked link origins (nl, 3) and rest-frame-to-world rotations (nl, 3, 3)."""
    nl = shape.nlinks
    pos = np.ascontiguousarray(link_pos, dtype=float)
    rot = np.asarray(link_rot, dtype=float)
    source = "e.g. from Dynamics.link_poses(q)"
    if pos.shape != (nl, 3):
        raise ValueError(f"link_pos has shape {pos.shape}; this body needs ({nl}, 3), {source}")
    if rot.shape != (nl, 3, 3):
        raise ValueError(f"link_rot has shape {rot.shape}; this body needs ({nl}, 3, 3), {source}")
    if not (np.isfinite(pos).all() and np.isfinite(rot).all()):
        raise ValueError("link_pos and link_rot must be finite")
    if np.abs(np.einsum("kji,kjl->kil", rot, rot) - np.eye(3)).max() > 1e-6:
        raise ValueError("link_rot must hold rotation matrices (orthonormal, 3x3 per link)")
    world = np.ascontiguousarray(np.einsum("kij,klj->kil", rot, shape.rest_rot))
    if shape.dim == 2 and np.abs(world[:, 2, 2] - 1).max() > 1e-6:
        raise ValueError(
            "a planar (2D) body's links turn about z only, but link_rot tilts a link out of "
            "the x-y plane"
        )
    return pos, world


def baked_arrays(shape: BodyShape) -> tuple:
    """The shape's arrays in the order the kernels take them."""
    return shape.sdf, shape.offset, shape.dims, shape.lower, shape.spacing


def as_3d(shape: tuple[int, ...]) -> tuple[int, int, int]:
    return tuple(shape) + (1,) * (3 - len(shape))


def origin_3d(origin, h: float) -> np.ndarray:
    """Grid origin in 3D; a 2D grid gets one layer of cells centred on z = 0."""
    return np.array(tuple(origin) + (-h / 2,) * (3 - len(origin)))


# --- kernels ------------------------------------------------------------------


@numba.njit(cache=True, nogil=True)
def link_world_box(dims, lower, spacing, rot, pos):
    """World box (lo, hi) of a link's signed-distance grid at its pose [m]."""
    lo = np.full(3, np.inf)
    hi = np.full(3, -np.inf)
    for corner in range(8):
        b = np.empty(3)
        for a in range(3):
            b[a] = lower[a] + ((corner >> a) & 1) * (dims[a] - 1) * spacing
        for a in range(3):
            w = pos[a] + rot[a, 0] * b[0] + rot[a, 1] * b[1] + rot[a, 2] * b[2]
            lo[a] = min(lo[a], w)
            hi[a] = max(hi[a], w)
    return lo, hi


@numba.njit(cache=True, nogil=True)
def cell_range(dims, lower, spacing, rot, pos, origin, h, shape, out):
    """Cells (out[a] = first, last) whose centres lie in the world box of a link's grid."""
    lo, hi = link_world_box(dims, lower, spacing, rot, pos)
    for a in range(3):
        if shape[a] == 1:  # the single layer of a 2D grid
            out[a, 0], out[a, 1] = 0, 0
            continue
        first = np.ceil((lo[a] - origin[a]) / h - 0.5)
        last = np.floor((hi[a] - origin[a]) / h - 0.5)
        out[a, 0] = int(min(max(first, 0.0), shape[a]))  # clipped before int: no overflow
        out[a, 1] = int(min(max(last, -1.0), shape[a] - 1))


@numba.njit(cache=True, nogil=True)
def link_distance(sdf, base, dims, lower, spacing, rot, pos, x, y, z):
    """Interpolated signed distance of one link at a world point [m]; +inf off its grid.

    Trilinear; bilinear when the grid has one z layer (2D).
    """
    dx, dy, dz = x - pos[0], y - pos[1], z - pos[2]
    u = (rot[0, 0] * dx + rot[1, 0] * dy + rot[2, 0] * dz - lower[0]) / spacing
    v = (rot[0, 1] * dx + rot[1, 1] * dy + rot[2, 1] * dz - lower[1]) / spacing
    n0, n1, n2 = dims[0], dims[1], dims[2]
    if u < 0 or v < 0 or u > n0 - 1 or v > n1 - 1:
        return np.inf
    i, j = min(int(u), n0 - 2), min(int(v), n1 - 2)
    fu, fv = u - i, v - j
    if n2 == 1:
        at = base + i * n1 + j
        low = sdf[at] * (1 - fv) + sdf[at + 1] * fv
        high = sdf[at + n1] * (1 - fv) + sdf[at + n1 + 1] * fv
        return low * (1 - fu) + high * fu
    w = (rot[0, 2] * dx + rot[1, 2] * dy + rot[2, 2] * dz - lower[2]) / spacing
    if w < 0 or w > n2 - 1:
        return np.inf
    l = min(int(w), n2 - 2)
    fw = w - l
    total = 0.0
    for di in range(2):
        for dj in range(2):
            at = base + ((i + di) * n1 + j + dj) * n2 + l
            weight = (fu if di else 1 - fu) * (fv if dj else 1 - fv)
            total += weight * (sdf[at] * (1 - fw) + sdf[at + 1] * fw)
    return total


@numba.njit(cache=True, nogil=True)
def _paint_owners_(sdf, offset, dims, lower, spacing, rot, pos, origin, h, owner, best, box):
    """Mark cells inside links with the deepest link, in place; box = solid bounds (lo, hi)."""
    nx, ny, nz = owner.shape
    box[0], box[1], box[2] = nx, ny, nz
    box[3], box[4], box[5] = -1, -1, -1
    span = np.empty((3, 2), dtype=np.int64)
    for k in range(dims.shape[0]):
        if dims[k, 0] == 0:
            continue
        cell_range(dims[k], lower[k], spacing, rot[k], pos[k], origin, h, owner.shape, span)
        for i in range(span[0, 0], span[0, 1] + 1):
            x = origin[0] + (i + 0.5) * h
            for j in range(span[1, 0], span[1, 1] + 1):
                y = origin[1] + (j + 0.5) * h
                for l in range(span[2, 0], span[2, 1] + 1):
                    z = origin[2] + (l + 0.5) * h
                    phi = link_distance(
                        sdf, offset[k], dims[k], lower[k], spacing, rot[k], pos[k], x, y, z
                    )
                    if phi < 0 and phi < best[i, j, l]:
                        best[i, j, l] = phi
                        owner[i, j, l] = k
                        box[0], box[3] = min(box[0], i), max(box[3], i)
                        box[1], box[4] = min(box[1], j), max(box[4], j)
                        box[2], box[5] = min(box[2], l), max(box[5], l)


@numba.njit(cache=True, nogil=True)
def _expanded(box, shape, a):
    """The solid bounds along axis ``a`` grown by one cell, clipped to the grid."""
    return max(box[a] - 1, 0), min(box[3 + a] + 1, shape[a] - 1)


@numba.njit(cache=True)
def _seal_pockets_(owner, box):
    """Turn fluid cells that cannot reach the border into solid, owned by the nearest solid.

    Only the solid's bounding box grown by one cell is searched: every cell
    outside the solid's box reaches the border in a straight line, so the
    grown box's outer layer is open water (or the grid border itself). In 3D
    the grown box has at least two layers along z (a grid has two cells or
    more per axis), so only a 2D grid's box is a single layer.
    """
    if box[3] < 0:
        return 0
    shape = owner.shape
    i0, i1 = _expanded(box, shape, 0)
    j0, j1 = _expanded(box, shape, 1)
    l0, l1 = _expanded(box, shape, 2)
    solid = np.empty((i1 - i0 + 1, j1 - j0 + 1, l1 - l0 + 1), dtype=np.bool_)
    for i in range(i0, i1 + 1):
        for j in range(j0, j1 + 1):
            for l in range(l0, l1 + 1):
                solid[i - i0, j - j0, l - l0] = owner[i, j, l] >= 0
    reached = np.zeros(solid.shape, dtype=np.bool_)
    flood_from_border_(solid, reached)
    pockets = 0
    for i in range(i0, i1 + 1):
        for j in range(j0, j1 + 1):
            for l in range(l0, l1 + 1):
                if not (solid[i - i0, j - j0, l - l0] or reached[i - i0, j - j0, l - l0]):
                    owner[i, j, l] = -2
                    pockets += 1
    if pockets:
        own_pockets_(owner, pockets, i0, i1, j0, j1, l0, l1)
    return pockets


@numba.njit(cache=True)
def own_pockets_(owner, pockets, i0, i1, j0, j1, l0, l1):
    """Give cells marked -2 the owner of the nearest solid cell, breadth first."""
    nx, ny, nz = owner.shape
    steps = ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1))
    queue = np.empty((pockets, 3), dtype=np.int64)
    found = np.empty(pockets, dtype=np.int32)
    tail = 0
    for i in range(i0, i1 + 1):  # first layer: pockets touching the solid
        for j in range(j0, j1 + 1):
            for l in range(l0, l1 + 1):
                if owner[i, j, l] != -2:
                    continue
                for di, dj, dl in steps:
                    a, b, c = i + di, j + dj, l + dl
                    if 0 <= a < nx and 0 <= b < ny and 0 <= c < nz and owner[a, b, c] >= 0:
                        queue[tail, 0], queue[tail, 1], queue[tail, 2] = i, j, l
                        found[tail] = owner[a, b, c]
                        tail += 1
                        break
    for n in range(tail):
        owner[queue[n, 0], queue[n, 1], queue[n, 2]] = found[n]
    head = 0
    while head < tail:
        i, j, l = queue[head, 0], queue[head, 1], queue[head, 2]
        head += 1
        for di, dj, dl in steps:
            a, b, c = i + di, j + dj, l + dl
            if 0 <= a < nx and 0 <= b < ny and 0 <= c < nz and owner[a, b, c] == -2:
                owner[a, b, c] = owner[i, j, l]
                queue[tail, 0], queue[tail, 1], queue[tail, 2] = a, b, c
                tail += 1


@numba.njit(cache=True, nogil=True)
def _coupled_faces(owner, box):
    """Faces between a fluid and a solid cell: axis, face index, the solid cell's link."""
    none, rows = np.empty(0, dtype=np.int64), np.empty((0, 3), dtype=np.int64)
    count = _face_sweep_(owner, box, none, rows, none)
    axis = np.empty(count, dtype=np.int64)
    index = np.empty((count, 3), dtype=np.int64)
    link = np.empty(count, dtype=np.int64)
    _face_sweep_(owner, box, axis, index, link)
    return axis, index, link


@numba.njit(cache=True, nogil=True)
def _face_sweep_(owner, box, axis, index, link):
    """Count the coupled faces; fill the arrays too when they are long enough."""
    if box[3] < 0:
        return 0
    shape = owner.shape
    fill = axis.size > 0
    i0, i1 = _expanded(box, shape, 0)
    j0, j1 = _expanded(box, shape, 1)
    l0, l1 = _expanded(box, shape, 2)
    count = 0
    for a in range(3):
        if shape[a] == 1:
            continue
        di, dj, dl = int(a == 0), int(a == 1), int(a == 2)
        for i in range(i0, i1 + 1 - di):
            for j in range(j0, j1 + 1 - dj):
                for l in range(l0, l1 + 1 - dl):
                    low, high = owner[i, j, l], owner[i + di, j + dj, l + dl]
                    if (low >= 0) == (high >= 0):
                        continue
                    if fill:  # the face between two cells has the upper cell's index
                        axis[count] = a
                        index[count, 0], index[count, 1], index[count, 2] = i + di, j + dj, l + dl
                        link[count] = low if low >= 0 else high
                    count += 1
    return count
