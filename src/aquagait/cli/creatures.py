"""``aquagait creatures``: list the creature library."""

from __future__ import annotations


def add_parser(commands) -> None:
    creatures = commands.add_parser("creatures", help="list the creature library")
    creatures.set_defaults(run=run)


def run(args) -> int:
    from aquagait import creatures

    print(creatures.format_table())
    return 0
