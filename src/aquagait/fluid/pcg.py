"""Matrix-free preconditioned conjugate gradients for the pressure system.

Solves ``(L + U C U^T) p = b`` where ``L`` is the cell-centred Laplacian over
fluid faces (open-boundary ghosts included, docs/method-coupling.md), each face
weighted by its water fraction where ``PartialFaces`` lists one (sub-cell
boundaries), and ``U C U^T`` an optional symmetric positive semi-definite
low-rank term. The fluid alone uses
``L``; two-way coupling adds ``(rho h / A) B^T Mt^-1 B`` as a ``LowRank`` whose
rows are the coupled cells, without touching this solver. The preconditioner
acts on ``L`` alone; the rank-``k`` term costs at most ``k`` extra iterations.

The iteration is a short Python loop over Numba kernels (a few microseconds
of overhead per iteration). The preconditioner is a function passed in
(docs/development.md, "How the code reads"): ``precondition(system) ->
apply(r, z)``, built once per solve; ``multigrid.preconditioner`` by
default, ``preconditioners.mic0`` and ``preconditioners.jacobi`` for
comparison.

Convergence is tested in the max norm, ``max |b - A p| <= atol``: after a
projection this bounds every cell's divergence, not only their average.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numba
import numpy as np

from aquagait.fluid import multigrid
from aquagait.fluid.cells import interior, padded_flat, padded_shape, seal_pockets
from aquagait.fluid.multigrid import Hierarchy, build_hierarchy, laplacian
from aquagait.fluid.scratch import per_thread_cache

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
class PartialFaces:
    """Faces between two cells with water that are only partly open.

    The Laplacian weights a face by its water fraction ``w`` (sub-cell solid
    boundaries, ``aquagait.body.subcell``): ``(L p)_c = sum_f w_f (p_c - p_n)``.
    Faces not listed have ``w = 1`` between two fluid cells, ``w = 0`` next to a
    solid one. A face on the grid's border has the ghost ``p = 0`` on one side.

    Attributes:
        below: ``(n, dim)`` the cell below each face (``-1`` along the axis: the ghost).
        above: ``(n, dim)`` the cell above (the grid's size along the axis: the ghost).
        weight: ``(n,)`` the water fractions, in [0, 1).
    """

    below: np.ndarray
    above: np.ndarray
    weight: np.ndarray

    def __post_init__(self):
        n = len(self.weight)
        if np.shape(self.below) != np.shape(self.above) or len(self.below) != n:
            raise ValueError(
                f"PartialFaces needs below and above (n, dim) and weight (n,); got "
                f"{np.shape(self.below)}, {np.shape(self.above)}, {np.shape(self.weight)}"
            )


@dataclass(frozen=True)
class PressureSystem:
    """The operator of one pressure solve: which cells are fluid, and extra terms.

    Build it with ``pressure_system``. A solve only reads it (the vectors it
    writes are the calling thread's), so threads may share one system.

    Attributes:
        shape: the grid's cell shape.
        solid: boolean cell mask after sealing enclosed pockets.
        hierarchy: the multigrid levels (level 0 holds the diagonal of the
            Laplacian with every face between fluid cells open).
        low_rank: an optional ``LowRank`` term.
        partial: optional ``PartialFaces``: faces weighted below 1. The
            multigrid's finest smoother uses them (``multigrid.band_rows``);
            ``mic0`` and ``jacobi`` act on the unweighted ``L``.
    """

    shape: tuple[int, ...]
    solid: np.ndarray
    hierarchy: Hierarchy
    low_rank: LowRank | None = None
    partial: PartialFaces | None = None

    def with_low_rank(self, low_rank: LowRank | None) -> PressureSystem:
        """The same Laplacian plus another low-rank term (the hierarchy is reused)."""
        if low_rank is not None and np.any(self.solid[tuple(np.asarray(low_rank.cells).T)]):
            raise ValueError(
                "a low-rank row sits on a solid (or sealed) cell; its rows must belong to "
                "fluid cells, the ones next to coupled faces"
            )
        return replace(self, low_rank=low_rank)


def pressure_system(
    solid: np.ndarray,
    low_rank: LowRank | None = None,
    sealed: bool = False,
    partial: PartialFaces | None = None,
) -> PressureSystem:
    """Build the pressure operator for a set of solid cells.

    Args:
        solid: boolean cell mask, ``(nx, ny)`` or ``(nx, ny, nz)``. Fluid that
            cannot reach the open boundary is sealed (treated as solid).
        low_rank: optional extra SPD term (two-way coupling).
        sealed: the caller has sealed the pockets already (skips a flood fill
            over the whole grid); with ``partial``, it must have (a closed face
            can seal water that the cells alone do not).
        partial: optional faces weighted by their water fraction.
    """
    solid = np.asarray(solid, dtype=bool)
    if not sealed:
        solid = seal_pockets(solid)
    system = PressureSystem(solid.shape, solid, _hierarchy(solid), partial=partial)
    return system.with_low_rank(low_rank)


def _hierarchy(solid: np.ndarray) -> Hierarchy:
    """``build_hierarchy``, reused while the solid cells stay the same.

    They often do from one step to the next: with sub-cell boundaries only the
    cells with no water at all are solid (a few dozen for the fish), and the
    build is a tenth of a 3D step. The key is the packed mask (a few KiB).
    """
    return _hierarchy_of(solid.shape, np.packbits(solid).tobytes())


@per_thread_cache(maxsize=2)
def _hierarchy_of(shape: tuple[int, ...], packed: bytes) -> Hierarchy:
    count = int(np.prod(shape))
    solid = np.unpackbits(np.frombuffer(packed, np.uint8), count=count).reshape(shape)
    return build_hierarchy(solid.astype(bool))


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
    precondition=multigrid.preconditioner,
) -> SolveResult:
    """Solve ``A x = b`` by preconditioned conjugate gradients.

    Args:
        system: the operator (``pressure_system``).
        b: right-hand side, the grid's cell shape; ignored in solid cells.
        atol: stop when ``max |b - A x| <= atol``.
        x0: warm start (e.g. the last step's pressure), or None for zero.
        max_iterations: give up (``SolverError``) after this many iterations.
        precondition: ``precondition(system) -> apply(r, z)``, where ``apply``
            writes an approximation of ``L^-1 r`` into ``z`` (padded layout).
    Returns:
        the solution, iterations and final residual.
    """
    if np.shape(b) != system.shape:
        raise ValueError(f"right-hand side has shape {np.shape(b)}, expected {system.shape}")
    if x0 is not None and np.shape(x0) != system.shape:
        raise ValueError(f"warm start has shape {np.shape(x0)}, expected {system.shape}")
    dim = len(system.shape)
    x, r, z, z_old, d, ad = _workspace(padded_shape(system.shape))
    diag = system.hierarchy.level_diag(0)
    if x0 is None:
        x[...] = 0.0
    else:
        _load_fluid_(x, _as_3d(np.asarray(x0, dtype=float)), diag)
    apply = _operator(system)
    apply(x, ad)
    residual = _initial_residual_(r, _as_3d(np.asarray(b, dtype=float)), ad, diag)
    iterations = 0
    if residual > atol:
        iterations, residual = _iterate(apply, precondition(system), x, r, z, z_old, d, ad,
                                        float(atol), max_iterations)  # fmt: skip
    if residual > atol:
        raise SolverError(
            f"pressure solve stopped at residual {residual:.3g} > tolerance {atol:.3g} "
            f"after {iterations} iterations; the system may be singular (fluid sealed in "
            f"by solids?) or the tolerance below round-off"
        )
    return SolveResult(interior(x, dim).copy(), iterations, residual)


def _iterate(apply, precondition, x, r, z, z_old, d, ad, atol, max_iterations):
    """The conjugate-gradient loop; ``r`` holds the initial residual.

    ``beta`` is Polak-Ribiere's, ``r.(z - z_old) / rz_old``: the same as the
    classical one for an exact symmetric preconditioner, and robust to the
    round-off of the single-precision V-cycle (flexible CG, Notay 2000).
    """
    precondition(r, z)
    d[...] = z
    rz = _dot(r, z)
    residual = np.inf
    for iteration in range(1, max_iterations + 1):
        apply(d, ad)
        alpha = rz / _dot(d, ad)
        residual = _step_(x, r, d, ad, alpha)
        if residual <= atol:
            return iteration, residual
        z, z_old = z_old, z
        precondition(r, z)
        rz, rz_old = _dot(r, z), rz
        _new_direction_(d, z, (rz - _dot(r, z_old)) / rz_old)
    return max_iterations, residual


def _operator(system: PressureSystem):
    """``apply(x, out)``: ``out = (L + U C U^T) x`` in the padded layout."""
    diag = system.hierarchy.level_diag(0)
    three_d = system.hierarchy.three_d
    if system.low_rank is None and system.partial is None:
        return lambda x, out: laplacian(x, diag, out, three_d)
    cells, rows, core = _low_rank_arrays(system, diag.shape)
    below, above, change = _partial_arrays(system, diag.shape)

    def apply(x, out):
        laplacian(x, diag, out, three_d)
        _add_partial_(x, below, above, change, diag, out)
        _add_low_rank_(x, cells, rows, core, out)

    return apply


@per_thread_cache(maxsize=4)
def _workspace(padded: tuple[int, int, int]):
    """The six vectors of a solve, kept between calls by the calling thread.

    Fresh multi-megabyte arrays cost page faults on first touch, more than a
    whole V-cycle on a 64x32x32 grid; reusing them keeps the solve's cost in
    the arithmetic. Each thread has its own (``scratch``): two solves in two
    threads never write the same vectors. Ghost entries stay zero: no kernel
    writes them.
    """
    return tuple(np.zeros(padded) for _ in range(6))


def _low_rank_arrays(system: PressureSystem, padded: tuple[int, int, int]):
    """The low-rank term's flat padded cells, each once, with its rows summed; and ``C``.

    Rows at the same cell add up (``LowRank``): a cell beside several coupled
    faces has one row per face, about five per cell for a 3D creature, so
    summing them first makes each product with ``U`` that much cheaper.
    """
    lr = system.low_rank
    if lr is None:
        return np.zeros(0, np.int64), np.zeros((0, 0)), np.zeros((0, 0))
    rows = np.ascontiguousarray(lr.rows, float)
    cells, rows = _summed_rows(padded_flat(lr.cells, padded), rows)
    return cells, rows, np.ascontiguousarray(lr.core, float)


@numba.njit(cache=True, nogil=True)
def _summed_rows(cells, rows):
    """The distinct ``cells`` in increasing order, and the sum of the ``rows`` at each."""
    order = np.argsort(cells, kind="mergesort")
    distinct = np.empty(cells.size, np.int64)
    summed = np.zeros_like(rows)
    n = -1
    for r in order:
        if n < 0 or cells[r] != distinct[n]:
            n += 1
            distinct[n] = cells[r]
        for j in range(rows.shape[1]):
            summed[n, j] += rows[r, j]
    return distinct[: n + 1], summed[: n + 1]


def _partial_arrays(system: PressureSystem, padded: tuple[int, int, int]):
    """Flat padded indices of the cells below and above each partial face, and ``w - 1``."""
    faces = system.partial
    if faces is None:
        return np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0)
    flat = [padded_flat(cells, padded) for cells in (faces.below, faces.above)]
    return flat[0], flat[1], np.asarray(faces.weight, dtype=float) - 1.0


def _as_3d(field: np.ndarray) -> np.ndarray:
    return field.reshape(field.shape + (1,) * (3 - field.ndim))


@numba.njit(cache=True, nogil=True)
def _load_fluid_(x, field, diag):
    """``x = field`` at fluid cells of the padded ``x`` and 0 elsewhere."""
    kz = 1 if x.shape[2] > 1 else 0
    x[:] = 0.0
    nx, ny, nz = field.shape
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                if diag[i + 1, j + 1, k + kz] != 0.0:
                    x[i + 1, j + 1, k + kz] = field[i, j, k]


@numba.njit(cache=True, nogil=True)
def _initial_residual_(r, b, ad, diag):
    """``r = b - A x`` at fluid cells (0 elsewhere), given ``ad = A x``; returns ``max |r|``."""
    _load_fluid_(r, b, diag)
    fr, fad = r.ravel(), ad.ravel()
    residual = 0.0
    for n in range(fr.size):
        fr[n] -= fad[n]
        residual = max(residual, abs(fr[n]))
    return residual


@numba.njit(cache=True, nogil=True)
def _add_partial_(x, below, above, change, diag, out):
    """``out += (w - 1) (x_c - x_n)`` at both cells of every partial face, in place.

    The Laplacian counted each with weight 1; ghosts (``diag == 0``) hold 0
    and are never written.
    """
    flat_x, flat_out, flat_diag = x.ravel(), out.ravel(), diag.ravel()
    for f in range(below.size):
        lo, hi = below[f], above[f]
        flux = change[f] * (flat_x[lo] - flat_x[hi])
        if flat_diag[lo] != 0.0:
            flat_out[lo] += flux
        if flat_diag[hi] != 0.0:
            flat_out[hi] -= flux


@numba.njit(cache=True, nogil=True)
def _add_low_rank_(x, cells, rows, core, out):
    """``out += U C U^T x`` with ``U`` given by its nonzero rows at flat ``cells``."""
    flat_x, flat_out = x.ravel(), out.ravel()
    m, k = rows.shape
    w = np.zeros(k)
    for r in range(m):
        xr = flat_x[cells[r]]
        for j in range(k):
            w[j] += rows[r, j] * xr
    cw = core @ w
    for r in range(m):
        total = 0.0
        for j in range(k):
            total += rows[r, j] * cw[j]
        flat_out[cells[r]] += total


@numba.njit(cache=True, fastmath=True, nogil=True)
def _dot(a, b):
    fa, fb = a.ravel(), b.ravel()
    total = 0.0
    for i in range(fa.size):
        total += fa[i] * fb[i]
    return total


@numba.njit(cache=True, fastmath=True, nogil=True)
def _step_(x, r, d, ad, alpha):
    """``x += alpha d``, ``r -= alpha A d``; returns ``max |r|``."""
    fx, fr, fd, fad = x.ravel(), r.ravel(), d.ravel(), ad.ravel()
    residual = 0.0
    for i in range(fx.size):
        fx[i] += alpha * fd[i]
        fr[i] -= alpha * fad[i]
        residual = max(residual, abs(fr[i]))
    return residual


@numba.njit(cache=True, nogil=True)
def _new_direction_(d, z, beta):
    """``d = z + beta d``."""
    fd, fz = d.ravel(), z.ravel()
    for i in range(fd.size):
        fd[i] = fz[i] + beta * fd[i]


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
    if system.partial is not None:
        A = (A + _partial_matrix(system.partial, index)).tocsr()
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


def _partial_matrix(faces: PartialFaces, index: np.ndarray):
    """The change ``(w - 1)`` per partial face makes to the unweighted Laplacian, sparse."""
    import scipy.sparse as sp

    n = int(index.max()) + 1
    rows, cols, vals = [], [], []
    shape = np.array(index.shape)

    def row(cell):  # -1 for a ghost
        inside = np.all((cell >= 0) & (cell < shape))
        return int(index[tuple(cell)]) if inside else -1

    for lo, hi, w in zip(faces.below, faces.above, faces.weight, strict=True):
        a, b = row(np.asarray(lo)), row(np.asarray(hi))
        for this, other in ((a, b), (b, a)):
            if this < 0:
                continue
            rows.append(this), cols.append(this), vals.append(w - 1.0)
            if other >= 0:
                rows.append(this), cols.append(other), vals.append(1.0 - w)
    return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
