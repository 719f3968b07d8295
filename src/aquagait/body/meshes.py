"""Triangle meshes of a creature's links, for the 3D renderer (``aquagait.viz.gl``).

Each link's geoms become one mesh in the link's own frame, so a frame's
picture places it by the link's world pose, ``x = p + R x_link``. Primitive
geoms are tessellated here; mesh geoms keep MuJoCo's triangles.

What is drawn: a link that has visual-only geoms (massless and visible, beside
a visible geom with mass; ``aquagait.body.model``, ``Model.visuals``) is drawn
by those, in place of the geoms the water sees, so a manta's 45 mm fluid
plates can look like a ray's thin wings; every other link by the geoms the
water sees. ``link_meshes(model, visual=False)`` draws exactly what the water
sees, link by link (for a picture of the fluid's body, or a test).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from aquagait.body.dynamics import describe, mesh_faces

AZIMUTHS = 32
"""Facets around a round geom: an outline within 0.5 % of the true radius."""

CREASE_DEGREES = 40.0
"""A mesh edge whose faces turn more than this keeps a sharp (flat-shaded) edge."""


@dataclass(frozen=True)
class LinkMesh:
    """One link's surface in the link's own frame, ready to upload.

    Attributes:
        vertices: (n, 3) positions [m] in the link frame.
        normals: (n, 3) unit outward normals.
        colours: (n, 4) RGBA in [0, 1] (the geom's ``rgba``).
        triangles: (m, 3) vertex indices, counter-clockwise seen from outside.
    """

    vertices: np.ndarray
    normals: np.ndarray
    colours: np.ndarray
    triangles: np.ndarray


def link_meshes(model, visual: bool = True) -> list[LinkMesh]:
    """Triangle meshes of every link of ``model``, each in its link's frame.

    Primitive geoms are tessellated here (MuJoCo sizes: sphere radius,
    ellipsoid semi-axes, capsule and cylinder radius and half-length along
    local z, box half-sides); mesh geoms keep their triangles, smooth-shaded
    except across creases sharper than ``CREASE_DEGREES``. Geoms with zero
    alpha are left out, as MuJoCo's own renderer does.

    Args:
        model: an ``aquagait.body.model.Model``.
        visual: draw a link that has visual-only geoms (``Model.visuals``) by
            those alone (module doc); False: every link by the geoms the water sees.
    Returns:
        one ``LinkMesh`` per link, in link order (empty for a link without geoms).
    """
    facts, faces = describe(model.mj), mesh_faces(model.mj)
    parts = [[] for _ in facts.link_names]
    for g, kind in enumerate(facts.geom_kind):
        if facts.geom_rgba[g][3] == 0:
            continue
        link = int(facts.geom_link[g])
        p0, r0 = facts.link_pos[link], facts.link_rot[link]  # x_link = R0^T (x_world - p0)
        centre, rot, world = facts.geom_pos[g], facts.geom_rot[g], facts.geom_vertices[g]
        own = None if world is None else (world - centre) @ rot  # a mesh's, in its frame
        parts[link].append(_placed(_geom_mesh(kind, facts.geom_size[g], own, faces[g]),
                                   r0.T @ rot, (centre - p0) @ r0, facts.geom_rgba[g]))  # fmt: skip
    for link, drawn in enumerate(model.visuals if visual else ()):
        if drawn:
            parts[link] = [
                _placed(_geom_mesh(v.kind, v.size, v.vertices, v.faces), v.rot, v.pos, v.rgba)
                for v in drawn
            ]
    return [_joined(part) for part in parts]


def _geom_mesh(kind, size, vertices, faces) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Vertices (n, 3) [m], unit normals (n, 3) and triangles (m, 3) of a geom in its own
    frame: a mesh's ``vertices`` (in that frame) and ``faces``, or a primitive of ``size``."""
    if kind == "mesh":
        return _smooth_mesh(vertices, faces)
    return _primitive(kind, size)


def _placed(mesh, rot, pos, rgba) -> tuple:
    """A geom's (vertices, normals, colours, triangles) in its link's frame, where its
    own frame has axes ``rot`` (3, 3) and origin ``pos`` (3,) [m]."""
    vertices, normals, triangles = mesh
    colours = np.tile(rgba, (len(vertices), 1))
    return pos + vertices @ rot.T, normals @ rot.T, colours, triangles


def _joined(parts) -> LinkMesh:
    """One mesh of several (vertices, normals, colours, triangles) pieces."""
    if not parts:
        return LinkMesh(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 4)),
                        np.zeros((0, 3), dtype=np.int64))  # fmt: skip
    starts = np.cumsum([0] + [len(part[0]) for part in parts[:-1]])
    return LinkMesh(
        vertices=np.concatenate([part[0] for part in parts]),
        normals=np.concatenate([part[1] for part in parts]),
        colours=np.concatenate([part[2] for part in parts]),
        triangles=np.concatenate(
            [part[3] + start for part, start in zip(parts, starts, strict=True)]
        ),
    )


def _smooth_mesh(vertices, faces) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A mesh's corners with normals: at each corner, the area-weighted normal of the
    faces around its vertex that turn less than ``CREASE_DEGREES`` from the corner's
    own face, so a surface is smooth up to its creases (a box's edges, a fin plate's
    rim) and each side of a crease keeps its own shading."""
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    face_normals = np.cross(b - a, c - a)  # length: twice the area, the weight
    unit = _unit(face_normals)
    corner_vertex, corner_face = faces.ravel(), np.repeat(np.arange(len(faces)), 3)
    # every pair of corners at one vertex (each with itself too): sort the corners by
    # vertex, then pair each with every corner of its vertex's run
    order = np.argsort(corner_vertex, kind="stable")
    per_vertex = np.bincount(corner_vertex, minlength=len(vertices))
    run_start = (np.cumsum(per_vertex) - per_vertex)[corner_vertex[order]]
    run_length = per_vertex[corner_vertex[order]]
    mine = np.repeat(order, run_length)
    step = np.arange(run_length.sum()) - np.repeat(np.cumsum(run_length) - run_length, run_length)
    theirs = order[np.repeat(run_start, run_length) + step]
    near = np.einsum("ij,ij->i", unit[corner_face[mine]], unit[corner_face[theirs]]) >= (
        math.cos(math.radians(CREASE_DEGREES)))  # fmt: skip
    normals = np.zeros((len(corner_vertex), 3))
    np.add.at(normals, mine[near], face_normals[corner_face[theirs[near]]])
    return vertices[corner_vertex], _unit(normals), np.arange(3 * len(faces)).reshape(-1, 3)


def _unit(vectors: np.ndarray) -> np.ndarray:
    length = np.linalg.norm(vectors, axis=-1, keepdims=True)
    return vectors / np.where(length > 0, length, 1.0)


def _primitive(kind: str, size) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Vertices (n, 3) [m], unit normals (n, 3) and triangles (m, 3) of a
    primitive geom of MuJoCo ``size`` in the geom's own frame."""
    rows = AZIMUTHS // 2 + 1
    if kind == "sphere":
        points, normals = _lattice(np.linspace(0, math.pi, rows))
        return points * size[0], normals, _wrapped_grid(rows)
    if kind == "ellipsoid":
        points, normals = _lattice(np.linspace(0, math.pi, rows))
        return points * size, _unit(normals / size), _wrapped_grid(rows)
    if kind == "capsule":  # a sphere cut at the equator, its halves pulled apart
        half = rows // 2 + 1
        polar = np.concatenate(
            [np.linspace(0, math.pi / 2, half), np.linspace(math.pi / 2, math.pi, half)]
        )
        points, normals = _lattice(polar)
        shift = np.repeat(np.where(np.arange(2 * half) < half, size[1], -size[1]), AZIMUTHS)
        return points * size[0] + shift[:, None] * [0, 0, 1], normals, _wrapped_grid(2 * half)
    if kind == "cylinder":
        return _cylinder(size[0], size[1])
    if kind == "box":
        return _box(np.asarray(size, dtype=float))
    raise ValueError(
        f"geom type {kind!r} cannot be drawn; "
        "use a mesh, box, sphere, ellipsoid, capsule or cylinder"
    )


def _lattice(polar) -> tuple[np.ndarray, np.ndarray]:
    """Points on the unit sphere, rows of ``polar`` angles from +z, ``AZIMUTHS``
    columns counter-clockwise about z; returned twice (points and normals)."""
    azimuth = np.linspace(0, 2 * math.pi, AZIMUTHS, endpoint=False)
    p, a = np.meshgrid(polar, azimuth, indexing="ij")
    points = np.stack([np.sin(p) * np.cos(a), np.sin(p) * np.sin(a), np.cos(p)], -1).reshape(-1, 3)
    return points, points.copy()


def _wrapped_grid(rows: int) -> np.ndarray:
    """Triangles of a rows x ``AZIMUTHS`` grid closed around its columns, outward
    when rows run from +z down and columns counter-clockwise about z."""
    r, c = np.meshgrid(np.arange(rows - 1), np.arange(AZIMUTHS), indexing="ij")
    here, east = r * AZIMUTHS + c, r * AZIMUTHS + (c + 1) % AZIMUTHS
    south, south_east = here + AZIMUTHS, east + AZIMUTHS
    return np.concatenate(
        [np.stack([here, south, east], -1), np.stack([east, south, south_east], -1)]
    ).reshape(-1, 3)


def _cylinder(radius: float, half_length: float):
    """A capped cylinder along z: its side (radial normals) and two flat caps."""
    ring, _ = _lattice([math.pi / 2])
    side = np.concatenate(
        [ring * radius + [0, 0, half_length], ring * radius - [0, 0, half_length]]
    )
    up = np.array([0.0, 0.0, 1.0])
    i = np.arange(AZIMUTHS)
    cap = 2 * AZIMUTHS  # top: centre then ring; bottom likewise after it
    vertices = [side, [up * half_length], side[:AZIMUTHS], [-up * half_length], side[AZIMUTHS:]]
    normals = [
        np.concatenate([ring, ring]),
        np.tile(up, (AZIMUTHS + 1, 1)),
        -np.tile(up, (AZIMUTHS + 1, 1)),
    ]
    top = np.stack([np.full(AZIMUTHS, cap), cap + 1 + i, cap + 1 + (i + 1) % AZIMUTHS], -1)
    bottom = top[:, [0, 2, 1]] + AZIMUTHS + 1
    triangles = np.concatenate([_wrapped_grid(2), top, bottom])
    return np.concatenate(vertices), np.concatenate(normals), triangles


def _box(half: np.ndarray):
    """A box of half-sides ``half``: four corners and one normal per face."""
    vertices, normals, triangles = [], [], []
    square = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float)
    for axis in range(3):
        u, v = np.eye(3)[(axis + 1) % 3], np.eye(3)[(axis + 2) % 3]
        for sign in (1.0, -1.0):
            normal = sign * np.eye(3)[axis]
            corners = normal + square[:, :1] * u + square[:, 1:] * v
            order = [0, 1, 2, 0, 2, 3] if sign > 0 else [0, 2, 1, 0, 3, 2]  # CCW about normal
            triangles.append(np.array(order).reshape(2, 3) + 4 * len(vertices))
            vertices.append(corners * half)
            normals.append(np.tile(normal, (4, 1)))
    return np.concatenate(vertices), np.concatenate(normals), np.concatenate(triangles)
