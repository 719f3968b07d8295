"""A follower in a leader's wake: its cost of transport against its phase lag (docs/schools.md).

Two eel2d in line in one fluid, the leader on its shipped gait, the follower on
the same gait lagging it by PHASE cycles, GAP body lengths of clear water
between the leader's tail and the follower's head at the start; both swim
free (nothing holds the gap, so it drifts: the table reports by how much, as
the distance between their roots, head to head).
Each swim's last half is measured: the follower's speed (its root's straight-line
travel) and its cost of transport (actuator work over mass and that distance), beside a lone eel's
over the same cycles on the same grid.

    python tools/phase_sweep.py --gaps 0.5 1.0 --phases 8 --out runs/phase-sweep
    python tools/phase_sweep.py --gaps 0.5 --phases 8 --dt 0.005556 --out runs/phase-sweep-fine

Writes ``sweep.csv`` (a row per swim) and ``sweep.png`` into ``--out``.
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

import numpy as np

import aquagait as ag
from aquagait.body.group import Pose, compose
from aquagait.control.group import GroupPolicy
from aquagait.sim.group import group_grid, member_trajectory


def measured(trajectory, model, period: float, cycles: int) -> dict:
    """Speed [m/s] and cost of transport [J/(kg m)] over the last ``cycles`` cycles."""
    fps = trajectory.fps
    start = len(trajectory.time) - 1 - int(round(cycles * period * fps))
    xy = trajectory.qpos[:, :2]  # the root's path, whichever way it heads
    distance = np.linalg.norm(xy[-1] - xy[start])
    work = trajectory.energy[-1].sum() - trajectory.energy[start].sum()
    return {"speed": distance / (cycles * period), "cot": work / (model.mass * distance)}


def swim_pair(eel, gait, gap: float, phase: float, seconds: float, dt, cell_size):
    model, length = eel.model, eel.model.body_length
    group = compose(
        [model, model], ["leader", "follower"], [Pose(), Pose((-(1 + gap) * length, 0, 0))]
    )
    shape, h, origin = group_grid(group, [eel.resolution] * 2, [cell_size] * 2)
    scene = ag.make_scene(group, shape, h, fluid="euler", origin=origin)
    policy = GroupPolicy(group, [eel.servo(gait), eel.servo(gait.lagging(phase))])
    swim = ag.rollout(scene, ag.init_state(scene), policy, seconds, dt=dt, record_fluid=False)
    return group, swim


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--gaps",
        type=float,
        nargs="+",
        default=[0.5, 1.0],
        help="clear water between tail and head at the start [body lengths]",
    )
    parser.add_argument("--phases", type=int, default=8, help="phase lags over one cycle")
    parser.add_argument("--seconds", type=float, default=8.0, help="each swim [s]")
    parser.add_argument("--dt", type=float, help="largest step [s] (default the fluid's, 1/90)")
    parser.add_argument("--cell-size", type=float, help="cell [m] (default eel2d's)")
    parser.add_argument("--out", default="runs/phase-sweep", help="directory for csv and png")
    args = parser.parse_args(argv)

    eel = ag.creatures.get("eel2d")
    gait = eel.spec().unpack(eel.default_gait)
    period = float(np.max(gait.period))
    cycles = int(args.seconds / period) // 2
    h = args.cell_size or eel.cell_size
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    alone = ag.make_scene(eel, eel.resolution, h, fluid="euler")
    solo = ag.rollout(alone, ag.init_state(alone), eel.servo(gait), args.seconds, dt=args.dt,
                      record_fluid=False)  # fmt: skip
    lone = measured(solo, eel.model, period, cycles)
    print(f"alone: {lone['speed']:.4f} m/s, cost of transport {lone['cot']:.4f} J/(kg m)")
    rows = []
    for gap in args.gaps:
        for phase in np.arange(args.phases) / args.phases:
            started = time.perf_counter()
            group, swim = swim_pair(eel, gait, gap, float(phase), args.seconds, args.dt, h)
            leader, follower = (member_trajectory(swim, m) for m in group.members)
            lead = measured(leader, eel.model, period, cycles)
            follow = measured(follower, eel.model, period, cycles)
            spacing = np.linalg.norm(leader.qpos[:, :2] - follower.qpos[:, :2], axis=1)
            row = {
                "gap": gap, "phase": float(phase),
                "follower_speed": follow["speed"], "follower_cot": follow["cot"],
                "leader_speed": lead["speed"], "leader_cot": lead["cot"],
                "alone_speed": lone["speed"], "alone_cot": lone["cot"],
                "spacing_start_bl": spacing[0] / eel.model.body_length,
                "spacing_end_bl": spacing[-1] / eel.model.body_length,
                "heading_end_leader": float(leader.qpos[-1, 2]),
                "heading_end_follower": float(follower.qpos[-1, 2]),
                "seconds": time.perf_counter() - started,
            }  # fmt: skip
            rows.append(row)
            print(
                f"gap {gap:g} BL, phase {phase:.3f}: follower {follow['speed']:.4f} m/s, CoT "
                f"{follow['cot']:.4f} ({follow['cot'] / lone['cot'] - 1:+.1%} against alone); "
                f"spacing {row['spacing_start_bl']:.2f} -> {row['spacing_end_bl']:.2f} BL "
                f"({row['seconds']:.0f} s)",
                flush=True,
            )
            with open(out / "sweep.csv", "w", newline="") as f:
                writer = csv.DictWriter(f, fieldnames=list(rows[0]))
                writer.writeheader()
                writer.writerows(rows)
    plot(rows, out / "sweep.png")


def plot(rows, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 3.6), constrained_layout=True)
    for gap in sorted({r["gap"] for r in rows}):
        these = [r for r in rows if r["gap"] == gap]
        phase = [r["phase"] for r in these]
        ratio = [r["follower_cot"] / r["alone_cot"] for r in these]
        ax.plot(phase + [1.0], ratio + ratio[:1], "o-", label=f"gap {gap:g} body lengths")
    ax.axhline(1.0, color="0.5", lw=0.8, ls="--", label="alone")
    ax.set_xlabel("follower's phase lag [cycles]")
    ax.set_ylabel("follower's cost of transport / alone")
    ax.legend(frameon=False)
    fig.savefig(path, dpi=120)


if __name__ == "__main__":
    main()
