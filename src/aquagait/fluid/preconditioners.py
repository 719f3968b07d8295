"""Preconditioners to compare with multigrid: Jacobi and modified incomplete Cholesky.

Each is ``precondition(system) -> apply(r, z)`` for ``pcg``. Measured on a
grid with a ball obstacle, random right-hand side, residual 1e-8 (iterations):

    grid          multigrid   MIC(0)   Jacobi
    64x32              8         30      161
    256x128           11         88      618
    32x16x16           9         21       83
    64x32x32          10         34      167

MIC(0) grows with the square root of the cells per axis (its condition number
is O(1/h)); multigrid by about one iteration per doubling, so multigrid is the
default (``aquagait bench fluid`` prints both in every run).
"""

from __future__ import annotations

import numba
import numpy as np

MIC_TAU = 0.97
"""Weight of the modified (dropped fill-in) part of MIC(0) (Bridson 2015, §5.2)."""

MIC_SIGMA = 0.25
"""Safety: a pivot below this fraction of the diagonal falls back to the diagonal."""


def jacobi(system):
    """``z = r / diag``: the diagonal preconditioner."""
    inverse = np.zeros_like(system.hierarchy.level_diag(0))
    diag = system.hierarchy.level_diag(0)
    np.divide(1.0, diag, out=inverse, where=diag != 0)

    def apply(r, z):
        np.multiply(r, inverse, out=z)

    return apply


def mic0(system):
    """``z = (F F^T)^-1 r`` with ``F`` the modified incomplete Cholesky factor of ``L``."""
    diag = system.hierarchy.level_diag(0)
    three_d = system.hierarchy.three_d
    factor = np.zeros_like(diag)
    _mic0_factor(diag, factor, three_d)
    scratch = np.zeros_like(diag)
    return lambda r, z: _mic0_solve(diag, factor, r, scratch, z, three_d)


@numba.njit(cache=True, nogil=True)
def _mic0_factor(d, pre, three_d):
    """Inverse square roots of the MIC(0) pivots, in lexicographic order."""
    nx, ny, nz = d.shape
    k0, k1 = (1, nz - 1) if three_d else (0, 1)
    for i in range(1, nx - 1):
        for j in range(1, ny - 1):
            for k in range(k0, k1):
                if d[i, j, k] == 0.0:
                    continue
                # earlier neighbours couple with -1 when fluid
                ax = 1.0 if d[i - 1, j, k] != 0.0 else 0.0
                ay = 1.0 if d[i, j - 1, k] != 0.0 else 0.0
                az = 1.0 if (three_d and d[i, j, k - 1] != 0.0) else 0.0
                px, py, pz = pre[i - 1, j, k], pre[i, j - 1, k], pre[i, j, k - 1]
                e = d[i, j, k] - (ax * px) ** 2 - (ay * py) ** 2 - (az * pz) ** 2
                fill = ax * _forward_couplings(d, i - 1, j, k, 0, three_d) * px * px
                fill += ay * _forward_couplings(d, i, j - 1, k, 1, three_d) * py * py
                fill += az * _forward_couplings(d, i, j, k - 1, 2, three_d) * pz * pz
                e -= MIC_TAU * fill
                if e < MIC_SIGMA * d[i, j, k]:
                    e = d[i, j, k]
                pre[i, j, k] = 1.0 / np.sqrt(e)


@numba.njit(cache=True, nogil=True)
def _forward_couplings(d, i, j, k, axis, three_d):
    """Number of fluid neighbours of (i, j, k) ahead of it along the axes other than ``axis``."""
    total = 0.0
    if axis != 0 and d[i + 1, j, k] != 0.0:
        total += 1.0
    if axis != 1 and d[i, j + 1, k] != 0.0:
        total += 1.0
    if three_d and axis != 2 and d[i, j, k + 1] != 0.0:
        total += 1.0
    return total


@numba.njit(cache=True, nogil=True)
def _mic0_solve(d, pre, r, q, z, three_d):
    """Forward then backward substitution with the factor (``z`` zeroed first: it is reused)."""
    z[:] = 0.0
    nx, ny, nz = d.shape
    k0, k1 = (1, nz - 1) if three_d else (0, 1)
    for i in range(1, nx - 1):
        for j in range(1, ny - 1):
            for k in range(k0, k1):
                p = pre[i, j, k]
                if p == 0.0:
                    continue
                t = r[i, j, k] + pre[i - 1, j, k] * q[i - 1, j, k]
                t += pre[i, j - 1, k] * q[i, j - 1, k]
                if three_d:
                    t += pre[i, j, k - 1] * q[i, j, k - 1]
                q[i, j, k] = t * p
    for i in range(nx - 2, 0, -1):
        for j in range(ny - 2, 0, -1):
            for k in range(k1 - 1, k0 - 1, -1):
                p = pre[i, j, k]
                if p == 0.0:
                    continue
                t = q[i, j, k] + p * (z[i + 1, j, k] + z[i, j + 1, k])
                if three_d:
                    t += p * z[i, j, k + 1]
                z[i, j, k] = t * p
