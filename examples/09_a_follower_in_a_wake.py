"""09 - A follower in its leader's wake: the same gait, three lags, three costs of transport.

Two eel2d in line in one fluid, half a body length of clear water between
the leader's tail and the follower's head, both on the shipped gait; the
follower's lags behind the leader's by 0, 0.1 and 0.5 cycles. For each lag
the pair swims from rest and the example prints how far each went, on how
much work, and the follower's cost of transport against its leader's.
Measured over 8 s: 5.8 % below at lag 0, 9.8 % below at 0.1 (about the lag a
search inside the group finds, docs/schools.md) and 4.3 % above at 0.5. The
command line does one of these:
``aquagait swim eel2d --formation in-line --spacing 0.5 --phase 0.1 --seconds 8``.

Run:  python examples/09_a_follower_in_a_wake.py [--seconds 8] [--out runs/ex09]
(``--steps N`` swims N frames only, in the simple fluid, for a quick look.)
About a minute a lag on one core.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from aquagait.app.school import formation_members, prepare_school, run_school, write_school

LAGS = (0.0, 0.1, 0.5)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=8.0, help="each pair's swim [s]")
    parser.add_argument("--out", default="runs/ex09", help="where the runs go")
    parser.add_argument("--steps", type=int, help="swim this many frames only")
    args = parser.parse_args(argv)

    quick = args.steps is not None
    fluid = "simple" if quick else "euler"
    seconds = args.steps / 30 if quick else args.seconds
    for lag in LAGS:
        members = formation_members("eel2d", "in-line", spacing=0.5, phase=lag)
        run = run_school(prepare_school(members, seconds=seconds, fluid=fluid))
        out = write_school(run, Path(args.out) / f"lag-{lag:g}")
        leader, follower = (run.member_metrics[m.label] for m in run.setup.members)
        print(f"lag {lag:g} cycles: leader {leader['distance']:.2f} m on {leader['energy']:.3g} J, "
              f"follower {follower['distance']:.2f} m on {follower['energy']:.3g} J; the "
              f"follower's cost of transport is {_ratio(follower, leader)} its leader's "
              f"(wrote {out})")  # fmt: skip


def _ratio(follower: dict, leader: dict) -> str:
    """The follower's cost of transport against the leader's, in words."""
    if not leader["cost_of_transport"] > 0 or not follower["cost_of_transport"] > 0:
        return "not comparable with"  # a pair that has not moved yet
    change = follower["cost_of_transport"] / leader["cost_of_transport"] - 1
    return f"{abs(change):.1%} {'below' if change < 0 else 'above'}"


if __name__ == "__main__":
    main()
