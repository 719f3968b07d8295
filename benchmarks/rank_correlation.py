"""Do coarse swims rank gaits as the target grid does? Spearman's rho per boundary.

A coarse-to-fine search (``aquagait optimize --coarse FACTOR``) ranks every
sample on a grid FACTOR times coarser and swims only the best again on the
target grid; that pays only if the coarse grid ranks gaits as the target grid
does. This swims random gaits of one creature (uniform within its search
bounds and joint limits, a fixed seed) on both grids, with each solid boundary
(the staircase and sub-cell fractions), and prints the objective the optimizer
minimizes on each grid and the rank correlation between them.

    python benchmarks/rank_correlation.py fish --gaits 8 --factor 2
"""

import argparse
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np
from scipy.stats import spearmanr

import aquagait as ag
from aquagait import objectives
from aquagait.app.coarse import coarse_grid
from aquagait.body.subcell import voxelize_subcell
from aquagait.body.voxelize import voxelize
from aquagait.sim import CLEARANCE, EulerFluid

BOUNDARIES = {"staircase": voxelize, "subcell": voxelize_subcell}


def random_gaits(creature, count: int, seed: int) -> np.ndarray:
    """``count`` gaits drawn uniformly within the search bounds, within the joint limits."""
    rng = np.random.default_rng(seed)
    gait, limits = creature.gait, creature.gait_limits()
    gaits = []
    while len(gaits) < count:
        x = rng.uniform(gait.lower, gait.upper)
        if not gait.limit_violations(x, *limits):
            gaits.append(x)
    return np.array(gaits)


def objective(name: str, params, resolution, cell_size: float, clearance, boundary: str) -> float:
    """The optimizer's objective ``E`` of a two-cycle swim on one grid."""
    creature = ag.creatures.get(name)
    fluid = EulerFluid(boundary=BOUNDARIES[boundary], clearance=clearance)
    scene = ag.make_scene(creature, resolution, cell_size, fluid=fluid)
    traj = ag.rollout(scene, ag.init_state(scene), creature.policy(params), 2.0,
                      record_fluid=False)  # fmt: skip
    direction = (1.0,) + (0.0,) * (creature.dim - 1)
    return objectives.total(scene, traj, direction, creature.energy_bound)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("creature")
    parser.add_argument("--gaits", type=int, default=8)
    parser.add_argument("--factor", type=float, default=2.0)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    creature = ag.creatures.get(args.creature)
    fine = (creature.resolution, creature.cell_size)
    coarse = coarse_grid(creature, *fine, args.factor)
    grids = {"target": (*fine, CLEARANCE), "coarse": (coarse.resolution, coarse.cell_size,
                                                      coarse.clearance)}  # fmt: skip
    print(f"{args.creature}: target {'x'.join(map(str, fine[0]))} h = {fine[1] * 1e3:.3g} mm, "
          f"coarse {'x'.join(map(str, coarse.resolution))} h = {coarse.cell_size * 1e3:.3g} mm; "
          f"{args.gaits} random gaits, seed {args.seed}")  # fmt: skip
    for note in coarse.notes:
        print(f"note: {note}")
    gaits = random_gaits(creature, args.gaits, args.seed)
    with ProcessPoolExecutor(args.workers) as pool:
        for boundary in BOUNDARIES:
            values, seconds = {}, {}
            for grid, (resolution, h, clearance) in grids.items():
                start = time.perf_counter()
                n = len(gaits)
                values[grid] = np.array(list(pool.map(
                    objective, [args.creature] * n, gaits, [resolution] * n, [h] * n,
                    [clearance] * n, [boundary] * n,
                )))  # fmt: skip
                seconds[grid] = time.perf_counter() - start
            rho = spearmanr(values["target"], values["coarse"]).statistic
            print(f"{boundary:>10}: Spearman rho {rho:+.2f}; coarse swims "
                  f"{seconds['target'] / seconds['coarse']:.1f}x cheaper")  # fmt: skip
            for grid in grids:
                print(f"{'':>12}{grid:>7} E: {np.array2string(values[grid], precision=4)}")


if __name__ == "__main__":
    main()
