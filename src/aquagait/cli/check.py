"""``aquagait check``: a creature's table and voxels, and on request its convergence study."""

from __future__ import annotations

from pathlib import Path

from aquagait.cli.errors import fail
from aquagait.cli.flags import thicken_flag


def add_parser(commands) -> None:
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
                       help="with --convergence: seconds swum in each case "
                       "(default 2)")  # fmt: skip
    thicken_flag(check)
    check.set_defaults(run=run)


def run(args) -> int:
    from aquagait.app import SetupError, output_directory, prepare_check
    from aquagait.app.check import format_check, run_check, write_check

    try:
        setup = prepare_check(args.name)
        out = output_directory(args.out or Path("runs") / f"{setup.creature.name}-check")
    except SetupError as err:
        return fail("check", err, status=2)
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
