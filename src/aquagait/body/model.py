"""Creature models: load an MJCF, check it is a swimmer we can simulate, describe it.

A creature is one tree of links under the world (docs/method-bodies.md):

- 3D: the root link has a ``<freejoint/>`` (6 DOF: position, quaternion).
- 2D (planar): the root link has exactly the joints slide x, slide y, hinge z,
  in that order, and everything lives in the x-y plane. Every link is a prism
  of depth ``depth`` along z, centred on z = 0, so its mass is
  ``density * cross-section area * depth``. The depth is declared in the MJCF
  as ``<custom><numeric name="aquagait_depth" data="D"/></custom>`` [m], and
  every geom must be such a prism: a box with half-size ``D/2`` along z, a
  cylinder whose axis is z with half-height ``D/2``, or a mesh whose vertices
  all lie on z = +-D/2 (an extruded convex polygon).

Every other joint is actuated: hinge (1 DOF) or ball (3 DOF). Its ``range``
(degrees unless the MJCF says ``<compiler angle="radian"/>``) bounds the
gait, enforced by MuJoCo or not (``limited="false"``); a joint without one
takes the targets of its ``<position>`` servo, else +-``DEFAULT_RANGE``, with
a note. Masses and inertias are MuJoCo's, however the file gives them (geom
densities, MuJoCo's default being water's; geom ``mass``; ``<inertial>``);
the water sees each link's geoms, except hidden ones that only carry mass
and visual-only ones that are only drawn (``aquagait.body.reshape``).
Gravity is off. Allowed geoms: capsule, box, sphere, ellipsoid, cylinder, mesh.

A geom is *visual-only* when MuJoCo gives it no mass (``mass="0"``, or
``density="0"`` and no mass), it is visible (group below 3, alpha above 0),
and its link has another visible geom that has mass. It is taken out of the
physics model ``Model.mj`` before anything is checked or measured, so the
fluid's shape, voxels, the simple fluid's patches, self-collision, the tail
tip, the bounds and body length, thickening and ``aquagait check``'s tables
all ignore it; it is kept in ``Model.visuals`` for the pictures
(``aquagait.body.meshes``). A link whose visible geoms are all massless (the
control suites' fish, its mass on a hidden geom) keeps them as its shape.

What only describes scenery or another simulator's set-up (floors, lights,
cameras, materials, actuators, sensors, contacts, tendons, keyframes,
``<option>``, joint armature and damping) is ignored with one note per kind
(``Model.notes``; ``aquagait.body.mjcf`` says why for each). Every check
collects its problems: one ``ModelError`` lists them all, each naming the
element and what would be right, before MuJoCo's dynamics is ever called.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from aquagait.body.dynamics import (
    CompiledFacts,
    compile_mjcf,
    describe,
    massless_geoms,
    mesh_faces,
)
from aquagait.body.flatten import area, outlines, prism_depth, prism_xml
from aquagait.body.mjcf import ModelError, prepare_mjcf, read_mjcf
from aquagait.body.reshape import (
    VisualGeom,
    inertia_only,
    pin_inertia,
    thin_geoms,
    turn_root,
    visual_only,
    visual_record,
)
from aquagait.body.scenery import listing
from aquagait.body.shape import geom_volume

DEPTH_NAME = "aquagait_depth"
ACTUATED_KINDS = ("hinge", "ball")
DEFAULT_RANGE = np.radians(60.0)
"""A joint's gait bound [rad] when the model gives it no range and no position servo."""

HEAD_END = 0.1
"""For its end to be taken as the head (``Model.forward``), the root link's centre must lie
this many body lengths off the body's middle along the body's longest side, ..."""

ELONGATED = 1.5
"""... and that side be this many times the next longest (a fish, an eel, a swimmer; a
turtle, a frog or a ray, whose root is the middle of a wide body, faces +x unless its
side-car says otherwise)."""

X = np.array([1.0, 0.0, 0.0])

PLANAR_FLUIDS = ("2d", "3d")
"""Where a planar model swims (``load_model``'s ``planar_fluid``)."""

FLATTEN = -1.0
"""``_check_planar``'s depth for a planar model whose geoms are to be cut by its plane."""


@dataclass(frozen=True)
class Joint:
    """One MuJoCo joint.

    ``kind``: 'free', 'slide', 'hinge' or 'ball'; ``link``: index of the link it
    moves; ``qpos``/``dof``: first index into q (nq,) and qd (nv,); ``nq``/``nv``
    its sizes; ``range``: (lo, hi) [rad or m] for hinges and slides, (0, max
    rotation angle) for balls: MuJoCo's limits, or for an actuated joint without
    them the bounds its gait gets instead (``load_model``); None for an
    unlimited root joint; ``axis``: (3,) world axis at
    the reference pose (hinge and slide).
    """

    name: str
    kind: str
    link: int
    qpos: int
    dof: int
    nq: int
    nv: int
    range: tuple[float, float] | None
    axis: tuple[float, float, float]


@dataclass(frozen=True, eq=False)
class Model:
    """A checked creature model (fixed; shipped with the scene to workers).

    Attributes:
        source: the file path, or '<string>'.
        mj: the compiled MuJoCo model; opaque outside ``aquagait.body``.
        dim: 2 (planar prism) or 3.
        depth: the prism depth [m] in 2D, None in 3D.
        links: link names (MuJoCo bodies without the world), nlinks.
        link_mass: (nlinks,) [kg].
        joints: every joint, root first.
        root_dofs: (3,) in 2D (x, y, theta) or (6,) in 3D, indices into qd.
        actuated_dofs: (na,) indices into qd of the gait-driven DOFs.
        dof_names: (nv,) names: the joint name, or 'joint:x|y|z' for a ball's
            components and 'root:x|y|z|rx|ry|rz' for a free root.
        lower, upper: (na,) joint limits of the actuated DOFs [rad] (a ball
            joint's limit applies to each component).
        mass: total mass [kg] (2D: of the prism of depth ``depth``).
        bounds: (2, 3) lower and upper corners of the world bounding box of
            all geoms at the reference pose [m].
        extent: (3,) its sides [m].
        body_length: the longest of them [m].
        qpos0: (nq,) reference configuration.
        notes: one line per kind of MJCF content the loader ignored and why
            (a floor, lights, actuators, armature, ...); empty for a model that
            describes only the creature.
        forward: (3,) the direction its head points in the file's frame: given
            (the side-car's ``forward``), or, for an ``ELONGATED`` body whose root
            link lies ``HEAD_END`` body lengths or more towards one end of its
            longest side, the way to that end; else +x. The model is turned so
            that this is +x, the direction aquagait swims.
        planar: its root moves in the x-y plane (slide x, slide y, hinge z):
            every 2D model, and a planar model swum in the 3D fluid with its
            root held to its plane (``load_model``'s ``planar_fluid='3d'``).
        visuals: per link, its visual-only geoms (module doc), in the link's
            frame, for pictures only: not in ``mj``; () for a link without
            (every link of most models).
        mjcf: the MJCF text ``mj`` was compiled from (the fluid's shape, turned to
            face +x), for composing several creatures into one model
            (``aquagait.body.group``).
    """

    source: str
    mj: object
    dim: int
    depth: float | None
    links: tuple[str, ...]
    link_mass: np.ndarray
    joints: tuple[Joint, ...]
    root_dofs: np.ndarray
    actuated_dofs: np.ndarray
    dof_names: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    mass: float
    bounds: np.ndarray
    extent: np.ndarray
    body_length: float
    qpos0: np.ndarray
    notes: tuple[str, ...] = ()
    forward: tuple[float, float, float] = (1.0, 0.0, 0.0)
    planar: bool = False
    visuals: tuple[tuple[VisualGeom, ...], ...] = ()
    mjcf: str = field(default="", repr=False)

    @property
    def nq(self) -> int:
        return int(self.qpos0.shape[0])

    @property
    def nv(self) -> int:
        return len(self.dof_names)

    def joint(self, name: str) -> Joint:
        """The joint called ``name``; the error lists the known ones."""
        for joint in self.joints:
            if joint.name == name:
                return joint
        known = ", ".join(j.name for j in self.joints if j.name)
        raise KeyError(f"{self.source}: no joint {name!r}; joints: {known}")

    def dof(self, name: str) -> int:
        """Index into qd of the DOF called ``name`` (see ``dof_names``)."""
        if name not in self.dof_names:
            raise KeyError(f"{self.source}: no DOF {name!r}; DOFs: {', '.join(self.dof_names)}")
        return self.dof_names.index(name)


def load_model(
    mjcf: str | Path, thicken_to: float | None = None, forward=None, planar_fluid: str = "2d"
) -> Model:
    """Load and check an MJCF creature, listing every problem at once.

    What only describes scenery or another simulator's set-up (a floor,
    lights, actuators, sensors, armature, ``<option>``; ``aquagait.body.mjcf``
    lists it) is ignored, with one note per kind in ``Model.notes``.

    Args:
        mjcf: a path to an MJCF file, or the MJCF text itself (a string
            starting with '<').
        thicken_to: if given, every primitive geom thinner than this [m] is
            widened to it for the fluid, masses and inertias unchanged
            (``aquagait.body.reshape``), with a note naming each.
        forward: the direction the head points in the file's frame, (2,) or
            (3,); None: from the model (``Model.forward``). A creature facing
            elsewhere than +x is turned to face +x, with a note.
        planar_fluid: where a planar model (root slide x, slide y, hinge z)
            swims: '2d', the 2D fluid, its geoms as prisms (cut by the plane of
            motion where they are 3D shapes); or '3d', the 3D fluid with its
            shapes as they are and its root held to its plane (``Model.planar``).

    Returns:
        The checked ``Model``.

    Raises:
        ModelError: the file cannot be read, is not MJCF, or is not a swimmer we
            can simulate; ``problems`` lists each problem with its fix, and the
            message starts with the file.
    """
    text, path, source = read_mjcf(mjcf)
    prepared = prepare_mjcf(text, path, source)
    problems, notes = list(prepared.problems), list(prepared.notes)
    try:
        mj = compile_mjcf(xml=prepared.xml)
    except ValueError as err:
        raise ModelError(source, [*problems, prepared.compile_error(err)]) from None
    facts = describe(mj)
    xml, mj, facts, visuals = _drawn_only(prepared.xml, mj, facts, notes)
    if planar_fluid not in PLANAR_FLUIDS:
        raise ValueError(f"planar_fluid must be one of {PLANAR_FLUIDS}, got {planar_fluid!r}")
    root, dim, depth, ranges = _check_compiled(facts, prepared, problems, notes, planar_fluid)
    if problems:
        raise ModelError(source, problems)
    xml, mj, facts, depth = _fluid_shape(xml, mj, facts, root, dim, depth, thicken_to,
                                         notes, source)  # fmt: skip
    planar = _is_planar(facts, root)
    heading, why = _forward(facts, 2 if planar else dim, forward, problems)
    if problems:
        raise ModelError(source, problems)
    if not np.allclose(heading, X):
        notes.append(
            f"forward is the model's {direction_label(heading)} ({why}): turned to face +x, "
            "aquagait's forward, so positions in its swims are in the turned frame"
        )
        xml = turn_root(xml, facts, _turning(heading))
        mj = compile_mjcf(xml=xml)
        facts = describe(mj)
    forward = tuple(float(v) for v in heading)
    model = _build(mj, facts, source, dim, depth, root, ranges, tuple(notes), forward, planar,
                   visuals)  # fmt: skip
    return replace(model, mjcf=xml)


def _drawn_only(xml, mj, facts, notes):
    """The model without its visual-only geoms (module doc), MuJoCo's masses and
    inertias pinned (``aquagait.body.reshape``), and their records for the pictures.
    Returns ``(xml, mj, facts, visuals)``; as they were, and no visuals, if it has none."""
    if len(facts.geom_kind) <= len(facts.link_names):  # no link has two geoms
        return xml, mj, facts, ()
    drawn = visual_only(facts, massless_geoms(xml))
    if not drawn:
        return xml, mj, facts, ()
    notes.append(_visual_note(facts, drawn))
    visuals = visual_record(facts, mesh_faces(mj), drawn)
    xml = pin_inertia(xml, facts, drawn)
    mj = compile_mjcf(xml=xml)
    return xml, mj, describe(mj), visuals


def _fluid_shape(xml, mj, facts, root, dim, depth, thicken_to, notes, source):
    """The model rewritten into the shape the water sees (``aquagait.body.reshape``): hidden
    geoms dropped, thin ones thickened, a planar model's 3D shapes cut by its plane; MuJoCo's
    masses and inertias kept. Returns ``(xml, mj, facts, depth)``, as they were if nothing
    needed doing."""
    hidden = inertia_only(facts)
    if hidden:
        notes.append(_inertia_only_note(facts, hidden))
    sizes, meshes = thin_geoms(facts, thicken_to, dim == 2) if thicken_to else ({}, [])
    sizes = {g: size for g, size in sizes.items() if g not in hidden}
    meshes = [g for g in meshes if g not in hidden]
    if sizes or meshes:
        notes.append(_thickened_note(facts, thicken_to, sizes, meshes))
    if not (hidden or sizes or depth == FLATTEN):
        return xml, mj, facts, depth
    xml = pin_inertia(xml, facts, hidden, sizes)
    mj = compile_mjcf(xml=xml)
    facts = describe(mj)
    if depth != FLATTEN:
        return xml, mj, facts, depth
    xml, depth, note = _flattened(xml, mj, facts, root, _depth(facts, dim, []), source)
    notes.append(note)
    mj = compile_mjcf(xml=xml)
    facts = describe(mj)
    problems = []
    if _check_planar(facts, root, depth, problems, []) != depth or problems:
        raise ModelError(source, problems or ["its cut by the plane of motion is no prism"])
    return xml, mj, facts, depth


# --- checks on the compiled model ---------------------------------------------
# Each appends its problems, with their fixes, to ``problems`` and goes on.


def _check_compiled(facts: CompiledFacts, prepared, problems: list[str], notes: list[str],
                    planar_fluid: str = "2d"):  # fmt: skip
    """(root link, dimension, depth, gait ranges); a part that cannot be known is None.

    A planar model's depth is ``FLATTEN`` when its geoms are to be cut by the plane of
    motion (``_check_planar``)."""
    root = _check_tree(facts, problems)
    if root is None:
        return None, None, None, None
    dim = _root_dimension(facts, root, problems)
    ranges = _gait_ranges(facts, root, prepared, problems, notes)
    if dim is None:
        return root, None, None, ranges
    if dim == 2 and planar_fluid == "3d":
        dim = 3
        unused = " (its aquagait_depth unused)" if DEPTH_NAME in facts.numeric else ""
        notes.append(
            "planar, swum in the 3D fluid: its shapes as they are, its root held to the plane "
            f"it moves in (slide x, slide y, hinge z){unused}"
        )
        return root, dim, None, ranges
    depth = _depth(facts, dim, problems)
    if dim == 2:
        depth = _check_planar(facts, root, depth, problems, notes)
    return root, dim, depth, ranges


def _is_planar(facts: CompiledFacts, root: int) -> bool:
    """Whether the root moves in the x-y plane (slide x, slide y, hinge z)."""
    return [facts.joint_kind[j] for j in np.flatnonzero(facts.joint_link == root)] == [
        "slide", "slide", "hinge"]  # fmt: skip


def _link(facts: CompiledFacts, k: int) -> str:
    name = facts.link_names[k]
    return f"link {name!r}" if name else f"link #{k}"


def _joint(facts: CompiledFacts, j: int) -> str:
    name = facts.joint_names[j]
    label = f"joint {name!r}" if name else f"joint #{j}"
    return f"{label} in {_link(facts, facts.joint_link[j])}"


def _check_tree(facts: CompiledFacts, problems: list[str]) -> int | None:
    roots = np.flatnonzero(facts.parent == -1)
    if roots.size == 0:
        problems.append("no bodies in <worldbody>; a creature needs at least one")
        return None
    if roots.size > 1:
        names = ", ".join(_link(facts, k) for k in roots)
        problems.append(
            f"several bodies directly in <worldbody> ({names}); a creature is one tree under "
            "one root body: nest the others inside it, or remove them"
        )
        return None
    return int(roots[0])


def _root_dimension(facts: CompiledFacts, root: int, problems: list[str]) -> int | None:
    joints = np.flatnonzero(facts.joint_link == root)
    kinds = [facts.joint_kind[j] for j in joints]
    fix = (
        "give the root body <freejoint/> (3D) or the joints slide x, slide y, "
        "hinge z in that order (2D)"
    )
    if not kinds:
        problems.append(f"no root joint: {_link(facts, root)} is fixed; {fix}")
        return None
    if kinds == ["free"]:
        return 3
    planar = np.eye(3)
    axes = facts.joint_axis[joints] if len(joints) == 3 else None
    if kinds == ["slide", "slide", "hinge"] and np.allclose(axes, planar, atol=1e-9):
        return 2
    problems.append(
        f"the root joints of {_link(facts, root)} are {kinds}; {fix}, "
        "with the axes along world x, y, z"
    )
    return None


def _gait_ranges(facts: CompiledFacts, root: int, prepared, problems: list[str], notes: list[str]):
    """Each actuated joint's range for the gait, {joint index: (lo, hi)} [rad].

    MuJoCo's own limits where they are on; else, with a note per kind, the
    range given but switched off (``limited="false"``), the targets of the
    joint's position servo, or ``DEFAULT_RANGE``. A ball's range is (0, max angle).
    """
    ranges, switched_off, servo, default = {}, [], [], []
    for j in np.flatnonzero(facts.joint_link != root):
        kind, (lo, hi) = facts.joint_kind[j], facts.joint_range[j]
        if kind not in ACTUATED_KINDS:
            problems.append(
                f"{_joint(facts, j)} is a {kind} joint; below the root only hinge and ball "
                "joints are allowed: make it a hinge or a ball, or remove it"
            )
            continue
        name = facts.joint_names[j]
        if (hi > lo if kind == "hinge" else hi > 0) and not facts.joint_limited[j]:
            if prepared.angle != "radian":  # MuJoCo converts only the ranges it enforces
                lo, hi = np.radians(lo), np.radians(hi)
            switched_off.append(j)
        elif not hi > lo and kind == "hinge" and name in prepared.servos:
            lo, hi = prepared.servos[name]
            servo.append(j)
        elif not hi > lo:
            lo, hi = (-DEFAULT_RANGE, DEFAULT_RANGE) if kind == "hinge" else (0.0, DEFAULT_RANGE)
            default.append(j)
        ranges[int(j)] = (float(lo), float(hi))
    if switched_off:
        notes.append(
            f"{_joints(facts, switched_off)} a range that is switched off "
            '(limited="false"): it bounds the gait\'s amplitudes and offsets'
        )
    if servo:
        targets = ", ".join(f"{facts.joint_names[j]!r} {ranges[j][0]:.3g} to {ranges[j][1]:.3g} rad"
                            for j in servo)  # fmt: skip
        notes.append(
            f"{_joints(facts, servo)} no range: the targets of its position servo bound "
            f"the gait instead ({targets})"
        )
    if default:
        notes.append(
            f"{_joints(facts, default)} no range and no position servo: the gait is bounded "
            f"at +-{np.degrees(DEFAULT_RANGE):g} degrees (give the joint a range to choose)"
        )
    return ranges


def _labels(names, indices) -> list[str]:
    """How notes name joints or geoms: the quoted name, or '#index' for an unnamed one."""
    return [repr(names[i]) if names[i] else f"#{i}" for i in indices]


def _joints(facts: CompiledFacts, js) -> str:
    """ "joint 'a' has" or "3 joints ('a', 'b', 'c') have"."""
    labels = _labels(facts.joint_names, js)
    if len(labels) == 1:
        return f"joint {labels[0]} has"
    return f"{len(labels)} joints ({listing(labels)}) have"


def _geom(facts: CompiledFacts, g: int) -> str:
    name = facts.geom_names[g]
    label = f"geom {name!r}" if name else f"geom #{g}"
    return f"{label} in {_link(facts, facts.geom_link[g])}"


def _depth(facts: CompiledFacts, dim: int, problems: list[str]) -> float | None:
    declared = facts.numeric.get(DEPTH_NAME)
    if dim == 3:
        if declared is not None:
            problems.append(
                f"numeric {DEPTH_NAME!r} is set but the root is a free joint (3D); "
                "the depth belongs to planar models only: remove it"
            )
        return None
    if declared is None:
        return None
    if declared.size != 1 or not declared[0] > 0:
        problems.append(
            f"numeric {DEPTH_NAME!r} is {declared.tolist()}; it must be one positive number [m]"
        )
        return None
    return float(declared[0])


def _check_planar(facts: CompiledFacts, root: int, depth, problems, notes) -> float | None:
    """Joints about z and links in the root's plane; the prism depth, or ``FLATTEN``.

    A model whose geoms are all z-prisms at z = 0 (box, cylinder along z, mesh
    with its vertices on two faces) of the declared depth, or of one thickness
    when none is declared, swims as it is; any other is cut by its plane of
    motion (``aquagait.body.flatten``) and ``FLATTEN`` is returned.
    """
    tol = 1e-6 * max(depth or 0.0, 1e-3)
    for j in np.flatnonzero(facts.joint_link != root):
        kind = facts.joint_kind[j]
        if kind in ACTUATED_KINDS and (
            kind != "hinge" or abs(abs(facts.joint_axis[j, 2]) - 1) > 1e-9
        ):
            problems.append(
                f"the model is planar (2D) but {_joint(facts, j)} is not a hinge about z; "
                'a planar creature bends only in the x-y plane: make it a hinge with axis="0 0 1"'
            )
    plane = facts.link_pos[root, 2]
    for k in np.flatnonzero(np.abs(facts.link_pos[:, 2] - plane) > tol):
        problems.append(
            f"the model is planar (2D) but {_link(facts, k)} is at z = {facts.link_pos[k, 2]:g}, "
            f"off the plane its root moves in (z = {plane:g}); every link must lie in that plane"
        )
    prisms = all(_prism_problem(facts, g, depth, tol) is None for g in range(len(facts.geom_kind)))
    if not prisms or abs(plane) > tol:
        return FLATTEN
    if depth is None:
        thick = {round(t / tol) for t in _prism_thickness(facts)}
        if len(thick) != 1:
            return FLATTEN
        depth = float(_prism_thickness(facts)[0])
        notes.append(f"prism depth {depth * 1e3:.4g} mm: its geoms' thickness along z")
    return depth


def _prism_thickness(facts: CompiledFacts) -> list[float]:
    """Each z-prism geom's thickness along z [m]."""
    out = []
    for g, kind in enumerate(facts.geom_kind):
        if kind == "mesh":
            z = facts.geom_vertices[g][:, 2]
            out.append(float(z.max() - z.min()))
        else:
            out.append(2 * float(facts.geom_size[g][2 if kind == "box" else 1]))
    return out


def _prism_problem(facts: CompiledFacts, g: int, depth, tol: float) -> str | None:
    kind, size, rot = facts.geom_kind[g], facts.geom_size[g], facts.geom_rot[g]
    if kind not in ("box", "cylinder", "mesh"):
        return f"is {'an' if kind[0] in 'aeiou' else 'a'} {kind}"
    if abs(facts.geom_pos[g, 2]) > tol and kind != "mesh":
        return f"is centred at z = {facts.geom_pos[g, 2]:g}"
    if kind in ("box", "cylinder"):
        if abs(abs(rot[2, 2]) - 1) > 1e-9:
            return "is tilted out of the x-y plane"
        half = size[2] if kind == "box" else size[1]
        if depth is not None and abs(half - depth / 2) > tol:
            return f"has z half-size {half:g}"
        return None
    if depth is None:
        return None
    off = np.abs(np.abs(facts.geom_vertices[g][:, 2]) - depth / 2)
    if off.max() > tol:
        return f"has a vertex at z = {facts.geom_vertices[g][off.argmax(), 2]:.4g}"
    return None


def _inertia_only_note(facts: CompiledFacts, geoms) -> str:
    labels = _labels(facts.geom_names, geoms)
    links = sorted({_link(facts, facts.geom_link[g]) for g in geoms})
    what = f"geom {labels[0]}" if len(labels) == 1 else f"{len(labels)} geoms ({listing(labels)})"
    verb = "gives" if len(labels) == 1 else "give"
    where = listing(links) if len(links) <= 2 else f"{len(links)} links"
    return (
        f"{what} of {where}, hidden (group >= 3 or alpha 0), only {verb} mass: the "
        "water sees each link's visible geoms (MuJoCo's masses and inertias unchanged)"
    )


def _visual_note(facts: CompiledFacts, geoms) -> str:
    labels = _labels(facts.geom_names, geoms)
    links = sorted({_link(facts, facts.geom_link[g]) for g in geoms})
    what = f"geom {labels[0]}" if len(labels) == 1 else f"{len(labels)} geoms ({listing(labels)})"
    where = listing(links) if len(links) <= 2 else f"{len(links)} links"
    verb = "is" if len(labels) == 1 else "are"
    return (
        f"{what} of {where} {verb} only drawn (massless and visible, beside a visible geom "
        "with mass): the water, the masses and the checks see the geoms with mass"
    )


def _thickened_note(facts: CompiledFacts, minimum: float, sizes: dict, meshes: list) -> str:
    """Which geoms were widened for the fluid, from what to what, and which meshes were not."""
    parts = []
    for g, size in sizes.items():
        (label,) = _labels(facts.geom_names, [g])
        was = 2 * facts.geom_size[g][size != facts.geom_size[g]].min()
        parts.append(f"{label} {was * 1e3:.3g} -> {minimum * 1e3:.3g} mm")
    said = []
    if parts:
        said.append(
            f"thickened for the fluid to {minimum * 1e3:.3g} mm: {listing(parts, 6)} (masses "
            "and inertias unchanged; --no-thicken keeps them as written)"
        )
    if meshes:
        labels = _labels(facts.geom_names, meshes)
        said.append(f"mesh geoms thinner than {minimum * 1e3:.3g} mm are not thickened: "
                    f"{listing(labels)}")  # fmt: skip
    return "; ".join(said)


def _forward(facts: CompiledFacts, dim: int, given, problems: list[str]):
    """The head's direction in the file's frame (``Model.forward``) and why."""
    if given is not None:
        heading = np.zeros(3)
        heading[: len(given)] = given
        if dim == 2 and heading[2] != 0:
            problems.append(
                f"forward {list(given)} leaves the plane of a planar model: give [x, y]"
            )
        if not np.linalg.norm(heading) > 0:
            problems.append("forward [0, 0, 0] has no direction: give the way the head points")
            return X, ""
        return heading / np.linalg.norm(heading), "as the side-car's forward says"
    box = facts.geom_box
    lo, hi = box[:, 0].min(axis=0), box[:, 1].max(axis=0)
    mine = facts.geom_link == 0
    offset = ((box[mine, 0].min(axis=0) + box[mine, 1].max(axis=0)) / 2 - (lo + hi) / 2)[:dim]
    sides = (hi - lo)[:dim]
    axis, (second, length) = int(np.argmax(sides)), np.sort(sides)[-2:]
    if length < ELONGATED * second or abs(offset[axis]) < HEAD_END * length:
        return X, ""
    heading = np.zeros(3)
    heading[axis] = np.sign(offset[axis])
    return heading, f"its root link {facts.link_names[0]!r} lies towards that end"


def direction_label(v) -> str:
    """A direction (3,) for people: '+y' for an axis, else the vector."""
    for i, name in enumerate("xyz"):
        if abs(abs(v[i]) - 1) < 1e-12:
            return ("+" if v[i] > 0 else "-") + name
    return "[" + ", ".join(f"{c:.3g}" for c in v) + "]"


def _turning(heading) -> np.ndarray:
    """The rotation that takes ``heading`` (a unit (3,)) to +x: about z when it lies in
    the x-y plane (a planar creature stays in its plane), else the shortest one."""
    h = np.asarray(heading, dtype=float)
    if abs(h[2]) < 1e-12 or np.allclose(h, -X):
        angle = -np.arctan2(h[1], h[0])
        c, s = np.cos(angle), np.sin(angle)
        return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    axis = np.cross(h, X)
    sin, cos = np.linalg.norm(axis), h @ X
    k = axis / sin
    cross = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + sin * cross + (1 - cos) * cross @ cross


def _flattened(xml: str, mj, facts: CompiledFacts, root: int, declared, source: str):
    """A planar model's geoms cut by its plane of motion (``aquagait.body.flatten``):
    the new MJCF text, the prism depth and a note saying what was done."""
    faces = mesh_faces(mj)
    plane = float(facts.link_pos[root, 2])
    shapes = outlines(facts, faces, plane)
    volumes = np.array([geom_volume(kind, facts.geom_size[g], facts.geom_vertices[g], faces[g])
                        for g, kind in enumerate(facts.geom_kind)])  # fmt: skip
    if all(s is None for s in shapes):
        raise ModelError(source, "the plane its root moves in misses every geom: nothing to swim")
    depth = declared if declared is not None else prism_depth(volumes, shapes)
    why = "declared" if declared is not None else "the geoms' volume over their outlines' area"
    links = len(facts.link_names)
    prism, solid = np.zeros(links), np.zeros(links)
    for g, s in enumerate(shapes):
        if s is not None:
            prism[facts.geom_link[g]] += area(s) * depth
            solid[facts.geom_link[g]] += volumes[g]
    ratio = prism[solid > 0] / solid[solid > 0] - 1
    missed = _labels(facts.geom_names, [g for g, s in enumerate(shapes) if s is None])
    note = (
        f"planar with 3D shapes: each geom is its cross-section by the plane of motion (z = "
        f"{plane:g}) as a prism {depth * 1e3:.4g} mm deep ({why}; each link's prism volume "
        f"{ratio.min():+.1%} to {ratio.max():+.1%} of its 3D volume)"
        + (", moved to z = 0" if plane else "")
    )
    if missed:
        note += f"; the plane misses {listing(missed)}, which shape nothing"
    return prism_xml(xml, facts, shapes, depth, plane), depth, note


# --- the description ------------------------------------------------------------


def _build(mj, facts: CompiledFacts, source, dim, depth, root, ranges, notes, forward,
           planar, visuals) -> Model:  # fmt: skip
    joints = tuple(_joint_record(facts, j, ranges.get(j)) for j in range(len(facts.joint_names)))
    dof_names = [""] * facts.nv
    for joint in joints:
        for i, name in enumerate(_dof_labels(joint)):
            dof_names[joint.dof + i] = name
    root_dofs = np.array([d for j in joints if j.link == root for d in range(j.dof, j.dof + j.nv)])
    actuated = [j for j in joints if j.link != root]
    lower = np.concatenate([_limits(j)[0] for j in actuated]) if actuated else np.zeros(0)
    upper = np.concatenate([_limits(j)[1] for j in actuated]) if actuated else np.zeros(0)
    box = facts.geom_box
    bounds = np.stack([box[:, 0].min(axis=0), box[:, 1].max(axis=0)])
    extent = bounds[1] - bounds[0]
    return Model(
        source=source,
        mj=mj,
        dim=dim,
        depth=depth,
        links=facts.link_names,
        link_mass=facts.link_mass,
        joints=joints,
        root_dofs=root_dofs,
        actuated_dofs=np.array([d for j in actuated for d in range(j.dof, j.dof + j.nv)], int),
        dof_names=tuple(dof_names),
        lower=lower,
        upper=upper,
        mass=float(facts.link_mass.sum()),
        bounds=bounds,
        extent=extent,
        body_length=float(extent.max()),
        qpos0=facts.qpos0,
        notes=notes,
        forward=forward,
        planar=planar,
        visuals=visuals or tuple(() for _ in facts.link_names),
    )


def _joint_record(facts: CompiledFacts, j: int, gait_range) -> Joint:
    """Joint ``j``; an actuated joint's range is ``gait_range`` (``_gait_ranges``), a
    root joint's MuJoCo's own (None when unlimited)."""
    kind = facts.joint_kind[j]
    nq, nv = {"free": (7, 6), "ball": (4, 3), "hinge": (1, 1), "slide": (1, 1)}[kind]
    lo, hi = facts.joint_range[j]
    if gait_range is None and facts.joint_limited[j]:
        gait_range = (float(lo), float(hi))
    return Joint(
        name=facts.joint_names[j],
        kind=kind,
        link=int(facts.joint_link[j]),
        qpos=int(facts.joint_qpos[j]),
        dof=int(facts.joint_dof[j]),
        nq=nq,
        nv=nv,
        range=gait_range,
        axis=tuple(float(a) for a in facts.joint_axis[j]),
    )


def _dof_labels(joint: Joint) -> list[str]:
    name = joint.name or f"joint{joint.dof}"
    if joint.kind == "free":
        return [f"root:{s}" for s in ("x", "y", "z", "rx", "ry", "rz")]
    if joint.kind == "ball":
        return [f"{name}:{s}" for s in "xyz"]
    return [name]


def _limits(joint: Joint) -> tuple[np.ndarray, np.ndarray]:
    lo, hi = joint.range
    if joint.kind == "ball":
        return np.full(3, -hi), np.full(3, hi)
    return np.array([lo]), np.array([hi])
