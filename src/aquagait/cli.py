"""The ``aquagait`` command line: thin, each flag maps to a library argument."""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import math
import os
import signal
import sys
import threading
import time
from pathlib import Path

import aquagait
from aquagait.bench import BENCHMARKS
from aquagait.control.gait import FREE_PERIOD
from aquagait.objectives import (
    EFFICIENCY_CYCLES,
    EFFICIENCY_WINDOW,
    MANEUVERS,
    MIN_SPEED_SHARE,
    OBJECTIVES,
    TURN,
)
from aquagait.sim import FLUIDS

CONVERGED = math.inf
"""``compare --optimize`` with no count: no generation count, each search runs until it has
converged (not a string: argparse would pass it through ``int``)."""

NAME_HELP = "a library creature (see: aquagait creatures) or the path of an MJCF file"
GAIT_HELP = (
    "a gait.json, or the name of a gait the creature ships (hand-set, optimized, turn-left, "
    "...; default: its shipped straight gait)"
)


def _cmd_bench(args) -> int:
    from aquagait.bench import run_benchmark

    try:
        run_benchmark(args.what, repeats=args.repeats, out=sys.stdout, profile=args.profile,
                      compare_advection=args.compare_advection,
                      compare_precision=args.compare_precision,
                      compare_boundary=args.compare_boundary,
                      compare_start=args.compare_start,
                      compare_thin=args.compare_thin,
                      creature=args.creature, seeds=args.seeds)  # fmt: skip
    except (ValueError, KeyError) as err:  # KeyError: an unknown creature
        return _fail("bench", err, status=2)
    return 0


def _cmd_creatures(args) -> int:
    from aquagait import creatures

    print(creatures.format_table())
    return 0


def _cmd_check(args) -> int:
    from aquagait.app import SetupError, output_directory, prepare_check
    from aquagait.app.check import format_check, run_check, write_check

    try:
        setup = prepare_check(args.name)
        out = output_directory(args.out or Path("runs") / f"{setup.creature.name}-check")
    except SetupError as err:
        return _fail("check", err, status=2)
    report = run_check(setup)
    write_check(report, out, picture=not args.no_picture)
    files = ["check.txt", "check.json"] + ["voxels.png"] * (not args.no_picture)
    print(format_check(report))
    if args.convergence:
        files += _convergence(setup.creature, args.seconds, out)
    print(f"\nwrote {out}/: {', '.join(files)}")
    return 0


def _convergence(creature, seconds: float, out: Path) -> list[str]:
    """Run and write the step, grid and domain study (``aquagait.app.convergence``)."""
    from aquagait.app.convergence import (
        CASES,
        convergence_study,
        format_convergence,
        write_convergence,
    )

    print(
        f"\nconvergence: {creature.name}'s default gait, {seconds:g} s from rest, "
        f"{len(CASES)} swims"
    )
    study = convergence_study(
        creature,
        seconds,
        progress=lambda swim: print(
            f"  {swim.case.label}: {swim.distance:.4f} m ({swim.seconds:.0f} s)", flush=True
        ),
    )
    print(f"\n{format_convergence(study)}")
    return write_convergence(study, out)


def _look_flags(parser) -> None:
    """--view, --wake and --size: how a 3D swim is drawn (``aquagait.app.render.picture_look``)."""
    from aquagait.app.render import VIEWS, WAKES

    parser.add_argument("--view", choices=VIEWS,
                        help="3D camera (default: the creature's own view, e.g. follow: "
                        "behind, beside and above; the manta's front-above)")  # fmt: skip
    parser.add_argument("--wake", choices=WAKES,
                        help="3D wake: q (vortex surfaces), traces (particle traces) or both "
                        "(default)")  # fmt: skip
    parser.add_argument("--size", type=int, nargs=2, metavar=("W", "H"),
                        help="3D picture size in pixels (default 1280 720)")  # fmt: skip


def _cmd_swim(args) -> int:
    from aquagait.app import SetupError, output_directory, prepare_swim

    try:
        setup = prepare_swim(
            args.name,
            gait=args.gait,
            seconds=args.seconds,
            fluid=args.fluid,
            resolution=args.resolution,
            cell_size=args.cell_size,
            maneuver=args.maneuver,
            view=args.view,
            wake=args.wake,
            size=args.size,
            keep_course=args.keep_course,
            progress=lambda maneuver: ProgressBar(f"measuring {maneuver}"),
        )
        label = setup.creature.name + (f"-{args.maneuver}" if args.maneuver else "")
        out = output_directory(args.out or Path("runs") / label)
    except SetupError as err:
        return _fail("swim", err, status=2)
    return _swim_and_write(setup, out, not args.no_video)


def _swim_and_write(setup, out: Path, video: bool, extra_config=None, notes=None) -> int:
    """Swim a prepared setup, write its run directory and (optionally) its video;
    ``notes(run)``, if given, adds notes on the swim to its config.json and summary."""
    from aquagait.app import RenderUnavailable, run_swim, swim_summary, write_swim
    from aquagait.sim import SimulationError

    try:
        run = run_swim(setup, progress=ProgressBar("swimming"))
    except SimulationError as err:
        return _fail("swim", err, status=1)
    if notes is not None:
        run = dataclasses.replace(run, notes=run.notes + notes(run))
    try:
        write_swim(run, out, video, extra_config, progress=ProgressBar("rendering"))
    except RenderUnavailable as err:
        print(f"aquagait: the video is skipped, the run is kept: {err}", file=sys.stderr)
    print(swim_summary(run, out))
    return 0


def _cmd_follow(args) -> int:
    from aquagait.app import RenderUnavailable, SetupError, output_directory
    from aquagait.app.follow import follow_summary, prepare_follow, run_follow, write_follow
    from aquagait.sim import SimulationError

    try:
        setup = prepare_follow(
            args.name,
            args.path,
            cycles=args.cycles,
            learned=args.learned or (),
            resolution=args.resolution,
            cell_size=args.cell_size,
            dead_band=args.dead_band,
            open_loop=args.open_loop,
            steer=args.steer,
            progress=lambda maneuver: ProgressBar(f"measuring {maneuver}"),
        )
        mode = "open-loop" if args.open_loop else "follow"
        out = output_directory(args.out or Path("runs") / f"{setup.creature.name}-{mode}")
    except SetupError as err:
        return _fail("follow", err, status=2)
    try:
        run = run_follow(setup, progress=ProgressBar("swimming"))
    except SimulationError as err:
        return _fail("follow", err, status=1)
    try:
        write_follow(run, out, video=not args.no_video, progress=ProgressBar("rendering"))
    except RenderUnavailable as err:
        print(f"aquagait: the pictures are skipped, the run is kept: {err}", file=sys.stderr)
    print(follow_summary(run, out))
    return 0


def _cmd_export(args) -> int:
    from aquagait.app import SetupError
    from aquagait.app.export import prepare_export, run_export

    try:
        setup = prepare_export(args.run_dir, args.format, args.out, args.traces)
    except SetupError as err:
        return _fail("export", err, status=2)
    path = run_export(setup)
    print(f"wrote {path}" + "".join(f" ({note})" for note in setup.notes))
    return 0


def _cmd_render(args) -> int:
    from aquagait.app import RenderUnavailable, SetupError, prepare_render, run_render

    try:
        setup = prepare_render(args.run_dir, args.format, args.view, args.frames, args.out,
                               args.wake, args.size)  # fmt: skip
    except SetupError as err:
        return _fail("render", err, status=2)
    try:
        path = run_render(setup, progress=ProgressBar("rendering"))
    except RenderUnavailable as err:
        return _fail("render", err, status=1)
    print(f"wrote {path}")
    return 0


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


def _cmd_optimize(args) -> int:
    from aquagait.app import SetupError, output_directory

    try:
        setup = optimization_setup(args)
        label = setup.creature.name + ("" if args.maneuver == "straight" else f"-{args.maneuver}")
        out = output_directory(args.out or Path("runs") / label)
    except SetupError as err:
        return _fail("optimize", err, status=2)
    for note in setup.notes:
        print(f"note: {note}", file=sys.stderr)
    return _optimize_and_swim(setup, out, args, video=not args.no_video)


def _optimize_and_swim(setup, out: Path, args, video: bool, default_grid=False, seconds=None):
    """Optimize, write gait.json and convergence.png, then swim the best gait.

    Exit status 2 for a mistake in the flags or files; 1, with one line that
    says how to resume, when the executor is lost (a Dask scheduler died, no
    worker for a minute): the checkpoint keeps the last complete generation.
    """
    from aquagait.app import run_optimization, write_optimization
    from aquagait.app.optimize import best_swim, search_notes
    from aquagait.optimize import ExecutorLost

    try:
        with _executor(args) as executor:
            workers = executor.describe() if executor else "1 worker (this process)"
            name, size = setup.creature.name, setup.problem.size
            print(f"optimizing {name}: {size} parameters, {setup.budget()}; {workers}",
                  file=sys.stderr)  # fmt: skip
            _say_if_finished(out, args.resume)
            _say_if_idle(setup.settings, args)
            result = run_optimization(setup, out, executor, args.resume, GenerationLine())
    except ExecutorLost as err:
        return _fail("optimize", err, status=1)
    except (FileExistsError, FileNotFoundError, ValueError, ImportError, OSError) as err:
        return _fail("optimize", err, status=2)
    write_optimization(setup, result, out, plot=video)
    start = "" if result.start_f is None else f"; the start: {result.start_f:.4g}"
    if result.start_f is not None and result.best_f == result.start_f:
        start += ", not bettered"
    print(f"best objective {result.best_f:.4g} after {result.evaluations} samples "
          f"({result.stopped}{start})")  # fmt: skip
    swim = best_swim(setup, out, default_grid=default_grid, seconds=seconds)
    return _swim_and_write(swim, out, video, extra_config={"optimization": setup.config()},
                           notes=lambda run: search_notes(setup, run, out))  # fmt: skip


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


def _executor(args):
    """The evaluator the flags ask for: a Dask cluster, local processes, or this process."""
    from aquagait.optimize import dask_executor, local_executor

    if args.scheduler:
        return dask_executor(args.scheduler)
    if args.workers == 1:
        return contextlib.nullcontext(None)
    return local_executor(args.workers)


def _cmd_demo(args) -> int:
    from aquagait import creatures
    from aquagait.app import SetupError, demo, output_directory

    try:
        setup = demo.prepare_demo(generations=args.generations, seed=args.seed)
        out = output_directory(args.out)
    except SetupError as err:
        return _fail("demo", err, status=2)
    args.resume = args.scheduler = None
    (nx, ny), fine = demo.GRID[0], creatures.get(demo.CREATURE).resolution
    print(f"aquagait demo: CMA-ES finds {demo.CREATURE} a gait on a {nx}x{ny} grid, then it "
          f"swims at {fine[0]}x{fine[1]} into {out}/", file=sys.stderr)  # fmt: skip
    status = _optimize_and_swim(setup, out, args, True, default_grid=True,
                                seconds=demo.SWIM_SECONDS)  # fmt: skip
    if status:
        return status
    print(f"aquagait demo: the {demo.CREATURE_3D} swims its shipped gait in 3D into "
          f"{out}/{demo.CREATURE_3D}/", file=sys.stderr)  # fmt: skip
    return _swim_and_write(demo.prepare_demo_3d(), out / demo.CREATURE_3D, video=True)


def _cmd_compare(args) -> int:
    from aquagait.app import SetupError, output_directory
    from aquagait.app.compare import cross_optimize, forward_distance, swim_both, write_compare
    from aquagait.app.resolve import find_creature
    from aquagait.sim import SimulationError

    grid = dict(resolution=args.resolution, cell_size=args.cell_size)
    given = {"--resume": args.resume, "--start": args.start, "--popsize": args.popsize}
    alone = [flag for flag, value in given.items() if value]
    if alone and args.optimize is None:
        return _fail("compare", f"{', '.join(alone)}: only with --optimize [G]", status=2)
    try:
        name = find_creature(args.name).name
        out = output_directory(args.out or Path("runs") / f"{name}-compare")
        runs = swim_both(args.name, args.gait, args.seconds, progress=_fluid_bar(), **grid)
    except SetupError as err:
        return _fail("compare", err, status=2)
    except SimulationError as err:
        return _fail("compare", err, status=1)
    for fluid, run in runs.items():
        m = run.metrics
        steady = f", {m['steady_body_lengths_per_cycle']:.3f} steady" if "steady_speed" in m else ""
        print(f"{fluid:>7} fluid: {forward_distance(run):+.4f} m along x, "
              f"{m['body_lengths_per_cycle_from_rest']:.3f} body lengths per cycle from rest"
              f"{steady}")  # fmt: skip
        for note in run.grid_notes:
            print(f"        {note}")
    cross = None
    if args.optimize is not None:
        from aquagait.optimize import ExecutorLost

        budget = "until converged" if args.optimize == CONVERGED else f"{args.optimize} generations"
        generations_given = None if args.optimize == CONVERGED else args.optimize

        def generations(fluid):
            print(f"optimizing {name} in the {fluid} fluid ({budget}, "
                  f"run directory {out / f'optimize-{fluid}'})", file=sys.stderr)  # fmt: skip
            return GenerationLine()

        try:
            with _executor(args) as executor:
                cross = cross_optimize(
                    args.name, generations_given, args.seconds, seed=args.seed, executor=executor,
                    out=out, resume=args.resume, start=args.start, popsize=args.popsize,
                    progress=generations, **grid,
                )  # fmt: skip
        except SetupError as err:
            return _fail("compare", err, status=2)
        except (ExecutorLost, SimulationError) as err:  # a trained gait's swim may fail too
            return _fail("compare", err, status=1)
        except (FileExistsError, FileNotFoundError, ValueError, OSError) as err:
            return _fail("compare", err, status=2)
        for trained, swum in cross["distance"].items():
            row = ", ".join(f"in {fluid} {metres:+.4f} m" for fluid, metres in swum.items())
            print(f"gait trained in the {trained} fluid swims {row}")
        for note in cross["notes"]:
            print(f"        {note}")
    from aquagait.app import RenderUnavailable

    try:
        write_compare(runs, out, args.gait, cross, video=not args.no_video,
                      progress=ProgressBar("rendering"))  # fmt: skip
    except RenderUnavailable as err:
        print(f"aquagait: the video is skipped, the runs are kept: {err}", file=sys.stderr)
    print(f"wrote {out}/")
    return 0


def _fluid_bar():
    bars = {}
    return lambda fluid, done, total: bars.setdefault(fluid, ProgressBar(fluid))(done, total)


class GenerationLine:
    """``progress(report)`` of an optimization: one line per generation on stderr.

    The line counts the samples penalized in the generation (failed: the
    simulation raised or gave nan; lost: the worker died; infeasible: outside
    the joint limits). A generation that loses more than an eighth of its
    population (``GenerationReport.lossy``) adds a warning line with the first
    reason; every reason is in the run's failures.csv.
    """

    def __init__(self, stream=None):
        self.stream = stream or sys.stderr

    def __call__(self, report) -> None:
        left = f"{report.remaining:.0f} s left" if math.isfinite(report.remaining) else ""
        planned = "" if report.planned is None else f"/{report.planned}"
        print(
            f"generation {report.generation:>3}{planned}  best {report.best:.4g}  "
            f"mean {report.mean:.4g}  sigma {report.sigma:.3g}  failed {report.failed}  "
            f"lost {report.lost}  infeasible {report.infeasible}  {report.elapsed:.0f} s  {left}",
            file=self.stream,
            flush=True,
        )
        if report.lossy:
            print(
                f"warning: generation {report.generation} lost {report.failures} of "
                f"{report.samples} samples ({report.failed} failed, {report.lost} lost); "
                f"first: {' '.join(report.reasons[0].split())} (all reasons: failures.csv)",
                file=self.stream,
                flush=True,
            )


class ProgressBar:
    """``progress(done, total)`` drawn as a one-line text bar on stderr.

    On a terminal the bar is redrawn in place every call; into a file or a
    pipe (logs, CI) it is written as a new line at every tenth of the work.
    """

    def __init__(self, label: str, width: int = 30, stream=None):
        self.label, self.width, self.stream = label, width, stream or sys.stderr
        self.start = time.perf_counter()
        self.live = getattr(self.stream, "isatty", lambda: False)()
        self.shown = -1

    def __call__(self, done: int, total: int) -> None:
        tenth = 10 * done // max(total, 1)
        if not self.live and tenth == self.shown:
            return
        self.shown = tenth
        filled = self.width * done // max(total, 1)
        elapsed = time.perf_counter() - self.start
        bar = "#" * filled + "-" * (self.width - filled)
        line = f"{self.label} [{bar}] {done}/{total} frames {elapsed:.1f} s"
        if self.live:
            end = "\n" if done >= total else ""
            print(f"\r{line}", end=end, file=self.stream, flush=True)
        else:
            print(line, file=self.stream, flush=True)


def _fail(command: str, err: Exception | str, status: int) -> int:
    print(f"aquagait {command}: error: {err}", file=sys.stderr)
    return status


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``aquagait`` command."""
    parser = argparse.ArgumentParser(
        prog="aquagait",
        description="Discover and simulate swimming gaits for articulated creatures "
        "in an incompressible fluid (Tan et al. 2011).",
    )
    parser.add_argument("--version", action="version", version=f"aquagait {aquagait.__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")

    bench = commands.add_parser("bench", help="measure speed against in-run baselines")
    bench.add_argument("what", choices=BENCHMARKS, help="which benchmark to run")
    bench.add_argument("--repeats", type=int, default=10, help="timed repetitions per case")
    bench.add_argument("--profile", action="store_true", help="swim: time per phase of a step")
    bench.add_argument(
        "--compare-advection", action="store_true", help="swim: old and new advection, one run"
    )
    bench.add_argument(
        "--compare-precision", action="store_true",
        help="swim: float64 and float32 face velocities, one run",
    )  # fmt: skip
    bench.add_argument(
        "--compare-boundary",
        action="store_true",
        help="swim: staircase and sub-cell boundaries, one run",
    )
    bench.add_argument(
        "--compare-start",
        action="store_true",
        help="swim: the step as the 3D-speed work found it beside today's, one run",
    )
    bench.add_argument(
        "--compare-thin",
        action="store_true",
        help="swim: the step before thin parts were closed beside today's, one run",
    )
    bench.add_argument(
        "--creature", metavar="NAME", help="optimize: the creature to time (default eel2d)"
    )
    bench.add_argument("--seeds", type=int, metavar="K",
                       help="optimize: default searches run whole, seeds 1..K (default 3; 0: "
                       "time the samples only)")  # fmt: skip
    bench.set_defaults(run=_cmd_bench)

    creatures = commands.add_parser("creatures", help="list the creature library")
    creatures.set_defaults(run=_cmd_creatures)

    check = commands.add_parser(
        "check", help="a creature's table and its voxels on the default grid; thin-link warnings"
    )
    check.add_argument(
        "name", metavar="NAME|PATH", help="a library creature (aquagait creatures) or an MJCF file"
    )
    check.add_argument("--out", metavar="DIR", help="directory (default: runs/NAME-check)")
    check.add_argument("--no-picture", action="store_true", help="skip voxels.png")
    check.add_argument(
        "--convergence", action="store_true",
        help="also swim the default gait at 1/3 and 1/6 of the step, on 1.5x and 2x finer "
             "grids over the same domain, and with the same cell on a grid 1.5x as large, "
             "and compare the distances (minutes; the frog's, most of an hour)",
    )  # fmt: skip
    check.add_argument("--seconds", type=float, default=2.0,
                       help="with --convergence: seconds swum in each case")  # fmt: skip
    _thicken_flag(check)
    check.set_defaults(run=_cmd_check)

    swim = commands.add_parser(
        "swim", help="swim a creature with a gait; write trajectory, metrics and video"
    )
    swim.add_argument("name", metavar="NAME", help=NAME_HELP)
    _thicken_flag(swim)
    swim.add_argument("--gait", metavar="FILE|NAME", help=GAIT_HELP)
    swim.add_argument("--maneuver", choices=MANEUVERS,
                      help="swim a learned manoeuvre's shipped gait instead")  # fmt: skip
    swim.add_argument("--seconds", type=float, default=2.0, help="simulated time [s]")
    swim.add_argument("--keep-course", action="store_true",
                      help="keep to the line ahead of the start with the creature's learned "
                      "manoeuvres, a share mixed into the gait each cycle (each manoeuvre's "
                      "turn is measured first by a two-cycle swim)")  # fmt: skip
    swim.add_argument("--fluid", choices=list(FLUIDS), default="euler")
    swim.add_argument(
        "--resolution",
        type=int,
        nargs="+",
        metavar="N",
        help="cells per axis: NX NY (2D) or NX NY NZ (3D)",
    )
    swim.add_argument("--cell-size", type=float, metavar="H", help="cell size [m]")
    swim.add_argument("--out", metavar="DIR", help="run directory (default: runs/NAME)")
    swim.add_argument("--no-video", action="store_true", help="skip swim.mp4")
    _look_flags(swim)
    swim.set_defaults(run=_cmd_swim)

    optimize = commands.add_parser(
        "optimize", help="find a gait with CMA-ES; write gait.json, the log and the best swim"
    )
    optimize.add_argument("name", metavar="NAME", help=NAME_HELP)
    _thicken_flag(optimize)
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
    _add_evaluator_flags(optimize)
    optimize.add_argument("--seed", type=int, default=0, help="random seed")
    optimize.add_argument("--resolution", type=int, nargs="+", metavar="N",
                          help="cells per axis: NX NY (2D) or NX NY NZ (3D)")  # fmt: skip
    optimize.add_argument("--cell-size", type=float, metavar="H", help="cell size [m]")
    optimize.add_argument("--out", metavar="DIR", help="run directory (default: runs/NAME)")
    optimize.add_argument("--coarse", type=float, metavar="FACTOR",
                          help="rank samples on a grid FACTOR times coarser and swim each "
                          "generation's best again on the target grid")  # fmt: skip
    optimize.add_argument("--refine-top", type=int, default=2, metavar="K",
                          help="with --coarse: samples a generation swum on the "
                          "target grid")  # fmt: skip
    optimize.add_argument("--maneuver", choices=MANEUVERS, default="straight",
                          help="learn a manoeuvre (paper §5; 2D creatures turn, 3D ones "
                          "also pitch): offsets freed, rotation rewarded")  # fmt: skip
    optimize.add_argument("--turn-limit", type=float, metavar="RAD",
                          help="a manoeuvre: the most rotation about its axis rewarded over "
                          f"a sample [rad] (default {TURN:.4g}, 90 degrees; "
                          "smaller, the search buys travel past it)")  # fmt: skip
    optimize.add_argument("--start", metavar="FILE|NAME",
                          help="start the search from this gait: a gait.json or a shipped "
                          "gait's name (default: the shipped straight gait)")  # fmt: skip
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
    optimize.add_argument("--resume", action="store_true", help="continue the run in --out")
    optimize.add_argument("--no-video", action="store_true", help="skip the plot and video")
    optimize.set_defaults(run=_cmd_optimize)

    follow = commands.add_parser(
        "follow", help="follow a path with learned manoeuvres (paper §5); write the run, "
        "the distance to the path, a video and a picture of the way"
    )  # fmt: skip
    follow.add_argument("name", metavar="NAME", help=NAME_HELP)
    _thicken_flag(follow)
    follow.add_argument("--path", required=True, metavar="FILE|SHAPE",
                        help="a CSV or JSON file of points [m], or a shape: line, circle, "
                        "s-curve, with parameters as NAME:key=value,... (e.g. circle:"
                        "radius=0.6, s-curve:length=4,amplitude=0.5,vertical=true)")  # fmt: skip
    follow.add_argument("--cycles", type=int, default=10, help="gait cycles to swim")
    follow.add_argument("--learned", nargs="+", metavar="RUN|FILE",
                        help="manoeuvres learned by aquagait optimize --maneuver (run "
                        "directories or gait.json), beside the shipped ones")  # fmt: skip
    follow.add_argument("--dead-band", type=float, metavar="M",
                        help="distance from the path [m] within which the paper's rule "
                        "swims straight (--steer paper, and graded steering's first "
                        "cycle; default: a tenth of a body length)")  # fmt: skip
    follow.add_argument("--steer", choices=("graded", "paper"), default="graded",
                        help="graded (default): a share of a manoeuvre mixed into the "
                        "straight gait, by how far the path ahead bears off the heading; "
                        "paper: one whole manoeuvre a cycle, or straight (the paper's "
                        "rule)")  # fmt: skip
    follow.add_argument(
        "--open-loop",
        action="store_true",
        help="swim straight only, to measure the drift without following",
    )
    follow.add_argument(
        "--resolution",
        type=int,
        nargs="+",
        metavar="N",
        help="cells per axis (default: the creature's made roomier: square in 2D, the "
        "cross-section a quarter larger in 3D)",
    )
    follow.add_argument("--cell-size", type=float, metavar="H", help="cell size [m]")
    follow.add_argument("--out", metavar="DIR", help="run directory (default: runs/NAME-follow)")
    follow.add_argument("--no-video", action="store_true", help="skip swim.mp4 and follow.png")
    follow.set_defaults(run=_cmd_follow)

    compare = commands.add_parser(
        "compare", help="one gait in the Euler and the simple fluid: distances, plot, video"
    )
    compare.add_argument("name", metavar="NAME", help=NAME_HELP)
    _thicken_flag(compare)
    compare.add_argument("--gait", metavar="FILE|NAME", help=GAIT_HELP)
    compare.add_argument("--seconds", type=float, default=3.0, help="simulated time [s]")
    compare.add_argument("--optimize", type=int, nargs="?", const=CONVERGED, metavar="G",
                         help="also optimize a gait in each fluid (G generations; without G, "
                         "until converged) and swim each in both")  # fmt: skip
    compare.add_argument("--popsize", type=int, metavar="N",
                         help="--optimize: samples per generation (default: CMA-ES's "
                         "for the number of parameters)")  # fmt: skip
    compare.add_argument("--seed", type=int, default=0, help="--optimize: random seed")
    compare.add_argument("--start", metavar="FILE|NAME",
                         help="--optimize: the gait both searches start from "
                         "(default: the shipped gait)")  # fmt: skip
    compare.add_argument("--resume", action="store_true",
                         help="--optimize: continue the searches in --out")  # fmt: skip
    _add_evaluator_flags(compare)
    compare.add_argument("--resolution", type=int, nargs="+", metavar="N",
                         help="Euler grid cells per axis")  # fmt: skip
    compare.add_argument("--cell-size", type=float, metavar="H", help="Euler cell size [m]")
    compare.add_argument("--out", metavar="DIR", help="directory (default: runs/NAME-compare)")
    compare.add_argument("--no-video", action="store_true", help="skip the plot and video")
    compare.set_defaults(run=_cmd_compare)

    render = commands.add_parser(
        "render", help="draw a run directory's swim again (video, GIF or pictures), no simulation"
    )
    render.add_argument("run_dir", metavar="RUN_DIR", help="a directory written by aquagait swim")
    render.add_argument("--format", choices=("mp4", "gif", "png"), default="mp4",
                        help="png: the frame, or a contact sheet of six frames")  # fmt: skip
    render.add_argument("--frames", metavar="A:B", help="frames A to B-1 (default all)")
    _look_flags(render)
    render.add_argument("--out", metavar="FILE", help="default RUN_DIR/swim[-VIEW].FORMAT")
    render.set_defaults(run=_cmd_render)

    export = commands.add_parser(
        "export", help="write a run directory's swim for other tools: USD, glTF, VTK or HTML"
    )
    export.add_argument("run_dir", metavar="RUN_DIR", help="a directory written by aquagait swim")
    export.add_argument("--format", required=True, choices=("usd", "gltf", "vtk", "html"),
                        help="usd (Blender, Houdini), gltf, vtk (ParaView), html")  # fmt: skip
    export.add_argument("--out", metavar="PATH", help="default RUN_DIR/swim.usd, swim.glb, ...")
    export.add_argument("--traces", type=int, default=1000, help="particle traces exported")
    export.set_defaults(run=_cmd_export)

    demo = commands.add_parser(
        "demo", help="optimize eel2d on a coarse grid, swim and film it; the fish in 3D"
    )
    demo.add_argument("--generations", type=int, default=20, help="CMA-ES generations")
    demo.add_argument("--workers", type=int, help="worker processes (default: all cores)")
    demo.add_argument("--seed", type=int, default=0, help="random seed")
    demo.add_argument("--out", default="runs/demo", metavar="DIR", help="run directory")
    demo.set_defaults(run=_cmd_demo)
    return parser


def _add_evaluator_flags(parser) -> None:
    parser.add_argument("--workers", type=int, help="worker processes (default: all cores)")
    parser.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                        help="evaluate on a Dask cluster instead (extra: dist)")  # fmt: skip


def _thicken_flag(command) -> None:
    command.add_argument(
        "--no-thicken",
        action="store_true",
        help="an MJCF's parts thinner than a cell of its default grid stay as written "
        "(by default they are thickened for the fluid, masses unchanged)",
    )


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread: a command stops as on Ctrl-C, unwinding, so a
    search's worker processes are killed (``ProcessExecutor.__exit__``) and not left
    behind, and its checkpoint keeps the last whole generation."""


def _terminate(signum, frame):
    raise Terminated


@contextlib.contextmanager
def _sigterm_unwinds():
    """Within the block, SIGTERM raises ``Terminated`` (in the main thread only: a signal
    handler cannot be set elsewhere), and the handler before is restored after it."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    before = signal.signal(signal.SIGTERM, _terminate)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, before)


def _stopped(args, stop: KeyboardInterrupt) -> int:
    """A command stopped by Ctrl-C (exit status 130) or SIGTERM (143), in one line."""
    status, how = (
        (143, "terminated (SIGTERM)") if isinstance(stop, Terminated) else (130, "interrupted")
    )
    resume = ""
    if args.command == "optimize" or getattr(args, "optimize", None) is not None:  # compare's
        resume = ("; a search's checkpoint keeps its last whole generation: the same command "
                  "with --resume goes on from it")  # fmt: skip
    print(f"aquagait {args.command}: {how}{resume}", file=sys.stderr)
    return status


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``aquagait`` console script; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 0
    if getattr(args, "no_thicken", False):
        from aquagait.creatures import as_written

        args.name = as_written(args.name)
    with _sigterm_unwinds():
        try:
            return args.run(args)
        except KeyboardInterrupt as stop:
            return _stopped(args, stop)
