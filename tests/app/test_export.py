"""The export job: settings and the run checked first; nothing half-written left behind."""

import shutil

import pytest

from aquagait.app import prepare_swim, run_swim
from aquagait.app.export import ExportSetupError, prepare_export, run_export
from aquagait.app.swim import write_swim
from aquagait.cli import main


@pytest.fixture(scope="module")
def eel_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("eel2d")
    write_swim(run_swim(prepare_swim("eel2d", seconds=0.2, resolution=(48, 24), cell_size=0.025)),
               out)  # fmt: skip
    return out


def copy_of(run, tmp_path):
    return shutil.copytree(run, tmp_path / "run")


def test_export_writes_each_format_into_the_run_directory(eel_run, tmp_path, capsys):
    run = copy_of(eel_run, tmp_path)
    for fmt, name in (("gltf", "swim.glb"), ("vtk", "swim-vtk"), ("html", "swim.html")):
        assert main(["export", str(run), "--format", fmt, "--traces", "50"]) == 0
        assert (run / name).exists() and f"wrote {run / name}" in capsys.readouterr().out
    assert not [p for p in run.iterdir() if p.name.endswith(".partial")]


def test_a_missing_or_cut_trajectory_is_named(eel_run, tmp_path):
    run = copy_of(eel_run, tmp_path)
    data = (run / "trajectory.npz").read_bytes()
    (run / "trajectory.npz").write_bytes(data[: len(data) // 2])
    with pytest.raises(ExportSetupError, match="may be damaged or cut short: swim it again"):
        prepare_export(run, "gltf")
    (run / "trajectory.npz").unlink()
    with pytest.raises(ExportSetupError, match="no trajectory at"):
        prepare_export(run, "gltf")
    with pytest.raises(ExportSetupError, match="is not a run directory: it has no config.json"):
        prepare_export(tmp_path, "gltf")


def test_bad_formats_and_paths_are_refused_before_any_work(eel_run, tmp_path, capsys):
    with pytest.raises(ExportSetupError, match="unknown format 'obj'; formats: usd, gltf, vtk"):
        prepare_export(eel_run, "obj")
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(ExportSetupError, match="cannot write the run directory .*file"):
        prepare_export(eel_run, "html", out=blocker / "swim.html")
    (tmp_path / "folder.glb").mkdir()
    with pytest.raises(ExportSetupError, match="exists and is not a file: gltf writes a file"):
        prepare_export(eel_run, "gltf", out=tmp_path / "folder.glb")
    assert main(["export", str(eel_run), "--format", "vtk", "--traces", "-1"]) == 2
    assert "traces must be a whole number >= 0" in capsys.readouterr().err


def test_a_writer_that_fails_leaves_the_old_file_as_it_was(eel_run, tmp_path, monkeypatch):
    import aquagait.io.export.gltf as gltf

    out = tmp_path / "swim.glb"
    out.write_bytes(b"old")
    setup = prepare_export(eel_run, "gltf", out=out, traces=0)

    def broken(data, path):
        path.write_bytes(b"half")
        raise OSError("disk full")

    monkeypatch.setattr(gltf, "write", broken)
    with pytest.raises(OSError, match="disk full"):
        run_export(setup)
    assert out.read_bytes() == b"old" and [p.name for p in tmp_path.iterdir()] == ["swim.glb"]


def test_the_formats_extension_is_added_when_missing_and_said(eel_run, tmp_path, capsys):
    """USD tools and Blender open a file by its extension: ``--out swim`` writes swim.usd
    (here the glTF and HTML, which need no extra library), and says so."""
    for fmt, suffix in (("gltf", ".glb"), ("html", ".html")):
        out = tmp_path / f"swim-{fmt}"
        assert main(["export", str(eel_run), "--format", fmt, "--out", str(out),
                     "--traces", "0"]) == 0  # fmt: skip
        written = out.with_name(out.name + suffix)
        assert written.is_file() and not out.exists()
        assert f"wrote {written} (added the {suffix} extension" in capsys.readouterr().out
    setup = prepare_export(eel_run, "usd", out=tmp_path / "my.swim") if _has_usd() else None
    if setup is not None:
        assert setup.path.name == "my.swim.usd"
    with pytest.raises(ExportSetupError, match=r"a gltf export is a \.glb file, not \.html"):
        prepare_export(eel_run, "gltf", out=tmp_path / "swim.html")
    assert prepare_export(eel_run, "vtk", out=tmp_path / "fluid").path.name == "fluid"


def _has_usd() -> bool:
    from aquagait.io.export import ExportUnavailable, check_format

    try:
        check_format("usd")
    except ExportUnavailable:
        return False
    return True
