"""Divergence, vorticity and energy on exact fields."""

import numpy as np
import pytest

from aquagait.fluid.operators import cell_centered, curl, divergence, kinetic_energy, vorticity
from aquagait.grid import Grid


def test_divergence_of_a_linear_field_is_exact():
    grid = Grid((10, 8, 6), 0.2)
    u = (
        1.5 * grid.face_centers(0)[0],
        -0.5 * grid.face_centers(1)[1],
        0.25 * grid.face_centers(2)[2],
    )
    np.testing.assert_allclose(divergence(grid, u), 1.5 - 0.5 + 0.25, atol=1e-12)


def test_vorticity_of_solid_body_rotation_is_twice_the_rate():
    omega = 3.0
    grid = Grid((16, 12), 0.05, origin=(-0.4, -0.3))
    x0, y0 = grid.face_centers(0)
    x1, y1 = grid.face_centers(1)
    u = (-omega * y0, omega * x1)
    np.testing.assert_allclose(vorticity(grid, u), 2 * omega, rtol=1e-10)
    grid3 = Grid((8, 8, 8), 0.1, origin=(-0.4,) * 3)
    u3 = (
        -omega * grid3.face_centers(0)[1],
        omega * grid3.face_centers(1)[0],
        np.zeros(grid3.face_shape(2)),
    )
    w = vorticity(grid3, u3)
    np.testing.assert_allclose(w[2], 2 * omega, rtol=1e-10)
    np.testing.assert_allclose(w[:2], 0.0, atol=1e-10)


def test_curl_of_a_cell_centred_rotation_is_twice_the_rate_in_any_float_dtype():
    # the pictures record cell-centred float32 planes and take their vorticity here
    omega, h = 1.5, 0.01
    x, y = (np.indices((20, 10)) + 0.5) * h - 0.07
    centred = np.stack([-omega * y, omega * x]).astype(np.float32)
    w = curl(centred, h)
    assert w.dtype == np.float64 and w.shape == (20, 10)
    np.testing.assert_allclose(w, 2 * omega, rtol=1e-6)
    with pytest.raises(ValueError, match=r"give \(2, nx, ny\) or \(3, nx, ny, nz\)"):
        curl(centred[..., None], h)


def test_kinetic_energy_of_uniform_flow():
    grid = Grid((10, 10), 0.1)
    u, v = grid.zeros_velocity()
    u[:] = 2.0
    # 110 x-faces of h^2 = 0.01 m^2 each, per metre of depth
    assert kinetic_energy(grid, (u, v), density=1000.0) == pytest.approx(
        0.5 * 1000 * 4 * 110 * 0.01
    )
    assert cell_centered(grid, (u, v)).shape == (2, 10, 10)
