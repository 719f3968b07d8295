"""``aquagait bench fluid``: one fluid step around a static obstacle, and the solve alone.

Each case starts from uniform flow past a disc (2D) or sphere (3D) of a
sixth of the grid's smallest side, warms up, then times BFECC advection plus
projection. The pressure solve of the last step is solved again by SciPy's
unpreconditioned CG (``scipy.sparse.linalg.cg``) on the same matrix, from the
same warm start, to the same 2-norm residual that our solve reached: that is
the in-run baseline of the ``speedup`` column. The same solve preconditioned
with MIC(0) instead of multigrid is timed too (``mic0_*``).
"""

from __future__ import annotations

import statistics
import time
from typing import TextIO

import numpy as np

from aquagait.fluid.advection import advect_velocity
from aquagait.fluid.euler import Obstacles
from aquagait.fluid.pcg import pcg, sparse_matrix
from aquagait.fluid.preconditioners import mic0
from aquagait.fluid.projection import project
from aquagait.grid import Grid

CASES = {
    "2d": (128, 64),
    "3d-small": (64, 32, 32),
    "3d": (96, 64, 48),
}
TARGET_MS = {"2d": 3.0, "3d-small": 30.0, "3d": 120.0}
CELL_SIZE = 0.01  # [m]
INFLOW = 0.2  # [m/s]
WARMUP_STEPS = 5


class _TimedSolve:
    """Wraps ``pcg``: records its wall time and its last problem."""

    def __init__(self):
        self.seconds = 0.0
        self.last = None

    def __call__(self, system, b, atol, x0=None):
        start = time.perf_counter()
        result = pcg(system, b, atol, x0=x0)
        self.seconds = time.perf_counter() - start
        self.last = (system, b.copy(), atol, x0, result)
        return result


def run(repeats: int, out: TextIO) -> list[dict]:
    """Time every case and print the table; returns its rows."""
    rows = []
    header = f"{'case':<10}{'cells':>9}{'ms_per_step':>13}{'solve_ms':>10}"
    header += f"{'scipy_cg_ms':>13}{'speedup':>9}{'target_ms':>11}{'iters':>7}"
    header += f"{'mic0_iters':>12}{'mic0_ms':>9}"
    print(header, file=out)
    for name, shape in CASES.items():
        row = _run_case(name, shape, repeats)
        rows.append(row)
        print(
            f"{name:<10}{row['cells']:>9}{row['ms_per_step']:>13.2f}{row['solve_ms']:>10.2f}"
            f"{row['scipy_cg_ms']:>13.1f}{row['speedup']:>9.1f}{TARGET_MS[name]:>11.0f}"
            f"{row['iterations']:>7}{row['mic0_iterations']:>12}{row['mic0_ms']:>9.2f}",
            file=out,
            flush=True,
        )
    return rows


def _run_case(name: str, shape: tuple[int, ...], repeats: int) -> dict:
    grid = Grid(shape, CELL_SIZE)
    ball = grid.ball(np.asarray(grid.extent) / 2, min(grid.extent) / 6)
    obstacles = Obstacles.at_rest(grid, ball)
    velocity = grid.zeros_velocity()
    velocity[0][:] = INFLOW
    dt = grid.cfl_dt(velocity)
    timed = _TimedSolve()
    pressure = None
    step_ms, solve_ms = [], []
    for i in range(WARMUP_STEPS + repeats):
        start = time.perf_counter()
        advected = advect_velocity(grid, velocity, dt)
        result = project(
            grid, advected, dt, pressure=pressure, system=obstacles.system, solve=timed
        )
        elapsed = time.perf_counter() - start
        velocity, pressure = result.velocity, result.pressure
        if i >= WARMUP_STEPS:
            step_ms.append(1e3 * elapsed)
            solve_ms.append(1e3 * timed.seconds)
    system, b, atol, x0, ours = timed.last
    scipy_ms = _scipy_cg_ms(system, b, x0, ours.x)
    mic_ms = []
    for _ in range(2):  # the first run loads the kernels
        start = time.perf_counter()
        mic = pcg(system, b, atol, x0=x0, precondition=mic0, max_iterations=5000)
        mic_ms.append(1e3 * (time.perf_counter() - start))
    solve = statistics.median(solve_ms)
    return dict(
        case=name,
        cells=grid.cell_count,
        ms_per_step=statistics.median(step_ms),
        solve_ms=solve,
        scipy_cg_ms=scipy_ms,
        speedup=scipy_ms / solve,
        iterations=ours.iterations,
        mic0_iterations=mic.iterations,
        mic0_ms=mic_ms[-1],
    )


def _scipy_cg_ms(system, b, x0, ours) -> float:
    """SciPy CG, no preconditioner, to the 2-norm residual our solve reached."""
    import scipy.sparse.linalg as spla

    A, _ = sparse_matrix(system)
    fluid = ~system.solid
    rhs = b[fluid]
    target = float(np.linalg.norm(rhs - A @ ours[fluid]))
    start = time.perf_counter()
    spla.cg(A, rhs, x0=None if x0 is None else x0[fluid], rtol=0.0, atol=target, maxiter=100_000)
    return 1e3 * (time.perf_counter() - start)
