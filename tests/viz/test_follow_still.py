"""The 3D still of a path following looks at the path the way it bends."""

import pytest

from aquagait.path import shape
from aquagait.viz.follow import still_view


@pytest.mark.parametrize(
    "path, view",
    [
        (shape("s-curve", dim=3, length=1.0, amplitude=0.1, vertical=True), "side-above"),
        (shape("s-curve", dim=3, length=1.0, amplitude=0.1), "top"),
        (shape("circle", dim=3, radius=0.6), "top"),
    ],
)
def test_a_path_that_climbs_is_seen_from_the_side_one_that_turns_from_above(path, view):
    assert still_view(path.points) == view
