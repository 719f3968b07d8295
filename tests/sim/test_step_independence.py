"""The swim does not depend on the step where the coupling is consistent in time (issue 30).

BFECC corrects its own error from a back-and-forth trace; next to a moving
body the field holds the body's velocity, not an advected one, and the
correction across it changed the fish's swim with the step. Advecting the
faces within two cells of the body at first order (``EulerFluid.near_body``)
removes that.
"""

import pytest

import aquagait as ag
from aquagait.app.convergence import CASES, convergence_study
from aquagait.metrics import travel_metrics

SECONDS = 1.0
"""The fish's first second from rest: 11 mm swum, the tail beating fully."""

STEPS = (1 / 90, 1 / 270)

TOLERANCE = 0.05
"""Relative difference allowed between the two steps' distances. Measured: 3.6%
(over 2 s, 0.3%), against 15.5% with BFECC corrected up to the body."""


def distances(creature, fluid):
    out = []
    for dt in STEPS:
        scene = ag.make_scene(creature, fluid=fluid)
        run = ag.rollout(scene, ag.init_state(scene), creature.policy(), SECONDS, dt=dt,
                         record_fluid=False)  # fmt: skip
        out.append(travel_metrics(creature.model, run)["distance"])
    return out


@pytest.fixture(scope="module")
def fish():
    return ag.creatures.get("fish")


def test_the_fish_swims_as_far_at_a_third_of_the_step(fish):
    coarse, fine = distances(fish, ag.EulerFluid())
    assert fine == pytest.approx(coarse, rel=TOLERANCE)


def test_with_bfecc_corrected_up_to_the_body_it_does_not(fish):
    """The check above can fail: the previous scheme misses it threefold."""
    coarse, fine = distances(fish, ag.EulerFluid(near_body=-1))
    assert abs(fine / coarse - 1) > 2 * TOLERANCE


@pytest.mark.slow
def test_the_fishs_two_second_swim_is_step_independent_to_a_third_of_the_step(fish):
    """Measured: 0.0321 and 0.0320 m (0.3%); with BFECC up to the body, 14.1%."""
    study = convergence_study(fish, cases=CASES[:2])
    assert abs(study.swims[1].distance / study.swims[0].distance - 1) < 0.03


@pytest.mark.slow
def test_eel2d_without_the_per_step_hold_is_step_independent_to_a_sixth_of_the_step():
    """``mostly_water=0``: 0.656, 0.653 and 0.644 m at 1/90, 1/270 and 1/540 s (the
    default rule: 0.695, 0.772, 0.794)."""
    study = convergence_study("eel2d", fluid=ag.EulerFluid(mostly_water=0), cases=CASES[:3])
    assert abs(study.step_change) < 0.03
