"""01 - A creature swims its default gait in vacuum.

Shows the body half of aquagait on its own: load a library creature, build a
vacuum scene (``fluid="none"``), and step it with the stable PD servo
tracking the creature's hand-set travelling-wave gait. With only internal
joint torques the creature wriggles but goes nowhere: its centre of mass
stays put (up to the first-order drift of the integrator). Prints, per
simulated frame, the tracking error, the energy spent and the centre of mass.

Run:  python examples/01_vacuum_gait.py [--creature fish] [--steps 600] [--dt 0.005]
"""

from __future__ import annotations

import argparse

import numpy as np

import aquagait as ag


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--creature", default="eel2d", choices=ag.creatures.names())
    parser.add_argument("--steps", type=int, default=400, help="simulation steps")
    parser.add_argument("--dt", type=float, default=0.005, help="time step [s]")
    args = parser.parse_args(argv)

    creature = ag.creatures.get(args.creature)
    scene = ag.make_scene(creature, fluid="none")
    state = ag.init_state(scene)
    policy = creature.policy()  # stable PD tracking creature.default_gait
    joints = creature.model.actuated_dofs
    com0 = scene.dynamics.center_of_mass(state.qpos)
    print(f"{creature.name}: {creature.description}; mass {creature.model.mass * 1000:.1f} g")
    print(f"{'t [s]':>6} {'max |q - qbar| [rad]':>21} {'energy [J]':>11} {'CoM moved [mm]':>15}")
    every = max(1, round(0.1 / args.dt))
    for n in range(1, args.steps + 1):
        state = ag.step(scene, state, args.dt, policy)
        if n % every == 0 or n == args.steps:
            error = np.abs(policy.error(state.time, state.qpos)[joints]).max()
            moved = np.linalg.norm(scene.dynamics.center_of_mass(state.qpos) - com0) * 1000
            print(f"{state.time:6.2f} {error:21.4f} {state.energy.sum():11.2e} {moved:15.3f}")


if __name__ == "__main__":
    main()
