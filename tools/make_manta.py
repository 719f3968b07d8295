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
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from creature_mjcf import fmt, mjcf

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
            parent, pad = o, pad + "  "
        lines += [indent + "  " * j + "</body>" for j in range(ROW_PLATES[k] - 1, -1, -1)]
    return lines, assets


def xml() -> str:
    left, left_assets = fin("left", "      ")
    right, right_assets = fin("right", "      ")
    asset = "\n".join(
        [f'    <mesh name="body" vertex="{fmt(body_mesh())}"/>', *left_assets, *right_assets]
    )
    span = 2 * (Y_ROOT + max(ROW_SPAN))
    worldbody = "\n".join([
        '    <body name="body" pos="0 0 0">',
        '      <freejoint name="root"/>',
        f'      <geom name="body" type="mesh" mesh="body" rgba="{BODY_COLOUR}"/>',
        *left,
        *right,
        "    </body>",
    ])  # fmt: skip
    summary = (
        f"a small devil ray, {span:g} m span, a body and two fins of 4 rows of plates, "
        "14 hinges about x, 3D."
    )
    return mjcf("manta", summary, worldbody, Path(__file__).name, asset=asset, source="dimensions")


if __name__ == "__main__":
    path = OUT / "manta.xml"
    path.write_text(xml())
    print(f"wrote {path}")
