"""A swim as VTK XML files for ParaView: the fluid as image data, the body as polydata.

``write(data, path)`` makes the folder ``path`` (``swim-vtk/``)::

    fluid.pvd                 the fluid's frames as one time series
    fluid/frame_00000.vti     ImageData: the lattice's cell centres as points
    body.pvd, body/frame_00000.vtp      PolyData: every link's triangles
    traces.pvd, traces/frame_00000.vtp  PolyData: one polyline per particle trace

Open it with ``paraview swim-vtk/fluid.pvd swim-vtk/body.pvd``: each ``.pvd``
plays as a time series (``timestep`` in seconds from the first frame).

Fluid (where the run recorded one): the cell centres of frame f are VTK
points, ``Origin`` = the lattice's lower corner + h/2 and ``Spacing`` = h, so
each frame sits where the grid was (it follows the creature by whole cells).
A 2D swim is one layer of points in the plane z = 0. Point data:
``velocity`` (3 components, z = 0 in 2D) [m/s], ``vorticity`` [1/s] (3D: the
vector; 2D: the scalar dv/dx - du/dy, ``aquagait.sim.particles.vorticity``)
and ``solid`` (1 inside the body). The run directory keeps no pressure, so
none is written.

Body: world positions [m] of all links' vertices, point data ``Normals``
(unit, world) and ``colour`` (RGBA bytes of the MJCF colours, shown with
"Map Scalars" off), cell data ``link`` (the link's index in ``link_names``).
Traces: the positions [m] each particle held over the last frames, oldest
first, point data ``opacity`` in [0, 1] (``SwimExport.trace_alpha``).

The files are binary, appended raw (``header_type="UInt64"``, little-endian,
Float32 values) and zlib-compressed at level 1 (``COMPRESSION``: the 4 s fish
swim's folder 224 MB raw, ~90 MB compressed), written with numpy and zlib.
"""

from __future__ import annotations

import zlib
from pathlib import Path

import numpy as np

from aquagait.io.export.data import SwimExport
from aquagait.sim.frames import FluidFrames
from aquagait.sim.particles import vorticity

COMPRESSION = 1
"""zlib's level: the fastest; higher levels gain a few per cent at several times the time."""

LIBRARY = "numpy"
"""What this writer needs: nothing beyond the core install."""

_TYPES = {"f4": "Float32", "u1": "UInt8", "i4": "Int32"}
"""VTK's names for the numpy types written (``dtype.str`` without its byte order)."""


def check_available() -> None:
    """Nothing to check: the files are written with numpy alone."""


def write(data: SwimExport, path: Path) -> None:
    """Write ``data`` as the folder ``path`` of VTK XML files (module docstring).

    Args:
        data: the swim (``swim_export``).
        path: the folder to make; it must not exist yet.
    """
    path = Path(path)
    path.mkdir()
    if data.fluid is not None:
        frames = (_image(data.fluid, f) for f in range(data.frames))
        _series(path, "fluid", "vti", data.time, frames)
    _series(path, "body", "vtp", data.time, (_body(data, f) for f in range(data.frames)))
    if data.traces is not None:
        frames = (_traces(data.traces[f], data.trace_alpha[f]) for f in range(data.frames))
        _series(path, "traces", "vtp", data.time, frames)


def _series(path: Path, name: str, suffix: str, time, frames) -> None:
    """Files ``name/frame_00000.suffix``... and ``name.pvd``, which plays them at ``time`` [s]."""
    (path / name).mkdir()
    rows = []
    for f, (t, content) in enumerate(zip(time, frames, strict=True)):
        file = f"{name}/frame_{f:05d}.{suffix}"
        (path / file).write_bytes(content)
        rows.append(f'    <DataSet timestep="{float(t)!r}" group="" part="0" file="{file}"/>')
    (path / f"{name}.pvd").write_text(
        '<?xml version="1.0"?>\n<VTKFile type="Collection" version="1.0" '
        'byte_order="LittleEndian">\n  <Collection>\n' + "\n".join(rows) + "\n  </Collection>\n"
        "</VTKFile>\n"
    )


def _image(fluid: FluidFrames, f: int) -> bytes:
    """Frame ``f`` of the fluid as a ``.vti`` file: point data at the cell centres."""
    h, shape = float(fluid.cell_size), fluid.shape
    velocity = fluid.velocity[f].astype(np.float32)
    omega = vorticity(fluid, f)
    if fluid.dim == 2:
        velocity = np.concatenate([velocity, np.zeros_like(velocity[:1])])
        shape = (*shape, 1)
    tags, blob = _appended(
        {
            "velocity": _points(velocity, fluid.dim),
            "vorticity": _points(omega.astype(np.float32), fluid.dim),
            "solid": _points(fluid.solid[f].astype(np.uint8), fluid.dim),
        }
    )
    extent = " ".join(f"0 {n - 1}" for n in shape)
    origin = np.append(fluid.origin[f] + h / 2, [0.0] * (3 - fluid.dim))
    inner = (
        f'<ImageData WholeExtent="{extent}" Origin="{" ".join(map(repr, origin.tolist()))}" '
        f'Spacing="{h!r} {h!r} {h!r}">\n<Piece Extent="{extent}">\n'
        f'<PointData Vectors="velocity">\n{tags["velocity"]}\n{tags["vorticity"]}\n'
        f"{tags['solid']}\n</PointData>\n</Piece>\n</ImageData>"
    )
    return _document("ImageData", inner, blob)


def _points(field: np.ndarray, dim: int) -> np.ndarray:
    """A cell-centred field, (nx, ny[, nz]) or (c, nx, ny[, nz]), as VTK points: x fastest."""
    if field.ndim == dim:
        return field.T.ravel()
    return np.stack([component.T.ravel() for component in field], axis=1)


def _body(data: SwimExport, f: int) -> bytes:
    """Frame ``f`` of the body as a ``.vtp`` file: all links' triangles in world coordinates."""
    points, normals, colours, triangles, links, start = [], [], [], [], [], 0
    for link, mesh in enumerate(data.meshes):
        rot = data.link_rot[f, link]
        points.append(data.link_pos[f, link] + mesh.vertices @ rot.T)
        normals.append(mesh.normals @ rot.T)
        colours.append(np.round(np.clip(mesh.colours, 0, 1) * 255))
        triangles.append(mesh.triangles + start)
        links.append(np.full(len(mesh.triangles), link))
        start += len(mesh.vertices)
    point_data = {
        "Normals": np.concatenate(normals).astype(np.float32),
        "colour": np.concatenate(colours).astype(np.uint8),
    }
    cell_data = {"link": np.concatenate(links).astype(np.int32)}
    triangles = np.concatenate(triangles)
    return _polydata(np.concatenate(points), "Polys", triangles.ravel(), np.full(len(triangles), 3),
                     point_data, cell_data)  # fmt: skip


def _traces(traces: np.ndarray, alpha: np.ndarray) -> bytes:
    """One frame's traces (N, L, 3) and opacity (N, L) as a ``.vtp`` file of polylines.

    A trace keeps its finite positions (NaN where it is younger than L
    frames); one with fewer than two is left out.
    """
    finite = np.isfinite(traces).all(axis=-1)
    finite[finite.sum(axis=1) < 2] = False
    sizes = finite.sum(axis=1)
    points = traces[finite]
    opacity = {"opacity": alpha[finite].astype(np.float32)}
    return _polydata(points, "Lines", np.arange(len(points)), sizes[sizes > 0], opacity, {})


def _polydata(points, kind: str, connectivity, sizes, point_data: dict, cell_data: dict) -> bytes:
    """A ``.vtp`` file: ``points`` (n, 3) [m] joined into cells of ``kind`` ("Polys", "Lines").

    Args:
        connectivity: the cells' point indices, one cell after another.
        sizes: (cells,) points per cell.
        point_data, cell_data: name: (n,) or (n, components) arrays.
    """
    tags, blob = _appended(
        {
            "Points": np.asarray(points, np.float32),
            "connectivity": np.asarray(connectivity, np.int32),  # a frame has < 2^31 points
            "offsets": np.cumsum(sizes, dtype=np.int32),
            **point_data,
            **cell_data,
        }
    )
    counts = {key: 0 for key in ("Verts", "Lines", "Strips", "Polys")} | {kind: len(sizes)}
    numbers = " ".join(f'NumberOf{key}="{n}"' for key, n in counts.items())
    normals = ' Normals="Normals"' if "Normals" in point_data else ""
    inner = (
        f'<PolyData>\n<Piece NumberOfPoints="{len(points)}" {numbers}>\n<PointData{normals}>\n'
        + "".join(tags[name] + "\n" for name in point_data)
        + "</PointData>\n<CellData>\n"
        + "".join(tags[name] + "\n" for name in cell_data)
        + f"</CellData>\n<Points>\n{tags['Points']}\n</Points>\n"
        f"<{kind}>\n{tags['connectivity']}\n{tags['offsets']}\n</{kind}>\n</Piece>\n</PolyData>"
    )
    return _document("PolyData", inner, blob)


def _appended(arrays: dict[str, np.ndarray]) -> tuple[dict[str, str], bytes]:
    """Each array's ``DataArray`` tag, and the appended block holding them all, compressed.

    Args:
        arrays: name: (n,) or (n, components) values.
    Returns:
        the tags by name, and the block: per array VTK's zlib header (UInt64:
        the number of blocks, 1 (0 for an empty array), the block's size, the
        last block's size and the compressed size) then the values,
        little-endian, compressed; a tag's ``offset`` counts from the block's start.
    """
    tags, parts, offset = {}, [], 0
    for name, values in arrays.items():
        values = np.ascontiguousarray(values, values.dtype.newbyteorder("<"))
        raw = values.tobytes()
        packed = zlib.compress(raw, COMPRESSION) if raw else b""
        header = [1, len(raw), len(raw), len(packed)] if raw else [0, 0, 0]
        components = 1 if values.ndim == 1 else values.shape[1]
        tags[name] = (
            f'<DataArray type="{_TYPES[values.dtype.str[1:]]}" Name="{name}" '
            f'NumberOfComponents="{components}" format="appended" offset="{offset}"/>'
        )
        parts += [np.array(header, "<u8").tobytes(), packed]
        offset += 8 * len(header) + len(packed)
    return tags, b"".join(parts)


def _document(kind: str, inner: str, blob: bytes) -> bytes:
    """A VTK XML file of ``kind`` with the element ``inner`` and the appended block ``blob``."""
    head = (
        f'<?xml version="1.0"?>\n<VTKFile type="{kind}" version="1.0" byte_order="LittleEndian" '
        f'header_type="UInt64" compressor="vtkZLibDataCompressor">\n{inner}\n'
        '<AppendedData encoding="raw">\n_'
    )
    return head.encode() + blob + b"\n</AppendedData>\n</VTKFile>\n"
