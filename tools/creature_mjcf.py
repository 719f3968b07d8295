"""What every creature generator (``tools/make_*.py``) writes the same way: the MJCF
document around a creature's bodies, mesh vertex lists, and the closed surfaces
of visual-only geoms.

A creature whose fluid shape is a thickened stand-in (a plate a grid cell or
two thick where the animal's fin is a few millimetres) also carries a *visual
body*: geoms of the default class ``visual`` (density 0, so MuJoCo gives them
no mass) on the same links as the massive ones. aquagait draws those in its
pictures in place of the link's massive geoms and ignores them for
everything physical (``aquagait.body.reshape``, ``visual_only``). Their
meshes are given with faces (``loft``), so they may be non-convex.

The generators run as scripts (``python tools/make_frog.py``), so Python finds
this module beside them.
"""

from __future__ import annotations

import textwrap

import numpy as np


def fmt(points) -> str:
    """Points (n, 3) or one point as MJCF's space-separated numbers, to 0.01 mm."""
    return " ".join(f"{c:.5f}" for p in np.atleast_2d(points) for c in p)


def faces_fmt(faces) -> str:
    """Triangles (m, 3) as MJCF's space-separated vertex indices."""
    return " ".join(str(int(i)) for i in np.asarray(faces).ravel())


def mesh_xml(name: str, vertices, faces=None) -> str:
    """An ``<asset>`` line: a mesh of ``vertices`` (n, 3), with its ``faces`` (m, 3) if
    given (else MuJoCo takes the convex hull)."""
    given = "" if faces is None else f' face="{faces_fmt(faces)}"'
    return f'    <mesh name="{name}" vertex="{fmt(vertices)}"{given}/>'


def loft(rings) -> tuple[np.ndarray, np.ndarray]:
    """A closed surface through ``rings`` (n, m, 3): n closed polygons of m points,
    joined in order, each end shut by a fan from the ring's centroid.

    Returns:
        vertices (n m + 2, 3) and triangles (2 m (n - 1) + 2 m, 3), wound so that
        their normals point out (a positive enclosed volume), as MuJoCo wants.
    """
    rings = np.asarray(rings, dtype=float)
    n, m = rings.shape[:2]
    vertices = np.concatenate([rings.reshape(-1, 3), rings[[0, -1]].mean(axis=1)])
    i, j = np.meshgrid(np.arange(n - 1), np.arange(m), indexing="ij")
    a, b = i * m + j, i * m + (j + 1) % m
    c, d = a + m, b + m
    side = np.concatenate([np.stack([a, b, d], -1), np.stack([a, d, c], -1)]).reshape(-1, 3)
    ring = np.arange(m)
    first = np.stack([np.full(m, n * m), (ring + 1) % m, ring], -1)
    last = np.stack([np.full(m, n * m + 1), (n - 1) * m + ring, (n - 1) * m + (ring + 1) % m], -1)
    faces = np.concatenate([side, first, last])
    p, q, r = (vertices[faces[:, k]] for k in range(3))
    if np.einsum("ij,ij->i", p, np.cross(q, r)).sum() < 0:
        faces = faces[:, ::-1]
    return vertices, faces


def airfoil(xi) -> np.ndarray:
    """A section's thickness profile over its chord, ``xi`` 0 at the blunt (leading)
    edge to 1 at the thin (trailing) one: 1 at a third of the chord, 0 at both ends."""
    xi = np.clip(xi, 0.0, 1.0)
    return np.sqrt(xi) * (1 - xi) / (2 / 3**1.5)


def foil(span, lead, trail, half_thickness, edge=0.0002, chords=12):
    """A thin blade (a flipper, a wing, a fin) as a closed surface: its span along y,
    its chord along x, its thickness along z.

    Args:
        span: (n,) the stations' y [m], in order.
        lead, trail: (n,) x of the section's blunt and thin edges there [m].
        half_thickness: (n,) the section's largest half-thickness [m] (``airfoil``).
        edge: the half-thickness at both edges [m], so the surface stays closed.
        chords: points across each section, closer together at the edges.
    Returns:
        (vertices, faces) of ``loft``.
    """
    xi = (1 - np.cos(np.linspace(0, np.pi, chords))) / 2
    rings = []
    for y, le, te, h in zip(span, lead, trail, half_thickness, strict=True):
        x = le + (te - le) * xi
        z = np.maximum(h * airfoil(xi), edge)
        top = np.stack([x, np.full_like(x, y), z], -1)
        bottom = np.stack([x, np.full_like(x, y), -z], -1)[::-1]
        rings.append(np.concatenate([top, bottom]))
    return loft(rings)


def mjcf(name, summary, worldbody, script, depth=None, asset=None, source="dimensions",
         visual=None) -> str:  # fmt: skip
    """An MJCF document in the form all built-in creatures share: degrees, no
    gravity, water-density geoms without contacts, and a 2D creature's depth.

    Args:
        name: the model's name.
        summary: the header comment's description.
        worldbody: the ``<worldbody>``'s lines.
        script: the generator's file name, for the header.
        depth: a 2D creature's prism depth [m]; None in 3D.
        asset: the ``<asset>``'s lines, or None.
        source: what to edit in ``script`` to change the creature.
        visual: what its visual-only geoms (class ``visual``, density 0) are, for
            the header; None: it has none.
    """
    custom = (
        f'  <custom>\n    <numeric name="aquagait_depth" data="{depth:g}"/>\n  </custom>\n'
        if depth is not None
        else ""
    )
    assets = f"  <asset>\n{asset}\n  </asset>\n" if asset is not None else ""
    header, visual_class = "", ""
    if visual is not None:
        said = textwrap.fill(
            f'Visual geoms (class "visual", density 0: no mass): {visual} aquagait draws '
            "them in place of their links' massive geoms; the water, masses and inertias see "
            "only the massive ones.",
            width=95, initial_indent="     ", subsequent_indent="     ",
        )  # fmt: skip
        header = "\n" + said
        visual_class = '    <default class="visual">\n      <geom density="0"/>\n    </default>\n'
    return f"""<!-- {name}: {summary}{header}
     Generated by tools/{script}; edit the {source} there. -->
<mujoco model="{name}">
  <compiler angle="degree"/>
  <option gravity="0 0 0"/>
{custom}  <default>
    <geom density="1000" contype="0" conaffinity="0"/>
{visual_class}  </default>
{assets}  <worldbody>
{worldbody}
  </worldbody>
</mujoco>
"""
