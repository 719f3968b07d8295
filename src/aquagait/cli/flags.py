"""Flags and help texts that several commands share."""

from __future__ import annotations

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
