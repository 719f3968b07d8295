"""``aquagait optimize``: find a gait with CMA-ES, write it and its log, and swim the best."""

from __future__ import annotations

import os
import sys
from pathlib import Path

from aquagait.cli.errors import fail
from aquagait.cli.flags import (
    FORMATION_DEFAULTS,
    NAME_HELP,
    formation_flags,
    group_members,
    refuse_group_flags,
    thicken_flag,
)
from aquagait.cli.progress import GenerationLine, ProgressBar
from aquagait.cli.swim import swim_and_write
from aquagait.cli.workers import add_evaluator_flags, executor_for
from aquagait.control.gait import FREE_PERIOD
from aquagait.objectives import (
    EFFICIENCY_CYCLES,
    EFFICIENCY_WINDOW,
    MANEUVERS,
    MIN_SPEED_SHARE,
    OBJECTIVES,
    TURN,
)


def add_parser(commands) -> None:
    optimize = commands.add_parser(
        "optimize", help="find a gait with CMA-ES; write gait.json, the log and the best swim"
    )
    optimize.add_argument("name", metavar="NAME",
                          help=f"{NAME_HELP}; or a scene file (SCENE.json) of several creatures, "
                          "one of which is searched (--member)")  # fmt: skip
    thicken_flag(optimize)
    optimize.add_argument("--generations", type=int,
                          help="the most CMA-ES generations (per group); given alone, a fixed "
                          "budget as in the paper (100); default: stop when converged")  # fmt: skip
    optimize.add_argument("--popsize", type=int,
                          help="samples per generation (default: CMA-ES's 4 + 3 ln n for n "
                          "parameters; the paper's: 16 in 2D, 31 in 3D)")  # fmt: skip
    optimize.add_argument("--max-evaluations", type=int, metavar="N",
                          help="stop after N swims in all (default: no cap)")  # fmt: skip
    optimize.add_argument("--surrogate", action="store_true",
                          help="lq-CMA-ES: a quadratic model of the objective ranks each "
                          "generation and only what it cannot vouch for is swum")  # fmt: skip
    optimize.add_argument("--surrogate-batch", type=int, default=2, metavar="N",
                          help="with --surrogate: swim at least N samples at a time; give at "
                          "least --workers (default 2)")  # fmt: skip
    optimize.add_argument("--patience", type=int, metavar="G",
                          help="stop a group when its best improved less than 1%% in G "
                          "generations (default: 10 + 30 n / popsize; off with "
                          "--generations alone)")  # fmt: skip
    add_evaluator_flags(optimize)
    optimize.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    optimize.add_argument("--resolution", type=int, nargs="+", metavar="N",
                          help="cells per axis: NX NY (2D) or NX NY NZ (3D)")  # fmt: skip
    optimize.add_argument("--cell-size", type=float, metavar="H", help="cell size [m]")
    optimize.add_argument("--out", metavar="DIR",
                          help="run directory (default: runs/NAME-optimize, runs/NAME-MANEUVER-"
                          "optimize for a manoeuvre: never a swim's runs/NAME)")  # fmt: skip
    optimize.add_argument("--coarse", type=float, metavar="FACTOR",
                          help="rank samples on a grid FACTOR times coarser and swim each "
                          "generation's best again on the target grid")  # fmt: skip
    optimize.add_argument("--refine-top", type=int, default=2, metavar="K",
                          help="with --coarse: samples a generation swum on the "
                          "target grid (default 2)")  # fmt: skip
    optimize.add_argument("--maneuver", "--manoeuvre", choices=MANEUVERS, default="straight",
                          metavar="NAME",
                          help=f"learn a manoeuvre, one of {', '.join(MANEUVERS)} (default "
                          "straight; paper §5: 2D creatures turn, 3D ones also pitch): "
                          "offsets freed, rotation rewarded")  # fmt: skip
    optimize.add_argument("--turn-limit", type=float, metavar="RAD",
                          help="a manoeuvre: the most rotation about its axis rewarded over "
                          "a sample [rad] (default: the creature's, "
                          f"{TURN:.4g} or 90 degrees unless its side-car says; the manta's "
                          "0.25; smaller, the search buys travel past it)")  # fmt: skip
    optimize.add_argument("--start", "--gait", metavar="FILE|NAME",
                          help="start the search from this gait: a gait.json or a shipped "
                          "gait's name (default: the shipped straight gait); --gait, as in "
                          "swim, is the same")  # fmt: skip
    optimize.add_argument("--step", type=float, metavar="F",
                          help="initial spread of each parameter, a fraction of its range "
                          "(default 0.25; smaller polishes the start)")  # fmt: skip
    optimize.add_argument("--energy-weight", type=float, metavar="W",
                          help="the weight of the actuator work [J] in the objective once "
                          "it passes the energy bound (default: the creature's, 1 unless its "
                          "metadata says)")  # fmt: skip
    optimize.add_argument("--deviation-weight", type=float, metavar="W",
                          help="the weight of the drift [m] and turning [rad] in the "
                          "objective (default 0.2, the paper's; heavier, with more --cycles, "
                          "charges a gait that slowly pitches or turns)")  # fmt: skip
    optimize.add_argument(
        "--objective",
        choices=OBJECTIVES,
        default="distance",
        help="what to minimize: the paper's (distance, the default), or the "
        "cost of transport at cruise at or above --min-speed (efficiency)",
    )
    optimize.add_argument(
        "--min-speed",
        type=float,
        metavar="U",
        help="efficiency: the cruising speed to keep at least [m/s] (default: "
        f"{100 * MIN_SPEED_SHARE:g}%% of the starting gait's)",
    )
    optimize.add_argument("--cycles", type=float, metavar="N",
                          help="gait cycles swum per sample (default 2, the paper's; "
                          f"efficiency: {EFFICIENCY_CYCLES:g}, the last "
                          f"{EFFICIENCY_WINDOW} measured)")  # fmt: skip
    low, high = FREE_PERIOD
    optimize.add_argument("--free-period", action="store_true",
                          help="search the gait's period too, one for every joint, "
                          f"{low:g} to {high:g} times the creature's (straight)")  # fmt: skip
    formation_flags(optimize)
    optimize.add_argument("--member", metavar="LABEL",
                          help="in a group (--formation or a scene file): the creature whose "
                          "gait or phase is searched and scored, the others swimming theirs "
                          "(default: the last, a formation's last follower)")  # fmt: skip
    optimize.add_argument("--search", choices=("gait", "phase"), default="gait",
                          help="in a group: search the member's gait (default) or its phase, "
                          "its lag behind the group's clock in cycles")  # fmt: skip
    optimize.add_argument("--resume", action="store_true", help="continue the run in --out")
    optimize.add_argument("--no-video", action="store_true", help="skip the plot and video")
    optimize.set_defaults(run=run)


def optimization_setup(args):
    """The search ``aquagait optimize``'s parsed ``args`` set up
    (``aquagait.app.prepare_optimization``; raises its ``OptimizationSetupError``)."""
    from aquagait.app import prepare_optimization

    return prepare_optimization(
        args.name,
        generations=args.generations,
        popsize=args.popsize,
        seed=args.seed,
        resolution=args.resolution,
        cell_size=args.cell_size,
        coarse=args.coarse,
        refine_top=args.refine_top,
        maneuver=args.maneuver,
        start=args.start,
        step=args.step,
        energy_weight=args.energy_weight,
        deviation_weight=args.deviation_weight,
        max_evaluations=args.max_evaluations,
        patience=args.patience,
        objective=args.objective,
        min_speed=args.min_speed,
        cycles=args.cycles,
        free_period=args.free_period,
        turn_limit=args.turn_limit,
        surrogate=args.surrogate,
        surrogate_batch=args.surrogate_batch,
    )


def default_directory(name: str, maneuver: str) -> Path:
    """``runs/NAME-optimize`` (``runs/NAME-MANEUVER-optimize``): a search's own, so that a
    later ``swim NAME`` (``runs/NAME``) does not overwrite its gait.json."""
    return Path("runs") / "-".join([name, *([] if maneuver == "straight" else [maneuver]),
                                    "optimize"])  # fmt: skip


def run(args) -> int:
    if args.formation is not None or args.name.endswith(".json"):
        return run_group(args)
    from aquagait.app import SetupError, output_directory

    try:
        refuse_group_flags(args, MEMBER_FLAGS)
        setup = optimization_setup(args)
        out = output_directory(args.out or default_directory(setup.creature.name, args.maneuver))
    except SetupError as err:
        return fail("optimize", err, status=2)
    for note in setup.notes:
        print(f"note: {note}", file=sys.stderr)
    return optimize_and_swim(setup, out, args, video=not args.no_video)


def optimize_and_swim(setup, out: Path, args, video: bool, default_grid=False, seconds=None):
    """Optimize, write gait.json and convergence.png, then swim the best gait.

    Exit status 2 for a mistake in the flags or files; 1, with one line that
    says how to resume, when the executor is lost (a Dask scheduler died, no
    worker for a minute): the checkpoint keeps the last complete generation.
    """
    from aquagait.app import write_optimization
    from aquagait.app.optimize import best_swim, search_notes

    result = search(setup, out, args, setup.creature.name)
    if isinstance(result, int):
        return result
    write_optimization(setup, result, out, plot=video)
    swim = best_swim(setup, out, default_grid=default_grid, seconds=seconds)
    return swim_and_write(swim, out, video, extra_config={"optimization": setup.config()},
                          notes=lambda run: search_notes(setup, run, out))  # fmt: skip


def search(setup, out: Path, args, name: str):
    """Run the search on the flags' evaluator and print its outcome; its ``Result``, or the
    exit status of a failure (``optimize_and_swim``)."""
    from aquagait.app import run_optimization
    from aquagait.optimize import ExecutorLost

    try:
        with executor_for(args) as executor:
            workers = executor.describe() if executor else "1 worker (this process)"
            print(f"optimizing {name}: {setup.problem.size} parameters, {setup.budget()}; "
                  f"{workers}", file=sys.stderr)  # fmt: skip
            _say_if_finished(out, args.resume)
            _say_if_idle(setup.settings, args)
            result = run_optimization(setup, out, executor, args.resume, GenerationLine())
    except ExecutorLost as err:
        return fail("optimize", err, status=1)
    except (FileExistsError, FileNotFoundError, ValueError, ImportError, OSError) as err:
        return fail("optimize", err, status=2)
    start = "" if result.start_f is None else f"; the start: {result.start_f:.4g}"
    if result.start_f is not None and result.best_f == result.start_f:
        start += ", not bettered"
    print(f"best objective {result.best_f:.4g} after {result.evaluations} samples "
          f"({result.stopped}{start})")  # fmt: skip
    return result


GROUP_REFUSES = {
    "maneuver": ("straight", "a group's search is for swimming straight"),
    "turn_limit": (None, "a group's search is for swimming straight"),
    "free_period": (False, "a group keeps each creature's period"),
    "coarse": (None, "a group's search swims on the group's grid"),
}
"""Flags a search inside a group refuses: each one's default and why."""

MEMBER_FLAGS = {"member": None, "search": "gait", **FORMATION_DEFAULTS}
"""Flags only a search inside a group takes, and their defaults."""


def run_group(args) -> int:
    """``aquagait optimize NAME --formation ...`` or ``optimize SCENE.json``: search one
    member's gait or phase in its group, then swim the group with the best."""
    from aquagait.app import RenderUnavailable, SetupError, output_directory
    from aquagait.app.school import run_school, school_summary, write_school
    from aquagait.app.school_search import prepare_school_search, write_school_search
    from aquagait.sim import SimulationError

    try:
        for flag, (default, why) in GROUP_REFUSES.items():
            if getattr(args, flag) != default:
                raise SetupError(f"--{flag.replace('_', '-')} is refused in a group: {why}")
        members, grid, formation, label = group_members(args, args.start, "optimize")
        setup = prepare_school_search(
            members, searched=args.member, search=args.search, objective=args.objective,
            min_speed=args.min_speed, cycles=args.cycles,
            resolution=args.resolution or grid.get("resolution"),
            cell_size=args.cell_size or grid.get("cell_size"), step=args.step,
            formation=formation, generations=args.generations, popsize=args.popsize,
            seed=args.seed, max_evaluations=args.max_evaluations, patience=args.patience,
            energy_weight=args.energy_weight, deviation_weight=args.deviation_weight,
            surrogate=args.surrogate, surrogate_batch=args.surrogate_batch,
        )  # fmt: skip
        out = output_directory(args.out or Path("runs") / f"{label}-{setup.label}-optimize")
    except SetupError as err:
        return fail("optimize", err, status=2)
    for note in setup.search_setup.notes:
        print(f"note: {note}", file=sys.stderr)
    what = f"{setup.label}'s {setup.search} in {label}"
    result = search(setup.search_setup, out, args, what)
    if isinstance(result, int):
        return result
    best = write_school_search(setup, result, out, plot=not args.no_video)
    try:
        run = run_school(best, progress=ProgressBar("swimming the best"))
    except SimulationError as err:
        return fail("optimize", err, status=1)
    config = {"optimization": setup.search_setup.config()}
    try:
        write_school(run, out, not args.no_video, progress=ProgressBar("rendering"),
                     extra_config=config)  # fmt: skip
    except RenderUnavailable as err:
        print(f"aquagait: the video is skipped, the run is kept: {err}", file=sys.stderr)
    print(school_summary(run, out))
    return 0


def _say_if_finished(out: Path, resume: bool) -> None:
    """A resumed run that had already stopped is not searched again: say so."""
    from aquagait.optimize import finished_run

    stopped = finished_run(out) if resume else None
    if stopped is not None:
        print(f"the run in {out} has already stopped ({stopped}): nothing to resume; "
              "its best gait is written and swum again", file=sys.stderr)  # fmt: skip


def _say_if_idle(settings, args) -> None:
    """A surrogate batch smaller than the local worker count leaves workers idle."""
    workers = args.workers or os.cpu_count() or 1  # None: all cores
    if settings.surrogate and not args.scheduler and settings.surrogate_batch < workers:
        print(f"note: --surrogate-batch {settings.surrogate_batch} keeps at most that many "
              f"of the {workers} workers busy; give --surrogate-batch {workers}",
              file=sys.stderr)  # fmt: skip
