"""Points on a creature's geoms, and its tail tip (docs/development.md, "Layers").

Pure geometry of the model at given poses, used by the swim metrics and the
pictures. ``geom_point_sets`` / ``geom_points`` sample every geom at the
reference pose: box corners and mesh vertices exactly, spheres, ellipsoids,
capsules and cylinders on a lattice of 24 azimuths (enough for outlines and
extreme points).

The *tail tip* is a point fixed to one link, found once from the model's
geometry at the reference pose (``tail_tip``): the long axis is the
coordinate axis of the body's largest bounding-box side, pointing from the
centre of mass towards the root link's origin (the head); the tip is the
centroid of the geometry's points that lie farthest back along that axis
(for a fin with a straight trailing edge: the middle of that edge), attached
to the link that owns them. ``tail_tip_path`` follows it through a sequence
of poses.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aquagait.body.dynamics import Dynamics, describe, mesh_faces
from aquagait.body.model import Model
from aquagait.body.shape import geom_volume


@dataclass(frozen=True)
class TailTip:
    """A point fixed to a link: ``link`` index and ``offset`` (3,) in the link's frame [m]."""

    link: int
    offset: np.ndarray


def tail_tip(model: Model) -> TailTip:
    """The tail tip of ``model`` (module docstring): the rearmost point along the long axis."""
    facts = describe(model.mj)
    links, points = geom_points(model, world=True)
    axis = int(np.argmax(model.extent))
    root = facts.link_pos[model.joints[0].link]
    centre = Dynamics(model.mj).center_of_mass(model.qpos0)
    forward = 1.0 if root[axis] >= centre[axis] else -1.0
    back = -forward * points[:, axis]
    rearmost = back >= back.max() - 1e-9 * max(model.body_length, 1e-12)
    link = int(links[rearmost][0])
    tip = points[rearmost & (links == link)].mean(axis=0)
    offset = facts.link_rot[link].T @ (tip - facts.link_pos[link])
    return TailTip(link=link, offset=offset)


def tail_tip_path(model: Model, qpos, tip: TailTip | None = None) -> np.ndarray:
    """World position of the tail tip at each pose.

    Args:
        model: the creature.
        qpos: (F, nq) generalized positions, one pose per row.
        tip: the point to follow; default ``tail_tip(model)``.

    Returns:
        (F, dim) positions [m] (the swim plane in 2D).
    """
    tip = tail_tip(model) if tip is None else tip
    dynamics = Dynamics(model.mj)
    path = []
    for q in np.asarray(qpos, dtype=float):
        pos, rot = dynamics.link_poses(q)
        path.append((pos[tip.link] + rot[tip.link] @ tip.offset)[: model.dim])
    return np.array(path).reshape(-1, model.dim)


def body_boxes(model: Model, qpos) -> np.ndarray:
    """The body's world bounding box at each pose: (F, 2, 3) low and high corners [m].

    From the geoms' points (``geom_point_sets``): exact for meshes and boxes,
    within a few per cent of a round geom's radius.
    """
    dynamics, sets = Dynamics(model.mj), geom_point_sets(model)
    boxes = []
    for q in np.asarray(qpos, dtype=float).reshape(-1, model.nq):
        pos, rot = dynamics.link_poses(q)
        points = np.concatenate([pos[link] + p @ rot[link].T for link, p in sets])
        boxes.append([points.min(axis=0), points.max(axis=0)])
    return np.array(boxes)


def geom_points(model: Model, world: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Points on every geom of ``model`` at the reference pose, and the link of each.

    Args:
        model: the creature.
        world: world coordinates at ``qpos0`` if True, else each link's frame.

    Returns:
        ``links`` (n,) link index of each point, ``points`` (n, 3) [m]; see ``geom_point_sets``.
    """
    sets = geom_point_sets(model, world)
    links = np.concatenate([np.full(len(points), link) for link, points in sets])
    return links, np.concatenate([points for _, points in sets])


def geom_point_sets(model: Model, world: bool = False) -> list[tuple[int, np.ndarray]]:
    """Per geom: its link index and points on it (n_g, 3) [m] at the reference pose.

    Mesh vertices and box corners exactly; spheres, ellipsoids, capsules and
    cylinders sampled (24 azimuths); enough for outlines and extreme points.
    In each link's frame, or in the world at ``qpos0`` if ``world``.
    """
    facts = describe(model.mj)
    sets = []
    for g, kind in enumerate(facts.geom_kind):
        if kind == "mesh":
            points = facts.geom_vertices[g]
        else:
            local = _primitive_points(kind, facts.geom_size[g])
            points = facts.geom_pos[g] + local @ facts.geom_rot[g].T
        link = int(facts.geom_link[g])
        if not world:
            points = (points - facts.link_pos[link]) @ facts.link_rot[link]
        sets.append((link, np.asarray(points, dtype=float)))
    return sets


def _primitive_points(kind: str, size) -> np.ndarray:
    """Points (n, 3) [m] on a primitive geom of MuJoCo ``size`` in its own frame."""
    azimuth = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    polar = np.linspace(0, np.pi, 9)
    a, p = np.meshgrid(azimuth, polar)
    sphere = np.stack([np.sin(p) * np.cos(a), np.sin(p) * np.sin(a), np.cos(p)], -1).reshape(-1, 3)
    if kind == "box":
        return np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * size
    if kind == "sphere":
        return sphere * size[0]
    if kind == "ellipsoid":
        return sphere * size
    if kind == "capsule":
        return sphere * size[0] + np.sign(sphere[:, 2:]) * [0, 0, size[1]]
    if kind == "cylinder":
        ring = np.stack([np.cos(azimuth), np.sin(azimuth), np.zeros_like(azimuth)], -1) * size[0]
        return np.concatenate([ring + [0, 0, size[1]], ring - [0, 0, size[1]]])
    raise ValueError(f"geom kind {kind!r} has no point sampling; use a mesh, box or round geom")


def link_volumes(model) -> np.ndarray:
    """Each link's volume, the sum of its geoms' volumes, (nl,) [m^3].

    Overlapping geoms count twice, as in MuJoCo's mass, so ``link_mass /
    volume`` is the geoms' density. In 2D every geom is a z-prism of the
    model's depth, so this is the prism's volume.
    """
    facts, faces = describe(model.mj), mesh_faces(model.mj)
    out = np.zeros(len(facts.link_names))
    for g, kind in enumerate(facts.geom_kind):
        out[facts.geom_link[g]] += geom_volume(kind, facts.geom_size[g],
                                                facts.geom_vertices[g], faces[g])  # fmt: skip
    return out
