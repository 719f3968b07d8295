"""Write the MJCF files of the built-in creatures from their body profiles.

Run from the repository root: ``python tools/make_creature_meshes.py``. It
rewrites ``src/aquagait/creatures/eel2d.xml``, ``fish.xml`` and
``accordion2d.xml``. Each link is a
convex mesh, the hull of the body's cross-sections at a few stations along it,
so neighbouring links meet flush at the joints (no overlap, no gap at rest).

Arc length ``s`` runs from the snout (s = 0) to the tail tip. The creatures
swim towards +x with z up; each link's frame sits at its front joint (the root
link's at the middle of the body), so world x = x_snout - s at rest.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from creature_mjcf import fmt, mjcf

OUT = Path(__file__).resolve().parents[1] / "src" / "aquagait" / "creatures"
SCRIPT = Path(__file__).name

# eel2d: a European eel (Anguilla anguilla) seen from above, 0.5 m long, as a
# prism 4 cm deep (its dorsoventral height). Joints every 0.1 m.
EEL_LENGTH, EEL_DEPTH, EEL_HALF_WIDTH, EEL_TAIL_HALF_WIDTH = 0.5, 0.04, 0.0175, 0.003
EEL_CUTS = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5]
EEL_LINKS = ["head", "trunk1", "trunk2", "trunk3", "tail"]
EEL_LIMIT_DEG = 45

# fish: a clownfish (Amphiprion ocellaris), 0.10 m total length. Stations
# (arc length), half-height along z and half-width along y of the body [m].
FISH_S = [0.0, 0.003, 0.007, 0.012, 0.02, 0.03, 0.035, 0.045, 0.06, 0.07, 0.08]
FISH_H = [0.004, 0.009, 0.0135, 0.017, 0.0205, 0.0225, 0.0225, 0.021, 0.015, 0.009, 0.0065]
FISH_B = [0.002, 0.0045, 0.006, 0.0075, 0.0085, 0.009, 0.009, 0.0085, 0.006, 0.004, 0.003]
FISH_CUTS = [0.0, 0.035, 0.06, 0.08]
FISH_LINKS = ["head", "trunk", "peduncle"]
FISH_LIMITS_DEG = [12, 25, 40]  # head-trunk, trunk-peduncle, peduncle-tail: tail-dominant
# caudal fin, a plate: from s = 0.08 (half-height 6.5 mm) to 0.10 (17 mm), 5 mm thick:
# real fins are thinner, but the fluid must see it at the default 5 mm cells.
FISH_FIN = {"s0": 0.08, "s1": 0.10, "h0": 0.0065, "h1": 0.017, "half_thickness": 0.003}


def eel_half_width(s: float) -> float:
    """Half the eel's width [m] at arc length s: round snout, even trunk, tapering tail."""
    nose = 0.06
    if s < nose:
        return EEL_HALF_WIDTH * np.sqrt(1 - (1 - s / nose) ** 2)
    if s < 0.2:
        return EEL_HALF_WIDTH
    taper = (s - 0.2) / (EEL_LENGTH - 0.2)
    return EEL_HALF_WIDTH + (EEL_TAIL_HALF_WIDTH - EEL_HALF_WIDTH) * taper


def eel_meshes():
    """Mesh vertices of each eel link: a z-prism over the outline between two cuts."""
    meshes = {}
    for i, name in enumerate(EEL_LINKS):
        s0, s1 = EEL_CUTS[i], EEL_CUTS[i + 1]
        nose = [0.0, 0.0015, 0.006, 0.015, 0.03, 0.045, 0.06] if i == 0 else []
        stations = sorted({s0, s1, (s0 + s1) / 2, *nose})
        origin = (s0 + s1) / 2 if i == 0 else s0
        meshes[name] = [
            (origin - s, sy * max(eel_half_width(s), 1e-4), sz * EEL_DEPTH / 2)
            for s in stations
            for sy in (-1, 1)
            for sz in (-1, 1)
        ]
    return meshes


def eel_xml() -> str:
    meshes = eel_meshes()
    colours = [
        "0.30 0.27 0.14 1",
        "0.33 0.30 0.15 1",
        "0.36 0.32 0.16 1",
        "0.39 0.35 0.18 1",
        "0.42 0.38 0.20 1",
    ]
    asset = "\n".join(f'    <mesh name="{n}" vertex="{fmt(v)}"/>' for n, v in meshes.items())
    x_root = EEL_LENGTH / 2 - (EEL_CUTS[0] + EEL_CUTS[1]) / 2
    lines = [
        f'    <body name="head" pos="{x_root:g} 0 0">',
        '      <joint name="root_x" type="slide" axis="1 0 0"/>',
        '      <joint name="root_y" type="slide" axis="0 1 0"/>',
        '      <joint name="root_theta" type="hinge" axis="0 0 1"/>',
        f'      <geom name="head" type="mesh" mesh="head" rgba="{colours[0]}"/>',
    ]
    indent = "      "
    for i, name in enumerate(EEL_LINKS[1:], start=1):
        front = (EEL_CUTS[0] + EEL_CUTS[1]) / 2 if i == 1 else EEL_CUTS[i - 1]  # parent origin
        dx = -(EEL_CUTS[i] - front)
        lines += [
            f'{indent}<body name="{name}" pos="{dx:g} 0 0">',
            f'{indent}  <joint name="j{i}" type="hinge" axis="0 0 1" '
            f'range="-{EEL_LIMIT_DEG} {EEL_LIMIT_DEG}"/>',
            f'{indent}  <geom name="{name}" type="mesh" mesh="{name}" rgba="{colours[i]}"/>',
        ]
        indent += "  "
    for i in range(len(EEL_LINKS) - 1, 0, -1):
        lines.append(" " * (4 + 2 * i) + "</body>")
    lines.append("    </body>")
    summary = "a 0.5 m European eel seen from above, 5 links, 4 yaw joints, planar."
    return mjcf("eel2d", summary, "\n".join(lines), SCRIPT, EEL_DEPTH, asset, "profile")


def fish_profile(s: float) -> tuple[float, float]:
    """(half-height, half-width) [m] of the clownfish body at arc length s."""
    return float(np.interp(s, FISH_S, FISH_H)), float(np.interp(s, FISH_S, FISH_B))


def fish_meshes(ring: int = 16):
    """Mesh vertices of each fish link: elliptic cross-sections at the stations in it."""
    angles = np.linspace(0, 2 * np.pi, ring, endpoint=False)
    meshes = {}
    for i, name in enumerate(FISH_LINKS):
        s0, s1 = FISH_CUTS[i], FISH_CUTS[i + 1]
        stations = sorted({s0, s1, *[s for s in FISH_S if s0 < s < s1]})
        origin = 0.02 if i == 0 else s0
        meshes[name] = [
            (origin - s, fish_profile(s)[1] * np.cos(a), fish_profile(s)[0] * np.sin(a))
            for s in stations
            for a in angles
        ]
    fin = FISH_FIN
    meshes["caudal"] = [
        (-(s - fin["s0"]), sy * fin["half_thickness"], sz * h)
        for s, h in ((fin["s0"], fin["h0"]), (fin["s1"], fin["h1"]))
        for sy in (-1, 1)
        for sz in (-1, 1)
    ]
    return meshes


def fish_xml() -> str:
    meshes = fish_meshes()
    asset = "\n".join(f'    <mesh name="{n}" vertex="{fmt(v)}"/>' for n, v in meshes.items())
    orange, white = "1 0.42 0.05 1", "0.95 0.95 0.92 1"
    lim = FISH_LIMITS_DEG
    summary = "a 0.10 m clownfish (Amphiprion ocellaris), 4 links, 3 yaw joints, 3D."
    worldbody = f"""    <body name="head" pos="{0.05 - 0.02:g} 0 0">
      <freejoint name="root"/>
      <geom name="head" type="mesh" mesh="head" rgba="{orange}"/>
      <body name="trunk" pos="{-(FISH_CUTS[1] - 0.02):g} 0 0">
        <joint name="j1" type="hinge" axis="0 0 1" range="-{lim[0]} {lim[0]}"/>
        <geom name="trunk" type="mesh" mesh="trunk" rgba="{white}"/>
        <body name="peduncle" pos="{-(FISH_CUTS[2] - FISH_CUTS[1]):g} 0 0">
          <joint name="j2" type="hinge" axis="0 0 1" range="-{lim[1]} {lim[1]}"/>
          <geom name="peduncle" type="mesh" mesh="peduncle" rgba="{orange}"/>
          <body name="caudal" pos="{-(FISH_CUTS[3] - FISH_CUTS[2]):g} 0 0">
            <joint name="j3" type="hinge" axis="0 0 1" range="-{lim[2]} {lim[2]}"/>
            <geom name="caudal" type="mesh" mesh="caudal" rgba="{orange}"/>
          </body>
        </body>
      </body>
    </body>"""
    return mjcf("fish", summary, worldbody, SCRIPT, asset=asset, source="profile")


# accordion2d: an imaginary creature (paper Figure 14), a head plate with two
# mirrored zigzag arms of plates, like the two sides of a bellows.
ACCORDION_PLATES, ACCORDION_PLATE = 5, (0.04, 0.006)  # per arm; length, thickness [m]
ACCORDION_HEAD, ACCORDION_DEPTH, ACCORDION_FOLD_DEG = (0.05, 0.05), 0.04, 45
ACCORDION_LIMIT_DEG = 60


def accordion_arm(name: str, side: int, first_joint: int, indent: str) -> list[str]:
    """One zigzag arm: plates leave the head's back corner away from the axis
    (``side`` +1 above, -1 below) at the fold angle, then alternate."""
    length, thickness = ACCORDION_PLATE
    hx, hy = ACCORDION_HEAD
    pos = (-hx / 2, side * (hy / 2 - thickness / 2))
    lines = []
    for k in range(ACCORDION_PLATES):
        turn = ACCORDION_FOLD_DEG if k == 0 else 2 * ACCORDION_FOLD_DEG
        angle = -side * turn * (1 if k % 2 == 0 else -1)
        pad = indent + "  " * k
        lines += [
            f'{pad}<body name="{name}{k + 1}" pos="{pos[0]:g} {pos[1]:g} 0" euler="0 0 {angle:g}">',
            f'{pad}  <joint name="j{first_joint + k}" type="hinge" axis="0 0 1" '
            f'range="-{ACCORDION_LIMIT_DEG} {ACCORDION_LIMIT_DEG}"/>',
            f'{pad}  <geom type="box" size="{length / 2:g} {thickness / 2:g} '
            f'{ACCORDION_DEPTH / 2:g}" pos="{-length / 2:g} 0 0" rgba="0.25 0.45 0.7 1"/>',
        ]
        pos = (-length, 0.0)
    lines += [indent + "  " * k + "</body>" for k in range(ACCORDION_PLATES - 1, -1, -1)]
    return lines


def accordion_xml() -> str:
    hx, hy = ACCORDION_HEAD
    head = f'size="{hx / 2:g} {hy / 2:g} {ACCORDION_DEPTH / 2:g}" rgba="0.9 0.5 0.2 1"'
    arms = accordion_arm("upper", +1, 1, "      ")
    arms += accordion_arm("lower", -1, ACCORDION_PLATES + 1, "      ")
    body = "\n".join(arms)
    worldbody = "\n".join([
        '    <body name="head" pos="0 0 0">',
        '      <joint name="root_x" type="slide" axis="1 0 0"/>',
        '      <joint name="root_y" type="slide" axis="0 1 0"/>',
        '      <joint name="root_rz" type="hinge" axis="0 0 1"/>',
        f'      <geom name="head" type="box" {head}/>',
        body,
        "    </body>",
    ])  # fmt: skip
    summary = "an imaginary planar creature, a head and two mirrored zigzag arms."
    return mjcf("accordion2d", summary, worldbody, SCRIPT, depth=ACCORDION_DEPTH)


if __name__ == "__main__":
    for name, xml in (("eel2d", eel_xml()), ("fish", fish_xml()), ("accordion2d", accordion_xml())):
        (OUT / f"{name}.xml").write_text(xml)
        print(f"wrote {OUT / (name + '.xml')}")
