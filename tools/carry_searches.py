"""Carry the library's searches from one session to the next: each run's best gait so
far, written into the repository, where the next session's search goes on from it.

A session's machine is new each time: ``runs/`` (and every checkpoint in it) does not
outlive it. Each search's best gait so far is written as the next *leg* of its search
(``tools/library_searches.sh`` does so every 15 minutes and when a search ends; carry by
hand and commit before a session ends); the lane then starts a search that has no
checkpoint from its last leg (``--start LEG --step S``: S is the spread the search had
reached, so it goes on polishing rather than exploring again from scratch). A leg is a
gait file (``aquagait swim NAME --gait LEG`` swims it) with a ``carried`` record: which
run, how far it got, its best objective, and the leg it started from. Legs are small and
committed; run directories never are. A finished search's last leg says so, and the
lane skips it.

Run from the repository root::

    python tools/carry_searches.py                        # every search under runs/
    python tools/carry_searches.py runs/manta-straight-51
    python tools/carry_searches.py --continue manta-straight-51   # the lane's arguments
    python tools/carry_searches.py --list                 # how far every search has got

What a leg loses is the search's shape: CMA-ES's covariance and its patience start
again (the spread is kept as one number), so legs cost a few generations each to
re-adapt, and a grouped search (the frog's: hind legs, then forelimbs) starts again at
its first group. The objective of a search continued from a leg is that of the first leg's
search (for an efficiency search the minimum speed is passed on; its unit, the start's
cost of transport, is the leg's own, which scales the objective and not its minimum).
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from datetime import UTC, datetime
from pathlib import Path

import numpy as np
from ship_gait import side_car_json

import aquagait as ag
from aquagait.optimize import checkpoint

ROOT = Path(__file__).resolve().parents[1]
CARRIED = ROOT / "tools" / "carried"
LEG = re.compile(r"\.leg(\d+)\.json$")


def legs(name: str) -> list[Path]:
    """The search ``name``'s legs so far, first to last."""
    found = [(int(LEG.search(p.name).group(1)), p) for p in CARRIED.glob(f"{name}.leg*.json")]
    return [path for _, path in sorted(found)]


def carry(run: Path) -> Path | None:
    """Write the run's best gait so far as the next leg of its search (the leg after the
    one it started from, replacing one carried from it earlier); None when there is
    nothing to carry (no checkpoint, or, while it runs, nothing better than its start
    yet). A search that has finished is carried even if it found nothing better, so that
    its lane does not run it again."""
    if not (run / checkpoint.CHECKPOINT).is_file():
        return None
    state = checkpoint.load(run)
    fingerprint, progress = state["fingerprint"], state["run"]
    start_f = progress["start_f"]  # None: not scored
    bettered = start_f is None or progress["best_f"] < start_f
    if not progress["history"] or not (bettered or progress["finished"]):
        return None
    objective = fingerprint["objective"]
    before = legs(run.name)
    start = _start_leg(before, fingerprint["x0"])
    creature = ag.creatures.get(objective["creature"])
    names = creature.spec(objective["maneuver"], objective["free_period"]).names
    width = np.asarray(fingerprint["upper"]) - np.asarray(fingerprint["lower"])
    record = {
        "run": run.name,
        "leg": before.index(start) + 2 if start else 1,
        "from": start.name if start else "the search's own start",
        "generations": len(progress["history"]),
        "evaluations": progress["evaluations"],
        "start_objective": progress["start_f"],
        "objective": progress["best_f"],
        "wall_time": round(progress["elapsed"]),
        "finished": progress["finished"],
        "stopped": progress["stopped"],
        "step": _spread(progress, width, fingerprint["groups"]),
        "min_speed": objective["min_speed"],
        "start": list(fingerprint["x0"]),  # where this leg's search started
        "aquagait": ag.__version__,
        "date": datetime.now(UTC).date().isoformat(),
    }
    gait = {
        "creature": creature.name,
        "maneuver": objective["maneuver"],
        "names": list(names),
        "params": np.asarray(progress["best_x"], dtype=float).tolist(),
        "carried": record,
    }
    CARRIED.mkdir(exist_ok=True)
    path = CARRIED / f"{run.name}.leg{record['leg']}.json"
    path.write_text(side_car_json(gait) + "\n")
    return path


def _spread(progress: dict, width: np.ndarray, groups: list[list[int]]) -> float:
    """The spread the search reached, as ``--step`` takes it: each parameter's standard
    deviation, a share of its range, averaged over the group being searched (the
    covariance's shape is not kept). A group that has ended keeps only its last step
    size."""
    es = progress["es"]
    if es is not None:
        group = groups[progress["group"]] if groups else slice(None)
        share = np.mean(es.stds / width[group])
    else:  # the problem scales coordinate i by width_i / mean(width)
        share = progress["history"][-1]["sigma"] / np.mean(width)
    return float(np.clip(share, 1e-3, 1.0))


def _start_leg(before: list[Path], x0) -> Path | None:
    """The leg the run started from (the last whose gait is its start, not carried from a
    search that started there itself), or None: it started from its own start. Legs after
    it were carried from this run before, and the next one replaces them."""
    for leg in reversed(before):
        gait = json.loads(leg.read_text())
        carried_from_here = np.allclose(gait["carried"].get("start", np.nan), x0)
        if np.allclose(gait["params"], x0) and not carried_from_here:
            return leg
    return None


def continuation(name: str) -> list[str]:
    """``aquagait optimize``'s arguments, beyond the lane's own, that go on with the search
    ``name``: ``--resume`` if ``runs/NAME`` holds its checkpoint (with the leg it started
    from, which its checkpoint must match), else a start from its last leg, else nothing.
    Exits with status 3 if the last leg finished the search."""
    run = ROOT / "runs" / name
    found = legs(name)
    resume = (run / checkpoint.CHECKPOINT).is_file()
    if resume:
        leg = _start_leg(found, checkpoint.load(run)["fingerprint"]["x0"])
    else:
        leg = found[-1] if found else None
    arguments = ["--resume"] if resume else []
    if leg is None:
        return arguments
    record = json.loads(leg.read_text())["carried"]
    if record["finished"] and not resume:
        sys.exit(3)
    arguments += ["--start", str(leg.relative_to(ROOT)), "--step", f"{record['step']:.4g}"]
    if record["min_speed"] is not None:
        arguments += ["--min-speed", f"{record['min_speed']:.6g}"]
    return arguments


def summary() -> list[str]:
    """A table of every carried search: its legs, and over them all the generations, the
    samples and the wall time, its best objective (the last leg's) and whether it has
    finished."""
    names = sorted({LEG.sub("", path.name) for path in CARRIED.glob("*.leg*.json")})
    rows = ["| search | legs | generations | samples | hours | best objective | finished |",
            "|---|---|---|---|---|---|---|"]  # fmt: skip
    for name in names:
        records = [json.loads(leg.read_text())["carried"] for leg in legs(name)]
        last = records[-1]
        rows.append(
            f"| `{name}` | {len(records)} | {sum(r['generations'] for r in records)} "
            f"| {sum(r['evaluations'] for r in records)} "
            f"| {sum(r['wall_time'] for r in records) / 3600:.1f} | {last['objective']:.4g} "
            f"| {'yes' if last['finished'] else 'no'} |"
        )
    return rows


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="*", type=Path, help="run directories (default: runs/*)")
    parser.add_argument("--continue", dest="name", help="print the arguments that go on "
                        "with this search (exit status 3: it has finished)")  # fmt: skip
    parser.add_argument("--list", action="store_true", help="print a table of every "
                        "carried search's progress")  # fmt: skip
    args = parser.parse_args()
    if args.list:
        print("\n".join(summary()))
        sys.exit(0)
    if args.name:
        print(" ".join(continuation(args.name)))
        sys.exit(0)
    for run in args.runs or sorted(p for p in (ROOT / "runs").glob("*") if p.is_dir()):
        path = carry(run)
        print(f"{run.name}: {'wrote ' + str(path.relative_to(ROOT)) if path else 'nothing new'}")
