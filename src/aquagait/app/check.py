"""Check a creature before swimming it: its table, and its body on the default grid.

docs/own-creature.md, "Check a creature", says what it prints and writes.

    setup = prepare_check("eel2d")              # or the path of an MJCF file; CheckSetupError
    report = run_check(setup)                   # the numbers, warnings for thin links
    print(format_check(report))                 # the table
    write_check(report, "runs/eel2d-check")     # check.txt, check.json, voxels.png

The table lists the links (mass, volume, size, thickness in mm and in cells
of the default grid, solid cells at the reference pose), the DOFs with their
limits, PD gains and each servo's inertia, natural frequency and damping
ratio in a vacuum and in water (``aquagait.sim.inertia``), the gait's
parameters, the default grid, the energy bound and the loader's notes. The
picture (the paper's Figure 5) shows the body voxelized at the reference
pose on the default grid, so a user sees whether thin fins survive
voxelization.

Volume: each geom's own (closed forms for primitives, the divergence theorem
over a mesh's triangles, the same triangles MuJoCo's mass uses), summed per
link as MuJoCo sums masses, so ``density = mass / volume`` is the geoms'
density (water, 1000 kg/m^3, in the library).

Thin links: ``link_thickness`` (the largest inscribed ball, from the baked
signed distance) underestimates by up to about one sample spacing ``s``
(``h / 4``, finer where a link is under three samples thick:
``resolving_shape``); a link measured below ``2 h - s`` is thinner than about
two cells and gets a warning: the fluid sees it only through partly open
faces (``aquagait.body.subcell``; on the staircase its cell centres fall in
and out of it as it moves). The table says how much of each link's volume
the sub-cell faces see.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from aquagait.app.check_text import format_check, mm
from aquagait.app.errors import SetupError
from aquagait.app.resolve import creature_key, find_creature
from aquagait.body.geometry import link_volumes
from aquagait.body.shape import BodyShape, body_shape, link_thickness
from aquagait.body.subcell import voxelize_subcell
from aquagait.body.voxelize import Voxels, voxelize
from aquagait.control.pd import apparent_inertia, gains, servo_figures
from aquagait.creatures import Creature
from aquagait.creatures.creature import STRAIGHT
from aquagait.grid import Grid
from aquagait.io.run import read_json, write_json
from aquagait.sim import CLEARANCE, Scene, make_scene
from aquagait.sim.follow import cells_for, check_room, room, widest_box
from aquagait.sim.inertia import inertia_in_fluid

THIN_CELLS = 2.0
"""A link should be at least this many cells thick (docs/own-creature.md, "Check a creature")."""

NEUTRAL = (0.8, 1.25)
"""A body whose mass is outside these multiples of the water it displaces gets a warning."""

FINEST_REFINE = {2: 32, 3: 8}
"""Most signed-distance samples per cell (per axis) ``resolving_shape`` bakes, 2D and 3D."""


class CheckSetupError(SetupError):
    """A check cannot start: an unknown creature, or a file that is not a usable creature."""


@dataclass(frozen=True, eq=False)
class CheckSetup:
    """What a check looks at: the creature, and its scene on the default grid.

    Attributes:
        creature: the resolved creature.
        scene: ``make_scene(creature, fluid="none")``: the default grid placed
            as every job places it (centred on the centre of mass), and the
            links' signed distance at its cell size (``scene.shape``).
    """

    creature: Creature
    scene: Scene

    @property
    def grid(self) -> Grid:
        return self.scene.grid


@dataclass(frozen=True, eq=False)
class CheckReport:
    """A finished check.

    Attributes:
        setup: from ``prepare_check``.
        numbers: everything ``check.json`` holds, plain JSON values (see ``run_check``).
        shape: the links' signed distance at the default cell size, sampled
            finely enough to resolve thin links (``resolving_shape``): their
            thickness and the picture's outlines come from it.
        voxels: the body voxelized at the reference pose on the default grid.
        link_pos: (nl, 3) link origins at the reference pose [m].
        link_rot: (nl, 3, 3) link rotations at the reference pose.
    """

    setup: CheckSetup
    numbers: dict
    shape: BodyShape
    voxels: Voxels
    link_pos: np.ndarray
    link_rot: np.ndarray

    @property
    def warnings(self) -> list[str]:
        return self.numbers["warnings"]


def prepare_check(name_or_path) -> CheckSetup:
    """Resolve the creature (a library name, the path of an MJCF file, or a ``Creature``).

    Raises:
        CheckSetupError: an unknown name, or a file that is not a usable creature
            (the message says what is wrong and what would be right).
    """
    if isinstance(name_or_path, Creature):
        creature = name_or_path
    else:
        try:
            creature = find_creature(name_or_path)
        except SetupError as err:
            raise CheckSetupError(str(err)) from None
    try:
        scene = make_scene(creature, fluid="none")
    except ValueError as err:
        raise CheckSetupError(f"{creature.name}: {err}") from None
    return CheckSetup(creature, scene)


def run_check(setup: CheckSetup) -> CheckReport:
    """Measure the creature: links, DOFs, gait, grid, clearance; warn about thin links.

    ``numbers`` holds: ``creature``, ``description``, ``source``, ``dim``,
    ``depth`` [m] (2D), ``forward`` (3,) the head's direction in the file's frame
    (``Model.forward``), ``mass`` [kg], ``displaced`` (the mass of the water the
    body displaces) [kg], ``body_length`` [m], ``links`` (per link: ``name``,
    ``mass`` [kg], ``volume`` [m^3], ``density`` [kg/m^3], ``buoyancy`` (its
    mass over that of the water it displaces),
    ``size`` (3,) [m], ``thickness`` [m], ``thickness_cells``,
    ``solid_cells``, ``voxel_fraction``: the volume of its staircase cells over
    its volume, ``seen_fraction``: the volume the sub-cell faces see over its
    volume), ``thinnest``, ``root``, ``dofs``, ``gait``, ``grid``,
    ``clearance``, ``energy_bound`` [J], ``energy_weight`` [1/J], ``pd``, ``notes``
    and ``warnings``.
    """
    creature, grid = setup.creature, setup.grid
    model = creature.model
    link_pos, link_rot = setup.scene.dynamics.link_poses(model.qpos0)
    voxels = voxelize(setup.scene.shape, grid, link_pos, link_rot)  # the staircase's cells
    fractions = voxelize_subcell(setup.scene.shape, grid, link_pos, link_rot)  # what the fluid sees
    shape = resolving_shape(model, setup.scene.shape)
    links = _links(creature, shape, voxels, fractions, setup.scene.density)
    numbers = {
        "creature": creature.name,
        "description": creature.description,
        "source": str(model.source),
        "library": creature_key(creature) == creature.name,
        "dim": model.dim,
        "depth": model.depth,
        "mass": float(model.mass),
        "displaced": sum(r["volume"] for r in links) * setup.scene.density,
        "body_length": float(model.body_length),
        "forward": list(model.forward),
        "links": links,
        "volume_from": "geoms",
        "thinnest": _thinnest(links),
        "root": _root(model),
        "dofs": _dofs(creature, _inertia_in_water(creature)),
        "gait": _gait(creature),
        "grid": _grid(creature, grid),
        "clearance": _clearance(creature, setup.scene),
        "energy_bound": float(creature.energy_bound),
        "energy_weight": float(creature.energy_weight),
        "pd": {
            "natural_frequency": creature.natural_frequency,
            "damping_ratio": creature.damping_ratio,
            "about": "each DOF's inertia in a vacuum, 1/(M^-1)_ii at the reference pose",
        },
        "notes": [*model.notes, *creature.notes],
    }
    numbers["warnings"] = _warnings(numbers, shape)
    return CheckReport(setup, numbers, shape, voxels, link_pos, link_rot)


# --- the numbers ------------------------------------------------------------------


def resolving_shape(model, shape: BodyShape) -> BodyShape:
    """``shape`` baked again, finer, when a link is under about three samples thick.

    ``link_thickness`` is good to about one sample spacing, and a part
    thinner than a spacing may hold no sample at all (no outline, thickness
    0); so the spacing is brought to a quarter of the thinnest link's
    thickness bound (measured + one spacing), at most ``FINEST_REFINE``
    samples per cell. The library's creatures need no rebaking.
    """
    h, s = shape.cell_size, shape.spacing
    solid = shape.dims[:, 0] > 0
    if not solid.any():
        return shape
    wanted = (link_thickness(shape)[solid].min() + s) / 4
    refine = min(math.ceil(h / wanted - 1e-9), FINEST_REFINE[shape.dim])
    if refine * s <= h * (1 + 1e-9):
        return shape
    try:
        return body_shape(model, h, refine)
    except ValueError:  # too many samples for a large link: keep the coarser measure
        return shape


def _links(creature: Creature, shape: BodyShape, voxels: Voxels, fractions: Voxels,
           water: float) -> list[dict]:  # fmt: skip
    """Per link: mass, volume, density and its ratio to ``water``'s [kg/m^3], box size,
    thickness, solid cells and what they hold, and the share of its volume the fluid
    sees through the sub-cell faces."""
    model, h = creature.model, shape.cell_size
    volume = link_volumes(model)
    thickness = link_thickness(shape)
    cell_volume = h**model.dim * (model.depth or 1.0)
    seen = _seen_volumes(fractions, len(model.links)) * cell_volume
    rows = []
    for k, name in enumerate(model.links):
        cells = int(np.count_nonzero(voxels.owner == k))
        mass, v = float(model.link_mass[k]), float(volume[k])
        rows.append({
            "name": name,
            "mass": mass,
            "volume": v,
            "density": mass / v if v > 0 else None,
            "buoyancy": mass / (v * water) if v > 0 else None,
            "size": (shape.bounds[k, 1] - shape.bounds[k, 0]).tolist(),
            "thickness": float(thickness[k]),
            "thickness_accuracy": shape.spacing,
            "thickness_cells": float(thickness[k] / h),
            "solid_cells": cells,
            "voxel_fraction": cells * cell_volume / v if v > 0 else None,
            "seen_fraction": float(seen[k]) / v if v > 0 else None,
        })  # fmt: skip
    return rows


def _seen_volumes(fractions: Voxels, nlinks: int) -> np.ndarray:
    """Each link's volume in cells as the sub-cell faces normal to x see it: its
    shares of the coupled faces, plus the faces between two cells with no water
    that it owns (the lower cell's owner)."""
    seen = np.zeros(nlinks)
    x = fractions.face_axis == 0
    np.add.at(seen, fractions.face_link[x], fractions.face_share[x])
    solid, owner = fractions.solid, fractions.owner
    inside = solid[:-1] & solid[1:]
    np.add.at(seen, owner[:-1][inside], 1.0)
    return seen


def _thinnest(links: list[dict]) -> dict | None:
    solid = [row for row in links if row["volume"] > 0]
    if not solid:
        return None
    row = min(solid, key=lambda r: r["thickness"])
    return {"link": row["name"], "thickness": row["thickness"], "cells": row["thickness_cells"]}


def _root(model) -> dict:
    root = [model.dof_names[d] for d in model.root_dofs]
    kind = "planar: slide x, slide y, hinge z" if model.planar else "free joint"
    if model.planar and model.dim == 3:
        kind += ", held to its plane in the 3D fluid"
    return {"kind": kind, "dofs": root}


def _dofs(creature: Creature, water: np.ndarray | None) -> list[dict]:
    """Per actuated DOF: joint kind, limits [rad], PD gains, what drives it, and its
    servo's inertia, natural frequency and damping ratio in a vacuum and in ``water``
    (each DOF's inertia there, ``_inertia_in_water``; None: not measured)."""
    model, gait = creature.model, creature.gait
    kp, kd = gains(model, creature.natural_frequency, creature.damping_ratio)
    vacuum = apparent_inertia(model)
    in_water = servo_figures(kp, kd, water) if water is not None else None
    kind = {j.dof + i: j.kind for j in model.joints for i in range(j.nv)}
    mirror = {dof: (source, sign) for dof, source, sign in gait.mirror}
    rows = []
    for i, d in enumerate(model.actuated_dofs):
        name = model.dof_names[d]
        driven = name in gait.dofs
        if name in mirror:
            driven = f"{mirror[name][1]:+g} x {mirror[name][0]}"
        rows.append({
            "name": name, "kind": kind[int(d)],
            "lower": float(model.lower[i]), "upper": float(model.upper[i]),
            "kp": float(kp[d]), "kd": float(kd[d]),
            "gait": "yes" if driven is True else (driven or "no"),
            "inertia": float(vacuum[d]),
            "inertia_water": None if water is None else float(water[d]),
            "natural_frequency_water": None if in_water is None else float(in_water[0][d]),
            "damping_ratio_water": None if in_water is None else float(in_water[1][d]),
        })  # fmt: skip
    return rows


def _inertia_in_water(creature: Creature) -> np.ndarray | None:
    """Each DOF's inertia ``1/((M + M_a)^-1)_ii`` in the Euler fluid on the default grid at
    the reference pose (``aquagait.sim.inertia``), (nv,); None where that grid cannot hold
    the body (the clearance line says why)."""
    try:
        scene = make_scene(creature, fluid="euler")
    except ValueError:
        return None
    water = np.full(creature.model.nv, np.nan)
    dofs = creature.model.actuated_dofs
    water[dofs] = inertia_in_fluid(scene, dofs=dofs)
    return water


def _gait(creature: Creature) -> dict:
    spec = creature.gait
    fixed = {k: getattr(spec, k) for k in ("amplitude", "phase", "period", "offset")}
    return {
        "names": list(spec.names),
        "lower": spec.lower.tolist(),
        "upper": spec.upper.tolist(),
        "default": creature.default_gait.tolist(),
        "free": list(spec.free),
        "fixed": {k: float(v) for k, v in fixed.items() if k not in spec.free},
        "shared": list(spec.shared),
        "mirror": [[dof, source, float(sign)] for dof, source, sign in spec.mirror],
        "groups": [list(g) for g in spec.groups],
    }


def _grid(creature: Creature, grid: Grid) -> dict:
    extent = np.asarray(grid.shape) * grid.cell_size
    return {
        "resolution": list(grid.shape),
        "cell_size": float(grid.cell_size),
        "origin": list(grid.origin),
        "extent": extent.tolist(),
        "extent_body_lengths": (extent / creature.model.body_length).tolist(),
    }


def _clearance(creature: Creature, scene: Scene) -> dict:
    """Does the default grid hold the body with the Euler fluid's clearance (``make_scene``),
    at rest and at its shipped gait's widest pose (``widest_box``)?"""
    model, grid = creature.model, scene.grid
    water = float(room(grid, model.bounds[:, : model.dim]).min())
    try:
        check_room(model, grid, CLEARANCE)  # what make_scene(..., fluid="euler") asks
        error = None
    except ValueError as err:
        error = str(err)
    sides = widest_box(scene, creature.spec(STRAIGHT).unpack(creature.default_gait))
    swimming = (np.asarray(grid.shape) - sides / grid.cell_size) / 2  # centred, per axis
    needed = np.maximum(grid.shape, cells_for(sides, grid.cell_size, CLEARANCE))
    return {
        "cells": CLEARANCE, "room": water, "holds": error is None, "error": error,
        "gait_box": sides.tolist(), "gait_room": float(swimming.min()),
        "gait_resolution": needed.tolist(),
    }  # fmt: skip


def _warnings(numbers: dict, shape: BodyShape) -> list[str]:
    """A warning per link thinner than about two cells, and one if the grid is too small."""
    h, s = shape.cell_size, shape.spacing
    out = []
    for k, row in enumerate(numbers["links"]):
        if row["volume"] > 0 and row["thickness"] < THIN_CELLS * h - s:
            out.append(_thin_warning(row, shape, k, numbers["grid"]))
    ratio = numbers["mass"] / numbers["displaced"]
    if not NEUTRAL[0] <= ratio <= NEUTRAL[1]:
        out.append(
            f"the body's mass, {numbers['mass']:.4g} kg, is {ratio:.2f}x that of the "
            f"{numbers['displaced']:.4g} kg of water it displaces: the water here has no gravity, "
            "so the body neither sinks nor floats, but its mass sets how far the water's push "
            f"moves it ({'a light body is moved more' if ratio < 1 else 'a heavy one coasts'}"
            "); the library's creatures have water's density"
        )
    c = numbers["clearance"]
    if not c["holds"]:
        out.append(f"the default grid is too small: {c['error']}")
    elif c["gait_room"] < c["cells"]:
        out.append(
            f"the default grid is too narrow for the shipped gait: its widest pose "
            f"({' x '.join(f'{x:.3g}' for x in c['gait_box'])} m) leaves {c['gait_room']:.1f} "
            f"cells of water, fewer than {c['cells']}, so a swim would stop (BodyOutsideGrid); "
            f"use at least {'x'.join(map(str, c['gait_resolution']))} cells (--resolution)"
        )
    return out


def _thin_warning(row: dict, shape: BodyShape, k: int, grid: dict) -> str:
    h, s = shape.cell_size, shape.spacing
    t = row["thickness"]
    if t < s:  # below what the samples resolve: the box's thinnest side bounds it
        sides = np.asarray(row["size"])[: shape.dim]
        t = float(sides.min())
        measured = f"thinner than the {mm(s)} signed-distance spacing (its box: {mm(t)})"
    else:
        measured = f"{mm(t)} thick, {t / h:.2f} cells of {mm(h)}"
    finer = t / THIN_CELLS
    # thickness is sampled in float32: round a hair down before ceil (128.000003 -> 128)
    cells = "x".join(str(math.ceil(n * h / finer * (1 - 1e-6))) for n in grid["resolution"])
    seen = row["seen_fraction"]
    sees = f"{seen:.0%} of its volume" if seen is not None else "it"
    return (
        f"link {row['name']!r} is {measured}: thinner than about two cells, the fluid sees it "
        f"only through partly open faces ({sees} at the reference pose; {row['solid_cells']} "
        f"cells on a staircase); cells of {mm(finer)} or less keep it two cells thick "
        f"({cells} cells for the same grid extent)"
    )


# --- the table and the files --------------------------------------------------------


def write_check(report: CheckReport, out, picture: bool = True) -> Path:
    """Write ``check.txt`` (the table), ``check.json`` (the numbers) and ``voxels.png``.

    Args:
        report: from ``run_check``.
        out: the directory (created if missing).
        picture: also draw ``voxels.png`` (the ``viz`` extra).
    Returns:
        the directory.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "check.txt").write_text(format_check(report) + "\n")
    write_json(out / "check.json", report.numbers)
    if picture:
        from aquagait.viz import plot_voxels

        plot_voxels(report.shape, report.setup.grid, report.voxels, report.link_pos,
                    report.link_rot, out / "voxels.png", title=_title(report),
                    labels=_labels(report))  # fmt: skip
    return out


def read_check(out) -> dict:
    """The numbers of a check written by ``write_check`` (``check.json``)."""
    return read_json(Path(out) / "check.json")


def _title(report: CheckReport) -> str:
    n, g = report.numbers, report.numbers["grid"]
    cells = "x".join(str(x) for x in g["resolution"])
    return (f"{n['creature']}: the body voxelized at the reference pose on its default grid "
            f"({cells} cells of {g['cell_size'] * 1000:g} mm)")  # fmt: skip


def _labels(report: CheckReport) -> list[str]:
    return [
        f"{r['name']} ({r['thickness_cells']:.2f} cells thick)" for r in report.numbers["links"]
    ]
