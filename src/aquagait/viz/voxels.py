"""The body on its fluid grid: solid cells per link under the links' true outlines (paper Fig. 5).

    from aquagait.viz import plot_voxels
    plot_voxels(shape, grid, voxels, link_pos, link_rot, "runs/eel2d-check/voxels.png")

What the fluid sees of a creature: every solid cell filled in a pale tint of
the colour of the link that owns it, the cell lattice in thin grey, and over
them each link's outline (the zero level of its baked signed distance,
``aquagait.body.shape``) in the full colour, zoomed to the body with a few
cells of margin. A part thinner than about two cells shows as an outline
with few or no cells under it. 2D: the plane z = 0 (the creature's cut);
3D: three orthogonal slices through the middle of the body, each through a
layer of cell centres, so a cell is filled exactly where its centre lies
inside an outline (sealed pockets aside).

matplotlib is imported inside the function (the ``viz`` extra).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy.ndimage import map_coordinates

from aquagait.body.shape import BodyShape, world_bounds
from aquagait.body.voxelize import Voxels
from aquagait.grid import Grid

AXES = "xyz"
MARGIN = 3
"""Cells shown around the body on every side."""

TINT = 0.45
"""How much of a link's colour fills its cells (the rest is white)."""

LATTICE = (0.72, 0.72, 0.72)


def plot_voxels(
    shape: BodyShape,
    grid: Grid,
    voxels: Voxels,
    link_pos,
    link_rot,
    path,
    title: str = "",
    labels=None,
    margin: int = MARGIN,
) -> Path:
    """Draw the solid cells per link and the links' outlines at one pose, zoomed to the body.

    Args:
        shape: the links' baked geometry (at ``grid.cell_size``).
        grid: the fluid grid the body was voxelized on.
        voxels: ``voxelize(shape, grid, link_pos, link_rot)``.
        link_pos: (nl, 3) world link origins [m].
        link_rot: (nl, 3, 3) world link rotations.
        path: the PNG to write.
        title: a heading (e.g. the creature and the grid).
        labels: (nl,) legend entries, default the link names.
        margin: cells shown around the body.
    Returns:
        the path written.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    pos, turn = _poses(shape, link_pos, link_rot)
    colours = _colours(shape.nlinks)
    window = _window(shape, grid, voxels, pos, link_rot, margin)
    planes = _planes(shape, grid, pos, link_rot)
    widths = [window[p[0], 1] - window[p[0], 0] for p in planes]
    heights = [window[p[1], 1] - window[p[1], 0] for p in planes]
    handles = [
        Patch(facecolor=_tint(colours[k]), edgecolor=colours[k], label=label)
        for k, label in enumerate(labels or shape.links)
        if shape.dims[k, 0] > 0
    ]
    columns = min(len(handles), 5)
    legend = 0.2 + 0.25 * -(-len(handles) // columns)  # inches
    panels = max(1.2, 10.0 * max(heights) / sum(widths))
    height = panels + legend + 1.2  # title and axis labels
    fig, axes = plt.subplots(1, len(planes), figsize=(11.5, height), width_ratios=widths,
                             squeeze=False)  # fmt: skip
    for ax, plane in zip(axes[0], planes, strict=True):
        _draw_plane(ax, shape, grid, voxels, pos, turn, colours, window, plane)
    fig.legend(handles=handles, loc="lower center", ncol=columns, frameon=False)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout(rect=(0, legend / height, 1, 1))
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _poses(shape: BodyShape, link_pos, link_rot) -> tuple[np.ndarray, np.ndarray]:
    """Link origins (nl, 3) and rest-frame-to-world rotations (nl, 3, 3)."""
    rot = np.asarray(link_rot, dtype=float)
    return np.asarray(link_pos, dtype=float), rot @ np.swapaxes(shape.rest_rot, 1, 2)


def _colours(n: int) -> list[np.ndarray]:
    from matplotlib import colormaps

    if n <= 10:
        return [np.array(colormaps["tab10"](k)[:3]) for k in range(n)]
    order = [*range(0, 20, 2), *range(1, 20, 2)]  # tab20's strong colours first, then pale
    return [np.array(colormaps["tab20"](order[k % 20])[:3]) for k in range(n)]


def _tint(colour) -> np.ndarray:
    return TINT * np.asarray(colour) + (1 - TINT)


def _window(shape, grid, voxels, pos, link_rot, margin) -> np.ndarray:
    """(3, 2) world box shown: the body's box and its solid cells, plus ``margin`` cells."""
    box = world_bounds(shape, pos, link_rot)
    h, origin = grid.cell_size, _origin_3d(grid)
    solid = np.argwhere(voxels.solid.reshape(_shape_3d(grid)))
    if solid.size:
        box = np.stack([np.minimum(box[0], origin + solid.min(axis=0) * h),
                        np.maximum(box[1], origin + (solid.max(axis=0) + 1) * h)])  # fmt: skip
    lo = origin + np.floor((box[0] - origin) / h - margin) * h
    hi = origin + np.ceil((box[1] - origin) / h + margin) * h
    top = origin + np.asarray(_shape_3d(grid)) * h
    return np.stack([np.maximum(lo, origin), np.minimum(hi, top)], axis=1)


def _planes(shape, grid, pos, link_rot) -> list[tuple[int, int, int, int]]:
    """Each panel as (horizontal axis, vertical axis, normal axis, layer of cells)."""
    if shape.dim == 2:
        return [(0, 1, 2, 0)]
    centre = world_bounds(shape, pos, link_rot).mean(axis=0)
    layer = np.floor((centre - _origin_3d(grid)) / grid.cell_size).astype(int)
    layer = np.clip(layer, 0, np.asarray(grid.shape) - 1)
    return [(0, 1, 2, layer[2]), (0, 2, 1, layer[1]), (1, 2, 0, layer[0])]


def _draw_plane(ax, shape, grid, voxels, pos, turn, colours, window, plane) -> None:
    """One panel: tinted solid cells, the lattice, the outlines through the layer's cell centres."""
    from matplotlib.collections import LineCollection
    from matplotlib.ticker import FuncFormatter

    u, v, normal, layer = plane
    h, origin = grid.cell_size, _origin_3d(grid)
    owner = np.take(voxels.owner.reshape(_shape_3d(grid)), layer, axis=normal)  # axes (u, v)
    first = np.rint((window[[u, v], 0] - origin[[u, v]]) / h).astype(int)
    last = np.rint((window[[u, v], 1] - origin[[u, v]]) / h).astype(int)
    cells = owner[first[0] : last[0], first[1] : last[1]]
    fill = np.ones(cells.shape + (3,))
    for k, colour in enumerate(colours):
        fill[cells == k] = _tint(colour)
    extent = (window[u, 0], window[u, 1], window[v, 0], window[v, 1])
    ax.imshow(np.swapaxes(fill, 0, 1), origin="lower", extent=extent, interpolation="nearest")
    xs = window[u, 0] + h * np.arange(last[0] - first[0] + 1)
    ys = window[v, 0] + h * np.arange(last[1] - first[1] + 1)
    lines = [[(x, ys[0]), (x, ys[-1])] for x in xs] + [[(xs[0], y), (xs[-1], y)] for y in ys]
    ax.add_collection(LineCollection(lines, colors=[LATTICE], linewidths=0.4))
    height = origin[normal] + (layer + 0.5) * h if shape.dim == 3 else 0.0
    _draw_outlines(ax, shape, pos, turn, colours, window, (u, v, normal, height))
    ax.set_xlim(extent[:2])
    ax.set_ylim(extent[2:])
    ax.set_aspect("equal")
    millimetres = FuncFormatter(lambda metres, _: f"{metres * 1000:.4g}")
    for axis, name in ((ax.xaxis, AXES[u]), (ax.yaxis, AXES[v])):
        axis.set_major_formatter(millimetres)
        axis.set_label_text(f"{name} [mm]")
    if shape.dim == 3:
        ax.set_title(f"{AXES[u]}-{AXES[v]} slice at {AXES[normal]} = {height * 1000:.3g} mm",
                     fontsize=9)  # fmt: skip


def _draw_outlines(ax, shape, pos, turn, colours, window, plane) -> None:
    """The zero level of every link's signed distance on the plane, sampled finer than cells."""
    u, v, normal, height = plane
    step = shape.spacing / 2
    a = np.arange(window[u, 0], window[u, 1] + step, step)
    b = np.arange(window[v, 0], window[v, 1] + step, step)
    points = np.zeros((a.size, b.size, 3))
    points[..., u], points[..., v] = np.meshgrid(a, b, indexing="ij")
    points[..., normal] = height
    points = points.reshape(-1, 3)
    for k in range(shape.nlinks):
        if shape.dims[k, 0] == 0:
            continue
        phi = _link_distance(shape, k, pos[k], turn[k], points).reshape(a.size, b.size)
        if phi.min() < 0 < phi.max():
            ax.contour(a, b, phi.T, levels=[0.0], colors=[colours[k]], linewidths=1.3)


def _link_distance(shape: BodyShape, k: int, pos, turn, points) -> np.ndarray:
    """Link ``k``'s signed distance at world points (n, 3), interpolated [m]; > 0 off its grid."""
    rest = (points - pos) @ turn  # world = pos + turn @ rest
    index = (rest - shape.lower[k]) / shape.spacing
    sdf = shape.link_sdf(k).astype(float)
    if shape.dim == 2:
        sdf, index = sdf[:, :, 0], index[:, :2]
    return map_coordinates(sdf, index.T, order=1, mode="constant", cval=1.0)


def _shape_3d(grid: Grid) -> tuple[int, int, int]:
    return tuple(grid.shape) + (1,) * (3 - grid.dim)


def _origin_3d(grid: Grid) -> np.ndarray:
    """Grid origin in 3D; a 2D grid is one layer of cells centred on z = 0 (as ``voxelize``)."""
    return np.array(tuple(grid.origin) + (-grid.cell_size / 2,) * (3 - grid.dim))
