"""04 - Your own creature: write an MJCF, check it, optimize its gait briefly, swim it.

A planar three-link swimmer written as MJCF the way other MuJoCo projects
write models (a floor, a light, an actuator: scenery aquagait ignores with a
note), with no aquagait metadata at all: the defaults come from the model
(amplitude and phase for both hinges, period 1 s, a grid a few body lengths
long, an energy bound scaled by its mass). ``aquagait check`` would print the
same table; the same file works on the command line:

    aquagait check runs/own/swimmer.xml
    aquagait optimize runs/own/swimmer.xml --generations 10
    aquagait swim runs/own/swimmer.xml --gait runs/swimmer-optimize/gait.json

Run:  python examples/04_own_creature.py [--generations 6] [--out runs/own] [--steps N]
(``--steps N``: one generation of two samples, each swimming N frames, and a
swim of N frames, for a quick look.)
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import aquagait as ag
from aquagait.app import prepare_optimization, prepare_swim, run_optimization, run_swim
from aquagait.app.check import format_check, prepare_check, run_check

SWIMMER = """<mujoco model="three-link swimmer">
  <custom><numeric name="aquagait_depth" data="0.03"/></custom>
  <option timestep="0.002" viscosity="0.1"/>
  <worldbody>
    <light pos="0 0 2"/>
    <geom name="floor" type="plane" size="2 2 .1"/>
    <body name="head">
      <joint name="x" type="slide" axis="1 0 0"/><joint name="y" type="slide" axis="0 1 0"/>
      <joint name="yaw" type="hinge" axis="0 0 1"/>
      <geom type="box" size=".05 .015 .015" density="1000"/>
      <body name="middle" pos="-.05 0 0">
        <joint name="j1" type="hinge" axis="0 0 1" range="-60 60"/>
        <geom type="box" size=".05 .012 .015" pos="-.05 0 0" density="1000"/>
        <body name="tail" pos="-.1 0 0">
          <joint name="j2" type="hinge" axis="0 0 1" range="-60 60"/>
          <geom type="box" size=".05 .008 .015" pos="-.05 0 0" density="1000"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="j1"/><motor joint="j2"/></actuator>
</mujoco>
"""


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--generations", type=int, default=6, help="CMA-ES generations")
    parser.add_argument("--out", help="where to write swimmer.xml (default: a temporary folder)")
    parser.add_argument("--steps", type=int, help="frames per swim, for a quick look")
    args = parser.parse_args(argv)

    folder = Path(args.out or tempfile.mkdtemp(prefix="aquagait-own-"))
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "swimmer.xml"
    path.write_text(SWIMMER)

    creature = ag.creatures.load(path)  # the MJCF, its side-car if any, defaults filled
    print(format_check(run_check(prepare_check(path))))

    quick = args.steps is not None
    cycles = args.steps / 30 if quick else 2.0  # a gait cycle is 1 s
    setup = prepare_optimization(
        path, generations=1 if quick else args.generations, popsize=2 if quick else 8,
        resolution=(64, 32), cell_size=0.01, cycles=cycles,
    )  # fmt: skip
    result = run_optimization(setup)
    print(f"\nbest objective {result.best_f:.4g} after {result.evaluations} samples")
    best = {n: round(float(x), 3) for n, x in zip(creature.gait.names, result.best_x, strict=True)}
    print(f"best gait: {best}")

    swim = prepare_swim(path, gait=result.best_x, seconds=cycles if quick else 4.0,
                        resolution=(64, 32), cell_size=0.01)  # fmt: skip
    run = run_swim(swim)
    print(f"it swims {run.metrics['distance']:.3f} m in {run.metrics['duration']:.2f} s")


if __name__ == "__main__":
    main()
