"""``aquagait swim``: swim a creature with a gait; write its run directory and video."""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

from aquagait.cli.errors import fail
from aquagait.cli.flags import (
    FORMATION_DEFAULTS,
    GAIT_HELP,
    NAME_HELP,
    formation_flags,
    group_members,
    look_flags,
    refuse_group_flags,
    thicken_flag,
)
from aquagait.cli.progress import ProgressBar
from aquagait.objectives import MANEUVERS
from aquagait.sim import FLUIDS


def add_parser(commands) -> None:
    swim = commands.add_parser(
        "swim", help="swim a creature with a gait; write trajectory, metrics and video"
    )
    swim.add_argument("name", metavar="NAME",
                      help=f"{NAME_HELP}; or a scene file (SCENE.json) of several creatures, "
                      "their poses and gaits (docs/schools.md)")  # fmt: skip
    thicken_flag(swim)
    swim.add_argument("--gait", metavar="FILE|NAME", help=GAIT_HELP)
    swim.add_argument("--maneuver", "--manoeuvre", choices=MANEUVERS, metavar="NAME",
                      help="swim a learned manoeuvre's shipped gait instead, one of "
                      f"{', '.join(MANEUVERS)}")  # fmt: skip
    swim.add_argument("--seconds", type=float, default=2.0, help="simulated time [s] (default 2)")
    swim.add_argument("--keep-course", action="store_true",
                      help="keep to the line ahead of the start with the creature's learned "
                      "manoeuvres, a share mixed into the gait each cycle (each manoeuvre's "
                      "turn is measured first by a two-cycle swim)")  # fmt: skip
    swim.add_argument("--fluid", choices=list(FLUIDS), default="euler",
                      help="euler: the inviscid fluid, two-way coupled (default); simple: "
                      "drag alone, no grid; none: a vacuum")  # fmt: skip
    swim.add_argument(
        "--resolution",
        type=int,
        nargs="+",
        metavar="N",
        help="cells per axis: NX NY (2D) or NX NY NZ (3D)",
    )
    swim.add_argument("--cell-size", type=float, metavar="H", help="cell size [m]")
    swim.add_argument("--out", metavar="DIR",
                      help="run directory (default: runs/NAME; a group's runs/NAME-FORMATION "
                      "or runs/SCENE)")  # fmt: skip
    swim.add_argument("--no-video", action="store_true", help="skip swim.mp4")
    formation_flags(swim)
    look_flags(swim)
    swim.set_defaults(run=run)


def run(args) -> int:
    if args.formation is not None or args.name.endswith(".json"):
        return run_group(args)
    from aquagait.app import SetupError, output_directory, prepare_swim

    try:
        refuse_group_flags(args, FORMATION_DEFAULTS)
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
        return fail("swim", err, status=2)
    return swim_and_write(setup, out, not args.no_video)


def swim_and_write(setup, out: Path, video: bool, extra_config=None, notes=None) -> int:
    """Swim a prepared setup, write its run directory and (optionally) its video;
    ``notes(run)``, if given, adds notes on the swim to its config.json and summary."""
    from aquagait.app import RenderUnavailable, run_swim, swim_summary, write_swim
    from aquagait.sim import SimulationError

    try:
        run = run_swim(setup, progress=ProgressBar("swimming"))
    except SimulationError as err:
        return fail("swim", err, status=1)
    if notes is not None:
        run = dataclasses.replace(run, notes=run.notes + notes(run))
    try:
        write_swim(run, out, video, extra_config, progress=ProgressBar("rendering"))
    except RenderUnavailable as err:
        print(f"aquagait: the video is skipped, the run is kept: {err}", file=sys.stderr)
    print(swim_summary(run, out))
    return 0


def run_group(args) -> int:
    """``aquagait swim NAME --formation ...`` or ``aquagait swim SCENE.json``: a group."""
    from aquagait.app import RenderUnavailable, SetupError, output_directory
    from aquagait.app.school import prepare_school, run_school, school_summary, write_school
    from aquagait.sim import SimulationError

    try:
        if args.maneuver or args.keep_course:
            raise SetupError(
                "--maneuver and --keep-course steer one creature; a group swims straight "
                "gaits (--gait, or each creature's in the scene file)"
            )
        members, grid, formation, label = group_members(args, args.gait, "swim")
        setup = prepare_school(
            members, seconds=args.seconds, fluid=args.fluid,
            resolution=args.resolution or grid.get("resolution"),
            cell_size=args.cell_size or grid.get("cell_size"),
            view=args.view, wake=args.wake, size=args.size, formation=formation,
        )  # fmt: skip
        out = output_directory(args.out or Path("runs") / label)
    except SetupError as err:
        return fail("swim", err, status=2)
    try:
        run = run_school(setup, progress=ProgressBar("swimming"))
    except SimulationError as err:
        return fail("swim", err, status=1)
    try:
        write_school(run, out, not args.no_video, progress=ProgressBar("rendering"))
    except RenderUnavailable as err:
        print(f"aquagait: the video is skipped, the run is kept: {err}", file=sys.stderr)
    print(school_summary(run, out))
    return 0
