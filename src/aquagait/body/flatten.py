"""Planar models with 3D shapes: each geom's cross-section in the plane of motion, as a prism.

A planar creature (root joints slide x, slide y, hinge z) swims in aquagait's
2D fluid, where every link is a prism: an outline in the plane, extruded to
the model's depth. Models written for MuJoCo's own planar swimmers use 3D
shapes instead (capsules lying in the plane, ellipsoid heads, spheres) and
sit at any height above a floor. Such a model is read as what the plane of
motion cuts through it:

- the plane is the one the root moves in, at the root's height; every link
  must lie in it;
- each geom's outline is its cross-section by that plane (a capsule lying in
  the plane gives a stadium, an ellipsoid an ellipse, a sphere a disc), found
  by marching ``RAYS`` rays out from the geom's centre to its surface (exact
  for the convex primitives up to the polygon's chords; a non-convex mesh is
  taken as seen from its centre); a geom the plane misses shapes nothing;
- the depth is the model's ``aquagait_depth`` where it declares one, else the
  one that keeps the body's displaced volume: the geoms' 3D volume over
  their outlines' area (``prism_depth``), stated in a note with how far each
  link's prism volume is from its 3D volume;
- the creature is moved down to z = 0, and each geom becomes a mesh prism
  of that depth, while MuJoCo's masses and inertias of the 3D shapes stay
  (``aquagait.body.reshape.pin_inertia``).

This is the default. A planar model may instead swim in the 3D fluid, its
shapes as written and its root held to its plane (``load_model``'s
``planar_fluid="3d"``, the side-car's ``"planar_fluid": "3d"``).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np

from aquagait.body.reshape import detach, elements, numbers
from aquagait.body.scenery import remove_from
from aquagait.body.shape import _mesh_sdf, _primitive_sdf

RAYS = 128
"""Vertices of each outline, spread evenly along it: a disc's polygon holds 99.96 % of its
area, a stadium five times as long as wide 99.9 %."""

MESH_PREFIX = "aquagait_outline_"


def outlines(facts, faces, plane_z: float) -> list[np.ndarray | None]:
    """Each geom's cross-section by the plane z = ``plane_z``, at the reference pose.

    Args:
        facts: the compiled model's ``CompiledFacts``.
        faces: per geom its mesh triangles or None (``dynamics.mesh_faces``).
        plane_z: the height of the plane of motion [m].
    Returns:
        per geom an (RAYS, 2) counter-clockwise polygon in world x, y [m], or
        None where the plane misses the geom.
    """
    out = []
    for g in range(len(facts.geom_kind)):
        centre = np.array([*facts.geom_pos[g, :2], plane_z])
        sdf = _geom_sdf(facts, faces, g)
        if sdf(centre[None])[0] >= 0:
            out.append(None)
            continue
        reach = float(np.linalg.norm(facts.geom_box[g, 1] - facts.geom_box[g, 0]))
        first = _march(sdf, centre, np.linspace(0, 2 * np.pi, RAYS, endpoint=False), reach)
        # again, the rays spread evenly along the outline rather than in angle: a long
        # stadium's round ends get their share of vertices
        ring = np.vstack([first, first[:1]])
        along = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(ring, axis=0), axis=1))]
        angles = np.unwrap(np.arctan2(*(ring - centre[:2]).T[::-1]))
        even = np.interp(np.linspace(0, along[-1], RAYS, endpoint=False), along, angles)
        out.append(_march(sdf, centre, even, reach))
    return out


def _march(sdf, centre, angles, reach: float) -> np.ndarray:
    """Where rays from ``centre`` at ``angles`` leave the geom, (n, 2) [m] (bisection)."""
    ray = np.stack([np.cos(angles), np.sin(angles), np.zeros(len(angles))], axis=1)
    inside, outside = np.zeros(len(angles)), np.full(len(angles), reach)
    for _ in range(60):  # to well under a micrometre
        t = (inside + outside) / 2
        solid = sdf(centre + t[:, None] * ray) < 0
        inside, outside = np.where(solid, t, inside), np.where(solid, outside, t)
    return (centre + inside[:, None] * ray)[:, :2]


def _geom_sdf(facts, faces, g):
    """Signed distance of geom ``g`` at world points (n, 3), at the reference pose."""
    kind, pos, rot = facts.geom_kind[g], facts.geom_pos[g], facts.geom_rot[g]
    if kind == "mesh":
        vertices = facts.geom_vertices[g]
        return lambda p: _mesh_sdf(np.ascontiguousarray(p), vertices, faces[g], 3)
    return lambda p: _primitive_sdf(kind, facts.geom_size[g], (p - pos) @ rot, 3)


def area(polygon: np.ndarray) -> float:
    """The area of a counter-clockwise polygon (n, 2) [m^2] (the shoelace formula)."""
    x, y = polygon[:, 0], polygon[:, 1]
    return 0.5 * float(x @ np.roll(y, -1) - y @ np.roll(x, -1))


def prism_depth(volumes, shapes) -> float:
    """The depth [m] at which the outlines' prisms displace the geoms' 3D volume.

    Args:
        volumes: (ng,) each geom's volume [m^3] (0 for geoms that shape nothing).
        shapes: per geom its outline or None.
    """
    areas = sum(area(s) for s in shapes if s is not None)
    return float(np.sum([v for v, s in zip(volumes, shapes, strict=True) if s is not None])
                 / areas)  # fmt: skip


def prism_xml(xml: str, facts, shapes, depth: float, plane_z: float) -> str:
    """The MJCF ``xml`` with each geom an extruded outline of ``depth`` and the creature at
    z = 0; a geom without an outline is removed.

    Args:
        xml: MJCF text compiled into ``facts``, with the links' inertias pinned
            (``reshape.pin_inertia``), so that the new shapes change no mass.
        facts: its ``CompiledFacts``.
        shapes: per geom its outline (``outlines``) or None.
        depth: the prism depth [m], written as the model's ``aquagait_depth``.
        plane_z: the plane's height [m], moved to 0.
    """
    root = ET.fromstring(xml)
    bodies, geoms = elements(root, facts)
    assets = root.find("asset")
    if assets is None:
        assets = ET.SubElement(root, "asset")
    for g, ((body, geom), shape) in enumerate(zip(geoms, shapes, strict=True)):
        if shape is None:
            remove_from(body, geom)
            continue
        k = int(facts.geom_link[g])
        ring = np.vstack([shape, facts.geom_pos[g, :2]])  # the outline, then its centre
        world = np.concatenate([np.column_stack([ring, np.full(len(ring), z)])
                                for z in (plane_z - depth / 2, plane_z + depth / 2)])  # fmt: skip
        local = (world - facts.link_pos[k]) @ facts.link_rot[k]  # in the link's frame
        name = f"{MESH_PREFIX}{g}"
        ET.SubElement(assets, "mesh", name=name, vertex=numbers(local.ravel()),
                      face=" ".join(map(str, _prism_faces(len(shape)).ravel())))  # fmt: skip
        detach(root, geom, facts, g)
        geom.set("type", "mesh")
        geom.set("mesh", name)
    pos = facts.link_pos[0] - [0.0, 0.0, plane_z]  # the root is at the world's pose at qpos0
    bodies[0].set("pos", numbers(pos))
    custom = root.find("custom")
    if custom is None:
        custom = ET.SubElement(root, "custom")
    for numeric in custom.findall("numeric"):
        if numeric.get("name") == "aquagait_depth":
            custom.remove(numeric)
    ET.SubElement(custom, "numeric", name="aquagait_depth", data=repr(depth))
    return ET.tostring(root, encoding="unicode")


def _prism_faces(n: int) -> np.ndarray:
    """Outward triangles of an extruded star-shaped polygon: vertices 0..n-1 its outline at
    the bottom, n its centre there, then the same n + 1 at the top."""
    i = np.arange(n)
    j = (i + 1) % n
    top = n + 1
    return np.concatenate([
        np.column_stack([np.full(n, n), j, i]),  # bottom, facing -z
        np.column_stack([np.full(n, top + n), top + i, top + j]),  # top, facing +z
        np.column_stack([i, j, top + j]),  # the sides, facing out of the counter-clockwise outline
        np.column_stack([i, top + j, top + i]),
    ])  # fmt: skip
