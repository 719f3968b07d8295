"""The shape the water sees, apart from the masses MuJoCo computed.

MuJoCo's compiled masses and inertias are the truth for the dynamics, however
the file gives them: from geom densities (MuJoCo's default is water's, 1000
kg/m^3), geom ``mass=``, or a body's ``<inertial>``. What the water sees is
the union of the link's geoms, with one exception: files written for other
simulators often carry a link's mass on a geom nobody is meant to see (the
control suites' fish and swimmer put it on a box in a hidden group, or a fully
transparent one) and draw the link with massless geoms. Such an
*inertia-only* geom, hidden (MuJoCo's ``group`` 3 or above, which its viewer
does not show) or invisible (``rgba`` alpha 0) on a link that has a visible
geom, gives the link its mass but no shape. A link whose geoms are all hidden
keeps them as its shape.

The other way round, a file may draw a link finer than the water can see it:
a *visual-only* geom (``visual_only``) is one MuJoCo gives no mass (``mass``
0, or ``density`` 0 and no ``mass``; ``aquagait.body.dynamics.massless_geoms``),
visible (group below 3 and alpha above 0), on a link that also has a visible
geom with mass. It gives neither mass nor shape: it is removed from the
physics model before any check or measure (fluid shape, voxels, the simple
fluid's patches, self-collision, tail tip, bounds, thickening) and kept as a
``VisualGeom`` record for pictures only (``Model.visuals``,
``aquagait.body.meshes``). Where no visible geom of a link has mass (the
control suites' fish: its mass on a hidden geom, its looks on massless
visible ones), its visible geoms stay its shape, as before: only a massive
visible geom makes its massless neighbours visual.

To take a geom out of the water's view without changing the motion, the MJCF
is rewritten (``pin_inertia``): every body gets an ``<inertial>`` holding the
mass, centre of mass and principal inertia MuJoCo compiled for it, the
compiler is told to take inertia from those (``inertiafromgeom="false"``), and
the inertia-only (and visual-only) geoms are removed; compiled again, the
model moves exactly as before and its geoms are the shape.

The same rewrite thickens thin parts for the fluid (``thin_geoms``): a grid
sees a part well only when it is a cell or two thick (docs/own-creature.md), and
fins written for MuJoCo's own fluid model are often 2 mm plates. A primitive
geom thinner than a given minimum (``aquagait.creatures`` asks for one cell
of the default grid, as thick as the library's creatures were built) across
any of its sides gets that side widened to the minimum (its other sides, its
centre and its axes kept); its link's mass and inertia stay MuJoCo's, since
they are pinned. Meshes are not thickened (a note names them).

Last, a creature whose head points elsewhere than +x, the direction every
objective, metric and manoeuvre takes as forward, is turned as a whole to
face +x (``turn_root``): its root body's frame is rotated, and a planar root's
slide and hinge axes are rewritten so that they stay along world x, y and z.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass

import numpy as np

from aquagait.body.rotations import quat_from_matrix
from aquagait.body.scenery import kids, remove_from

HIDDEN_GROUP = 3
"""MuJoCo's viewer shows geom groups 0-2 by default; 3 and above are hidden."""

PLACEMENT = ("fromto", "pos", "quat", "euler", "axisangle", "xyaxes", "zaxis", "size")
"""The attributes that place and size a geom, replaced when it is rewritten."""

PLAIN_CLASS = "aquagait_plain"
"""A default class holding only the model's top-level defaults, for rewritten geoms."""


def inertia_only(facts) -> list[int]:
    """Indices of the geoms that give mass but no shape (module doc), by link.

    Args:
        facts: ``aquagait.body.dynamics.CompiledFacts`` of the compiled model.
    Returns:
        geom indices, ascending; empty when every geom shapes its link.
    """
    hidden = (facts.geom_group >= HIDDEN_GROUP) | (facts.geom_rgba[:, 3] == 0)
    dropped = []
    for link in range(len(facts.link_names)):
        geoms = np.flatnonzero(facts.geom_link == link)
        if hidden[geoms].any() and not hidden[geoms].all():
            dropped += geoms[hidden[geoms]].tolist()
    return sorted(dropped)


def visual_only(facts, massless) -> list[int]:
    """Indices of the geoms that are only drawn (module doc): massless, visible, on a
    link that has a visible geom with mass.

    Args:
        facts: ``aquagait.body.dynamics.CompiledFacts`` of the compiled model.
        massless: (ng,) bool, the geoms MuJoCo gives no mass (``massless_geoms``).
    Returns:
        geom indices, ascending; empty when every visible geom shapes its link.
    """
    visible = (facts.geom_group < HIDDEN_GROUP) & (facts.geom_rgba[:, 3] > 0)
    drawn = visible & np.asarray(massless, dtype=bool)
    massive = visible & ~drawn
    links = set(facts.geom_link[massive].tolist())
    return [g for g in np.flatnonzero(drawn).tolist() if facts.geom_link[g] in links]


@dataclass(frozen=True, eq=False)
class VisualGeom:
    """A geom that is only drawn (``visual_only``), in its link's frame.

    Attributes:
        name: the geom's name ('' if it has none).
        kind: 'box', 'sphere', 'ellipsoid', 'capsule', 'cylinder' or 'mesh'.
        size: (3,) MuJoCo's size [m] (radii, half-lengths, half-sides).
        pos: (3,) its centre in the link frame [m].
        rot: (3, 3) its axes in the link frame (columns).
        rgba: (4,) colour in [0, 1].
        vertices: (n, 3) a mesh's vertices in the geom's frame [m]; None otherwise.
        faces: (m, 3) a mesh's triangles (vertex indices, counter-clockwise seen
            from outside); None otherwise.
    """

    name: str
    kind: str
    size: np.ndarray
    pos: np.ndarray
    rot: np.ndarray
    rgba: np.ndarray
    vertices: np.ndarray | None = None
    faces: np.ndarray | None = None


def visual_record(facts, faces, geoms) -> tuple[tuple[VisualGeom, ...], ...]:
    """The visual-only ``geoms`` of each link as ``VisualGeom`` records, in link frames.

    Args:
        facts: the compiled model's ``CompiledFacts`` (at ``qpos0``).
        faces: its ``mesh_faces``.
        geoms: the geom indices to record (``visual_only``).
    Returns:
        per link (in link order), its visual geoms' records; () for a link without.
    """
    out = [[] for _ in facts.link_names]
    for g in geoms:
        link = int(facts.geom_link[g])
        p0, r0 = facts.link_pos[link], facts.link_rot[link]  # x_link = R0^T (x_world - p0)
        centre, rot, mesh = facts.geom_pos[g], facts.geom_rot[g], facts.geom_vertices[g]
        out[link].append(VisualGeom(
            name=facts.geom_names[g],
            kind=facts.geom_kind[g],
            size=facts.geom_size[g].copy(),
            pos=(centre - p0) @ r0,
            rot=r0.T @ rot,
            rgba=facts.geom_rgba[g].copy(),
            vertices=None if mesh is None else (mesh - centre) @ rot,
            faces=None if mesh is None else faces[g].copy(),
        ))  # fmt: skip
    return tuple(tuple(link) for link in out)


def thin_geoms(facts, minimum: float, planar: bool) -> tuple[dict[int, np.ndarray], list[int]]:
    """The primitive geoms thinner than ``minimum`` [m], each with its thickened size.

    Args:
        facts: the compiled model's ``CompiledFacts``.
        minimum: the thickness every part should have [m].
        planar: a planar (2D) model: only the sides along axes in the plane count
            (a prism's depth along z is the model's, not a thickness).
    Returns:
        ``(sizes, meshes)``: geom index -> its new MuJoCo size (3,) [m], for each
        primitive with a side under ``minimum``; and the mesh geoms that are
        that thin, left as they are.
    """
    half = minimum / 2
    sizes, meshes = {}, []
    for g, kind in enumerate(facts.geom_kind):
        size = facts.geom_size[g].copy()
        if kind == "mesh":
            lo, hi = facts.geom_box[g]
            sides = (hi - lo)[:2] if planar else hi - lo
            if sides.min() < minimum:
                meshes.append(g)
            continue
        # the entries of a MuJoCo size that are half-thicknesses (radii and half-sides); in
        # a planar model only those along axes in the plane, not along its depth
        seen = [not planar or abs(facts.geom_rot[g][2, i]) < 0.5 for i in range(3)]
        across = {
            "box": [i for i in range(3) if seen[i]],
            "ellipsoid": [i for i in range(3) if seen[i]],
            "cylinder": [0, 1] if seen[2] else [0],  # the height runs along the axis, z
            "capsule": [0],
            "sphere": [0],
        }[kind]
        thin = [i for i in across if size[i] < half]
        if thin:
            size[thin] = half
            sizes[g] = size
    return sizes, meshes


def pin_inertia(xml: str, facts, drop=(), sizes=None) -> str:
    """The MJCF ``xml`` with every body's compiled inertia pinned, ``drop`` removed
    and the geoms in ``sizes`` given those sizes.

    Args:
        xml: the MJCF text MuJoCo compiled into ``facts`` (one element per
            body and geom, as ``aquagait.body.mjcf.prepare_mjcf`` writes it).
        facts: its ``CompiledFacts``: the masses, centres of mass and principal
            inertias to pin.
        drop: indices of geoms to remove.
        sizes: geom index -> MuJoCo size (3,) [m] (``thin_geoms``); the geom is
            rewritten in MuJoCo's compiled form (type, pos, quat, size in its
            link's frame) with that size.
    Returns:
        MJCF text whose compiled model has the same link masses and inertias,
        the remaining geoms only, and the new sizes.
    Raises:
        RuntimeError: the text's bodies or geoms do not line up with the
            compiled model's (a bug here, not in the user's file).
    """
    root = ET.fromstring(xml)
    bodies, geoms = elements(root, facts)
    for k, body in enumerate(bodies):
        for old in body.findall("inertial"):
            body.remove(old)
        pinned = ET.Element("inertial", {
            "pos": numbers(facts.link_ipos[k]),
            "quat": numbers(facts.link_iquat[k]),
            "mass": repr(float(facts.link_mass[k])),
            "diaginertia": numbers(facts.link_inertia[k]),
        })  # fmt: skip
        body.insert(0, pinned)
    for g, size in (sizes or {}).items():
        _, geom = geoms[g]
        detach(root, geom, facts, g)
        geom.set("type", facts.geom_kind[g])
        geom.set("pos", numbers(facts.geom_local_pos[g]))
        geom.set("quat", numbers(facts.geom_local_quat[g]))
        geom.set("size", numbers(size))
    for g in drop:
        remove_from(*geoms[g])
    compilers = root.findall("compiler")
    if not compilers:
        compilers = [ET.Element("compiler")]
        root.insert(0, compilers[0])
    for compiler in compilers:
        compiler.set("inertiafromgeom", "false")
    return ET.tostring(root, encoding="unicode")


def elements(root, facts) -> tuple[list, list]:
    """The parsed MJCF's body elements and its (body, geom) element pairs, each list in the
    compiled model's order (MuJoCo numbers bodies depth first, and a body's geoms in turn).

    Raises:
        RuntimeError: they do not line up with ``facts`` (a bug here, not in the user's file).
    """
    bodies = list(root.find("worldbody").iter("body"))
    geoms = [(body, geom) for body in bodies for geom in kids(body, "geom")]
    if len(bodies) != len(facts.link_names) or len(geoms) != len(facts.geom_kind):
        raise RuntimeError(
            f"{len(bodies)} bodies and {len(geoms)} geoms in the MJCF text, "
            f"{len(facts.link_names)} and {len(facts.geom_kind)} compiled"
        )
    return bodies, geoms


def detach(root, geom, facts, g: int) -> None:
    """Free the element of geom ``g`` from its placement and its default class, to be
    placed anew: a class may carry a ``fromto`` that would override a new frame or type.
    Its colour and group are kept, written out."""
    defaults = root.find("default")
    if defaults is None:
        defaults = ET.Element("default")
        root.insert(0, defaults)
    if not any(d.get("class") == PLAIN_CLASS for d in defaults.findall("default")):
        ET.SubElement(defaults, "default", {"class": PLAIN_CLASS})
    for placement in PLACEMENT:
        geom.attrib.pop(placement, None)
    geom.set("class", PLAIN_CLASS)
    geom.set("rgba", numbers(facts.geom_rgba[g]))
    geom.set("group", str(int(facts.geom_group[g])))


def numbers(values) -> str:
    """Numbers as MJCF writes them: space-separated, each exact (its repr)."""
    return " ".join(repr(float(v)) for v in values)


ORIENTATION = ("quat", "euler", "axisangle", "xyaxes", "zaxis")
"""The attributes that can orient a body."""


def turn_root(xml: str, facts, rot) -> str:
    """The MJCF ``xml`` with its creature turned by ``rot`` about the world origin.

    Args:
        xml: the MJCF text MuJoCo compiled into ``facts``.
        facts: its ``CompiledFacts`` (the root's pose and joint axes at qpos0).
        rot: (3, 3) the rotation to apply.
    Returns:
        MJCF text whose root body sits at ``rot @ pos``, turned by ``rot``, with
        its slide and hinge joints along the same world axes as before.
    """
    root = ET.fromstring(xml)
    body = elements(root, facts)[0][0]
    rot = np.asarray(rot, dtype=float)
    turned = rot @ facts.link_rot[0]
    for attr in ORIENTATION:
        body.attrib.pop(attr, None)
    body.set("pos", numbers(rot @ facts.link_pos[0]))
    body.set("quat", numbers(quat_from_matrix(turned)))
    axes = [j for j in range(len(facts.joint_kind)) if facts.joint_link[j] == 0]
    for j, joint in zip(axes, kids(body, "joint"), strict=False):
        if facts.joint_kind[j] in ("slide", "hinge"):
            joint.set("axis", numbers(turned.T @ facts.joint_axis[j]))
    return ET.tostring(root, encoding="unicode")
