"""The swim does not depend on the step where the coupling is consistent in time (issue 30).

BFECC corrects its own error from a back-and-forth trace; next to a moving
body the field holds the body's velocity, not an advected one, and the
correction across it changed the fish's swim with the step. Advecting the
faces within two cells of the body at first order (``EulerFluid.near_body``)
removes that. And faces partly solid were held to the body once a step (the
rule before thin parts were closed, ``mostly_water=0.5``): a first-order error
in the step; with thin parts closed inside the solve nothing is held, and the
eel swims as far at a sixth of the step.
"""

import pytest

import aquagait as ag
from aquagait.app.convergence import CASES, convergence_study
from aquagait.body.subcell import voxelize_fractions
from aquagait.metrics import travel_metrics

SECONDS = 1.0
"""The fish's first second from rest: 11 mm swum, the tail beating fully."""

STEPS = (1 / 90, 1 / 270)

TOLERANCE = 0.05
"""Relative difference allowed between the two steps' distances. Measured: 3.6%
(over 2 s, 0.3%), against 15.5% with BFECC corrected up to the body."""


MEASURED_FISH_GAIT = {
    "amplitude[j1]": 0.09071012011838855, "amplitude[j2]": 0.43596361607240003,
    "amplitude[j3]": 0.6963879486562883, "phase[j1]": -0.5773247880931285,
    "phase[j2]": -1.3922685878948522, "phase[j3]": -1.8763957538758695,
}  # fmt: skip
"""The fish's straight gait of 2026-12-01, which the figures here were measured with, pinned
so that they stay true when the shipped gait changes (a gait searched again moved the
scheme-before's difference from 15.5 % to 9.2 %)."""


def distances(creature, fluid, steps=STEPS, gait=None):
    policy = creature.policy() if gait is None else creature.servo(
        creature.spec().unpack([gait[name] for name in creature.spec().names]))  # fmt: skip
    out = []
    for dt in steps:
        scene = ag.make_scene(creature, fluid=fluid)
        run = ag.rollout(scene, ag.init_state(scene), policy, SECONDS, dt=dt,
                         record_fluid=False)  # fmt: skip
        out.append(travel_metrics(creature.model, run)["distance"])
    return out


@pytest.fixture(scope="module")
def fish():
    return ag.creatures.get("fish")


def test_the_fish_swims_as_far_at_a_third_of_the_step(fish):
    coarse, fine = distances(fish, ag.EulerFluid(), gait=MEASURED_FISH_GAIT)
    assert fine == pytest.approx(coarse, rel=TOLERANCE)


def test_with_bfecc_corrected_up_to_the_body_it_does_not(fish):
    """The check above can fail: the previous scheme (BFECC corrected up to the body,
    water fractions alone, faces under half water held to the body once a step)
    misses it threefold."""
    before = ag.EulerFluid(near_body=-1, boundary=voxelize_fractions, mostly_water=0.5)
    coarse, fine = distances(fish, before, gait=MEASURED_FISH_GAIT)
    assert abs(fine / coarse - 1) > 2 * TOLERANCE


@pytest.mark.slow
def test_the_fishs_two_second_swim_is_step_independent_to_a_third_of_the_step(fish):
    """Measured: 0.0321 and 0.0320 m (0.3%); with BFECC up to the body, 14.1%."""
    study = convergence_study(fish, cases=CASES[:2])
    assert abs(study.swims[1].distance / study.swims[0].distance - 1) < 0.03


EEL_STEPS = (1 / 90, 1 / 540)
"""The default longest step and a sixth of it."""


def test_eel2d_swims_as_far_at_a_sixth_of_the_step():
    """The eel's first second from rest, 1/90 against 1/540 s: within 3 %. Measured
    over 2 s: 0.675, 0.671 and 0.666 m at 1/90, 1/270 and 1/540 s (-1.3 %)."""
    coarse, fine = distances(ag.creatures.get("eel2d"), ag.EulerFluid(), EEL_STEPS)
    assert fine == pytest.approx(coarse, rel=0.03)


def test_with_the_per_step_hold_and_leaky_thin_parts_it_does_not():
    """The check above can fail: the rule before (water fractions alone, faces under
    half water held to the body once a step) moves the eel's second by more than
    twice its tolerance. Measured over 2 s: 0.648, 0.718 and 0.736 m (+14 %)."""
    before = ag.EulerFluid(boundary=voxelize_fractions, mostly_water=0.5)
    coarse, fine = distances(ag.creatures.get("eel2d"), before, EEL_STEPS)
    assert abs(fine / coarse - 1) > 0.06
