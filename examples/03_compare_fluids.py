"""03 - One gait, two fluids: the accordion swims in the Euler fluid, barely in the simple one.

Shows the paper's §7 point with the library's accordion2d: the same creature
and the same gait (ten joints folding in phase, one amplitude) run in the
inviscid Euler fluid, two-way coupled, and in the simple drag model, where
every surface element feels -k rho A v_n^2 n. Prints the root's displacement
along x after every simulated second in both, and how far apart they end.

Run:  python examples/03_compare_fluids.py [--seconds 3] [--amplitude 0.7] [--steps N]
(``--steps N`` stops each swim after N frames, for a quick look.)
"""

from __future__ import annotations

import argparse

import aquagait as ag


def swim(fluid: str, params, seconds: float, frames: int | None):
    accordion = ag.creatures.get("accordion2d")
    scene = ag.make_scene(accordion, fluid=fluid)
    seconds = seconds if frames is None else frames / 30
    return ag.rollout(scene, ag.init_state(scene), accordion.policy(params), seconds)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=3.0, help="simulated time [s]")
    parser.add_argument("--amplitude", type=float, default=0.7, help="fold amplitude [rad]")
    parser.add_argument("--steps", type=int, help="stop after this many frames")
    args = parser.parse_args(argv)

    accordion = ag.creatures.get("accordion2d")
    params = accordion.gait.pack(amplitude=args.amplitude)
    trajectories = {f: swim(f, params, args.seconds, args.steps) for f in ("euler", "simple")}
    print(f"{'t [s]':>6} {'Euler x [m]':>12} {'simple x [m]':>13}")
    euler, simple = trajectories["euler"], trajectories["simple"]
    for k in range(0, len(euler.time), 30 if args.steps is None else 1):
        x_euler = euler.qpos[k, 0] - euler.qpos[0, 0]
        x_simple = simple.qpos[k, 0] - simple.qpos[0, 0]
        print(f"{euler.time[k]:>6.2f} {x_euler:>+12.4f} {x_simple:>+13.4f}")
    end_euler = euler.qpos[-1, 0] - euler.qpos[0, 0]
    end_simple = simple.qpos[-1, 0] - simple.qpos[0, 0]
    ratio = abs(end_simple / end_euler) if end_euler else float("nan")
    print(f"after {euler.time[-1]:.2f} s the simple fluid carried it {ratio:.1%} as far")


if __name__ == "__main__":
    main()
