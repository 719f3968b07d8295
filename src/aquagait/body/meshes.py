"""Triangle meshes of a creature's links, for the 3D renderer (``aquagait.viz.gl``).

Each link's geoms become one mesh in the link's own frame, so a frame's
picture places it by the link's world pose, ``x = p + R x_link``. Primitive
geoms are tessellated here; mesh geoms keep MuJoCo's triangles.
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


def link_meshes(model) -> list[LinkMesh]:
    """Triangle meshes of every link of ``model``, each in its link's frame.

    Primitive geoms are tessellated here (MuJoCo sizes: sphere radius,
    ellipsoid semi-axes, capsule and cylinder radius and half-length along
    local z, box half-sides); mesh geoms keep their triangles, smooth-shaded
    except across creases sharper than ``CREASE_DEGREES``. Geoms with zero
    alpha are left out, as MuJoCo's own renderer does.

    Args:
        model: an ``aquagait.body.model.Model``.
    Returns:
        one ``LinkMesh`` per link, in link order (empty for a link without geoms).
    """
    facts, faces = describe(model.mj), mesh_faces(model.mj)
    parts = [[] for _ in facts.link_names]
    for g, kind in enumerate(facts.geom_kind):
        if facts.geom_rgba[g][3] == 0:
            continue
        if kind == "mesh":
            vertices, normals, triangles = _smooth_mesh(facts.geom_vertices[g], faces[g])
        else:
            local, local_normals, triangles = _primitive(kind, facts.geom_size[g])
            vertices = facts.geom_pos[g] + local @ facts.geom_rot[g].T
            normals = local_normals @ facts.geom_rot[g].T
        link = int(facts.geom_link[g])
        p0, r0 = facts.link_pos[link], facts.link_rot[link]  # x_link = R0^T (x_world - p0)
        colours = np.tile(facts.geom_rgba[g], (len(vertices), 1))
        parts[link].append(((vertices - p0) @ r0, normals @ r0, colours, triangles))
    return [_joined(part) for part in parts]


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
    """A mesh's corners with normals: the area-weighted vertex normal, or the
    face's own where the two differ by more than ``CREASE_DEGREES`` (a box's
    edges, a fin plate's rim)."""
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    face_normals = np.cross(b - a, c - a)  # length: twice the area, the weight
    vertex_normals = np.zeros_like(vertices, dtype=float)
    np.add.at(vertex_normals, faces.ravel(), np.repeat(face_normals, 3, axis=0))
    flat = np.repeat(_unit(face_normals), 3, axis=0)
    smooth = _unit(vertex_normals)[faces.ravel()]
    sharp = np.einsum("ij,ij->i", flat, smooth) < math.cos(math.radians(CREASE_DEGREES))
    normals = np.where(sharp[:, None], flat, smooth)
    return vertices[faces.ravel()], normals, np.arange(3 * len(faces)).reshape(-1, 3)


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
