"""Numba kernels for advection: back-tracing and clamped linear interpolation.

Positions inside a kernel are in *grid units*, ``(world - origin) / h``: the
lower corner of the grid is 0 and cell ``i`` spans ``[i, i + 1)``. A field whose
samples sit at offset ``o`` (0 on a face axis, 1/2 on a cell-centred one) has
*field coordinates* ``grid_units - o``: sample ``i`` is at field coordinate ``i``.
Interpolation clamps a field coordinate into ``[0, n - 1]``, which extends the
field by its outermost samples (zero gradient).

The kernels are serial, take float64 C arrays and write into their trailing
arguments. They index flattened arrays with unsigned integers because that
spares Numba's negative-index wraparound on every load, and they interpolate
as ``a + f (b - a)`` so that a constant field comes back bit for bit. These two
choices and sharing the first RK2 stage between the forward and backward
traces roughly halve the cost of a BFECC step. All kernels that call one
another live in this one file: Numba's on-disk cache of a caller is not
invalidated when a callee in another module changes.
"""

from __future__ import annotations

from numba import njit, uint64

_FAST = {"contract"}  # fused multiply-add; changes nothing but round-off


@njit(cache=True, inline="always")
def _base(x, n):
    """Lower node (unsigned, in ``[0, n-2]``) and weight of coordinate ``x`` on ``n`` samples."""
    if x <= 0.0:
        return uint64(0), 0.0
    if x >= n - 1:
        return uint64(n - 2), 1.0
    i = uint64(x)
    return i, x - float(i)


@njit(cache=True, inline="always")
def _clamp(x, n):
    """``x`` clamped into the sample range ``[0, n-1]`` of an axis with ``n`` samples."""
    if x <= 0.0:
        return 0.0
    if x >= n - 1:
        return float(n - 1)
    return x


@njit(cache=True, inline="always", fastmath=_FAST)
def _interp_2d(a, n0, n1, x, y):
    """Bilinear interpolation of flat ``a`` (shape ``(n0, n1)``) at field coords ``(x, y)``."""
    i, fx = _base(x, n0)
    j, fy = _base(y, n1)
    sx = uint64(n1)
    b = i * sx + j
    lo = a[b] + fy * (a[b + uint64(1)] - a[b])
    b += sx
    hi = a[b] + fy * (a[b + uint64(1)] - a[b])
    return lo + fx * (hi - lo)


@njit(cache=True, inline="always", fastmath=_FAST)
def _interp_3d(a, n0, n1, n2, x, y, z):
    """Trilinear interpolation of flat ``a`` (shape ``(n0, n1, n2)``) at ``(x, y, z)``."""
    i, fx = _base(x, n0)
    j, fy = _base(y, n1)
    k, fz = _base(z, n2)
    one, sy, sx = uint64(1), uint64(n2), uint64(n1 * n2)
    b = i * sx + j * sy + k
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


@njit(cache=True, inline="always")
def _pair(i, on_face, n, own_axis):
    """The two nodes (maybe equal) a velocity component averages along one axis.

    At a sample ``i`` of a field (``on_face``: the field lives on faces of this
    axis), a velocity component that lives on faces of this axis (``own_axis``,
    ``n + 1`` samples) or is centred on it (``n`` samples) sits exactly on a node
    or half-way between two.
    """
    if own_axis:
        return (i, i) if on_face else (i, i + 1)
    return (max(i - 1, 0), min(i, n - 1)) if on_face else (i, i)


@njit(cache=True, inline="always")
def _box_2d(a, n1, x0, x1, y0, y1):
    """Mean of flat ``a`` (``n1`` columns) over nodes ``{x0, x1} x {y0, y1}``, exact if constant."""
    b = uint64(x0 * n1 + y0)
    ex, ey = uint64((x1 - x0) * n1), uint64(y1 - y0)
    return 0.25 * ((a[b] + a[b + ey]) + (a[b + ex] + a[b + ex + ey]))


@njit(cache=True, inline="always")
def _box_3d(a, n1, n2, x0, x1, y0, y1, z0, z1):
    """Mean of flat ``a`` over nodes ``{x0, x1} x {y0, y1} x {z0, z1}``, exact for constants."""
    b = uint64((x0 * n1 + y0) * n2 + z0)
    ex, ey, ez = uint64((x1 - x0) * n1 * n2), uint64((y1 - y0) * n2), uint64(z1 - z0)
    c = b + ex
    lo = (a[b] + a[b + ez]) + (a[b + ey] + a[b + ey + ez])
    hi = (a[c] + a[c + ez]) + (a[c + ey] + a[c + ey + ez])
    return 0.125 * (lo + hi)


@njit(cache=True, inline="always", fastmath=_FAST)
def _velocity_2d(u, v, nx, ny, x, y):
    """Carrier ``(u, v)`` (flat) at grid-unit point ``(x, y)`` [m/s]."""
    return (
        _interp_2d(u, nx + 1, ny, x, y - 0.5),
        _interp_2d(v, nx, ny + 1, x - 0.5, y),
    )


@njit(cache=True, inline="always", fastmath=_FAST)
def _velocity_3d(u, v, w, nx, ny, nz, x, y, z):
    """Carrier ``(u, v, w)`` (flat) at grid-unit point ``(x, y, z)`` [m/s]."""
    return (
        _interp_3d(u, nx + 1, ny, nz, x, y - 0.5, z - 0.5),
        _interp_3d(v, nx, ny + 1, nz, x - 0.5, y, z - 0.5),
        _interp_3d(w, nx, ny, nz + 1, x - 0.5, y - 0.5, z),
    )


@njit(cache=True, fastmath=_FAST)
def departure_2d(u2, v2, ox, oy, dt_h, px, py, qx, qy):
    """RK2 (midpoint) back-trace from every sample of a 2D field, over ``dt`` and ``-dt``.

    Args:
        u2, v2: carrier face velocities, shapes ``(nx+1, ny)``, ``(nx, ny+1)`` [m/s].
        ox, oy: the field's sample offsets in cells (0 on its face axis, 0.5 otherwise).
        dt_h: time step over cell size, ``dt / h`` [s/m].
        px, py: out, field-shaped: departure points over ``dt``, clamped field coordinates.
        qx, qy: out, the same over ``-dt`` (where fluid goes), or ``None`` to skip.
    """
    nx, ny = v2.shape[0], u2.shape[1]
    u, v = u2.ravel(), v2.ravel()
    mx, my = px.shape
    fx, fy = ox == 0.0, oy == 0.0
    s = 0.5 * dt_h
    for i in range(mx):
        ax0, ax1 = _pair(i, fx, nx, True)
        bx0, bx1 = _pair(i, fx, nx, False)
        x = i + ox
        for j in range(my):
            ay0, ay1 = _pair(j, fy, ny, True)
            by0, by1 = _pair(j, fy, ny, False)
            y = j + oy
            # first stage: the carrier at the sample itself is a mean of 1, 2 or 4 faces
            ux = _box_2d(u, ny, ax0, ax1, by0, by1)
            uy = _box_2d(v, ny + 1, bx0, bx1, ay0, ay1)
            vx, vy = _velocity_2d(u, v, nx, ny, x - s * ux, y - s * uy)
            px[i, j] = _clamp(x - dt_h * vx - ox, mx)
            py[i, j] = _clamp(y - dt_h * vy - oy, my)
            if qx is not None:
                vx, vy = _velocity_2d(u, v, nx, ny, x + s * ux, y + s * uy)
                qx[i, j] = _clamp(x + dt_h * vx - ox, mx)
                qy[i, j] = _clamp(y + dt_h * vy - oy, my)


@njit(cache=True, fastmath=_FAST)
def departure_3d(u3, v3, w3, ox, oy, oz, dt_h, px, py, pz, qx, qy, qz):
    """RK2 (midpoint) back-trace from every sample of a 3D field; see ``departure_2d``."""
    nx, ny, nz = v3.shape[0], u3.shape[1], u3.shape[2]
    u, v, w = u3.ravel(), v3.ravel(), w3.ravel()
    mx, my, mz = px.shape
    fx, fy, fz = ox == 0.0, oy == 0.0, oz == 0.0
    s = 0.5 * dt_h
    for i in range(mx):
        ax0, ax1 = _pair(i, fx, nx, True)
        bx0, bx1 = _pair(i, fx, nx, False)
        x = i + ox
        for j in range(my):
            ay0, ay1 = _pair(j, fy, ny, True)
            by0, by1 = _pair(j, fy, ny, False)
            y = j + oy
            for k in range(mz):
                az0, az1 = _pair(k, fz, nz, True)
                bz0, bz1 = _pair(k, fz, nz, False)
                z = k + oz
                ux = _box_3d(u, ny, nz, ax0, ax1, by0, by1, bz0, bz1)
                uy = _box_3d(v, ny + 1, nz, bx0, bx1, ay0, ay1, bz0, bz1)
                uz = _box_3d(w, ny, nz + 1, bx0, bx1, by0, by1, az0, az1)
                vx, vy, vz = _velocity_3d(u, v, w, nx, ny, nz, x - s * ux, y - s * uy, z - s * uz)
                px[i, j, k] = _clamp(x - dt_h * vx - ox, mx)
                py[i, j, k] = _clamp(y - dt_h * vy - oy, my)
                pz[i, j, k] = _clamp(z - dt_h * vz - oz, mz)
                if qx is not None:
                    vx, vy, vz = _velocity_3d(
                        u, v, w, nx, ny, nz, x + s * ux, y + s * uy, z + s * uz
                    )
                    qx[i, j, k] = _clamp(x + dt_h * vx - ox, mx)
                    qy[i, j, k] = _clamp(y + dt_h * vy - oy, my)
                    qz[i, j, k] = _clamp(z + dt_h * vz - oz, mz)


@njit(cache=True, fastmath=_FAST)
def gather_2d(phi2, px, py, out):
    """``out = phi`` interpolated bilinearly at field coordinates ``(px, py)``."""
    n0, n1 = phi2.shape
    phi, x, y, o = phi2.ravel(), px.ravel(), py.ravel(), out.ravel()
    for b in range(o.size):
        o[b] = _interp_2d(phi, n0, n1, x[b], y[b])


@njit(cache=True, fastmath=_FAST)
def gather_3d(phi3, px, py, pz, out):
    """``out = phi`` interpolated trilinearly at field coordinates ``(px, py, pz)``."""
    n0, n1, n2 = phi3.shape
    phi, x, y, z, o = phi3.ravel(), px.ravel(), py.ravel(), pz.ravel(), out.ravel()
    for b in range(o.size):
        o[b] = _interp_3d(phi, n0, n1, n2, x[b], y[b], z[b])


@njit(cache=True, fastmath=_FAST)
def compensate_2d(phi2, phi1_2, qx, qy, out):
    """BFECC's middle pass: ``out = phi + (phi - phi1(q)) / 2``, ``phi1`` interpolated at ``q``."""
    n0, n1 = phi2.shape
    phi, phi1, x, y, o = phi2.ravel(), phi1_2.ravel(), qx.ravel(), qy.ravel(), out.ravel()
    for b in range(o.size):
        o[b] = phi[b] + 0.5 * (phi[b] - _interp_2d(phi1, n0, n1, x[b], y[b]))


@njit(cache=True, fastmath=_FAST)
def compensate_3d(phi3, phi1_3, qx, qy, qz, out):
    """BFECC's middle pass in 3D; see ``compensate_2d``."""
    n0, n1, n2 = phi3.shape
    phi, phi1, o = phi3.ravel(), phi1_3.ravel(), out.ravel()
    x, y, z = qx.ravel(), qy.ravel(), qz.ravel()
    for b in range(o.size):
        o[b] = phi[b] + 0.5 * (phi[b] - _interp_3d(phi1, n0, n1, n2, x[b], y[b], z[b]))


@njit(cache=True, fastmath=_FAST)
def limited_gather_2d(phi_tilde2, phi2, px, py, out):
    """Interpolate ``phi_tilde`` at ``(px, py)``, clamped to the range of ``phi`` on the 4 nodes."""
    n0, n1 = phi2.shape
    pt, phi, x, y, o = phi_tilde2.ravel(), phi2.ravel(), px.ravel(), py.ravel(), out.ravel()
    one, sx = uint64(1), uint64(n1)
    for n in range(o.size):
        i, _ = _base(x[n], n0)
        j, _ = _base(y[n], n1)
        b = i * sx + j
        c = b + sx
        lo = min(min(phi[b], phi[b + one]), min(phi[c], phi[c + one]))
        hi = max(max(phi[b], phi[b + one]), max(phi[c], phi[c + one]))
        o[n] = min(max(_interp_2d(pt, n0, n1, x[n], y[n]), lo), hi)


@njit(cache=True, fastmath=_FAST)
def limited_gather_3d(phi_tilde3, phi3, px, py, pz, out):
    """Interpolate ``phi_tilde`` at ``(px, py, pz)``, clamped to ``phi``'s range on the 8 nodes."""
    n0, n1, n2 = phi3.shape
    pt, phi, o = phi_tilde3.ravel(), phi3.ravel(), out.ravel()
    x, y, z = px.ravel(), py.ravel(), pz.ravel()
    one, sy, sx = uint64(1), uint64(n2), uint64(n1 * n2)
    for n in range(o.size):
        i, _ = _base(x[n], n0)
        j, _ = _base(y[n], n1)
        k, _ = _base(z[n], n2)
        b = i * sx + j * sy + k
        lo = hi = phi[b]
        for c in (b, b + sy, b + sx, b + sx + sy):
            lo = min(lo, min(phi[c], phi[c + one]))
            hi = max(hi, max(phi[c], phi[c + one]))
        o[n] = min(max(_interp_3d(pt, n0, n1, n2, x[n], y[n], z[n]), lo), hi)
