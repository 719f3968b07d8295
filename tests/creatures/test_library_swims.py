"""Every library creature swims its shipped gait: forward, straight, within its energy bound.

Slow (four cycles of every creature on its default grid: several minutes);
run with ``python3 -m pytest -m slow tests/creatures/test_library_swims.py -s``
to see each creature's body lengths per cycle, Strouhal number and cost of
transport (the issue's table).
"""

import numpy as np
import pytest

import aquagait as ag
from aquagait.app import prepare_swim, run_swim
from aquagait.body.dynamics import Dynamics
from aquagait.body.geometry import TailTip, tail_tip, tail_tip_path
from aquagait.metrics import centre_of_mass_path, lateral_excursion

CYCLES = 4
STRAIGHT_DEGREES = 15.0
"""The heading (the way the root travels over the last two of four cycles) allowed off +x."""

ANGUILLIFORM = {"eel2d", "eel3d"}
"""Swimmers that undulate the whole body; the fish is carangiform."""

DRIFTS = {"turtle2d"}
"""Creatures that cannot swim straight open-loop (paper §7: the 2D turtle pitches; it needs
path following, issue 13)."""


def heading_change(creature, trajectory) -> float:
    """Degrees between +x (where the creature faces at rest) and the way its root travelled
    over the last two cycles: the heading, free of the body's recoil within a cycle."""
    dim = creature.dim
    travel = trajectory.qpos[-1, :dim] - trajectory.qpos[-1 - 2 * 30, :dim]
    return float(np.degrees(np.arccos(travel[0] / np.linalg.norm(travel))))


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(set(ag.creatures.names()) - {"accordion2d"}))
def test_the_shipped_gait_swims_forward_straight_within_its_energy_bound(name):
    creature = ag.creatures.get(name)
    run = run_swim(prepare_swim(name, seconds=float(CYCLES)))
    m, traj = run.metrics, run.trajectory
    turn = heading_change(creature, traj)
    two_cycles = traj.energy[2 * 30].sum()  # the objective's energy: the first two cycles
    print(f"{name}: {m['body_lengths_per_cycle_from_rest']:.3f} BL/cycle from rest, "
          f"{m['steady_body_lengths_per_cycle']:.3f} steady, Strouhal {m['strouhal']:.3g}, "
          f"cost of transport {m['cost_of_transport']:.3g} J/(kg m), heading {turn:.1f} deg, "
          f"energy {two_cycles:.3g} of {creature.energy_bound:.3g} J")  # fmt: skip
    # forward: 0.02 body lengths a cycle at least, beyond a body's recoil (the hand-set
    # alien, slowest, measured 0.047; the optimized ones swim ten times that)
    assert m["distance"] > 0.02 * creature.model.body_length * CYCLES
    assert two_cycles <= 1.05 * creature.energy_bound  # the objective lets it just past
    if name not in DRIFTS:
        assert turn < STRAIGHT_DEGREES


def joint_phases(creature, trajectory, period: float = 1.0) -> np.ndarray:
    """Each gait joint's phase [rad] at the gait frequency over the last two cycles."""
    model, frames = creature.model, 2 * 30
    shift = model.nq - model.nv  # a free root has one more position than velocity
    columns = [model.dof_names.index(d) + shift for d in creature.gait.dofs]
    t, q = trajectory.time[-frames:], trajectory.qpos[-frames:, columns]
    return np.angle(((q - q.mean(0)) * np.exp(-2j * np.pi * t / period)[:, None]).sum(0))


def lateral_envelope(creature, trajectory) -> tuple[np.ndarray, np.ndarray]:
    """The body's amplitude envelope over the last two cycles: the peak-to-peak excursion [m]
    across the way the centre of mass travelled of each link's origin (head to tail), then
    of the tail tip; and where along the body each point sits at rest, as a fraction of the
    body length from the snout."""
    model, frames = creature.model, 2 * 30
    qpos = trajectory.qpos[-frames - 1 :]
    com = centre_of_mass_path(model, trajectory)[-frames - 1 :]
    dynamics = Dynamics(model.mj)
    origins = [TailTip(link, np.zeros(3)) for link in range(dynamics.nlinks)]
    points = [*origins, tail_tip(model)]
    excursion = [lateral_excursion(tail_tip_path(model, qpos, p), com[-1] - com[0]) for p in points]
    rest = np.array([tail_tip_path(model, model.qpos0[None], p)[0, 0] for p in points])
    return np.array(excursion), (model.bounds[1, 0] - rest) / model.body_length


@pytest.mark.slow
@pytest.mark.parametrize("name", ["eel2d", "eel3d", "fish"])
def test_fish_and_eels_bend_in_a_wave_travelling_head_to_tail(name):
    """Biology (Lighthill 1969; Videler 1993): the body wave travels from head to tail, so
    each joint lags the one before it, and the tail tip sweeps widest. An eel (anguilliform,
    Gray 1933; Tytell and Lauder 2004) undulates its whole body: every point sweeps a
    sizeable share of the tail's width (here at least a fifth; the fish's front moves less
    than a tenth of it); a carangiform fish (Lindsey 1978) moves mostly its rear third: its
    front two thirds sweep less than half the tail's width."""
    creature = ag.creatures.get(name)
    traj = run_swim(prepare_swim(name, seconds=float(CYCLES))).trajectory
    lags = np.angle(np.exp(1j * np.diff(joint_phases(creature, traj))))
    envelope, along = lateral_envelope(creature, traj)
    share, tail = np.round(envelope / envelope[-1], 2), envelope[-1] / creature.model.body_length
    print(f"{name}: phase lag per joint {np.round(lags, 2).tolist()} rad; lateral envelope "
          f"{share.tolist()} of the tail's {tail:.3f} L")  # fmt: skip
    assert np.all(lags < 0)
    assert envelope[-1] == envelope.max()
    if name in ANGUILLIFORM:
        assert envelope.min() > 0.2 * envelope[-1]
    else:
        assert envelope[along < 2 / 3].max() < 0.5 * envelope[-1]


@pytest.mark.slow
@pytest.mark.parametrize("name, group", [("frog", 0), ("turtle3d", 0)])
def test_the_propulsive_limbs_do_most_of_the_work(name, group):
    """The frog kicks with its hind legs (Richards 2010), the sea turtle flies with its front
    flippers (Wyneken 1997): their first gait group does most of the actuator work."""
    creature = ag.creatures.get(name)
    traj = run_swim(prepare_swim(name, seconds=2.0)).trajectory
    work = traj.energy[-1]
    limbs = [creature.model.dof_names.index(d) for d in creature.gait.groups[group]]
    share = work[limbs].sum() / work.sum()
    print(f"{name}: group {group} does {100 * share:.1f}% of the work")
    assert share > 0.5
