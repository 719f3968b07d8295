"""The USD export read back with pxr: units, frame rate, link poses, traces, whole or no file."""

from dataclasses import replace

import numpy as np
import pytest

from aquagait.io.export import export_swim
from aquagait.sim.particles import sample, vorticity_magnitude

pytest.importorskip("pxr")
from pxr import Usd, UsdGeom  # noqa: E402

import aquagait.io.export.usd as usd  # noqa: E402

# The stage keeps points as float32: a vertex a metre from the origin is
# stored to about 6e-8 m, and a pose (float32 quaternion) rotates to ~1e-7.
FLOAT32_M = 1e-5


@pytest.fixture(params=["eel", "fish"])
def written(request, tmp_path):
    """(SwimExport, the stage read back from swim.usd, its path) for the 2D eel and the 3D fish."""
    _, data = request.getfixturevalue(f"{request.param}_export")
    path = export_swim(data, "usd", tmp_path / "swim.usd")
    return data, Usd.Stage.Open(str(path)), path


def _sample_frames(data):
    return sorted({0, data.frames // 2, data.frames - 1})


def test_the_stage_is_binary_in_metres_z_up_at_the_swims_frame_rate(written):
    data, stage, path = written
    assert path.read_bytes()[:8] == b"PXR-USDC"  # usdc, though written as .swim.usd.partial
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z
    assert stage.GetTimeCodesPerSecond() == stage.GetFramesPerSecond() == data.fps
    assert (stage.GetStartTimeCode(), stage.GetEndTimeCode()) == (0, data.frames - 1)
    assert stage.GetDefaultPrim().GetPath() == "/Swim"
    custom = stage.GetRootLayer().customLayerData
    assert custom["creature"] == data.name and custom["aquagaitVersion"]


def test_each_links_mesh_lies_where_the_swim_put_the_link(written):
    data, stage, _ = written
    names = usd._prim_names(data.link_names)
    for f in _sample_frames(data):
        for i, mesh in enumerate(data.meshes):
            if not len(mesh.triangles):
                continue
            prim = stage.GetPrimAtPath(f"/Swim/{names[i]}/Mesh")
            local = np.array(UsdGeom.Mesh(prim).GetPointsAttr().Get(f))
            matrix = np.array(UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(f))  # x M
            world = np.c_[local, np.ones(len(local))] @ matrix
            expected = data.link_pos[f, i] + mesh.vertices @ data.link_rot[f, i].T
            assert np.abs(world[:, :3] - expected).max() < FLOAT32_M
            assert len(UsdGeom.Mesh(prim).GetFaceVertexIndicesAttr().Get()) == mesh.triangles.size


def test_the_traces_are_the_known_positions_with_their_opacity_and_vorticity(written):
    data, stage, _ = written
    curves = UsdGeom.BasisCurves(stage.GetPrimAtPath("/Swim/Traces"))
    api = UsdGeom.PrimvarsAPI(curves)
    assert curves.GetTypeAttr().Get() == UsdGeom.Tokens.linear
    for f in _sample_frames(data):
        known = np.isfinite(data.traces[f, :, :, 0])
        curve = known.sum(axis=1) >= 2
        known &= curve[:, None]
        counts = np.array(curves.GetCurveVertexCountsAttr().Get(f))
        assert np.array_equal(counts, known.sum(axis=1)[curve])
        points = np.array(curves.GetPointsAttr().Get(f))
        assert np.array_equal(points, data.traces[f][known])  # float32 both: exact
        opacity = np.array(api.GetPrimvar("displayOpacity").Get(f))
        assert np.array_equal(opacity, data.trace_alpha[f][known])
        # Each trace's newest position: |omega| of this frame where the particle is now.
        omega = np.array(api.GetPrimvar("vorticity").Get(f))
        heads = np.cumsum(counts) - 1
        fluid = data.fluid
        now = data.traces[f, curve, -1, : fluid.dim]
        field = vorticity_magnitude(fluid, f).astype(np.float32)
        expected = sample(field, fluid.origin[f], fluid.cell_size, now)
        assert np.allclose(omega[heads], expected, rtol=1e-5, atol=1e-5)
        assert len(omega) == len(points) and (omega >= 0).all()
    assert api.GetPrimvar("vorticity").GetInterpolation() == UsdGeom.Tokens.vertex
    assert omega.max() > 0  # the last frame's wake has vortices


def test_a_traces_older_vorticity_is_where_the_particle_was_then(eel_export):
    # Position l of frame f was the particle's newest position at frame f - (L-1-l).
    _, data = eel_export
    omega = usd._trace_vorticity(data)
    f, length = data.frames - 1, data.traces.shape[2]
    back = 3
    was = data.traces[f, :, length - 1 - back]
    known = np.isfinite(was[:, 0])
    assert known.any()
    assert np.array_equal(was[known], data.traces[f - back, known, -1])
    assert np.array_equal(omega[f, known, length - 1 - back], omega[f - back, known, -1])


def test_a_failed_write_leaves_no_partial_file_and_the_old_file_untouched(
    eel_export, tmp_path, monkeypatch
):
    _, data = eel_export
    path = tmp_path / "swim.usd"
    path.write_bytes(b"an older export")

    def failing(data, partial):
        partial.write_bytes(b"half a stage")
        raise RuntimeError("disk full")

    monkeypatch.setattr(usd, "write", failing)
    with pytest.raises(RuntimeError, match="disk full"):
        export_swim(data, "usd", path)
    assert path.read_bytes() == b"an older export"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["swim.usd"]


def test_a_swim_without_traces_has_only_the_links(eel_export, tmp_path):
    _, data = eel_export
    bare = replace(data, traces=None, trace_alpha=None, fluid=None)
    stage = Usd.Stage.Open(str(export_swim(bare, "usd", tmp_path / "swim.usd")))
    assert not stage.GetPrimAtPath("/Swim/Traces")
    assert len(stage.GetDefaultPrim().GetChildren()) == len(data.link_names)


def test_link_names_become_distinct_valid_prim_names():
    assert usd._prim_names(["head", "tail.1", "tail 1", "Traces", ""]) == [
        "head",
        "tail_1",
        "tail_1_1",
        "Traces_1",
        "link4",
    ]
