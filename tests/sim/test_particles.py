"""Particle tracing through recorded flow: exact in uniform flow, moving grids, re-seeding."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.sim import FluidFrames, Trajectory
from aquagait.sim.particles import advect, inside, particle_traces, sample, vorticity, wake

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


# --- 3D ----------------------------------------------------------------------------

SHAPE3 = (16, 12, 10)


def frames3d(u, count=6, fps=10.0):
    """A 3D lattice in uniform flow ``u``, moving one cell along x per frame."""
    origin = np.array([[f * H, 0.0, 0.0] for f in range(count)])
    velocity = np.broadcast_to(np.asarray(u, np.float16)[None, :, None, None, None],
                               (count, 3, *SHAPE3)).copy()  # fmt: skip
    solid = np.zeros((count, *SHAPE3), bool)
    return FluidFrames(cell_size=H, origin=origin, velocity=velocity, solid=solid), np.arange(
        count
    ) / fps


def test_trilinear_sampling_is_exact_for_linear_fields():
    origin = np.array([0.1, -0.2, 0.05])
    centres = origin[:, None, None, None] + (np.indices(SHAPE3) + 0.5) * H
    field = 2 * centres[0] - 3 * centres[1] + 5 * centres[2]
    points = origin + np.array([[0.05, 0.05, 0.05], [0.123, 0.077, 0.031]])
    np.testing.assert_allclose(sample(field, origin, H, points), points @ [2, -3, 5])


def test_3d_particles_move_with_uniform_flow_and_are_seeded_in_their_region():
    u = np.array([0.25, 0.0, -0.125])  # exact in half precision
    fluid, time = frames3d(u)
    region = np.tile(np.array([[0.02, 0.03, 0.02], [0.06, 0.07, 0.05]]), (len(time), 1, 1))
    region[:, :, 0] += H * np.arange(len(time))[:, None]  # the region moves with the lattice
    lifetime = 3
    for f, traces in enumerate(particle_traces(fluid, time, length=4, count=200,
                                               region=region, lifetime=lifetime)):  # fmt: skip
        assert traces.shape == (200, 4, 3)
        steps = np.diff(traces, axis=1).reshape(-1, 3)
        steps = steps[np.all(np.isfinite(steps), axis=1)]
        np.testing.assert_allclose(steps, np.broadcast_to(u * 0.1, steps.shape), atol=1e-12)
        fresh = np.isnan(traces[:, -2, 0])
        seeded = traces[fresh, -1]
        assert np.all((seeded >= region[f, 0] - H) & (seeded <= region[f, 1] + H))  # whole cells
        # nobody outlives its lifetime: at most `lifetime` positions in a trace
        assert np.all(np.isfinite(traces[..., 0]).sum(axis=1) <= lifetime)


def test_a_wake_trace_is_as_opaque_as_the_vorticity_where_it_is():
    """A blob spinning about z at 5 rad/s behind the fish at rest: opaque in it, clear away."""
    fish = ag.creatures.get("fish").model
    at, core, count = np.array([-0.1, 0.0, 0.0]), 0.02, 4
    origin = np.tile([-0.2, -0.1, -0.1], (count, 1))
    centres = origin[0] + (np.moveaxis(np.indices((40, 20, 20)), 0, -1) + 0.5) * H
    r = centres - at
    spin = 5.0 * np.stack([-r[..., 1], r[..., 0], 0 * r[..., 2]], -1)
    spin *= np.exp(-(r**2).sum(-1) / core**2)[..., None]
    velocity = np.broadcast_to(np.moveaxis(spin, -1, 0), (count, 3, 40, 20, 20))
    fluid = FluidFrames(H, origin, velocity.astype(np.float16), np.zeros((count, 40, 20, 20), bool))
    zeros = np.zeros((count, fish.nv))
    traj = Trajectory(np.arange(count) / 30, np.tile(fish.qpos0, (count, 1)), zeros, zeros,
                      zeros, dt=1 / 90, fps=30.0, fluid=fluid)  # fmt: skip
    *_, (traces, alpha, turning) = wake(traj, fish, count=4000, lifetime=100)
    assert np.all(np.abs(turning) <= 1) and np.all(turning[alpha == 0] == 0)
    now = traces[:, -1]
    radius = np.hypot(*(now[:, :2] - at[:2]).T)
    near = (radius < core) & (np.abs(now[:, 2]) < core)
    far = radius > 4 * core
    assert near.sum() > 5 and far.sum() > 100
    assert alpha[near, -1].mean() > 0.5 and alpha[far, -1].max() < 0.05
    assert turning[near, -1].min() > 0.2  # counter-clockwise about +z: positive spin
