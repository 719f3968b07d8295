"""Particle tracing through recorded flow: exact in uniform flow, moving grids, re-seeding."""

import numpy as np
import pytest

from aquagait.sim import FluidFrames
from aquagait.viz.particles import advect, inside, particle_traces, sample, vorticity

H = 0.01
SHAPE = (40, 20)


def frames(velocity_at, count=10, fps=10.0, shift=(0, 0), solid_at=None):
    """FluidFrames whose plane moves by ``shift`` whole cells per frame; world-fixed fields."""
    origin = np.array([np.multiply(shift, f) * H for f in range(count)], dtype=float)
    velocity = np.zeros((count, 2, *SHAPE))
    solid = np.zeros((count, *SHAPE), bool)
    for f in range(count):
        centres = np.moveaxis(origin[f][:, None, None] + (np.indices(SHAPE) + 0.5) * H, 0, -1)
        velocity[f] = np.moveaxis(velocity_at(centres), -1, 0)
        if solid_at is not None:
            solid[f] = solid_at(centres)
    fluid = FluidFrames(cell_size=H, origin=origin, velocity=velocity, solid=solid)
    return fluid, np.arange(count) / fps


def uniform(u):
    return lambda x: np.broadcast_to(np.asarray(u, float), x.shape)


def rotation(omega, centre):
    return lambda x: omega * np.stack([-(x[..., 1] - centre[1]), x[..., 0] - centre[0]], -1)


def test_bilinear_sampling_is_exact_for_linear_fields_and_clamps_outside():
    origin = np.array([0.3, -0.2])
    centres = origin[:, None, None] + (np.indices(SHAPE) + 0.5) * H
    field = 2 * centres[0] - 3 * centres[1] + 1  # linear in space
    points = origin + np.array([[0.05, 0.05], [0.123, 0.077], [0.39, 0.19]])
    np.testing.assert_allclose(
        sample(field, origin, H, points), 2 * points[:, 0] - 3 * points[:, 1] + 1
    )
    far = sample(field, origin, H, origin + np.array([[-1.0, -1.0]]))
    assert far == pytest.approx(field[0, 0])


def test_vorticity_of_a_solid_body_rotation_is_twice_its_rate():
    fluid, _ = frames(rotation(1.5, (0.2, 0.1)), count=1)
    np.testing.assert_allclose(vorticity(fluid, 0), 3.0, atol=1e-12)


@pytest.mark.parametrize("shift", [(0, 0), (1, 0), (2, -1)])
def test_uniform_flow_carries_particles_exactly_whatever_the_grid_does(shift):
    u = np.array([0.3, -0.1])
    fluid, time = frames(uniform(u), shift=shift)
    start = np.array([[0.2, 0.1], [0.25, 0.15]])
    np.testing.assert_allclose(advect(fluid, time, 0, start), start + u * 0.1, atol=1e-14)
    for traces in particle_traces(fluid, time, per_cell=0.1, length=4):
        steps = np.diff(traces, axis=1).reshape(-1, 2)
        steps = steps[np.all(np.isfinite(steps), axis=1)]
        np.testing.assert_allclose(steps, np.broadcast_to(u * 0.1, steps.shape), atol=1e-12)


def test_rotation_keeps_particles_on_their_circles():
    fluid, time = frames(rotation(2.0, (0.2, 0.1)), count=2, fps=30.0)
    start = np.array([[0.25, 0.1], [0.2, 0.16]])
    end = advect(fluid, time, 0, start, substeps=3)
    radius = np.linalg.norm(end - [0.2, 0.1], axis=1)
    np.testing.assert_allclose(radius, [0.05, 0.06], rtol=1e-4)  # RK2: O((w dt)^3) per step
    angle = np.arctan2(*(end - [0.2, 0.1]).T[::-1]) - np.arctan2(*(start - [0.2, 0.1]).T[::-1])
    np.testing.assert_allclose(angle, 2.0 / 30, rtol=1e-4)


def test_particles_that_leave_or_enter_the_body_are_reseeded_in_the_fluid():
    def disc(x):
        return np.linalg.norm(x - [0.2, 0.1], axis=-1) < 0.05

    fluid, time = frames(uniform([1.0, 0.0]), count=6, solid_at=disc)
    counts = set()
    for f, traces in enumerate(particle_traces(fluid, time, per_cell=0.5, length=5)):
        now = traces[:, -1]
        assert np.all(inside(fluid, f, now))  # in the plane and out of the body
        counts.add(len(traces))
        fresh = np.isnan(traces[:, -2, 0])
        assert np.all(np.isnan(traces[fresh, :-1]))  # a new particle's trace starts afresh
        if f >= 2:
            assert fresh.sum() > 0  # 1 m/s sweeps 10 cells a frame: many leave
    assert counts == {400}
