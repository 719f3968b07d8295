"""The multigrid V-cycle: a symmetric positive-definite preconditioner that converges alone."""

import numpy as np
import pytest

from aquagait.fluid.cells import interior, pad
from aquagait.fluid.multigrid import band_rows, build_hierarchy, laplacian, vcycle
from aquagait.grid import Grid


def hierarchy_for(shape):
    grid = Grid(shape, 1.0)
    return build_hierarchy(grid.ball(np.array(shape) / 2, min(shape) / 5))


def apply_vcycle(h, r):
    z = np.zeros_like(r)
    vcycle(
        r,
        z,
        h.diag,
        h.inverse,
        h.shapes,
        h.offsets,
        np.zeros((5, h.offsets[-1])),
        h.three_d,
        band_rows(h, None),
    )
    return z


@pytest.mark.parametrize("shape", [(32, 16), (17, 9), (16, 8, 8), (12, 9, 7)])
def test_vcycle_is_symmetric_and_positive(shape):
    h = hierarchy_for(shape)
    fluid = h.level_diag(0) != 0
    rng = np.random.default_rng(0)
    a, b = (np.where(fluid, rng.standard_normal(fluid.shape), 0.0) for _ in range(2))
    va, vb = apply_vcycle(h, a), apply_vcycle(h, b)
    # the V-cycle runs in single precision: symmetric to float32 round-off
    assert np.vdot(b, va) == pytest.approx(np.vdot(a, vb), rel=1e-5)
    assert np.vdot(a, va) > 0 and np.vdot(b, vb) > 0


def contraction_per_cycle(shape, solid=True, cycles=6):
    """Average factor by which one V-cycle, used alone as a solver, cuts the residual."""
    h = hierarchy_for(shape) if solid else build_hierarchy(np.zeros(shape, bool))
    d0 = h.level_diag(0)
    b = np.where(d0 != 0, np.random.default_rng(1).standard_normal(d0.shape), 0.0)
    x, r = np.zeros_like(b), b.copy()
    norms = []
    for _ in range(cycles):
        x += apply_vcycle(h, r)
        laplacian(x, d0, r, h.three_d)
        r = np.where(d0 != 0, b - r, 0.0)
        norms.append(np.abs(r).max())
    return (norms[-1] / norms[1]) ** (1 / (cycles - 2))


@pytest.mark.parametrize(
    "shapes, solid, bound",
    [
        # open domain, 2D red-black Gauss-Seidel: measured 0.15 and 0.16
        (((64, 64), (256, 256)), False, 0.25),
        # open domain, 3D damped Jacobi (cheaper, vectorized): measured 0.28 and 0.29
        (((16, 16, 16), (48, 48, 48)), False, 0.35),
        # with a staircase obstacle (Neumann walls coarsen less well): measured 0.35-0.43
        (((64, 32), (256, 128)), True, 0.5),
        (((32, 16, 16), (64, 32, 32)), True, 0.5),
    ],
)
def test_vcycle_contraction_is_independent_of_resolution(shapes, solid, bound):
    coarse, fine = (contraction_per_cycle(s, solid) for s in shapes)
    assert coarse < bound and fine < bound
    assert fine < coarse + 0.1  # refining the grid does not slow multigrid down


def test_hierarchy_coarsens_to_two_cells_and_keeps_fluid():
    h = build_hierarchy(np.zeros((96, 64, 48), bool))
    assert [tuple(s) for s in h.shapes] == [
        (98, 66, 50), (50, 34, 26), (26, 18, 14), (14, 10, 8), (8, 6, 5), (5, 4, 4)
    ]  # fmt: skip
    # a coarse cell is fluid if any child is: a one-cell channel survives coarsening
    solid = np.ones((16, 16), bool)
    solid[:, 7] = False
    h = build_hierarchy(solid)
    assert all(np.any(h.level_diag(level) != 0) for level in range(h.levels))


def test_padded_layout_round_trip():
    field = np.arange(12.0).reshape(4, 3)
    padded = pad(field)
    assert padded.shape == (6, 5, 1)
    assert np.all(interior(padded, 2) == field)
    assert padded.sum() == field.sum()
