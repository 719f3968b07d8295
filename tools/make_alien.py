"""Write ``src/aquagait/creatures/alien.xml``: an imaginary swimmer, a long tail, four wings.

Run from the repository root: ``python tools/make_alien.py``. The numbers and
which of them are free choices are in ``src/aquagait/creatures/alien.py``;
this script only turns them into MJCF. The trunk and tail are hulls of
elliptic sections (each tail link from its front joint to the next), the
caudal fin and the four wings 8-vertex plates.

The alien swims towards +x with z up, its snout at x = TRUNK_LENGTH / 2. The
tail's 8 hinges bend it in the x-y plane (yaw). Each wing has two hinges at
its root: flap (about x, the wing beats up and down) and pitch (about the
span, y: the wing's angle of attack). The right wings (y < 0) are the left
ones reflected in the x-z plane, joint axes included (``n_right = M n_left``);
a reflected rotation turns the other way, so the mirrored gait is
``qbar_right = -qbar_left`` (``mirror`` sign -1 in ``alien.aquagait.json``).

The wings and the caudal fin are 8 mm plates, two of the grid's 4 mm cells,
so that the fluid sees them; drawn so, they are blocks. So those links also
carry a *visual* wing or fin (a massless geom of class ``visual``, drawn in
place of the plate and ignored by the water; ``tools/creature_mjcf.py``): a
thin blade (``foil``, 1.8 mm at the wing's root, 1.2 mm at the fin's
middle), the wing rounded and swept back at its tip, the caudal fin forked
(lunate) with pointed lobes.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from creature_mjcf import foil, mesh_xml, mjcf

OUT = Path(__file__).resolve().parents[1] / "src" / "aquagait" / "creatures" / "alien.xml"

# Trunk: stations s from the snout, half-width (y) and half-height (z) [m].
TRUNK_LENGTH = 0.13
TRUNK_S = [0.0, 0.008, 0.02, 0.04, 0.065, 0.09, 0.11, 0.13]
TRUNK_B = [0.003, 0.007, 0.0095, 0.0105, 0.0105, 0.010, 0.0095, 0.009]
TRUNK_H = [0.003, 0.006, 0.0075, 0.008, 0.008, 0.0078, 0.0074, 0.007]

# Tail: 7 tapering links, then the caudal fin link; each joint a yaw hinge.
TAIL_LINK = 0.015  # length of each of tail1..tail7 [m]
TAIL_B = [0.009, 0.0082, 0.0074, 0.0066, 0.0058, 0.005, 0.0044, 0.004]  # half-width at each joint
TAIL_H = [0.007, 0.0067, 0.0064, 0.006, 0.0056, 0.0052, 0.005, 0.005]  # half-height at each joint
TAIL_LIMIT_DEG = 20
# caudal fin: a vertical plate 20 mm long, 10 -> 20 mm high, 8 mm thick
FIN = {"length": 0.020, "h0": 0.005, "h1": 0.010, "half_thickness": 0.004}

# Wings: root positions along the trunk (x of the root's mid-chord), the
# plate's chord at root and tip, span and thickness [m]; limits [deg].
WING_X = {"wing1": 0.030, "wing2": -0.030}
WING = {"span": 0.022, "chord0": 0.026, "chord1": 0.016, "half_thickness": 0.004}
FLAP_LIMIT_DEG, PITCH_LIMIT_DEG = 12, 15

COLOURS = {"trunk": "0.45 0.2 0.55 1", "tail": "0.5 0.25 0.6 1", "wing": "0.2 0.65 0.6 1"}

# The visual wing and fin (no mass; drawn only) [m]. The wing along its span r:
# chord 26 mm at the root, rounding off at VISUAL_WING_SPAN, its middle swept
# back by up to WING_SWEEP (the tip a little behind the root's trailing edge).
# The caudal fin over its height z: its front edge at the joint where the tail
# meets it (|z| < FIN_ROOT), then swept back along the lobes; its trailing edge
# forked, FIN_NOTCH behind the joint in the middle and FIN_TIP at the lobes'
# tips, |z| = FIN_HEIGHT.
VISUAL_WING_SPAN = 0.025
WING_SWEEP = 0.016
WING_HALF_THICKNESS = (0.0009, 0.0004)  # root, tip
FIN_ROOT, FIN_HEIGHT, FIN_NOTCH, FIN_TIP = 0.004, 0.014, 0.014, 0.03
FIN_HALF_THICKNESS = (0.0006, 0.0003)  # middle, tips


def sections(xs, bs, hs, ring: int = 16) -> np.ndarray:
    """Vertices of elliptic sections at x with half-width b (y) and half-height h (z)."""
    angles = np.linspace(0, 2 * np.pi, ring, endpoint=False)
    return np.array([
        (x, b * np.cos(t), h * np.sin(t))
        for x, b, h in zip(xs, bs, hs, strict=True)
        for t in angles
    ])  # fmt: skip


def trunk_half_width(x: float) -> float:
    """The trunk's half-width [m] at world x."""
    return float(np.interp(TRUNK_LENGTH / 2 - x, TRUNK_S, TRUNK_B))


def trunk_mesh() -> np.ndarray:
    return sections([TRUNK_LENGTH / 2 - s for s in TRUNK_S], TRUNK_B, TRUNK_H)


def tail_mesh(k: int) -> np.ndarray:
    """Tail link k (0..6) in its frame at its front joint."""
    return sections([0.0, -TAIL_LINK], TAIL_B[k : k + 2], TAIL_H[k : k + 2])


def fin_mesh() -> np.ndarray:
    f = FIN
    return np.array([
        (-s, side * f["half_thickness"], up * h)
        for s, h in ((0.0, f["h0"]), (f["length"], f["h1"]))
        for side in (-1, 1)
        for up in (-1, 1)
    ])  # fmt: skip


def wing_mesh(side: int) -> np.ndarray:
    """A wing plate in its frame at the root's mid-chord; side +1 left, -1 right."""
    w = WING
    return np.array([
        (x * c / 2, side * y, up * w["half_thickness"])
        for y, c in ((0.0, w["chord0"]), (w["span"], w["chord1"]))
        for x in (-1, 1)
        for up in (-1, 1)
    ])  # fmt: skip


def wing_visual(side: int) -> tuple[np.ndarray, np.ndarray]:
    """The thin visual wing in the wing's frame (closed mesh); side +1 left, -1 right."""
    r = np.linspace(0, VISUAL_WING_SPAN, 12)
    u = r / VISUAL_WING_SPAN
    chord = np.maximum(WING["chord0"] * (1 - 0.2 * u) * (1 - u**3) ** 0.5, 0.0015)
    middle = -WING_SWEEP * u**1.5
    h0, h1 = WING_HALF_THICKNESS
    vertices, faces = foil(r, middle + chord / 2, middle - chord / 2, h0 + (h1 - h0) * u)
    if side < 0:
        vertices, faces = vertices * [1, -1, 1], faces[:, ::-1]
    return vertices, faces


def fin_visual() -> tuple[np.ndarray, np.ndarray]:
    """The thin, forked visual caudal fin in the fin link's frame (closed mesh): a blade
    spanning z, its chord along -x, thin in y."""
    z = FIN_HEIGHT * np.sin(np.linspace(-np.pi / 2, np.pi / 2, 21)) * 0.97  # tips: 1 mm chords
    a = np.abs(z)
    lead = -FIN_TIP * (np.clip(a - FIN_ROOT, 0, None) / (FIN_HEIGHT - FIN_ROOT)) ** 1.2
    trail = -FIN_NOTCH - (FIN_TIP - FIN_NOTCH) * (a / FIN_HEIGHT) ** 1.3
    h0, h1 = FIN_HALF_THICKNESS
    vertices, faces = foil(z, lead, trail, h0 + (h1 - h0) * a / FIN_HEIGHT)
    return vertices[:, [0, 2, 1]], faces[:, ::-1]  # span along z, thickness along y


def visual_geom(name: str, colour: str) -> str:
    return f'<geom name="{name}" class="visual" type="mesh" mesh="{name}" rgba="{colour}"/>'


def wing_xml(name: str, side: int, pad: str) -> list[str]:
    s = "l" if side > 0 else "r"
    x = WING_X[name]
    y = side * trunk_half_width(x)
    return [
        f'{pad}<body name="{name}_{s}" pos="{x:g} {y:.5f} 0">',
        f'{pad}  <joint name="{name}_flap_{s}" type="hinge" axis="1 0 0" '
        f'range="-{FLAP_LIMIT_DEG} {FLAP_LIMIT_DEG}"/>',
        f'{pad}  <joint name="{name}_pitch_{s}" type="hinge" axis="0 {side} 0" '
        f'range="-{PITCH_LIMIT_DEG} {PITCH_LIMIT_DEG}"/>',
        f'{pad}  <geom name="{name}_{s}" type="mesh" mesh="{name}_{s}" rgba="{COLOURS["wing"]}"/>',
        f"{pad}  " + visual_geom(f"{name}_{s}_look", COLOURS["wing"]),
        f"{pad}</body>",
    ]


def tail_xml(pad: str) -> list[str]:
    lines, pos = [], -TRUNK_LENGTH / 2
    for k in range(8):
        name = f"tail{k + 1}"
        indent = pad + "  " * k
        lines += [
            f'{indent}<body name="{name}" pos="{pos:g} 0 0">',
            f'{indent}  <joint name="t{k + 1}" type="hinge" axis="0 0 1" '
            f'range="-{TAIL_LIMIT_DEG} {TAIL_LIMIT_DEG}"/>',
            f'{indent}  <geom name="{name}" type="mesh" mesh="{name}" rgba="{COLOURS["tail"]}"/>',
        ]
        if k == 7:
            lines.append(f"{indent}  " + visual_geom("fin_look", COLOURS["tail"]))
        pos = -TAIL_LINK
    lines += [pad + "  " * k + "</body>" for k in range(7, -1, -1)]
    return lines


def alien_xml() -> str:
    meshes = {"trunk": trunk_mesh(), **{f"tail{k + 1}": tail_mesh(k) for k in range(7)}}
    meshes["tail8"] = fin_mesh()
    for name in WING_X:
        meshes[f"{name}_l"], meshes[f"{name}_r"] = wing_mesh(1), wing_mesh(-1)
    looks = {"fin_look": fin_visual()}
    for name in WING_X:
        looks[f"{name}_l_look"], looks[f"{name}_r_look"] = wing_visual(1), wing_visual(-1)
    asset = "\n".join(
        [mesh_xml(n, v) for n, v in meshes.items()] + [mesh_xml(n, *v) for n, v in looks.items()]
    )
    body = [
        '    <body name="trunk" pos="0 0 0">',
        '      <freejoint name="root"/>',
        f'      <geom name="trunk" type="mesh" mesh="trunk" rgba="{COLOURS["trunk"]}"/>',
    ]
    for name in WING_X:
        for side in (1, -1):
            body += wing_xml(name, side, "      ")
    body += tail_xml("      ")
    body.append("    </body>")
    summary = "an imaginary swimmer, four wings and a long tail, 16 hinges, 3D."
    visual = "thin wings, rounded and swept at the tips, and a thin forked caudal fin."
    return mjcf("alien", summary, "\n".join(body), Path(__file__).name, asset=asset,
                source="dimensions", visual=visual)  # fmt: skip


if __name__ == "__main__":
    OUT.write_text(alien_xml())
    print(f"wrote {OUT}")
