"""Write ``src/aquagait/creatures/turtle2d.xml``: a green sea turtle seen from the side.

Run from the repository root: ``python tools/make_turtle2d.py``. The turtle
lies in the x-y plane (x forward, y the turtle's up, z across its width), a
prism of depth ``DEPTH`` (the carapace width). The root link is the shell and
head: the convex hull of the carapace's side outline (a dome over a flatter
plastron) plus a separate hull for the head. The near-side front and rear
flippers are two-link chains of flat plates hinged about z; at rest they are
swept back, the front one under the shell's forward half, the rear one
trailing behind the shell (the far-side flippers coincide with them).

Dimensions (metres) are those of a subadult green turtle (Chelonia mydas) of
0.70 m straight carapace length; see ``src/aquagait/creatures/turtle2d.py``
for the sources and the reasons behind each number.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from creature_mjcf import fmt, mjcf

OUT = Path(__file__).resolve().parents[1] / "src" / "aquagait" / "creatures"

CARAPACE_LENGTH = 0.70  # straight carapace length
DEPTH = 0.55  # prism depth = carapace width (about 0.8 of the length)
DOME, PLASTRON = 0.14, 0.09  # carapace top and plastron below the shell's mid line
HEAD = {"x0": 0.30, "x1": 0.46, "half_height": 0.055, "y": 0.0}
PLATE = 0.05  # flipper thickness: 2 cells of the default 25 mm grid (real: 1-3 cm)

# Flipper chains: joint position of the first link (in the root frame), rest
# angle below the backward horizontal [deg], link lengths [m], limits [deg].
FRONT = {
    "pos": (0.20, -0.05),
    "rest_deg": 20,
    "links": [("front_arm", 0.13, "front_shoulder", 45), ("front_blade", 0.20, "front_wrist", 45)],
}
REAR = {
    "pos": (-0.28, -0.04),
    "rest_deg": 8,
    "links": [("rear_leg", 0.10, "rear_hip", 30), ("rear_blade", 0.12, "rear_knee", 30)],
}
SHELL_COLOUR, SKIN_COLOUR = "0.36 0.31 0.18 1", "0.55 0.52 0.40 1"


def prism(outline) -> list[tuple[float, float, float]]:
    """Vertices of a z-prism of depth ``DEPTH`` over a 2D outline."""
    return [(x, y, z) for x, y in outline for z in (-DEPTH / 2, DEPTH / 2)]


def shell_outline(n: int = 24) -> list[tuple[float, float]]:
    """The carapace's side outline: an elliptic dome above, a flatter plastron below."""
    a = CARAPACE_LENGTH / 2
    xs = a * np.cos(np.linspace(0, np.pi, n))
    top = [(x, DOME * np.sqrt(max(0.0, 1 - (x / a) ** 2))) for x in xs]
    bottom = [(x, -PLASTRON * max(0.0, 1 - (x / a) ** 2) ** 0.25) for x in xs]
    return top + bottom


def head_outline(n: int = 12) -> list[tuple[float, float]]:
    """The head and neck from the side: half an ellipse in front of a short neck."""
    x0, x1, h, y = HEAD["x0"], HEAD["x1"], HEAD["half_height"], HEAD["y"]
    half = x1 - x0
    angles = np.linspace(-np.pi / 2, np.pi / 2, n)
    return [(x0, y - h), (x0, y + h)] + [(x0 + half * np.cos(t), y + h * np.sin(t)) for t in angles]


def plate_outline(length: float) -> list[tuple[float, float]]:
    """A flipper link from the side: a plate from its joint back along local -x."""
    return [(x, y) for x in (0.0, -length) for y in (-PLATE / 2, PLATE / 2)]


def chain(spec: dict, indent: str) -> list[str]:
    """MJCF bodies of one flipper: each link hinged about z at its front end."""
    lines, pos, euler = [], spec["pos"], spec["rest_deg"]
    for k, (name, length, joint, limit) in enumerate(spec["links"]):
        pad = indent + "  " * k
        lines += [
            f'{pad}<body name="{name}" pos="{pos[0]:g} {pos[1]:g} 0" euler="0 0 {euler:g}">',
            f'{pad}  <joint name="{joint}" type="hinge" axis="0 0 1" range="-{limit} {limit}"/>',
            f'{pad}  <geom name="{name}" type="mesh" mesh="{name}" rgba="{SKIN_COLOUR}"/>',
        ]
        pos, euler = (-length, 0.0), 0
    lines += [indent + "  " * k + "</body>" for k in range(len(spec["links"]) - 1, -1, -1)]
    return lines


def turtle2d_xml() -> str:
    meshes = {"shell": prism(shell_outline()), "head": prism(head_outline())}
    for spec in (FRONT, REAR):
        meshes |= {name: prism(plate_outline(length)) for name, length, _, _ in spec["links"]}
    asset = "\n".join(f'    <mesh name="{n}" vertex="{fmt(v)}"/>' for n, v in meshes.items())
    lines = [
        '    <body name="shell" pos="0 0 0">',
        '      <joint name="root_x" type="slide" axis="1 0 0"/>',
        '      <joint name="root_y" type="slide" axis="0 1 0"/>',
        '      <joint name="root_theta" type="hinge" axis="0 0 1"/>',
        f'      <geom name="shell" type="mesh" mesh="shell" rgba="{SHELL_COLOUR}"/>',
        f'      <geom name="head" type="mesh" mesh="head" rgba="{SKIN_COLOUR}"/>',
        *chain(FRONT, "      "),
        *chain(REAR, "      "),
        "    </body>",
    ]
    summary = "a 0.7 m green sea turtle seen from the side, front and rear flippers, planar."
    return mjcf("turtle2d", summary, "\n".join(lines), Path(__file__).name, DEPTH, asset)


if __name__ == "__main__":
    path = OUT / "turtle2d.xml"
    path.write_text(turtle2d_xml())
    print(f"wrote {path}")
