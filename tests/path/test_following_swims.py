"""Following paths in water with the shipped manoeuvres (paper §5; slow: ``-m slow``).

Run with ``python3 -m pytest -m slow tests/path/test_following_swims.py -n 0 -s`` to
see the figures of the issue: the eel on a circle and an S-curve, the 2D
turtle open-loop and following a straight line, the manta on a vertical S;
with graded steering (the default) and, for the eel's circle, the paper's rule.
Distances are to the path until the creature reaches its end.
"""

import pytest

from aquagait.app.follow import FollowSetupError, prepare_follow, run_follow

pytestmark = pytest.mark.slow


def _follow(name, path, cycles, **options):
    run = run_follow(prepare_follow(name, path, cycles=cycles, **options))
    m = run.metrics
    counts = {}
    for d in run.decisions:
        counts[d.maneuver] = counts.get(d.maneuver, 0) + 1
    print(f"{name} {'open loop' if options.get('open_loop') else 'following'} {path} "
          f"({options.get('steer', 'graded')}), "
          f"{cycles} cycles: distance to the path mean {m['path_distance_mean_body_lengths']:.3f}"
          f", max {m['path_distance_max_body_lengths']:.3f}, final "
          f"{m['path_distance_final_body_lengths']:.3f} body lengths; {counts}; "
          f"{m['path_progress']:.2f} m along it")  # fmt: skip
    return m


@pytest.mark.parametrize(
    "path, steer, within",
    [
        ("circle:radius=0.6", "graded", 0.2),
        ("circle:radius=0.6", "paper", 0.2),
        ("s-curve:length=3,amplitude=0.4", "graded", 0.3),
    ],
)
def test_the_eel_follows_a_circle_and_an_s_curve(path, steer, within):
    """Within a fifth of a body length of the circle on average (the library issue's
    target: the paper's Figure 10 keeps the eel on it; with the turns of 2026-12-06
    measured 0.12 graded, 0.19 by the paper's rule), 0.3 of the S-curve, which it meets 50
    degrees off its tangent at the first bend (measured 0.29; the turns of 2026-12-04
    0.24: docs/follow.md)."""
    m = _follow("eel2d", path, 12, steer=steer)
    assert m["path_distance_mean_body_lengths"] < within
    assert m["path_progress_body_lengths"] > 4  # it went along, not round in place


def test_the_turtle_drifts_open_loop_and_holds_a_line_when_following():
    drift = _follow("turtle2d", "line:length=10", 10, open_loop=True)
    held = _follow("turtle2d", "line:length=10", 10)
    assert drift["path_distance_final_body_lengths"] > 1  # paper: it cannot swim straight
    assert held["path_distance_mean_body_lengths"] < 0.5
    assert held["path_distance_max_body_lengths"] < 1
    assert held["path_distance_final_body_lengths"] < drift["path_distance_final_body_lengths"] / 3


def test_the_manta_follows_a_vertical_s():
    """A 1 m S, 0.1 m high, in 20 cycles. Within a fifth of a body length of it on average
    (measured 0.049 with the straight gait of 2026-12-07; 0.06 with that of 2026-12-01 on
    the physics of 2026-12-06; 0.02 before, 0.17 by the paper's rule). Its pitches, learned
    from its hand-set gait on the physics of 2026-11-30, travel 0.03 body lengths a cycle,
    and graded steering mixes some of one into every cycle: it gets 2.1 body lengths along
    (0.83 m; 1.9 with the older straight gait), enough to say it went along and not round
    in place."""
    m = _follow("manta", "s-curve:length=1,amplitude=0.1,vertical=true", 20)
    assert m["path_distance_mean_body_lengths"] < 0.2
    assert m["path_progress_body_lengths"] > 1.5


@pytest.mark.xfail(
    strict=True,
    reason="the shipped pitches (learned before 2026-12-03, uncapped) travel 0.03 body "
    "lengths a cycle: 0.83 m of the S's 1.09 in 20 cycles (0.77 on 96x48x48) with the "
    "straight gait of 2026-12-07 (0.75 m with the one before); they are to be learned "
    "again from it with the side-car's cap of 0.25 rad (the library-refresh issue)",
)
@pytest.mark.parametrize("resolution", [None, (96, 48, 48)], ids=["default", "96x48x48"])
def test_the_manta_follows_the_vertical_s_to_its_end_within_a_fifth_of_a_body_length(
    resolution,
):
    """The library issue's target: the whole S in 20 cycles, never more than 0.2 body
    lengths off it. A manoeuvre's turn under way is not a reproducible figure after a few
    cycles (docs/follow.md, "How far ahead a manoeuvre's turn can be trusted": the
    solve's tolerance alone moves the pitch-up's climb over ten cycles from 39 to 57
    degrees), so the closed loop is held to it on the follower's default grid (64x40x40)
    and on a larger one."""
    m = _follow("manta", "s-curve:length=1,amplitude=0.1,vertical=true", 20,
                resolution=resolution)  # fmt: skip
    assert m["path_finished"]
    assert m["path_distance_max_body_lengths"] <= 0.2


@pytest.mark.xfail(
    strict=True,
    raises=FollowSetupError,
    reason="the frog has no pitches yet: they are learned from its straight gait once "
    "that is searched again on today's physics (the library-refresh issue)",
)
def test_the_frog_follows_a_vertical_s_to_its_end_within_a_fifth_of_a_body_length():
    """The frog's manoeuvres are pitches, which keep its left-right mirror (a turn would
    drop it and double its 18 parameters); its path is the manta's vertical S in the
    frog's body lengths (0.186 m: 2.7 long and 0.27 high), which its straight gait of
    0.24 body lengths a cycle from rest covers in about 11 of the 20 cycles."""
    m = _follow("frog", "s-curve:length=0.5,amplitude=0.05,vertical=true", 20)
    assert m["path_finished"]
    assert m["path_distance_max_body_lengths"] <= 0.2
