"""Pressure projection: divergence free, idempotent, energy non-increasing, and physical."""

import numpy as np
import pytest

from aquagait.fluid.operators import divergence, kinetic_energy
from aquagait.fluid.projection import project
from aquagait.grid import Grid

TOL = 1e-6


def random_velocity(grid, seed=0):
    rng = np.random.default_rng(seed)
    return tuple(rng.standard_normal(grid.face_shape(a)) for a in range(grid.dim))


def obstacle(grid):
    return grid.ball(np.asarray(grid.extent) / 2, min(grid.extent) / 5)


GRIDS = [Grid((48, 32), 0.02), Grid((24, 16, 12), 0.05)]


@pytest.mark.parametrize("grid", GRIDS, ids=["2d", "3d"])
def test_divergence_below_tolerance_after_projection(grid):
    u = random_velocity(grid)
    solid = obstacle(grid)
    result = project(grid, u, dt=0.01, solid=solid, tol=TOL)
    div = np.abs(divergence(grid, result.velocity))[~solid]
    speed = max(np.abs(c).max() for c in result.velocity)
    # the tolerance is on h |div u| relative to the speed U of the flow before projection
    assert div.max() * grid.cell_size <= TOL * max(np.abs(c).max() for c in u)
    assert result.max_divergence == pytest.approx(div.max())
    assert speed > 0.1  # not trivially zero


@pytest.mark.parametrize("grid", GRIDS, ids=["2d", "3d"])
def test_projecting_twice_equals_projecting_once(grid):
    solid = obstacle(grid)
    once = project(grid, random_velocity(grid, 1), dt=0.01, solid=solid, tol=TOL)
    twice = project(grid, once.velocity, dt=0.01, solid=solid, tol=TOL)
    scale = max(np.abs(c).max() for c in once.velocity)
    for a, b in zip(once.velocity, twice.velocity, strict=True):
        np.testing.assert_allclose(a, b, atol=10 * TOL * scale)


@pytest.mark.parametrize("grid", GRIDS, ids=["2d", "3d"])
def test_projection_never_adds_kinetic_energy(grid):
    solid = obstacle(grid)
    for seed in range(3):
        u = random_velocity(grid, seed)
        before = kinetic_energy(grid, u)
        after = kinetic_energy(grid, project(grid, u, dt=0.01, solid=solid).velocity)
        assert after <= before
    # a field that is already divergence free keeps its energy
    u = project(grid, random_velocity(grid, 7), dt=0.01, solid=solid, tol=1e-10).velocity
    again = project(grid, u, dt=0.01, solid=solid, tol=1e-10).velocity
    assert kinetic_energy(grid, again) == pytest.approx(kinetic_energy(grid, u), rel=1e-8)


def test_uniform_flow_through_the_open_boundary_is_unchanged():
    grid = Grid((32, 24, 16), 0.1)
    u, v, w = grid.zeros_velocity()
    u[:] = 0.7
    w[:] = -0.2
    result = project(grid, (u, v, w), dt=0.05)
    for before, after in zip((u, v, w), result.velocity, strict=True):
        np.testing.assert_allclose(after, before, atol=1e-12)
    assert np.abs(result.pressure).max() < 1e-9


def test_solid_faces_take_the_solid_velocity():
    grid = Grid((32, 32), 0.1)
    solid = obstacle(grid)
    moving = grid.zeros_velocity()
    moving[0][:] = 0.3  # a solid translating along x
    result = project(grid, grid.zeros_velocity(), dt=0.01, solid=solid, solid_velocity=moving)
    inside = solid[1:, :] & solid[:-1, :]  # x-faces between two solid cells
    assert np.all(result.velocity[0][1:-1][inside] == 0.3)
    # the fluid makes way: there is flow, and it is divergence free
    assert np.abs(result.velocity[1]).max() > 0.05
    assert result.max_divergence * grid.cell_size <= TOL * 0.3


@pytest.mark.parametrize("dim", [2, 3])
def test_flow_past_a_ball_matches_potential_flow(dim):
    """Uniform flow U projected around a ball at rest is potential flow.

    Theory, on the line through the ball's shoulder at distance r: the speed
    is U (1 + R^2 / r^2) past a cylinder and U (1 + R^3 / (2 r^3)) past a
    sphere. At r = 1.5 R the staircase surface hardly matters; the open
    boundary four to eight radii away costs about 1% (measured 1.0% in 2D,
    0.3% in 3D), so we allow 3%.
    """
    n, radius = (128, 8) if dim == 2 else (48, 6)
    grid = Grid((n,) * dim, 1.0 / n)
    solid = grid.ball(np.full(dim, 0.5), radius * grid.cell_size)
    u = grid.zeros_velocity()
    u[0][:] = 1.0
    flow = project(grid, u, dt=0.01, solid=solid, tol=1e-8).velocity[0]
    c = n // 2
    above = flow[c, c:] if dim == 2 else flow[c, c:, c]  # x-faces on the shoulder line
    k = int(round(1.5 * radius - 0.5))
    r = (k + 0.5) / radius  # face centre distance in radii
    expected = 1 + r**-2 if dim == 2 else 1 + 0.5 * r**-3
    assert above[k] == pytest.approx(expected, rel=0.03)


def test_enclosed_fluid_is_sealed_and_the_solve_succeeds():
    grid = Grid((32, 32), 0.1)
    ring = grid.ball((1.6, 1.6), 0.8) & ~grid.ball((1.6, 1.6), 0.5)
    u = random_velocity(grid, 4)
    result = project(grid, u, dt=0.01, solid=ring)
    assert result.max_divergence * grid.cell_size <= TOL * max(np.abs(c).max() for c in u)


def test_bad_input_gets_a_clear_message():
    grid = Grid((16, 16), 0.1)
    u = grid.zeros_velocity()
    with pytest.raises(ValueError, match="solid has shape"):
        project(grid, u, dt=0.01, solid=np.zeros((8, 8), bool))
    with pytest.raises(ValueError, match="boolean"):
        project(grid, u, dt=0.01, solid=np.zeros((16, 16)))
    with pytest.raises(ValueError, match="positive time"):
        project(grid, u, dt=0.0)
    with pytest.raises(ValueError, match=r"velocity\[0\] has shape"):
        project(grid, (np.zeros((16, 16)), u[1]), dt=0.01)
    with pytest.raises(ValueError, match="density"):
        project(grid, u, dt=0.01, density=-1.0)
