"""What a creature gets from its model when its metadata is silent (docs/own-creature.md).

- **Gait**: amplitude and phase for every actuated DOF (each hinge, each axis
  of a ball joint), period 1 s, offset 0.
- **Bounds**: phase [-pi, pi]; amplitude [0, the joint's half-range about the
  fixed offset], per DOF. With offset 0 and a symmetric limit [-l, l] that is
  [0, l]; with an asymmetric limit [lo, hi] it is the *smaller* side,
  min(-lo, hi), since a sine about 0 swings as far down as up, and the larger
  side would only give the optimizer samples to throw away. When the offset is
  free, the amplitude gets the whole half-range (hi - lo) / 2 and the offset
  [lo, hi]: the box around every admissible (amplitude, offset); samples
  outside the limits are resampled (docs/method-search.md). A mirrored DOF's
  limit narrows its source's bound; a shared amplitude gets the smallest of
  all.
- **Cell size**: half the thickness of the thinnest link (its largest
  inscribed ball, ``aquagait.body.shape.link_thickness``, baked at L/400 in 2D
  and L/100 in 3D, so accurate to that), rounded *down* to 1, 1.2, 1.5, 2,
  2.5, 3, 4, 5, 6 or 8 times a power of ten: the thinnest link is then two to
  2.7 cells thick and survives voxelization. Kept between L/20 (a coarser grid
  would not resolve the body at all) and L/100 in 2D or L/40 in 3D (at most
  about 256 x 128 or 112 x 64 x 64 cells: finer costs more than an
  optimization can pay; the note then says how thin the thinnest link is in
  cells, and ``aquagait check`` shows it).
- **Grid**: 2.5 body lengths along the body's longest axis and 1.25 across,
  but at least the body's box around its centre of mass (where ``make_scene``
  centres the grid) plus ``CLEARANCE`` (8) cells of water and ``ROOM`` (4)
  cells to move on each side; each axis rounded up to a multiple of 16 cells,
  so that the multigrid preconditioner coarsens four times without padding.
- **Default gait** (when none is shipped): a small travelling wave, amplitude
  min(0.3 rad, half its upper bound), phase falling by 1 rad per joint from
  the root (a ball's three axes in phase): inside every bound and limit.
- **PD**: natural frequency 100 rad/s, damping ratio 1.5.
- **Energy bound**: ``ENERGY_COEFFICIENT`` m (L/T)^2 over two cycles.
"""

from __future__ import annotations

import math

import numpy as np

from aquagait.body.model import Model
from aquagait.body.shape import body_shape, link_thickness
from aquagait.control.gait import GaitSpec
from aquagait.creatures.creature import dof_limits, smallest_grid
from aquagait.sim.follow import CLEARANCE

ENERGY_COEFFICIENT = 5.0
"""Energy bound = ENERGY_COEFFICIENT * mass * (body_length / period)^2 over two cycles [J].

The paper (§8) tunes one standard bound on its fish and scales it by mass;
(L/T)^2 makes it a work for bodies of any size. Calibrated on the actuator
work ``traj.energy[-1].sum()`` over two cycles in the Euler fluid on each
creature's default grid, in units of m (L/T)^2 (distance: the root's, from rest):

- eel2d, amplitudes 0.25..0.55 rad: phase lag 1.5 rad/joint (the shipped gait)
  1.84 (0.45 L); lag 1.0 3.13 (0.86 L); lag 0.75 4.00 (0.95 L); amplitudes
  x1.4 with lag 1.0 4.86 (1.10 L), with lag 0.75 6.53 (1.13 L); the largest
  the limits allow, lag 1.0, 7.09 (1.25 L). In vacuum the shipped gait: 0.60.
- fish: the shipped gait 1.09 (0.12 L); lag 0.8 1.19 (0.15 L); amplitudes at
  the joint limits 1.36-1.61 (0.15-0.18 L). Its tight limits (12/25/40 deg)
  cap the effort below any bound above 1.6.

So 5 admits the eel's good gaits (0.86-0.95 L in two cycles) with 1.25-1.6x of
margin and turns the energy term on only for its largest, wasteful swings
(twice the work for 20% more distance), and never binds the fish: kept as it
was. A creature whose body plan spends far more per unit mass states its own
bound: accordion2d spends 45 (0.33 J, 0.62 L) with its shipped fold of 0.7 rad,
and under 5 m (L/T)^2 its folds are smaller than 0.25 rad and swim 0.02 L,
so its metadata sets 0.5 J.
"""

PERIOD = 1.0
"""Default gait period T [s] (the paper uses 1 s for every creature)."""

NATURAL_FREQUENCY = 100.0
"""Default PD natural frequency w [rad/s]."""

DAMPING_RATIO = 1.5
"""Default PD damping ratio zeta."""

GRID_LENGTHS = (2.5, 1.25)
"""Default grid span in body lengths: along the longest axis, and across it."""

ROOM = 4
"""Cells of room to move kept beyond the clearance on each side of the body's box."""

GRID_MULTIPLE = 16
"""Default grid sizes are multiples of this (the multigrid coarsens by halving)."""

COARSEST = 20
"""Fewest cells per body length of a default cell size."""

FINEST = {2: 100, 3: 40}
"""Most cells per body length of a default cell size, by dimension."""

NICE = (1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0)
"""Mantissas a default cell size is rounded down (or up, at the fine cap) to."""

WAVE_AMPLITUDE = 0.3
"""Default gait amplitude [rad] where the bounds allow (half the upper bound otherwise)."""

WAVE_LAG = 1.0
"""Default gait phase lag per joint from the root [rad]."""


def energy_bound(model: Model, period: float = PERIOD) -> float:
    """The default energy bound [J] of a creature over two cycles (see ``ENERGY_COEFFICIENT``)."""
    return ENERGY_COEFFICIENT * model.mass * (model.body_length / period) ** 2


def amplitude_bounds(model: Model, dofs, mirror=(), free=(), shared=(), offset=0.0) -> dict:
    """Default amplitude (and, when free, offset) bounds from the joint limits (module doc).

    Args:
        model: the creature's model.
        dofs: gait DOF names; mirror: (dof, source, sign) triples.
        free, shared: the free and the shared kinds.
        offset: the fixed offset [rad] (when the offset is not free).

    Returns:
        ``{bound name: (lo, hi)}``: one entry per kind when every DOF has the same
        bound (or the kind is shared), else one per independent DOF.
    Raises:
        ValueError: a joint's range does not contain the fixed offset, so no
            sine about it stays inside (the message says what to do).
    """
    lower, upper = dof_limits(model, dofs)
    free_offset = "offset" in free
    half = (upper - lower) / 2 if free_offset else np.minimum(offset - lower, upper - offset)
    closed = [d for d, a in zip(dofs, half, strict=True) if a <= 0]
    if closed:
        raise ValueError(
            f"the ranges of {', '.join(closed)} do not contain the offset {offset:g} rad, so no "
            'sine about it stays inside the joint limits; free the offset ("free": '
            '["amplitude", "phase", "offset"]) or set "offset" inside the ranges'
        )
    source = {d: d for d in dofs} | {m[0]: m[1] for m in mirror}
    members = {d: [i for i, e in enumerate(dofs) if source[e] == d] for d in dofs if source[d] == d}
    amp = {d: (0.0, float(min(half[rows]))) for d, rows in members.items()}
    bounds = _per_kind("amplitude", amp, shared)
    if free_offset:
        off = {d: (float(max(lower[rows])), float(min(upper[rows]))) for d, rows in members.items()}
        bounds |= _per_kind("offset", off, shared)
    return bounds


def _per_kind(kind: str, per_dof: dict, shared) -> dict:
    values = set(per_dof.values())
    if kind in shared:
        return {kind: (max(v[0] for v in values), min(v[1] for v in values))}
    if len(values) == 1:
        return {kind: values.pop()}
    return {f"{kind}[{d}]": v for d, v in per_dof.items()}


def thinnest_link(model: Model) -> tuple[str, float, float]:
    """The thinnest link with geoms, its thickness [m] (largest inscribed ball) and the
    sampling it was measured at [m] (L/400 in 2D, L/100 in 3D: 3D meshes cost more)."""
    shape = body_shape(model, model.body_length / 100, refine=4 if model.dim == 2 else 1)
    thickness = link_thickness(shape)
    k = min(np.flatnonzero(shape.dims[:, 0] > 0), key=lambda k: thickness[k])
    return shape.links[k], float(thickness[k]), shape.spacing


def cell_size(model: Model) -> tuple[float, str]:
    """The default cell size [m] and a note saying why (module doc)."""
    link, thickness, spacing = thinnest_link(model)
    length, finest = model.body_length, model.body_length / FINEST[model.dim]
    h = round_down(min(thickness / 2, length / COARSEST)) if thickness / 2 >= finest else 0.0
    thin = f"the thinnest link ({link}, {_mm(thickness)} at a sampling of {_mm(spacing)})"
    if h >= finest:
        return h, f"cell size {_mm(h)} keeps {thin} {thickness / h:.2g} cells thick"
    h = round_up(finest)
    return h, (
        f"cell size {_mm(h)} (at most {FINEST[model.dim]} cells per body length) leaves {thin} "
        f"{thickness / h:.2g} cells thick: under two cells, the fluid sees it only through partly "
        "open faces"
    )


def resolution(model: Model, h: float) -> tuple[tuple[int, ...], str]:
    """The default grid at cell size ``h`` and a note saying why (module doc)."""
    dim = model.dim
    extent = np.asarray(model.extent[:dim])
    along = int(np.argmax(extent))
    lengths = [GRID_LENGTHS[0] if i == along else GRID_LENGTHS[1] for i in range(dim)]
    body = smallest_grid(model, h, clearance=0)
    cells = [
        max(math.ceil(n * model.body_length / h - 1e-9), b + 2 * (CLEARANCE + ROOM))
        for n, b in zip(lengths, body, strict=True)
    ]
    res = tuple(GRID_MULTIPLE * math.ceil(c / GRID_MULTIPLE) for c in cells)
    spans = " x ".join(f"{n * h / model.body_length:.3g}" for n in res)
    return res, f"grid {'x'.join(map(str, res))} of {_mm(h)} cells spans {spans} body lengths"


def gait_vector(spec: GaitSpec) -> np.ndarray:
    """The default gait: a small travelling wave inside every bound (module doc)."""
    joint_of = {d: d.split(":")[0] for d in spec.dofs}  # a ball's axes move in phase
    joints = list(dict.fromkeys(joint_of.values()))
    x = []
    for name, lo, hi in zip(spec.names, spec.lower, spec.upper, strict=True):
        kind, _, rest = name.partition("[")
        dof = rest[:-1]
        if kind == "amplitude":
            value = min(WAVE_AMPLITUDE, hi / 2)
        elif kind == "phase":
            value = _wrap(-WAVE_LAG * joints.index(joint_of[dof])) if dof else 0.0
        else:
            value = getattr(spec, kind)
        x.append(float(np.clip(value, lo, hi)))
    return np.array(x)


def gait_note(spec: GaitSpec, model: Model) -> str:
    """What the default gait parameterization drives, for ``Creature.notes``."""
    kinds = {j.name: j.kind for j in model.joints}
    joints = list(dict.fromkeys(d.split(":")[0] for d in spec.dofs))
    hinges = [j for j in joints if kinds.get(j) == "hinge"]
    balls = [j for j in joints if kinds.get(j) == "ball"]
    parts = [f"{len(hinges)} hinge{'s' * (len(hinges) != 1)}"] if hinges else []
    parts += [f"{len(balls)} ball joint{'s' * (len(balls) != 1)} (3 axes each)"] if balls else []
    return f"{' and '.join(spec.free)} for {' and '.join(parts)}, period {spec.period:g} s"


def round_down(x: float) -> float:
    """The largest 'nice' length (``NICE`` times a power of ten) not above ``x``."""
    exponent = math.floor(math.log10(x))
    scaled = x / 10.0**exponent
    mantissa = max(m for m in NICE if m <= scaled * (1 + 1e-9))
    return float(f"{mantissa * 10.0**exponent:.6g}")


def round_up(x: float) -> float:
    """The smallest 'nice' length not below ``x``."""
    exponent = math.floor(math.log10(x))
    scaled = x / 10.0**exponent
    mantissa = min(m for m in (*NICE, 10.0) if m >= scaled * (1 - 1e-9))
    return float(f"{mantissa * 10.0**exponent:.6g}")


def _wrap(angle: float) -> float:
    return float(np.angle(np.exp(1j * angle)))


def _mm(x: float) -> str:
    return f"{x * 1000:.3g} mm"
