"""Write ``src/aquagait/creatures/frog.xml``: a swimming frog, 9 actuated hinges per side.

Run from the repository root: ``python tools/make_frog.py``. The numbers and
their sources are in ``src/aquagait/creatures/frog.py``; this script only
turns them into MJCF. Every link is a convex mesh: limb segments are hulls of
two elliptic sections (one at each joint), the body a hull of elliptic
sections along its length, the foot web an 8-vertex plate.

The frog swims towards +x with z up and its snout at x = +0.04 m. No body
frame is turned: every joint axis is written in world coordinates at the
reference pose, which is the middle of the kick (the gait's offset is 0, so
the legs swing about it). The right limbs (y < 0) are the left ones
reflected in the x-z plane, joint axes included (``n_right = M n_left``);
reflecting a rotation reverses its sense, so the mirrored gait is
``qbar_right = -qbar_left`` (``mirror`` sign -1 in ``frog.aquagait.json``).

The web plate is 7 mm thick and the tarsus and forelimbs 7.2 mm across, so
that the grid's 4 mm cells see them; a real web is under 1 mm and those
limbs 3-4 mm. So these links also carry a *visual body* (massless geoms of
class ``visual``, drawn in place of the thick ones and ignored by the water;
``tools/creature_mjcf.py``): each foot five toes fanning out from the
tarso-metatarsal joint with a 0.6 mm web between them, scalloped between
the toe tips (``VISUAL_TOES``); a 4-5 mm tarsus; slim arms with four
fingers.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from creature_mjcf import fmt, loft, mesh_xml, mjcf

OUT = Path(__file__).resolve().parents[1] / "src" / "aquagait" / "creatures" / "frog.xml"

# Body (snout-vent length 0.08 m): stations s from the snout, half-width along
# y and half-height along z [m]; a flattened ranid body.
SVL = 0.08
BODY_S = [0.0, 0.006, 0.014, 0.024, 0.036, 0.05, 0.062, 0.072, 0.08]
BODY_B = [0.004, 0.011, 0.015, 0.0175, 0.018, 0.017, 0.014, 0.010, 0.006]
BODY_H = [0.003, 0.007, 0.0095, 0.0115, 0.012, 0.0115, 0.010, 0.008, 0.005]

HIP = (-0.032, 0.008, 0.0)  # left hip joint, near the vent [m]
SHOULDER = (0.018, 0.0145, -0.006)  # left shoulder, at the body's side, below its middle

# Hind limb segments (left side): name, length [m], direction at the reference
# pose as the angle from +x towards +y in the x-y plane [deg], half-thickness
# (horizontal, vertical) at the proximal and distal ends [m].
HIND = [
    ("thigh", 0.036, 130.0, (0.0075, 0.0065), (0.0055, 0.005)),
    ("shank", 0.040, 215.0, (0.005, 0.0045), (0.0035, 0.0032)),
    ("tarsus", 0.022, 140.0, (0.0036, 0.0036), (0.0036, 0.0036)),
]
# foot web: a plate from the tarso-metatarsal joint, 0.04 m long, 8 -> 28 mm wide,
# 7 mm thick; its long axis at 160 deg, its width tilted 60 deg out of the x-y plane.
FOOT = {
    "length": 0.04,
    "angle": 160.0,
    "w0": 0.004,
    "w1": 0.014,
    "half_thickness": 0.0035,
    "tilt": 60.0,
}
# Forelimb (left): upper arm lateral, a little back and down; forearm and hand forward.
FORE = [
    ("upperarm", 0.016, 105.0, -20.0, (0.0036, 0.0036), (0.0036, 0.0036)),
    ("forearm", 0.020, 35.0, -10.0, (0.0036, 0.0036), (0.0036, 0.0036)),
]

# Joint limits [deg], symmetric about the reference pose (the kick's middle).
LIMITS = {
    "hip_abd": 25, "hip_flex": 45, "knee": 85, "ankle": 85, "tmt": 30, "foot_twist": 50,
    "shoulder_abd": 30, "shoulder_flex": 40, "elbow": 45,
}  # fmt: skip

GREEN, DARK, WEB = "0.35 0.55 0.25 1", "0.28 0.45 0.2 1", "0.55 0.65 0.35 1"

# The visual body (no mass; drawn only). Toes of the left foot, first to fifth:
# their tips (along the foot, across the web) [m] from the tarso-metatarsal
# joint; the fourth is the longest, as in a ranid. Each toe is a capsule of
# TOE_RADIUS from the joint's fan; the web spans between the toes and reaches
# WEB_REACH of the way to the tips between them.
VISUAL_TOES = [(0.024, -0.016), (0.032, -0.012), (0.039, -0.004), (0.045, 0.007), (0.036, 0.018)]
TOE_RADIUS = 0.0007
TOE_ROOT = (-0.002, 0.0)  # where the toes' lines meet, on the foot's axis [m]
WEB_REACH = 0.8
SOLE = (0.007, 0.0019)  # the metatarsals' bundle at the foot's root: length, radius [m]
WEB_HALF_THICKNESS = 0.0003
# Slim limbs: half-thickness (across, up) at the proximal and distal ends [m].
VISUAL_LIMBS = {
    "tarsus": ((0.0026, 0.0024), (0.002, 0.002)),
    "upperarm": ((0.0024, 0.0022), (0.0019, 0.0018)),
    "forearm": ((0.0019, 0.0018), (0.0015, 0.0014)),
}
FINGERS = [(-25.0, 0.007), (-8.0, 0.009), (8.0, 0.008), (25.0, 0.006)]  # angle, length
FINGER_RADIUS = 0.0006


def direction(psi_deg: float, dip_deg: float = 0.0) -> np.ndarray:
    """Unit vector at azimuth psi from +x towards +y, dipping dip degrees towards +z."""
    psi, dip = np.radians(psi_deg), np.radians(dip_deg)
    return np.array([np.cos(psi) * np.cos(dip), np.sin(psi) * np.cos(dip), np.sin(dip)])


def section_frame(d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors across direction d: u horizontal, v as near to +z as possible."""
    u = np.cross(d, [0.0, 0.0, 1.0])
    u /= np.linalg.norm(u)
    return u, np.cross(u, d)


def segment_hull(d, length, end0, end1, ring: int = 12) -> np.ndarray:
    """Vertices of a tapered limb segment from the origin along d: elliptic sections
    of half-axes end0 and end1 (across, up) at its two ends."""
    u, v = section_frame(d)
    angles = np.linspace(0, 2 * np.pi, ring, endpoint=False)
    return np.array([
        s * length * d + a * np.cos(t) * u + b * np.sin(t) * v
        for s, (a, b) in ((0.0, end0), (1.0, end1))
        for t in angles
    ])  # fmt: skip


def body_hull(ring: int = 16) -> np.ndarray:
    """Vertices of the body: elliptic sections at the stations, snout at x = SVL / 2."""
    angles = np.linspace(0, 2 * np.pi, ring, endpoint=False)
    return np.array([
        (SVL / 2 - s, b * np.cos(t), h * np.sin(t))
        for s, b, h in zip(BODY_S, BODY_B, BODY_H, strict=True)
        for t in angles
    ])  # fmt: skip


def web_plate() -> np.ndarray:
    """The foot web's 8 vertices from the tarso-metatarsal joint (left foot)."""
    f = FOOT
    d = direction(f["angle"])
    u, v = section_frame(d)
    tilt = np.radians(f["tilt"])
    w = np.cos(tilt) * u + np.sin(tilt) * v  # across the foot, tilted out of the x-y plane
    n = np.cross(d, w)
    return np.array([
        s * f["length"] * d + side * half * w + face * f["half_thickness"] * n
        for s, half in ((0.0, f["w0"]), (1.0, f["w1"]))
        for side in (-1, 1)
        for face in (-1, 1)
    ])  # fmt: skip


def foot_axes() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The left foot's long axis d, the web's width w and its normal n (world)."""
    d = direction(FOOT["angle"])
    u, v = section_frame(d)
    tilt = np.radians(FOOT["tilt"])
    w = np.cos(tilt) * u + np.sin(tilt) * v
    return d, w, np.cross(d, w)


def web_visual(pos) -> tuple[np.ndarray, np.ndarray]:
    """The left foot's thin web (world, the joint at ``pos``): a fan between the first
    and fifth toes, reaching their tips along the toes and ``WEB_REACH`` of the way
    between them (a closed mesh)."""
    d, w, n = foot_axes()
    root = np.array(TOE_ROOT)
    tips = np.array(VISUAL_TOES) - root
    angle, reach = np.arctan2(tips[:, 1], tips[:, 0]), np.hypot(tips[:, 0], tips[:, 1])
    phi = np.linspace(angle[0], angle[-1], 41)
    k = np.clip(np.searchsorted(angle, phi, side="right") - 1, 0, len(angle) - 2)
    t = (phi - angle[k]) / (angle[k + 1] - angle[k])  # 0 at toe k, 1 at toe k + 1
    straight = reach[k] + (reach[k + 1] - reach[k]) * t
    edge = straight * (1 - (1 - WEB_REACH) * np.sin(np.pi * t))  # scalloped between tips
    rings = []
    for a, r in zip(phi, edge, strict=True):
        radial = np.linspace(0.003, r, 6)
        along, across = root[0] + radial * np.cos(a), root[1] + radial * np.sin(a)
        middle = pos + along[:, None] * d + across[:, None] * w
        rings.append(np.concatenate([middle + WEB_HALF_THICKNESS * n,
                                     (middle - WEB_HALF_THICKNESS * n)[::-1]]))  # fmt: skip
    return loft(rings)


def toe_lines(pos) -> list[tuple]:
    """Each left toe as a capsule: its ends (world), from near the joint to its tip, and
    its radius."""
    d, w, _ = foot_axes()
    root = np.array(TOE_ROOT)
    out = []
    for tip in np.array(VISUAL_TOES):
        start = root + 0.12 * (tip - root)
        out.append((pos + start[0] * d + start[1] * w, pos + tip[0] * d + tip[1] * w, TOE_RADIUS))
    return out


def finger_lines(pos, d) -> list[tuple]:
    """Each left finger as a capsule: its ends (world), fanning forward and a little down
    from the end of the forearm at ``pos``, which points along ``d``; and its radius."""
    out = []
    for angle, length in FINGERS:
        heading = np.arctan2(d[1], d[0]) + np.radians(angle)
        out.append((pos, pos + length * direction(np.degrees(heading), -15.0), FINGER_RADIUS))
    return out


def mirror(points) -> np.ndarray:
    """Reflect points (or axes) in the x-z plane: the right side of the left one."""
    return np.asarray(points) * np.array([1.0, -1.0, 1.0])


def frame(d, w=None) -> np.ndarray:
    """A link's rotation (columns: its x, y, z axes in world): x along the segment d,
    y across it (horizontal, or w), z completing a right-handed frame."""
    u = section_frame(d)[0] if w is None else np.asarray(w)
    return np.column_stack([d, u, np.cross(d, u)])


def left_limbs() -> list[list[dict]]:
    """The left hind and fore limbs, each a chain of links in world coordinates at the
    reference pose: name, joint position, frame (the link's box is tight in it),
    joints (name, world axis, limit [deg]), mesh vertices (world) and colour."""
    z = np.array([0.0, 0.0, 1.0])
    chain, pos = [], np.array(HIP)
    for k, (name, length, psi, end0, end1) in enumerate(HIND):
        d = direction(psi)
        if k == 0:
            joints = [
                ("hip_abd", section_frame(d)[0], LIMITS["hip_abd"]),
                ("hip_flex", z, LIMITS["hip_flex"]),
            ]
        else:
            joint = {1: "knee", 2: "ankle"}[k]
            joints = [(joint, z, LIMITS[joint])]
        mesh = pos + segment_hull(d, length, end0, end1)
        chain.append(
            dict(
                name=name,
                pos=pos,
                rot=frame(d),
                joints=joints,
                mesh=mesh,
                colour=GREEN if k < 2 else DARK,
                looks=slim_looks(name, pos, d, length, DARK),
            )
        )
        pos = pos + length * d
    d_foot = direction(FOOT["angle"])
    web = web_plate()
    across = (web[2] - web[0]) / np.linalg.norm(web[2] - web[0])  # the web's width
    sole = (pos, pos + SOLE[0] * d_foot, SOLE[1])
    looks = [("web", "mesh", web_visual(pos), WEB), ("sole", "capsule", sole, DARK)]
    looks += [(f"toe{i + 1}", "capsule", ends, DARK) for i, ends in enumerate(toe_lines(pos))]
    chain.append(dict(
        name="foot", pos=pos, rot=frame(d_foot, across),
        joints=[("tmt", z, LIMITS["tmt"]), ("foot_twist", d_foot, LIMITS["foot_twist"])],
        mesh=pos + web, colour=WEB, looks=looks,
    ))  # fmt: skip
    arm, pos = [], np.array(SHOULDER)
    for k, (name, length, psi, dip, end0, end1) in enumerate(FORE):
        d = direction(psi, dip)
        if k == 0:
            joints = [
                ("shoulder_abd", section_frame(d)[0], LIMITS["shoulder_abd"]),
                ("shoulder_flex", z, LIMITS["shoulder_flex"]),
            ]
        else:
            joints = [("elbow", z, LIMITS["elbow"])]
        mesh = pos + segment_hull(d, length, end0, end1)
        looks = slim_looks(name, pos, d, length, GREEN)
        if name == "forearm":
            ends = finger_lines(pos + length * d, d)
            looks += [(f"finger{i + 1}", "capsule", e, GREEN) for i, e in enumerate(ends)]
        arm.append(dict(name=name, pos=pos, rot=frame(d), joints=joints, mesh=mesh, colour=GREEN,
                        looks=looks))  # fmt: skip
        pos = pos + length * d
    return [chain, arm]


def slim_looks(name: str, pos, d, length: float, colour: str) -> list:
    """A link's slim visual segment (``VISUAL_LIMBS``), or none for a link not thickened."""
    if name not in VISUAL_LIMBS:
        return []
    end0, end1 = VISUAL_LIMBS[name]
    return [("slim", "hull", pos + segment_hull(d, length, end0, end1), colour)]


def reflected_look(look):
    """A visual geom of the right side: its points reflected (a mesh's faces turned)."""
    name, kind, shape, colour = look
    if kind == "mesh":
        vertices, faces = shape
        return name, kind, (mirror(vertices), faces[:, ::-1]), colour
    if kind == "capsule":
        *points, radius = shape
        return name, kind, (*(mirror(p) for p in points), radius), colour
    return name, kind, mirror(shape), colour


def reflected(link: dict) -> dict:
    """The right side's link: positions, axes and vertices reflected, the frame M R M."""
    m = np.diag([1.0, -1.0, 1.0])
    return dict(
        link,
        pos=mirror(link["pos"]),
        rot=m @ link["rot"] @ m,
        mesh=mirror(link["mesh"]),
        joints=[(j, mirror(a), lim) for j, a, lim in link["joints"]],
        looks=[reflected_look(look) for look in link.get("looks", [])],
    )


def chain_xml(chain, side: str, indent: str, asset: list) -> list[str]:
    """Nested <body> elements of one limb (side 'l' as given, 'r' reflected), each in
    its link's frame; appends the links' meshes to ``asset``."""
    lines, parent_pos, parent_rot = [], np.zeros(3), np.eye(3)
    for k, link in enumerate(chain):
        link = link if side == "l" else reflected(link)
        name, pos, rot = f"{link['name']}_{side}", link["pos"], link["rot"]
        rel_pos, rel_rot = parent_rot.T @ (pos - parent_pos), parent_rot.T @ rot
        pad = indent + "  " * k
        lines.append(
            f'{pad}<body name="{name}" pos="{fmt(rel_pos)}" xyaxes="{fmt(rel_rot[:, :2].T)}">'
        )
        for joint, axis, limit in link["joints"]:
            lines.append(
                f'{pad}  <joint name="{joint}_{side}" type="hinge" axis="{fmt(rot.T @ axis)}" '
                f'range="-{limit:g} {limit:g}"/>'
            )
        lines.append(
            f'{pad}  <geom name="{name}" type="mesh" mesh="{name}" rgba="{link["colour"]}"/>'
        )
        asset.append(f'    <mesh name="{name}" vertex="{fmt((link["mesh"] - pos) @ rot)}"/>')
        for look in link.get("looks", []):
            lines.append(f"{pad}  " + look_xml(name, look, pos, rot, asset))
        parent_pos, parent_rot = pos, rot
    lines += [indent + "  " * k + "</body>" for k in range(len(chain) - 1, -1, -1)]
    return lines


def look_xml(link: str, look, pos, rot, asset: list) -> str:
    """A visual geom's line in its link's frame (origin ``pos``, axes ``rot``, world);
    a mesh's asset is appended to ``asset``."""
    what, kind, shape, colour = look
    name = f"{link}_{what}"
    start = f'<geom name="{name}" class="visual" '
    if kind == "capsule":
        *points, radius = shape
        ends = fmt(np.concatenate([(p - pos) @ rot for p in points]))
        return start + f'type="capsule" fromto="{ends}" size="{radius:g}" rgba="{colour}"/>'
    if kind == "mesh":
        vertices, faces = shape
        asset.append(mesh_xml(name, (vertices - pos) @ rot, faces))
    else:  # a convex hull
        asset.append(mesh_xml(name, (shape - pos) @ rot))
    return start + f'type="mesh" mesh="{name}" rgba="{colour}"/>'


def frog_xml() -> str:
    limbs = left_limbs()
    asset = [f'    <mesh name="body" vertex="{fmt(body_hull())}"/>']
    body = [
        '    <body name="body" pos="0 0 0">',
        '      <freejoint name="root"/>',
        f'      <geom name="body" type="mesh" mesh="body" rgba="{GREEN}"/>',
    ]
    for chain in limbs:
        for side in ("l", "r"):
            body += chain_xml(chain, side, "      ", asset)
    body.append("    </body>")
    summary = "a ranid frog 8 cm snout to vent, webbed hind feet, 18 hinges, 3D."
    visual = (
        "on each foot five toes and a 0.6 mm web between them; a slim tarsus, upper arm "
        "and forearm, and four fingers."
    )
    return mjcf(
        "frog",
        summary,
        "\n".join(body),
        Path(__file__).name,
        asset="\n".join(asset),
        source="dimensions",
        visual=visual,
    )


if __name__ == "__main__":
    OUT.write_text(frog_xml())
    print(f"wrote {OUT}")
