"""The camera: views that frame a box, and where world points land in the picture."""

import numpy as np
import pytest

from aquagait.viz.camera import project, view_camera

WIDTH, HEIGHT = 160, 120


@pytest.mark.parametrize("view", ["side", "top", "follow"])
def test_view_camera_frames_the_box_to_the_share_asked(view):
    centre, extent = np.array([0.3, -0.2, 0.1]), np.array([0.1, 0.02, 0.045])
    camera = view_camera(view, centre, extent, WIDTH / HEIGHT, fill=0.8)
    corners = centre + extent / 2 * np.array([[x, y, z] for x in (-1, 1)
                                               for y in (-1, 1) for z in (-1, 1)])  # fmt: skip
    reach = np.abs(project(camera, corners, WIDTH, HEIGHT) / [WIDTH / 2, HEIGHT / 2] - 1)
    assert reach.max() == pytest.approx(0.8, abs=1e-9)
    assert project(camera, [centre], WIDTH, HEIGHT)[0] == pytest.approx([WIDTH / 2, HEIGHT / 2])


def test_side_view_shows_x_to_the_right_and_z_up_top_view_y_up():
    side = view_camera("side", [0, 0, 0], [1, 1, 1], 1.0)
    top = view_camera("top", [0, 0, 0], [1, 1, 1], 1.0)
    x, y, z = np.eye(3) * 0.1
    assert np.sign(project(side, [x, z], 100, 100) - 50).tolist() == [[1, 0], [0, -1]]
    assert np.sign(project(top, [x, y], 100, 100) - 50).tolist() == [[1, 0], [0, -1]]
