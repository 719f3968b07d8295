"""Ship an optimized gait: copy it from a finished ``aquagait optimize`` run into the
creature's side-car (``src/aquagait/creatures/NAME.aquagait.json``), with its provenance.

Run from the repository root::

    python tools/ship_gait.py runs/turtle2d-opt [--as straight]
    python tools/ship_gait.py runs/eel2d-turn-left      # a manoeuvre ships as its name

The run directory's ``gait.json`` (the best sample), ``config.json`` (the
optimization's settings: seed, grid, population, generations, the fluid's
settings) and ``optimization.csv`` (the best objective and the wall time)
become the gait's ``params`` and ``provenance``, so anyone can run the same
command again and compare (``tools/check_provenance.py`` does; the start is recorded by
value too, as the shipped gait a command starts from by default may have been replaced
since). The best gait's swim (``metrics.json``) adds its body lengths per cycle. Other
gaits in the side-car are kept; a hand-set gait the new one replaces is kept as
``hand-set``.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import re
import shlex
from datetime import UTC, datetime
from pathlib import Path

import numpy as np

from aquagait.app.optimize import DEFAULT_CYCLES
from aquagait.objectives import TURN, Weights

CREATURES = Path(__file__).resolve().parents[1] / "src" / "aquagait" / "creatures"


def provenance(run: Path, default_start: str | None = None) -> dict:
    """How the run found its gait: command, seed, grid, objective, wall time, versions.

    ``default_start``: the name the run's default start (the shipped straight gait it
    began from) goes by once the new gait displaces it, written into the command as
    ``--start`` so that the command still starts where the run did.
    """
    config = json.loads((run / "config.json").read_text())
    opt = config["optimization"]
    if opt.get("start") is None and default_start is not None:
        opt["start"] = default_start
    with (run / "optimization.csv").open() as f:
        rows = list(csv.DictReader(f))
    if opt.get("target_grid"):
        raise SystemExit(f"{run} is a coarse-to-fine search: write its provenance by hand")
    grid = {
        "resolution": opt["resolution"] or config["resolution"],
        "cell_size": opt["cell_size"] or config["cell_size"],
    }
    command = ["aquagait", "optimize", opt["creature"], "--seed", str(opt["seed"])]
    for flag in ("generations", "popsize", "patience", "max_evaluations"):  # None: the default
        if opt.get(flag) is not None:
            command += [f"--{flag.replace('_', '-')}", str(opt[flag])]
    if opt.get("maneuver", "straight") != "straight":
        command += ["--maneuver", opt["maneuver"]]
    # the grid always, the default's too: a creature's default grid may change later
    command += ["--resolution", *map(str, grid["resolution"])]
    command += ["--cell-size", f"{grid['cell_size']:g}"]
    # the energy weight always too: a creature's default comes from its side-car
    command += ["--energy-weight", f"{opt['weights']['energy']:g}"]
    if opt["weights"]["deviation"] != Weights.deviation:  # the paper's: left out
        command += ["--deviation-weight", f"{opt['weights']['deviation']:g}"]
    if opt.get("start") is not None:
        command += ["--start", opt["start"]]
    if opt.get("step") is not None:
        command += ["--step", f"{opt['step']:g}"]
    if opt.get("turn_limit") not in (None, TURN):  # the default: left out
        command += ["--turn-limit", f"{opt['turn_limit']:g}"]
    cycles = opt.get("cycles_per_sample") or opt["seconds_per_sample"] / config["period"]
    if opt.get("objective", "distance") != "distance":  # with what it was measured by
        command += ["--objective", opt["objective"], "--min-speed", f"{opt['min_speed']:.6g}",
                    "--cycles", f"{cycles:g}"]  # fmt: skip
    elif not math.isclose(cycles, DEFAULT_CYCLES):
        command += ["--cycles", f"{cycles:g}"]
    if opt.get("free_period"):
        command += ["--free-period"]
    metrics = json.loads((run / "metrics.json").read_text())
    return {
        "method": "optimized",
        "maneuver": opt.get("maneuver", "straight"),
        "command": shlex.join(command),
        "seed": opt["seed"],
        "generations": len({row["generation"] for row in rows}),
        "popsize": opt["popsize"],
        "grid": grid,
        "fluid_settings": opt.get("fluid_settings"),
        "objective_kind": opt.get("objective", "distance"),
        "objective": float(rows[-1]["best"]),
        "wall_time": round(float(rows[-1]["elapsed"])),
        "body_lengths_per_cycle_from_rest": metrics.get("body_lengths_per_cycle_from_rest"),
        "rotation_vector": turned(run),
        # where it started, by value: a start named by its shipped gait (the default, the
        # straight gait) is replaced when that gait is optimized again
        "start": dict(zip(opt["parameters"], opt["x0"], strict=True)),
        "aquagait": config.get("versions", {}).get("aquagait"),
        "date": datetime.now(UTC).date().isoformat(),
    }


def turned(run: Path) -> list[float]:
    """The root's rotation over the best gait's swim, a world rotation vector [rad]
    (z: yawed left; -y: pitched up; in 2D the hinge angle's change, however far it went)."""
    from scipy.spatial.transform import Rotation

    with np.load(run / "trajectory.npz") as data:
        first, last = data["root_rotation"][0], data["root_rotation"][-1]
        qpos = data["qpos"]
    if json.loads((run / "config.json").read_text())["dim"] == 2:  # unwrapped, past pi
        return [0.0, 0.0, round(float(qpos[-1, 2] - qpos[0, 2]), 4)]
    return [round(float(v), 4) for v in Rotation.from_matrix(last @ first.T).as_rotvec()]


def ship(run: Path, name: str | None) -> Path:
    """Copy the run's gait into its creature's side-car as ``name`` (default: the gait's
    manoeuvre: ``straight``, ``turn-left``, ...)."""
    gait = json.loads((run / "gait.json").read_text())
    start = json.loads((run / "config.json").read_text())["optimization"]["x0"]
    if gait["params"] == start:
        raise SystemExit(f"{run}'s search found nothing better than its start: nothing to ship")
    name = name or gait.get("maneuver", "straight")
    sidecar = CREATURES / f"{gait['creature']}.aquagait.json"
    meta = json.loads(sidecar.read_text())
    params = dict(zip(gait["names"], gait["params"], strict=True))
    gaits = meta.setdefault("gaits", {})
    displaced = gaits.get(name, {}).get("provenance", {}).get("method") == "hand-set"
    if displaced and "hand-set" not in gaits:  # kept: tests and figures measured with it
        gaits["hand-set"] = gaits[name]
    searched_from_it = displaced and name == "straight"  # the default start of the run
    record = provenance(run, "hand-set" if searched_from_it else None)
    gaits[name] = {"params": params, "provenance": record}
    sidecar.write_text(side_car_json(meta) + "\n")
    return sidecar


def side_car_json(obj) -> str:
    """Indented JSON with every list of plain values and every small dict on one line, as the
    side-cars are written by hand."""
    text = json.dumps(obj, indent=2)
    flat = re.compile(r"([\[{])\s*\n\s*([^\[\]{}]*?)\s*\n\s*([\]}])", re.S)
    joined = lambda m: m.group(1) + re.sub(r",\s*\n\s*", ", ", m.group(2)) + m.group(3)  # noqa: E731
    while True:
        shorter = flat.sub(lambda m: joined(m) if len(joined(m)) <= 72 else m.group(0), text)
        if shorter == text:
            return text
        text = shorter


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="a finished aquagait optimize run directory")
    parser.add_argument("--as", dest="name", help="the gait's name (default: its manoeuvre)")
    args = parser.parse_args()
    print(f"wrote {ship(args.run, args.name)}")
