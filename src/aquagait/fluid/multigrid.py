"""Geometric multigrid V-cycle: the preconditioner of the pressure solve.

Multigrid-preconditioned CG (McAdams, Sifakis and Teran 2010) keeps the
iteration count nearly flat as the grid is refined, where incomplete Cholesky
(MIC(0)) grows like the square root of the cell count per axis. We measured
both (``aquagait bench fluid`` and tests/fluid/test_pcg.py hold the budgets).

The hierarchy halves every axis (x and y only in 2D) until an axis reaches two
cells. A coarse cell is fluid when any of its children is; coarse ghosts are
again Dirichlet ``p = 0``. Transfers are cell-centred linear interpolation
``P`` (weights 3/4 and 1/4 per axis) and its transpose ``R = (4 / 2^dim) P^T``,
the factor matching the unscaled Laplacian (``L_2h ~ 4 L_h``). Coarse levels
place their open-boundary condition where the finest grid has it.

Smoothing is red-black Gauss-Seidel in 2D (red then black before the coarse
correction, black then red after) and damped Jacobi in 3D, whose sweeps read
one array and write another and so vectorize: per second of work it smooths
more than Gauss-Seidel there. Either way the V-cycle is a symmetric positive-
definite operator, as CG needs. It runs in single precision (CG itself, the
operator and the residual stay double): a preconditioner needs no more, and
it halves the memory traffic. All levels live in flat buffers (``offsets``) in
the padded layout of ``cells.py``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from aquagait.fluid.cells import padded_flat, padded_shape
from aquagait.fluid.scratch import per_thread_cache

SMOOTHING_STEPS_2D = 2
"""Red-black Gauss-Seidel steps before (and after) each coarse-grid correction in 2D."""

SMOOTHING_STEPS_3D = 1
"""Jacobi steps (two sweeps each) before (and after) each coarse-grid correction in 3D."""

JACOBI_WEIGHT = 6.0 / 7.0
"""Damping of Jacobi smoothing for the 7-point Laplacian (the optimal smoothing factor)."""

COARSEST_SWEEPS = 16
"""Symmetric sweep pairs that stand in for an exact solve on the coarsest grid."""


@dataclass(frozen=True)
class Hierarchy:
    """The levels of a multigrid cycle for one set of solid cells.

    Attributes:
        shapes: ``(levels, 3)`` padded array shape of each level, finest first.
        offsets: ``(levels + 1,)`` start of each level in the flat buffers.
        diag: flat float32, the Laplacian's diagonal per level (0 at solid and ghost cells).
        inverse: flat, ``1 / diag`` where ``diag`` is nonzero, else 0 (smoothing
            multiplies: a division costs more than the rest of a cell's update).
        three_d: whether z is a real axis (False: the 2D layout, one z layer).
    """

    shapes: np.ndarray
    offsets: np.ndarray
    diag: np.ndarray
    inverse: np.ndarray
    three_d: bool

    @property
    def levels(self) -> int:
        return len(self.shapes)

    def level_diag(self, level: int) -> np.ndarray:
        """The padded 3D diagonal of one level (a view)."""
        lo, hi = self.offsets[level], self.offsets[level + 1]
        return self.diag[lo:hi].reshape(self.shapes[level])


def build_hierarchy(solid: np.ndarray) -> Hierarchy:
    """Coarsen a solid-cell mask into a multigrid hierarchy.

    Args:
        solid: boolean cell mask, ``(nx, ny)`` or ``(nx, ny, nz)``; no enclosed
            fluid pockets (see ``cells.seal_pockets``).
    Returns:
        the hierarchy, finest level first.
    """
    three_d = solid.ndim == 3
    masks = [np.asarray(solid, dtype=np.bool_)]
    while min(masks[-1].shape) > 2:
        masks.append(_coarsen(masks[-1]))
    shapes = np.array([padded_shape(m.shape) for m in masks], dtype=np.int64)
    offsets = np.concatenate([[0], np.cumsum(np.prod(shapes, axis=1))]).astype(np.int64)
    diag = np.zeros(offsets[-1], dtype=np.float32)
    for level, mask in enumerate(masks):
        level_diag = diag[offsets[level] : offsets[level + 1]].reshape(shapes[level])
        _fill_diag(mask.reshape(mask.shape + (1,) * (3 - mask.ndim)), level_diag, three_d)
        _place_open_boundary(level_diag, solid.shape, level)
    inverse = np.zeros_like(diag)
    np.divide(np.float32(1.0), diag, out=inverse, where=diag != 0)
    return Hierarchy(shapes, offsets, diag, inverse, three_d)


def _place_open_boundary(diag: np.ndarray, fine_shape: tuple[int, ...], level: int) -> None:
    """Put a coarse level's Dirichlet condition where the finest grid has it.

    The finest ghosts sit half a fine cell outside the grid; a coarse level's
    ghosts sit half a coarse cell outside, too far. A border cell whose centre
    is ``theta`` of its own cell size from the true boundary couples to it
    with weight ``1 / theta`` instead of 1 (ghost-fluid style). Without this,
    errors next to the open boundary converge several times slower.
    """
    for axis, n_fine in enumerate(fine_shape):
        size = 2**level
        n = -(-n_fine // size)  # cells of this level along the axis
        theta_lo = (0.5 * size + 0.5) / size
        theta_hi = ((n_fine + 0.5) - (n - 0.5) * size) / size
        for index, theta in ((1, theta_lo), (n, theta_hi)):
            layer = [slice(1, -1)] * diag.ndim
            if len(fine_shape) == 2:
                layer[2] = slice(None)
            layer[axis] = index
            border = diag[tuple(layer)]
            border[border != 0] += 1.0 / max(theta, 0.25) - 1.0


def _coarsen(solid: np.ndarray) -> np.ndarray:
    """A coarse cell is solid only when all of its (existing) children are."""
    coarse = np.ones(tuple((n + 1) // 2 for n in solid.shape), dtype=np.bool_)
    as_3d = (1,) * (3 - solid.ndim)
    _clear_fluid_parents_(solid.reshape(solid.shape + as_3d), coarse.reshape(coarse.shape + as_3d))
    return coarse


@numba.njit(cache=True, nogil=True)
def _clear_fluid_parents_(solid, coarse):
    """``coarse`` (all True on entry) becomes False where any child is fluid."""
    nx, ny, nz = solid.shape
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if not solid[i, j, k]:
                    coarse[i // 2, j // 2, k // 2] = False


@numba.njit(cache=True, nogil=True)
def _fill_diag(solid, diag, three_d):
    nx, ny, nz = solid.shape
    kz = 1 if three_d else 0
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if solid[i, j, k]:
                    continue
                count = 0
                for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                    a, b = i + di, j + dj
                    if not (0 <= a < nx and 0 <= b < ny) or not solid[a, b, k]:
                        count += 1
                if three_d:
                    for c in (k - 1, k + 1):
                        if not (0 <= c < nz) or not solid[i, j, c]:
                            count += 1
                diag[i + 1, j + 1, k + kz] = count


@numba.njit(cache=True, nogil=True)
def laplacian(x, diag, out, three_d):
    """``out = L x`` in the padded layout: ``diag * x - sum of neighbours``."""
    nx, ny, nz = x.shape
    k0, k1 = (1, nz - 1) if three_d else (0, 1)
    for i in range(1, nx - 1):
        for j in range(1, ny - 1):
            for k in range(k0, k1):
                d = diag[i, j, k]
                if d == 0.0:
                    out[i, j, k] = 0.0
                    continue
                s = x[i - 1, j, k] + x[i + 1, j, k] + x[i, j - 1, k] + x[i, j + 1, k]
                if three_d:
                    s += x[i, j, k - 1] + x[i, j, k + 1]
                out[i, j, k] = d * x[i, j, k] - s


@numba.njit(cache=True, nogil=True)
def _smooth(x, b, inverse, color, three_d):
    """One red (color 0) or black (color 1) Gauss-Seidel half sweep, in place.

    Solid and ghost cells have ``inverse == 0`` and stay at zero without a branch.
    """
    nx, ny, nz = x.shape
    k0, k1 = (1, nz - 1) if three_d else (0, 1)
    for i in range(1, nx - 1):
        for j in range(1, ny - 1):
            if three_d:
                for k in range(k0 + ((i + j + k0 + color) & 1), k1, 2):
                    s = x[i - 1, j, k] + x[i + 1, j, k] + x[i, j - 1, k] + x[i, j + 1, k]
                    s += x[i, j, k - 1] + x[i, j, k + 1]
                    x[i, j, k] = (b[i, j, k] + s) * inverse[i, j, k]
            elif (i + j + color) & 1 == 0:
                s = x[i - 1, j, 0] + x[i + 1, j, 0] + x[i, j - 1, 0] + x[i, j + 1, 0]
                x[i, j, 0] = (b[i, j, 0] + s) * inverse[i, j, 0]


@numba.njit(cache=True, nogil=True)
def _residual(x, b, diag, r, three_d, band):
    laplacian(x, diag, r, three_d)
    nx, ny, nz = x.shape
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                r[i, j, k] = b[i, j, k] - r[i, j, k] if diag[i, j, k] != 0.0 else 0.0
    cells, near, weight, inverse, parity = band
    fx, fb, fr = x.ravel(), b.ravel(), r.ravel()
    for n in range(cells.size):
        c = cells[n]
        fr[c] = fb[c] - fx[c] / inverse[n] + _weighted_sum(fx, near, weight, n)


# Partial faces (``pcg.PartialFaces``) change the Laplacian at a band of cells
# next to the body. The finest level's smoother and residual use the weighted
# rows there (``band``: the cells, their neighbours' flat indices and face
# weights, ``1 / sum of weights``, and each cell's red-black colour); the
# kernels above run first and these overwrite the band cells. Coarser levels
# stay unweighted: the body is a few cells there anyway.


@numba.njit(cache=True, nogil=True)
def _weighted_sum(flat, near, weight, n):
    total = 0.0
    for m in range(near.shape[1]):
        total += weight[n, m] * flat[near[n, m]]
    return total


@numba.njit(cache=True, nogil=True)
def _band_gauss_seidel_(x, b, band, color):
    cells, near, weight, inverse, parity = band
    fx, fb = x.ravel(), b.ravel()
    for n in range(cells.size):
        if parity[n] == color:
            fx[cells[n]] = (fb[cells[n]] + _weighted_sum(fx, near, weight, n)) * inverse[n]


@numba.njit(cache=True, nogil=True)
def _band_jacobi_(x, b, out, band):
    cells, near, weight, inverse, parity = band
    fx, fb, fo = x.ravel(), b.ravel(), out.ravel()
    for n in range(cells.size):
        c = cells[n]
        fo[c] = (1 - JACOBI_WEIGHT) * fx[c] + JACOBI_WEIGHT * inverse[n] * (
            fb[c] + _weighted_sum(fx, near, weight, n)
        )


# Transfers are separable: one pass per axis, each a 4-tap (restriction) or
# 2-tap (prolongation) filter along that axis. Coarse padded cell I covers fine
# padded cells 2I-1 and 2I; along an axis it gathers fine 2I-2 .. 2I+1 with
# weights 1/4, 3/4, 3/4, 1/4. The passes run x, y, z when restricting and z, y,
# x when prolonging, so the stride-2 pattern along the contiguous z axis falls
# on the smallest array and the big passes vectorize. Fine ghosts hold zero.


@numba.njit(cache=True, nogil=True)
def _last_tap(f, n):
    """The fourth tap of a restriction window starting at ``f``: (index, weight)."""
    return (f + 3, 0.25) if f + 3 < n else (f + 2, 0.0)


@numba.njit(cache=True, nogil=True)
def _restrict(r, diag_c, b_c, t1, t2, three_d):
    """``b_c = (4 / 2^dim) P^T r`` on non-solid coarse cells (``t1``, ``t2``: scratch)."""
    fx, fy, fz = r.shape
    cx, cy, cz = b_c.shape
    a = t1[: cx * fy * fz].reshape((cx, fy, fz))
    for I in range(1, cx - 1):
        i = 2 * I - 2
        last, w = _last_tap(i, fx)
        for j in range(fy):
            for k in range(fz):
                a[I, j, k] = (
                    0.25 * r[i, j, k]
                    + 0.75 * (r[i + 1, j, k] + r[i + 2, j, k])
                    + (w * r[last, j, k])
                )
    c = t2[: cx * cy * fz].reshape((cx, cy, fz))
    for I in range(1, cx - 1):
        for J in range(1, cy - 1):
            j = 2 * J - 2
            last, w = _last_tap(j, fy)
            for k in range(fz):
                c[I, J, k] = (
                    0.25 * a[I, j, k]
                    + 0.75 * (a[I, j + 1, k] + a[I, j + 2, k])
                    + (w * a[I, last, k])
                )
    scale = 0.5 if three_d else 1.0
    for I in range(1, cx - 1):
        for J in range(1, cy - 1):
            if not three_d:
                b_c[I, J, 0] = scale * c[I, J, 0] * (diag_c[I, J, 0] != 0.0)
                continue
            for K in range(1, cz - 1):
                k = 2 * K - 2
                last, w = _last_tap(k, fz)
                v = 0.25 * c[I, J, k] + 0.75 * (c[I, J, k + 1] + c[I, J, k + 2]) + w * c[I, J, last]
                b_c[I, J, K] = scale * v * (diag_c[I, J, K] != 0.0)


@numba.njit(cache=True, nogil=True)
def _prolong_add(x_c, x, inverse, t1, t2, three_d):
    """``x += P x_c`` on non-solid fine cells (``t1``, ``t2``: scratch).

    Fine padded cell i takes 3/4 of its parent ``(i - 1) // 2 + 1`` and 1/4 of
    the parent's neighbour on its side.
    """
    fx, fy, fz = x.shape
    cx, cy, cz = x_c.shape
    k0, k1 = (1, fz - 1) if three_d else (0, 1)
    if three_d:
        a = t1[: cx * cy * fz].reshape((cx, cy, fz))
        for I in range(cx):
            for J in range(cy):
                for k in range(k0, k1):
                    K = (k - 1) // 2 + 1
                    K2 = K - 1 if (k - 1) % 2 == 0 else K + 1
                    a[I, J, k] = 0.75 * x_c[I, J, K] + 0.25 * x_c[I, J, K2]
    else:
        a = x_c
    c = t2[: cx * fy * fz].reshape((cx, fy, fz))
    for I in range(cx):
        for j in range(1, fy - 1):
            J = (j - 1) // 2 + 1
            J2 = J - 1 if (j - 1) % 2 == 0 else J + 1
            for k in range(k0, k1):
                c[I, j, k] = 0.75 * a[I, J, k] + 0.25 * a[I, J2, k]
    for i in range(1, fx - 1):
        I = (i - 1) // 2 + 1
        I2 = I - 1 if (i - 1) % 2 == 0 else I + 1
        for j in range(1, fy - 1):
            for k in range(k0, k1):
                x[i, j, k] += (0.75 * c[I, j, k] + 0.25 * c[I2, j, k]) * (inverse[i, j, k] != 0.0)


@numba.njit(cache=True, nogil=True)
def _jacobi(x, b, diag, inverse, out, three_d):
    """One damped Jacobi sweep ``out = x + omega (b - L x) / diag`` (weighted for 3D).

    Reads ``x`` and writes ``out``, so the loop vectorizes; solid and ghost
    cells (``inverse == 0``) keep their zero.
    """
    omega = JACOBI_WEIGHT
    nx, ny, nz = x.shape
    k0, k1 = (1, nz - 1) if three_d else (0, 1)
    for i in range(1, nx - 1):
        for j in range(1, ny - 1):
            for k in range(k0, k1):
                s = x[i - 1, j, k] + x[i + 1, j, k] + x[i, j - 1, k] + x[i, j + 1, k]
                if three_d:
                    s += x[i, j, k - 1] + x[i, j, k + 1]
                residual = b[i, j, k] + s - diag[i, j, k] * x[i, j, k]
                out[i, j, k] = x[i, j, k] + omega * inverse[i, j, k] * residual


@numba.njit(cache=True, nogil=True)
def _smooth_(x, b, diag, inverse, tmp, sweeps, adjoint, three_d, band):
    """``sweeps`` smoothing steps on ``x`` in place; ``adjoint`` reverses the order.

    3D: damped Jacobi, two sweeps a step (``x -> tmp -> x``), self-adjoint.
    2D: red-black Gauss-Seidel (red then black; black then red for the
    adjoint), which converges faster there and costs little.
    """
    for _ in range(sweeps):
        if three_d:
            _jacobi(x, b, diag, inverse, tmp, three_d)
            _band_jacobi_(x, b, tmp, band)
            _jacobi(tmp, b, diag, inverse, x, three_d)
            _band_jacobi_(tmp, b, x, band)
        else:
            _red_black_(x, b, inverse, adjoint, three_d, band)


@numba.njit(cache=True, nogil=True)
def _red_black_(x, b, inverse, adjoint, three_d, band):
    """Red then black Gauss-Seidel half sweeps (black then red for the adjoint)."""
    for color in (1, 0) if adjoint else (0, 1):
        _smooth(x, b, inverse, color, three_d)
        _band_gauss_seidel_(x, b, band, color)


@numba.njit(cache=True, nogil=True)
def _presmooth_from_zero(x, b, diag, inverse, tmp, sweeps, three_d, band):
    """``x = 0`` then ``_smooth_``; in 3D the first Jacobi sweep from zero is just
    ``omega b / diag``, an elementwise pass instead of a stencil."""
    if not three_d:
        x[:] = 0.0
        _smooth_(x, b, diag, inverse, tmp, sweeps, False, three_d, band)
        return
    ft, fb, fi = tmp.ravel(), b.ravel(), inverse.ravel()
    for n in range(ft.size):
        ft[n] = JACOBI_WEIGHT * fi[n] * fb[n]
    cells, inverse_band = band[0], band[3]
    for n in range(cells.size):
        ft[cells[n]] = JACOBI_WEIGHT * inverse_band[n] * fb[cells[n]]
    _jacobi(tmp, b, diag, inverse, x, three_d)
    _band_jacobi_(tmp, b, x, band)
    _smooth_(x, b, diag, inverse, tmp, sweeps - 1, False, three_d, band)


@numba.njit(cache=True, nogil=True)
def _level(buffer, shapes, offsets, level):
    lo, hi = offsets[level], offsets[level + 1]
    return buffer[lo:hi].reshape((shapes[level, 0], shapes[level, 1], shapes[level, 2]))


@numba.njit(cache=True, nogil=True)
def vcycle(r, z, diag, inverse, shapes, offsets, work, three_d, band):
    """``z = V r``: one symmetric multigrid V-cycle, the preconditioner of ``pcg``.

    Args:
        r: padded residual of the finest level.
        z: padded output, same shape.
        diag, inverse, shapes, offsets: the ``Hierarchy`` arrays.
        work: ``(5, offsets[-1])`` scratch: per-level solution, right side,
            residual, and two rows for the separable transfers.
        three_d: whether z is a real axis.
        band: the finest level's weighted rows (``band_rows``; empty without
            partial faces).
    """
    none = _no_band()
    coarsest = shapes.shape[0] - 1
    steps = SMOOTHING_STEPS_3D if three_d else SMOOTHING_STEPS_2D
    xs, bs, rs, t1, t2 = work[0], work[1], work[2], work[3], work[4]
    _level(bs, shapes, offsets, 0)[:] = r
    for level in range(coarsest + 1):
        x, b = _level(xs, shapes, offsets, level), _level(bs, shapes, offsets, level)
        d, inv = _level(diag, shapes, offsets, level), _level(inverse, shapes, offsets, level)
        res = _level(rs, shapes, offsets, level)
        rows = band if level == 0 else none
        if level == coarsest:  # symmetric Gauss-Seidel stands in for an exact solve
            x[:] = 0.0
            for adjoint in (False, True):
                for _ in range(COARSEST_SWEEPS):
                    _red_black_(x, b, inv, adjoint, three_d, rows)
            break
        _presmooth_from_zero(x, b, d, inv, res, steps, three_d, rows)
        _residual(x, b, d, res, three_d, rows)
        d_c, b_c = _level(diag, shapes, offsets, level + 1), _level(bs, shapes, offsets, level + 1)
        _restrict(res, d_c, b_c, t1, t2, three_d)
    for level in range(coarsest - 1, -1, -1):
        x, b = _level(xs, shapes, offsets, level), _level(bs, shapes, offsets, level)
        d, inv = _level(diag, shapes, offsets, level), _level(inverse, shapes, offsets, level)
        _prolong_add(_level(xs, shapes, offsets, level + 1), x, inv, t1, t2, three_d)
        rows = band if level == 0 else none
        _smooth_(x, b, d, inv, _level(rs, shapes, offsets, level), steps, True, three_d, rows)
    z[:] = _level(xs, shapes, offsets, 0)


@numba.njit(cache=True, nogil=True)
def _no_band():
    return (np.zeros(0, np.int64), np.zeros((0, 6), np.int64), np.zeros((0, 6), np.float32),
            np.zeros(0, np.float32), np.zeros(0, np.int64))  # fmt: skip


def preconditioner(system):
    """``apply(r, z)``: one V-cycle over ``system.hierarchy``, the default for ``pcg``.

    ``apply`` writes into the calling thread's scratch levels: build it in the
    thread that solves (``pcg`` does, once per solve). The hierarchy is only
    read, so threads may share one ``system``.
    """
    h = system.hierarchy
    work = _work(int(h.offsets[-1]))
    band = band_rows(h, system.partial)
    return lambda r, z: vcycle(r, z, h.diag, h.inverse, h.shapes, h.offsets, work, h.three_d, band)


def band_rows(hierarchy: Hierarchy, partial) -> tuple:
    """The finest level's rows at the cells of partial faces, weighted (``vcycle``).

    Args:
        hierarchy: the system's levels.
        partial: ``pcg.PartialFaces`` or None.
    Returns:
        ``(cells, near, weight, inverse, parity)``: flat padded cells (n,), their
        six neighbours (n, 6; a 2D grid's z neighbours have weight 0), the
        faces' weights (1 to water or a ghost, 0 to a solid cell, the water
        fraction on a partial face), ``1 / sum of weights``, and ``(i + j + k) % 2``.
    """
    if partial is None or len(partial.weight) == 0:
        return _no_band()
    shape = hierarchy.shapes[0]
    below, above = (padded_flat(c, tuple(shape)) for c in (partial.below, partial.above))
    weight = np.asarray(partial.weight, dtype=np.float32)
    return _band_rows(hierarchy.level_diag(0).ravel(), shape, below, above, weight)


@numba.njit(cache=True, nogil=True)
def _band_rows(diag, shape, below, above, fraction):
    """``band_rows`` from the flat padded cells beside each partial face."""
    row = np.full(diag.size, -1, np.int64)
    cells = np.empty(2 * below.size, np.int64)
    n = 0
    for f in range(below.size):
        for c in (below[f], above[f]):
            if diag[c] != 0.0 and row[c] < 0:
                row[c], cells[n] = n, c
                n += 1
    cells = cells[:n]
    three_d = shape[2] > 1
    steps = np.array([shape[1] * shape[2], shape[2], 1, -shape[1] * shape[2], -shape[2], -1])
    near = np.empty((n, 6), np.int64)
    weight = np.zeros((n, 6), np.float32)
    parity = np.empty(n, np.int64)
    for r in range(n):
        c = cells[r]
        i, j, k = c // steps[0], (c // shape[2]) % shape[1], c % shape[2]
        parity[r] = (i + j + k) % 2
        for m in range(6):
            near[r, m] = c + steps[m]
            if m % 3 == 2 and not three_d:
                continue  # a 2D grid's z "neighbours" are its y ones
            a, b, d = (i, j, k)
            if m % 3 == 0:
                a += 1 if m < 3 else -1
            elif m % 3 == 1:
                b += 1 if m < 3 else -1
            else:
                d += 1 if m < 3 else -1
            ghost = a == 0 or a == shape[0] - 1 or b == 0 or b == shape[1] - 1
            ghost = ghost or (three_d and (d == 0 or d == shape[2] - 1))
            weight[r, m] = 1.0 if ghost or diag[near[r, m]] != 0.0 else 0.0
    for f in range(below.size):
        for this, other in ((below[f], above[f]), (above[f], below[f])):
            r = row[this]
            if r < 0:
                continue
            for m in range(6):
                if steps[m] == other - this:
                    weight[r, m] = fraction[f]
    inverse = np.empty(n, np.float32)
    for r in range(n):
        inverse[r] = 1.0 / weight[r].sum()
    return cells, near, weight, inverse, parity


@per_thread_cache(maxsize=4)
def _work(size: int) -> np.ndarray:
    """Per-level scratch, kept by one thread between solves (fresh pages cost more than a cycle)."""
    return np.zeros((5, size), dtype=np.float32)
