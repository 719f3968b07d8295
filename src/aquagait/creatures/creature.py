"""A creature: a checked model plus what aquagait needs to swim it (docs/own-creature.md).

The model says what the body is; the rest says how to drive it and where to
put it: the gait's parameterization and bounds, the gait it swims by default,
the default fluid grid, the energy bound of the objective and the PD servo
gains. ``aquagait.creatures.metadata`` builds one from an MJCF file and its
side-car; the checks here hold for any creature, however it was built.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from aquagait.body.dynamics import Dynamics
from aquagait.body.model import Model
from aquagait.control.gait import DEFAULT_BOUNDS, GaitSpec, SineGait
from aquagait.control.pd import StablePD
from aquagait.objectives import MANEUVERS, STRAIGHT, TURN, Weights
from aquagait.sim.follow import CLEARANCE, cells_around


class CreatureError(ValueError):
    """A creature file, its metadata or a creature built from them is not usable;
    the message names the file, the entry, what is wrong and what would be right."""


class UnlearnedManeuver(CreatureError):
    """A manoeuvre the creature has no gait for; the message lists the learned ones and
    the command that learns it."""


class UnknownCreatureError(KeyError):
    """No creature of that name; the message lists the known ones."""

    def __str__(self) -> str:
        return str(self.args[0])


@dataclass(frozen=True, eq=False)
class ShippedGait:
    """A gait shipped with a creature: its parameter vector and where it came from.

    Attributes:
        params: (gait.size,) the parameter vector, in ``GaitSpec.names`` order.
        provenance: how it was made: ``method`` ('hand-set' or 'optimized'),
            ``command``, ``seed``, ``grid``, ``objective``, ``wall_time``,
            ``date``, ... (free-form; see ``aquagait.creatures.metadata``).
        free_period: its period is a parameter too (``spec(..., free_period=True)``): a
            gait found with ``aquagait optimize --free-period``.
    """

    params: np.ndarray
    provenance: Mapping[str, object] = field(default_factory=dict)
    free_period: bool = False


@dataclass(frozen=True, eq=False)
class Creature:
    """A creature: model, gait parameterization, default gait, grid, energy bound, PD gains.

    Attributes:
        name: registry name, or the MJCF file's stem.
        model: the checked MJCF model.
        gait: which sine parameters are optimized, and their bounds.
        default_gait: (gait.size,) the gait it swims by default: the shipped
            ``straight`` gait, else a small travelling wave; within bounds and limits.
        resolution: default grid cells per axis, (nx, ny) or (nx, ny, nz).
        cell_size: default h [m].
        energy_bound: [J] actuator work over two cycles above which the
            objective's energy term switches on (docs/method-search.md).
        energy_weight: [1/J] that term's weight (``objectives.Weights.energy``):
            once the work passes the bound, the objective adds this times it.
        turn_limit: [rad] the most rotation a manoeuvre's search rewards over a sample
            (``objectives.turning``; 90 degrees unless its side-car says).
        natural_frequency: PD servo w [rad/s] (see ``aquagait.control.pd``).
        damping_ratio: PD servo zeta.
        description: one line.
        source: the MJCF file it was loaded from ('' when built in Python).
        metadata_path: its side-car (``<stem>.aquagait.json``), or None.
        gaits: shipped gaits by name: ``straight``, the learned manoeuvres
            (``turn-left``, ``pitch-up``, ...: its manoeuvre library, each in the
            parameterization ``spec(name)``) and any others (``optimized``).
        notes: the defaults that were filled in, one line each.
        as_written: its thin parts are kept as its MJCF writes them, not
            thickened for the fluid (``aquagait.creatures.registry``, ``--no-thicken``).
        view: the view its 3D pictures take by default (``schema.VIEWS``).
    """

    name: str
    model: Model
    gait: GaitSpec
    default_gait: np.ndarray
    resolution: tuple[int, ...]
    cell_size: float
    energy_bound: float
    energy_weight: float = Weights.energy
    turn_limit: float = TURN
    natural_frequency: float = 100.0
    damping_ratio: float = 1.5
    description: str = ""
    source: str = ""
    metadata_path: Path | None = None
    gaits: Mapping[str, ShippedGait] = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    as_written: bool = False
    view: str = "follow"

    def __post_init__(self):
        object.__setattr__(self, "default_gait", np.asarray(self.default_gait, dtype=float))
        object.__setattr__(self, "resolution", tuple(int(n) for n in self.resolution))
        object.__setattr__(self, "gaits", dict(self.gaits))
        object.__setattr__(self, "notes", tuple(self.notes))
        object.__setattr__(self, "_specs", {(STRAIGHT, False): self.gait})  # as asked
        problems = creature_problems(self)
        if problems:
            raise CreatureError(f"creature {self.name!r}: " + "; ".join(problems))

    @property
    def dim(self) -> int:
        return self.model.dim

    def gait_limits(self, maneuver: str = STRAIGHT) -> tuple[np.ndarray, np.ndarray]:
        """Joint limits (lower, upper) of the DOFs of ``spec(maneuver)``, each (n,) [rad]."""
        return dof_limits(self.model, self.spec(maneuver).dofs)

    def spec(self, maneuver: str = STRAIGHT, free_period: bool = False) -> GaitSpec:
        """The gait parameterization manoeuvre ``maneuver`` is learned in (``maneuver_spec``);
        with ``free_period``, its period a parameter too (``GaitSpec.with_free_period``;
        the same spec if the side-car frees the period already)."""
        key = (maneuver, free_period)
        if key not in self._specs:
            spec = maneuver_spec(self.gait, self.model, maneuver)
            if free_period and not spec.free_period:
                spec = spec.with_free_period()
            self._specs[key] = spec
        return self._specs[key]

    def shipped_spec(self, name: str) -> GaitSpec:
        """The parameterization of shipped gait ``name``: its manoeuvre's (``straight`` for
        a gait kept for reference), with its period free if it was searched so."""
        maneuver = name if name in MANEUVERS else STRAIGHT
        return self.spec(maneuver, self.gaits[name].free_period)

    @property
    def maneuvers(self) -> tuple[str, ...]:
        """The manoeuvres it has learned: straight, then those with a shipped gait."""
        return (STRAIGHT,) + tuple(m for m in MANEUVERS if m != STRAIGHT and m in self.gaits)

    def maneuver_gait(self, maneuver: str) -> np.ndarray:
        """The parameter vector of a learned manoeuvre (``straight``: ``default_gait``).

        Raises:
            UnlearnedManeuver: it has no gait for ``maneuver``.
        """
        if maneuver == STRAIGHT:
            return self.default_gait
        if maneuver not in self.maneuvers:
            raise UnlearnedManeuver(
                f"{self.name} has not learned {maneuver!r}; it has learned "
                f"{', '.join(self.maneuvers)}. Learn it with: aquagait optimize {self.name} "
                f"--maneuver {maneuver} (into runs/{self.name}-{maneuver}-optimize)"
            )
        return self.gaits[maneuver].params

    def policy(self, params=None, maneuver: str = STRAIGHT) -> StablePD:
        """The stable PD servo tracking gait ``params`` of ``spec(maneuver)``
        (default: the manoeuvre's learned gait, straight: ``default_gait``)."""
        x = self.maneuver_gait(maneuver) if params is None else params
        return self.servo(self.spec(maneuver).unpack(x))

    def servo(self, gait) -> StablePD:
        """The stable PD servo, with this creature's gains, tracking ``gait`` (a ``SineGait``
        or anything with ``dofs`` and ``angles(t)``)."""
        return StablePD.tuned(self.model, gait, self.natural_frequency, self.damping_ratio)


def maneuver_spec(spec: GaitSpec, model: Model, maneuver: str) -> GaitSpec:
    """The gait parameterization a manoeuvre is learned in (paper §5, docs/follow.md).

    Straight swimming uses ``spec`` itself. A turn or a pitch frees the
    offsets, so that joints can hold a bend while they beat; each offset
    ranges over its joint's limits within ``DEFAULT_BOUNDS["offset"]``
    (+-0.5 rad; an offset the straight gait already frees keeps its bounds).
    Actuated DOFs the straight gait does not drive (held at rest: the 2D
    turtle's rear flipper) join as ``held`` DOFs, rudders that learn an
    offset and do not beat (in a grouped gait, a group of their own, last).
    A turn also drops the mirror: it bends one side unlike the other, so
    every DOF gets its own parameters (a mirrored DOF takes its source's
    bounds). A pitch keeps the mirror, as it is symmetric left to right.

    Raises:
        ValueError: an unknown manoeuvre.
    """
    if maneuver == STRAIGHT:
        return spec
    if maneuver not in MANEUVERS:
        raise ValueError(f"unknown manoeuvre {maneuver!r}; manoeuvres: {', '.join(MANEUVERS)}")
    bounds = dict(spec.bounds)
    mirror = spec.mirror
    if maneuver.startswith("turn"):
        mirror = ()
        for dof, source, sign in spec.mirror:
            for key, (lo, hi) in spec.bounds.items():
                kind, _, of = key.partition("[")
                if of == f"{source}]":
                    flip = sign < 0 and kind == "offset"
                    bounds[f"{kind}[{dof}]"] = (-hi, -lo) if flip else (lo, hi)
    held = tuple(d for d in actuated_dof_names(model) if d not in spec.dofs)
    dofs = spec.dofs + held
    free = spec.free if "offset" in spec.free else spec.free + ("offset",)
    low, high = DEFAULT_BOUNDS["offset"]
    mirrored = {m[0] for m in mirror}
    for dof, lo, hi in zip(dofs, *dof_limits(model, dofs), strict=True):
        if dof not in mirrored and (dof in held or "offset" not in spec.free):
            bounds[f"offset[{dof}]"] = (max(lo, low), min(hi, high))
    groups = spec.groups + (held,) if spec.groups and held else spec.groups
    return GaitSpec(
        dofs=dofs, free=free, shared=tuple(k for k in spec.shared if k != "offset"),
        mirror=mirror, groups=groups, bounds=bounds, amplitude=spec.amplitude,
        phase=spec.phase, period=spec.period, offset=spec.offset, held=held,
    )  # fmt: skip


def maneuver_start(
    creature: Creature, maneuver: str, gait: SineGait | None = None, free_period: bool = False
) -> np.ndarray:
    """Where a manoeuvre's search starts: ``gait`` (default the straight gait) in the
    manoeuvre's parameters (``free_period``: the period among them)."""
    spec = creature.spec(maneuver, free_period)
    gait = creature.gait.unpack(creature.default_gait) if gait is None else gait
    return spec.vector(gait.on(spec.dofs))


def actuated_dof_names(model: Model) -> tuple[str, ...]:
    """Names of the model's actuated DOFs in MuJoCo order (a ball's axes as 'name:x|y|z')."""
    return tuple(model.dof_names[int(d)] for d in model.actuated_dofs)


def dof_limits(model: Model, dofs) -> tuple[np.ndarray, np.ndarray]:
    """Joint limits (lower, upper) of the named actuated DOFs, each (len(dofs),) [rad]."""
    row = {name: i for i, name in enumerate(actuated_dof_names(model))}
    rows = [row[d] for d in dofs]
    return model.lower[rows], model.upper[rows]


def gait_problems(spec: GaitSpec, params, lower, upper) -> list[str]:
    """What keeps ``params`` from being an admissible gait: bounds, then joint limits."""
    x = np.asarray(params, dtype=float)
    if x.shape != (spec.size,):
        return [f"has {x.size} numbers, the gait has {spec.size}: {', '.join(spec.names)}"]
    outside = [
        f"{n} = {v:.6g} outside [{lo:.6g}, {hi:.6g}]"
        for n, v, lo, hi in zip(spec.names, x, spec.lower, spec.upper, strict=True)
        if not lo <= v <= hi
    ]
    if outside:
        return [f"is outside its bounds: {', '.join(outside)}"]
    violations = spec.limit_violations(x, lower, upper)
    return [f"leaves the joint limits: {'; '.join(violations)}"] if violations else []


def smallest_grid(model: Model, cell_size: float, clearance: int = CLEARANCE) -> tuple[int, ...]:
    """Cells per axis of the smallest grid ``make_scene`` accepts for the model at rest.

    ``make_scene`` centres the grid on the centre of mass, so each axis must
    hold twice the larger distance from it to the body's box, plus
    ``clearance`` cells of water on either side (``aquagait.sim.follow``).
    """
    dim = model.dim
    com = Dynamics(model.mj).center_of_mass(model.qpos0)[:dim]
    return cells_around(model.bounds[:, :dim], com, cell_size, clearance)


def creature_problems(c: Creature) -> list[str]:
    """Everything that makes a creature unusable, one message each (empty: usable)."""
    actuated = actuated_dof_names(c.model)
    missing = [d for d in c.gait.dofs if d not in actuated]
    if missing:
        return [f"gait DOFs {missing} are not actuated DOFs of the model ({', '.join(actuated)})"]
    problems = []
    for label, x, spec in [("default gait", c.default_gait, c.gait)] + [
        (f"shipped gait {name!r}", g.params, c.shipped_spec(name)) for name, g in c.gaits.items()
    ]:
        limits = dof_limits(c.model, spec.dofs)
        problems += [f"{label} {p}" for p in gait_problems(spec, x, *limits)]
    if len(c.resolution) != c.dim:
        problems.append(f"resolution {c.resolution} is not {c.dim}D")
    elif not (np.isfinite(c.cell_size) and c.cell_size > 0):
        problems.append(f"cell size {c.cell_size!r} must be a positive length [m]")
    else:
        need = smallest_grid(c.model, c.cell_size)
        if any(n < m for n, m in zip(c.resolution, need, strict=True)):
            problems.append(
                f"grid {'x'.join(map(str, c.resolution))} of {c.cell_size:g} m cells is too "
                f"small for a body of extent {np.round(c.model.extent[: c.dim], 4).tolist()} m "
                f"with {CLEARANCE} cells of water on every side around its centre of mass: "
                f"use at least {'x'.join(map(str, need))} cells"
            )
    if not (np.isfinite(c.energy_bound) and c.energy_bound > 0):
        problems.append(f"energy bound {c.energy_bound!r} must be a positive number of joules")
    if not (np.isfinite(c.energy_weight) and c.energy_weight >= 0):
        problems.append(f"energy weight {c.energy_weight!r} must be a number >= 0 (per joule)")
    if not (np.isfinite(c.turn_limit) and c.turn_limit > 0):
        problems.append(f"turn limit {c.turn_limit!r} must be an angle > 0 [rad]")
    if not (c.natural_frequency > 0 and c.damping_ratio >= 0):
        problems.append(
            f"PD gains need natural_frequency > 0 rad/s and damping_ratio >= 0; got "
            f"{c.natural_frequency}, {c.damping_ratio}"
        )
    return problems
