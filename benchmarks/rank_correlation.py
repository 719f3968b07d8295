"""Do coarse (or float32) swims rank gaits as the target grid does? Spearman's rho.

A coarse-to-fine search (``aquagait optimize --coarse FACTOR``) ranks every
sample on a grid FACTOR times coarser and swims only the best again on the
target grid; that pays only if the coarse grid ranks gaits as the target grid
does. This swims random gaits of one creature (uniform within its search
bounds and joint limits, a fixed seed) on both grids, with each solid boundary
(the staircase and sub-cell fractions), and prints the objective the optimizer
minimizes on each grid and the rank correlation between them.

    python benchmarks/rank_correlation.py fish --gaits 8 --factor 2

With ``--precision`` it asks the same of single precision instead: the same
gaits on the target grid with the default (sub-cell) boundary, the fluid in
float64 and in float32 (``EulerFluid(dtype=...)``), the largest difference
between the two objectives beside their spread, and the rank correlation:

    python benchmarks/rank_correlation.py manta --gaits 16 --precision
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


def objective(name: str, params, resolution, cell_size: float, clearance, boundary: str,
              dtype=np.float64) -> float:  # fmt: skip
    """The optimizer's objective ``E`` of a two-cycle swim on one grid, in one precision."""
    creature = ag.creatures.get(name)
    fluid = EulerFluid(boundary=BOUNDARIES[boundary], clearance=clearance, dtype=dtype)
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
    parser.add_argument(
        "--precision",
        action="store_true",
        help="float64 against float32 on the target grid, not fine against coarse",
    )
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()  # fmt: skip
    creature = ag.creatures.get(args.creature)
    gaits = random_gaits(creature, args.gaits, args.seed)
    with ProcessPoolExecutor(args.workers) as pool:

        def swim_all(resolution, h, clearance, boundary, dtype=np.float64):
            n = len(gaits)
            start = time.perf_counter()
            values = np.array(list(pool.map(
                objective, [args.creature] * n, gaits, [resolution] * n, [h] * n,
                [clearance] * n, [boundary] * n, [dtype] * n,
            )))  # fmt: skip
            return values, time.perf_counter() - start

        if args.precision:
            compare_precision(args, creature, swim_all)
        else:
            compare_grids(args, creature, swim_all)


def compare_grids(args, creature, swim_all) -> None:
    """The target grid against one ``args.factor`` times coarser, with each boundary."""
    fine = (creature.resolution, creature.cell_size)
    coarse = coarse_grid(creature, *fine, args.factor)
    grids = {"target": (*fine, CLEARANCE), "coarse": (coarse.resolution, coarse.cell_size,
                                                      coarse.clearance)}  # fmt: skip
    print(f"{args.creature}: target {'x'.join(map(str, fine[0]))} h = {fine[1] * 1e3:.3g} mm, "
          f"coarse {'x'.join(map(str, coarse.resolution))} h = {coarse.cell_size * 1e3:.3g} mm; "
          f"{args.gaits} random gaits, seed {args.seed}")  # fmt: skip
    for note in coarse.notes:
        print(f"note: {note}")
    for boundary in BOUNDARIES:
        values, seconds = {}, {}
        for grid, (resolution, h, clearance) in grids.items():
            values[grid], seconds[grid] = swim_all(resolution, h, clearance, boundary)
        rho = spearmanr(values["target"], values["coarse"]).statistic
        print(f"{boundary:>10}: Spearman rho {rho:+.2f}; coarse swims "
              f"{seconds['target'] / seconds['coarse']:.1f}x cheaper")  # fmt: skip
        for grid in grids:
            print(f"{'':>12}{grid:>7} E: {np.array2string(values[grid], precision=4)}")


def compare_precision(args, creature, swim_all) -> None:
    """The target grid's objectives in float64 and float32, sub-cell boundary."""
    grid = (creature.resolution, creature.cell_size, CLEARANCE)
    print(f"{args.creature}: {'x'.join(map(str, grid[0]))} h = {grid[1] * 1e3:.3g} mm, "
          f"float64 against float32; {args.gaits} random gaits, seed {args.seed}")  # fmt: skip
    double, double_s = swim_all(*grid, "subcell", np.float64)
    single, single_s = swim_all(*grid, "subcell", np.float32)
    rho = spearmanr(double, single).statistic
    apart = np.abs(double - single).max()
    print(f"Spearman rho {rho:+.4f}; objectives apart by at most {apart:.2e} "
          f"(their spread {np.ptp(double):.3g}); float32 swims {double_s / single_s:.2f}x "
          f"as fast, {args.workers} workers")  # fmt: skip
    print(f"  float64 E: {np.array2string(double, precision=6)}")
    print(f"  float32 E: {np.array2string(single, precision=6)}")


if __name__ == "__main__":
    main()
