"""The follower's rule on synthetic poses: towards the path, away from it, in the dead band."""

import numpy as np
import pytest

from aquagait.path import choose_maneuver, root_frame
from aquagait.path.rule import GAIN, graded_shares

EPS = 0.05


@pytest.mark.parametrize(
    "offset, tangent, expected",
    [
        ((1.0, 0.0), (1.0, 0.0), "straight"),  # on the path, along it
        ((0.5, 0.3), (1.0, 0.0), "turn-left"),  # the path runs parallel on the left
        ((0.5, -0.3), (1.0, 0.0), "turn-right"),
        ((0.5, 0.3), (0.6, -0.8), "straight"),  # on the left but coming back: closing in
        ((0.5, -0.3), (0.6, 0.8), "straight"),
        ((0.5, 0.3), (0.6, 0.8), "turn-left"),  # on the left and going further left
        ((0.5, 0.04), (1.0, 0.0), "straight"),  # within the dead band
        ((0.5, -0.04), (0.98, 0.2), "straight"),  # on the path, 12 degrees off its direction
        ((0.5, -0.04), (0.6, 0.8), "turn-left"),  # on it, 53 degrees off: align
        ((0.0, 0.0), (0.6, -0.8), "turn-right"),
        ((-0.5, 0.3), (1.0, 0.0), "turn-left"),  # behind and to the left: still turn left
    ],
)
def test_turns_in_2d(offset, tangent, expected):
    assert choose_maneuver(offset, tangent, EPS) == expected


@pytest.mark.parametrize(
    "offset, tangent, expected",
    [
        ((0.5, 0.0, 0.3), (1.0, 0.0, 0.0), "pitch-up"),  # above
        ((0.5, 0.0, -0.3), (1.0, 0.0, 0.0), "pitch-down"),  # below
        ((0.5, 0.0, 0.3), (0.8, 0.0, -0.6), "straight"),  # above, coming down to meet it
        ((0.5, 0.0, -0.3), (0.8, 0.0, 0.6), "straight"),
        ((0.5, 0.0, 0.02), (1.0, 0.0, 0.0), "straight"),  # dead band
        ((0.5, 0.1, 0.3), (1.0, 0.0, 0.0), "pitch-up"),  # both ask: the larger offset wins
        ((0.5, -0.4, 0.3), (1.0, 0.0, 0.0), "turn-right"),
    ],
)
def test_pitches_and_turns_in_3d(offset, tangent, expected):
    assert choose_maneuver(offset, tangent, EPS) == expected


def test_the_dead_band_stops_dithering_about_the_path():
    """Swaying either side of the path within the band: straight every time."""
    sway = 0.9 * EPS * np.sin(np.linspace(0, 6 * np.pi, 50))
    assert {choose_maneuver((0.3, s), (1.0, 0.0), EPS) for s in sway} == {"straight"}


def test_world_vectors_turn_into_the_root_frame():
    yaw = np.radians(90)  # the creature faces +y
    rot = np.array([[np.cos(yaw), -np.sin(yaw), 0], [np.sin(yaw), np.cos(yaw), 0], [0, 0, 1]])
    np.testing.assert_allclose(root_frame([0.0, 1.0], rot), [1.0, 0.0], atol=1e-12)  # ahead
    np.testing.assert_allclose(root_frame([-1.0, 0.0], rot), [0.0, 1.0], atol=1e-12)  # left
    np.testing.assert_allclose(root_frame([0.0, 0.0, 2.0], rot), [0.0, 0.0, 2.0], atol=1e-12)


def test_graded_steering_asks_for_a_share_by_the_bearing_and_the_turns_rate():
    rates = {"turn-left": 0.8, "turn-right": 0.5, "pitch-up": 0.2}
    bearing = np.radians(10)
    left = graded_shares((np.cos(bearing), np.sin(bearing)), rates)
    assert left == pytest.approx({"turn-left": GAIN * bearing / 0.8})
    right = graded_shares((np.cos(bearing), -np.sin(bearing)), rates)
    assert right == pytest.approx({"turn-right": GAIN * bearing / 0.5})
    assert graded_shares((1.0, 0.0), rates) == {}  # dead ahead: straight
    assert graded_shares((-1.0, 0.1), rates) == {"turn-left": 1.0}  # behind: all of it
    both = graded_shares((1.0, 1.0, 1.0), rates)  # in 3D both ask; their shares add to 1
    assert both == pytest.approx({"turn-left": 0.5, "pitch-up": 0.5})
    # an axis without a learned manoeuvre is left alone (the manta pitches only)
    assert graded_shares((1.0, 0.01, -0.1), {"pitch-down": 0.2}) == pytest.approx(
        {"pitch-down": min(GAIN * np.arctan(0.1) / 0.2, 1.0)})  # fmt: skip
