"""Sine gaits: a flat parameter vector mapped onto per-DOF sines (docs/method-search.md, paper §4).

Each actuated DOF i follows the reference

    qbar_i(t) = a_i sin(2 pi t / T_i + phi_i) + c_i

with amplitude ``a`` [rad], phase ``phi`` [rad], period ``T`` [s] and offset
``c`` [rad]. A ``GaitSpec`` says which of these *kinds* are optimized (by
default amplitude and phase; period 1 s and offset 0 fixed) and how the flat
vector ``x`` that CMA-ES sees drives them:

- ``shared`` kinds are one number for every DOF (an accordion: one amplitude);
- ``mirror`` copies a DOF's sine onto another with a sign, ``qbar_m = sign *
  qbar_source`` (left and right limbs: half the parameters);
- ``groups`` split the DOFs into sets optimized in turn (frog: hind, then fore);
- ``held`` DOFs do not beat: they hold an offset only (amplitude 0), a
  rudder a manoeuvre learns to set (the 2D turtle's rear flipper).

``with_free_period`` frees one period for every DOF (the paper's future work,
``aquagait optimize --free-period``): the gait keeps one rhythm, its frequency
searched within ``FREE_PERIOD`` times the fixed period.

Parameter names read ``amplitude[j1]`` or, when shared, ``amplitude``; the
layout of ``x`` is: for each free kind in ``KINDS`` order, one entry (shared)
or one per independent (not mirrored) DOF in ``dofs`` order; held DOFs only
have an ``offset`` entry.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace

import numpy as np

KINDS = ("amplitude", "phase", "period", "offset")
DEFAULT_BOUNDS = {
    "amplitude": (0.0, 1.0),  # rad
    "phase": (-np.pi, np.pi),  # rad
    "period": (0.5, 2.0),  # s
    "offset": (-0.5, 0.5),  # rad
}

FREE_PERIOD = (0.5, 2.0)
"""A freed period's search bounds, as multiples of the gait's fixed period (unless the
gait states its own period bounds): from twice the frequency to half of it."""


@dataclass(frozen=True)
class SineGait:
    """Per-DOF sine references, all arrays (n,) over ``dofs``.

    Attributes:
        dofs: names of the driven DOFs (``Model.dof_names`` entries).
        amplitude: a [rad] (may be negative on a mirrored DOF).
        phase: phi [rad].
        period: T [s], > 0.
        offset: c [rad].
    """

    dofs: tuple[str, ...]
    amplitude: np.ndarray
    phase: np.ndarray
    period: np.ndarray
    offset: np.ndarray

    def angles(self, t: float) -> np.ndarray:
        """Reference angles qbar(t), (n,) [rad]."""
        return self.amplitude * np.sin(2 * np.pi * t / self.period + self.phase) + self.offset

    def rates(self, t: float) -> np.ndarray:
        """Reference angular rates d qbar / dt, (n,) [rad/s]."""
        omega = 2 * np.pi / self.period
        return self.amplitude * omega * np.cos(omega * t + self.phase)

    def mirrored(self) -> SineGait:
        """The gait with every reference angle negated: the mirror image for yaw joints."""
        return SineGait(self.dofs, -self.amplitude, self.phase, self.period, -self.offset)

    def lagging(self, cycles: float) -> SineGait:
        """The same gait ``cycles`` of its longest period later: ``qbar'(t) = qbar(t - cycles
        T)`` (a follower's phase offset in a group, ``aquagait swim --phase``)."""
        lag = 2 * np.pi * cycles * np.max(self.period) / self.period
        return replace(self, phase=np.asarray(self.phase) - lag)

    def on(self, dofs) -> SineGait:
        """The same references over ``dofs`` (a superset of ``self.dofs``, in any order);
        a DOF it does not drive is held at 0 rad, as a servo holds an undriven DOF."""
        dofs = tuple(dofs)
        missing = [d for d in self.dofs if d not in dofs]
        if missing:
            raise ValueError(f"the gait drives {missing}, which are not among {dofs}")
        row = {d: i for i, d in enumerate(self.dofs)}
        take = np.array([row.get(d, -1) for d in dofs])

        def pick(values, rest):
            return np.where(take >= 0, np.asarray(values)[np.maximum(take, 0)], rest)

        return SineGait(dofs, pick(self.amplitude, 0.0), pick(self.phase, 0.0),
                        pick(self.period, 1.0), pick(self.offset, 0.0))  # fmt: skip


def mix(gaits, weights) -> SineGait:
    """The gait whose references are ``sum_k w_k qbar_k(t)``: sines of one period sum to a
    sine (their phasors ``a e^(i phi)`` add), so the mix is a ``SineGait`` itself.

    With weights summing to 1 it lies between the gaits: ``mix([straight, turn], [1 - s,
    s])`` is a share ``s`` of the turn (``aquagait.path.Follower``'s graded steering).
    One gait at weight 1, the others at 0, is that gait itself.

    Args:
        gaits: ``SineGait``s driving the same DOFs in the same order, with the same periods.
        weights: one number per gait.

    Raises:
        ValueError: no gaits, a weight count that differs, other DOFs or periods.
    """
    gaits, weights = list(gaits), np.asarray(weights, dtype=float)
    if not gaits or weights.shape != (len(gaits),):
        raise ValueError(f"a mix needs one weight per gait; got {len(gaits)} gaits and "
                         f"weights {weights.tolist()}")  # fmt: skip
    first = gaits[0]
    for gait in gaits[1:]:
        if tuple(gait.dofs) != tuple(first.dofs) or not np.allclose(gait.period, first.period):
            raise ValueError(
                f"a mix needs gaits on the same DOFs with the same periods; got "
                f"{first.dofs} at {first.period} s and {gait.dofs} at {gait.period} s"
            )
    if np.count_nonzero(weights) == 1 and weights.max() == 1.0:
        return gaits[int(np.argmax(weights))]  # one gait whole: itself, to the last bit
    pairs = list(zip(weights, gaits, strict=True))
    phasor = sum(w * g.amplitude * np.exp(1j * g.phase) for w, g in pairs)
    offset = sum(w * g.offset for w, g in pairs)
    return SineGait(first.dofs, np.abs(phasor), np.angle(phasor), first.period, offset)


@dataclass(frozen=True)
class SwitchedGait:
    """One gait handing over to another: the references blend over ``duration`` from ``start``.

    ``qbar(t) = (1 - s) qbar_before(t) + s qbar_after(t)`` with ``s`` rising
    smoothly (``3 u^2 - 2 u^3``, ``u = (t - start) / duration``) from 0 to 1, so
    that a path follower's change of manoeuvre does not jump the reference
    angles or their rates. Before ``start`` it is ``before``, after
    ``start + duration`` it is ``after``.

    Attributes:
        before, after: the gaits, driving the same ``dofs`` in the same order.
        start: when the hand-over begins [s].
        duration: how long it takes [s], >= 0 (0: a jump).
    """

    before: SineGait
    after: SineGait
    start: float
    duration: float

    def __post_init__(self):
        if tuple(self.before.dofs) != tuple(self.after.dofs):
            raise ValueError(
                f"a switch between gaits needs the same DOFs in the same order; got "
                f"{self.before.dofs} and {self.after.dofs}"
            )
        if not self.duration >= 0:
            raise ValueError(f"a switch's duration must be >= 0 s, got {self.duration!r}")

    @property
    def dofs(self) -> tuple[str, ...]:
        return self.after.dofs

    def weight(self, t: float) -> tuple[float, float]:
        """``(s, ds/dt)`` at time ``t`` [s]: the share of ``after`` and its rate [1/s]."""
        if self.duration == 0:
            return float(t >= self.start), 0.0
        u = min(max((t - self.start) / self.duration, 0.0), 1.0)
        return 3 * u**2 - 2 * u**3, 6 * u * (1 - u) / self.duration

    def angles(self, t: float) -> np.ndarray:
        """Reference angles qbar(t), (n,) [rad]."""
        s, _ = self.weight(t)
        return (1 - s) * self.before.angles(t) + s * self.after.angles(t)

    def rates(self, t: float) -> np.ndarray:
        """Reference angular rates d qbar / dt, (n,) [rad/s]."""
        s, ds = self.weight(t)
        return (
            (1 - s) * self.before.rates(t)
            + s * self.after.rates(t)
            + ds * (self.after.angles(t) - self.before.angles(t))
        )


@dataclass(frozen=True)
class GaitSpec:
    """Which sine parameters are optimized and how they drive the DOFs.

    Attributes:
        dofs: driven DOF names in order (e.g. ``("j1", "j2")``; a ball joint's
            components are ``"name:x"``, ``"name:y"``, ``"name:z"``).
        free: kinds in the parameter vector, a subset of ``KINDS``.
        shared: free kinds that are one number for all DOFs.
        mirror: ``(dof, source, sign)`` triples: ``qbar_dof = sign * qbar_source``.
        groups: tuples of DOF names optimized in turn; empty means one group.
        held: DOFs that hold an offset and do not beat (amplitude 0): only their
            ``offset`` is a parameter, when it is free.
        bounds: search bounds by kind (``"amplitude"``) or by parameter
            (``"amplitude[j3]"``), overriding ``DEFAULT_BOUNDS``.
        amplitude, phase, period, offset: the values of kinds that are not free.
    """

    dofs: tuple[str, ...]
    free: tuple[str, ...] = ("amplitude", "phase")
    shared: tuple[str, ...] = ()
    mirror: tuple[tuple[str, str, float], ...] = ()
    groups: tuple[tuple[str, ...], ...] = ()
    bounds: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    held: tuple[str, ...] = ()
    amplitude: float = 0.0
    phase: float = 0.0
    period: float = 1.0
    offset: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "dofs", tuple(self.dofs))
        object.__setattr__(self, "mirror", tuple(tuple(m) for m in self.mirror))
        object.__setattr__(self, "groups", tuple(tuple(g) for g in self.groups))
        object.__setattr__(self, "held", tuple(self.held))
        _check_spec(self)

    # --- layout -------------------------------------------------------------
    @property
    def independent(self) -> tuple[str, ...]:
        """DOFs with their own parameters (not mirrored copies)."""
        mirrored = {m[0] for m in self.mirror}
        return tuple(d for d in self.dofs if d not in mirrored)

    @property
    def names(self) -> tuple[str, ...]:
        """Name of each entry of the parameter vector, in order."""
        names = []
        for kind in (k for k in KINDS if k in self.free):
            dofs = [d for d in self.independent if kind == "offset" or d not in self.held]
            names += [kind] if kind in self.shared else [f"{kind}[{d}]" for d in dofs]
        return tuple(names)

    @property
    def size(self) -> int:
        """Length of the parameter vector."""
        return len(self.names)

    @property
    def lower(self) -> np.ndarray:
        """(size,) lower search bounds."""
        return np.array([self._bound(n)[0] for n in self.names])

    @property
    def upper(self) -> np.ndarray:
        """(size,) upper search bounds."""
        return np.array([self._bound(n)[1] for n in self.names])

    def _bound(self, name: str) -> tuple[float, float]:
        kind = name.split("[")[0]
        return tuple(self.bounds.get(name, self.bounds.get(kind, DEFAULT_BOUNDS[kind])))

    def group_indices(self, group: int) -> np.ndarray:
        """Indices into the parameter vector optimized in ``group`` (shared ones are in all)."""
        groups = self.groups or (self.dofs,)
        if not 0 <= group < len(groups):
            raise IndexError(f"gait has {len(groups)} group(s); asked for group {group}")
        members = set(groups[group])
        dof_of = [n[n.index("[") + 1 : -1] if "[" in n else None for n in self.names]
        return np.array([i for i, d in enumerate(dof_of) if d is None or d in members], dtype=int)

    @property
    def free_period(self) -> bool:
        """Whether the gait's period is a parameter (one for all DOFs, or one each)."""
        return "period" in self.free

    def with_free_period(self) -> GaitSpec:
        """The same parameterization with one period for every DOF set free, within
        ``FREE_PERIOD`` times ``period`` unless ``bounds`` states the period's.

        Raises:
            ValueError: the period is free already.
        """
        if self.free_period:
            raise ValueError(f"the gait's period is free already (free kinds: {self.free})")
        bounds = dict(self.bounds)
        bounds.setdefault("period", tuple(share * self.period for share in FREE_PERIOD))
        free = tuple(k for k in KINDS if k in self.free or k == "period")
        return replace(self, free=free, shared=self.shared + ("period",), bounds=bounds)

    # --- vector <-> sines -----------------------------------------------------
    def unpack(self, x) -> SineGait:
        """The per-DOF sines driven by parameter vector ``x`` (size,)."""
        x = np.asarray(x, dtype=float)
        if x.shape != (self.size,):
            raise ValueError(
                f"gait parameter vector has shape {x.shape}; this gait has {self.size}: "
                f"{', '.join(self.names)}"
            )
        values = dict(zip(self.names, x, strict=True))
        per_kind = {}
        for kind in KINDS:
            fixed = getattr(self, kind)
            per_kind[kind] = {
                d: values.get(kind, values.get(f"{kind}[{d}]", fixed)) for d in self.independent
            }
        for dof in self.held:
            per_kind["amplitude"][dof] = 0.0
        for dof, source, sign in self.mirror:
            for kind in KINDS:
                value = per_kind[kind][source]
                per_kind[kind][dof] = sign * value if kind in ("amplitude", "offset") else value
        arrays = {k: np.array([per_kind[k][d] for d in self.dofs]) for k in KINDS}
        if np.any(arrays["period"] <= 0):
            raise ValueError(f"gait periods must be > 0 s; got {arrays['period']}")
        return SineGait(self.dofs, **arrays)

    def pack(self, **per_dof) -> np.ndarray:
        """The parameter vector of per-DOF values: ``pack(amplitude=[...], phase=[...])``.

        Each keyword is a free kind with one value per DOF in ``dofs`` (or a
        scalar); a shared kind takes the first DOF's value, mirrored DOFs are
        ignored.
        """
        unknown = set(per_dof) - set(self.free)
        if unknown:
            raise ValueError(f"{sorted(unknown)} are not free in this gait; free: {self.free}")
        x = []
        for name in self.names:
            kind, _, dof = name.partition("[")
            if kind not in per_dof:
                raise ValueError(f"pack() needs a value for {kind!r}")
            values = np.broadcast_to(np.asarray(per_dof[kind], dtype=float), (len(self.dofs),))
            x.append(values[self.dofs.index(dof[:-1])] if dof else values[0])
        return np.array(x)

    def vector(self, gait: SineGait) -> np.ndarray:
        """The parameter vector that drives ``gait``: ``unpack``'s inverse.

        A negative amplitude is written as its size with the phase turned by
        pi (the same sine), that phase wrapped into [-pi, pi). A shared kind takes
        the first DOF's value and mirrored DOFs are not read, so the vector
        drives ``gait`` exactly only where this parameterization can express it.
        """
        if tuple(gait.dofs) != self.dofs:
            raise ValueError(f"the gait drives {gait.dofs}; this parameterization {self.dofs}")
        flip = gait.amplitude < 0
        values = {
            "amplitude": np.abs(gait.amplitude),
            "phase": np.where(flip, (gait.phase + 2 * np.pi) % (2 * np.pi) - np.pi, gait.phase),
            "period": gait.period,
            "offset": gait.offset,
        }
        return self.pack(**{kind: values[kind] for kind in self.free})

    def limit_violations(self, x, lower, upper) -> list[str]:
        """DOFs whose sine leaves their joint limits: ``offset +- |amplitude|`` outside [lo, hi].

        Args:
            x: (size,) parameter vector.
            lower: (n,) lower joint limits of ``dofs`` [rad].
            upper: (n,) upper joint limits of ``dofs`` [rad].

        Returns:
            One message per offending DOF; empty when the gait is admissible.
        """
        gait = self.unpack(x)
        swing = np.abs(gait.amplitude)
        low, high = gait.offset - swing, gait.offset + swing
        return [
            f"{d}: swings over [{lo:.3g}, {hi:.3g}] rad, limits [{a:.3g}, {b:.3g}]"
            for d, lo, hi, a, b in zip(self.dofs, low, high, lower, upper, strict=True)
            if lo < a - 1e-12 or hi > b + 1e-12
        ]


def _check_spec(spec: GaitSpec) -> None:
    if len(set(spec.dofs)) != len(spec.dofs) or not spec.dofs:
        raise ValueError(f"gait DOFs must be a non-empty list of distinct names; got {spec.dofs}")
    for label, kinds in (("free", spec.free), ("shared", spec.shared)):
        bad = [k for k in kinds if k not in KINDS]
        if bad:
            raise ValueError(f"gait {label} kinds {bad} unknown; kinds are {KINDS}")
    if not set(spec.shared) <= set(spec.free):
        raise ValueError(f"shared kinds {spec.shared} must also be free ({spec.free})")
    mirrored = [m[0] for m in spec.mirror]
    for dof, source, sign in spec.mirror:
        if dof not in spec.dofs or source not in spec.dofs:
            raise ValueError(f"mirror ({dof!r}, {source!r}) names a DOF not in {spec.dofs}")
        if source in mirrored or dof == source:
            raise ValueError(f"mirror source {source!r} must be an independent DOF")
        if sign not in (-1, 1, -1.0, 1.0):
            raise ValueError(f"mirror sign for {dof!r} must be +1 or -1, got {sign}")
    if len(set(mirrored)) != len(mirrored):
        raise ValueError(f"a DOF is mirrored twice in {spec.mirror}")
    if not set(spec.held) <= set(spec.dofs) - set(mirrored) or any(
        source in spec.held for _, source, _ in spec.mirror
    ):
        raise ValueError(f"held DOFs {spec.held} must be independent DOFs of {spec.dofs}")
    if spec.groups:
        listed = [d for g in spec.groups for d in g]
        if sorted(listed) != sorted(spec.dofs):
            raise ValueError(f"gait groups {spec.groups} must list every DOF of {spec.dofs} once")
    names = set(spec.names) | set(KINDS)
    bad = [b for b in spec.bounds if b not in names]
    if bad:
        raise ValueError(f"bounds given for {bad}, which are not gait parameters: {spec.names}")
    for name in spec.names:
        lo, hi = spec._bound(name)
        if not lo < hi:
            raise ValueError(f"bounds of {name} are ({lo}, {hi}); need lower < upper")
