"""Does a swim depend on the step, the grid or the domain? ``aquagait check --convergence``.

    study = convergence_study("eel2d")          # six swims of the shipped gait, 2 s from rest
    print(format_convergence(study))            # the table, with the verdicts

A simulator's first check is to refine the step and the cell and see the
answer stay put. The study swims the creature's default gait from rest on
its default grid at its default longest step, then at a third and a sixth of
that step, then on grids 1.5x and 2x finer over the same domain (the cell
shrinks, the box stays), then with the same cell on a grid 1.5x as large
in every axis (more cells, centred on the creature as the default is, on
the same lattice), and compares the distances swum:

- step: the default step's distance within ``STEP_TOLERANCE`` of a sixth of
  the step's;
- grid: the default grid's within ``GRID_TOLERANCE`` of the 2x finer one's;
- domain: the default domain's within ``DOMAIN_TOLERANCE`` of the 1.5x
  larger one's (the open boundary and the grid's shifts, docs/method-fluid.md,
  must not steer the swim).

A finer grid costs about ``2^dim`` times the cells and, through the CFL
limit, up to twice the steps, so the 2x swim of a 3D creature takes about
16x the default one's time (the frog's, minutes); the larger domain costs
``1.5^dim`` times the cells at the same steps (3.4x in 3D). ``cases`` picks
fewer.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from aquagait.app.errors import SetupError
from aquagait.app.resolve import find_creature
from aquagait.creatures import Creature
from aquagait.creatures.creature import STRAIGHT
from aquagait.io.run import write_json
from aquagait.metrics import travel_metrics
from aquagait.sim import init_state, make_scene, rollout
from aquagait.sim.fluids import EulerFluid

STEP_TOLERANCE = 0.03
"""The default step's distance may differ from a sixth of the step's by this fraction."""

GRID_TOLERANCE = 0.05
"""The default grid's distance may differ from the 2x finer grid's by this fraction."""

DOMAIN_TOLERANCE = 0.03
"""The default domain's distance may differ from the 1.5x larger one's by this fraction."""


@dataclass(frozen=True)
class Case:
    """One swim: the grid ``refine`` times finer per axis over the same domain, the step
    ``divide`` times shorter, the domain ``enlarge`` times larger per axis with the same cell."""

    label: str
    refine: float = 1.0
    divide: int = 1
    enlarge: float = 1.0


CASES = (
    Case("default"),
    Case("step / 3", divide=3),
    Case("step / 6", divide=6),
    Case("grid x1.5", refine=1.5),
    Case("grid x2", refine=2.0),
    Case("domain x1.5", enlarge=1.5),
)
"""The study's swims; the first is the reference every other is compared with."""


@dataclass(frozen=True)
class Swim:
    """One case swum: where and how, and how far.

    Attributes:
        case: the case.
        resolution: cells per axis.
        cell_size: h [m].
        origin: the grid's lower corner at the start [m], one entry per axis.
        dt: the longest step [s].
        distance: distance swum by the centre of mass [m].
        energy: actuators' work [J].
        seconds: wall time [s].
    """

    case: Case
    resolution: tuple[int, ...]
    cell_size: float
    origin: tuple[float, ...]
    dt: float
    distance: float
    energy: float
    seconds: float


@dataclass(frozen=True)
class ConvergenceStudy:
    """A finished study: the creature, how long each swim was, and the swims in ``CASES`` order."""

    creature: Creature
    duration: float
    fluid: EulerFluid
    swims: list[Swim] = field(default_factory=list)

    def swim(self, label: str) -> Swim | None:
        """The swim of the case called ``label``, or None when the study left it out."""
        return next((s for s in self.swims if s.case.label == label), None)

    @property
    def step_change(self) -> float | None:
        """The default step's distance relative to a sixth of the step's, minus 1."""
        return _change(self.swim("default"), self.swim("step / 6"))

    @property
    def grid_change(self) -> float | None:
        """The default grid's distance relative to the 2x finer grid's, minus 1."""
        return _change(self.swim("default"), self.swim("grid x2"))

    @property
    def domain_change(self) -> float | None:
        """The default domain's distance relative to the 1.5x larger one's, minus 1."""
        return _change(self.swim("default"), self.swim("domain x1.5"))

    def verdicts(self) -> list[str]:
        """One line per target the study measured: met or missed, by how much."""
        lines = []
        for change, tolerance, what in (
            (self.step_change, STEP_TOLERANCE, "step: default vs step / 6"),
            (self.grid_change, GRID_TOLERANCE, "grid: default vs grid x2"),
            (self.domain_change, DOMAIN_TOLERANCE, "domain: default vs domain x1.5"),
        ):
            if change is not None:
                verdict = "within" if abs(change) <= tolerance else "OUTSIDE"
                lines.append(f"{what}: {change:+.1%} ({verdict} {tolerance:.0%})")
        return lines

    def numbers(self) -> dict:
        """The study as plain JSON values."""
        return {
            "creature": self.creature.name,
            "duration": self.duration,
            "fluid": self.fluid.settings(),
            "swims": [
                {
                    "case": s.case.label,
                    "resolution": list(s.resolution),
                    "cell_size": s.cell_size,
                    "origin": list(s.origin),
                    "dt": s.dt,
                    "distance": s.distance,
                    "energy": s.energy,
                    "seconds": s.seconds,
                }
                for s in self.swims
            ],  # fmt: skip
            "step_change": self.step_change,
            "grid_change": self.grid_change,
            "domain_change": self.domain_change,
        }


def _change(swim: Swim | None, reference: Swim | None) -> float | None:
    if swim is None or reference is None or reference.distance == 0:
        return None
    return swim.distance / reference.distance - 1.0


def convergence_study(
    name_or_creature,
    duration: float = 2.0,
    fluid: EulerFluid | None = None,
    cases=CASES,
    progress=None,
) -> ConvergenceStudy:
    """Swim the creature's default gait from rest in every case (module docstring).

    Args:
        name_or_creature: a library name, the path of an MJCF file, or a ``Creature``.
        duration: seconds swum in each case [s], > 0.
        fluid: the Euler fluid (its coupling, tolerance); default ``EulerFluid()``.
        cases: the cases to swim, the reference first.
        progress: optional ``progress(swim)``, called after every case.
    Raises:
        SetupError: an unknown creature, or a bad duration.
    """
    creature = (
        name_or_creature if isinstance(name_or_creature, Creature)
        else find_creature(name_or_creature)
    )  # fmt: skip
    if not (np.isfinite(duration) and duration > 0):
        raise SetupError(
            f"the study's duration must be a positive number of seconds, got {duration!r}"
        )
    fluid = EulerFluid() if fluid is None else fluid
    policy = creature.policy(creature.default_gait, STRAIGHT)
    swims = []
    for case in cases:
        resolution, h = refined_grid(creature.resolution, creature.cell_size, case.refine)
        resolution = enlarged_grid(resolution, case.enlarge)
        scene = make_scene(creature, resolution=resolution, cell_size=h, fluid=fluid)
        dt = fluid.max_dt / case.divide
        start = time.perf_counter()
        trajectory = rollout(scene, init_state(scene), policy, duration, dt=dt, record_fluid=False)
        figures = travel_metrics(creature.model, trajectory)  # distance, energy: no period
        swim = Swim(case, resolution, h, scene.grid.origin, dt, figures["distance"],
                    figures["energy"], time.perf_counter() - start)  # fmt: skip
        swims.append(swim)
        if progress is not None:
            progress(swim)
    return ConvergenceStudy(creature, duration, fluid, swims)


def refined_grid(resolution, cell_size: float, refine: float) -> tuple[tuple[int, ...], float]:
    """The grid ``refine`` times finer over the same domain: cells per axis rounded,
    and the cell that keeps the first axis's length [m]."""
    cells = tuple(max(1, int(round(n * refine))) for n in resolution)
    return cells, cell_size * resolution[0] / cells[0]


def enlarged_grid(resolution, enlarge: float) -> tuple[int, ...]:
    """The cells per axis of a domain ``enlarge`` times as large with the same cell: the
    nearest count that adds an even number of cells, so that a grid centred on the
    creature as the default is (``make_scene``) puts its cells where the default's are."""
    return tuple(n + 2 * int(round(n * (enlarge - 1) / 2)) for n in resolution)


def format_convergence(study: ConvergenceStudy) -> str:
    """The study as a table (distance, change from the default, energy, wall time) and verdicts."""
    reference = study.swims[0].distance if study.swims else 0.0
    lines = [
        f"{study.creature.name}: default gait, {study.duration:g} s from rest",
        f"{'case':<12}{'grid':>14}{'h [mm]':>8}{'dt [s]':>10}{'distance [m]':>14}"
        f"{'vs default':>11}{'energy [J]':>12}{'wall [s]':>10}",
    ]
    for s in study.swims:
        change = s.distance / reference - 1.0 if reference else float("nan")
        grid = "x".join(map(str, s.resolution))
        lines.append(
            f"{s.case.label:<12}{grid:>14}{1e3 * s.cell_size:>8.2f}{f'1/{1 / s.dt:.0f}':>10}"
            f"{s.distance:>14.4f}{change:>+11.1%}{s.energy:>12.3f}{s.seconds:>10.0f}"
        )
    return "\n".join(lines + study.verdicts())


def write_convergence(study: ConvergenceStudy, out) -> list[str]:
    """Write ``convergence.txt`` and ``convergence.json`` into ``out``; returns their names."""
    out = Path(out)
    (out / "convergence.txt").write_text(format_convergence(study) + "\n")
    write_json(out / "convergence.json", study.numbers())
    return ["convergence.txt", "convergence.json"]
