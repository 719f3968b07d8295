"""05 - The fish swims in 3D and is filmed in 3D, its wake drawn as particle traces.

Shows the 3D pictures: simulate the fish's shipped gait in the Euler fluid
(the whole 3D flow is kept per frame, ``aquagait.sim.FluidFrames``), then
draw it with the headless OpenGL renderer from one of three cameras that
follow the swimmer: a GIF (or MP4) of the swim, and a contact sheet of six
frames. Needs the ``viz`` and ``render`` extras and EGL (Debian:
``libegl1``, ``libgl1-mesa-dri``); without OpenGL it says what to install.

Run:  python examples/05_fish_in_3d.py [--seconds 2] [--view follow|side|top] [--out runs/ex05]
(``--steps N`` swims N frames only, for a quick look.)
"""

from __future__ import annotations

import argparse
from pathlib import Path

import aquagait as ag
from aquagait.viz import render_swim
from aquagait.viz.gl import RenderUnavailable


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=2.0, help="simulated time [s]")
    parser.add_argument("--view", default="follow", choices=("follow", "side", "top"))
    parser.add_argument("--out", default="runs/ex05", help="where the pictures go")
    parser.add_argument("--steps", type=int, help="swim this many frames only")
    args = parser.parse_args(argv)

    fish = ag.creatures.get("fish")
    quick = args.steps is not None
    grid = ((32, 20, 24), 0.008) if quick else (None, None)  # quick: a small grid
    scene = ag.make_scene(fish, *grid, fluid="euler")
    seconds = args.steps / 30 if quick else args.seconds
    traj = ag.rollout(scene, ag.init_state(scene), fish.policy(), seconds)
    print(f"fish swam {traj.qpos[-1, 0] - traj.qpos[0, 0]:+.4f} m along x in {seconds:.2f} s; "
          f"kept {traj.fluid.velocity.nbytes / 1e6:.1f} MB of flow")  # fmt: skip
    out = Path(args.out)
    size = {"width": 320, "height": 240} if quick else {}
    try:
        video = render_swim(traj, fish.model, out / "swim.gif", view=args.view, **size)
        sheet = render_swim(traj, fish.model, out / "sheet.png", view=args.view, **size)
    except RenderUnavailable as err:
        print(f"no pictures: {err}")
        return
    print(f"wrote {video} and {sheet}")


if __name__ == "__main__":
    main()
