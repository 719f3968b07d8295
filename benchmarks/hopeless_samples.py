"""Would ending hopeless samples after their first cycle pay? A count, not a timing.

A sample swims two gait cycles (paper §4). After the first, its objective
``E`` is bounded below by what the second cycle could still change: the
distance term can fall by at most the farthest a cycle can swim, ``D``,
while the energy term (the work is cumulative, its penalty only grows once
past the bound) and the deviation (>= 0) cannot help it. So

    E >= -(d_1 + D) + w_energy * max(0, W_1 - bound)

with ``d_1`` the distance and ``W_1`` the work of the first cycle. A sample
whose bound is worse than the generation's ``popsize // 2``-th best final
value (the samples CMA-ES selects) cannot be selected, and could have been
stopped half way. ``D`` is an assumption, in body lengths a cycle (2, 1
and 1/2 by default: no library creature swims one at cruise, and eel2d, the
fastest, 0.95). This swims generations drawn
as CMA-ES would draw them, around the hand-set gait with a quarter of each
range (a first generation) and around the shipped gait with a twentieth (a
late one), and counts such samples: the share of the search's time early
stopping could save is at most half of their share.

    python benchmarks/hopeless_samples.py eel2d --popsize 10 --generations 3
"""

import argparse

import numpy as np

import aquagait as ag
from aquagait import objectives
from aquagait.app.optimize import JointLimits


def draws(creature, start, step, count, rng):
    """``count`` admissible gaits around ``start``, each parameter spread over ``step`` of
    its range."""
    spec, feasible = creature.gait, JointLimits(creature.name)
    width, gaits = spec.upper - spec.lower, []
    while len(gaits) < count:
        x = np.clip(start + step * width * rng.standard_normal(spec.size), spec.lower, spec.upper)
        if feasible(x):
            gaits.append(x)
    return gaits


def final_and_bound(scene, creature, params):
    """The objective of a two-cycle swim, and its lower bound after the first cycle but for
    the reach ``D`` (subtract it)."""
    period = float(np.max(creature.gait.unpack(params).period))
    traj = ag.rollout(scene, ag.init_state(scene), creature.policy(params), 2 * period,
                      record_fluid=False)  # fmt: skip
    direction = (1.0,) + (0.0,) * (creature.dim - 1)
    weights = objectives.Weights(energy=creature.energy_weight)
    final = objectives.total(scene, traj, direction, creature.energy_bound, weights,
                             period=period)  # fmt: skip
    half = int(np.searchsorted(traj.time, period - 1e-9))
    d1 = traj.qpos[half, 0] - traj.qpos[0, 0]
    w1 = traj.energy[half].sum() - traj.energy[0].sum()
    penalty = creature.energy_weight * w1 if w1 > creature.energy_bound else 0.0
    return final, -d1 + penalty


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("creature", nargs="?", default="eel2d")
    parser.add_argument("--popsize", type=int, default=10)
    parser.add_argument("--generations", type=int, default=3)
    parser.add_argument("--reach", type=float, nargs="+", default=[2.0, 1.0, 0.5],
                        help="D, body lengths a cycle (several: a count for each)")  # fmt: skip
    parser.add_argument("--seed", type=int, default=5)
    args = parser.parse_args()
    creature = ag.creatures.get(args.creature)
    scene = ag.make_scene(creature, fluid="euler")
    rng = np.random.default_rng(args.seed)
    hand_set = creature.gaits.get("hand-set", creature.gaits["straight"]).params
    spreads = {"first generation": (hand_set, 0.25), "late generation": (creature.default_gait,
                                                                          0.05)}  # fmt: skip
    length = creature.model.body_length
    for label, (start, step) in spreads.items():
        hopeless = dict.fromkeys(args.reach, 0)
        for generation in range(args.generations):
            values = [final_and_bound(scene, creature, x)
                      for x in draws(creature, start, step, args.popsize, rng)]  # fmt: skip
            final, bound = np.array(values).T
            selected = np.sort(final)[args.popsize // 2 - 1]
            for reach in args.reach:
                hopeless[reach] += int(np.sum(bound - reach * length > selected))
            print(f"{label} {generation + 1}: E {np.round(np.sort(final), 3).tolist()}, the "
                  f"selected up to {selected:.3f}", flush=True)  # fmt: skip
        total = args.popsize * args.generations
        for reach, count in hopeless.items():
            print(
                f"{args.creature}, {label}, D = {reach:g} body lengths a cycle: {count} of "
                f"{total} samples hopeless after their first cycle; early stopping would "
                f"save at most {0.5 * count / total:.0%} of the search's swimming"
            )


if __name__ == "__main__":
    main()
