"""06 - The eel follows a circle by mixing, every cycle, some of a learned turn into its gait.

Shows path following (paper §5) through the Python API: the eel's manoeuvre
library (straight and the turns it ships, learned with ``aquagait optimize
eel2d --maneuver turn-left``), a path (a named shape placed at the eel's
head), each turn's rate (its turn a cycle under way: two cycles of it after
two of the straight gait), and the ``Follower``: a planner that ``rollout`` asks at every frame;
at each cycle's start it looks at the path ahead in the eel's own frame and
mixes into the straight gait the share of turn-left or turn-right that
turns towards it, blending the switch over a quarter cycle (without
``rates``, the paper's rule: one whole manoeuvre or straight). Prints the
manoeuvre and share of every cycle and how far the eel kept from the path;
writes the picture of its way (the path in red) and the video. The command
line does the same: ``aquagait follow eel2d --path circle:radius=0.6
--cycles 12``.

Run:  python examples/06_follow_a_path.py [--cycles 12] [--radius 0.6] [--out runs/ex06]
(``--steps N`` swims N frames only, on a small grid, for a quick look.)
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import aquagait as ag
from aquagait.app.course import turn_rates
from aquagait.path import Follower, root_pose, shape
from aquagait.path import Path as Route


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cycles", type=int, default=12, help="gait cycles to swim")
    parser.add_argument("--radius", type=float, default=0.6, help="the circle's radius [m]")
    parser.add_argument("--out", default="runs/ex06", help="where the pictures go")
    parser.add_argument("--steps", type=int, help="swim this many frames only")
    args = parser.parse_args(argv)

    eel = ag.creatures.get("eel2d")
    quick = args.steps is not None
    grid = ((48, 48), 0.025) if quick else ((128, 128), 0.01)  # square: it turns
    scene = ag.make_scene(eel, *grid, fluid="euler")
    start, _ = root_pose(scene, ag.init_state(scene).qpos)
    path = Route(shape("circle", radius=args.radius).points + start)
    library = {m: eel.spec(m).unpack(eel.maneuver_gait(m)) for m in eel.maneuvers}
    print(f"eel2d has learned: {', '.join(library)}")
    rates = turn_rates(eel, scene, library["straight"], library, period=1.0)
    print("their turn a cycle: " + ", ".join(f"{m} {r:.2f} rad" for m, r in rates.items()))
    follower = Follower(scene, library, eel.servo, path, period=1.0,
                        dead_band=0.1 * eel.model.body_length, rates=rates)  # fmt: skip
    seconds = args.steps / 30 if quick else float(args.cycles)
    traj = ag.rollout(scene, ag.init_state(scene), None, seconds, plan=follower)

    distance = [path.distance(root_pose(scene, q)[0]) for q in traj.qpos]
    length = eel.model.body_length
    chosen = [f"{d.maneuver} {d.shares.get(d.maneuver, 0.0):.2f}" for d in follower.decisions]
    print("manoeuvre and share per cycle: " + ", ".join(chosen))
    print(f"distance to the path: mean {np.mean(distance) / length:.2f}, "
          f"max {np.max(distance) / length:.2f} body lengths")  # fmt: skip

    from aquagait.viz.follow import draw_follow, render_follow

    out = Path(args.out)
    draw_follow(traj, eel.model, path.points, out / "follow.png")
    video = render_follow(traj, eel.model, path.points, out / "swim.mp4")
    print(f"wrote {out / 'follow.png'} and {video}")


if __name__ == "__main__":
    main()
