"""Paths: shapes that start where a creature starts, nearest points, files, clear errors."""

import json

import numpy as np
import pytest

from aquagait.path import Path, PathError, circle, line, read_path, s_curve, shape


def test_shapes_start_at_the_origin_heading_along_x():
    for path in (line(), circle(), circle(dim=3)):
        point, tangent = path.nearest(np.zeros(path.dim))
        np.testing.assert_allclose(point, 0, atol=1e-12)
        assert tangent[0] > 0.999
    for path in (s_curve(), s_curve(dim=3, vertical=True)):  # an S crosses the x axis there
        point, tangent = path.nearest(np.zeros(path.dim))
        np.testing.assert_allclose(point, 0, atol=1e-12)
        slope = 2 * np.pi * 0.5 / 4.0  # of y = 0.5 sin(2 pi x / 4) at x = 0
        assert np.arctan2(tangent[1:].sum(), tangent[0]) == pytest.approx(np.arctan(slope), 1e-3)


def test_a_circle_is_round_and_turns_left():
    path = circle(radius=0.8)
    radius = np.linalg.norm(path.points - [0.0, 0.8], axis=1)
    np.testing.assert_allclose(radius, 0.8, atol=1e-12)
    assert path.length == pytest.approx(2 * np.pi * 0.8, rel=1e-3)  # 5 mm chords
    _, tangent = path.nearest([0.8, 0.8])  # a quarter turn on: heading +y
    np.testing.assert_allclose(tangent, [0, 1], atol=0.01)


def test_nearest_point_and_tangent_on_a_polyline():
    path = Path([[0, 0], [1, 0], [1, 1]])
    point, tangent = path.nearest([0.5, 0.3])
    np.testing.assert_allclose(point, [0.5, 0]) and np.testing.assert_allclose(tangent, [1, 0])
    point, tangent = path.nearest([1.4, 0.6])
    np.testing.assert_allclose(point, [1, 0.6]) and np.testing.assert_allclose(tangent, [0, 1])
    assert path.distance([3.0, 1.0]) == pytest.approx(2.0)


def test_a_vertical_s_curve_climbs_in_z():
    path = s_curve(length=4, amplitude=0.5, dim=3, vertical=True)
    assert np.abs(path.points[:, 1]).max() == 0
    assert path.points[:, 2].max() == pytest.approx(0.5, abs=1e-4)


def test_files_csv_with_a_header_and_json(tmp_path):
    csv = tmp_path / "p.csv"
    csv.write_text("x,y\n0,0\n1,0.5\n2,0\n")
    np.testing.assert_allclose(read_path(csv, dim=2).points, [[0, 0], [1, 0.5], [2, 0]])
    js = tmp_path / "p.json"
    js.write_text(json.dumps({"points": [[0, 0, 0], [1, 0, 1]]}))
    assert read_path(js, dim=3).dim == 3


@pytest.mark.parametrize(
    "points, message",
    [
        ([[0, 0]], "at least two points; got 1"),
        ([[0, 0], [0, 0]], "all the same point"),
        ([[0, 0], [1, np.nan]], "path point 1 is not a number"),
        ([0, 1, 2], "2D \\(x, y\\) or 3D \\(x, y, z\\) points"),
        ([[0, 0, 0, 0], [1, 1, 1, 1]], "2D \\(x, y\\) or 3D"),
    ],
)
def test_bad_paths_say_what_is_wrong(points, message):
    with pytest.raises(PathError, match=message):
        Path(points)


def test_bad_files_shapes_and_far_paths(tmp_path):
    with pytest.raises(PathError, match="does not exist"):
        read_path(tmp_path / "none.csv", dim=2)
    wrong = tmp_path / "w.csv"
    wrong.write_text("0,0,0\n1,0,0\n")
    with pytest.raises(PathError, match="holds 3D points but the creature swims in 2D"):
        read_path(wrong, dim=2)
    garbled = tmp_path / "g.csv"
    garbled.write_text("0,0\n1,a\n")
    with pytest.raises(PathError, match="not a list of points"):
        read_path(garbled, dim=2)
    with pytest.raises(PathError, match="unknown path shape 'spiral'; shapes: line:length=5.0; "
                       "circle:radius=1.0,turns=1.0; s-curve:length=4.0,"):  # fmt: skip
        shape("spiral")
    with pytest.raises(PathError, match="path shape 'circle' takes radius, turns, not radus: "
                       "circle:radius=1.0,turns=1.0"):  # fmt: skip
        shape("circle", radus=0.6)
    with pytest.raises(PathError, match="radius must be a positive number"):
        shape("circle", radius=-1)
    with pytest.raises(PathError, match="vertical S-curve is 3D"):
        s_curve(vertical=True)
    far = line().points + [0.0, 3.0]
    with pytest.raises(PathError, match=r"passes 3 m \(6.0 body lengths\).*move the path by"):
        Path(far).check_start([0.0, 0.0], body_length=0.5)


def test_progress_is_the_arc_length_to_the_nearest_point():
    corner = Path(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]))
    assert corner.progress([0.5, 0.2]) == pytest.approx(0.5)
    assert corner.progress([2.0, 0.5]) == pytest.approx(1.5)  # beside the second leg
    assert corner.progress([-1.0, 0.0]) == 0.0 and corner.progress([1.0, 3.0]) == 2.0
    ring = circle(radius=1.0)
    assert ring.progress([1.2, 1.0]) == pytest.approx(np.pi / 2, rel=1e-3)  # a quarter round


def test_the_point_and_tangent_at_an_arc_length():
    path = Path(np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0]]))
    for arc, point, tangent in [(0.5, [0.5, 0.0], [1, 0]), (2.0, [2.0, 0.0], [0, 1]),
                                (2.5, [2.0, 0.5], [0, 1]), (-1.0, [0.0, 0.0], [1, 0]),
                                (9.0, [2.0, 1.0], [0, 1])]:  # fmt: skip
        at, along = path.at(arc)
        np.testing.assert_allclose(at, point, atol=1e-12)
        np.testing.assert_allclose(along, tangent, atol=1e-12)
        if 0 <= arc <= path.length:
            assert path.progress(at) == pytest.approx(arc)
