"""Swim a group of creatures in one fluid and keep the run on disk (docs/schools.md).

    setup = prepare_school(formation_members("eel2d", "in-line:2", spacing=0.5, phase=0.25))
    members, grid = read_scene_file("pair.json")              # or a scene file
    setup = prepare_school(members, **grid)
    run = run_school(setup, progress=...)
    write_school(run, "runs/eel2d-in-line", video=True)

A group is described by its members, each a ``MemberSpec``: a creature (a
library name or an MJCF path), a label, a pose (offset [m] and heading
[rad] from the creature's reference pose) and a gait (a shipped gait's
name or a ``gait.json``) lagging the group's clock by ``phase`` cycles.
``formation_members`` makes them for a formation of one creature; a scene
file (``read_scene_file``) lists them:

    {"creatures": [
        {"name": "eel2d", "label": "leader"},
        {"name": "eel2d", "label": "follower", "offset": [-0.75, 0, 0], "phase": 0.25,
         "gait": "runs/eel2d-optimize/gait.json"}],
     "cell_size": 0.01}

The group swims as one composed body (``aquagait.body.group``) on one grid
that holds each member's own default grid at its pose
(``aquagait.sim.group.group_grid``), in the finest of their cells. The run
directory is a swim's (``config.json``, ``trajectory.npz`` of the whole
group, ``metrics.json`` with the group's figures, ``swim.mp4`` drawing every
member) plus ``members/LABEL/`` for each member: its own ``trajectory.npz``,
``metrics.json`` and ``gait.json``.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from aquagait.app.errors import SetupError
from aquagait.app.render import draw_swim, picture_look
from aquagait.app.resolve import creature_key, find_creature, find_gait
from aquagait.app.swim import check_times, measure, run_config
from aquagait.body.group import FORMATIONS, Group, GroupError, Pose, compose
from aquagait.body.group import formation as place
from aquagait.control.group import GroupPolicy
from aquagait.creatures import Creature
from aquagait.io.gait import write_gait
from aquagait.io.run import write_run
from aquagait.sim import (
    FRAMES_PER_SECOND,
    Scene,
    Trajectory,
    growth_notes,
    init_state,
    make_scene,
    rollout,
)
from aquagait.sim.group import group_grid, member_trajectory

SCENE_KEYS = {"name", "label", "offset", "heading", "gait", "phase"}
"""What a scene file may say of each creature."""


class SchoolSetupError(SetupError):
    """A group swim cannot start: a bad formation or scene file, creatures that cannot
    share a fluid or that overlap, a bad gait."""


@dataclass(frozen=True)
class MemberSpec:
    """One creature of a group, as asked for.

    Attributes:
        name: a library creature or an MJCF path.
        label: its name in the group; default ``NAME-k``.
        offset: (3,) from its reference pose [m].
        heading: turned about the vertical through its root [rad].
        gait: a shipped gait's name or a gait file; None: the creature's default.
        phase: its gait lags the group's clock by this many of its cycles.
    """

    name: str
    label: str | None = None
    offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    heading: float = 0.0
    gait: str | None = None
    phase: float = 0.0


@dataclass(frozen=True, eq=False)
class SchoolSetup:
    """Everything a group swim needs, resolved and checked.

    Attributes:
        members: the specs, labels filled in.
        creatures: each member's creature.
        params: each member's gait parameters (its ``spec()``'s names).
        sources: where each gait came from.
        group: the composed group.
        scene: its scene (fluid, grid).
        seconds, dt, fps: as a swim's.
        look: how its video is drawn (``picture_look``).
        formation: how the members were made (the command line's words), or None.
    """

    members: tuple[MemberSpec, ...]
    creatures: tuple[Creature, ...]
    params: tuple[np.ndarray, ...]
    sources: tuple[str, ...]
    group: Group
    scene: Scene
    seconds: float
    dt: float | None = None
    fps: float = FRAMES_PER_SECOND
    look: dict = field(default_factory=dict)
    formation: dict | None = None

    def gaits(self):
        """Each member's ``SineGait``, lagged by its phase."""
        found = zip(self.creatures, self.params, self.members, strict=True)
        return [c.spec().unpack(p).lagging(m.phase) for c, p, m in found]

    def period(self, k: int) -> float:
        """Member ``k``'s gait cycle [s]."""
        return float(np.max(self.creatures[k].spec().unpack(self.params[k]).period))


@dataclass(frozen=True, eq=False)
class SchoolRun:
    """A finished group swim: the group's ``trajectory``, each member's ``metrics`` (by
    label) and the group's, the resolved ``config``, notes."""

    setup: SchoolSetup
    trajectory: Trajectory
    metrics: dict
    member_metrics: dict
    config: dict
    notes: tuple[str, ...] = ()


def formation_members(name: str, formation: str, spacing: float = 0.5, phase: float = 0.0,
                      gait: str | None = None) -> list[MemberSpec]:  # fmt: skip
    """The members of a formation of one creature.

    Args:
        name: the creature (a library name or an MJCF path).
        formation: ``in-line``, ``side-by-side`` or ``diamond``, optionally ``:COUNT``
            (default 2, 2 and 4).
        spacing: in body lengths: in line, the clear water between one's tail and
            the next one's head; side by side, between neighbours' axes; in a
            diamond, both (the wings beside the leader's wake, the last behind).
        phase: the gait's lag from one creature to the next [cycles].
        gait: every member's gait (a shipped gait's name or a gait file).

    Raises:
        SchoolSetupError: an unknown formation, a count below 1, a bad spacing.
    """
    kind, _, count = formation.partition(":")
    if kind not in FORMATIONS:
        raise SchoolSetupError(
            f"unknown formation {formation!r}; formations: {', '.join(FORMATIONS)} "
            "(optionally :COUNT, e.g. in-line:3)"
        )
    try:
        n = int(count) if count else FORMATIONS[kind]
    except ValueError:
        n = 0
    if not np.isfinite(phase):
        raise SchoolSetupError(f"phase must be a number of cycles, got {phase}")
    try:
        places = place(kind, n, spacing, find_creature(name).model.body_length)
    except GroupError as err:
        raise SchoolSetupError(f"formation {formation!r}: {err}") from None
    return [MemberSpec(name, None, pose.offset, 0.0, gait, rank * phase) for pose, rank in places]


def read_scene_file(path) -> tuple[list[MemberSpec], dict]:
    """The members of a scene file (module doc), and its grid settings (``resolution``,
    ``cell_size``; either may be absent).

    Raises:
        SchoolSetupError: the file is missing, not JSON, or says something unknown or
            malformed (which creature, which key, what would be right).
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text())
    except OSError as err:
        raise SchoolSetupError(f"scene file {path}: {err.strerror or err}") from None
    except json.JSONDecodeError as err:
        raise SchoolSetupError(f"scene file {path} is not JSON: {err}") from None
    if not isinstance(data, dict) or not isinstance(data.get("creatures"), list):
        raise SchoolSetupError(
            f'scene file {path}: give {{"creatures": [{{"name": ...}}, ...]}}, a list of the '
            f"creatures, each with {', '.join(sorted(SCENE_KEYS))}"
        )
    unknown = set(data) - {"creatures", "resolution", "cell_size"}
    if unknown:
        raise SchoolSetupError(
            f"scene file {path}: unknown keys {', '.join(sorted(unknown))}; known: creatures, "
            "resolution, cell_size"
        )
    members = []
    for k, entry in enumerate(data["creatures"]):
        where = f"scene file {path}, creature {k + 1}"
        if not isinstance(entry, dict) or "name" not in entry:
            raise SchoolSetupError(f"{where}: give an object with at least a name")
        extra = set(entry) - SCENE_KEYS
        if extra:
            raise SchoolSetupError(
                f"{where}: unknown keys {', '.join(sorted(extra))}; known: "
                f"{', '.join(sorted(SCENE_KEYS))}"
            )
        try:
            offset = tuple(float(v) for v in entry.get("offset", (0, 0, 0)))
            heading, phase = float(entry.get("heading", 0.0)), float(entry.get("phase", 0.0))
        except (TypeError, ValueError):
            raise SchoolSetupError(
                f"{where}: offset is 2 or 3 numbers [m], heading [rad] and phase [cycles] are "
                "numbers"
            ) from None
        if len(offset) > 3:
            raise SchoolSetupError(f"{where}: offset is 2 or 3 numbers [m]")
        offset = (*offset, 0.0, 0.0, 0.0)[:3]
        members.append(MemberSpec(str(entry["name"]), entry.get("label"), offset, heading,
                                  entry.get("gait"), phase))  # fmt: skip
    grid = {k: data[k] for k in ("resolution", "cell_size") if k in data}
    return members, grid


def prepare_school(
    members,
    seconds: float = 2.0,
    fluid: str = "euler",
    resolution=None,
    cell_size: float | None = None,
    dt: float | None = None,
    fps: float = FRAMES_PER_SECOND,
    view: str | None = None,
    wake: str | None = None,
    size=None,
    formation: dict | None = None,
) -> SchoolSetup:
    """Resolve a group swim's settings: creatures, gaits, the group, its scene.

    Args:
        members: ``MemberSpec``s (``formation_members``, ``read_scene_file``).
        seconds: simulated time [s], > 0.
        fluid: 'euler', 'simple' or 'none' (see ``aquagait.make_scene``).
        resolution: cells per axis; default a grid that holds each member's own
            default grid at its pose (``aquagait.sim.group.group_grid``).
        cell_size: h [m]; default the finest of the members' cells.
        dt: largest time step [s], default ``rollout``'s.
        fps: frames per second recorded.
        view: a 3D video's camera (``picture_look``); default the first member's view.
        wake: a 3D video's wake, 'both' (default), 'q' or 'traces'.
        size: a 3D video's width and height; default 1280x720.
        formation: how the members were made, recorded in ``config.json``.

    Raises:
        SchoolSetupError: what is wrong and what would be right.
    """
    members = tuple(members)
    if not members:
        raise SchoolSetupError("a group needs at least one creature")
    try:
        creatures = tuple(find_creature(m.name) for m in members)
    except SetupError as err:
        raise SchoolSetupError(str(err)) from None
    params, sources = [], []
    for member, creature in zip(members, creatures, strict=True):
        if member.gait is None:
            params.append(creature.default_gait)
            sources.append("default")
            continue
        try:
            found, source, maneuver, free_period = find_gait(creature, member.gait)
        except SetupError as err:
            raise SchoolSetupError(str(err)) from None
        if maneuver != "straight" or free_period:
            raise SchoolSetupError(
                f"{member.gait}: a group swims straight gaits of the shipped period; this one "
                f"{'sets its own period' if free_period else 'is ' + maneuver}"
            )
        params.append(found)
        sources.append(source)
    check_times(seconds, fps, dt, SchoolSetupError)
    labels = [m.label for m in members]
    try:
        group = compose([c.model for c in creatures], None if None in labels else labels,
                        [Pose(m.offset, m.heading) for m in members])  # fmt: skip
        labels = [m.label for m in group.members]
        members = tuple(MemberSpec(s.name, label, s.offset, s.heading, s.gait, s.phase)
                        for s, label in zip(members, labels, strict=True))  # fmt: skip
        if resolution is None or cell_size is None:
            own = group_grid(group, [c.resolution for c in creatures],
                             [cell_size or c.cell_size for c in creatures])  # fmt: skip
            shape, h, origin = own
            resolution, cell_size = resolution or shape, h
        else:
            origin = None
        scene = make_scene(group, resolution, cell_size, fluid=fluid, origin=origin)
    except (GroupError, ValueError) as err:
        raise SchoolSetupError(str(err)) from None
    try:
        look = picture_look(group.model, view, wake, size, creatures[0].view)
    except SetupError as err:
        raise SchoolSetupError(str(err)) from None
    return SchoolSetup(members, creatures, tuple(params), tuple(sources), group, scene,
                       float(seconds), dt, float(fps), look, formation)  # fmt: skip


def run_school(setup: SchoolSetup, progress=None) -> SchoolRun:
    """Simulate the group from its poses at rest and measure each member and the group.

    Raises:
        aquagait.sim.SimulationError: as a swim's; also two creatures that touched
            (``aquagait.sim.group.CreaturesTouched``).
    """
    servos = [c.servo(g) for c, g in zip(setup.creatures, setup.gaits(), strict=True)]
    policy = GroupPolicy(setup.group, servos)
    steps = {} if setup.dt is None else {"dt": setup.dt}
    scene = setup.scene
    with growth_notes() as grew:
        trajectory = rollout(scene, init_state(scene), policy, setup.seconds, fps=setup.fps,
                             progress=progress, **steps)  # fmt: skip
    member_metrics, notes = {}, list(grew)
    for k, member in enumerate(setup.group.members):
        own = member_trajectory(trajectory, member)
        metrics, why = measure(member.model, own, setup.period(k))
        member_metrics[member.label] = metrics
        notes += [f"{member.label}: {note}" for note in why]
    return SchoolRun(setup, trajectory, group_metrics(setup, member_metrics), member_metrics,
                     school_config(setup, trajectory), tuple(notes))  # fmt: skip


def group_metrics(setup: SchoolSetup, member_metrics: dict) -> dict:
    """The group's figures: its members' mean speed from rest [m/s], total energy [J],
    and cost of transport (all the work over all the mass and the mean distance)."""
    figures = list(member_metrics.values())
    mass = sum(c.model.mass for c in setup.creatures)
    distance = float(np.mean([m["distance"] for m in figures]))
    energy = float(sum(m["energy"] for m in figures))
    return {
        "members": len(figures),
        "duration": figures[0]["duration"],
        "distance": distance,
        "speed_from_rest": float(np.mean([m["speed_from_rest"] for m in figures])),
        "energy": energy,
        "mass": mass,
        "cost_of_transport": energy / (mass * distance) if distance > 0 else float("nan"),
    }


def school_config(setup: SchoolSetup, trajectory: Trajectory) -> dict:
    """Every resolved setting of a group swim, for ``config.json``: a swim's, with
    ``school`` listing each member (its creature, label, pose, gait and phase)."""
    first = setup.creatures[0]
    config = run_config("swim", first, setup.scene, trajectory, {
        "school": {
            "formation": setup.formation,
            "members": [
                {"creature": c.name, "creature_source": creature_key(c), "label": m.label,
                 "offset": list(m.offset), "heading": m.heading, "phase": m.phase,
                 "gait": {"source": s, "names": list(c.spec().names), "params": p}}
                for m, c, p, s in zip(setup.members, setup.creatures, setup.params,
                                      setup.sources, strict=True)
            ],
        },
        "seconds": setup.seconds,
    })  # fmt: skip
    config["creature"] = setup.group.model.source
    del config["creature_source"]  # the members' are in "school"
    return config


def write_school(
    run: SchoolRun, out, video: bool = False, progress=None, extra_config=None
) -> Path:
    """Write the run directory (module doc); with ``video`` also ``swim.mp4``;
    ``extra_config`` joins ``config.json`` (a search's settings).

    Raises:
        aquagait.viz.gl.RenderUnavailable: a 3D video and no OpenGL; the files are written.
    """
    setup = run.setup
    config = {**run.config, **(extra_config or {}), "notes": list(run.notes)}
    out = write_run(out, run.trajectory, config, run.metrics, model=setup.group.model)
    for k, member in enumerate(setup.group.members):
        folder = out / "members" / member.label
        own = member_trajectory(run.trajectory, member)
        settings = {
            "command": "swim",
            "member_of": str(out),
            "label": member.label,
            "creature": setup.creatures[k].name,
            "phase": setup.members[k].phase,
        }
        write_run(folder, own, settings, run.member_metrics[member.label], model=member.model)
        write_gait(folder / "gait.json", setup.creatures[k], setup.params[k])
    if video:
        draw_swim(run.trajectory, setup.group.model, out / "swim.mp4", progress=progress,
                  **setup.look)  # fmt: skip
    return out


def school_summary(run: SchoolRun, out=None) -> str:
    """A few lines for people: each member's travel and cost, the group's, the files."""
    setup, lines = run.setup, []
    for member in setup.members:
        m = run.member_metrics[member.label]
        lines.append(
            f"{member.label} ({member.name}, phase {member.phase:g}): {m['distance']:.3f} m in "
            f"{m['duration']:.2f} s, {m['body_lengths_per_cycle_from_rest']:.2f} body lengths "
            f"per cycle, energy {m['energy']:.3g} J, cost of transport "
            f"{m['cost_of_transport']:.3g} J/(kg m)"
        )
    g = run.metrics
    lines.append(
        f"the group ({setup.scene.fluid.name} fluid): {g['speed_from_rest']:.3f} m/s from rest, "
        f"energy {g['energy']:.3g} J, cost of transport {g['cost_of_transport']:.3g} J/(kg m)"
    )
    lines.extend(run.notes)
    if out is not None:
        files = sorted(p.name for p in Path(out).iterdir() if p.is_file())
        lines.append(f"wrote {out}/: {', '.join(files)}, and members/LABEL/ for each creature")
    return "\n".join(lines)
