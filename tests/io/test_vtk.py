"""The VTK export, read back by VTK's own XML readers: what ParaView would see.

Comparison with a reference: the fluid arrays equal the recorded frames, the
body's points equal the link meshes placed by the recorded poses, the
collections play the frames at the recorded times; in 2D and in 3D.
"""

import xml.etree.ElementTree as ET

import numpy as np
import pytest

from aquagait.io.export import export_swim
from aquagait.sim.particles import vorticity

vtk = pytest.importorskip("vtk")
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402

FLOAT32 = 2e-7
"""Float32's relative rounding (2^-23 ~ 1.2e-7, rounded up): what the files store."""


@pytest.fixture(scope="module", params=["eel", "fish"])
def exported(request, tmp_path_factory):
    """(SwimExport, folder written by the vtk export) for the 2D eel and the 3D fish."""
    _, data = request.getfixturevalue(f"{request.param}_export")
    return data, export_swim(data, "vtk", tmp_path_factory.mktemp("vtk") / "swim-vtk")


def _read(reader_class, path):
    reader = reader_class()
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput()


def _samples(data):
    return sorted({0, data.frames // 2, data.frames - 1})


def _vtk_field(image, name, shape):
    """A point array of ``image`` (x fastest) as (components, *shape), the recorded layout."""
    values = vtk_to_numpy(image.GetPointData().GetArray(name))
    components = values.reshape(*reversed(shape), -1)  # x fastest: (nz, ny, nx, c)
    return components.T.reshape(-1, *shape)  # (c, nx, ny, nz)


def test_each_fluid_frame_is_the_recorded_lattice_at_its_cell_centres(exported):
    data, folder = exported
    fluid = data.fluid
    dim, h = fluid.dim, fluid.cell_size
    points = (*fluid.shape, 1)[:3]
    for f in _samples(data):
        image = _read(vtk.vtkXMLImageDataReader, folder / f"fluid/frame_{f:05d}.vti")
        assert image.GetDimensions() == points
        assert np.allclose(image.GetSpacing(), h, rtol=1e-12)
        centre = np.append(fluid.origin[f] + h / 2, [0.0] * (3 - dim))
        assert np.allclose(image.GetOrigin(), centre, rtol=0, atol=1e-12)
        cell = np.array([fluid.shape[0] - 1, 1, 2][:dim])  # VTK's own indexing finds it
        point = image.ComputePointId([*cell, 0][:3])
        assert np.allclose(image.GetPoint(point)[:dim], fluid.origin[f] + (cell + 0.5) * h)
        assert np.array_equal(
            vtk_to_numpy(image.GetPointData().GetArray("velocity"))[point, :dim],
            fluid.velocity[f][(slice(None), *cell)].astype(np.float32),
        )
        velocity = _vtk_field(image, "velocity", fluid.shape)
        assert velocity.shape == (3, *fluid.shape)
        # Float32 holds the float32 (2D) and float16 (3D) recordings exactly.
        assert np.array_equal(velocity[:dim], fluid.velocity[f].astype(np.float32))
        assert not velocity[dim:].any()  # 2D: z = 0
        omega = _vtk_field(image, "vorticity", fluid.shape)
        expected = vorticity(fluid, f).reshape(-1, *fluid.shape)  # 2D: one component
        assert np.allclose(omega, expected, rtol=FLOAT32, atol=FLOAT32 * np.abs(expected).max())
        solid = _vtk_field(image, "solid", fluid.shape)[0]
        assert np.array_equal(solid, fluid.solid[f]) and fluid.solid[f].any()


def test_each_body_frame_is_every_link_mesh_at_its_recorded_pose(exported):
    data, folder = exported
    for f in _samples(data):
        body = _read(vtk.vtkXMLPolyDataReader, folder / f"body/frame_{f:05d}.vtp")
        world = [p + m.vertices @ r.T for p, r, m in zip(data.link_pos[f], data.link_rot[f],
                                                           data.meshes, strict=True)]  # fmt: skip
        world = np.concatenate(world)
        points = vtk_to_numpy(body.GetPoints().GetData())
        # float32 points: within 1e-6 of the swim's extent of the float64 positions
        assert np.allclose(points, world, rtol=0, atol=1e-6 * np.abs(world).max())
        triangles = sum(len(m.triangles) for m in data.meshes)
        assert body.GetNumberOfCells() == triangles
        links = vtk_to_numpy(body.GetCellData().GetArray("link"))
        expected = np.repeat(np.arange(len(data.meshes)), [len(m.triangles) for m in data.meshes])
        assert np.array_equal(links, expected)
        normals = vtk_to_numpy(body.GetPointData().GetNormals())
        assert np.allclose(np.linalg.norm(normals, axis=1), 1, atol=1e-5)
        polys = vtk_to_numpy(body.GetPolys().GetConnectivityArray()).reshape(-1, 3)
        starts = np.cumsum([0] + [len(m.vertices) for m in data.meshes[:-1]])
        placed = [m.triangles + s for m, s in zip(data.meshes, starts, strict=True)]
        assert np.array_equal(polys, np.concatenate(placed))


def test_the_collections_play_every_frame_at_its_time(exported):
    data, folder = exported
    for name in ("fluid", "body", "traces"):
        root = ET.parse(folder / f"{name}.pvd").getroot()
        assert root.get("type") == "Collection"
        rows = root.find("Collection").findall("DataSet")
        assert [float(row.get("timestep")) for row in rows] == list(data.time)
        assert all((folder / row.get("file")).is_file() for row in rows)


def test_the_traces_are_polylines_of_their_finite_positions_with_opacity(exported):
    data, folder = exported
    f = data.frames - 1
    lines = _read(vtk.vtkXMLPolyDataReader, folder / f"traces/frame_{f:05d}.vtp")
    finite = np.isfinite(data.traces[f]).all(axis=-1)
    kept = finite.sum(axis=1) >= 2
    assert lines.GetNumberOfLines() == kept.sum() > 0
    points = vtk_to_numpy(lines.GetPoints().GetData())
    assert np.allclose(points, data.traces[f][finite & kept[:, None]], rtol=FLOAT32, atol=1e-9)
    opacity = vtk_to_numpy(lines.GetPointData().GetArray("opacity"))
    assert np.array_equal(opacity, data.trace_alpha[f][finite & kept[:, None]])
