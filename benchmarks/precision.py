"""Would single-precision fluid fields make the step faster? The advection kernels timed
on float64 and float32 fields, in one run.

Advection is the largest phase of a 3D step (35-41 %, ``aquagait bench swim
--profile``) and its kernels (``aquagait.fluid._interp``) are compiled by
Numba for the dtype of the arrays they are given, so this times exactly what
an ``EulerFluid`` with float32 fields would run: the same BFECC passes
(departure points, gather, compensate, limited gather) on a smooth velocity
field of the fish's and the frog's default grids, float64 (the baseline,
today's) beside float32, in turn, with the departure points kept in float64 and in
float32. Printed: ns per face sample of each pass, the ratio to float64,
and the largest difference of the advected velocity [m/s].

    python benchmarks/precision.py --repeats 20
"""

import argparse
import time
from functools import partial

import numpy as np

from aquagait.fluid import _interp
from aquagait.fluid.advection import STILL
from aquagait.grid import Grid

GRIDS = {"fish": ((64, 32, 32), 0.004), "frog": ((96, 80, 56), 0.004)}
DT = 1 / 90


def swirl(grid: Grid, dtype) -> tuple[np.ndarray, ...]:
    """A smooth velocity field of up to 0.1 m/s: a vortex about z, a wave along x."""
    out = []
    for axis in range(grid.dim):
        shape = grid.face_shape(axis)
        x, y, z = np.meshgrid(*[np.linspace(0, 2 * np.pi, n) for n in shape], indexing="ij")
        component = (np.sin(y) * np.cos(z), -np.sin(x) * np.cos(z), 0.3 * np.sin(x + y))[axis]
        out.append((0.1 * component).astype(dtype))
    return tuple(out)


def bfecc_passes(grid, velocity, dtype, coordinates):
    """The BFECC passes of one velocity step, timed; returns (seconds per pass, result)."""
    seconds, result = {}, []
    for axis in range(grid.dim):
        shape = grid.face_shape(axis)
        offsets = [0.0 if n == m + 1 else 0.5 for n, m in zip(shape, grid.shape, strict=True)]
        points = [np.empty(shape, coordinates) for _ in range(6)]
        phi1, tilde, final = (np.empty(shape, dtype) for _ in range(3))
        phi = velocity[axis]
        calls = {
            "departure": partial(_interp.departure_3d, None, *velocity, *offsets,
                                 DT / grid.cell_size, STILL, *points, np.empty(shape, bool)),
            "gather": partial(_interp.gather_3d, None, phi, *points[:3], phi1),
            "compensate": partial(_interp.compensate_3d, None, phi, phi1, *points[3:], tilde),
            "limited gather": partial(_interp.limited_gather_3d, None, tilde, phi, *points[:3],
                                      final),
        }  # fmt: skip
        for name, call in calls.items():
            start = time.perf_counter()
            call()
            seconds[name] = seconds.get(name, 0.0) + time.perf_counter() - start
        result.append(final.copy())
    return seconds, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=20)
    args = parser.parse_args()
    cases = {"float64": (np.float64, np.float64), "float32": (np.float32, np.float64),
             "float32, float32 points": (np.float32, np.float32)}  # fmt: skip
    for creature, (shape, h) in GRIDS.items():
        grid = Grid(shape, h)
        samples = sum(np.prod(grid.face_shape(a)) for a in range(grid.dim))
        velocities = {label: swirl(grid, dtype) for label, (dtype, _) in cases.items()}
        runs = {label: [] for label in cases}
        for _ in range(args.repeats + 1):  # the cases in turn, so that load hits each alike
            for label, (dtype, coordinates) in cases.items():
                runs[label].append(bfecc_passes(grid, velocities[label], dtype, coordinates))
        timings = {
            label: {name: np.median([r[0][name] for r in done[1:]]) for name in done[0][0]}
            for label, done in runs.items()
        }  # the first of each compiled and warmed
        results = {label: done[-1][1] for label, done in runs.items()}
        print(f"{creature} {'x'.join(map(str, shape))}: ns per face sample (ratio to float64)")
        for label, passes in timings.items():
            cells = "  ".join(
                f"{name} {1e9 * t / samples:.1f} ({timings['float64'][name] / t:.2f}x)"
                for name, t in passes.items()
            )
            total = sum(passes.values())
            pairs = zip(results[label], results["float64"], strict=True)
            error = max(float(np.abs(a.astype(float) - b).max()) for a, b in pairs)
            print(
                f"  {label:<24} {cells}  all {1e9 * total / samples:.1f} "
                f"({sum(timings['float64'].values()) / total:.2f}x)  max |du| {error:.1e} m/s"
            )


if __name__ == "__main__":
    main()
