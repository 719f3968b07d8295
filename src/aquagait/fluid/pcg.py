"""Matrix-free preconditioned conjugate gradients for the pressure system.

Solves ``(L + U C U^T) p = b`` where ``L`` is the cell-centred Laplacian over
fluid faces (open-boundary ghosts included, DESIGN.md §2.3) and ``U C U^T`` an
optional symmetric positive semi-definite low-rank term. The fluid alone uses
``L``; two-way coupling adds ``(rho h / A) B^T Mt^-1 B`` as a ``LowRank`` whose
rows are the coupled cells, without touching this solver. The preconditioner
acts on ``L`` alone; the rank-``k`` term costs at most ``k`` extra iterations.

The whole iteration is one Numba call: the preconditioner is a Numba function
passed in (``vcycle`` by default, ``jacobi`` for comparison), STYLE.md §5.

Convergence is tested in the max norm, ``max |b - A p| <= atol``: after a
projection this bounds every cell's divergence, not only their average.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numba
import numpy as np

from aquagait.fluid.cells import interior, padded_shape, seal_pockets
from aquagait.fluid.multigrid import Hierarchy, build_hierarchy, laplacian, vcycle

DEFAULT_MAX_ITERATIONS = 200


class SolverError(RuntimeError):
    """The pressure solve did not reach its tolerance."""


@dataclass(frozen=True)
class LowRank:
    """A symmetric low-rank term ``U C U^T`` added to the Laplacian.

    ``U`` is sparse by rows: row ``r`` of ``rows`` sits at cell ``cells[r]``.
    A cell may appear in several rows (one per coupled face); they add up.

    Attributes:
        cells: ``(m, dim)`` integer cell indices.
        rows: ``(m, k)`` the nonzero rows of ``U``.
        core: ``(k, k)`` symmetric positive semi-definite ``C``.
    """

    cells: np.ndarray
    rows: np.ndarray
    core: np.ndarray

    def __post_init__(self):
        m, k = np.shape(self.rows)
        if np.shape(self.cells)[0] != m or np.shape(self.core) != (k, k):
            raise ValueError(
                f"LowRank needs cells (m, dim), rows (m, k) and core (k, k); got cells "
                f"{np.shape(self.cells)}, rows {np.shape(self.rows)}, core {np.shape(self.core)}"
            )


@dataclass(frozen=True)
class PressureSystem:
    """The operator of one pressure solve: which cells are fluid, and extra terms.

    Build it with ``pressure_system``. Attributes:
        shape: the grid's cell shape.
        solid: boolean cell mask after sealing enclosed pockets.
        hierarchy: the multigrid levels (level 0 holds the Laplacian's diagonal).
        low_rank: an optional ``LowRank`` term.
    """

    shape: tuple[int, ...]
    solid: np.ndarray
    hierarchy: Hierarchy
    low_rank: LowRank | None = None

    def with_low_rank(self, low_rank: LowRank | None) -> PressureSystem:
        """The same Laplacian plus another low-rank term (the hierarchy is reused)."""
        if low_rank is not None and np.any(self.solid[tuple(np.asarray(low_rank.cells).T)]):
            raise ValueError(
                "a low-rank row sits on a solid (or sealed) cell; its rows must belong to "
                "fluid cells, the ones next to coupled faces"
            )
        return PressureSystem(self.shape, self.solid, self.hierarchy, low_rank)


def pressure_system(solid: np.ndarray, low_rank: LowRank | None = None) -> PressureSystem:
    """Build the pressure operator for a set of solid cells.

    Args:
        solid: boolean cell mask, ``(nx, ny)`` or ``(nx, ny, nz)``. Fluid that
            cannot reach the open boundary is sealed (treated as solid).
        low_rank: optional extra SPD term (two-way coupling).
    """
    solid = seal_pockets(np.asarray(solid, dtype=bool))
    return PressureSystem(solid.shape, solid, build_hierarchy(solid)).with_low_rank(low_rank)


@dataclass(frozen=True)
class SolveResult:
    """Outcome of a pressure solve.

    Attributes:
        x: solution, the grid's cell shape (zero in solid cells).
        iterations: CG iterations taken.
        residual: final ``max |b - A x|`` (units of ``b``).
    """

    x: np.ndarray
    iterations: int
    residual: float


def pcg(
    system: PressureSystem,
    b: np.ndarray,
    atol: float,
    x0: np.ndarray | None = None,
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    precondition=vcycle,
) -> SolveResult:
    """Solve ``A x = b`` by preconditioned conjugate gradients.

    Args:
        system: the operator (``pressure_system``).
        b: right-hand side, the grid's cell shape; ignored in solid cells.
        atol: stop when ``max |b - A x| <= atol``.
        x0: warm start (e.g. the last step's pressure), or None for zero.
        max_iterations: give up (``SolverError``) after this many iterations.
        precondition: a Numba preconditioner with the signature of ``vcycle``.
    Returns:
        the solution, iterations and final residual.
    """
    if np.shape(b) != system.shape:
        raise ValueError(f"right-hand side has shape {np.shape(b)}, expected {system.shape}")
    if x0 is not None and np.shape(x0) != system.shape:
        raise ValueError(f"warm start has shape {np.shape(x0)}, expected {system.shape}")
    dim = len(system.shape)
    hier = system.hierarchy
    x, rhs, scratch, work = _workspace(padded_shape(system.shape), int(hier.offsets[-1]))
    interior(rhs, dim)[...] = np.where(system.solid, 0.0, b)
    interior(x, dim)[...] = 0.0 if x0 is None else np.where(system.solid, 0.0, x0)
    cells, rows, core = _low_rank_arrays(system, x.shape)
    iterations, residual = _pcg(
        x, rhs, hier.level_diag(0), hier.three_d, cells, rows, core,
        precondition, hier.diag, hier.shapes, hier.offsets, work, scratch,
        float(atol), int(max_iterations),
    )  # fmt: skip
    if residual > atol:
        raise SolverError(
            f"pressure solve stopped at residual {residual:.3g} > tolerance {atol:.3g} "
            f"after {iterations} iterations; the system may be singular (fluid sealed in "
            f"by solids?) or the tolerance below round-off"
        )
    return SolveResult(interior(x, dim).copy(), iterations, residual)


@functools.lru_cache(maxsize=4)
def _workspace(padded: tuple[int, int, int], levels_size: int):
    """Scratch arrays of a solve, kept between calls.

    Fresh multi-megabyte arrays cost page faults on first touch, more than a
    whole V-cycle on a 64x32x32 grid; reusing them keeps the solve's cost in
    the arithmetic. Ghost entries stay zero: the kernels never write them.
    """
    x = np.zeros(padded)
    return x, np.zeros(padded), np.zeros((4,) + padded), np.zeros((3, levels_size))


def _low_rank_arrays(system: PressureSystem, padded: tuple[int, int, int]):
    lr = system.low_rank
    if lr is None:
        return np.zeros(0, np.int64), np.zeros((0, 0)), np.zeros((0, 0))
    cells = np.asarray(lr.cells, dtype=np.int64) + 1  # into the padded layout
    if cells.shape[1] == 2:
        cells = np.column_stack([cells, np.zeros(len(cells), np.int64)])
    flat = np.ravel_multi_index(tuple(cells.T), padded)
    return flat, np.ascontiguousarray(lr.rows, float), np.ascontiguousarray(lr.core, float)


@numba.njit(cache=True)
def jacobi(r, z, diag, shapes, offsets, work, three_d):
    """``z = r / diag``: the diagonal preconditioner, for comparison with ``vcycle``."""
    d0 = diag[offsets[0] : offsets[1]].reshape((shapes[0, 0], shapes[0, 1], shapes[0, 2]))
    z[:] = 0.0
    nx, ny, nz = r.shape
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if d0[i, j, k] != 0.0:
                    z[i, j, k] = r[i, j, k] / d0[i, j, k]


MIC_TAU = 0.97
"""Weight of the modified (dropped fill-in) part of MIC(0) (Bridson 2015)."""

MIC_SIGMA = 0.25
"""Safety: a pivot below this fraction of the diagonal falls back to the diagonal."""


@numba.njit(cache=True)
def mic0(r, z, diag, shapes, offsets, work, three_d):
    """``z = (L_ic L_ic^T)^-1 r``: modified incomplete Cholesky, for comparison with ``vcycle``.

    The factor is rebuilt from the finest diagonal on every call (one extra
    sweep), so this has the same signature as the other preconditioners.
    """
    d = diag[offsets[0] : offsets[1]].reshape((shapes[0, 0], shapes[0, 1], shapes[0, 2]))
    pre = work[0, : d.size].reshape(d.shape)
    q = work[1, : d.size].reshape(d.shape)
    pre[:] = 0.0
    q[:] = 0.0
    nx, ny, nz = d.shape
    k0, k1 = (1, nz - 1) if three_d else (0, 1)
    for i in range(1, nx - 1):
        for j in range(1, ny - 1):
            for k in range(k0, k1):
                if d[i, j, k] == 0.0:
                    continue
                e = d[i, j, k]
                # neighbours before this cell: coupling -1 when both are fluid
                ax = 1.0 if d[i - 1, j, k] != 0.0 else 0.0
                ay = 1.0 if d[i, j - 1, k] != 0.0 else 0.0
                az = 1.0 if (three_d and d[i, j, k - 1] != 0.0) else 0.0
                px, py, pz = pre[i - 1, j, k], pre[i, j - 1, k], pre[i, j, k - 1]
                e -= (ax * px) ** 2 + (ay * py) ** 2 + (az * pz) ** 2
                fill = ax * _couplings(d, i - 1, j, k, 0, three_d) * px * px
                fill += ay * _couplings(d, i, j - 1, k, 1, three_d) * py * py
                fill += az * _couplings(d, i, j, k - 1, 2, three_d) * pz * pz
                e -= MIC_TAU * fill
                if e < MIC_SIGMA * d[i, j, k]:
                    e = d[i, j, k]
                pre[i, j, k] = 1.0 / np.sqrt(e)
                t = r[i, j, k] + ax * px * q[i - 1, j, k] + ay * py * q[i, j - 1, k]
                t += az * pz * q[i, j, k - 1]
                q[i, j, k] = t * pre[i, j, k]
    z[:] = 0.0
    for i in range(nx - 2, 0, -1):
        for j in range(ny - 2, 0, -1):
            for k in range(k1 - 1, k0 - 1, -1):
                p = pre[i, j, k]
                if p == 0.0:
                    continue
                t = q[i, j, k]
                if d[i + 1, j, k] != 0.0:
                    t += p * z[i + 1, j, k]
                if d[i, j + 1, k] != 0.0:
                    t += p * z[i, j + 1, k]
                if three_d and d[i, j, k + 1] != 0.0:
                    t += p * z[i, j, k + 1]
                z[i, j, k] = t * p


@numba.njit(cache=True)
def _couplings(d, i, j, k, axis, three_d):
    """Sum of the forward couplings of cell (i, j, k) along the axes other than ``axis``."""
    total = 0.0
    if axis != 0 and d[i + 1, j, k] != 0.0:
        total += 1.0
    if axis != 1 and d[i, j + 1, k] != 0.0:
        total += 1.0
    if three_d and axis != 2 and d[i, j, k + 1] != 0.0:
        total += 1.0
    return total


@numba.njit(cache=True)
def apply_operator(x, diag, three_d, cells, rows, core, out):
    """``out = (L + U C U^T) x`` in the padded layout."""
    laplacian(x, diag, out, three_d)
    if cells.shape[0] == 0:
        return
    flat_x = x.ravel()
    flat_out = out.ravel()
    k = rows.shape[1]
    w = np.zeros(k)
    for r in range(cells.shape[0]):
        w += rows[r] * flat_x[cells[r]]
    cw = core @ w
    for r in range(cells.shape[0]):
        flat_out[cells[r]] += np.dot(rows[r], cw)


@numba.njit(cache=True)
def _dot_max(a, b):
    """Return ``(a . b, max |a|)`` over flat arrays."""
    fa, fb = a.ravel(), b.ravel()
    dot, big = 0.0, 0.0
    for i in range(fa.size):
        dot += fa[i] * fb[i]
        big = max(big, abs(fa[i]))
    return dot, big


@numba.njit(cache=True)
def _pcg(x, b, diag, three_d, cells, rows, core, precondition, hdiag, shapes, offsets,
         work, scratch, atol, max_iterations):  # fmt: skip
    r, z, d, ad = scratch[0], scratch[1], scratch[2], scratch[3]
    apply_operator(x, diag, three_d, cells, rows, core, ad)
    fr, fad, fb, fdiag = r.ravel(), ad.ravel(), b.ravel(), diag.ravel()
    for i in range(fr.size):
        fr[i] = fb[i] - fad[i] if fdiag[i] != 0.0 else 0.0
    residual = np.max(np.abs(fr))
    if residual <= atol:
        return 0, residual
    precondition(r, z, hdiag, shapes, offsets, work, three_d)
    d[:] = z
    rz, _ = _dot_max(r, z)
    fx, fd, fz = x.ravel(), d.ravel(), z.ravel()
    for it in range(1, max_iterations + 1):
        apply_operator(d, diag, three_d, cells, rows, core, ad)
        dad, _ = _dot_max(d, ad)
        alpha = rz / dad
        residual = 0.0
        for i in range(fr.size):
            fx[i] += alpha * fd[i]
            fr[i] -= alpha * fad[i]
            residual = max(residual, abs(fr[i]))
        if residual <= atol:
            return it, residual
        precondition(r, z, hdiag, shapes, offsets, work, three_d)
        rz_new, _ = _dot_max(r, z)
        beta = rz_new / rz
        rz = rz_new
        for i in range(fd.size):
            fd[i] = fz[i] + beta * fd[i]
    return max_iterations, residual


def sparse_matrix(system: PressureSystem):
    """The same operator as a SciPy sparse matrix over the fluid cells.

    A slow, obviously correct assembly for tests and for the SciPy baseline
    of ``aquagait bench fluid``.

    Returns:
        ``(A, fluid_index)``: ``A`` is CSR, ``(n, n)`` for the ``n`` fluid cells
        taken in C order; ``fluid_index`` maps a cell to its row (-1 if solid).
    """
    import scipy.sparse as sp

    fluid = ~system.solid
    index = np.full(system.shape, -1, dtype=np.int64)
    index[fluid] = np.arange(int(fluid.sum()))
    n = int(fluid.sum())
    rows, cols, vals = [], [], []
    diag = np.zeros(n)
    for axis in range(fluid.ndim):
        for step in (-1, 1):
            neighbour = np.roll(index, -step, axis=axis)
            edge = [slice(None)] * fluid.ndim
            edge[axis] = -1 if step == 1 else 0
            outside = np.zeros(system.shape, dtype=bool)
            outside[tuple(edge)] = True
            open_face = fluid & (outside | (neighbour >= 0))
            diag[index[open_face]] += 1
            inner = fluid & ~outside & (neighbour >= 0)
            rows.append(index[inner])
            cols.append(neighbour[inner])
            vals.append(-np.ones(int(inner.sum())))
    rows.append(np.arange(n))
    cols.append(np.arange(n))
    vals.append(diag)
    A = sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)
    )
    lr = system.low_rank
    if lr is not None:
        U = sp.csr_matrix(
            (
                np.ravel(lr.rows),
                (
                    np.repeat(index[tuple(np.asarray(lr.cells).T)], lr.rows.shape[1]),
                    np.tile(np.arange(lr.rows.shape[1]), len(lr.rows)),
                ),
            ),
            shape=(n, lr.rows.shape[1]),
        )
        A = (A + U @ sp.csr_matrix(lr.core) @ U.T).tocsr()
    return A, index
