"""Does each shipped gait's provenance still reproduce it? Swim every optimized gait once
with the search its side-car's command sets up, and compare the objective with the one
the search recorded.

Run from the repository root::

    python tools/check_provenance.py                 # every creature's optimized gaits
    python tools/check_provenance.py eel2d manta     # some
    python tools/check_provenance.py --json rows.json

The search is deterministic for its seed, so a gait whose objective today equals the
recorded one (to the solver's tolerance) comes out of its command again; one that does
not was found on physics that has changed since, and its command now finds another.
One sample per gait: seconds for the 2D creatures, a minute or two for the frog.
"""

from __future__ import annotations

import argparse
import json
import shlex
import tempfile
import time
from pathlib import Path

import numpy as np

import aquagait as ag
from aquagait.cli import build_parser, optimization_setup
from aquagait.io import write_gait

AGREE = 1e-3
"""Relative difference [-] within which today's objective is the recorded one: the
pressure solve's tolerance (1e-4) moves a sample's objective by less."""


def recorded_search(creature, provenance: dict, scratch: Path):
    """The search a gait's provenance sets up (``aquagait.cli.optimization_setup``): its
    command, started where it started (``provenance["start"]``, written to ``scratch``)
    when the command names no start, as the gait it starts from by default may have been
    replaced since (it changes the efficiency objective's unit)."""
    args = build_parser().parse_args(shlex.split(provenance["command"])[1:])
    if args.start is None and "start" in provenance:
        names, values = zip(*provenance["start"].items(), strict=True)
        free_period = "period" in names
        if names != creature.spec(args.maneuver, free_period).names:
            raise SystemExit(f"{creature.name}: the recorded start's parameters are not "
                             f"those of its {args.maneuver} search")  # fmt: skip
        path = write_gait(scratch / "start.json", creature, values, args.maneuver, free_period)
        args.start = str(path)
    return optimization_setup(args)


def check(name: str, gait: str) -> dict:
    """The gait's recorded objective beside today's, swum as its search would."""
    creature = ag.creatures.get(name)
    shipped = creature.gaits[gait]
    provenance = shipped.provenance
    with tempfile.TemporaryDirectory() as scratch:
        setup = recorded_search(creature, provenance, Path(scratch))
    x = np.asarray(shipped.params, dtype=float)  # in the order of its manoeuvre's spec
    if x.shape != setup.problem.x0.shape:
        raise SystemExit(
            f"{name} {gait}: {x.size} parameters, its search has {setup.problem.x0.size}"
        )
    tic = time.perf_counter()
    today = float(setup.problem.objective(x))
    recorded = float(provenance["objective"])
    change = abs(today - recorded) / max(abs(recorded), 1e-12)
    return {
        "creature": name, "gait": gait, "date": provenance.get("date"),
        "recorded": recorded, "today": today, "relative_change": change,
        "reproduces": change <= AGREE, "seconds": round(time.perf_counter() - tic, 1),
    }  # fmt: skip


def optimized_gaits(names):
    for name in names:
        for gait, shipped in ag.creatures.get(name).gaits.items():
            if shipped.provenance.get("method") == "optimized":
                yield name, gait


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("creatures", nargs="*", help="default: the whole library")
    parser.add_argument("--json", help="also write the rows to this file")
    args = parser.parse_args()
    rows = []
    print("creature | gait | shipped | recorded objective | today | change | reproduces")
    for name, gait in optimized_gaits(args.creatures or ag.creatures.names()):
        row = check(name, gait)
        rows.append(row)
        print(f"{name} | {gait} | {row['date']} | {row['recorded']:.5g} | {row['today']:.5g} | "
              f"{100 * row['relative_change']:.2g} % | {'yes' if row['reproduces'] else 'no'}",
              flush=True)  # fmt: skip
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
