"""Swim a library creature with a gait and keep the run on disk (docs/swim.md).

    setup = prepare_swim("eel2d", gait="runs/eel2d-optimize/gait.json", seconds=2.0)
    run = run_swim(setup, progress=lambda done, total: ...)
    write_swim(run, "runs/eel2d", video=True)   # config.json, gait.json, trajectory.npz,
                                                 # metrics.json, swim.mp4

``prepare_swim`` resolves and checks every setting before anything is
simulated and fails with a ``SwimSetupError`` that says what was wrong;
with ``keep_course=True`` it also measures the creature's learned
manoeuvres, with which the swim keeps to the line ahead of its start
(``aquagait.app.course``: a share of a manoeuvre mixed into the gait at
each cycle's start, as path following does);
``run_swim`` simulates and measures; ``write_swim`` writes the run directory
and, if asked, the video (``aquagait.viz``, the ``viz`` extra).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from datetime import UTC, datetime
from pathlib import Path

import numpy as np

from aquagait.app.course import Course, SteeringError, prepare_course
from aquagait.app.errors import SetupError
from aquagait.app.render import draw_swim, picture_look
from aquagait.app.resolve import creature_key, find_creature, find_gait
from aquagait.control.gait import SineGait
from aquagait.creatures import Creature, CreatureError
from aquagait.io.gait import write_gait
from aquagait.io.run import library_versions, write_run
from aquagait.metrics import (
    SETTLED,
    NoSteadyWindow,
    attitude_metrics,
    cruise_metrics,
    steady_metrics,
    travel_metrics,
)
from aquagait.sim import (
    FRAMES_PER_SECOND,
    Scene,
    Trajectory,
    growth_notes,
    init_state,
    make_scene,
    rollout,
)


class SwimSetupError(SetupError):
    """A swim cannot start: unknown creature, bad gait file, bad grid or fluid."""


@dataclass(frozen=True, eq=False)
class SwimSetup:
    """Everything a swim needs, resolved and checked.

    Attributes:
        creature: the library creature.
        params: (n,) gait parameter vector (``spec.names``).
        gait_source: 'default' or the gait file it came from.
        scene: the scene (fluid, grid).
        seconds: simulated time [s].
        dt: largest time step [s], or None for ``rollout``'s default.
        fps: frames per second recorded.
        maneuver: the manoeuvre the gait swims (its parameterization: ``spec``).
        look: how its video is drawn (``aquagait.app.render.picture_look``).
        free_period: the gait's period is among its parameters (``spec``).
        course: keep to the line ahead of the start with these manoeuvres
            (``aquagait.app.course``), or None: the gait alone, open loop.
    """

    creature: Creature
    params: np.ndarray
    gait_source: str
    scene: Scene
    seconds: float
    dt: float | None = None
    fps: float = FRAMES_PER_SECOND
    maneuver: str = "straight"
    look: dict = field(default_factory=dict)
    free_period: bool = False
    course: Course | None = None

    @property
    def spec(self):
        """The gait's parameterization (``Creature.spec``)."""
        return self.creature.spec(self.maneuver, self.free_period)

    @property
    def gait(self) -> SineGait:
        """The gait the swim drives its servo with."""
        return self.spec.unpack(self.params)

    @property
    def period(self) -> float:
        """The gait's cycle T [s] (the longest, if the DOFs' periods differ)."""
        return float(np.max(self.gait.period))


@dataclass(frozen=True, eq=False)
class SwimRun:
    """A finished swim: its ``setup``, ``trajectory``, ``metrics`` and resolved ``config``.

    ``notes`` says what could not be measured (e.g. a swim shorter than two
    cycles has no steady speed or Strouhal number) and, if it kept its course, how it
    steered; ``grid_notes`` when and how the body outgrew its grid, which grew
    (``aquagait.sim.GridGrew``).
    """

    setup: SwimSetup
    trajectory: Trajectory
    metrics: dict
    config: dict
    notes: tuple[str, ...] = field(default=())
    grid_notes: tuple[str, ...] = field(default=())


def prepare_swim(
    name: str,
    gait=None,
    seconds: float = 2.0,
    fluid: str = "euler",
    resolution=None,
    cell_size: float | None = None,
    dt: float | None = None,
    fps: float = FRAMES_PER_SECOND,
    maneuver: str | None = None,
    view: str | None = None,
    wake: str | None = None,
    size=None,
    keep_course: bool = False,
    progress=None,
) -> SwimSetup:
    """Resolve a swim's settings: creature, gait, scene.

    Args:
        name: a library creature (``aquagait.creatures.names()``) or the path
            of an MJCF file (with its ``.aquagait.json`` side-car, if any).
        gait: a ``gait.json`` path, the name of a gait shipped in the creature's
            side-car (``hand-set``, ``optimized``, a manoeuvre's), a parameter
            vector, or None for the creature's default gait.
        seconds: simulated time [s], > 0.
        fluid: 'euler', 'simple' or 'none' (see ``aquagait.make_scene``).
        resolution: cells per axis, default the creature's.
        cell_size: h [m], default the creature's.
        dt: largest time step [s], default ``rollout``'s.
        fps: frames per second recorded.
        maneuver: swim this learned manoeuvre's shipped gait (``turn-left``, ...)
            instead of the default one; not with ``gait``.
        view: the camera of a 3D swim's video (``picture_look``); default the
            creature's view.
        wake: the wake a 3D swim's video draws, 'both' (default), 'q' (vortex surfaces)
            or 'traces'.
        size: a 3D swim's video's width and height; default 1280x720.
        keep_course: keep to the line ahead of the start (+x) by mixing shares of the
            creature's learned manoeuvres into the gait (``aquagait.app.course``); each
            manoeuvre's turn a cycle is measured first, by a two-cycle swim.
        progress: ``progress(manoeuvre) -> progress(done, total)`` for those swims, or None.

    Raises:
        SwimSetupError: the message says which setting is wrong and what would be right
            (with ``keep_course``: a creature with no learned manoeuvre, a gait that is
            itself a manoeuvre or sets its own period).
    """
    try:
        creature = find_creature(name)
    except SetupError as err:
        raise SwimSetupError(str(err)) from None
    free_period = False
    if maneuver is not None:
        if gait is not None:
            raise SwimSetupError("give a gait or a manoeuvre, not both")
        try:
            params = creature.maneuver_gait(maneuver)
        except (CreatureError, ValueError) as err:
            raise SwimSetupError(str(err)) from None
        source = f"shipped {maneuver}"
    elif isinstance(gait, str | Path):
        try:
            params, source, maneuver, free_period = find_gait(creature, gait)
        except SetupError as err:
            raise SwimSetupError(str(err)) from None
    else:
        maneuver = "straight"
        params = creature.default_gait if gait is None else np.asarray(gait, dtype=float)
        source = "default" if gait is None else "given"
        if params.shape != (creature.gait.size,):
            raise SwimSetupError(
                f"{name} has {creature.gait.size} gait parameters "
                f"({', '.join(creature.gait.names)}); got {params.size}"
            )
    check_times(seconds, fps, dt, SwimSetupError)
    try:
        scene = make_scene(creature, resolution=resolution, cell_size=cell_size, fluid=fluid)
    except ValueError as err:
        raise SwimSetupError(str(err)) from None
    try:
        look = picture_look(creature.model, view, wake, size, creature.view)
    except SetupError as err:
        raise SwimSetupError(str(err)) from None
    setup = SwimSetup(creature, params, source, scene, float(seconds), dt, float(fps), maneuver,
                      look, free_period)  # fmt: skip
    if not keep_course:
        return setup
    if maneuver != "straight" or free_period:
        gait_is = "sets its own period (--free-period)" if free_period else f"is {maneuver}"
        raise SwimSetupError(
            "keeping a course mixes manoeuvres into a straight gait of the shipped period; "
            f"this gait {gait_is}: swim a straight gait, or swim without keeping a course"
        )
    try:
        course = prepare_course(creature, scene, setup.gait, setup.period, progress)
    except SteeringError as err:
        raise SwimSetupError(str(err)) from None
    return replace(setup, course=course)


def check_times(seconds: float, fps: float, dt: float | None, error: type[SetupError]) -> None:
    """Refuse a swim's ``seconds`` [s], ``fps`` [1/s] or ``dt`` [s] (None: the default) that is
    not a positive number, with ``error``."""
    for value, what in ((seconds, "seconds"), (fps, "fps")) + ((dt, "dt"),) * (dt is not None):
        if not (np.isfinite(value) and value > 0):
            raise error(f"{what} must be a positive number, got {value!r}")


def run_swim(setup: SwimSetup, progress=None) -> SwimRun:
    """Simulate the swim from the reference pose at rest and measure it.

    Args:
        setup: from ``prepare_swim``.
        progress: optional ``progress(frames_done, frames_total)`` after every frame.

    Raises:
        aquagait.sim.SimulationError: the simulation cannot go on (it blew up, or
            the body outgrew the grid; time and place in the message).
    """
    creature, scene = setup.creature, setup.scene
    gait = setup.gait
    policy, plan = creature.servo(gait), None
    if setup.course is not None:
        policy, plan = None, setup.course.follower(scene, gait, creature.servo, setup.period)
    steps = {} if setup.dt is None else {"dt": setup.dt}
    with growth_notes() as grew:
        trajectory = rollout(scene, init_state(scene), policy, setup.seconds, fps=setup.fps,
                             progress=progress, plan=plan, **steps)  # fmt: skip
    metrics, notes = measure(creature.model, trajectory, setup.period)
    config = swim_config(setup, trajectory)
    if plan is not None:
        shares = {name: float(np.mean([d.shares.get(name, 0.0) for d in plan.decisions]))
                  for name in setup.course.maneuvers}  # fmt: skip
        metrics["course_shares"] = shares
        mean = ", ".join(f"{name} {share:.2f}" for name, share in shares.items())
        notes += (f"kept its course with its manoeuvres, mixed in at mean shares of {mean}",)
    return SwimRun(setup, trajectory, metrics, config, notes, tuple(grew))


def measure(model, trajectory: Trajectory, period: float) -> tuple[dict, tuple[str, ...]]:
    """A swim's metrics (``aquagait.metrics``): all that its length allows, and notes on
    what it does not (no steady window, not settled at cruise)."""
    metrics = travel_metrics(model, trajectory, period)
    try:
        metrics.update(steady_metrics(model, trajectory, period))
    except NoSteadyWindow as err:
        return metrics, (str(err),)
    metrics.update(cruise_metrics(model, trajectory, period))
    metrics.update(attitude_metrics(model, trajectory, period))
    if metrics["settled"]:
        return metrics, ()
    why = unsettled(metrics["cycle_distances"])
    return metrics, (f"{why}; no cruise figures: swim longer (--seconds)",)


def unsettled(distances) -> str:
    """Why a swim has not settled at cruise (``metrics.settled_cycle``), in words, from the
    distance of each of its whole cycles [m], (n,)."""
    d = distances
    why = f"not yet at cruising speed after {len(d)} cycle(s)"
    if len(d) >= 3:
        change = abs(d[-1] - d[-3]) / d[-1] if d[-1] > 0 else float("inf")
        why += f": the last cycle swam {d[-1]:.3g} m, {change:.1%} off the one two before"
    return f"{why} (settled: within {SETTLED:.0%})"


def swim_config(setup: SwimSetup, trajectory: Trajectory) -> dict:
    """Every resolved setting of a swim, for ``config.json``."""
    return run_config("swim", setup.creature, setup.scene, trajectory, {
        "gait": {
            "source": setup.gait_source,
            "maneuver": setup.maneuver,
            "names": list(setup.spec.names),
            "params": setup.params,
        },
        "period": setup.period,
        "seconds": setup.seconds,
        "keep_course": None if setup.course is None else {"rates": dict(setup.course.rates)},
    })  # fmt: skip


def run_config(command: str, creature: Creature, scene: Scene, trajectory: Trajectory,
               settings: dict) -> dict:  # fmt: skip
    """``config.json`` of a run of ``command``: its own ``settings``, then what every run
    records (creature, fluid and grid, steps and frames, PD gains, library versions, date)."""
    grid = scene.grid
    return {
        "command": command,
        "creature": creature.name,
        "creature_source": creature_key(creature),
        "dim": creature.dim,
        **settings,
        "fluid": scene.fluid.name,
        "fluid_settings": scene.fluid.settings(),
        "density": scene.density,
        "resolution": None if grid is None else list(grid.shape),
        "cell_size": None if grid is None else grid.cell_size,
        "grid_origin": None if grid is None else list(grid.origin),
        "dt": trajectory.dt,
        "fps": trajectory.fps,
        "frames": len(trajectory.time),
        "pd": {"natural_frequency": creature.natural_frequency, "damping": creature.damping_ratio},
        "seed": None,  # a swim is deterministic
        "versions": library_versions(),
        "created": datetime.now(UTC).isoformat(timespec="seconds"),
    }


def write_swim(run: SwimRun, out, video: bool = False, extra_config=None, progress=None) -> Path:
    """Write the run directory: config.json (with the run's notes), gait.json,
    trajectory.npz, metrics.json.

    Args:
        run: from ``run_swim``.
        out: the run directory (created if missing).
        video: also render ``swim.mp4`` (the ``viz`` extra; 3D also ``render``),
            after the run's files are written.
        extra_config: entries added to ``config.json`` (e.g. the optimization's settings).
        progress: optional ``progress(frames_done, frames_total)`` while rendering.

    Raises:
        aquagait.viz.gl.RenderUnavailable: a 3D video and no OpenGL; the run's
            files are written, the message says what to install.
    """
    creature = run.setup.creature
    notes = [*run.grid_notes, *run.notes]
    config = {**run.config, "notes": notes, **(extra_config or {})}
    out = write_run(out, run.trajectory, config, run.metrics, model=creature.model)
    write_gait(out / "gait.json", creature, run.setup.params, run.setup.maneuver,
               run.setup.free_period)  # fmt: skip
    if video:
        look = run.setup.look or picture_look(creature.model, default_view=creature.view)
        draw_swim(run.trajectory, creature.model, out / "swim.mp4", progress=progress, **look)
    return out


def swim_summary(run: SwimRun, out=None) -> str:
    """A few lines for people: how far and fast, at what cost, where the files are."""
    m, setup = run.metrics, run.setup
    lines = [
        f"{setup.creature.name} swam {m['distance']:.3f} m in {m['duration']:.2f} s "
        f"({setup.scene.fluid.name} fluid), from rest: {m['speed_from_rest']:.3f} m/s, "
        f"{m['body_lengths_per_cycle_from_rest']:.2f} body lengths per cycle"
    ]
    if m.get("settled"):
        lines.append(
            f"at cruise from cycle {m['settled_cycle']:.0f} ({m['cruise_start']:g}-"
            f"{m['cruise_end']:g} s): {m['cruise_speed']:.3f} m/s, "
            f"{m['cruise_body_lengths_per_cycle']:.2f} body lengths per cycle, Strouhal number "
            f"{m['cruise_strouhal']:.3g}, cost of transport {m['cruise_cost_of_transport']:.3g} "
            "J/(kg m)"
        )
    elif "steady_speed" in m:
        lines.append(
            f"steady over {m['steady_start']:g}-{m['steady_end']:g} s: {m['steady_speed']:.3f} "
            f"m/s, {m['steady_body_lengths_per_cycle']:.2f} body lengths per cycle, "
            f"Strouhal number {m['strouhal']:.3g}"
        )
    lines.append(
        f"energy {m['energy']:.3g} J, cost of transport {m['cost_of_transport']:.3g} J/(kg m)"
    )
    if "roll" in m:
        lines.append(
            f"attitude over the last cycle: heading {m['heading']:+.1f}, pitch "
            f"{m['pitch']:+.1f}, roll {m['roll']:+.1f} deg (largest pitch {m['max_pitch']:.1f}, "
            f"roll {m['max_roll']:.1f})"
        )
    lines.extend((*run.grid_notes, *run.notes))
    if out is not None:
        files = sorted(p.name for p in Path(out).iterdir() if p.is_file())
        lines.append(f"wrote {out}{'/' if not str(out).endswith('/') else ''}: {', '.join(files)}")
    return "\n".join(lines)
