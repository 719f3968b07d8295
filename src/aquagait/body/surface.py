"""The links' surfaces as small flat patches in their link frames (docs/compare-fluids.md).

The simple fluid (paper §7) needs, for every surface element of every link,
where it is, which way it faces and how large it is. They are built once per
model, here, from the geoms at the reference pose ``qpos0``, and stored in
each link's own frame (the frame ``Dynamics.link_poses`` reports), so at any
pose ``surface_world`` moves them with one rotation per patch.

How each geom is cut into patches no longer than ``resolution`` (the longest
side, [m]):

- box: each face a grid of rectangles.
- sphere, ellipsoid, capsule, cylinder: a grid in their natural parameters
  (polar and azimuth angle; azimuth and height for a cylinder's side; radius
  and azimuth for its end discs). A patch sits at its parameter midpoint with
  the exact outward normal there, and its area is the surface integral over
  its parameter cell by 3 x 3 Gauss-Legendre quadrature, so the areas sum to
  the geom's exact surface area to about 1e-9 (``AREA_TOLERANCE``).
- mesh (3D): its triangles (``dynamics.mesh_faces``; the convex hull for a
  mesh given by vertices), each split into ``n^2`` equal triangles; exact area.
- 2D (planar prisms of depth ``D``, ``aquagait.body.model``): only the side
  walls, as patches on z = 0 with normals in the x-y plane and area
  ``edge length x D``: a box's rectangle, a cylinder's circle (arcs, exact
  area), a mesh's polygon where it cuts z = 0. The end caps (normals +-z) are
  dropped: a planar body never moves along z, so they would never feel a force.

Buried faces: a patch whose centre lies inside or on another geom at the
reference pose (the faces where neighbouring links meet at a joint, or two
geoms of one link overlap) never touches water and is dropped, unless
``keep_buried``. The test is made once, at ``qpos0``; a joint that bends
opens a wedge whose faces stay dropped, and one that closes may bury a kept
patch: both are small against the body and are the simple model's price.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aquagait.body.dynamics import describe, mesh_faces
from aquagait.body.shape import _mesh_sdf, _primitive_sdf, cross_section

PATCHES_PER_LENGTH = 25
"""Default resolution: the body length over this many patches (the eel: 2 cm, the fish: 4 mm).

The drag on the library creatures swimming is then within about 2% of its
limit for ever finer patches (the eel: 96 patches, the fish: 4,300).
"""

AREA_TOLERANCE = 1e-6
"""Bound on the relative error of a geom's summed patch areas against its exact surface area."""

MIN_AROUND = 12
"""Fewest patches around a curved geom, whatever the resolution, so its normals turn smoothly."""

BURIED_TOLERANCE = 1e-6
"""A patch centre within this fraction of the body length of another geom's inside is buried."""

_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(3)


@dataclass(frozen=True, eq=False)
class Surface:
    """Every link's surface as flat patches in its link frame (fixed; picklable).

    ``m`` patches. A patch of link ``k`` at pose ``(pos, rot)`` sits at
    ``pos[k] + rot[k] @ centre`` facing ``rot[k] @ normal``.

    Attributes:
        dim: 2 (planar prisms: side walls only, on z = 0) or 3.
        resolution: the longest patch side asked for [m].
        centre: (m, 3) patch centres in the link frame [m].
        normal: (m, 3) outward unit normals in the link frame.
        area: (m,) patch areas [m^2] (2D: edge length x depth).
        link: (m,) int64 owning link.
        geom: (m,) int64 the MuJoCo geom the patch belongs to.
    """

    dim: int
    resolution: float
    centre: np.ndarray
    normal: np.ndarray
    area: np.ndarray
    link: np.ndarray
    geom: np.ndarray

    @property
    def size(self) -> int:
        """Number of patches m."""
        return int(self.area.shape[0])


def body_surface(model, resolution: float | None = None, keep_buried: bool = False) -> Surface:
    """Cut every geom of a model into patches in its link's frame (module docstring).

    Args:
        model: a checked ``aquagait.body.Model`` (2D or 3D).
        resolution: longest patch side [m]; default ``body_length / PATCHES_PER_LENGTH``.
        keep_buried: keep the patches inside or on other geoms (joint faces).
    Returns:
        the ``Surface``.
    Raises:
        ValueError: a non-positive resolution.
    """
    if resolution is None:
        resolution = model.body_length / PATCHES_PER_LENGTH
    if not (np.isfinite(resolution) and resolution > 0):
        raise ValueError(f"resolution must be a positive length in metres, got {resolution!r}")
    facts, faces = describe(model.mj), mesh_faces(model.mj)
    parts = []
    for g, kind in enumerate(facts.geom_kind):
        if model.dim == 2:
            centre, normal, area = _prism_patches(facts, faces, g, model.depth, resolution)
        elif kind == "mesh":
            centre, normal, area = _mesh_patches(facts.geom_vertices[g], faces[g], resolution)
        else:
            centre, normal, area = _primitive_patches(kind, facts.geom_size[g], resolution)
            rot = facts.geom_rot[g]
            centre, normal = facts.geom_pos[g] + centre @ rot.T, normal @ rot.T
        keep = area > 0
        parts.append((centre[keep], normal[keep], area[keep], np.full(keep.sum(), g)))
    centre, normal, area, geom = (np.concatenate(p) for p in zip(*parts, strict=True))
    if not keep_buried:
        tol = BURIED_TOLERANCE * model.body_length
        open_ = ~_buried(facts, faces, centre, geom, model.dim, tol)
        centre, normal, area, geom = centre[open_], normal[open_], area[open_], geom[open_]
    link = facts.geom_link[geom].astype(np.int64)
    rot, pos = facts.link_rot[link], facts.link_pos[link]  # world -> link frame at qpos0
    return Surface(
        dim=model.dim,
        resolution=float(resolution),
        centre=np.einsum("mji,mj->mi", rot, centre - pos),
        normal=np.einsum("mji,mj->mi", rot, normal),
        area=area,
        link=link,
        geom=geom.astype(np.int64),
    )


def surface_world(surface: Surface, link_pos, link_rot) -> tuple[np.ndarray, np.ndarray]:
    """The patches at a pose: world centres (m, 3) [m] and unit normals (m, 3).

    Args:
        surface: the body's surface.
        link_pos: (nlinks, 3) link origins [m]; link_rot: (nlinks, 3, 3)
            rotations, as ``Dynamics.link_poses(q)`` returns them.
    """
    rot = np.asarray(link_rot)[surface.link]
    centre = np.asarray(link_pos)[surface.link] + np.einsum("mij,mj->mi", rot, surface.centre)
    return centre, np.einsum("mij,mj->mi", rot, surface.normal)


# --- primitives, in the geom's own frame -------------------------------------------


def _primitive_patches(kind: str, size: np.ndarray, res: float):
    """Patches (centre, normal, area) of a MuJoCo primitive in its own frame."""
    if kind == "box":
        return _join([_box_face(size, axis, sign, res) for axis in range(3) for sign in (1, -1)])
    if kind == "sphere":
        return _ellipsoid(np.full(3, size[0]), 0.0, np.pi, res)
    if kind == "ellipsoid":
        return _ellipsoid(size[:3], 0.0, np.pi, res)
    r, half = size[0], size[1]
    side = _cylinder_side(r, half, res)
    if kind == "capsule":
        ball = np.full(3, r)
        top, bottom = _ellipsoid(ball, 0, np.pi / 2, res), _ellipsoid(ball, np.pi / 2, np.pi, res)
        return _join([side, _shifted(top, half), _shifted(bottom, -half)])
    if kind == "cylinder":
        return _join([side, _disc(r, half, 1, res), _disc(r, -half, -1, res)])
    raise ValueError(f"cannot build the surface of a {kind} geom")


def _parametric(point, normal, density, u_range, v_range, nu, nv):
    """An ``nu x nv`` grid of patches of a parametric surface.

    ``point(u, v)`` and ``normal(u, v)`` give (..., 3) arrays, ``density(u, v)``
    the area element ``|r_u x r_v|``; areas by 3 x 3 Gauss-Legendre per cell.
    """
    u_edges, v_edges = np.linspace(*u_range, nu + 1), np.linspace(*v_range, nv + 1)
    u_mid, v_mid = (u_edges[1:] + u_edges[:-1]) / 2, (v_edges[1:] + v_edges[:-1]) / 2
    u_half, v_half = np.diff(u_edges)[0] / 2, np.diff(v_edges)[0] / 2
    uq = u_mid[:, None, None, None] + u_half * _GAUSS_X[None, None, :, None]
    vq = v_mid[None, :, None, None] + v_half * _GAUSS_X[None, None, None, :]
    weights = np.outer(_GAUSS_W, _GAUSS_W) * u_half * v_half
    area = (density(uq, vq) * weights).sum(axis=(2, 3))
    u, v = np.meshgrid(u_mid, v_mid, indexing="ij")
    return point(u, v).reshape(-1, 3), normal(u, v).reshape(-1, 3), area.ravel()


def _count(length: float, res: float, least: int = 1) -> int:
    return max(least, int(np.ceil(length / res - 1e-9)))


def _ellipsoid(radii, theta_lo: float, theta_hi: float, res: float):
    """An ellipsoid (a sphere when the radii agree) between two polar angles."""
    a, b, c = radii

    def point(t, p):
        return np.stack([a * np.sin(t) * np.cos(p), b * np.sin(t) * np.sin(p), c * np.cos(t)], -1)

    def normal(t, p):
        n = point(t, p) / np.asarray(radii) ** 2
        return n / np.linalg.norm(n, axis=-1, keepdims=True)

    def density(t, p):
        s, cp, sp = np.sin(t), np.cos(p), np.sin(p)
        inner = (b * c * s * cp) ** 2 + (a * c * s * sp) ** 2 + (a * b * np.cos(t)) ** 2
        return s * np.sqrt(inner)

    longest = max(a, b, c)
    nt = _count(longest * (theta_hi - theta_lo), res, MIN_AROUND // 4)
    nphi = _count(2 * np.pi * longest, res, MIN_AROUND)
    return _parametric(point, normal, density, (theta_lo, theta_hi), (0, 2 * np.pi), nt, nphi)


def _cylinder_side(r: float, half: float, res: float):
    def point(p, z):
        return np.stack([r * np.cos(p), r * np.sin(p), z], -1)

    def normal(p, z):
        return np.stack([np.cos(p), np.sin(p), np.zeros_like(z)], -1)

    def density(p, z):
        return np.full(np.broadcast(p, z).shape, r)

    n_around, n_along = _count(2 * np.pi * r, res, MIN_AROUND), _count(2 * half, res)
    return _parametric(point, normal, density, (0, 2 * np.pi), (-half, half), n_around, n_along)


def _disc(r: float, z: float, sign: int, res: float):
    def point(rho, p):
        return np.stack([rho * np.cos(p), rho * np.sin(p), np.full_like(rho * p, z)], -1)

    def normal(rho, p):
        return np.broadcast_to([0.0, 0.0, sign], np.broadcast(rho, p).shape + (3,))

    def density(rho, p):
        return np.broadcast_to(rho, np.broadcast(rho, p).shape)

    n_around = _count(2 * np.pi * r, res, MIN_AROUND)
    return _parametric(point, normal, density, (0, r), (0, 2 * np.pi), _count(r, res), n_around)


def _box_face(half: np.ndarray, axis: int, sign: int, res: float):
    """The face of a centred box whose outward normal is ``sign * e_axis``."""
    i, j = (axis + 1) % 3, (axis + 2) % 3
    e = np.eye(3)

    def point(u, v):
        return sign * half[axis] * e[axis] + u[..., None] * e[i] + v[..., None] * e[j]

    def normal(u, v):
        return np.broadcast_to(sign * e[axis], np.broadcast(u, v).shape + (3,))

    def density(u, v):
        return np.ones(np.broadcast(u, v).shape)

    nu, nv = _count(2 * half[i], res), _count(2 * half[j], res)
    return _parametric(point, normal, density, (-half[i], half[i]), (-half[j], half[j]), nu, nv)


def _shifted(patches, dz: float):
    centre, normal, area = patches
    return centre + [0.0, 0.0, dz], normal, area


def _join(parts):
    return tuple(np.concatenate(p) for p in zip(*parts, strict=True))


# --- meshes and planar prisms, in world coordinates at qpos0 ---------------------------


def _mesh_patches(vertices: np.ndarray, faces: np.ndarray, res: float):
    """Each triangle split into ``n^2`` equal triangles (``n`` from its longest edge)."""
    tri = vertices[faces]  # (nf, 3 corners, 3)
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    twice_area = np.linalg.norm(cross, axis=1)
    ok = twice_area > 0
    tri, cross, twice_area = tri[ok], cross[ok], twice_area[ok]
    edges = np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=2).max(axis=1)
    n = np.maximum(1, np.ceil(edges / res - 1e-9)).astype(int)
    parts = []
    for split in np.unique(n):
        rows = n == split
        # centroids of the n^2 small triangles, as barycentric offsets (s, t) along the edges
        i, j = np.meshgrid(np.arange(split), np.arange(split), indexing="ij")
        up = (i + j <= split - 1).ravel()
        down = (i + j <= split - 2).ravel()
        s = np.concatenate([i.ravel()[up] + 1 / 3, i.ravel()[down] + 2 / 3]) / split
        t = np.concatenate([j.ravel()[up] + 1 / 3, j.ravel()[down] + 2 / 3]) / split
        a, ab, ac = tri[rows, 0], tri[rows, 1] - tri[rows, 0], tri[rows, 2] - tri[rows, 0]
        centre = a[:, None] + s[None, :, None] * ab[:, None] + t[None, :, None] * ac[:, None]
        normal = cross[rows] / twice_area[rows, None]
        area = twice_area[rows] / 2 / split**2
        count = s.size
        parts.append(
            (
                centre.reshape(-1, 3),
                np.repeat(normal, count, axis=0),
                np.repeat(area, count),
            )
        )
    return _join(parts)


def _prism_patches(facts, faces, g: int, depth: float, res: float):
    """Side walls of a planar prism geom, as patches on z = 0 (area = edge x depth)."""
    kind, size = facts.geom_kind[g], facts.geom_size[g]
    if kind == "cylinder":
        r = size[0]
        n = _count(2 * np.pi * r, res, MIN_AROUND)
        phi = (np.arange(n) + 0.5) * 2 * np.pi / n
        normal = np.column_stack([np.cos(phi), np.sin(phi), np.zeros(n)])
        centre = facts.geom_pos[g] + r * normal
        return centre, normal, np.full(n, 2 * np.pi * r / n * depth)
    if kind == "box":
        corners = np.array([[1, -1], [1, 1], [-1, 1], [-1, -1]]) * size[:2]  # counter-clockwise
        corners3 = np.column_stack([corners, np.zeros(4)]) @ facts.geom_rot[g].T
        start = (facts.geom_pos[g] + corners3)[:, :2]
        end = np.roll(start, -1, axis=0)
        if facts.geom_rot[g][2, 2] < 0:  # a box flipped about x or y winds the other way
            start, end = end, start
    elif kind == "mesh":
        start, end = cross_section(facts.geom_vertices[g], faces[g])
    else:
        raise ValueError(f"a planar model has only box, cylinder and mesh geoms, not {kind}")
    return _segment_patches(start, end, depth, res)


def _segment_patches(start: np.ndarray, end: np.ndarray, depth: float, res: float):
    """Counter-clockwise polygon edges (outside on the right) cut into pieces of at most ``res``."""
    step = end - start
    length = np.linalg.norm(step, axis=1)
    ok = length > 0
    start, step, length = start[ok], step[ok], length[ok]
    n = np.maximum(1, np.ceil(length / res - 1e-9)).astype(int)
    edge = np.repeat(np.arange(length.size), n)
    first = np.repeat(np.cumsum(n) - n, n)
    frac = (np.arange(n.sum()) - first + 0.5) / n[edge]
    centre2 = start[edge] + frac[:, None] * step[edge]
    normal2 = np.column_stack([step[:, 1], -step[:, 0]]) / length[:, None]
    zeros = np.zeros(edge.size)
    centre = np.column_stack([centre2, zeros])
    normal = np.column_stack([normal2[edge], zeros])
    return centre, normal, (length / n * depth)[edge]


def _buried(facts, faces, centre, geom, dim: int, tol: float) -> np.ndarray:
    """(m,) bool: the patch centre is inside or on a geom other than its own."""
    buried = np.zeros(centre.shape[0], dtype=bool)
    for g, kind in enumerate(facts.geom_kind):
        other = geom != g
        lo, hi = facts.geom_box[g, 0] - tol, facts.geom_box[g, 1] + tol
        near = other & np.all((centre >= lo) & (centre <= hi), axis=1)
        if dim == 2:
            near = other & np.all((centre[:, :2] >= lo[:2]) & (centre[:, :2] <= hi[:2]), axis=1)
        if not near.any():
            continue
        points = centre[near]
        if kind == "mesh":
            phi = _mesh_sdf(points, facts.geom_vertices[g], faces[g], dim)
        else:
            local = (points - facts.geom_pos[g]) @ facts.geom_rot[g]
            phi = _primitive_sdf(kind, facts.geom_size[g], local, dim)
        buried[np.flatnonzero(near)[phi <= tol]] = True
    return buried
