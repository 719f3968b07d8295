"""The 3D renderer: pixels where the camera says the body and the traces are, and nowhere else."""

import math
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

moderngl = pytest.importorskip("moderngl")

import aquagait as ag  # noqa: E402
from aquagait.body.dynamics import Dynamics  # noqa: E402
from aquagait.body.geometry import geom_points  # noqa: E402
from aquagait.body.meshes import link_meshes  # noqa: E402
from aquagait.viz.camera import Camera, project, view_camera  # noqa: E402
from aquagait.viz.gl import (  # noqa: E402
    Renderer,
    RenderUnavailable,
    SurfaceMesh,
    egl_context,
    trace_segments,
)

WIDTH, HEIGHT = 160, 120
BLACK = (0.0, 0.0, 0.0)  # no lit surface is black: every geom here has a colour

BALL = """<mujoco><worldbody><body name="b"><freejoint/>
    <geom type="sphere" size=".05" rgba="1 0 0 1" density="1000"/>
  </body></worldbody></mujoco>"""


def renderer(model, width=WIDTH, height=HEIGHT, background=BLACK) -> Renderer:
    """A renderer of ``model``'s links, or a skip where this machine has no OpenGL."""
    try:
        return Renderer(link_meshes(model), width, height, background)
    except RenderUnavailable as err:
        pytest.skip(f"no headless OpenGL here: {err}")


def rest_pose(model):
    return Dynamics(model.mj).link_poses(model.qpos0)


def drawn(image) -> np.ndarray:
    """(H, W) bool: pixels that are not the black background."""
    return image.any(axis=-1)


def pixel_centres(shape) -> np.ndarray:
    rows, cols = np.indices(shape)
    return np.stack([cols + 0.5, rows + 0.5], -1)


def inside_box(mask, corners, margin) -> bool:
    """Whether every set pixel of ``mask`` lies within the box of projected ``corners``."""
    centres = pixel_centres(mask.shape)[mask]
    low, high = corners.min(0) - margin, corners.max(0) + margin
    return bool(((centres >= low) & (centres <= high)).all())


def distance_to_segment(points, a, b) -> np.ndarray:
    t = np.clip(((points - a) @ (b - a)) / ((b - a) @ (b - a)), 0, 1)
    return np.linalg.norm(points - (a + t[..., None] * (b - a)), axis=-1)


@pytest.fixture(scope="module")
def ball():
    return ag.load_model(BALL)


@pytest.fixture(scope="module")
def fish():
    return ag.creatures.get("fish").model


# --- the body --------------------------------------------------------------------


def test_a_sphere_covers_its_projected_disc(ball):
    camera = view_camera("side", [0, 0, 0], [0.1] * 3, WIDTH / HEIGHT)
    with renderer(ball) as r:
        mask = drawn(r.draw(*rest_pose(ball), camera))
    corners = project(camera, geom_points(ball, world=True)[1], WIDTH, HEIGHT)
    assert inside_box(mask, corners, margin=1.0)
    # the silhouette of a sphere seen from distance d subtends asin(r / d): its disc, in pixels
    d = np.linalg.norm(camera.eye)
    radius = HEIGHT / 2 * math.tan(math.asin(0.05 / d)) / math.tan(math.radians(camera.fov) / 2)
    assert mask.sum() == pytest.approx(math.pi * radius**2, rel=0.04)
    assert np.allclose(pixel_centres(mask.shape)[mask].mean(0), [WIDTH / 2, HEIGHT / 2], atol=0.5)


@pytest.mark.parametrize("view", ["side", "top", "follow"])
def test_the_fish_appears_where_project_says(fish, view):
    camera = view_camera(view, fish.bounds.mean(0), fish.extent, WIDTH / HEIGHT)
    with renderer(fish) as r:
        mask = drawn(r.draw(*rest_pose(fish), camera))
    points = project(camera, geom_points(fish, world=True)[1], WIDTH, HEIGHT)
    assert inside_box(mask, points, margin=1.0)
    # every vertex of the fish's meshes lies on a drawn pixel or next to one
    near = np.zeros_like(mask)
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            near |= np.roll(mask, (dr, dc), axis=(0, 1))
    cols, rows = np.clip(points.astype(int), 0, [WIDTH - 1, HEIGHT - 1]).T
    assert near[rows, cols].all()


def test_moving_the_body_moves_its_pixels_by_the_projected_amount(ball):
    camera = view_camera("side", [0, 0, 0], [0.3, 0.3, 0.3], WIDTH / HEIGHT)
    pos, rot = rest_pose(ball)
    shift = np.array([0.06, 0.0, -0.03])
    with renderer(ball) as r:
        before = drawn(r.draw(pos, rot, camera))
        after = drawn(r.draw(pos + shift, rot, camera))
    centres = pixel_centres(before.shape)
    moved = centres[after].mean(0) - centres[before].mean(0)
    expected = np.diff(project(camera, [pos[0], pos[0] + shift], WIDTH, HEIGHT), axis=0)[0]
    assert np.linalg.norm(expected) > 15  # many pixels: a real move
    assert moved == pytest.approx(expected, abs=1.0)


# --- traces ----------------------------------------------------------------------


def _trace_scene(ball):
    """The ball from the side, and a straight trace (4 points, the third unknown) above it."""
    camera = view_camera("side", [0, 0, 0], [0.3, 0.3, 0.3], WIDTH / HEIGHT)
    trace = np.array([[[-0.12, 0, 0.09], [-0.04, 0, 0.09], [np.nan] * 3, [0.12, 0, 0.09]]])
    return camera, trace


def test_a_trace_appears_along_its_known_segments_and_nowhere_else(ball):
    camera, trace = _trace_scene(ball)
    with renderer(ball) as r:
        plain = r.draw(*rest_pose(ball), camera)
        lined = r.draw(*rest_pose(ball), camera, trace)
    changed = (lined != plain).any(-1)
    a, b, _, c = project(camera, trace[0], WIDTH, HEIGHT)
    distance = distance_to_segment(pixel_centres(changed.shape), a, b)
    assert (distance[changed] <= 1.0).all()  # on the first segment only: the rest has a NaN end
    assert changed.sum() >= 0.9 * np.linalg.norm(b - a)  # along all of it
    assert np.allclose(b[1], c[1])  # the missing stretch lies on the same row, to the right


def test_trace_opacity_darkens_monotonically_and_zero_draws_nothing(ball):
    camera, trace = _trace_scene(ball)
    pose = rest_pose(ball)
    darkness = []
    with renderer(ball, background=(1.0, 1.0, 1.0)) as r:
        plain = r.draw(*pose, camera)
        for alpha in (0.0, 0.25, 0.5, 1.0):
            image = r.draw(*pose, camera, trace, np.full(trace.shape[:2], alpha))
            darkness.append(int(plain.astype(int).sum() - image.astype(int).sum()))
    assert darkness[0] == 0
    assert darkness[1] < darkness[2] < darkness[3]


def test_a_trace_behind_the_body_is_hidden_and_one_in_front_is_not(ball):
    camera = view_camera("side", [0, 0, 0], [0.3, 0.3, 0.3], WIDTH / HEIGHT)
    across = np.array([[-0.1, 0.0, 0.0], [0.1, 0.0, 0.0]])
    with renderer(ball) as r:
        plain = r.draw(*rest_pose(ball), camera)
        disc = drawn(plain)
        for depth, hidden in ((0.08, True), (-0.08, False)):  # +y is away from the side camera
            image = r.draw(*rest_pose(ball), camera, (across + [0, depth, 0])[None])
            changed = (image != plain).any(-1)
            assert changed[~disc].any()  # drawn where it passes beside the ball
            assert changed[disc].any() != hidden


def squares(*ys, size=0.1, rgba=(0.0, 0.0, 1.0, 0.5)) -> SurfaceMesh:
    """One surface of squares in the planes at ``ys``, facing the 'side' camera."""
    corners = np.array([[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]]) * [size, 0, size]
    vertices = np.concatenate([corners + [0, y, 0] for y in ys])
    triangles = np.concatenate([np.array([[0, 1, 2], [0, 2, 3]]) + 4 * k for k in range(len(ys))])
    normals = np.tile([0.0, -1.0, 0.0], (len(vertices), 1))
    return SurfaceMesh(vertices, normals, np.tile(rgba, (len(vertices), 1)), triangles)


def test_see_through_surfaces_blend_their_nearest_layer_and_the_body_shows_through(ball):
    camera = view_camera("side", [0, 0, 0], [0.3, 0.3, 0.3], WIDTH / HEIGHT)
    with renderer(ball, background=(1.0, 1.0, 1.0)) as r:
        plain = r.draw(*rest_pose(ball), camera).astype(int)
        one = r.draw(*rest_pose(ball), camera, surfaces=(squares(-0.15),)).astype(int)
        two = [r.draw(*rest_pose(ball), camera, surfaces=(squares(*ys),)).astype(int)
               for ys in ((-0.15, -0.1), (-0.1, -0.15))]  # fmt: skip
        behind = r.draw(*rest_pose(ball), camera, surfaces=(squares(0.1),)).astype(int)
    corner = (slice(5, 15), slice(5, 15))  # outside the squares: background
    centre = (HEIGHT // 2, WIDTH // 2)  # the ball, through the square
    edge = (HEIGHT // 2, WIDTH // 2 + 25)  # beside the ball, inside the square
    assert np.array_equal(one[corner], plain[corner])
    assert one[edge][2] > one[edge][0] + 50  # white turned blue-ish
    for image in two:  # a second layer behind the first adds nothing, in either order
        assert np.abs(image - one).max() <= 1
    assert 0 < np.abs(one[centre] - plain[centre]).max() and one[centre][0] > 60  # red through
    assert np.array_equal(behind[centre], plain[centre])  # hidden by the ball


def test_trace_segments_skip_every_segment_with_a_missing_end():
    traces = np.zeros((2, 4, 3))
    traces[0, :2] = np.nan  # younger than the window: two positions known
    segments = trace_segments(traces, np.full((2, 4), 0.5), colour=(0.1, 0.2, 0.3))
    assert segments.shape == (2 * (1 + 3), 7)
    assert (segments[:, 6] == 0.5).all()
    assert np.allclose(segments[:, 3:6], [0.1, 0.2, 0.3])


# --- contexts ----------------------------------------------------------------------


def test_renderers_take_turns_in_one_thread(ball, fish):
    camera = view_camera("side", [0, 0, 0], [0.15] * 3, WIDTH / HEIGHT)
    fish_camera = view_camera("top", fish.bounds.mean(0), fish.extent, 4 / 3)
    with renderer(ball) as first, renderer(fish, 80, 60, background=(1, 1, 1)) as second:
        alone = first.draw(*rest_pose(ball), camera)
        other = second.draw(*rest_pose(fish), fish_camera)
        assert np.array_equal(first.draw(*rest_pose(ball), camera), alone)
        assert np.array_equal(second.draw(*rest_pose(fish), fish_camera), other)
        assert other.shape == (60, 80, 3)


def test_renderers_in_threads_draw_what_one_alone_draws(fish):
    """Each thread with its own renderer (a Dask worker drawing two runs at once)."""
    camera = view_camera("follow", fish.bounds.mean(0), fish.extent, WIDTH / HEIGHT)

    def pictures(_):
        with renderer(fish) as r:
            return [r.draw(*rest_pose(fish), camera) for _ in range(3)]

    alone = pictures(None)[0]
    with ThreadPoolExecutor(2) as pool:
        drawn_in_threads = [image for images in pool.map(pictures, range(2)) for image in images]
    assert all(np.array_equal(image, alone) for image in drawn_in_threads)


def test_a_closed_renderer_says_so(ball):
    r = renderer(ball)
    r.close()
    with pytest.raises(RuntimeError, match="closed"):
        r.draw(*rest_pose(ball), Camera([0, -1, 0], [0, 0, 0], [0, 0, 1]))


def test_no_egl_names_the_debian_packages(monkeypatch):
    def no_display(**kwargs):
        raise Exception("eglGetDisplay failed")

    monkeypatch.setattr(moderngl, "create_standalone_context", no_display)
    with pytest.raises(RenderUnavailable) as raised:
        egl_context()
    message = str(raised.value)
    assert "libegl1" in message and "libgl1-mesa-dri" in message
    assert "eglGetDisplay failed" in message


def test_no_moderngl_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "moderngl", None)  # import moderngl raises ImportError
    with pytest.raises(RenderUnavailable, match=r'pip install "aquagait\[render\]"'):
        egl_context()
