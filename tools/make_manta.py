"""Write ``src/aquagait/creatures/manta.xml``: a small manta (devil) ray of plates.

Run from the repository root: ``python tools/make_manta.py``. The body (the
disc's thick middle: head and trunk) is one convex mesh, the hull of
elliptic cross-sections along x. Each pectoral fin is four rows of plates
(paper §7: "four rows of thin plates that are connected"), front to back;
each row is a chain of plates outward, joined by hinges about x, so the fin
bends up and down. The rows are strips of the fin's swept planform: row k
covers ``[X_ROOT - (k+1) CHORD, X_ROOT - k CHORD]`` at the root, shifted back
by ``SWEEP`` per metre outward, and reaches ``ROW_SPAN[k]`` out from the
body; the plates are 8-vertex hulls (a quadrilateral extruded to the plate's
thickness), cut at the hinges' spans so neighbouring plates meet flush at
rest. The left fin is built and the right is its mirror image in y.

The ray swims towards +x with z up and its left fin on +y. A hinge's frame
sits on its axis at the plate's inner edge, mid-chord of the row there. Both
fins' hinges turn about +x, so a positive angle lifts the left fin and lowers
the right: flapping together is ``q_right = -q_left``.

The plates are 45 mm thick so that 25 mm cells see them; drawn so, the ray
looks like a stack of bricks. So every link also carries a *visual body*
(massless geoms of class ``visual``, drawn in place of the plates and
ignored by the water; ``tools/creature_mjcf.py``): a ray's wing, one
continuous planform with a falcate tip swept back (``wing_edges``), cut
along the rows' chord lines and the hinges' spans into one piece per plate,
a few millimetres thick (an airfoil-like section, ``WING_HALF_THICKNESS`` at
the root tapering by ``WING_TAPER`` to the tip); and on the body a
flattened disc centre that the wings' roots tuck into, two cephalic lobes
and a short tail stump. Each piece is two closed meshes, its dorsal half
dark and its ventral half pale, as a manta is.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from creature_mjcf import airfoil, fmt, loft, mesh_xml, mjcf

OUT = Path(__file__).resolve().parents[1] / "src" / "aquagait" / "creatures"

# Body: stations along x (snout at +0.13 m) and the half-width (y) and
# half-height (z) of the elliptic section there [m]: a blunt head 8 cm wide
# (the cephalic lobes left out), a trunk 9 cm wide and 6 cm deep, the back
# end rounded off (the whip-like tail left out: a few millimetres thick).
BODY_X = [0.13, 0.125, 0.11, 0.08, 0.0, -0.10, -0.13, -0.15]
BODY_HALF_WIDTH = [0.012, 0.025, 0.038, 0.045, 0.045, 0.045, 0.035, 0.02]
BODY_HALF_HEIGHT = [0.010, 0.016, 0.023, 0.027, 0.027, 0.027, 0.024, 0.022]
RING = 16

# Fins: each a swept planform of four rows, cut into plates at these spans.
Y_ROOT = 0.045  # the hinge line of the root plates: the body's side [m]
X_ROOT = 0.07  # the fin's leading edge at the root [m]
CHORD = 0.05  # each row's chord along x [m]: four rows, 0.2 m at the root
SWEEP = 0.5  # the rows shift back 0.5 m per metre outward (27 deg sweep)
ROW_SPAN = [0.125, 0.115, 0.10, 0.065]  # how far each row reaches out from Y_ROOT [m]
ROW_PLATES = [2, 2, 2, 1]  # plates per row: 7 hinges per fin
HALF_THICKNESS = 0.0225  # 4.5 cm plates: 1.8 cells of 25 mm (a real fin is ~1 cm at its root)
LIMIT_DEG = 45  # every fin hinge
BODY_COLOUR, FIN_COLOUR = "0.22 0.24 0.28 1", "0.30 0.33 0.38 1"

# The visual body (no mass; drawn only). The wing's planform in the fins'
# swept coordinates: span s = y - Y_ROOT, sigma = s / S, and chord depth
# c = row_front(0, y) - x (behind the plates' leading edge). The leading edge,
# c_le = TIP_SWEEP sigma^3, follows the plates' near the body and bends back
# to the tip at s = S, TIP_SWEEP behind it; the trailing edge runs in x from the
# root plates' back edge to the tip as sigma^TE_POWER, a little ahead of a
# straight line (concave, as a manta's is): a falcate, pointed wing.
WING_SPAN = 0.13  # S: the tip's distance from the hinge line [m] (the plates reach 0.125)
TIP_SWEEP = 0.065  # how far behind the plates' leading edge the tip lies [m]
TE_POWER = 0.85
WING_HALF_THICKNESS = 0.0035  # at the root's thickest chord point [m]: a 7 mm wing root
WING_TAPER = 0.7  # the tip is this much thinner than the root
EDGE = 0.0003  # half-thickness at the leading and trailing edges [m]
WING_ROWS, WING_CHORDS = 9, 8  # samples per piece, spanwise and chordwise
# The body's disc centre: half-width, half-height, from snout to tail stump [m].
DISC_X = [0.13, 0.128, 0.124, 0.115, 0.10, 0.08, 0.06, 0.0, -0.09, -0.125, -0.14, -0.152]
DISC_HALF_WIDTH = [0.014, 0.022, 0.028, 0.034, 0.039, 0.045, 0.049, 0.052, 0.05, 0.047, 0.03,
                   0.008]  # fmt: skip
DISC_HALF_HEIGHT = [0.004, 0.007, 0.010, 0.013, 0.015, 0.017, 0.019, 0.020, 0.019, 0.016, 0.012,
                    0.006]  # fmt: skip
DISC_EDGE = 0.0015  # half-height at the disc's rim [m]
LOBE = {"root": (0.112, 0.024), "length": 0.036, "width": 0.014, "half_thickness": 0.0015}
TAIL = {"length": 0.07, "radius": (0.0045, 0.0008)}
DORSAL, VENTRAL = "0.17 0.19 0.24 1", "0.86 0.87 0.85 1"


def body_mesh() -> list:
    angles = np.linspace(0, 2 * np.pi, RING, endpoint=False)
    return [
        (x, w * np.cos(a), h * np.sin(a))
        for x, w, h in zip(BODY_X, BODY_HALF_WIDTH, BODY_HALF_HEIGHT, strict=True)
        for a in angles
    ]


def row_front(k: int, y: float) -> float:
    """x of row k's front edge at span y (distance from the centre line) [m]."""
    return X_ROOT - k * CHORD - SWEEP * (y - Y_ROOT)


def plate_spans(k: int) -> list[float]:
    """Span positions (y) of row k's hinges and tip, from the root outward [m]."""
    n = ROW_PLATES[k]
    return [Y_ROOT + ROW_SPAN[k] * j / n for j in range(n + 1)]


def frame(k: int, y: float) -> np.ndarray:
    """A plate's frame in body coordinates: on its hinge, at mid-chord of row k at span y."""
    return np.array([row_front(k, y) - CHORD / 2, y, 0.0])


def plate_mesh(k: int, y0: float, y1: float) -> list:
    """8 vertices of row k's plate between spans y0 and y1, in its frame (at y0)."""
    o = frame(k, y0)
    return [
        (x - o[0], y - o[1], z)
        for y in (y0, y1)
        for x in (row_front(k, y), row_front(k, y) - CHORD)
        for z in (-HALF_THICKNESS, HALF_THICKNESS)
    ]


def plate_name(side: str, k: int, j: int) -> str:
    """Link name: ``left2_in``, ``left2_out``; a row of one plate: ``left4``."""
    if ROW_PLATES[k] == 1:
        return f"{side}{k + 1}"
    return f"{side}{k + 1}_{('in', 'out')[j]}"


def joint_name(side: str, k: int, j: int) -> str:
    """Hinge name: ``l1a`` (row 1's root hinge, left), ``l1b`` (its outer), ``r4a``."""
    return f"{side[0]}{k + 1}{'ab'[j]}"


def fin(side: str, indent: str) -> tuple[list[str], list[str]]:
    """The MJCF bodies of one fin (``side`` 'left' on +y, 'right' its mirror), and its meshes."""
    sign = 1 if side == "left" else -1
    lines, assets = [], []
    for k in range(4):
        spans = plate_spans(k)
        parent = np.zeros(3)  # the body's frame
        pad = indent
        for j in range(ROW_PLATES[k]):
            name = plate_name(side, k, j)
            o = frame(k, spans[j])
            pos = (o - parent) * [1, sign, 1]
            vertices = [(x, sign * y, z) for x, y, z in plate_mesh(k, spans[j], spans[j + 1])]
            assets.append(f'    <mesh name="{name}" vertex="{fmt(vertices)}"/>')
            lines += [
                f'{pad}<body name="{name}" pos="{pos[0]:.5g} {pos[1]:.5g} 0">',
                f'{pad}  <joint name="{joint_name(side, k, j)}" type="hinge" axis="1 0 0" '
                f'range="-{LIMIT_DEG} {LIMIT_DEG}"/>',
                f'{pad}  <geom name="{name}" type="mesh" mesh="{name}" rgba="{FIN_COLOUR}"/>',
            ]
            for half, colour in (("dorsal", DORSAL), ("ventral", VENTRAL)):
                piece = wing_piece(k, spans[j], spans[j + 1], half == "dorsal")
                lines.append(pad + "  " + visual_geom(f"{name}_{half}", piece, colour,
                                                      assets, sign))  # fmt: skip
            parent, pad = o, pad + "  "
        lines += [indent + "  " * j + "</body>" for j in range(ROW_PLATES[k] - 1, -1, -1)]
    return lines, assets


def wing_edges(s):
    """The visual wing's leading and trailing edges at span ``s`` [m], as chord depths
    behind the plates' leading edge (module doc): ``(c_le, c_te)``."""
    sigma = np.asarray(s) / WING_SPAN
    back = SWEEP * WING_SPAN + TIP_SWEEP - 4 * CHORD  # tip x less root trailing edge x
    return TIP_SWEEP * sigma**3, 4 * CHORD - SWEEP * WING_SPAN * sigma + back * sigma**TE_POWER


def wing_half_thickness(s, c):
    """Half the visual wing's thickness at span ``s`` and chord depth ``c`` [m]: an
    airfoil-like section (blunt front, thin back), thinner towards the tip."""
    le, te = wing_edges(s)
    section = airfoil((c - le) / (te - le))
    return np.maximum(WING_HALF_THICKNESS * (1 - WING_TAPER * s / WING_SPAN) * section, EDGE)


def piece_chords(k: int, s):
    """Row k's share of the visual wing at span s: chord depths ``(lo, hi)`` [m]."""
    le, te = wing_edges(s)
    return np.maximum(k * CHORD, le), np.minimum((k + 1) * CHORD, te)


def wing_corners() -> np.ndarray:
    """The spans [m] where the wing's edges cross the rows' chord lines: each row's share
    of the wing has a corner there, so every piece is sampled there."""
    s = np.linspace(0, WING_SPAN, 20001)
    found = []
    for edge in wing_edges(s):
        for m in range(1, 4):
            side = edge > m * CHORD
            found += [s[i] for i in np.flatnonzero(side[1:] != side[:-1])]
    return np.array(found)


def piece_end(k: int, s0: float, s1: float) -> float:
    """Where row k's share of the wing, between spans s0 and s1, narrows to a 1 mm
    chord (or s1, if it never does) [m]."""
    lo, hi = piece_chords(k, np.linspace(s0, s1, 4001))
    narrow = np.flatnonzero(hi - lo < 0.001)
    return s1 if narrow.size == 0 else s0 + (s1 - s0) * (narrow[0] - 1) / 4000


def wing_piece(k: int, y0: float, y1: float, upper: bool) -> tuple[np.ndarray, np.ndarray]:
    """The dorsal (``upper``) or ventral half of the visual wing over row k's plate from
    span y0 to y1 (left fin), in the plate's frame: a closed mesh (vertices, faces)."""
    s0, s1 = y0 - Y_ROOT, y1 - Y_ROOT
    if np.isclose(s1, ROW_SPAN[k]):  # the row's outer plate: as far out as the wing has it
        s1 = piece_end(k, s0, WING_SPAN)
    sign, o = (1 if upper else -1), frame(k, y0)
    corners = wing_corners()
    spans = np.union1d(np.linspace(s0, s1, WING_ROWS), corners[(corners > s0) & (corners < s1)])
    rings = []
    for s in spans:
        lo, hi = piece_chords(k, s)
        c = lo + (hi - lo) * (1 - np.cos(np.linspace(0, np.pi, WING_CHORDS))) / 2
        x, y = X_ROOT - SWEEP * s - c, np.full_like(c, Y_ROOT + s)
        surface = np.stack([x, y, sign * wing_half_thickness(s, c)], -1)
        middle = np.stack([x, y, np.zeros_like(c)], -1)[[-1, 0]]  # flat: its two ends
        rings.append(np.concatenate([surface, middle]) - o)
    return loft(rings)


def disc_piece(upper: bool) -> tuple[np.ndarray, np.ndarray]:
    """The dorsal or ventral half of the body's disc centre (a closed mesh, body frame):
    lens-shaped sections, thin at the rim where the wings' roots tuck in."""
    sign, rings = (1 if upper else -1), []
    xs = np.linspace(DISC_X[0], DISC_X[-1], 28)
    for x in xs[1:-1]:
        w = np.interp(x, DISC_X[::-1], DISC_HALF_WIDTH[::-1])
        h = np.interp(x, DISC_X[::-1], DISC_HALF_HEIGHT[::-1])
        y = w * np.cos(np.linspace(0, np.pi, 19))
        z = np.maximum(h * (1 - (y / w) ** 2) ** 0.9, DISC_EDGE)
        top = np.stack([np.full_like(y, x), y, sign * z], -1)
        middle = [(x, -w, 0.0), (x, w, 0.0)]  # the flat mid-plane: its two ends
        rings.append(np.concatenate([top, middle]))
    return loft(rings)


def lobe(side: int) -> tuple[np.ndarray, np.ndarray]:
    """A cephalic lobe: a flat paddle from the head's front corner, forward and curling
    in and down (body frame); ``side`` +1 left, -1 right."""
    x0, y0 = LOBE["root"]
    rings = []
    for t in np.linspace(0, 1, 10):
        centre = np.array([x0 + LOBE["length"] * t, side * (y0 - 0.004 * t**2), -0.008 * t**1.5])
        half = LOBE["width"] / 2 * (1 - 0.4 * t)
        a = np.linspace(0, 2 * np.pi, 12, endpoint=False)
        ring = np.stack([0 * a, half * np.cos(a), LOBE["half_thickness"] * np.sin(a)], -1)
        tilt = np.radians(side * -60)  # the paddle's flat side turned inward, half rolled
        roll = np.array(
            [[1, 0, 0], [0, np.cos(tilt), -np.sin(tilt)], [0, np.sin(tilt), np.cos(tilt)]]
        )
        rings.append(centre + ring @ roll.T)
    return loft(rings)


def tail() -> tuple[np.ndarray, np.ndarray]:
    """A short tail stump behind the disc (body frame), tapering to a point."""
    a = np.linspace(0, 2 * np.pi, 10, endpoint=False)
    r0, r1 = TAIL["radius"]
    rings = [
        np.stack([np.full_like(a, DISC_X[-1] + 0.004 - TAIL["length"] * t),
                  r * np.cos(a), r * np.sin(a) + 0.002], -1)
        for t, r in zip(np.linspace(0, 1, 8), np.linspace(r0, r1, 8), strict=True)
    ]  # fmt: skip
    return loft(rings)


def visual_geom(name: str, mesh, colour: str, assets: list, sign: int = 1) -> str:
    """A visual geom's line, its mesh (mirrored in y when ``sign`` is -1) added to ``assets``."""
    vertices, faces = mesh
    if sign < 0:
        vertices, faces = vertices * [1, -1, 1], faces[:, ::-1]
    assets.append(mesh_xml(name, vertices, faces))
    return f'<geom name="{name}" class="visual" type="mesh" mesh="{name}" rgba="{colour}"/>'


def xml() -> str:
    left, left_assets = fin("left", "      ")
    right, right_assets = fin("right", "      ")
    body_assets = [f'    <mesh name="body" vertex="{fmt(body_mesh())}"/>']
    looks = [
        visual_geom("disc_dorsal", disc_piece(True), DORSAL, body_assets),
        visual_geom("disc_ventral", disc_piece(False), VENTRAL, body_assets),
        visual_geom("lobe_left", lobe(1), DORSAL, body_assets),
        visual_geom("lobe_right", lobe(-1), DORSAL, body_assets),
        visual_geom("tail", tail(), DORSAL, body_assets),
    ]
    asset = "\n".join([*body_assets, *left_assets, *right_assets])
    span = 2 * (Y_ROOT + max(ROW_SPAN))
    worldbody = "\n".join([
        '    <body name="body" pos="0 0 0">',
        '      <freejoint name="root"/>',
        f'      <geom name="body" type="mesh" mesh="body" rgba="{BODY_COLOUR}"/>',
        *("      " + line for line in looks),
        *left,
        *right,
        "    </body>",
    ])  # fmt: skip
    summary = (
        f"a small devil ray, {span:g} m span, a body and two fins of 4 rows of plates, "
        "14 hinges about x, 3D."
    )
    visual = (
        "per plate, its share of a ray's thin wing (a falcate planform, 7 mm thick at the "
        "root, tapering), dorsal half dark and ventral half pale; on the body, a flattened "
        "disc centre, two cephalic lobes and a tail stump."
    )
    return mjcf("manta", summary, worldbody, Path(__file__).name, asset=asset,
                source="dimensions", visual=visual)  # fmt: skip


if __name__ == "__main__":
    path = OUT / "manta.xml"
    path.write_text(xml())
    print(f"wrote {path}")
