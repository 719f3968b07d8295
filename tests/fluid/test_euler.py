"""The fluid step on a steady Euler solution: the Gresho vortex keeps its shape."""

import numpy as np
import pytest

from aquagait.fluid.advection import bfecc, semi_lagrangian
from aquagait.fluid.euler import Obstacles, step
from aquagait.fluid.operators import divergence, kinetic_energy
from aquagait.grid import CFLError, Grid

TURNOVER = 2 * np.pi * 0.2  # one revolution at the vortex's fastest radius [s]


def gresho(grid: Grid, centre=(0.5, 0.5)):
    """Gresho's vortex: u_theta = 5r (r < 0.2), 2 - 5r (r < 0.4), 0 beyond [m/s].

    A steady solution of the Euler equations whose pressure is constant for
    r > 0.4, so it sits in an open box (p = 0 outside) unchanged. In 3D the
    same vortex is a column along z.
    """
    velocity = []
    for axis in range(grid.dim):
        x, y = grid.face_centers(axis)[:2]
        dx, dy = x - centre[0], y - centre[1]
        r = np.hypot(dx, dy)
        speed = np.where(r < 0.2, 5 * r, np.where(r < 0.4, 2 - 5 * r, 0.0))
        direction = {0: -dy, 1: dx}.get(axis, np.zeros_like(r))
        velocity.append(np.divide(direction * speed, r, out=np.zeros_like(r), where=r > 0))
    return tuple(velocity)


def run(grid, velocity, seconds, scheme=bfecc, cfl=0.5, solid=None):
    obstacles = Obstacles.at_rest(grid, solid)
    dt = cfl * grid.cell_size / 1.0  # the vortex's top speed is 1 m/s
    pressure = None
    for _ in range(int(round(seconds / dt))):
        result = step(grid, velocity, dt, obstacles, pressure=pressure, scheme=scheme)
        velocity, pressure = result.velocity, result.pressure
    return velocity


def relative_error(u, exact):
    return np.sqrt(sum(np.sum((a - b) ** 2) for a, b in zip(u, exact, strict=True)) / sum(
        np.sum(b**2) for b in exact
    ))  # fmt: skip


def test_gresho_vortex_keeps_its_shape_for_a_turnover():
    grid = Grid((64, 64), 1 / 64)
    start = gresho(grid)
    end = run(grid, start, TURNOVER)
    loss = 1 - kinetic_energy(grid, end) / kinetic_energy(grid, start)
    error = relative_error(end, start)
    print(f"Gresho 64x64, one turnover, BFECC: energy loss {loss:.1%}, shape error {error:.1%}")
    # measured 13.2% and 8.2%: the velocity's kinks at r = 0.2 and 0.4 sit 13 and
    # 26 cells out, and BFECC's limiter flattens them a little every step
    assert 0 < loss < 0.18
    assert error < 0.11
    assert np.abs(divergence(grid, end)).max() * grid.cell_size < 1e-5


def test_bfecc_loses_far_less_energy_than_semi_lagrangian():
    grid = Grid((64, 64), 1 / 64)
    start = gresho(grid)
    losses = [
        1 - kinetic_energy(grid, run(grid, start, TURNOVER, scheme)) / kinetic_energy(grid, start)
        for scheme in (semi_lagrangian, bfecc)
    ]
    # measured 45% against 13%
    assert losses[1] < losses[0] / 3


def test_gresho_error_shrinks_with_resolution():
    errors = []
    for n in (32, 64):
        grid = Grid((n, n), 1 / n)
        errors.append(relative_error(run(grid, gresho(grid), TURNOVER), gresho(grid)))
    # measured 14.6% -> 8.2% (1.8x): the profile is only piecewise linear, so
    # its kinks hold convergence below second order
    assert errors[1] < errors[0] / 1.5


def test_gresho_column_between_plates_keeps_its_energy():
    """In 3D the vortex is a column along z, held between two solid plates.

    With open ends instead, the low pressure of the core would draw water in
    along the axis (as a real open-ended vortex does): not a steady solution.
    """
    grid = Grid((32, 32, 8), 1 / 32)
    plates = np.zeros(grid.shape, bool)
    plates[:, :, [0, -1]] = True
    start = gresho(grid)
    for component in start[:2]:
        component[:, :, [0, -1]] = 0.0  # the plates are at rest
    end = run(grid, start, TURNOVER / 2, solid=plates)
    loss = 1 - kinetic_energy(grid, end) / kinetic_energy(grid, start)
    print(f"Gresho column 32x32x8 between plates, half a turnover: energy loss {loss:.1%}")
    # measured 13.6%, as in 2D at this resolution and time; flow along z stays
    # a small artefact next to the plates (measured 1e-4 of the top speed)
    assert 0 < loss < 0.18
    assert np.abs(end[2]).max() < 1e-3


def test_a_step_far_beyond_cfl_is_refused():
    grid = Grid((32, 32), 1 / 32)
    with pytest.raises(CFLError, match="cells per step"):
        step(grid, gresho(grid), dt=1.0)
