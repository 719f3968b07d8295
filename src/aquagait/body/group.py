"""Several creatures as one body: a group that swims in one fluid (docs/schools.md).

``compose`` attaches the members' MJCF trees under one world, each renamed
``LABEL/NAME``, as one MuJoCo model with several roots, and describes it as
one ``Model``. Nothing joins the trees, so the group's mass matrix is
block-diagonal, one block a member, and everything that takes a model takes
the group unchanged: one ``Dynamics``, one body shape and voxelizing, one
coupled pressure solve whose body term ``B^T Mt^-1 B`` is exactly the sum
of the members' (docs/method-coupling.md), one grid that follows and grows
around the group. What is a member's own (its positions and velocities, its
links, its gait) is a slice of the group's (``Member``).

Each member stands at its own pose: its reference pose moved by ``offset``
[m] and turned by ``heading`` [rad] about the vertical through its root.
The group's ``qpos0`` is the members' poses, and ``Model.bounds`` the box
around them there.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numba
import numpy as np
from scipy.spatial.transform import Rotation

from aquagait.body.dynamics import compose_mjcf, describe
from aquagait.body.model import Model
from aquagait.body.shape import BodyShape
from aquagait.body.surface import surface_world
from aquagait.body.voxelize import baked_arrays, checked_pose, link_distance

__all__ = [
    "FORMATIONS",
    "Group",
    "GroupError",
    "Member",
    "Pose",
    "compose",
    "deepest_overlap",
    "formation",
    "member_gaps",
    "posed",
    "refuse_overlap",
]


class GroupError(ValueError):
    """Creatures that cannot swim as one group; the message says which and why."""


@dataclass(frozen=True)
class Pose:
    """Where a member starts: its reference pose moved by ``offset`` and turned by
    ``heading`` about the vertical (z) through its root.

    Attributes:
        offset: (3,) [m]; in 2D the z entry must be 0.
        heading: [rad], counter-clockwise seen from above.
    """

    offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    heading: float = 0.0


@dataclass(frozen=True)
class Member:
    """One creature of a group, and where its numbers lie in the group's.

    Attributes:
        label: its name in the group (unique), the prefix of its links and DOFs.
        model: the creature alone.
        pose: where it starts.
        qpos: its slice of the group's positions (nq,).
        dofs: its slice of the group's velocities and forces (nv,).
        links: its slice of the group's links.
    """

    label: str
    model: Model
    pose: Pose
    qpos: slice
    dofs: slice
    links: slice


@dataclass(frozen=True, eq=False)
class Group:
    """Creatures composed into one model (module doc).

    Attributes:
        model: the group as one ``Model``: its ``source`` lists the members,
            its ``root_dofs`` are every member's root, ``body_length`` the
            longest member's.
        members: each creature, in order.
    """

    model: Model
    members: tuple[Member, ...]

    def member(self, label: str) -> Member:
        """The member called ``label``; the error lists the labels."""
        for member in self.members:
            if member.label == label:
                return member
        known = ", ".join(m.label for m in self.members)
        raise KeyError(f"no member {label!r} in the group; its members: {known}")

    def member_of_link(self) -> np.ndarray:
        """(nlinks,) the index of the member each of the group's links belongs to."""
        return np.concatenate(
            [np.full(m.links.stop - m.links.start, i) for i, m in enumerate(self.members)]
        )


def compose(models, labels=None, poses=None) -> Group:
    """Compose creatures into one group model (module doc).

    Args:
        models: the creatures' ``Model``s, two or more (one is allowed: a group
            of one swims as the creature does).
        labels: a unique name for each, default ``NAME-1``, ``NAME-2``, ... after
            each model's file (``eel2d-1``).
        poses: a ``Pose`` for each; default all at their reference pose (which
            overlaps: give poses).

    Raises:
        GroupError: no models, 2D and 3D creatures mixed, 2D creatures of
            different depths, labels not unique or with a '/', a 2D pose
            off its plane, or counts that disagree.
    """
    models = tuple(models)
    if not models:
        raise GroupError("a group needs at least one creature")
    labels = tuple(_default_labels(models) if labels is None else labels)
    poses = tuple([Pose()] * len(models) if poses is None else poses)
    _check(models, labels, poses)
    members, nq, nv, nl = [], 0, 0, 0
    for model, label, pose in zip(models, labels, poses, strict=True):
        ends = nq + model.nq, nv + model.nv, nl + len(model.links)
        members.append(Member(label, model, pose, slice(nq, ends[0]), slice(nv, ends[1]),
                              slice(nl, ends[2])))  # fmt: skip
        nq, nv, nl = ends
    qpos0 = np.concatenate([posed(m.model, m.pose) for m in members])
    mj, xml = compose_mjcf([(m.label, m.model.mjcf) for m in members])
    return Group(_group_model(mj, xml, members, qpos0), tuple(members))


FORMATIONS = {"in-line": 2, "side-by-side": 2, "diamond": 4}
"""The formations ``formation`` places, and how many creatures each has by default."""


def formation(kind: str, count: int, spacing: float, length: float) -> list[tuple[Pose, int]]:
    """Where a formation's creatures stand, and each one's rank (0 the leader, 1 the next).

    Args:
        kind: ``in-line`` (each behind the one before), ``side-by-side`` (abreast)
            or ``diamond`` (4: a leader, two wings behind it to either side, one last).
        count: creatures (a diamond has 4).
        spacing: in body lengths: in line, the clear water from one's tail to the
            next one's head; side by side, between their axes; in a diamond both.
        length: the creature's body length [m].

    Raises:
        GroupError: an unknown kind, a bad count or spacing.
    """
    if kind not in FORMATIONS:
        raise GroupError(f"unknown formation {kind!r}; formations: {', '.join(FORMATIONS)}")
    if count < 1 or (kind == "diamond" and count != 4):
        raise GroupError(
            f"a formation needs a whole number of creatures >= 1, got {count}"
            + (" (a diamond has 4)" if kind == "diamond" else "")
        )
    if not (np.isfinite(spacing) and spacing > 0):
        raise GroupError(f"spacing must be a positive number of body lengths, got {spacing}")
    along, beside = (1 + spacing) * length, spacing * length  # head to head; axis to axis
    if kind == "in-line":
        places, ranks = [(-k * along, 0.0) for k in range(count)], list(range(count))
    elif kind == "side-by-side":
        places = [(0.0, (k - (count - 1) / 2) * beside) for k in range(count)]
        ranks = list(range(count))
    else:
        places = [(0.0, 0.0), (-along / 2, beside), (-along / 2, -beside), (-along, 0.0)]
        ranks = [0, 1, 1, 2]
    return [(Pose((x, y, 0.0)), rank) for (x, y), rank in zip(places, ranks, strict=True)]


def posed(model: Model, pose: Pose) -> np.ndarray:
    """``model``'s reference positions (nq,) moved and turned to ``pose``."""
    q = model.qpos0.copy()
    root = model.joints[0]
    offset = np.asarray(pose.offset, dtype=float)
    if root.kind == "free":
        turn = Rotation.from_rotvec([0.0, 0.0, pose.heading])
        q[root.qpos : root.qpos + 3] += offset
        w, x, y, z = q[root.qpos + 3 : root.qpos + 7]
        x, y, z, w = (turn * Rotation.from_quat([x, y, z, w])).as_quat()
        q[root.qpos + 3 : root.qpos + 7] = (w, x, y, z)
        return q
    slide_x, slide_y, hinge = model.joints[:3]  # planar: slide x, slide y, hinge z
    q[slide_x.qpos] += offset[0]
    q[slide_y.qpos] += offset[1]
    q[hinge.qpos] += pose.heading
    return q


def _default_labels(models) -> list[str]:
    names = [_stem(m.source) for m in models]
    return [f"{name}-{names[:i].count(name) + 1}" for i, name in enumerate(names)]


def _stem(source: str) -> str:
    name = source.replace("\\", "/").rsplit("/", 1)[-1]
    return name.split(".", 1)[0] or "creature"


def _check(models, labels, poses) -> None:
    problems = []
    if not (len(models) == len(labels) == len(poses)):
        raise GroupError(
            f"{len(models)} creatures, {len(labels)} labels and {len(poses)} poses: give one "
            "label and one pose per creature"
        )
    dims = {m.dim for m in models}
    if len(dims) > 1:
        problems.append(
            "2D and 3D creatures cannot share a fluid: "
            + ", ".join(f"{label} is {m.dim}D" for m, label in zip(models, labels, strict=True))
        )
    depths = {m.depth for m in models if m.dim == 2}
    if len(depths) > 1:
        listed = ", ".join(f"{label} {1e3 * m.depth:.3g} mm"
                           for m, label in zip(models, labels, strict=True))  # fmt: skip
        problems.append(
            f"2D creatures share one slab of water as deep as each prism, so their depths must "
            f"agree: {listed}"
        )
    repeated = sorted({label for label in labels if labels.count(label) > 1})
    if repeated:
        problems.append(f"labels must be unique: {', '.join(map(repr, repeated))} repeated")
    for label in labels:
        if not label or "/" in label:
            problems.append(f"label {label!r} must be a non-empty name without '/'")
    for model, label, pose in zip(models, labels, poses, strict=True):
        offset = np.asarray(pose.offset, dtype=float)
        if offset.shape != (3,) or not np.isfinite(offset).all():
            problems.append(f"{label}'s offset {pose.offset!r} must be three finite numbers [m]")
        elif model.dim == 2 and offset[2] != 0:
            problems.append(f"{label} is 2D: its offset's z must be 0, not {offset[2]:g}")
        if not np.isfinite(pose.heading):
            problems.append(f"{label}'s heading must be a finite angle [rad]")
        if model.dim == 3 and model.joints[0].kind != "free":
            problems.append(
                f"{label} ({model.source}) is a planar model swum in the 3D fluid; a group takes "
                "3D creatures with a free root (or 2D creatures in the 2D fluid)"
            )
    if problems:
        raise GroupError("; ".join(problems))


def _group_model(mj, xml: str, members, qpos0: np.ndarray) -> Model:
    """The composed model described as one ``Model``: the members' records shifted to their
    slices and renamed ``LABEL/NAME``, the links' facts and the box at the group's poses."""
    facts = describe(mj, qpos0)
    joints, dof_names, roots, actuated = [], [], [], []
    for m in members:
        for joint in m.model.joints:
            joints.append(replace(
                joint, name=f"{m.label}/{joint.name}" if joint.name else "",
                link=joint.link + m.links.start, qpos=joint.qpos + m.qpos.start,
                dof=joint.dof + m.dofs.start,
            ))  # fmt: skip
        dof_names += [f"{m.label}/{name}" for name in m.model.dof_names]
        roots.append(m.model.root_dofs + m.dofs.start)
        actuated.append(m.model.actuated_dofs + m.dofs.start)
    box = facts.geom_box
    bounds = np.stack([box[:, 0].min(axis=0), box[:, 1].max(axis=0)])
    models = [m.model for m in members]
    return Model(
        source=" + ".join(m.label for m in members),
        mj=mj,
        dim=models[0].dim,
        depth=models[0].depth,
        links=facts.link_names,
        link_mass=facts.link_mass,
        joints=tuple(joints),
        root_dofs=np.concatenate(roots),
        actuated_dofs=np.concatenate(actuated),
        dof_names=tuple(dof_names),
        lower=np.concatenate([m.lower for m in models]),
        upper=np.concatenate([m.upper for m in models]),
        mass=float(sum(m.mass for m in models)),
        bounds=bounds,
        extent=bounds[1] - bounds[0],
        body_length=max(m.body_length for m in models),
        qpos0=qpos0,
        notes=(),
        forward=(1.0, 0.0, 0.0),
        planar=all(m.planar for m in models),
        visuals=tuple(v for m in models for v in m.visuals),
        mjcf=xml,
    )


def member_gaps(group: Group, shape: BodyShape, surfaces, link_pos, link_rot) -> np.ndarray:
    """How far each member's surface keeps out of each other member, (n, n) [m].

    Entry ``(i, j)`` is the least signed distance of member ``i``'s surface
    patches (``surfaces[i]``, ``aquagait.body.surface``) to member ``j``'s links
    (``shape``, the group's): negative where ``i``'s surface lies inside
    ``j``; ``inf`` where no patch of ``i`` comes within the few samples of
    margin around ``j``'s links that their distance grids hold
    (``aquagait.body.shape.PAD``), and on the diagonal.

    Args:
        group: the group.
        shape: the group model's body shape.
        surfaces: each member's ``Surface``, in its own links.
        link_pos: (nlinks, 3) the group's link origins (``Dynamics.link_poses``) [m].
        link_rot: (nlinks, 3, 3) their rotations.
    """
    pos, rot = checked_pose(shape, link_pos, link_rot)
    arrays = baked_arrays(shape)
    n = len(group.members)
    gaps = np.full((n, n), np.inf)
    for i, member in enumerate(group.members):
        points, _ = surface_world(surfaces[i], link_pos[member.links], link_rot[member.links])
        points = np.ascontiguousarray(points)
        for j, other in enumerate(group.members):
            if j != i:
                links = np.arange(other.links.start, other.links.stop)
                gaps[i, j] = _least_distance(*arrays, rot, pos, links, points)
    return gaps


def deepest_overlap(group: Group, gaps: np.ndarray) -> tuple[Member, Member, str] | None:
    """The two members that overlap most (in group order), and how deep in words, from
    ``member_gaps``; None when none overlap."""
    if not (gaps < 0).any():
        return None
    i, j = np.unravel_index(np.argmin(gaps), gaps.shape)
    a, b = group.members[i], group.members[j]
    inside = f"{a.label}'s surface lies {1e3 * -gaps[i, j]:.3g} mm inside {b.label}"
    first, second = sorted((a, b), key=group.members.index)
    return first, second, inside


def refuse_overlap(group: Group, gaps: np.ndarray) -> None:
    """Refuse members that overlap at their starting poses (``gaps`` there).

    Raises:
        GroupError: which two, how deep, and what to change.
    """
    overlap = deepest_overlap(group, gaps)
    if overlap is not None:
        a, b, inside = overlap
        raise GroupError(
            f"{a.label} and {b.label} overlap at their starting poses ({inside}): place them "
            "further apart (a larger spacing)"
        )


@numba.njit(cache=True, nogil=True)
def _least_distance(sdf, offset, dims, lower, spacing, rot, pos, links, points):
    """The least signed distance of ``points`` (m, 3) to the links ``links`` [m]."""
    best = np.inf
    for p in range(points.shape[0]):
        x, y, z = points[p, 0], points[p, 1], points[p, 2]
        for k in links:
            if dims[k, 0] == 0:
                continue
            d = link_distance(sdf, offset[k], dims[k], lower[k], spacing, rot[k], pos[k], x, y, z)
            best = min(best, d)
    return best
