"""Numba kernels for advection: back-tracing and clamped linear interpolation.

Positions inside a kernel are in *grid units*, ``(world - origin) / h``: the
lower corner of the grid is 0 and cell ``i`` spans ``[i, i + 1)``. A field whose
samples sit at offset ``o`` (0 on a face axis, 1/2 on a cell-centred one) has
*field coordinates* ``grid_units - o``: sample ``i`` is at field coordinate ``i``.
Interpolation clamps a field coordinate into ``[0, n - 1]``, which extends the
field by its outermost samples (zero gradient).

The kernels are serial, take float64 C arrays and write into their trailing
arguments. Their first argument, ``branching``, picks how coordinates are
clamped, by its type (Numba compiles one version per type and drops the
other branch): None, branch-free (``min``/``max`` and signed conversions),
or True, the branches and unsigned conversions of the code before issue 10,
kept as a reference for the benchmark. Both give the same numbers to
round-off (the two compiled versions of a kernel may fuse different
multiplies and adds: a last bit or two); the branch-free traces are 1.6x
faster (fish, 64x32x32, one core), the branches and unsigned conversions are
the cost. What else makes them fast (each measured): still water traced by
one Euler step (``aquagait.fluid.advection``, "Still water"); the first RK2
stage, the carrier at a sample, is a mean of 1 to 4 face values rather than a general
interpolation, and the forward and backward traces of BFECC share it; flat
arrays are indexed with unsigned integers, which spares Numba's negative-index
wraparound on every load. Interpolation is written ``a + f (b - a)`` so that a
constant field comes back bit for bit. Kernels that call one another live in
this one file: Numba's on-disk cache of a caller is not invalidated when a
callee in another module changes.
"""

from __future__ import annotations

from numba import int64, njit, uint64

_FAST = {"contract"}  # fused multiply-add; changes nothing but round-off


@njit(cache=True, inline="always")
def _base(x, n, branching):
    """Lower node (unsigned, in ``[0, n-2]``) and weight of coordinate ``x`` on ``n`` samples.

    Branch-free when ``branching`` is None: clamp, then a signed conversion
    (one instruction each way, where the unsigned ones are sequences), the
    node capped at ``n-2`` so that the last sample gets weight exactly 1.
    The same weights as the branching form, 1.6x faster traces.
    """
    if branching is None:
        x = min(max(x, 0.0), float(n - 1))
        i = min(int64(x), n - 2)
        return uint64(i), x - float(i)
    if x <= 0.0:
        return uint64(0), 0.0
    if x >= n - 1:
        return uint64(n - 2), 1.0
    i = uint64(x)
    return i, x - float(i)


@njit(cache=True, inline="always")
def _clamp(x, n, branching):
    """``x`` clamped into the sample range ``[0, n-1]`` of an axis with ``n`` samples."""
    if branching is None:
        return min(max(x, 0.0), float(n - 1))
    if x <= 0.0:
        return 0.0
    if x >= n - 1:
        return float(n - 1)
    return x


@njit(cache=True, inline="always", fastmath=_FAST)
def _bilerp(a, b, sx, fx, fy):
    """Bilinear blend of flat ``a`` from lower node ``b``, row stride ``sx``, weights ``fx, fy``."""
    one = uint64(1)
    lo = a[b] + fy * (a[b + one] - a[b])
    b += sx
    hi = a[b] + fy * (a[b + one] - a[b])
    return lo + fx * (hi - lo)


@njit(cache=True, inline="always", fastmath=_FAST)
def _trilerp(a, b, sx, sy, fx, fy, fz):
    """Trilinear blend of flat ``a`` from lower node ``b``, strides ``sx, sy, 1``."""
    one = uint64(1)
    c = b + sy
    a00 = a[b] + fz * (a[b + one] - a[b])
    a01 = a[c] + fz * (a[c + one] - a[c])
    b += sx
    c += sx
    a10 = a[b] + fz * (a[b + one] - a[b])
    a11 = a[c] + fz * (a[c + one] - a[c])
    lo = a00 + fy * (a01 - a00)
    hi = a10 + fy * (a11 - a10)
    return lo + fx * (hi - lo)


@njit(cache=True, inline="always", fastmath=_FAST)
def _interp_2d(a, n0, n1, x, y, branching):
    """Bilinear interpolation of flat ``a`` (shape ``(n0, n1)``) at field coords ``(x, y)``."""
    i, fx = _base(x, n0, branching)
    j, fy = _base(y, n1, branching)
    sx = uint64(n1)
    return _bilerp(a, i * sx + j, sx, fx, fy)


@njit(cache=True, inline="always", fastmath=_FAST)
def _interp_3d(a, n0, n1, n2, x, y, z, branching):
    """Trilinear interpolation of flat ``a`` (shape ``(n0, n1, n2)``) at ``(x, y, z)``."""
    i, fx = _base(x, n0, branching)
    j, fy = _base(y, n1, branching)
    k, fz = _base(z, n2, branching)
    sx, sy = uint64(n1 * n2), uint64(n2)
    return _trilerp(a, i * sx + j * sy + k, sx, sy, fx, fy, fz)


@njit(cache=True, inline="always")
def _at_sample_2d(u, v, i, j, face):
    """Carrier at sample ``(i, j)`` of a field on faces normal to axis ``face`` (-1: cells).

    The sample sits on a face node or half-way between two, so the carrier
    there is a mean of 1, 2 or 4 face values (clamped at the edges), summed
    pairwise so that a constant comes back exactly.
    """
    nx, ny = v.shape[0], u.shape[1]
    if face == 0:
        i0, i1 = max(i - 1, 0), min(i, nx - 1)
        return u[i, j], 0.25 * ((v[i0, j] + v[i0, j + 1]) + (v[i1, j] + v[i1, j + 1]))
    if face == 1:
        j0, j1 = max(j - 1, 0), min(j, ny - 1)
        return 0.25 * ((u[i, j0] + u[i + 1, j0]) + (u[i, j1] + u[i + 1, j1])), v[i, j]
    return 0.5 * (u[i, j] + u[i + 1, j]), 0.5 * (v[i, j] + v[i, j + 1])


@njit(cache=True, inline="always")
def _at_sample_3d(u, v, w, i, j, k, face):
    """Carrier at sample ``(i, j, k)`` of a field on faces normal to ``face``; see the 2D one."""
    nx, ny, nz = v.shape[0], u.shape[1], u.shape[2]
    if face == 0:
        i0, i1 = max(i - 1, 0), min(i, nx - 1)
        return (
            u[i, j, k],
            0.25 * ((v[i0, j, k] + v[i0, j + 1, k]) + (v[i1, j, k] + v[i1, j + 1, k])),
            0.25 * ((w[i0, j, k] + w[i0, j, k + 1]) + (w[i1, j, k] + w[i1, j, k + 1])),
        )
    if face == 1:
        j0, j1 = max(j - 1, 0), min(j, ny - 1)
        return (
            0.25 * ((u[i, j0, k] + u[i + 1, j0, k]) + (u[i, j1, k] + u[i + 1, j1, k])),
            v[i, j, k],
            0.25 * ((w[i, j0, k] + w[i, j0, k + 1]) + (w[i, j1, k] + w[i, j1, k + 1])),
        )
    if face == 2:
        k0, k1 = max(k - 1, 0), min(k, nz - 1)
        return (
            0.25 * ((u[i, j, k0] + u[i + 1, j, k0]) + (u[i, j, k1] + u[i + 1, j, k1])),
            0.25 * ((v[i, j, k0] + v[i, j + 1, k0]) + (v[i, j, k1] + v[i, j + 1, k1])),
            w[i, j, k],
        )
    return (
        0.5 * (u[i, j, k] + u[i + 1, j, k]),
        0.5 * (v[i, j, k] + v[i, j + 1, k]),
        0.5 * (w[i, j, k] + w[i, j, k + 1]),
    )


@njit(cache=True, inline="always", fastmath=_FAST)
def _velocity_2d(u, v, nx, ny, x, y, branching):
    """Carrier ``(u, v)`` (flat) at grid-unit point ``(x, y)`` [m/s]."""
    return (
        _interp_2d(u, nx + 1, ny, x, y - 0.5, branching),
        _interp_2d(v, nx, ny + 1, x - 0.5, y, branching),
    )


@njit(cache=True, inline="always", fastmath=_FAST)
def _velocity_3d(u, v, w, nx, ny, nz, x, y, z, branching):
    """Carrier ``(u, v, w)`` (flat) at grid-unit point ``(x, y, z)`` [m/s]."""
    return (
        _interp_3d(u, nx + 1, ny, nz, x, y - 0.5, z - 0.5, branching),
        _interp_3d(v, nx, ny + 1, nz, x - 0.5, y, z - 0.5, branching),
        _interp_3d(w, nx, ny, nz + 1, x - 0.5, y - 0.5, z, branching),
    )


@njit(cache=True, fastmath=_FAST, nogil=True)
def departure_2d(branching, u2, v2, ox, oy, dt_h, still, px, py, qx, qy, moving):
    """RK2 (midpoint) back-trace from every sample of a 2D field, over ``dt`` and ``-dt``.

    Two passes: every sample by one Euler step, the carrier at the sample (no
    interpolation, so the loop vectorizes), then the samples the carrier moves
    ``still`` cells or more again, by the midpoint rule.

    Args:
        u2, v2: carrier face velocities, shapes ``(nx+1, ny)``, ``(nx, ny+1)`` [m/s].
        ox, oy: the field's sample offsets in cells (0 on its face axis, 0.5 otherwise).
        dt_h: time step over cell size, ``dt / h`` [s/m].
        still: where the carrier at a sample moves it less than this many cells
            along every axis, the trace stays the single Euler step; 0 traces
            every sample by the midpoint rule.
        px, py: out, field-shaped: departure points over ``dt``, clamped field coordinates.
        qx, qy: out, the same over ``-dt`` (where fluid goes), or ``None`` to skip.
        moving: scratch, field-shaped booleans: the samples traced by the midpoint rule.
    """
    nx, ny = v2.shape[0], u2.shape[1]
    u, v = u2.ravel(), v2.ravel()
    mx, my = px.shape
    face = 0 if ox == 0.0 else 1 if oy == 0.0 else -1
    for i in range(mx):
        x = i + ox
        for j in range(my):
            y = j + oy
            ux, uy = _at_sample_2d(u2, v2, i, j, face)
            moving[i, j] = max(abs(ux), abs(uy)) * dt_h >= still
            px[i, j] = _clamp(x - dt_h * ux - ox, mx, branching)
            py[i, j] = _clamp(y - dt_h * uy - oy, my, branching)
            if qx is not None:
                qx[i, j] = _clamp(x + dt_h * ux - ox, mx, branching)
                qy[i, j] = _clamp(y + dt_h * uy - oy, my, branching)
    s = 0.5 * dt_h
    for i in range(mx):
        x = i + ox
        for j in range(my):
            if not moving[i, j]:
                continue
            y = j + oy
            ux, uy = _at_sample_2d(u2, v2, i, j, face)
            vx, vy = _velocity_2d(u, v, nx, ny, x - s * ux, y - s * uy, branching)
            px[i, j] = _clamp(x - dt_h * vx - ox, mx, branching)
            py[i, j] = _clamp(y - dt_h * vy - oy, my, branching)
            if qx is not None:
                vx, vy = _velocity_2d(u, v, nx, ny, x + s * ux, y + s * uy, branching)
                qx[i, j] = _clamp(x + dt_h * vx - ox, mx, branching)
                qy[i, j] = _clamp(y + dt_h * vy - oy, my, branching)


@njit(cache=True, fastmath=_FAST, nogil=True)
def departure_3d(branching, u3, v3, w3, ox, oy, oz, dt_h, still, px, py, pz, qx, qy, qz, moving):
    """RK2 (midpoint) back-trace from every sample of a 3D field; see ``departure_2d``."""
    nx, ny, nz = v3.shape[0], u3.shape[1], u3.shape[2]
    u, v, w = u3.ravel(), v3.ravel(), w3.ravel()
    mx, my, mz = px.shape
    face = 0 if ox == 0.0 else 1 if oy == 0.0 else 2 if oz == 0.0 else -1
    for i in range(mx):
        x = i + ox
        for j in range(my):
            y = j + oy
            for k in range(mz):
                z = k + oz
                ux, uy, uz = _at_sample_3d(u3, v3, w3, i, j, k, face)
                moving[i, j, k] = max(max(abs(ux), abs(uy)), abs(uz)) * dt_h >= still
                px[i, j, k] = _clamp(x - dt_h * ux - ox, mx, branching)
                py[i, j, k] = _clamp(y - dt_h * uy - oy, my, branching)
                pz[i, j, k] = _clamp(z - dt_h * uz - oz, mz, branching)
                if qx is not None:
                    qx[i, j, k] = _clamp(x + dt_h * ux - ox, mx, branching)
                    qy[i, j, k] = _clamp(y + dt_h * uy - oy, my, branching)
                    qz[i, j, k] = _clamp(z + dt_h * uz - oz, mz, branching)
    s = 0.5 * dt_h
    for i in range(mx):
        x = i + ox
        for j in range(my):
            y = j + oy
            for k in range(mz):
                if not moving[i, j, k]:
                    continue
                z = k + oz
                ux, uy, uz = _at_sample_3d(u3, v3, w3, i, j, k, face)
                vx, vy, vz = _velocity_3d(
                    u, v, w, nx, ny, nz, x - s * ux, y - s * uy, z - s * uz, branching
                )
                px[i, j, k] = _clamp(x - dt_h * vx - ox, mx, branching)
                py[i, j, k] = _clamp(y - dt_h * vy - oy, my, branching)
                pz[i, j, k] = _clamp(z - dt_h * vz - oz, mz, branching)
                if qx is not None:
                    vx, vy, vz = _velocity_3d(
                        u, v, w, nx, ny, nz, x + s * ux, y + s * uy, z + s * uz, branching
                    )
                    qx[i, j, k] = _clamp(x + dt_h * vx - ox, mx, branching)
                    qy[i, j, k] = _clamp(y + dt_h * vy - oy, my, branching)
                    qz[i, j, k] = _clamp(z + dt_h * vz - oz, mz, branching)


@njit(cache=True, fastmath=_FAST, nogil=True)
def gather_2d(branching, phi2, px, py, out):
    """``out = phi`` interpolated bilinearly at field coordinates ``(px, py)``."""
    n0, n1 = phi2.shape
    phi, x, y, o = phi2.ravel(), px.ravel(), py.ravel(), out.ravel()
    for b in range(o.size):
        o[b] = _interp_2d(phi, n0, n1, x[b], y[b], branching)


@njit(cache=True, fastmath=_FAST, nogil=True)
def gather_3d(branching, phi3, px, py, pz, out):
    """``out = phi`` interpolated trilinearly at field coordinates ``(px, py, pz)``."""
    n0, n1, n2 = phi3.shape
    phi, x, y, z, o = phi3.ravel(), px.ravel(), py.ravel(), pz.ravel(), out.ravel()
    for b in range(o.size):
        o[b] = _interp_3d(phi, n0, n1, n2, x[b], y[b], z[b], branching)


@njit(cache=True, fastmath=_FAST, nogil=True)
def compensate_2d(branching, phi2, phi1_2, qx, qy, out):
    """BFECC's middle pass: ``out = phi + (phi - phi1(q)) / 2``, ``phi1`` interpolated at ``q``."""
    n0, n1 = phi2.shape
    phi, phi1, x, y, o = phi2.ravel(), phi1_2.ravel(), qx.ravel(), qy.ravel(), out.ravel()
    for b in range(o.size):
        o[b] = phi[b] + 0.5 * (phi[b] - _interp_2d(phi1, n0, n1, x[b], y[b], branching))


@njit(cache=True, fastmath=_FAST, nogil=True)
def compensate_3d(branching, phi3, phi1_3, qx, qy, qz, out):
    """BFECC's middle pass in 3D; see ``compensate_2d``."""
    n0, n1, n2 = phi3.shape
    phi, phi1, o = phi3.ravel(), phi1_3.ravel(), out.ravel()
    x, y, z = qx.ravel(), qy.ravel(), qz.ravel()
    for b in range(o.size):
        o[b] = phi[b] + 0.5 * (phi[b] - _interp_3d(phi1, n0, n1, n2, x[b], y[b], z[b], branching))


@njit(cache=True, fastmath=_FAST, nogil=True)
def limited_gather_2d(branching, phi_tilde2, phi2, px, py, out):
    """Interpolate ``phi_tilde`` at ``(px, py)``, clamped to the range of ``phi`` on the 4 nodes."""
    n0, n1 = phi2.shape
    pt, phi, x, y, o = phi_tilde2.ravel(), phi2.ravel(), px.ravel(), py.ravel(), out.ravel()
    one, sx = uint64(1), uint64(n1)
    for n in range(o.size):
        i, fx = _base(x[n], n0, branching)
        j, fy = _base(y[n], n1, branching)
        b = i * sx + j
        c = b + sx
        p0, p1, p2, p3 = phi[b], phi[b + one], phi[c], phi[c + one]
        lo = min(min(p0, p1), min(p2, p3))
        hi = max(max(p0, p1), max(p2, p3))
        o[n] = min(max(_bilerp(pt, b, sx, fx, fy), lo), hi)


@njit(cache=True, fastmath=_FAST, nogil=True)
def limited_gather_3d(branching, phi_tilde3, phi3, px, py, pz, out):
    """Interpolate ``phi_tilde`` at ``(px, py, pz)``, clamped to ``phi``'s range on the 8 nodes."""
    n0, n1, n2 = phi3.shape
    pt, phi, o = phi_tilde3.ravel(), phi3.ravel(), out.ravel()
    x, y, z = px.ravel(), py.ravel(), pz.ravel()
    one, sx, sy = uint64(1), uint64(n1 * n2), uint64(n2)
    for n in range(o.size):
        i, fx = _base(x[n], n0, branching)
        j, fy = _base(y[n], n1, branching)
        k, fz = _base(z[n], n2, branching)
        b = i * sx + j * sy + k
        c, d = b + sy, b + sx
        e = d + sy
        p0, p1, p2, p3 = phi[b], phi[b + one], phi[c], phi[c + one]
        p4, p5, p6, p7 = phi[d], phi[d + one], phi[e], phi[e + one]
        lo = min(min(min(p0, p1), min(p2, p3)), min(min(p4, p5), min(p6, p7)))
        hi = max(max(max(p0, p1), max(p2, p3)), max(max(p4, p5), max(p6, p7)))
        o[n] = min(max(_trilerp(pt, b, sx, sy, fx, fy, fz), lo), hi)
