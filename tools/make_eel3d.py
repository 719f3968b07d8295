"""Write ``src/aquagait/creatures/eel3d.xml``: a seven-link European eel in 3D.

Run from the repository root: ``python tools/make_eel3d.py``. Each link is a
convex mesh, the hull of the eel's elliptic cross-sections at the stations
inside it (and at its cuts, so neighbouring links meet flush at the joints).

Arc length ``s`` runs from the snout (s = 0) to the tail tip (s = L). The eel
swims towards +x with z up; the joints are hinges about z (lateral bending).
The head's frame sits at the middle of the head, every other link's at its
front joint, and the snout at x = L/2 at rest (world x = L/2 - s).

The profile is a male European eel (Anguilla anguilla) 0.40 m long: round in
front (about 6% of the length deep and wide, e.g. Tesch, "The Eel", 2003:
body depth 5-7% of total length), laterally compressed behind the vent (about
40% of the length), where the dorsal and anal fins make one continuous fin
fold around the tail. The fold is modelled as the tail's taller, narrower
ellipse, kept 19 mm wide (1.9 cells of the default 10 mm grid) to the tip:
the real fold is a membrane a millimetre thick, which no 10 mm cell would see.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from creature_mjcf import fmt, mjcf

OUT = Path(__file__).resolve().parents[1] / "src" / "aquagait" / "creatures"

LENGTH = 0.40  # m, total length of a small (male) adult
LINKS = ["head", "trunk1", "trunk2", "trunk3", "tail1", "tail2", "tail3"]
CUTS = np.linspace(0.0, LENGTH, len(LINKS) + 1)  # seven links of L/7 = 57 mm
LIMIT_DEG = 30  # each of the six hinges; six of them bend the eel into a half circle

# Stations (arc length) and the half-width (y) and half-height (z) of the
# section there [m]: a rounded snout, an even trunk 24 mm wide and 26 mm deep
# (6.5% of L), then behind the vent a tail narrowing to 19 mm wide while the
# fin fold makes it deeper (32 mm), rounded off at the tip.
STATION_S = [0.0, 0.004, 0.012, 0.025, 0.045, 0.08, 0.16, 0.22, 0.28, 0.34, 0.38, 0.395, 0.40]
HALF_WIDTH = [0.002, 0.005, 0.008, 0.0105, 0.0115, 0.012, 0.012, 0.0115, 0.0105, 0.0098,
              0.0095, 0.0094, 0.0093]  # fmt: skip
HALF_HEIGHT = [0.002, 0.005, 0.008, 0.0105, 0.012, 0.013, 0.013, 0.0145, 0.016, 0.016,
               0.0145, 0.012, 0.009]  # fmt: skip
RING = 16  # points per cross-section
COLOURS = ["0.30 0.27 0.14 1", "0.32 0.29 0.15 1", "0.34 0.31 0.16 1", "0.36 0.32 0.17 1",
           "0.38 0.34 0.18 1", "0.40 0.36 0.19 1", "0.42 0.38 0.20 1"]  # fmt: skip


def section(s: float) -> tuple[float, float]:
    """(half-width, half-height) [m] of the eel's cross-section at arc length s."""
    return float(np.interp(s, STATION_S, HALF_WIDTH)), float(np.interp(s, STATION_S, HALF_HEIGHT))


def origin(i: int) -> float:
    """Arc length of link i's frame: the head's middle, else its front joint."""
    return (CUTS[0] + CUTS[1]) / 2 if i == 0 else CUTS[i]


def meshes() -> dict[str, list]:
    """Mesh vertices of each link, in its frame: elliptic sections at its stations."""
    angles = np.linspace(0, 2 * np.pi, RING, endpoint=False)
    out = {}
    for i, name in enumerate(LINKS):
        s0, s1 = CUTS[i], CUTS[i + 1]
        stations = sorted({s0, s1, *[s for s in STATION_S if s0 < s < s1]})
        out[name] = [
            (origin(i) - s, section(s)[0] * np.cos(a), section(s)[1] * np.sin(a))
            for s in stations
            for a in angles
        ]
    return out


def xml() -> str:
    asset = "\n".join(f'    <mesh name="{n}" vertex="{fmt(v)}"/>' for n, v in meshes().items())
    lines = [
        f'    <body name="head" pos="{LENGTH / 2 - origin(0):g} 0 0">',
        '      <freejoint name="root"/>',
        f'      <geom name="head" type="mesh" mesh="head" rgba="{COLOURS[0]}"/>',
    ]
    indent = "      "
    for i, name in enumerate(LINKS[1:], start=1):
        lines += [
            f'{indent}<body name="{name}" pos="{-(CUTS[i] - origin(i - 1)):g} 0 0">',
            f'{indent}  <joint name="j{i}" type="hinge" axis="0 0 1" '
            f'range="-{LIMIT_DEG} {LIMIT_DEG}"/>',
            f'{indent}  <geom name="{name}" type="mesh" mesh="{name}" rgba="{COLOURS[i]}"/>',
        ]
        indent += "  "
    lines += [" " * (4 + 2 * i) + "</body>" for i in range(len(LINKS) - 1, -1, -1)]
    summary = f"a {LENGTH:g} m European eel (Anguilla anguilla), 7 links, 6 yaw joints, 3D."
    return mjcf(
        "eel3d", summary, "\n".join(lines), Path(__file__).name, asset=asset, source="profile"
    )


if __name__ == "__main__":
    path = OUT / "eel3d.xml"
    path.write_text(xml())
    print(f"wrote {path}")
