"""Follow a path with learned manoeuvres and keep the run on disk (paper §5, docs/follow.md).

    setup = prepare_follow("eel2d", "circle:radius=0.6", cycles=12)
    run = run_follow(setup, progress=lambda done, total: ...)
    write_follow(run, "runs/eel2d-circle", video=True)
    # config.json, trajectory.npz, metrics.json, path.csv, maneuvers.csv,
    # path_distance.csv, swim.mp4 (the path in red), follow.png (Figure 10)

The path is a CSV or JSON file of points in metres (``aquagait.path.read_path``)
or a named shape with parameters, ``NAME[:key=value,...]`` (``line``,
``circle``, ``s-curve``; ``aquagait.path.shape``), placed to start at the
root link's starting position and heading along +x, where every library
creature faces. The manoeuvres are the creature's learned ones (its
side-car's ``turn-left``, ``pitch-up``, ...) and any ``gait.json`` of
``aquagait optimize --maneuver`` given as ``learned``.

At the start of every cycle the follower (``aquagait.path.Follower``) mixes
a share of a manoeuvre into the straight gait, by how far the path ahead
bears off the heading and how fast the manoeuvre turns (``steer="graded"``,
the default: ``aquagait.path.rule``, which gives the figures that chose it);
each manoeuvre's turn a cycle is measured first, under way: two cycles of
it after two of the straight gait (``aquagait.app.course.turn_rates``). With
``steer="paper"`` it picks one whole manoeuvre or straight by the paper's
rule, with a dead band of ``dead_band`` (by default a tenth of a body
length). Either way a switch blends over a quarter of a cycle. ``open_loop``
swims the straight gait alone along the same path, to measure how far the
creature drifts without following.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path as FilePath

import numpy as np

from aquagait.app.course import (
    DEAD_BAND,
    SteeringError,
    shipped_maneuvers,
    sines,
    turn_rates,
)
from aquagait.app.errors import SetupError
from aquagait.app.render import picture_look
from aquagait.app.resolve import find_creature
from aquagait.app.swim import run_config
from aquagait.creatures import Creature
from aquagait.creatures.creature import STRAIGHT
from aquagait.io.gait import GaitFileError, read_gait
from aquagait.io.run import write_run
from aquagait.metrics import travel_metrics
from aquagait.objectives import MANEUVERS
from aquagait.path import BLEND, Decision, Follower, Path, PathError, parse_path, root_pose
from aquagait.sim import (
    FRAMES_PER_SECOND,
    Scene,
    Trajectory,
    growth_notes,
    init_state,
    make_scene,
    rollout,
)

DEFAULT_CYCLES = 10

SNAPSHOTS = 12
"""At most this many snapshots of the creature (whole cycles apart) in ``follow.png``."""
SNAPSHOT_SPACING = 0.75
"""Body lengths the creature moves, on average, between two snapshots in ``follow.png``."""

NEEDED = {1: ("turn-left", "turn-right"), 2: ("pitch-up", "pitch-down")}
"""Per axis across the root frame (y, z), the manoeuvres that correct it."""

STEERING = ("paper", "graded")
"""How the follower turns: the paper's rule (one whole manoeuvre a cycle, or straight) or
graded (a share of a manoeuvre mixed into the straight gait: ``aquagait.path.rule``)."""


class FollowSetupError(SetupError):
    """A path cannot be followed: a bad path, an unlearned manoeuvre, a bad grid or setting."""


@dataclass(frozen=True, eq=False)
class FollowSetup:
    """Everything a path following needs, resolved and checked.

    Attributes:
        creature: the creature.
        scene: the scene (fluid, grid).
        path: the path, in world coordinates [m].
        path_source: the file or shape it came from.
        gaits: the manoeuvre library, ``{name: (spec, params, source)}``.
        cycles: gait cycles swum.
        period: the gait cycle T [s].
        dead_band: the follower's ``eps`` [m].
        blend: share of a cycle a switch blends over.
        open_loop: swim straight only (to measure the drift).
        fps: frames per second recorded.
        steer: one of ``STEERING``.
        rates: graded steering's ``{manoeuvre: its turn a cycle}`` [rad]
            (``turn_rates``); None by the paper's rule or open loop.
    """

    creature: Creature
    scene: Scene
    path: Path
    path_source: str
    gaits: dict
    cycles: int
    period: float
    dead_band: float
    blend: float = BLEND
    open_loop: bool = False
    fps: float = FRAMES_PER_SECOND
    steer: str = "graded"
    rates: dict | None = None

    @property
    def seconds(self) -> float:
        return self.cycles * self.period


@dataclass(frozen=True, eq=False)
class FollowRun:
    """A finished path following: ``setup``, ``trajectory``, the follower's ``decisions``,
    the root's ``distance`` to the path per frame [m], ``metrics`` and ``config``."""

    setup: FollowSetup
    trajectory: Trajectory
    decisions: list[Decision]
    distance: np.ndarray
    metrics: dict
    config: dict
    notes: tuple[str, ...] = field(default=())


def prepare_follow(
    name: str,
    path,
    cycles: int = DEFAULT_CYCLES,
    learned=(),
    resolution=None,
    cell_size: float | None = None,
    dead_band: float | None = None,
    blend: float = BLEND,
    open_loop: bool = False,
    fps: float = FRAMES_PER_SECOND,
    fluid: str = "euler",
    steer: str = "graded",
    progress=None,
) -> FollowSetup:
    """Resolve a path following: creature, manoeuvres, path, scene.

    Args:
        name: a library creature or the path of an MJCF file.
        path: a CSV or JSON file of points [m], a ``NAME[:key=value,...]`` shape,
            or an ``aquagait.path.Path``.
        cycles: gait cycles to swim, >= 1.
        learned: ``gait.json`` files (or ``aquagait optimize`` run directories)
            of manoeuvres, added to (or replacing) the creature's shipped ones.
        resolution, cell_size: the fluid grid; default the creature's made roomier
            (``roomy_grid``: square in 2D, the cross-section a quarter larger in 3D).
        dead_band: the rule's ``eps`` [m]; default a tenth of a body length.
        blend: share of a cycle over which a switch blends, in [0, 1].
        open_loop: swim the straight gait only, to measure the drift.
        fps: frames per second recorded.
        fluid: 'euler', 'simple' or 'none' (``aquagait.make_scene``).
        steer: 'graded' (the default) or 'paper' (the paper's rule): ``STEERING``.
        progress: ``progress(manoeuvre) -> progress(done, total)``, for the swims that
            measure graded steering's rates (``turn_rates``), or None.

    Raises:
        FollowSetupError: what is wrong and what would be right: the path (too
            few points, not numbers, the wrong dimension, far from the start),
            a manoeuvre the path needs that the creature has not learned (the
            learned ones and the command that learns it), one that does not turn
            its way (graded), a bad grid or setting.
    """
    try:
        creature = find_creature(name)
    except SetupError as err:
        raise FollowSetupError(str(err)) from None
    if int(cycles) != cycles or cycles < 1:
        raise FollowSetupError(f"cycles must be a whole number >= 1, got {cycles!r}")
    if not 0 <= blend <= 1:
        raise FollowSetupError(f"blend is a share of a cycle in [0, 1], got {blend!r}")
    if steer not in STEERING:
        raise FollowSetupError(f"steer is one of {', '.join(STEERING)}; got {steer!r}")
    gaits = maneuver_library(creature, learned)
    if resolution is None:
        resolution = roomy_grid(creature.resolution)
    try:
        scene = make_scene(creature, resolution=resolution, cell_size=cell_size, fluid=fluid)
    except ValueError as err:
        raise FollowSetupError(str(err)) from None
    position, _ = root_pose(scene, init_state(scene).qpos)
    length = creature.model.body_length
    try:
        path, source = parse_path(path, creature.dim, position)
        path.check_start(position, length)
    except PathError as err:
        raise FollowSetupError(str(err)) from None
    eps = DEAD_BAND * length if dead_band is None else float(dead_band)
    if not eps >= 0:
        raise FollowSetupError(f"dead band must be >= 0 m, got {dead_band!r}")
    if not open_loop:
        _check_learned(creature, gaits, path, position, eps)
    spec, x, _ = gaits[STRAIGHT]
    period = float(np.max(spec.unpack(x).period))
    graded = steer == "graded" and not open_loop
    try:
        library = sines(gaits)
        rates = (turn_rates(creature, scene, library[STRAIGHT], library, period, progress)
                 if graded else None)  # fmt: skip
    except SteeringError as err:
        raise FollowSetupError(f"{err}, or follow by the paper's rule (--steer paper)") from None
    return FollowSetup(creature, scene, path, source, gaits, int(cycles), period, eps,
                       float(blend), bool(open_loop), float(fps), steer, rates)  # fmt: skip


def roomy_grid(resolution) -> tuple[int, ...]:
    """The grid a manoeuvring creature follows on: in 2D square (a turning body needs room
    whichever way it faces), in 3D the cross-section a quarter larger (multiples of 8: a
    pitching or turning body spans more than its straight swim's grid allows)."""
    if len(resolution) == 2:
        return (max(resolution),) * 2
    nx, ny, nz = resolution
    return nx, *(int(8 * np.ceil(1.25 * n / 8)) for n in (ny, nz))


def run_follow(setup: FollowSetup, progress=None) -> FollowRun:
    """Swim along the path, choosing a manoeuvre every cycle, and measure how close it kept.

    Raises:
        aquagait.sim.SimulationError: the simulation cannot go on.
    """
    creature, scene = setup.creature, setup.scene
    library = {STRAIGHT: setup.gaits[STRAIGHT]} if setup.open_loop else setup.gaits
    follower = Follower(scene, sines(library), creature.servo, setup.path, setup.period,
                        setup.dead_band, setup.blend, rates=setup.rates)  # fmt: skip
    with growth_notes() as grew:
        trajectory = rollout(scene, init_state(scene), None, setup.seconds, fps=setup.fps,
                             progress=progress, plan=follower)  # fmt: skip
    positions = np.array([root_pose(scene, q)[0] for q in trajectory.qpos])
    distance = np.array([setup.path.distance(p) for p in positions])
    metrics = travel_metrics(creature.model, trajectory, setup.period)
    length = creature.model.body_length
    along = _progress(setup.path, positions, length)  # not the callback ``progress``
    end = _end_frame(setup.path, along)
    followed = distance[: end + 1]
    for label, value in (("mean", followed.mean()), ("max", followed.max()),
                         ("final", followed[-1])):  # fmt: skip
        metrics[f"path_distance_{label}"] = float(value)
        metrics[f"path_distance_{label}_body_lengths"] = float(value / length)
    metrics["path_progress"] = float(along[-1])
    metrics["path_progress_body_lengths"] = float(along[-1] / length)
    finished = end < len(positions) - 1
    metrics["path_finished"] = bool(finished)
    metrics["path_followed_seconds"] = float(trajectory.time[end] - trajectory.time[0])
    unlearned = sum(d.unlearned for d in follower.decisions)
    metrics["unlearned_requests"] = unlearned
    notes = tuple(grew)
    if unlearned:
        wanted = sorted({d.wanted for d in follower.decisions if d.unlearned})
        notes += (f"{unlearned} cycle(s) asked for {', '.join(wanted)}, not learned: "
                 "swum straight instead",)  # fmt: skip
    if finished:
        notes += (f"reached the path's end at {trajectory.time[end]:.3g} s, "
                  f"{setup.seconds - trajectory.time[end]:.3g} s before the swim's: the "
                  "distances to the path are measured until then",)  # fmt: skip
    config = follow_config(setup, trajectory)
    return FollowRun(setup, trajectory, follower.decisions, distance, metrics, config, notes)


def _progress(path: Path, positions, body_length: float) -> np.ndarray:
    """How far along ``path`` [m] each of the root's ``positions`` (frames, dim) lies, followed
    frame by frame (within a body length of the frame before): a closed path's end is its
    start again, and a lap is not read as its start."""
    progress, along = np.empty(len(positions)), 0.0
    for k, position in enumerate(positions):
        along = progress[k] = path.progress(position, around=along, reach=body_length)
    return progress


def _end_frame(path: Path, progress) -> int:
    """The frame at which the root first reached the path's end (the last frame if it did
    not): beyond it, the creature has no path left to follow."""
    reached = np.flatnonzero(progress >= path.length * (1 - 1e-9))
    return int(reached[0]) if len(reached) else len(progress) - 1


def follow_config(setup: FollowSetup, trajectory: Trajectory) -> dict:
    """Every resolved setting of a path following, for ``config.json``."""
    return run_config("follow", setup.creature, setup.scene, trajectory, {
        "path": setup.path_source,
        "path_points": len(setup.path.points),
        "path_length": setup.path.length,
        "maneuvers": {
            name: {"names": list(spec.names), "params": x, "source": source}
            for name, (spec, x, source) in setup.gaits.items()
        },
        "open_loop": setup.open_loop,
        "cycles": setup.cycles,
        "period": setup.period,
        "seconds": setup.seconds,
        "dead_band": setup.dead_band,
        "blend": setup.blend,
        "steer": setup.steer,
        "rates": setup.rates,
    })  # fmt: skip


def write_follow(run: FollowRun, out, video: bool = False, progress=None) -> FilePath:
    """Write the run directory: config.json, trajectory.npz, metrics.json, path.csv (the path),
    maneuvers.csv (a row per cycle), path_distance.csv (a row per frame); with ``video`` also
    swim.mp4 with the path drawn and follow.png, the creature's snapshots along the path
    (``snapshot_every``).

    Raises:
        aquagait.viz.gl.RenderUnavailable: a 3D picture and no OpenGL; the run's
            files are written, the message says what to install.
    """
    creature = run.setup.creature
    config = {**run.config, "notes": list(run.notes)}
    out = write_run(out, run.trajectory, config, run.metrics, model=creature.model)
    axes = "xyz"[: creature.dim]
    _write_csv(out / "path.csv", [f"{a}_m" for a in axes], run.setup.path.points)
    _write_csv(
        out / "maneuvers.csv",
        ["cycle", "time_s", "maneuver", "wanted", "share"]
        + [f"offset_{a}_m" for a in axes] + [f"tangent_{a}" for a in axes],
        [[k, d.time, d.maneuver, d.wanted, d.shares.get(d.maneuver, 0.0), *d.offset,
          *d.tangent] for k, d in enumerate(run.decisions)],
    )  # fmt: skip
    _write_csv(out / "path_distance.csv", ["time_s", "distance_m"],
               np.stack([run.trajectory.time, run.distance], axis=1))  # fmt: skip
    if video:
        from aquagait.viz.follow import draw_follow, render_follow

        look = picture_look(creature.model, default_view=creature.view) if creature.dim == 3 else {}
        render_follow(run.trajectory, creature.model, run.setup.path.points, out / "swim.mp4",
                      progress=progress, **look)  # fmt: skip
        draw_follow(run.trajectory, creature.model, run.setup.path.points, out / "follow.png",
                    every=snapshot_every(run))  # fmt: skip
    return out


def snapshot_every(run: FollowRun) -> int:
    """Frames between ``follow.png``'s snapshots: whole cycles, enough that the creature has
    moved ``SNAPSHOT_SPACING`` body lengths on average (a slow swimmer is not drawn over
    itself), and no more than ``SNAPSHOTS`` snapshots."""
    setup = run.setup
    per_cycle = max(run.metrics["path_progress_body_lengths"] / setup.cycles, 1e-9)
    cycles = max(np.ceil(setup.cycles / SNAPSHOTS), np.ceil(SNAPSHOT_SPACING / per_cycle))
    return max(1, int(round(setup.period * run.trajectory.fps)) * int(min(cycles, setup.cycles)))


def follow_summary(run: FollowRun, out=None) -> str:
    """A few lines for people: how close it kept to the path, which manoeuvres it swam
    (graded: in how many cycles, and their mean share there)."""
    m, setup = run.metrics, run.setup
    mean, top, final = (m[f"path_distance_{k}_body_lengths"] for k in ("mean", "max", "final"))
    shares = {}
    for d in run.decisions:
        shares.setdefault(d.maneuver, []).append(d.shares.get(d.maneuver, 1.0))
    graded = setup.rates is not None
    swum = [f"{name} x{len(s)}" + (f" (mean share {np.mean(s):.2f})"
                                   if graded and name != STRAIGHT else "")
            for name, s in shares.items()]  # fmt: skip
    mode = "open loop (straight only)" if setup.open_loop else f"following ({setup.steer})"
    lines = [
        f"{setup.creature.name}, {mode}, {setup.cycles} cycles along {setup.path_source} "
        f"({setup.path.length:.3g} m): distance to the path mean {mean:.2f}, max {top:.2f}, "
        f"final {final:.2f} body lengths; {m['path_progress']:.3g} m along it",
        "manoeuvres: " + ", ".join(swum),
        *run.notes,
    ]
    if out is not None:
        files = sorted(p.name for p in FilePath(out).iterdir() if p.is_file())
        lines.append(f"wrote {out}: {', '.join(files)}")
    return "\n".join(lines)


# --- what to follow, and with what -------------------------------------------


def maneuver_library(creature: Creature, learned) -> dict:
    """``{manoeuvre: (spec, params, source)}``: the shipped manoeuvres, then the learned ones
    (``gait.json`` files or run directories; each replaces a shipped one of its name).

    Raises:
        FollowSetupError: a learned file that cannot be read, is another creature's, or
            sets its own period.
    """
    gaits = shipped_maneuvers(creature)
    for item in learned:
        file = FilePath(item)
        file = file / "gait.json" if file.is_dir() else file
        try:
            gait = read_gait(file, creature)
        except GaitFileError as err:
            raise FollowSetupError(str(err)) from None
        if gait.free_period:
            raise FollowSetupError(
                f"{file} sets its own period (searched with --free-period); the follower "
                "switches between gaits at whole cycles of the one period they share: learn "
                "the manoeuvres without --free-period"
            )
        gaits[gait.maneuver] = (creature.spec(gait.maneuver), gait.params, str(file))
    return gaits


def _check_learned(creature: Creature, gaits: dict, path: Path, start, eps: float) -> None:
    """Refuse a path that needs manoeuvres the creature has not learned."""
    spread = np.ptp(np.vstack([path.points, start]), axis=0)
    if creature.dim == 2:
        needed = NEEDED[1]  # in the plane every drift is corrected by turning
    else:
        needed = sum((NEEDED[axis] for axis in (1, 2) if spread[axis] > eps), ())
    missing = [m for m in needed if m not in gaits]
    if missing:
        have = ", ".join(n for n in MANEUVERS if n in gaits)
        learn = "; ".join(
            f"aquagait optimize {creature.name} --maneuver {m} "
            f"--out runs/{creature.name}-{m}-optimize"
            for m in missing
        )
        raise FollowSetupError(
            f"following this path needs {', '.join(missing)}, which {creature.name} has not "
            f"learned (it has learned: {have}). Learn them with: {learn}; then pass the runs "
            "with --learned"
        )


def _write_csv(path: FilePath, header: list, rows) -> None:
    lines = [",".join(header)]
    for row in rows:
        lines.append(",".join(f"{v:.9g}" if isinstance(v, float | np.floating) else str(v)
                              for v in row))  # fmt: skip
    path.write_text("\n".join(lines) + "\n")
