"""``aquagait render``: draw a run directory's swim again, with no simulation."""

from __future__ import annotations

from aquagait.cli.errors import fail
from aquagait.cli.flags import look_flags
from aquagait.cli.progress import ProgressBar


def add_parser(commands) -> None:
    render = commands.add_parser(
        "render", help="draw a run directory's swim again (video, GIF or pictures), no simulation"
    )
    render.add_argument("run_dir", metavar="RUN_DIR", help="a directory written by aquagait swim")
    render.add_argument("--format", choices=("mp4", "gif", "png"), default="mp4",
                        help="mp4 (default), gif, or png: the frame, or a contact sheet of "
                        "six frames")  # fmt: skip
    render.add_argument("--frames", metavar="A:B", help="frames A to B-1 (default all)")
    look_flags(render)
    render.add_argument("--out", metavar="FILE", help="default RUN_DIR/swim[-VIEW].FORMAT")
    render.set_defaults(run=run)


def run(args) -> int:
    from aquagait.app import RenderUnavailable, SetupError, prepare_render, run_render

    try:
        setup = prepare_render(args.run_dir, args.format, args.view, args.frames, args.out,
                               args.wake, args.size)  # fmt: skip
    except SetupError as err:
        return fail("render", err, status=2)
    try:
        path = run_render(setup, progress=ProgressBar("rendering"))
    except RenderUnavailable as err:
        return fail("render", err, status=1)
    print(f"wrote {path}")
    return 0
