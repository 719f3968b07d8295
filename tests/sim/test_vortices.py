"""The Q-criterion against closed forms: a solid-body rotation and a Lamb-Oseen vortex."""

import numpy as np
import pytest

from aquagait.sim.frames import FluidFrames
from aquagait.sim.vortices import frame_q, q_criterion, q_level, velocity_gradient


def _centres(n, h):
    """Cell centres of an n^3 lattice of spacing h centred on the origin, (3, n, n, n)."""
    axis = (np.arange(n) - (n - 1) / 2) * h
    return np.stack(np.meshgrid(axis, axis, axis, indexing="ij"))


def test_solid_body_rotation_has_q_equal_to_the_rate_squared():
    """u = w e_z x r: all rotation, no strain; Q = w^2 everywhere, edges included (a
    linear field is differenced exactly)."""
    x, y, z = _centres(12, 0.01)
    w = 3.0
    velocity = np.stack([-w * y, w * x, 0 * z])
    assert np.allclose(q_criterion(velocity, 0.01), w**2, rtol=1e-12)


def test_pure_strain_has_negative_q():
    """u = (s x, -s y, 0): a stagnation-point flow, Q = -s^2."""
    x, y, z = _centres(10, 0.02)
    velocity = np.stack([2.0 * x, -2.0 * y, 0 * z])
    assert np.allclose(q_criterion(velocity, 0.02), -4.0, rtol=1e-12)


def test_lamb_oseen_vortex_matches_its_closed_form():
    """u_theta = G / (2 pi r) (1 - exp(-r^2 / a^2)): Q = (u_theta / r) du_theta/dr, positive in
    the core and negative beyond the radius of fastest swirl, r = 1.1209 a. Central
    differences at h = a / 8 are second order: within 2 % of the peak Q."""
    a, h, n, circulation = 0.04, 0.005, 48, 0.05
    x, y, _ = _centres(n, h)
    r = np.hypot(x, y)
    swirl = circulation / (2 * np.pi * np.maximum(r, 1e-12)) * (1 - np.exp(-(r**2) / a**2))
    velocity = np.stack([-swirl * y / np.maximum(r, 1e-12), swirl * x / np.maximum(r, 1e-12),
                         0 * r])  # fmt: skip
    slope = (
        circulation
        / (2 * np.pi)
        * (
            -(1 - np.exp(-(r**2) / a**2)) / np.maximum(r, 1e-12) ** 2
            + 2 / a**2 * np.exp(-(r**2) / a**2)
        )
    )
    exact = np.where(
        r > 1e-9, swirl / np.maximum(r, 1e-12) * slope, (circulation / (np.pi * a**2)) ** 2
    )
    q = q_criterion(velocity, h)
    inner = (slice(2, -2),) * 3  # away from the one-sided edges
    assert np.abs(q - exact)[inner].max() < 0.02 * exact.max()
    ring = np.abs(r - 1.1209 * a) < h / 2
    assert np.all(q[r < 0.9 * a] > 0) and np.all(q[(r > 1.35 * a) & (r < 3 * a)] < 0)
    assert np.abs(q[ring]).max() < 0.05 * exact.max()


def test_body_cells_and_their_neighbours_are_not_a_vortex():
    x, y, z = _centres(12, 0.01)
    velocity = np.stack([-y, x, 0 * z])[None].astype(np.float16)
    solid = np.zeros((1, 12, 12, 12), bool)
    solid[0, 5:7, 5:7, 5:7] = True
    fluid = FluidFrames(0.01, np.zeros((1, 3)), velocity, solid)
    q = frame_q(fluid, 0)
    # 3D frames keep half precision: about three digits of u, 2 % of its differences here
    assert np.all(q[3:9, 3:9, 3:9] == 0) and np.allclose(q[0], 1.0, rtol=0.02)
    assert q_level(fluid, 0.5) == pytest.approx(0.5, rel=0.02)
    still = FluidFrames(0.01, np.zeros((1, 3)), np.zeros_like(velocity), solid)
    assert q_level(still) == np.inf


def test_velocity_gradient_refuses_a_flat_lattice():
    with pytest.raises(ValueError, match="at least 3 cells"):
        velocity_gradient(np.zeros((3, 2, 5, 5)), 0.01)
