"""The library's Table 1 (docs/library.md) regenerated: each creature's shipped straight
gait swum twenty cycles from rest on its default grid, its figures at cruise, and for a
creature whose open-loop swim turns more than 30 degrees, the same gait keeping its course
beside it.

Run from the repository root (about 15 minutes on one core for the whole library, the frog
most of it)::

    python tools/library_table.py                  # every creature
    python tools/library_table.py fish manta --json rows.json

Each row: body lengths per cycle from rest over the twenty cycles; the cycle from which
the swim settled at cruise; at cruise, body lengths per cycle, the Strouhal number and the
cost of transport (``aquagait.metrics``); the way it travels over its last two cycles,
degrees off +x (where it faced at rest); its energy over the first two cycles, the
objective's, against its bound. The seconds a frame come from ``aquagait bench swim``.
``tests/creatures/test_library_swims.py`` (``-m slow``) checks the same swims.
"""

from __future__ import annotations

import argparse
import json

import aquagait as ag
from aquagait.app import prepare_swim, run_swim
from aquagait.app.swim import SwimSetupError
from aquagait.metrics import course

CYCLES = 20
TURNS = 30.0
"""Degrees off +x after twenty cycles beyond which the table adds the swim that keeps its
course (the library issue's rule)."""


def row(name: str, keep_course: bool = False) -> dict:
    """One creature's swim of ``CYCLES`` cycles from rest, as a Table 1 row."""
    creature = ag.creatures.get(name)
    setup = prepare_swim(name, seconds=float(CYCLES), keep_course=keep_course)
    run = run_swim(setup)
    m, trajectory = run.metrics, run.trajectory
    period = m["period"]
    frames = int(round(2 * period * trajectory.fps))
    return {
        "creature": name,
        "keep_course": keep_course,
        "from_rest": m["body_lengths_per_cycle_from_rest"],
        "settled_cycle": m["settled_cycle"],
        "cruise": m["cruise_body_lengths_per_cycle"],
        "strouhal": m["cruise_strouhal"],
        "cost_of_transport": m["cruise_cost_of_transport"],
        "turned": course(trajectory, creature.dim, 2 * period),
        "energy_two_cycles": float(trajectory.energy[frames].sum()),
        "energy_bound": creature.energy_bound,
        "grid_notes": list(run.grid_notes),
    }


def markdown(r: dict) -> str:
    name = f"`{r['creature']}`" + (", keeping its course" if r["keep_course"] else "")
    return (f"| {name} | {r['from_rest']:.3f} | {r['settled_cycle']:.0f} | {r['cruise']:.3f} | "
            f"{r['strouhal']:.2f} | {r['cost_of_transport']:.3g} | {r['turned']:.0f} | "
            f"{r['energy_two_cycles']:.3g} of {r['energy_bound']:.3g} J |")  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("creatures", nargs="*", help="default: the whole library")
    parser.add_argument("--json", help="write the rows here too")
    args = parser.parse_args()
    print("| creature | BL/cycle from rest | settled from cycle | BL/cycle at cruise | "
          "Strouhal at cruise | cost of transport J/(kg m) | degrees off +x at the end | "
          "energy, first two cycles |\n|---|---|---|---|---|---|---|---|", flush=True)  # fmt: skip
    rows = []
    for name in args.creatures or ag.creatures.names():
        rows.append(row(name))
        print(markdown(rows[-1]), flush=True)
        if rows[-1]["turned"] > TURNS:
            try:
                rows.append(row(name, keep_course=True))
            except SwimSetupError as err:  # no learned manoeuvre to keep it with
                why = str(err).split(" (")[0]  # the reason, not the commands that would help
                print(f"| `{name}`, keeping its course | cannot: {why} |", flush=True)
                continue
            print(markdown(rows[-1]), flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
