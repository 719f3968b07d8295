"""Semi-Lagrangian and BFECC advection on the MAC grid (paper §3.1).

The fluid carries its own velocity (and any passive field) along: each sample
takes the value found where the fluid came from a step ago. ``semi_lagrangian``
traces that departure point back with a midpoint (RK2) step and interpolates
linearly there: unconditionally stable and first order. ``bfecc`` runs it back
and forth to estimate and cancel its own error (Kim, Liu, Llamas and Rossignac,
"Advections with Significantly Reduced Dissipation and Diffusion", 2007),
which makes it second order where the field is smooth; a limiter keeps it from
creating new extrema where it is not.

A field's staggering follows from its shape: ``grid.shape`` is cell-centred,
``grid.face_shape(a)`` lives on the faces normal to axis ``a``. Beyond the grid
each field is extended by its outermost samples (zero gradient). Schemes share
one signature, ``scheme(grid, carrier, fields, dt) -> tuple``, so a caller picks
one by passing the function (``advect_velocity(..., scheme=semi_lagrangian)``).

Still water: where the carrier at a sample moves it less than ``STILL`` cells a
step along every axis, its departure point is traced by one Euler step, the
carrier at the sample (a mean of face values), rather than by the midpoint
rule, whose midpoint needs a full interpolation of the carrier. The two
differ by ``dt (u(x) - u(midpoint))``, the midpoint being less than
``STILL / 2`` cells away: at most ``STILL / 2`` times the carrier's change
over a cell in one step's travel (``dt |grad u|``, below the Courant number),
so under ``STILL / 2`` cells wherever the step is stable. Most of a
swimmer's grid is such water (90 % of the fish's faces move under 1e-3
cells a step after 2 s); tracing it cheaply halves the fish's advection
(17.1 -> 8.5 ms a step, ``aquagait bench swim --compare-still``), and its
2-s swim ends within 1e-9 m of the same place. ``still=0`` traces every
sample at second order.

Precision: float32 fields (``EulerFluid(dtype=np.float32)``) are advected in
float32, by the same kernels compiled for that type, when the carrier and
every field are float32; anything else is advected in float64. Departure
points are float64 either way (in float32 the trace was slower and less
exact: ``benchmarks/precision.py``).
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable, Sequence

import numpy as np

from aquagait.fluid import _interp
from aquagait.grid import Grid, Velocity

STILL = 1e-3
"""Samples that the carrier moves less than this many cells a step along every axis
are traced by one Euler step (module docstring, "Still water")."""

Fields = tuple[np.ndarray, ...]
Scheme = Callable[[Grid, Velocity, Sequence[np.ndarray], float], Fields]


def semi_lagrangian(
    grid: Grid,
    carrier: Velocity,
    fields: Sequence[np.ndarray],
    dt: float,
    first_order=None,
    still: float = STILL,
) -> Fields:
    """Advect each field by the carrier over ``dt``: RK2 back-trace, linear interpolation.

    Paper §3.1 (Stam 1999's semi-Lagrangian scheme with a midpoint trace).

    Args:
        grid: the MAC grid.
        carrier: face velocities that move the fields, ``carrier[a].shape ==
            grid.face_shape(a)`` [m/s].
        fields: arrays to advect, each cell-centred (``grid.shape``) or a face
            component (``grid.face_shape(a)``) [any unit].
        dt: time step [s]; a negative step traces forward (used by BFECC).
        first_order: ignored (every sample is first order here); accepted so
            that the schemes are interchangeable (``bfecc``).
        still: samples the carrier moves less than this many cells along every
            axis are traced by one Euler step (module docstring, "Still
            water"); 0 traces all at second order.
    Returns:
        new arrays, one per field, same shapes and units; float32 when the
        carrier and every field are, else float64.
    Raises:
        ValueError: malformed carrier or field, non-finite ``dt``;
            ``grid.CFLError`` when ``|dt|`` carries fluid beyond the hard CFL limit.
    """
    carrier, fields = _checked(grid, carrier, fields, dt)
    if dt == 0:
        return tuple(f.copy() for f in fields)
    out = [None] * len(fields)
    for shape, members in _by_shape(fields).items():  # one trace per staggering
        ahead, _ = _trace(grid, carrier, shape, dt, both=False, still=still)
        for n in members:
            out[n] = _run("gather", None, fields[n], *ahead, np.empty(shape, fields[n].dtype))
    return tuple(out)


def bfecc(
    grid: Grid,
    carrier: Velocity,
    fields: Sequence[np.ndarray],
    dt: float,
    limit: bool = True,
    first_order: Sequence[np.ndarray] | None = None,
    still: float = STILL,
) -> Fields:
    """Advect each field by the carrier over ``dt`` with BFECC error correction.

    Back and Forth Error Compensation and Correction (Kim et al. 2007), paper §3.1:
    ``phi1 = SL(phi, dt)``, ``phi2 = SL(phi1, -dt)``, ``phi~ = phi + (phi - phi2)/2``,
    result ``SL(phi~, dt)``. The first and last passes share their departure
    points. The limiter clamps each result to the range of the original ``phi``
    over the 2^d interpolation nodes at its departure point, so no new extrema
    appear at discontinuities (Selle et al. 2008).

    Args:
        grid, carrier, fields, dt: as for ``semi_lagrangian``.
        limit: apply the extremum limiter (turn off only to study the scheme).
        first_order: optional boolean masks, one per field and of its shape:
            where True, the result is the first pass, ``phi1`` (semi-Lagrangian;
            no cost). Next to a moving body, whose faces carry the body's
            velocity rather than an advected one, the correction made the
            distance swum depend on the step (``aquagait.sim.EulerFluid.near_body``).
        still: as for ``semi_lagrangian``; both traces (over ``dt`` and ``-dt``)
            of a sample in still water are Euler steps.
    Returns:
        new arrays, one per field, same shapes, units and precision as for
        ``semi_lagrangian``.
    Raises:
        ValueError, grid.CFLError: as for ``semi_lagrangian``.
    """
    return _bfecc(grid, carrier, fields, dt, limit, None, first_order, still)


def bfecc_previous(
    grid: Grid,
    carrier: Velocity,
    fields: Sequence[np.ndarray],
    dt: float,
    limit: bool = True,
    first_order: Sequence[np.ndarray] | None = None,
    still: float = STILL,
) -> Fields:
    """``bfecc`` as compiled before issue 10: the same numbers to round-off, slower.

    Its kernels clamp coordinates with branches and convert them with
    unsigned integers (``_interp``, ``branching=True``); ``bfecc`` does both
    without branches. Kept so that ``aquagait bench swim --compare-advection``
    times the two in one run (``EulerFluid(advect=bfecc_previous)``).
    """
    return _bfecc(grid, carrier, fields, dt, limit, True, first_order, still)


def _bfecc(grid, carrier, fields, dt, limit, branching, first_order=None, still=0.0):
    """``bfecc``, with the kernels' clamping chosen by ``branching`` (None or True)."""
    carrier, fields = _checked(grid, carrier, fields, dt)
    if first_order is not None and [np.shape(m) for m in first_order] != [f.shape for f in fields]:
        raise ValueError("first_order must hold one boolean mask per field, of the field's shape")
    if dt == 0:
        return tuple(f.copy() for f in fields)
    out = [None] * len(fields)
    for shape, members in _by_shape(fields).items():
        ahead, back = _trace(grid, carrier, shape, dt, True, branching, still)
        phi1, phi_tilde = _scratch(shape, 2, "fields", fields[members[0]].dtype)
        for n in members:
            phi = fields[n]
            _run("gather", branching, phi, *ahead, phi1)
            _run("compensate", branching, phi, phi1, *back, phi_tilde)
            final = np.empty(shape, phi.dtype)
            if limit:
                out[n] = _run("limited_gather", branching, phi_tilde, phi, *ahead, final)
            else:
                out[n] = _run("gather", branching, phi_tilde, *ahead, final)
            if first_order is not None:
                np.copyto(out[n], phi1, where=first_order[n])
    return tuple(out)


def advect_velocity(
    grid: Grid, velocity: Velocity, dt: float, scheme: Scheme = bfecc, first_order=None
) -> Velocity:
    """Self-advection of the face velocity field, the first phase of a fluid step (§3.1).

    Args:
        grid: the MAC grid.
        velocity: face velocities, ``velocity[a].shape == grid.face_shape(a)`` [m/s].
        dt: time step [s].
        scheme: ``bfecc`` (default) or ``semi_lagrangian``, or any function
            with their signature.
        first_order: optional boolean masks, one per component: faces advected
            at first order (``bfecc``); passed to the scheme only when given.
    Returns:
        the advected face velocities [m/s], new arrays.
    """
    if first_order is None:
        return tuple(scheme(grid, velocity, velocity, dt))
    return tuple(scheme(grid, velocity, velocity, dt, first_order=first_order))


def _trace(grid: Grid, carrier: Velocity, shape: tuple[int, ...], dt: float, both: bool,
           branching=None, still: float = 0.0):  # fmt: skip
    """Departure points over ``dt`` (and over ``-dt`` if ``both``) of a field of ``shape``,
    samples in still water (``still`` cells a step) traced by one Euler step.

    Returns:
        ``(ahead, back)``: tuples of field-shaped scratch arrays of clamped field
        coordinates, one per axis; ``back`` is ``None`` unless ``both``.
    """
    if not still >= 0 or not math.isfinite(still):
        raise ValueError(f"still must be a finite number of cells >= 0, got {still!r}")
    offsets = [0.0 if n == m + 1 else 0.5 for n, m in zip(shape, grid.shape, strict=True)]
    points = _scratch(shape, 2 * len(shape) if both else len(shape), "points", np.float64)
    ahead, back = tuple(points[: len(shape)]), tuple(points[len(shape) :]) or None
    skip = (None,) * len(shape)
    (moving,) = _scratch(shape, 1, "moving", np.bool_)
    dt_h = dt / grid.cell_size
    _run("departure", branching, *carrier, *offsets, dt_h, float(still), *ahead, *(back or skip),
         moving)  # fmt: skip
    return ahead, back


def _by_shape(fields) -> dict[tuple[int, ...], list[int]]:
    """Indices of the fields, grouped by shape (that is, by staggering)."""
    groups: dict[tuple[int, ...], list[int]] = {}
    for n, phi in enumerate(fields):
        groups.setdefault(phi.shape, []).append(n)
    return groups


_workspace = threading.local()


def _scratch(shape: tuple[int, ...], count: int, role: str, dtype) -> list[np.ndarray]:
    """``count`` scratch arrays of ``shape`` and ``dtype`` for ``role`` ("points",
    "fields" or "moving"), reused between calls.

    Fresh memory costs a page fault per 4 KiB on first touch, which made up a
    fifth of a BFECC step; this thread's scratch buffers (one per role and
    dtype, so that points and fields never overlap) are kept and grown instead.
    """
    size, dtype = int(np.prod(shape)), np.dtype(dtype)
    stride = size + _STAGGER // dtype.itemsize
    buffers = _workspace.__dict__.setdefault("buffers", {})
    buffer = buffers.get((role, dtype))
    if buffer is None or buffer.size < count * stride:
        buffer = buffers[(role, dtype)] = np.empty(max(count, 6) * stride, dtype)
    return [buffer[n * stride : n * stride + size].reshape(shape) for n in range(count)]


_STAGGER = 576
"""Bytes between one scratch array's end and the next's start. Arrays whose starts
lie a whole number of 4 KiB pages apart (a 64x32x32 grid's faces are 130 pages)
and are written in step alias in the CPU's store buffer and cache sets: the
fish's traces ran 1.5-2.5x slower than into separate arrays. 576 = 9 cache lines
puts six arrays' starts at distinct lines of a page."""


def _run(kernel: str, branching, *args):
    """Call the 2D or 3D version of an ``_interp`` kernel, by the rank of its first array.

    ``branching``: None for the branch-free kernels, True for the previous ones.
    """
    getattr(_interp, f"{kernel}_{args[0].ndim}d")(branching, *args)
    return args[-1]


def _checked(grid: Grid, carrier: Velocity, fields, dt: float):
    """Validate the inputs; return them as C arrays of one precision: float32 if all of
    them are, else float64."""
    grid.check_velocity(carrier, "carrier")
    if isinstance(fields, np.ndarray):
        raise ValueError("fields must be a sequence of arrays; wrap a single field as (phi,)")
    allowed = [grid.shape] + [grid.face_shape(a) for a in range(grid.dim)]
    for n, phi in enumerate(fields):
        if np.shape(phi) not in allowed:
            raise ValueError(
                f"fields[{n}] has shape {np.shape(phi)}, but a field on a grid of "
                f"{grid.shape} cells is cell-centred, shape {grid.shape}, or a face "
                f"component, shape {' or '.join(map(str, allowed[1:]))}"
            )
    if dt != 0:
        grid.check_dt(carrier, abs(dt))
    single = all(np.asarray(a).dtype == np.float32 for a in (*carrier, *fields))
    dtype = np.float32 if single else np.float64
    as_dtype = lambda a: np.ascontiguousarray(a, dtype=dtype)  # noqa: E731
    return tuple(map(as_dtype, carrier)), tuple(map(as_dtype, fields))
