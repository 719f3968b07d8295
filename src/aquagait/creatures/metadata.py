"""Creature metadata as data: the side-car ``<stem>.aquagait.json`` (docs/own-creature.md).

A creature is an MJCF file plus, optionally, a JSON file beside it with the
same stem (``eel2d.xml`` and ``eel2d.aquagait.json``) stating what the model
cannot: how the gait drives the joints, the default grid, the energy bound,
the PD gains and the shipped gaits. Every entry is optional; what is left out
comes from the model (``aquagait.creatures.defaults``), and ``Creature.notes``
says which defaults were filled. A complete example (an imaginary newt: two
tail hinges, mirrored legs optimized after the tail):

    {
      "description": "a newt, 5 links, 3D",
      "gait": {
        "dofs": ["tail1", "tail2", "leg_l", "leg_r"],
        "free": ["amplitude", "phase"],
        "shared": [],
        "period": 1.0,
        "offset": 0.0,
        "mirror": [["leg_r", "leg_l", -1]],
        "groups": [["tail1", "tail2"], ["leg_l", "leg_r"]],
        "bounds": {"amplitude": [0, 0.6], "amplitude[tail2]": [0, 0.9], "phase": [-3.14, 3.14]}
      },
      "pd": {"natural_frequency": 100, "damping_ratio": 1.5},
      "grid": {"resolution": [96, 48, 48], "cell_size": 0.004},
      "energy_bound": 0.02,
      "energy_weight": 1.0,
      "turn_limit": 1.5708,
      "forward": [1, 0, 0],
      "planar_fluid": "2d",
      "view": "side-above",
      "gaits": {
        "straight": {
          "params": {
            "amplitude[tail1]": 0.3, "amplitude[tail2]": 0.6, "amplitude[leg_l]": 0.4,
            "phase[tail1]": 0.0, "phase[tail2]": -1.2, "phase[leg_l]": 1.5
          },
          "provenance": {
            "method": "optimized",
            "command": "aquagait optimize newt.xml --generations 100 --seed 3",
            "seed": 3, "grid": [96, 48, 48], "objective": -0.31, "wall_time": 5400,
            "date": "2026-11-30"
          }
        }
      }
    }

The eel's (``eel2d.aquagait.json``) states its DOFs, period, offset, PD gains,
grid and hand-set gait, and leaves the amplitude bounds (its joint limits) and
the energy bound to the defaults.

The entries (units: rad, s, m, J; the paper's gait is
``qbar_i(t) = a_i sin(2 pi t / T_i + phi_i) + c_i``, ``aquagait.control.gait``):

- ``description``: one line.
- ``gait.dofs``: the driven DOFs, actuated DOFs of the model (``Model.dof_names``;
  a ball joint's axes are ``"name:x"``, ``"name:y"``, ``"name:z"``). Default: all.
- ``gait.free``: the kinds CMA-ES optimizes, of amplitude, phase, period,
  offset. Default ``["amplitude", "phase"]``.
- ``gait.amplitude``, ``phase``, ``period``, ``offset``: the values of kinds
  that are not free (defaults 0, 0, 1 s, 0). A free period or offset starts
  the default gait at its value; the period is also the energy bound's ``T``.
- ``gait.shared``: free kinds that are one number for every DOF.
- ``gait.mirror``: ``[dof, source, sign]`` triples, ``qbar_dof = sign * qbar_source``
  (sign +1 or -1): symmetric limbs share parameters.
- ``gait.groups``: lists of DOFs optimized in turn, together listing every DOF once.
- ``gait.bounds``: ``{"kind": [lo, hi]}`` or ``{"kind[dof]": [lo, hi]}``: search
  bounds; a kind's bound replaces every default bound of that kind, a
  ``kind[dof]`` bound overrides it for one parameter. Defaults: amplitude
  [0, the joint limit] per DOF (the smaller side of an asymmetric one; with a
  free offset, the half-range, and the offset the range), phase [-pi, pi],
  period [0.5, 2] s (``defaults``, ``aquagait.control.gait.DEFAULT_BOUNDS``).
- ``pd.natural_frequency`` [rad/s] (> 0) and ``pd.damping_ratio`` (>= 0): the
  servo gains, about each DOF's inertia in a vacuum (``aquagait.control.pd``;
  ``aquagait check`` also gives both about its inertia in water). Defaults 100
  and 1.5. A servo with damping ratio below 1 is refused at steps it cannot
  follow (``aquagait.control.discretization``: 0.5 beyond w dt = 1.1).
- ``grid.resolution`` (cells per axis, one per dimension) and ``grid.cell_size``
  [m]: the default grid; it must hold the body with 8 cells of water on every
  side around its centre of mass. Defaults from the body's thinnest link and length.
- ``energy_bound`` [J]: actuator work over two cycles above which the objective's
  energy term switches on. Default ``5 m (L/T)^2`` (``defaults.ENERGY_COEFFICIENT``).
- ``energy_weight`` [1/J] (>= 0): the energy term's weight, ``w2`` of
  ``objectives.total``: once the work passes the bound, the objective adds this
  times it. Default 1 (paper §4). A small creature, whose joule is worth more
  than a metre of swimming, needs more: the frog has 20 (at 1 its search spent
  4.1x the bound for 2.7x the distance). ``aquagait optimize --energy-weight``
  overrides it.
- ``turn_limit`` [rad] (> 0): the most rotation a manoeuvre's search rewards over
  a sample (``objectives.turning``). Default 90 degrees (``objectives.TURN``).
  Smaller, a slow turner's search buys travel past it instead of more
  rotation: the manta has 0.25 (pitches searched with that cap travelled
  0.10-0.22 body lengths a cycle under way, against 0.04-0.06 uncapped).
  ``aquagait optimize --turn-limit`` overrides it.
- ``forward``: the direction the creature's head points, in the MJCF's frame
  ([x, y] or [x, y, z]; in a planar model, in its plane). By default the
  model's axis from its body's middle towards its root link, when the root
  clearly lies towards one end, else +x (``aquagait.body.model``). A creature
  facing elsewhere than +x is turned on loading to face +x, the direction
  every objective, metric and manoeuvre takes as forward.
- ``planar_fluid``: ``"2d"`` (default) or ``"3d"``: where a planar model (root
  slide x, slide y, hinge z) swims. In 2D its geoms are prisms, 3D shapes cut
  by the plane of motion (``aquagait.body.flatten``); in 3D its shapes are as
  written and its root is held to its plane (no rolling, pitching or rising):
  the better physics for 3D shapes, at a 3D fluid's cost.
- ``view``: the view its 3D pictures take by default, one of
  ``schema.VIEWS``: ``"follow"`` (default: three-quarters from behind and
  above), ``"side"``, ``"top"``, ``"side-above"``, ``"front-above"``; the one
  that shows its stroke (a ray's wings from in front and above).
- ``gaits``: shipped gaits by name; ``straight`` is the creature's default
  gait; ``turn-left``, ``turn-right``, ``pitch-up`` and ``pitch-down`` are its
  learned manoeuvres (``aquagait optimize --maneuver``, followed by
  ``aquagait follow``); any other name is a gait kept for reference. ``params``
  is the parameter vector, either by name (``{"amplitude[j1]": 0.25, ...}``,
  exactly the gait's parameter names) or as a list in their order
  (``GaitSpec.names``: for each free kind, one entry if shared, else one per
  DOF that is not mirrored). Every shipped gait is checked against the
  gait's parameterization; a manoeuvre's against its own
  (``creature.maneuver_spec``: the offsets freed, and for a turn the mirror
  dropped). A gait searched with its period free (``aquagait optimize
  --free-period``) names ``period`` among its parameters (by name only), and
  may not be ``straight`` or a manoeuvre, which share the gait's period;
  ``provenance`` is a free-form record of how it was made: ``method``
  ('hand-set' or 'optimized'), ``command``, ``seed``, ``grid``, ``objective``,
  ``wall_time`` [s], ``date``, anything else worth keeping.

Problems are reported together, in one ``CreatureError`` naming the file,
the JSON path of each bad entry (``gait.mirror[0][2]``,
``gaits.straight.params["amplitude[j1]"]``), what is wrong and what would be
right: unknown keys (with the known ones), wrong types and shapes, DOFs that
are not actuated DOFs of the model (a side-car for another creature), a grid
too small for the body, a shipped gait of the wrong length or outside its
bounds or the joint limits. Shapes and types are checked first, all of them;
once they are right, the fit to the model (the DOFs first: a wrong one leaves
nothing else to check against).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from aquagait.body.model import Model
from aquagait.control.gait import GaitSpec
from aquagait.creatures import defaults
from aquagait.creatures.creature import (
    Creature,
    CreatureError,
    ShippedGait,
    actuated_dof_names,
    dof_limits,
    gait_problems,
    maneuver_spec,
    smallest_grid,
)
from aquagait.creatures.schema import at, check_sidecar
from aquagait.objectives import MANEUVERS, TURN, Weights
from aquagait.sim.follow import CLEARANCE

SUFFIX = ".aquagait.json"
"""A side-car's name: the MJCF file's stem plus this."""


@dataclass(frozen=True)
class Metadata:
    """A side-car's entries, checked for shape and type (absent entries are absent).

    Attributes:
        path: the side-car file, or None when there is none.
        description: one line, or None.
        gait: the ``gait`` entries given (lists as tuples, bounds as (lo, hi)).
        pd: the ``pd`` entries given.
        grid: the ``grid`` entries given (resolution as a tuple of ints).
        energy_bound: [J], or None.
        energy_weight: [1/J], or None.
        turn_limit: [rad], or None.
        forward: (3,) the direction the head points in the MJCF's frame, or None.
        planar_fluid: "2d" or "3d", where a planar model swims, or None ("2d").
        view: the 3D pictures' default view, or None ("follow").
        gaits: shipped gaits by name: ``{"params": dict | list, "provenance": dict}``.
    """

    path: Path | None = None
    description: str | None = None
    gait: Mapping = field(default_factory=dict)
    pd: Mapping = field(default_factory=dict)
    grid: Mapping = field(default_factory=dict)
    energy_bound: float | None = None
    energy_weight: float | None = None
    turn_limit: float | None = None
    forward: tuple[float, float, float] | None = None
    planar_fluid: str | None = None
    view: str | None = None
    gaits: Mapping = field(default_factory=dict)


def sidecar_path(mjcf) -> Path:
    """Where an MJCF file's side-car is: ``<stem>.aquagait.json`` beside it."""
    mjcf = Path(mjcf)
    return mjcf.with_name(mjcf.stem + SUFFIX)


def read_metadata(path) -> Metadata:
    """Read and check a side-car's shape and types (the model is checked in ``build_creature``).

    Raises:
        CreatureError: the file cannot be read, is not JSON, or has entries of
            the wrong shape; every problem is listed with its JSON path.
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text())
    except OSError as err:
        raise CreatureError(f"{path}: cannot read the metadata: {err.strerror}") from None
    except json.JSONDecodeError as err:
        raise CreatureError(
            f"{path}: not JSON: {err.msg} at line {err.lineno}, column {err.colno}"
        ) from None
    return parse_metadata(data, path)


def parse_metadata(data, path: Path | None = None) -> Metadata:
    """Check decoded JSON ``data`` against the format (module doc); ``path`` names it in errors."""
    entries, problems = check_sidecar(data)
    _raise(path, problems)
    return Metadata(path=path, **entries)


def build_creature(model: Model, meta: Metadata, name: str) -> Creature:
    """The creature of ``model`` and its metadata, with defaults from the model where silent.

    Raises:
        CreatureError: metadata that does not fit the model: DOFs that are not
            its actuated DOFs, a grid of the wrong dimension or too small, a
            shipped gait of the wrong length or outside its bounds or limits.
    """
    notes = [] if meta.path else [f"no metadata ({Path(model.source).stem}{SUFFIX}): defaults"]
    spec, problems = _gait_spec(model, meta, notes)
    _raise(meta.path, problems)
    resolution, cell_size, problems = _grid(model, meta, notes)
    gaits, wrong = _shipped_gaits(model, spec, meta)
    _raise(meta.path, problems + wrong)
    pd = {"natural_frequency": defaults.NATURAL_FREQUENCY, "damping_ratio": defaults.DAMPING_RATIO}
    if set(pd) - set(meta.pd):
        notes.append(
            f"PD gains w = {pd['natural_frequency']:g} rad/s, zeta = "
            f"{pd['damping_ratio']:g} where not given"
        )
    pd |= dict(meta.pd)
    return Creature(
        name=name,
        model=model,
        gait=spec,
        default_gait=_default_gait(model, spec, meta, gaits, notes),
        resolution=resolution,
        cell_size=cell_size,
        energy_bound=_energy_bound(model, spec, meta, notes),
        energy_weight=Weights.energy if meta.energy_weight is None else meta.energy_weight,
        turn_limit=TURN if meta.turn_limit is None else meta.turn_limit,
        natural_frequency=float(pd["natural_frequency"]),
        damping_ratio=float(pd["damping_ratio"]),
        description=meta.description or _description(model),
        source=str(model.source),
        metadata_path=meta.path,
        gaits=gaits,
        notes=tuple(notes),
        view=meta.view or "follow",
    )


def _grid(model: Model, meta: Metadata, notes: list) -> tuple[tuple, float, list]:
    """The default grid and cell size: stated, else from the model; and what is wrong."""
    cell_size = meta.grid.get("cell_size")
    if cell_size is None:
        cell_size, note = defaults.cell_size(model)
        notes.append(note)
    resolution = meta.grid.get("resolution")
    if resolution is None:
        resolution, note = defaults.resolution(model, cell_size)
        notes.append(note)
    return tuple(resolution), float(cell_size), _grid_problems(model, resolution, cell_size)


def _shipped_gaits(model: Model, spec: GaitSpec, meta: Metadata) -> tuple[dict, list]:
    """The shipped gaits as vectors, and what is wrong with them."""
    gaits, problems = {}, []
    for name, entry in meta.gaits.items():
        where = at(at("gaits", name), "params")
        own = maneuver_spec(spec, model, name) if name in MANEUVERS else spec
        free_period = _own_period(own, entry["params"])
        if free_period and name in MANEUVERS:
            problems.append(
                f"{where}: a gait with its own period ('period' among its parameters, from "
                f"aquagait optimize --free-period) is kept under another name than "
                f"{', '.join(MANEUVERS)}: those share the gait's period of {spec.period:g} s, "
                "as the path follower switches between them at whole cycles"
            )
            continue
        own = own.with_free_period() if free_period else own
        x, wrong = _params(own, entry["params"], where)
        if not wrong:
            limits = dof_limits(model, own.dofs)
            wrong = [f"{where}: the gait {p}" for p in gait_problems(own, x, *limits)]
        problems += wrong
        gaits[name] = ShippedGait(x, entry["provenance"], free_period)
    return gaits, problems


def _own_period(spec: GaitSpec, params) -> bool:
    """Whether shipped ``params`` (by name) set the period the gait ``spec`` fixes."""
    return isinstance(params, dict) and "period" in params and not spec.free_period


def _default_gait(model, spec, meta, gaits, notes) -> np.ndarray:
    """The shipped straight gait, else a small travelling wave (``defaults.gait_vector``)."""
    if "straight" in gaits:
        return gaits["straight"].params
    x = defaults.gait_vector(spec)
    notes.append(
        f"no shipped gait: a travelling wave, amplitude up to {defaults.WAVE_AMPLITUDE:g} rad, "
        f"{defaults.WAVE_LAG:g} rad of phase lag per joint"
    )
    wrong = gait_problems(spec, x, *dof_limits(model, spec.dofs))
    if wrong:
        _raise(meta.path, [f"gait: the default gait {wrong[0]}; ship a 'straight' gait"])
    return x


def _energy_bound(model, spec, meta, notes) -> float:
    """The stated energy bound, else ``defaults.energy_bound`` at the gait's period."""
    if meta.energy_bound is not None:
        return meta.energy_bound
    bound = defaults.energy_bound(model, spec.period)
    notes.append(
        f"energy bound {defaults.ENERGY_COEFFICIENT:g} m (L/T)^2 = {bound:.3g} J over two cycles"
    )
    return bound


# --- the gait ------------------------------------------------------------------


def _gait_spec(model: Model, meta: Metadata, notes: list) -> tuple[GaitSpec | None, list]:
    g = meta.gait
    actuated = actuated_dof_names(model)
    dofs = g.get("dofs", actuated)
    problems = []
    unknown = [d for d in dofs if d not in actuated]
    if unknown:
        verb = "is not an actuated DOF" if len(unknown) == 1 else "are not actuated DOFs"
        problems.append(
            f"gait.dofs: {', '.join(unknown)} {verb} of {model.source} (metadata for "
            "another model?); its actuated DOFs are "
            f"{', '.join(actuated)} (a ball joint's axes as name:x, name:y, name:z)"
        )
    for i, triple in enumerate(g.get("mirror", ())):
        problems += [
            f"gait.mirror[{i}][{j}]: {d!r} is not a gait DOF ({', '.join(dofs)})"
            for j, d in enumerate(triple[:2])
            if d not in dofs
        ]
    for i, group in enumerate(g.get("groups", ())):
        problems += [
            f"gait.groups[{i}][{j}]: {d!r} is not a gait DOF ({', '.join(dofs)})"
            for j, d in enumerate(group)
            if d not in dofs
        ]
    for key in g.get("bounds", {}):
        dof = key.partition("[")[2][:-1]
        if dof and dof not in dofs:
            problems.append(
                f"{at('gait.bounds', key)}: {dof!r} is not a gait DOF ({', '.join(dofs)})"
            )
    if problems:
        return None, problems
    free, shared = g.get("free", ("amplitude", "phase")), g.get("shared", ())
    fixed = {k: g[k] for k in ("amplitude", "phase", "period", "offset") if k in g}
    try:
        bounds = _bounds(model, g, dofs, free, shared, notes)
        spec = GaitSpec(
            dofs=dofs,
            free=free,
            shared=shared,
            mirror=g.get("mirror", ()),
            groups=g.get("groups", ()),
            bounds=bounds,
            **fixed,
        )
    except ValueError as err:
        return None, [f"gait: {err}"]
    if "dofs" not in g or "free" not in g:
        notes.append(f"gait: {defaults.gait_note(spec, model)}")
    return spec, []


def _bounds(model, g, dofs, free, shared, notes) -> dict:
    """Default bounds of the free kinds, overridden by the metadata's (module doc)."""
    given = g.get("bounds", {})
    bounds = {}
    from_limits = [k for k in ("amplitude", "offset") if k in free and k not in given]
    if from_limits:
        limits = defaults.amplitude_bounds(
            model, dofs, g.get("mirror", ()), free, shared, g.get("offset", 0.0)
        )
        bounds = {k: v for k, v in limits.items() if k.partition("[")[0] in from_limits}
        notes.append(f"bounds from the joint limits: {_show(bounds)}")
    if "phase" in free:
        bounds["phase"] = (-math.pi, math.pi)
    for key, value in sorted(given.items(), key=lambda kv: "[" in kv[0]):  # kinds first
        if "[" not in key:
            bounds = {k: v for k, v in bounds.items() if k.partition("[")[0] != key}
        bounds[key] = value
    return bounds


def _params(spec: GaitSpec, params, where: str) -> tuple[np.ndarray, list]:
    if isinstance(params, dict):
        missing = [n for n in spec.names if n not in params]
        unknown = [n for n in params if n not in spec.names]
        if missing or unknown:
            return np.zeros(0), [
                f"{where}: "
                + "; ".join(
                    [f"missing {', '.join(missing)}"] * bool(missing)
                    + [f"unknown {', '.join(unknown)}"] * bool(unknown)
                )
                + f"; the gait's parameters are {', '.join(spec.names)}"
            ]
        return np.array([params[n] for n in spec.names], dtype=float), []
    if len(params) != spec.size:
        return np.zeros(0), [
            f"{where}: {len(params)} numbers; the gait has {spec.size}: {', '.join(spec.names)}"
        ]
    return np.array(params, dtype=float), []


def _grid_problems(model: Model, resolution, cell_size) -> list[str]:
    if len(resolution) != model.dim:
        axes = "[nx, ny]" if model.dim == 2 else "[nx, ny, nz]"
        return [f"grid.resolution: {list(resolution)} for a {model.dim}D model; give {axes}"]
    need = smallest_grid(model, cell_size)
    if any(n < m for n, m in zip(resolution, need, strict=True)):
        return [
            f"grid.resolution: {list(resolution)} cells of {cell_size:g} m cannot hold the body "
            f"with {CLEARANCE} cells of water on every side around its centre of mass; "
            f"use at least {[max(n, m) for n, m in zip(resolution, need, strict=True)]}, "
            "or a larger cell_size"
        ]
    return []


def _description(model: Model) -> str:
    return (
        f"{Path(model.source).name}: {model.dim}D, {len(model.links)} links, "
        f"{len(model.actuated_dofs)} actuated DOFs, {model.body_length:.3g} m long"
    )


def _show(bounds: dict) -> str:
    return ", ".join(f"{k} [{lo:.3g}, {hi:.3g}]" for k, (lo, hi) in bounds.items())


def _raise(path: Path | None, problems: list[str]) -> None:
    if not problems:
        return
    label = str(path) if path else "metadata"
    if len(problems) == 1:
        raise CreatureError(f"{label}: {problems[0]}")
    raise CreatureError(
        f"{label}: {len(problems)} problems:\n" + "\n".join(f"  {p}" for p in problems)
    )
