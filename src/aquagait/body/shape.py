"""Link shapes as signed-distance grids, baked once per model and cell size.

``voxelize`` asks, every fluid step (docs/method-coupling.md, "The coupled
step"), "is this cell centre inside link k, and how deep?". Answering from
the geoms themselves would mean a branch per geom type and, for a mesh, a
loop over its triangles at every cell. Instead each
link's geometry is sampled once, here, as a signed distance ``phi`` (negative
inside, [m]) on a regular grid of spacing ``s = h / refine`` in the link's
*rest frame*: the link's origin with the world axes at the reference pose
``qpos0``. The rest frame is fixed to the link, so at pose ``(pos, rot)`` a
rest-frame point ``b`` sits at ``pos + rot @ rest_rot.T @ b``. Sampling it is
then one trilinear (2D: bilinear) interpolation per cell, whatever the geoms.

How each geom is sampled (the union of a link's geoms is the minimum of theirs):

- sphere, capsule, box, cylinder: exact signed distance; ellipsoid: the usual
  first-order estimate ``k0 (k0 - 1) / k1`` (``k0 = |p / r|``,
  ``k1 = |p / r^2|``), exact in sign and on the surface, and inside held to
  no deeper than the least semi-axis (deep inside a flat ellipsoid the
  estimate reaches the longest one, so a 2 mm fin measured 32 mm thick).
- mesh: exact distance to the nearest triangle, signed by the generalized
  winding number (the solid angle the triangles subtend, over 4 pi): a point
  is inside when it exceeds 1/2. This holds for non-convex closed meshes too,
  so the volume the fluid sees is the mesh's own, the one MuJoCo's mass uses
  (a mesh given by vertices only is its convex hull, for MuJoCo and here).
  Cost: samples x triangles, once (milliseconds for the library creatures,
  seconds for meshes of many thousand triangles).
- 2D (a planar model, every geom a z-prism): the cross-section at z = 0, as a
  2D signed distance: a box is its rectangle, a cylinder its disc, a mesh the
  polygon where its triangles cut z = 0 (winding number of the cut segments).

Error: the interpolated zero level set is exact on flat faces away from
edges, within ``s^2 / (4 R)`` of a curved surface of radius ``R`` (``s^2 / 8``
times the trace of the distance's Hessian, ``(d - 1) / R``), and within about
``s / 2`` of a mesh's or box's edges and corners, where the exact distance is
not smooth. With the default ``s = h / 4`` that is well inside the ``+-h/2``
staircase error of voxelizing at cell centres. Samples are stored as float32
(about 1e-8 m of rounding for a body of 10 cm).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from aquagait.body.dynamics import describe, mesh_faces

REFINE = 4
"""Signed-distance samples per fluid cell along each axis, for parts at least
``THIN_SAMPLES`` of them thick."""

THIN_SAMPLES = 1.5
"""The fewest samples across the thinnest geom: a thinner one doubles the samples
per cell (up to ``MAX_REFINE``). Interpolated between samples, a plate thinner
than about that, tilted against the samples' axes, is not negative everywhere
along its mid-plane, and the closure of thin parts (``aquagait.body.thin``)
could not find where water would cross it: a plate a fifth of a cell thick let
water through at 2 of 20 random poses at 4 samples a cell, at none at 8."""

MAX_REFINE = 16
"""Most signed-distance samples per cell ``body_shape`` picks by itself."""

PAD = 2
"""Samples of margin around each link's geoms, so interpolation near the surface sees outside."""

MAX_SAMPLES = 20_000_000
"""Most samples one link may need; beyond it the cell size is far too small for the link."""


@dataclass(frozen=True, eq=False)
class BodyShape:
    """Every link's geometry as a signed-distance grid in its rest frame (fixed; picklable).

    Built once per model and cell size by ``body_shape`` and shipped with the
    scene to workers. Link ``k``'s samples are
    ``sdf[offset[k]:offset[k + 1]].reshape(dims[k])``; sample ``(i, j, l)`` sits
    at rest-frame position ``lower[k] + (i, j, l) * spacing``.

    Attributes:
        dim: 2 (planar prisms, sampled at z = 0) or 3.
        depth: prism depth [m] in 2D, None in 3D.
        cell_size: the fluid cell size ``h`` the shape was built for [m].
        spacing: ``s``, distance between samples [m].
        links: (nl,) link names.
        parent: (nl,) parent link index, -1 for the root.
        rest_rot: (nl, 3, 3) world rotation of each link at ``qpos0``; a link at
            world rotation ``rot`` carries its rest frame to ``rot @ rest_rot.T``.
        sdf: (total,) float32 signed distance, negative inside [m].
        offset: (nl + 1,) int64 start of each link's samples in ``sdf``.
        dims: (nl, 3) int64 samples per axis, ``(n0, n1, 1)`` in 2D, zeros for
            a link without geoms.
        lower: (nl, 3) rest-frame position of each link's first sample [m].
        bounds: (nl, 2, 3) lower and upper corners of each link's geoms' box
            in its rest frame [m] (zeros for a link without geoms).
    """

    dim: int
    depth: float | None
    cell_size: float
    spacing: float
    links: tuple[str, ...]
    parent: np.ndarray
    rest_rot: np.ndarray
    sdf: np.ndarray
    offset: np.ndarray
    dims: np.ndarray
    lower: np.ndarray
    bounds: np.ndarray

    @property
    def nlinks(self) -> int:
        return len(self.links)

    def link_sdf(self, k: int) -> np.ndarray:
        """Link ``k``'s samples as a ``dims[k]`` array (a view) [m]."""
        return self.sdf[self.offset[k] : self.offset[k + 1]].reshape(self.dims[k])


def body_shape(model, cell_size: float, refine: int | None = None) -> BodyShape:
    """Bake every link's geoms into a signed-distance grid in its rest frame.

    Args:
        model: a checked ``aquagait.body.Model`` (2D or 3D).
        cell_size: the fluid cell size ``h`` [m].
        refine: samples per cell along each axis; the spacing is ``h / refine``.
            None: ``REFINE``, doubled while the thinnest geom is less than
            ``THIN_SAMPLES`` samples thick (``auto_refine``).
    Returns:
        the ``BodyShape``.
    Raises:
        ValueError: a non-positive cell size or refinement, or a link so large
            against ``h / refine`` that its grid would exceed ``MAX_SAMPLES``.
    """
    if not np.isfinite(cell_size) or cell_size <= 0:
        raise ValueError(f"cell_size must be a positive length in metres, got {cell_size!r}")
    facts, faces = describe(model.mj), mesh_faces(model.mj)
    link_geoms = [np.flatnonzero(facts.geom_link == k) for k in range(len(facts.link_names))]
    bounds = [_link_bounds(facts, geoms, k) for k, geoms in enumerate(link_geoms)]
    if refine is None:
        refine = auto_refine(geom_thickness(facts, model.dim), cell_size)
        while (
            refine > REFINE and _most_samples(bounds, cell_size / refine, model.dim) > MAX_SAMPLES
        ):
            refine //= 2
    if int(refine) != refine or refine < 1:
        raise ValueError(f"refine must be a whole number of samples per cell >= 1, got {refine!r}")
    spacing = float(cell_size) / int(refine)
    grids, lowers = [], []
    for k, name in enumerate(facts.link_names):
        phi, lower = _bake_link(facts, faces, link_geoms[k], k, bounds[k], spacing, model.dim)
        if phi.size > MAX_SAMPLES:
            raise ValueError(
                f"{model.source}: link {name!r} needs {phi.size} signed-distance samples at "
                f"spacing {spacing:.3g} m (more than {MAX_SAMPLES}); use a larger cell size "
                "or a smaller refine"
            )
        grids.append(phi)
        lowers.append(lower)
    sizes = [g.size for g in grids]
    return BodyShape(
        dim=model.dim,
        depth=model.depth,
        cell_size=float(cell_size),
        spacing=spacing,
        links=tuple(facts.link_names),
        parent=np.asarray(facts.parent, dtype=np.int64),
        rest_rot=facts.link_rot.copy(),
        sdf=np.concatenate([g.ravel() for g in grids]).astype(np.float32),
        offset=np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64),
        dims=np.array([g.shape for g in grids], dtype=np.int64).reshape(-1, 3),
        lower=np.array(lowers, dtype=float).reshape(-1, 3),
        bounds=np.array(bounds, dtype=float).reshape(-1, 2, 3),
    )


def _most_samples(bounds, spacing: float, dim: int) -> int:
    """The most samples any link's grid would hold at ``spacing`` (as ``_bake_link``)."""
    counts = [_sample_counts(b, spacing, dim).prod() for b in bounds]
    return int(max(counts, default=0))


def _sample_counts(bounds, spacing: float, dim: int) -> np.ndarray:
    """(3,) samples per axis of a link's grid: its box and ``PAD`` samples a side."""
    half = np.ceil(0.5 * (bounds[1] - bounds[0]) / spacing + PAD - 1e-9).astype(int)
    counts = 2 * half + 1
    if dim == 2:
        counts[2] = 1
    return counts


def auto_refine(thickness: np.ndarray, cell_size: float) -> int:
    """Samples per cell: ``REFINE``, doubled while the thinnest of ``thickness`` [m] is
    less than ``THIN_SAMPLES`` samples across, at most ``MAX_REFINE``."""
    thinnest = float(np.min(thickness, initial=np.inf))
    refine = REFINE
    while refine < MAX_REFINE and thinnest < THIN_SAMPLES * cell_size / refine:
        refine *= 2
    return refine


def geom_thickness(facts, dim: int) -> np.ndarray:
    """Each geom's least extent [m], (ng,): in 2D across its outline in the plane.

    A box's or ellipsoid's shortest axis, a sphere's, capsule's or cylinder's
    diameter (or a cylinder's length, if shorter), a mesh's extent along the
    direction its vertices spread least (a flat fin's thickness).
    """
    out = np.empty(len(facts.geom_kind))
    for g, kind in enumerate(facts.geom_kind):
        size = facts.geom_size[g]
        if kind == "mesh":
            points = np.asarray(facts.geom_vertices[g], dtype=float)
            points = points[:, :2] if dim == 2 else points
            centred = points - points.mean(axis=0)
            axes = np.linalg.svd(centred, full_matrices=False)[2]
            out[g] = np.ptp(centred @ axes.T, axis=0).min()
        elif kind in ("box", "ellipsoid"):
            out[g] = 2 * (size[:2] if dim == 2 else size).min()
        elif kind == "cylinder" and dim == 3:
            out[g] = 2 * min(size[0], size[1])
        else:  # sphere, capsule, a 2D cylinder's disc
            out[g] = 2 * size[0]
    return out


def _link_bounds(facts, geoms, k) -> np.ndarray:
    """(2, 3) box of a link's geoms in its rest frame [m] (zeros without geoms)."""
    if geoms.size == 0:
        return np.zeros((2, 3))
    origin = facts.link_pos[k]
    return (
        np.stack([facts.geom_box[geoms, 0].min(axis=0), facts.geom_box[geoms, 1].max(axis=0)])
        - origin
    )


def world_bounds(shape: BodyShape, link_pos, link_rot) -> np.ndarray:
    """A world box holding every link's geoms at a pose: (2, 3) lower and upper corners [m].

    Each link's rest-frame box of geoms (``bounds``) is turned with the link,
    so the result holds the body wherever it is; at the reference pose it is
    the model's own ``bounds``. In 2D the z extent is zero.

    Args:
        shape: the baked geometry.
        link_pos: (nl, 3) world origins of the links [m].
        link_rot: (nl, 3, 3) world rotations of the links.
    """
    world = link_box_corners(shape, link_pos, link_rot)[0].reshape(-1, 3)
    return np.stack([world.min(axis=0), world.max(axis=0)])


def link_box_corners(shape: BodyShape, link_pos, link_rot) -> tuple[np.ndarray, np.ndarray]:
    """The world corners of each link's rest-frame box of geoms at a pose (``world_bounds``):
    (n, 8, 3) [m] for the n links that have geoms, and those links' indices (n,)."""
    links = np.flatnonzero(shape.dims[:, 0] > 0)
    lo, hi = shape.bounds[links, 0], shape.bounds[links, 1]
    if shape.dim == 2:
        lo, hi = lo * [1, 1, 0], hi * [1, 1, 0]  # the cross-section at z = 0
    turn = np.asarray(link_rot)[links] @ np.swapaxes(shape.rest_rot[links], 1, 2)
    return box_corners(lo, hi, np.asarray(link_pos)[links], turn), links


def turned_boxes(lo, hi, pos, turn) -> np.ndarray:
    """The world box, (2, 3) lower and upper corners [m], holding n boxes turned and placed
    (arguments as ``box_corners``)."""
    world = box_corners(lo, hi, pos, turn).reshape(-1, 3)
    return np.stack([world.min(axis=0), world.max(axis=0)])


def box_corners(lo, hi, pos, turn) -> np.ndarray:
    """The world corners of n boxes turned and placed, (n, 8, 3) [m].

    Args:
        lo, hi: (n, 3) corners of each box in its own frame [m].
        pos: (n, 3) world position of each frame's origin [m].
        turn: (n, 3, 3) rotation from each frame to the world.
    """
    corners = np.stack(
        [np.where(np.array(c, bool), hi, lo) for c in np.ndindex(2, 2, 2)], axis=1
    )  # (n, 8, 3)
    return pos[:, None, :] + np.einsum("kij,kcj->kci", turn, corners)


def _bake_link(facts, faces, geoms, k, bounds, spacing, dim):
    """Signed distance of one link's geoms on its rest-frame sample grid, and its corner.

    ``bounds``: (2, 3) the geoms' box in the link's rest frame (``_link_bounds``) [m].
    """
    if geoms.size == 0:
        return np.zeros((0, 0, 0)), np.zeros(3)
    origin = facts.link_pos[k]
    counts = _sample_counts(bounds, spacing, dim)
    half = (counts - 1) // 2
    # centred on the box, a sample in its middle: a link symmetric about a plane through
    # its box's middle is sampled symmetrically, its mid-plane too (the lattice from the
    # lower corner overhung the upper one by up to a spacing: the fish's face fractions
    # differed by 0.4% top to bottom, and over 20 s it pitched 14 degrees)
    lo = 0.5 * (bounds[0] + bounds[1]) - half * spacing
    if dim == 2:
        lo[2] = 0.0  # the cross-section at z = 0
    axes = [lo[a] + spacing * np.arange(counts[a]) for a in range(3)]
    points = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    phi = np.full(points.shape[0], np.inf)
    for g in geoms:
        centre = facts.geom_pos[g] - origin  # rest frame = world axes at qpos0
        if facts.geom_kind[g] == "mesh":
            vertices = facts.geom_vertices[g] - origin
            phi = np.minimum(phi, _mesh_sdf(points, vertices, faces[g], dim))
        else:
            local = (points - centre) @ facts.geom_rot[g]
            phi = np.minimum(
                phi, _primitive_sdf(facts.geom_kind[g], facts.geom_size[g], local, dim)
            )
    return phi.reshape(counts), lo


def _primitive_sdf(kind: str, size: np.ndarray, p: np.ndarray, dim: int) -> np.ndarray:
    """Signed distance [m] of a MuJoCo primitive at points ``p`` (n, 3) in its own frame.

    In 2D the geom is a z-prism (its z axis is world z) and the distance is
    that of its cross-section, so the z coordinate is ignored.
    """
    if dim == 2:
        if kind == "box":
            return _box_sdf(p[:, :2], size[:2])
        if kind == "cylinder":
            return np.linalg.norm(p[:, :2], axis=1) - size[0]
        raise ValueError(f"a planar model has only box, cylinder and mesh geoms, not {kind}")
    if kind == "sphere":
        return np.linalg.norm(p, axis=1) - size[0]
    if kind == "capsule":
        axis = np.clip(p[:, 2], -size[1], size[1])
        return np.linalg.norm(p - np.outer(axis, [0, 0, 1]), axis=1) - size[0]
    if kind == "box":
        return _box_sdf(p, size)
    if kind == "cylinder":
        radial = np.linalg.norm(p[:, :2], axis=1)  # a rectangle in (radius, z)
        return _box_sdf(np.column_stack([radial, p[:, 2]]), size[:2])
    if kind == "ellipsoid":
        k0 = np.linalg.norm(p / size, axis=1)
        k1 = np.linalg.norm(p / size**2, axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            estimate = np.where(k1 > 0, k0 * (k0 - 1) / k1, -size.min())
        return np.maximum(estimate, -size.min())  # nothing inside is deeper than its least axis
    raise ValueError(f"cannot voxelize a {kind} geom")


def _box_sdf(p: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Exact signed distance of a centred box (or rectangle) of half-sizes ``half``."""
    q = np.abs(p) - half
    outside = np.linalg.norm(np.maximum(q, 0.0), axis=1)
    return outside + np.minimum(q.max(axis=1), 0.0)


def _mesh_sdf(points, vertices, faces, dim) -> np.ndarray:
    """Signed distance of a closed triangle mesh (3D) or of its cross-section at z = 0 (2D)."""
    if dim == 3:
        return _triangles_sdf(points, vertices, faces)
    start, end = cross_section(vertices, faces)
    return _segments_sdf(points[:, :2].copy(), start, end)


def cross_section(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Segments where a closed triangle mesh cuts the plane z = 0, oriented counter-clockwise.

    Args:
        vertices: (nv, 3) [m]; faces: (nf, 3) indices, outward by the right-hand rule.
    Returns:
        segment starts and ends, each (n, 2) [m]; the mesh's outside lies on
        the right of each segment, so the cut polygons wind counter-clockwise.
    """
    edges = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 3, 2)
    edges = np.sort(edges, axis=2)  # an edge shared by two faces gives the same point
    za, zb = vertices[edges[..., 0], 2], vertices[edges[..., 1], 2]
    crossing = (za < 0) != (zb < 0)
    cut = crossing.sum(axis=1) == 2
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(crossing, za / (za - zb), 0.0)
    va, vb = vertices[edges[..., 0]], vertices[edges[..., 1]]
    points = (va + t[..., None] * (vb - va))[..., :2]
    pick = np.argsort(~crossing, axis=1, kind="stable")[cut, :2]
    rows = np.flatnonzero(cut)
    start, end = points[rows, pick[:, 0]], points[rows, pick[:, 1]]
    tri = vertices[faces[cut]]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])[:, :2]
    step = end - start
    flip = step[:, 1] * normal[:, 0] - step[:, 0] * normal[:, 1] < 0  # outward = (t_y, -t_x)
    start[flip], end[flip] = end[flip].copy(), start[flip].copy()
    return start, end


@numba.njit(cache=True)
def _segments_sdf(points, start, end):
    """Signed distance to a set of closed polygons given as segments; inside by winding number."""
    out = np.empty(points.shape[0])
    for n in range(points.shape[0]):
        px, py = points[n, 0], points[n, 1]
        best, winding = np.inf, 0.0
        for s in range(start.shape[0]):
            ax, ay = start[s, 0] - px, start[s, 1] - py
            bx, by = end[s, 0] - px, end[s, 1] - py
            winding += np.arctan2(ax * by - ay * bx, ax * bx + ay * by)
            ex, ey = bx - ax, by - ay
            length2 = ex * ex + ey * ey
            t = 0.0 if length2 == 0 else min(1.0, max(0.0, -(ax * ex + ay * ey) / length2))
            dx, dy = ax + t * ex, ay + t * ey
            best = min(best, dx * dx + dy * dy)
        distance = np.sqrt(best)
        out[n] = -distance if abs(winding) > np.pi else distance
    return out


@numba.njit(cache=True)
def _triangles_sdf(points, vertices, faces):
    """Signed distance to a closed triangle mesh; inside by generalized winding number."""
    nf = faces.shape[0]
    centre = np.empty((nf, 3))
    radius = np.empty(nf)
    for f in range(nf):
        for c in range(3):
            centre[f, c] = (
                vertices[faces[f, 0], c] + vertices[faces[f, 1], c] + vertices[faces[f, 2], c]
            ) / 3
        r = 0.0
        for v in range(3):
            r = max(r, _norm(_sub(_row(vertices, faces[f, v]), _row(centre, f))))
        radius[f] = r
    out = np.empty(points.shape[0])
    for n in range(points.shape[0]):
        p = _row(points, n)
        best, angle = np.inf, 0.0
        for f in range(nf):
            a = _sub(_row(vertices, faces[f, 0]), p)
            b = _sub(_row(vertices, faces[f, 1]), p)
            c = _sub(_row(vertices, faces[f, 2]), p)
            angle += _solid_angle(a, b, c)
            if _norm(_sub(_row(centre, f), p)) - radius[f] < best:  # else it cannot be nearer
                best = min(best, np.sqrt(_origin_to_triangle2(a, b, c)))
        out[n] = -best if abs(angle) > 2 * np.pi else best
    return out


@numba.njit(cache=True, inline="always")
def _row(array, i):
    return (array[i, 0], array[i, 1], array[i, 2])


@numba.njit(cache=True, inline="always")
def _sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@numba.njit(cache=True, inline="always")
def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@numba.njit(cache=True, inline="always")
def _norm(a):
    return np.sqrt(_dot(a, a))


@numba.njit(cache=True, inline="always")
def _axpy(a, t, b):
    """``a + t b``."""
    return (a[0] + t * b[0], a[1] + t * b[1], a[2] + t * b[2])


@numba.njit(cache=True)
def _solid_angle(a, b, c):
    """Signed solid angle of triangle (a, b, c) seen from the origin (Van Oosterom-Strackee)."""
    la, lb, lc = _norm(a), _norm(b), _norm(c)
    cross = (b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0])
    numerator = _dot(a, cross)
    denominator = la * lb * lc + _dot(a, b) * lc + _dot(a, c) * lb + _dot(b, c) * la
    return 2.0 * np.arctan2(numerator, denominator)


@numba.njit(cache=True)
def _origin_to_triangle2(a, b, c):
    """Squared distance from the origin to triangle (a, b, c), by its Voronoi regions."""
    ab, ac = _sub(b, a), _sub(c, a)
    p = (-a[0], -a[1], -a[2])  # origin relative to a
    d1, d2 = _dot(ab, p), _dot(ac, p)
    if d1 <= 0 and d2 <= 0:
        return _dot(a, a)
    bp = (-b[0], -b[1], -b[2])
    d3, d4 = _dot(ab, bp), _dot(ac, bp)
    if d3 >= 0 and d4 <= d3:
        return _dot(b, b)
    vc = d1 * d4 - d3 * d2
    if vc <= 0 and d1 >= 0 and d3 <= 0:
        q = _axpy(a, d1 / (d1 - d3), ab)
        return _dot(q, q)
    cp = (-c[0], -c[1], -c[2])
    d5, d6 = _dot(ab, cp), _dot(ac, cp)
    if d6 >= 0 and d5 <= d6:
        return _dot(c, c)
    vb = d5 * d2 - d1 * d6
    if vb <= 0 and d2 >= 0 and d6 <= 0:
        q = _axpy(a, d2 / (d2 - d6), ac)
        return _dot(q, q)
    va = d3 * d6 - d5 * d4
    if va <= 0 and d4 - d3 >= 0 and d5 - d6 >= 0:
        q = _axpy(b, (d4 - d3) / ((d4 - d3) + (d5 - d6)), _sub(c, b))
        return _dot(q, q)
    total = va + vb + vc
    if total <= 0:  # a degenerate (flat) triangle: its vertices bound the distance
        return min(_dot(a, a), _dot(b, b), _dot(c, c))
    q = _axpy(_axpy(a, vb / total, ab), vc / total, ac)
    return _dot(q, q)


def link_thickness(shape: BodyShape) -> np.ndarray:
    """Each link's thickness: the diameter of the largest ball (disc in 2D) inside it, (nl,) [m].

    Twice the deepest signed distance sampled inside the link, so it is
    accurate to about one sample spacing (``shape.spacing``); a plate of
    thickness t gives t, a cylinder of radius r gives 2r (2D) or the smaller of
    2r and its length. A link without geoms gives 0. This is what decides
    whether cells of size h resolve a part: fewer than about two cells
    across, and the fluid sees it only through partly open faces (on the
    staircase, it flickers in and out of the solid).
    """
    out = np.zeros(shape.nlinks)
    for k in range(shape.nlinks):
        phi = shape.link_sdf(k)
        if phi.size:
            out[k] = max(0.0, -2.0 * float(phi.min()))
    return out


def geom_volume(kind: str, size, vertices, faces) -> float:
    """The volume of one MuJoCo geom [m^3]."""
    r = size[0]
    if kind == "mesh":  # divergence theorem; faces wind outward
        a, b, c = (vertices[faces[:, i]] for i in range(3))
        return abs(float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum())) / 6
    volumes = {
        "box": lambda: 8 * size[0] * size[1] * size[2],
        "sphere": lambda: 4 / 3 * math.pi * r**3,
        "ellipsoid": lambda: 4 / 3 * math.pi * size[0] * size[1] * size[2],
        "capsule": lambda: math.pi * r**2 * (2 * size[1] + 4 / 3 * r),
        "cylinder": lambda: math.pi * r**2 * 2 * size[1],
    }
    return float(volumes[kind]())
