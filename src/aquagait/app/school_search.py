"""Search one creature's gait, or its phase, inside a group (docs/schools.md).

    members = formation_members("eel2d", "in-line:2", spacing=0.5)
    setup = prepare_school_search(members, searched="eel2d-2", objective="efficiency")
    result = run_optimization(setup.search_setup, "runs/eel2d-follower", executor)
    best = write_school_search(setup, result, "runs/eel2d-follower")  # gait.json, scene.json
    run = run_school(best)                                  # the group with the best found

The searched creature swims in the group from the group's start, the others
on their given gaits and phases; its objective (the paper's distance
objective, or the efficiency objective) is measured on its own part of the
group's swim (``aquagait.sim.group.member_trajectory``), exactly as a lone
creature's search measures its swim. ``GroupObjective`` is the one seam:
a ``SwimObjective`` whose swim is the group's, so the search itself, its
checkpoint and its parallel evaluation are the lone creature's, and the same
seed gives the same gait serially, in processes and on a Dask cluster. A
sample in which two creatures touch raises ``CreaturesTouched`` and scores
the search's penalty. Unlike a lone creature's, the group's grid grows when
the group spreads (a follower pushed aside by the wake), as a group swim's
does, so such a sample is scored, not penalized.

Searching the ``phase`` is a search over one number: the searched creature's
lag behind the group's clock, in its gait's cycles, within [0, 1].
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from aquagait import creatures
from aquagait.app.optimize import (
    OptimizationSetup,
    SwimObjective,
    check_objective,
    efficiency_unit,
    prepare_optimization,
    search_fluid,
)
from aquagait.app.resolve import creature_key
from aquagait.app.school import MemberSpec, SchoolSetup, SchoolSetupError, prepare_school
from aquagait.body.group import Pose, compose
from aquagait.control.group import GroupPolicy
from aquagait.creatures.creature import STRAIGHT
from aquagait.io.gait import write_gait
from aquagait.io.run import write_json
from aquagait.objectives import EFFICIENCY_CYCLES
from aquagait.optimize import Problem, Result
from aquagait.sim import EulerFluid, init_state, make_scene, rollout
from aquagait.sim.group import member_trajectory

SEARCHES = ("gait", "phase")
"""What a search inside a group varies: the searched creature's gait, or its phase."""


@dataclass(frozen=True)
class GroupObjective(SwimObjective):
    """``evaluate(params) -> float``: the objective of one member's swim in its group.

    A ``SwimObjective`` (its fields say how the searched member is scored) whose swim
    is the whole group's, scored on the searched member's part.

    Attributes:
        school: each member as ``(creature key, label, offset, heading, params, phase)``,
            the params a tuple of its gait's numbers; picklable, so workers build the
            same group.
        member: the searched member's index.
        search: 'gait' (``params`` is its gait, in its ``spec()``'s names) or 'phase'
            (``params`` is ``[lag]``, in cycles).
        origin: the group grid's lower corner [m] (``resolution`` and ``cell_size``
            are the group grid's).
    """

    school: tuple = ()
    member: int = 0
    search: str = "gait"
    origin: tuple[float, ...] | None = None

    def _swim(self, params):
        placed = tuple(entry[:4] for entry in self.school)
        (group_creatures, lone_scenes), scene = _group_scene(
            placed, self.resolution, self.cell_size, self.origin, self.fluid_model()
        )
        gaits = []
        for k, (creature, entry) in enumerate(zip(group_creatures, self.school, strict=True)):
            own, phase = np.asarray(entry[4]), entry[5]
            if k == self.member:
                if self.search == "gait":
                    own = np.asarray(params, dtype=float)
                else:
                    phase = float(np.asarray(params).reshape(-1)[0])
            gaits.append(creature.spec().unpack(own).lagging(phase))
        servos = [c.servo(g) for c, g in zip(group_creatures, gaits, strict=True)]
        period = float(np.max(gaits[self.member].period))
        seconds = self.seconds if self.cycles is None else self.cycles * period
        traj = rollout(scene, init_state(scene), GroupPolicy(scene.group, servos), seconds,
                       record_fluid=False)  # fmt: skip
        member = scene.group.members[self.member]
        return (group_creatures[self.member], lone_scenes[self.member],
                member_trajectory(traj, member), period)  # fmt: skip

    def fluid_model(self):
        """The lone search's fluid (``search_fluid``), but the Euler fluid's grid grows when
        the group spreads (module doc)."""
        fluid = search_fluid(self.fluid, self.clearance)
        return replace(fluid, grow=True) if isinstance(fluid, EulerFluid) else fluid

    def scene_config(self) -> dict:
        """The group, the searched member and what is searched, for ``config.json``."""
        return {
            "school": {
                "members": [
                    {"creature": key, "label": label, "offset": list(offset), "heading": heading,
                     "params": list(params), "phase": phase}
                    for key, label, offset, heading, params, phase in self.school
                ],
                "searched": self.school[self.member][1],
                "search": self.search,
                "origin": None if self.origin is None else list(self.origin),
            }
        }  # fmt: skip


@functools.lru_cache(maxsize=2)
def _group_scene(placed, resolution, cell_size, origin, fluid):
    """A group's creatures, each one's own vacuum scene (the objective's terms read a
    member's model, shape and dynamics from it) and the group's scene, built once per
    process. ``placed``: each member's ``(key, label, offset, heading)``."""
    found = tuple(creatures.resolve(key) for key, *_ in placed)
    group = compose([c.model for c in found], [label for _, label, *_ in placed],
                    [Pose(tuple(offset), heading) for *_, offset, heading in placed])  # fmt: skip
    scene = make_scene(group, resolution, cell_size, fluid=fluid, origin=origin)
    lone = tuple(make_scene(member.model) for member in group.members)
    return (found, lone), scene


@dataclass(frozen=True, eq=False)
class SchoolSearchSetup:
    """A search inside a group: the group as given (``school``), which member is searched
    (``member``, its index), what (``search``), the search itself (``search_setup``, an
    ``OptimizationSetup`` whose objective is a ``GroupObjective``) and the grid as asked
    for (``grid``: ``resolution`` and ``cell_size``, either absent for the default), which
    the best's group is built with again."""

    school: SchoolSetup
    member: int
    search: str
    search_setup: OptimizationSetup
    grid: dict

    @property
    def label(self) -> str:
        """The searched member's label."""
        return self.school.members[self.member].label


def prepare_school_search(
    members,
    searched: str | None = None,
    search: str = "gait",
    objective: str = "distance",
    min_speed: float | None = None,
    cycles: float | None = None,
    resolution=None,
    cell_size: float | None = None,
    fluid: str = "euler",
    step: float | None = None,
    formation: dict | None = None,
    **options,
) -> SchoolSearchSetup:
    """Resolve a search of one member's gait or phase inside a group.

    Args:
        members: the group (``aquagait.app.school.formation_members``, ``read_scene_file``).
        searched: the searched member's label; None: the last (a formation's last
            follower).
        search: 'gait' (its gait, from its given one) or 'phase' (its lag, from its
            given one, the gait kept).
        objective: 'distance' (the paper's) or 'efficiency' (``prepare_optimization``),
            measured on the searched member; the efficiency objective's unit is its cost
            of transport in the group with its given gait and phase.
        min_speed: as ``prepare_optimization``'s.
        cycles: as ``prepare_optimization``'s.
        resolution: the group's grid (``prepare_school``).
        cell_size: the group's grid (``prepare_school``).
        fluid: the group's fluid (``prepare_school``).
        step: as ``prepare_optimization``'s.
        formation: how the members were made, recorded in ``config.json``.
        options: ``prepare_optimization``'s budget and weights: ``generations``,
            ``popsize``, ``seed``, ``max_evaluations``, ``patience``, ``energy_weight``,
            ``deviation_weight``, ``surrogate``, ``surrogate_batch``.

    Raises:
        SchoolSetupError: the group cannot swim (``prepare_school``), or an unknown member
            or search.
        OptimizationSetupError: a bad budget or objective setting.
    """
    if search not in SEARCHES:
        raise SchoolSetupError(f"unknown search {search!r}; give one of {', '.join(SEARCHES)}")
    school = prepare_school(members, fluid=fluid, resolution=resolution, cell_size=cell_size,
                            formation=formation)  # fmt: skip
    labels = [m.label for m in school.members]
    label = labels[-1] if searched is None else searched
    if label not in labels:
        raise SchoolSetupError(
            f"no creature labelled {label!r} in the group to search; its creatures: "
            f"{', '.join(labels)}"
        )
    k = labels.index(label)
    spec, creature = school.members[k], school.creatures[k]
    check_objective(objective, STRAIGHT, min_speed, cycles)
    if cycles is None and objective == "efficiency":
        cycles = EFFICIENCY_CYCLES
    # the lone search's start, bounds, weights and budget, checked; in the vacuum, as its
    # own grid and the notes on it (room, a coarse grid) are not the group's
    lone = prepare_optimization(creature_key(creature), start=spec.gait, cycles=cycles,
                                fluid="none", step=step, **options)  # fmt: skip
    grid = school.scene.grid
    fields = {name: getattr(lone.objective, name) for name in SwimObjective.__dataclass_fields__}
    group_objective = GroupObjective(
        **{**fields, "fluid": fluid},
        school=tuple(
            (creature_key(c), m.label, tuple(m.offset), m.heading, tuple(map(float, p)), m.phase)
            for c, m, p in zip(school.creatures, school.members, school.params, strict=True)
        ),
        member=k,
        search=search,
    )  # fmt: skip
    if grid is not None:
        group_objective = replace(group_objective, resolution=tuple(grid.shape),
                                  cell_size=grid.cell_size, origin=tuple(grid.origin))  # fmt: skip
    problem = replace(lone.problem, objective=group_objective)
    if search == "phase":
        problem = Problem(group_objective, x0=[spec.phase % 1.0], lower=[0.0], upper=[1.0],
                          sigma0=step, names=("phase",))  # fmt: skip
    notes = ()
    if objective == "efficiency":
        group_objective, measured = efficiency_unit(replace(group_objective, objective=objective),
                                                problem.x0, min_speed)  # fmt: skip
        problem = replace(problem, objective=group_objective)
        notes += tuple(f"{label} in the group: {note}" for note in measured)
    search_setup = replace(lone, objective=group_objective, problem=problem, notes=notes)
    asked = {"resolution": resolution, "cell_size": cell_size}
    grid = {key: value for key, value in asked.items() if value is not None}
    return SchoolSearchSetup(school, k, search, search_setup, grid)


def best_members(setup: SchoolSearchSetup, best_x, gait_file) -> tuple[MemberSpec, ...]:
    """The group's members with the searched one's best: its gait from ``gait_file`` (a
    gait search) or its best phase (a phase search)."""
    members = list(setup.school.members)
    k = setup.member
    if setup.search == "gait":
        members[k] = replace(members[k], gait=str(Path(gait_file).resolve()))
    else:
        members[k] = replace(members[k], phase=float(np.asarray(best_x).reshape(-1)[0]))
    return tuple(members)


def write_school_search(
    setup: SchoolSearchSetup, result: Result, out, plot: bool = True
) -> SchoolSetup:
    """Write the searched member's gait (``gait.json``), the group with its best
    (``scene.json``, a scene file ``aquagait swim`` takes) and, if ``plot``,
    ``convergence.png`` into ``out``; the group to swim with its best, on the search's
    grid and for as long as a sample.

    ``optimization.csv`` and the checkpoint are the optimizer's.
    """
    out = Path(out)
    school, k = setup.school, setup.member
    params = result.best_x if setup.search == "gait" else school.params[k]
    gait_file = write_gait(out / "gait.json", school.creatures[k], params)
    members = best_members(setup, result.best_x, gait_file)
    objective = setup.search_setup.objective
    write_json(out / "scene.json", {
        "creatures": [
            {"name": creature_key(c), "label": m.label, "offset": list(m.offset),
             "heading": m.heading, "phase": m.phase,
             **({} if m.gait is None else {"gait": m.gait})}
            for c, m in zip(school.creatures, members, strict=True)
        ],
        **{key: list(value) if key == "resolution" else value
           for key, value in setup.grid.items()},
    })  # fmt: skip
    if plot:
        from aquagait.optimize import LOG
        from aquagait.viz import plot_convergence

        plot_convergence(out / LOG, out / "convergence.png", title=f"{setup.label} in its group")
    seconds = objective.seconds
    if objective.cycles is not None:
        seconds = objective.cycles * school.period(k)
    return prepare_school(members, seconds=seconds, fluid=objective.fluid,
                          formation=school.formation, **setup.grid)  # fmt: skip
