"""``aquagait export``: write a run directory's swim for other tools (USD, glTF, VTK, HTML)."""

from __future__ import annotations

from aquagait.cli.errors import fail


def add_parser(commands) -> None:
    export = commands.add_parser(
        "export", help="write a run directory's swim for other tools: USD, glTF, VTK or HTML"
    )
    export.add_argument("run_dir", metavar="RUN_DIR", help="a directory written by aquagait swim")
    export.add_argument("--format", required=True, choices=("usd", "gltf", "vtk", "html"),
                        help="usd (Blender, Houdini), gltf, vtk (ParaView), html")  # fmt: skip
    export.add_argument("--out", metavar="PATH", help="default RUN_DIR/swim.usd, swim.glb, ...")
    export.add_argument("--traces", type=int, default=1000,
                        help="particle traces exported (default 1000)")  # fmt: skip
    export.set_defaults(run=run)


def run(args) -> int:
    from aquagait.app import SetupError
    from aquagait.app.export import prepare_export, run_export

    try:
        setup = prepare_export(args.run_dir, args.format, args.out, args.traces)
    except SetupError as err:
        return fail("export", err, status=2)
    path = run_export(setup)
    print(f"wrote {path}" + "".join(f" ({note})" for note in setup.notes))
    return 0
