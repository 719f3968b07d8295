"""MAC grid geometry: shapes, coordinates, index maths, the CFL time step, flood fills.

The grid is the lowest layer of aquagait and imports nothing of its own
(docs/development.md, "Layers"). It knows where things are, not what they do.

Layout (Harlow & Welch's marker-and-cell grid, paper §3.1):

- pressure and every cell quantity at cell centres, array shape ``shape``;
- velocity component ``a`` on the faces normal to axis ``a``, array shape
  ``shape`` with one more entry along ``a`` (``face_shape(a)``).

Cell ``(i, j[, k])`` has its centre at ``origin + (i + 1/2, j + 1/2[, k + 1/2]) h``;
face ``i`` along axis 0 sits at ``origin[0] + i h``. A velocity field is a tuple
of one float64 array per axis, ``(u, v)`` in 2D and ``(u, v, w)`` in 3D.

Flood fills work on 3D arrays; a 2D grid is one layer along z, ``(nx, ny, 1)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numba
import numpy as np

Velocity = tuple[np.ndarray, ...]
"""Face velocities, one array per axis: ``velocity[a].shape == grid.face_shape(a)`` [m/s]."""

DEFAULT_CFL = 1.0
"""Default Courant number: the fastest fluid moves at most one cell per step."""

CFL_HARD_LIMIT = 5.0
"""A step that moves fluid more than this many cells is refused outright."""


class CFLError(ValueError):
    """A time step is far beyond the CFL limit of the grid."""


@dataclass(frozen=True)
class Grid:
    """A uniform MAC grid in 2D or 3D.

    Attributes:
        shape: cells per axis, ``(nx, ny)`` or ``(nx, ny, nz)``.
        cell_size: edge length ``h`` of a (square or cubic) cell [m].
        origin: world position of the grid's lower corner, one entry per axis [m].
    """

    shape: tuple[int, ...]
    cell_size: float
    origin: tuple[float, ...] = field(default=None)  # type: ignore[assignment]

    def __post_init__(self):
        shape = tuple(self.shape)
        if len(shape) not in (2, 3):
            raise ValueError(f"grid shape must have 2 or 3 entries (nx, ny[, nz]), got {shape!r}")
        if any(int(n) != n or n < 2 for n in shape):
            raise ValueError(
                f"grid shape needs whole numbers of cells >= 2 per axis, got {shape!r}"
            )
        if not np.isfinite(self.cell_size) or self.cell_size <= 0:
            raise ValueError(
                f"cell_size must be a positive length in metres, got {self.cell_size!r}"
            )
        origin = (0.0,) * len(shape) if self.origin is None else tuple(map(float, self.origin))
        if len(origin) != len(shape):
            raise ValueError(
                f"origin has {len(origin)} entries but the grid is {len(shape)}D: give one per axis"
            )
        object.__setattr__(self, "shape", tuple(int(n) for n in shape))
        object.__setattr__(self, "cell_size", float(self.cell_size))
        object.__setattr__(self, "origin", origin)

    @property
    def dim(self) -> int:
        """Number of spatial dimensions, 2 or 3."""
        return len(self.shape)

    @property
    def cell_count(self) -> int:
        """Total number of cells."""
        return int(np.prod(self.shape))

    @property
    def extent(self) -> tuple[float, ...]:
        """Size of the domain along each axis [m]."""
        return tuple(n * self.cell_size for n in self.shape)

    @property
    def cell_volume(self) -> float:
        """``h^dim``: volume of a cell in 3D, area of a cell in 2D (per unit depth)."""
        return self.cell_size**self.dim

    def face_shape(self, axis: int) -> tuple[int, ...]:
        """Array shape of the velocity component normal to ``axis``."""
        shape = list(self.shape)
        shape[axis] += 1
        return tuple(shape)

    def zeros_velocity(self, dtype=np.float64) -> Velocity:
        """Still fluid: a zero velocity field (float64, or ``dtype``)."""
        return tuple(np.zeros(self.face_shape(a), dtype=dtype) for a in range(self.dim))

    def zeros_cells(self, dtype=np.float64) -> np.ndarray:
        """A zero cell-centred field, shape ``shape``."""
        return np.zeros(self.shape, dtype=dtype)

    def cell_centers(self) -> tuple[np.ndarray, ...]:
        """World coordinates of cell centres, one ``shape`` array per axis [m]."""
        return self._points(0.5 * np.ones(self.dim), self.shape)

    def face_centers(self, axis: int) -> tuple[np.ndarray, ...]:
        """World coordinates of the centres of faces normal to ``axis`` [m]."""
        offset = 0.5 * np.ones(self.dim)
        offset[axis] = 0.0
        return self._points(offset, self.face_shape(axis))

    def _points(self, offset, shape) -> tuple[np.ndarray, ...]:
        axes = [
            self.origin[a] + (np.arange(shape[a]) + offset[a]) * self.cell_size
            for a in range(self.dim)
        ]
        return tuple(np.meshgrid(*axes, indexing="ij"))

    def ball(self, center, radius: float) -> np.ndarray:
        """Boolean mask of the cells whose centres lie inside a disc (2D) or sphere (3D).

        Args:
            center: world position, one entry per axis [m].
            radius: [m].
        """
        centers = self.cell_centers()
        r2 = sum((x - c) ** 2 for x, c in zip(centers, center, strict=True))
        return r2 < radius**2

    def cell_of(self, point) -> tuple[int, ...]:
        """Index of the cell containing a world point (may lie outside the grid)."""
        rel = (np.asarray(point, dtype=float) - np.asarray(self.origin)) / self.cell_size
        return tuple(int(c) for c in np.floor(rel))

    def shifted(self, cells) -> Grid:
        """The same grid moved by whole cells (``cells[a]`` along axis ``a``)."""
        cells = tuple(int(c) for c in cells)
        if len(cells) != self.dim:
            raise ValueError(f"a {self.dim}D grid shifts by {self.dim} whole cells, got {cells!r}")
        origin = tuple(o + c * self.cell_size for o, c in zip(self.origin, cells, strict=True))
        return Grid(self.shape, self.cell_size, origin)

    def check_velocity(self, velocity: Velocity, name: str = "velocity") -> None:
        """Raise ``ValueError`` unless ``velocity`` is a face field of this grid."""
        if len(velocity) != self.dim:
            raise ValueError(
                f"{name} has {len(velocity)} components but the grid is {self.dim}D: "
                f"give one face array per axis"
            )
        for a, comp in enumerate(velocity):
            if np.shape(comp) != self.face_shape(a):
                raise ValueError(
                    f"{name}[{a}] has shape {np.shape(comp)}, but faces normal to axis {a} "
                    f"of a grid of {self.shape} cells need shape {self.face_shape(a)}"
                )

    def check_cells(self, field: np.ndarray, name: str) -> None:
        """Raise ``ValueError`` unless ``field`` is a cell-centred array of this grid."""
        if np.shape(field) != self.shape:
            raise ValueError(
                f"{name} has shape {np.shape(field)}, but this grid has {self.shape} cells"
            )

    def cfl_dt(self, velocity: Velocity, cfl: float = DEFAULT_CFL, max_dt: float = np.inf) -> float:
        """Largest step that moves the fastest face velocity ``cfl`` cells.

        Args:
            velocity: face velocities [m/s].
            cfl: Courant number, cells per step.
            max_dt: upper bound, returned for still fluid [s].
        Returns:
            the time step [s].
        """
        speed = max_speed(velocity)
        return min(max_dt, cfl * self.cell_size / speed) if speed > 0 else max_dt

    def check_dt(self, velocity: Velocity, dt: float, limit: float = CFL_HARD_LIMIT) -> None:
        """Refuse a step that carries fluid more than ``limit`` cells.

        Semi-Lagrangian advection stays stable beyond CFL 1, but far beyond it
        the back-trace jumps over whole features: that is a mistake, not a choice.
        """
        if not np.isfinite(dt) or dt <= 0:
            raise ValueError(f"dt must be a positive time in seconds, got {dt!r}")
        cells = max_speed(velocity) * dt / self.cell_size
        if cells > limit:
            raise CFLError(
                f"dt = {dt:.3g} s moves the fastest fluid {cells:.1f} cells per step, beyond "
                f"the limit of {limit:g}; use dt <= {self.cfl_dt(velocity):.3g} s "
                f"(grid.cfl_dt) or sub-step"
            )


def max_speed(velocity: Velocity) -> float:
    """Largest absolute face velocity component [m/s]."""
    return float(max(max(c.max(), -c.min()) for c in velocity))  # no |c| temporary


def sealed(solid: np.ndarray) -> np.ndarray:
    """Fluid cells that cannot reach the grid's border through fluid: sealed pockets.

    Fluid passes between cells that share a face (4 neighbours in 2D, 6 in
    3D), never across an edge or corner alone. A pocket has no open-boundary
    neighbour, so its block of the pressure Laplacian is singular
    (docs/method-coupling.md).

    Args:
        solid: boolean cell mask, ``grid.shape`` (2D or 3D).
    Returns:
        a new boolean mask of that shape, True at every sealed fluid cell.
    """
    solid = np.ascontiguousarray(solid, dtype=np.bool_)
    solid3 = solid.reshape(solid.shape + (1,) * (3 - solid.ndim))
    reached = np.zeros(solid3.shape, dtype=np.bool_)
    flood_from_border_(solid3, reached)
    reached |= solid3
    return ~reached.reshape(solid.shape)


@numba.njit(cache=True, nogil=True)
def flood_from_border_(solid, reached):
    """Set ``reached`` at every fluid cell joined to the array's border by fluid, in place.

    Args:
        solid: (nx, ny, nz) bool; ``nz == 1`` is a 2D grid, whose z faces are
            not border.
        reached: (nx, ny, nz) bool, all False on entry.
    """
    nx, ny, nz = solid.shape
    stack = np.empty((solid.size, 3), dtype=np.int64)  # each cell is pushed at most once
    top = 0
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                border = i == 0 or i == nx - 1 or j == 0 or j == ny - 1
                border = border or (nz > 1 and (k == 0 or k == nz - 1))
                if border and not solid[i, j, k]:
                    reached[i, j, k] = True
                    stack[top, 0], stack[top, 1], stack[top, 2] = i, j, k
                    top += 1
    steps = ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1))
    while top > 0:
        top -= 1
        i, j, k = stack[top, 0], stack[top, 1], stack[top, 2]
        for di, dj, dk in steps:
            a, b, c = i + di, j + dj, k + dk
            if 0 <= a < nx and 0 <= b < ny and 0 <= c < nz:
                if not solid[a, b, c] and not reached[a, b, c]:
                    reached[a, b, c] = True
                    stack[top, 0], stack[top, 1], stack[top, 2] = a, b, c
                    top += 1
