"""Write ``src/aquagait/creatures/turtle3d.xml``: a green sea turtle with four flippers.

Run from the repository root: ``python tools/make_turtle3d.py``. The turtle
swims towards +x with z up. The root link is the shell (a flattened
ellipsoid, the carapace and plastron together) with the head (an ellipsoid)
in front. Each front flipper is two links, the arm (humerus and forearm) and
the hand blade; each rear flipper one link. Flippers are tapered plates (the
convex hull of 8 vertices: a root chord and a shorter tip chord, one
thickness). At rest every flipper lies flat (in the x-y plane), swept back
by ``sweep_deg`` from the lateral direction, so that the creature fits the
32-cell-wide default grid. Each flipper's frame has its span along local
+y (left, y > 0) or -y (right) and its chord along local x; the shoulder and
hip hinge about local x (flap: up and down) and local y (feather: pitch of
the blade about its span), the wrist about local x (the hand bends up and
down). Left and right are mirror images in the x-z plane.

Dimensions (metres) are those of a subadult green turtle (Chelonia mydas) of
0.70 m straight carapace length; ``src/aquagait/creatures/turtle3d.py`` gives
the sources and why the flippers are thicker than real.

The plates are 120 mm thick so that the 60 mm cells see them; drawn so, the
turtle paddles with planks. So each flipper link also carries a *visual*
flipper (a massless geom of class ``visual``, drawn in place of the plate and
ignored by the water; ``tools/creature_mjcf.py``): a smooth, thin blade
(``foil``) whose outline follows a sea turtle's: the front flipper long and
narrow, widest at the wrist and curving back to a pointed tip, cut at the
wrist into the arm's and the hand's pieces; the rear flipper a rounded
paddle. They are ``VISUAL_ROOT_THICKNESS`` thick at the root, thinning
towards the tip, as a real flipper's 2-3 cm.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from creature_mjcf import fmt, foil, mesh_xml, mjcf

OUT = Path(__file__).resolve().parents[1] / "src" / "aquagait" / "creatures"

SHELL = (0.35, 0.26, 0.11)  # semi-axes: 0.70 m long, 0.52 m wide, 0.22 m high
HEAD = {"pos": 0.40, "size": (0.09, 0.06, 0.05)}  # ellipsoid centre x and semi-axes
PLATE = 0.12  # flipper thickness: 2 cells of the default 60 mm grid (real: 1-3 cm)

FLAP, FEATHER = "1 0 0", "0 1 0"  # hinge axes in a flipper frame: chord (up-down), span (pitch)

# Per flipper (left side; the right is its mirror image): joint position in the
# parent (the shell for the first link), sweep back from lateral [deg], and its
# links: (name, span length, root chord, tip chord, joints (name, local axis,
# limit [deg])).
FRONT = {
    "pos": (0.20, 0.16, 0.0),
    "sweep_deg": 55,
    "links": [
        ("arm", 0.13, 0.16, 0.15, [("shoulder_flap", FLAP, 50), ("shoulder_feather", FEATHER, 45)]),
        ("hand", 0.20, 0.15, 0.07, [("wrist", FLAP, 35)]),
    ],
}
REAR = {
    "pos": (-0.27, 0.10, 0.0),
    "sweep_deg": 65,
    "links": [("rear", 0.18, 0.15, 0.08, [("hip_flap", FLAP, 30), ("hip_feather", FEATHER, 30)])],
}
SHELL_COLOUR, SKIN_COLOUR = "0.36 0.31 0.18 1", "0.55 0.52 0.40 1"

# The visual flippers (no mass; drawn only), along the whole flipper's span r
# from the shoulder or hip: chord, how far its middle lies behind the span
# axis (the flipper curves back), and thickness [m].
VISUAL_ROOT_THICKNESS = {"front": 0.03, "rear": 0.022}
VISUAL_TIP_THICKNESS = 0.006
TIP_CHORD = 0.006  # where the outline closes, rounded [m]


def front_outline(r):
    """The front flipper's chord and its middle's offset along local x [m] at span r:
    0.13 m at the shoulder, widest (0.14 m) at the wrist, narrowing to a pointed tip
    that curves back (0.33 m span)."""
    wrist, length = FRONT["links"][0][1], sum(link[1] for link in FRONT["links"])
    u = np.clip((r - wrist) / (length - wrist), 0, 1)
    chord = np.where(r < wrist, 0.13 + 0.01 * r / wrist, 0.14 * (1 - u**1.6) ** 0.6)
    return chord, -0.06 * (r / length) ** 2


def rear_outline(r):
    """The rear flipper's: 0.13 m at the hip, a rounded paddle 0.18 m long."""
    length = REAR["links"][0][1]
    u = np.clip(r / length, 0, 1)
    return 0.13 * (1 + 0.15 * np.sin(np.pi * u)) * (1 - u**4) ** 0.5, -0.02 * u**2


def visual_piece(kind: str, r0: float, r1: float, side: int):
    """The visual flipper between spans r0 and r1 of a ``kind`` ('front' or 'rear')
    flipper, in the frame of the link that starts at r0: a closed mesh."""
    outline = front_outline if kind == "front" else rear_outline
    length = r1
    r = np.linspace(r0, r1, 200)
    chord, _ = outline(r)
    r1 = r[np.flatnonzero(chord > TIP_CHORD)[-1]]  # the tip: where the outline closes
    r = np.linspace(r0, r1, 12)
    chord, middle = outline(r)
    taper = VISUAL_ROOT_THICKNESS[kind] + (VISUAL_TIP_THICKNESS - VISUAL_ROOT_THICKNESS[kind]) * (
        r / length)  # fmt: skip
    vertices, faces = foil(r - r0, middle + chord / 2, middle - chord / 2, taper / 2, chords=10)
    if side < 0:
        vertices, faces = vertices * [1, -1, 1], faces[:, ::-1]
    return vertices, faces


def plate(length: float, root: float, tip: float, side: int) -> list[tuple[float, float, float]]:
    """A tapered flipper plate: 8 vertices, span ``length`` along local ``side`` * y
    from the joint, chord ``root`` at the joint and ``tip`` at the end, centred on
    the span axis, ``PLATE`` thick."""
    return [
        (sx * chord / 2, side * s, sz * PLATE / 2)
        for s, chord in ((0.0, root), (length, tip))
        for sx in (-1, 1)
        for sz in (-1, 1)
    ]


def flipper(spec: dict, side: int, indent: str) -> tuple[list[str], dict]:
    """MJCF bodies and meshes of one flipper; ``side`` +1 left, -1 right."""
    label = "l" if side > 0 else "r"
    kind = "front" if spec is FRONT else "rear"
    total = sum(link[1] for link in spec["links"])
    x, y, z = spec["pos"]
    pos, euler = (x, side * y, z), side * spec["sweep_deg"]  # sweep back about z
    lines, meshes, r0 = [], {}, 0.0
    for k, (name, length, root, tip, joints) in enumerate(spec["links"]):
        pad, body = indent + "  " * k, f"{name}_{label}"
        meshes[body] = plate(length, root, tip, side)
        r1 = r0 + length if k < len(spec["links"]) - 1 else total
        meshes[f"{body}_look"] = visual_piece(kind, r0, r1, side)
        r0 = r1
        lines.append(f'{pad}<body name="{body}" pos="{fmt([pos])}" euler="0 0 {euler:g}">')
        lines += [
            f'{pad}  <joint name="{joint}_{label}" type="hinge" axis="{axis}" '
            f'range="-{limit} {limit}"/>'
            for joint, axis, limit in joints
        ]
        lines.append(f'{pad}  <geom name="{body}" type="mesh" mesh="{body}" rgba="{SKIN_COLOUR}"/>')
        lines.append(f'{pad}  <geom name="{body}_look" class="visual" type="mesh" '
                     f'mesh="{body}_look" rgba="{SKIN_COLOUR}"/>')  # fmt: skip
        pos, euler = (0.0, side * length, 0.0), 0
    lines += [indent + "  " * k + "</body>" for k in range(len(spec["links"]) - 1, -1, -1)]
    return lines, meshes


def turtle3d_xml() -> str:
    lines = [
        '    <body name="shell" pos="0 0 0">',
        '      <freejoint name="root"/>',
        f'      <geom name="shell" type="ellipsoid" size="{fmt([SHELL])}" rgba="{SHELL_COLOUR}"/>',
        f'      <geom name="head" type="ellipsoid" size="{fmt([HEAD["size"]])}" '
        f'pos="{HEAD["pos"]:g} 0 0" rgba="{SKIN_COLOUR}"/>',
    ]
    meshes = {}
    for spec in (FRONT, REAR):
        for side in (1, -1):
            body, mesh = flipper(spec, side, "      ")
            lines += body
            meshes |= mesh
    lines.append("    </body>")
    asset = "\n".join(
        mesh_xml(n, *v) if isinstance(v, tuple) else mesh_xml(n, v) for n, v in meshes.items()
    )
    summary = "a 0.7 m green sea turtle, shell, two 2-link front and two rear flippers, 3D."
    visual = (
        "per flipper link, its piece of a thin, smooth flipper (30 mm thick at the front "
        "flipper's root, 6 mm at the tip) shaped as a sea turtle's."
    )
    return mjcf("turtle3d", summary, "\n".join(lines), Path(__file__).name, asset=asset,
                visual=visual)  # fmt: skip


if __name__ == "__main__":
    path = OUT / "turtle3d.xml"
    path.write_text(turtle3d_xml())
    print(f"wrote {path}")
