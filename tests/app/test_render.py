"""The render job: a run directory drawn again, the same pictures as the swim drew."""

import imageio.v2 as imageio
import numpy as np
import pytest

from aquagait.app import RenderSetupError, prepare_render, prepare_swim, run_render, run_swim
from aquagait.app.swim import write_swim


@pytest.fixture(scope="module")
def eel_run(tmp_path_factory):
    """A short eel2d swim in the Euler fluid, with its video."""
    out = tmp_path_factory.mktemp("eel2d")
    setup = prepare_swim("eel2d", seconds=0.3, resolution=(48, 24), cell_size=0.025)
    write_swim(run_swim(setup), out, video=True)
    return out


def frames_of(path):
    with imageio.get_reader(path) as video:
        return [frame.astype(int) for frame in video]


def test_render_draws_what_the_swim_drew(eel_run, tmp_path):
    path = run_render(prepare_render(eel_run, out=tmp_path / "again.mp4"))
    swum, again = frames_of(eel_run / "swim.mp4"), frames_of(path)
    assert len(again) == len(swum) == 10
    for a, b in zip(swum, again, strict=True):
        assert np.abs(a - b).max() <= 2  # the same pictures, through the same encoder


def test_a_frame_range_draws_those_frames_as_the_whole_swim_drew_them(eel_run, tmp_path):
    whole = run_render(prepare_render(eel_run, "png", frames="7:8", out=tmp_path / "7.png"))
    video = frames_of(eel_run / "swim.mp4")
    picture = imageio.imread(whole).astype(int)[..., :3]
    assert picture.shape == video[7].shape
    assert np.abs(picture - video[7]).mean() < 2  # video frames went through H.264
    sheet = imageio.imread(run_render(prepare_render(eel_run, "png", out=tmp_path / "s.png")))
    assert sheet.shape[:2] == (2 * picture.shape[0], 3 * picture.shape[1])  # six frames, 3x2
    gif = run_render(prepare_render(eel_run, "gif", frames="0:6"))
    assert gif == eel_run / "swim.gif"
    with imageio.get_reader(gif) as frames:
        assert len(list(frames)) == 3  # 30 fps swims go into GIFs at 15 fps


@pytest.mark.parametrize(
    "kwargs,message",
    [
        ({"frames": "8:3"}, "select nothing of this run's 10 frames"),
        ({"frames": "a:b"}, "give A:B"),
        ({"frames": "12:"}, "select nothing"),
        ({"view": "top"}, "a 2D swim has one picture: --view, --wake and --size are for 3D"),
        ({"wake": "q"}, "a 2D swim has one picture"),
        ({"size": (640, 480)}, "a 2D swim has one picture"),
        ({"format": "avi"}, "unknown format 'avi'; formats: mp4, gif, png"),
    ],
)
def test_bad_render_settings_say_what_would_be_right(eel_run, kwargs, message):
    with pytest.raises(RenderSetupError, match=message):
        prepare_render(eel_run, **kwargs)


def test_a_directory_that_is_not_a_run_is_named(tmp_path):
    with pytest.raises(RenderSetupError, match="is not a run directory: it has no config.json"):
        prepare_render(tmp_path)


def test_an_output_that_cannot_be_written_is_refused_before_drawing(eel_run, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(RenderSetupError, match="cannot write the run directory .*file"):
        prepare_render(eel_run, out=blocker / "swim.mp4")


# --- 3D ------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def fish_run(tmp_path_factory):
    """A short fish swim in the Euler fluid, without its video."""
    pytest.importorskip("moderngl")
    out = tmp_path_factory.mktemp("fish")
    setup = prepare_swim("fish", seconds=0.2, resolution=(32, 24, 24), cell_size=0.008)
    write_swim(run_swim(setup), out)
    return out


def test_a_3d_run_renders_from_each_view_and_again_the_same(fish_run, tmp_path):
    from aquagait.app import RenderUnavailable

    small = {"size": (320, 240)}
    try:
        side = run_render(prepare_render(fish_run, "png", view="side", frames="3:4", **small))
    except RenderUnavailable as err:
        pytest.skip(f"no headless OpenGL here: {err}")
    assert side == fish_run / "swim-side.png"
    top = imageio.imread(run_render(prepare_render(fish_run, "png", view="top", frames="3:4")))
    assert top.shape == (720, 1280, 3) and (top < 200).any()  # the shaded fish, by default
    own = prepare_render(fish_run, "png", frames="3:4", wake="traces", **small)
    assert own.look == {"view": "side-above", "wake": "traces", "width": 320, "height": 240}
    assert own.path == fish_run / "swim.png"  # the creature's own view has no suffix
    assert not np.array_equal(imageio.imread(side), imageio.imread(run_render(own)))
    first = run_render(prepare_render(fish_run, out=tmp_path / "a.mp4", **small))
    again = run_render(prepare_render(fish_run, out=tmp_path / "b.mp4", **small))
    assert first.read_bytes() == again.read_bytes()  # the same arrays, the same pictures


@pytest.mark.parametrize(
    "kwargs,message",
    [
        ({"view": "under"}, "unknown view 'under'; views: side, top, follow, side-above, front"),
        ({"wake": "dye"}, "unknown wake 'dye'; wakes: both, q, traces"),
        ({"size": (641, 480)}, r"size \[641, 480\]: give an even width and height of 16"),
        ({"size": (8, 8)}, "of 16 pixels or more"),
    ],
)
def test_bad_3d_looks_say_what_would_be_right(fish_run, kwargs, message):
    with pytest.raises(RenderSetupError, match=message):
        prepare_render(fish_run, **kwargs)


def test_a_3d_swim_without_opengl_keeps_its_run_and_says_what_to_install(
    tmp_path, capsys, monkeypatch
):
    import sys

    from aquagait.cli import main

    monkeypatch.setitem(sys.modules, "moderngl", None)  # import moderngl fails
    out = tmp_path / "fish"
    argv = ["swim", "fish", "--seconds", "0.1", "--resolution", "32", "24", "24",
            "--cell-size", "0.008", "--out", str(out)]  # fmt: skip
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert "the video is skipped, the run is kept" in err and "aquagait[render]" in err
    assert (out / "trajectory.npz").is_file() and not (out / "swim.mp4").exists()
    assert main(["render", str(out)]) == 1
    assert "aquagait render: error: the 3D renderer needs moderngl" in capsys.readouterr().err
