"""The export dispatcher: whole files or none, unknown formats named, the data gathered once."""

import numpy as np
import pytest

from aquagait.io.export import FORMATS, export_swim


def test_the_gathered_swim_has_poses_meshes_and_traces_for_every_frame(eel_export, fish_export):
    for _, data in (eel_export, fish_export):
        frames, links = data.frames, len(data.link_names)
        assert data.link_pos.shape == (frames, links, 3) and data.link_rot.shape[1] == links
        assert np.allclose(np.linalg.norm(data.link_quat, axis=-1), 1)
        assert (np.einsum("fli,fli->fl", data.link_quat[1:], data.link_quat[:-1]) > 0).all()
        assert len(data.meshes) == links and data.time[0] == 0
        assert data.traces.shape == (frames, 200, 15, 3) and data.trace_alpha.shape[:2] == (
            frames,
            200,
        )
    eel = eel_export[1]
    assert np.all(eel.traces[..., 2][np.isfinite(eel.traces[..., 2])] == 0)  # 2D: the plane z = 0


def test_an_unknown_format_is_named_and_a_failed_writer_leaves_nothing(eel_export, tmp_path):
    _, data = eel_export
    with pytest.raises(ValueError, match="unknown format 'obj'; formats: usd, gltf, vtk, html"):
        export_swim(data, "obj", tmp_path / "swim.obj")
    assert set(FORMATS) == {"usd", "gltf", "vtk", "html"}
