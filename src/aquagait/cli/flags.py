"""Flags and help texts that several commands share."""

from __future__ import annotations

from pathlib import Path

NAME_HELP = "a library creature (see: aquagait creatures) or the path of an MJCF file"
GAIT_HELP = (
    "a gait.json, or the name of a gait the creature ships (hand-set, optimized, turn-left, "
    "...; default: its shipped straight gait)"
)


def look_flags(parser) -> None:
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


def thicken_flag(command) -> None:
    command.add_argument(
        "--no-thicken",
        action="store_true",
        help="an MJCF's parts thinner than a cell of its default grid stay as written "
        "(by default they are thickened for the fluid, masses unchanged)",
    )


FORMATION_DEFAULTS = {"spacing": 0.5, "phase": 0.0}
"""The defaults of a formation's flags, which mean nothing without ``--formation``."""


def formation_flags(command) -> None:
    """``--formation``, ``--spacing`` and ``--phase``: a group of one creature (``swim``,
    ``optimize``)."""
    command.add_argument("--formation", metavar="KIND[:COUNT]",
                         help="a group of this creature in one fluid: in-line, "
                         "side-by-side or diamond, optionally :COUNT (default 2, 2, 4); "
                         "default: one creature")  # fmt: skip
    command.add_argument("--spacing", type=float, default=FORMATION_DEFAULTS["spacing"],
                         metavar="BL",
                         help="a formation's spacing in body lengths: in line the clear water "
                         "from one's tail to the next one's head, side by side between their "
                         "axes (default 0.5)")  # fmt: skip
    command.add_argument("--phase", type=float, default=FORMATION_DEFAULTS["phase"],
                         metavar="CYCLES",
                         help="a formation's phase offset: each creature's gait lags the one "
                         "before by this many cycles (default 0)")  # fmt: skip


def refuse_group_flags(args, defaults: dict) -> None:
    """Refuse flags that only a group takes (``defaults``: each one's default) when given
    to one creature.

    Raises:
        aquagait.app.SetupError: naming them.
    """
    from aquagait.app import SetupError

    given = [f"--{flag}" for flag, default in defaults.items() if getattr(args, flag) != default]
    if given:
        raise SetupError(
            f"{', '.join(given)}: for a group: give --formation, or a scene file (SCENE.json) "
            "as NAME"
        )


def group_members(args, gait: str | None, command: str):
    """The members ``--formation`` (each on ``gait``, ``--gait``'s) or a scene file
    (``args.name`` ending in .json) asks for, their grid settings, the formation's words
    for ``config.json`` and the run's label (``NAME-FORMATION`` or the scene file's stem).

    Raises:
        aquagait.app.SetupError: a bad formation or scene file, or ``--gait`` beside a
            scene file.
    """
    from aquagait.app import SetupError
    from aquagait.app.school import formation_members, read_scene_file

    if args.formation is not None:
        members = formation_members(args.name, args.formation, args.spacing, args.phase, gait)
        formation = {"kind": args.formation, "spacing": args.spacing, "phase": args.phase}
        return members, {}, formation, f"{Path(args.name).stem}-{args.formation.replace(':', '')}"
    if gait is not None:
        raise SetupError(
            f"a scene file names each creature's gait: give none with {command}'s --gait"
        )
    members, grid = read_scene_file(args.name)
    return members, grid, None, Path(args.name).stem
