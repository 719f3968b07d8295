"""``aquagait follow``: follow a path with learned manoeuvres (paper §5)."""

from __future__ import annotations

import sys
from pathlib import Path

from aquagait.cli.errors import fail
from aquagait.cli.flags import NAME_HELP, thicken_flag
from aquagait.cli.progress import ProgressBar


def add_parser(commands) -> None:
    follow = commands.add_parser(
        "follow", help="follow a path with learned manoeuvres (paper §5); write the run, "
        "the distance to the path, a video and a picture of the way"
    )  # fmt: skip
    follow.add_argument("name", metavar="NAME", help=NAME_HELP)
    thicken_flag(follow)
    follow.add_argument("--path", required=True, metavar="FILE|SHAPE",
                        help="a CSV or JSON file of points [m], or a shape: line, circle, "
                        "s-curve, with parameters as NAME:key=value,... (e.g. circle:"
                        "radius=0.6, s-curve:length=4,amplitude=0.5,vertical=true)")  # fmt: skip
    follow.add_argument("--cycles", type=int, default=10, help="gait cycles to swim (default 10)")
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
    follow.set_defaults(run=run)


def run(args) -> int:
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
        return fail("follow", err, status=2)
    try:
        run = run_follow(setup, progress=ProgressBar("swimming"))
    except SimulationError as err:
        return fail("follow", err, status=1)
    try:
        write_follow(run, out, video=not args.no_video, progress=ProgressBar("rendering"))
    except RenderUnavailable as err:
        print(f"aquagait: the pictures are skipped, the run is kept: {err}", file=sys.stderr)
    print(follow_summary(run, out))
    return 0
