"""Optimize a library creature's gait and keep the run on disk (docs/optimize.md).

    setup = prepare_optimization("eel2d", generations=30, resolution=(64, 32), cell_size=0.02)
    result = run_optimization(setup, run_dir="runs/eel2d", executor=local_executor(2))
    write_optimization(setup, result, "runs/eel2d")   # gait.json, convergence.png
    swim = best_swim(setup, "runs/eel2d")             # a SwimSetup of the best gait

The physics enters the optimizer through one seam, ``SwimObjective``: a
picklable ``evaluate(params) -> float`` that swims the gait for two cycles
and scores the run with ``aquagait.objectives``. Each process builds its
scene once and keeps it (``_scene``), so a worker pays for the MJCF and the
voxel geometry only on its first sample; the threads of a process share it
(a step writes only into the call's or the thread's scratch space, so a Dask
worker with several threads gives the serial numbers). Joint limits are
checked before anything is simulated (``feasible``).
"""

from __future__ import annotations

import functools
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np

from aquagait import creatures, objectives
from aquagait.app.coarse import coarse_grid
from aquagait.app.errors import SetupError
from aquagait.app.resolve import creature_key, find_creature, find_gait
from aquagait.app.swim import SwimRun, SwimSetup, prepare_swim, unsettled
from aquagait.creatures import Creature
from aquagait.creatures.creature import STRAIGHT, gait_problems, maneuver_start
from aquagait.io.gait import write_gait
from aquagait.metrics import Cycles, settled_cycle
from aquagait.objectives import EFFICIENCY_CYCLES, MIN_SPEED_SHARE, OBJECTIVES
from aquagait.optimize import Problem, Result, Settings, optimize
from aquagait.sim import EulerFluid, FluidModel, Scene, fluid_model, init_state, make_scene, rollout
from aquagait.sim.follow import CLEARANCE, cells_for, widest_box

DEFAULT_CYCLES = 2.0
"""Gait cycles simulated per sample (paper §4)."""


POPULATION = {2: 16, 3: 31}
"""The paper's CMA-ES population per creature dimension (§4); the default is CMA-ES's own
for the number of parameters (``aquagait.optimize.default_popsize``)."""

PAPER_GENERATIONS = 100
"""The paper's generations (§4); by default a search stops when it has converged."""


class OptimizationSetupError(SetupError):
    """An optimization cannot start: unknown creature, bad grid, bad budget."""


@dataclass(frozen=True)
class SwimObjective:
    """``evaluate(params) -> float``: the objective ``E`` of swimming a gait (picklable).

    Attributes:
        creature: a library creature's name or the absolute path of its MJCF
            file (``aquagait.app.resolve.creature_key``: workers find it by this).
        resolution: grid cells per axis, or None for the creature's default.
        cell_size: h [m], or None for the creature's default.
        fluid: 'euler', 'simple' (drag only), or 'none' (vacuum, to test the machinery).
        seconds: simulated time per sample [s] (two cycles).
        direction: desired swimming direction, (dim,).
        weights: the objective's weights.
        clearance: cells of water the Euler fluid keeps around the body, or
            None for its default (a coarse grid keeps fewer, as many metres).
        maneuver: the manoeuvre learned (``objectives.MANEUVERS``); the
            parameters are in its parameterization (``Creature.spec``).
        axis: the manoeuvre's desired axis of rotation (3,), None for straight.
        objective: 'distance' (the paper's, ``objectives.total``) or 'efficiency'
            (``objectives.efficiency_total``).
        min_speed: efficiency: the cruising speed to reach at least [m/s].
        reference_cost: efficiency: the starting gait's cost of transport [J/(kg m)],
            the unit of the cost term.
        free_period: the gait's period is a parameter (``Creature.spec``).
        cycles: when set, a sample swims this many of its own gait cycles instead of
            ``seconds`` (the efficiency objective with a free period: it measures whole
            cycles at cruise, and a slower rhythm takes longer to reach it).
        turn_limit: a manoeuvre: the most rotation about ``axis`` rewarded over a
            sample [rad] (``objectives.TURN``, 90 degrees, by default).
    """

    creature: str
    resolution: tuple[int, ...] | None
    cell_size: float | None
    fluid: str = "euler"
    seconds: float = 2.0
    direction: tuple[float, ...] = (1.0, 0.0)
    weights: objectives.Weights = field(default_factory=objectives.Weights)
    clearance: float | None = None
    maneuver: str = STRAIGHT
    axis: tuple[float, ...] | None = None
    objective: str = "distance"
    min_speed: float | None = None
    reference_cost: float | None = None
    free_period: bool = False
    cycles: float | None = None
    turn_limit: float = objectives.TURN

    def __call__(self, params) -> float:
        creature, scene, traj, period = self._swim(params)
        if self.objective == "efficiency":
            return objectives.efficiency_total(scene, traj, self.direction, period,
                                               self.min_speed, self.reference_cost,
                                               self.weights)  # fmt: skip
        return objectives.total(scene, traj, self.direction, creature.energy_bound, self.weights,
                                axis=self.axis, period=period,
                                turn_limit=self.turn_limit)  # fmt: skip

    def fingerprint(self) -> dict:
        """What makes it the same function, which a resumed search must share (``optimize``'s
        checkpoint): every field; the two measured from the start's swim (``reference_cost``
        and the default ``min_speed``) to six digits, as a swim's last bits may differ
        between machines. ``turn_limit`` is left out at its default, so checkpoints from
        before it existed resume."""
        values = asdict(self)
        if values["turn_limit"] == objectives.TURN:
            del values["turn_limit"]
        for name in ("min_speed", "reference_cost"):
            if values[name] is not None:
                values[name] = float(f"{values[name]:.6g}")
        return values

    def fluid_model(self) -> FluidModel:
        """The fluid a sample swims in (``search_fluid``)."""
        return search_fluid(self.fluid, self.clearance)

    def scene_config(self) -> dict:
        """What ``config.json`` says of the scene beyond the creature and its grid: nothing
        alone (a search inside a group names the group, ``app.school_search``)."""
        return {}

    def cruise(self, params) -> tuple[float, float, np.ndarray]:
        """Speed [m/s] and cost of transport [J/(kg m)] of the gait over the sample's last
        cycles (``objectives.cruise``), and the distance of each of its whole cycles [m]."""
        _, scene, traj, period = self._swim(params)
        speed, cost = objectives.cruise(scene.model, traj, self.direction, period)
        return speed, cost, Cycles(scene.model, traj, period).distances()

    def _swim(self, params):
        creature, scene = _scene(self.creature, self.resolution, self.cell_size, self.fluid,
                                 self.clearance)  # fmt: skip
        gait = creature.spec(self.maneuver, self.free_period).unpack(params)
        period = float(np.max(gait.period))
        seconds = self.seconds if self.cycles is None else self.cycles * period
        traj = rollout(scene, init_state(scene), creature.servo(gait), seconds,
                       record_fluid=False)  # fmt: skip
        return creature, scene, traj, period


@functools.lru_cache(maxsize=4)
def _scene(name: str, resolution, cell_size, fluid: str, clearance=None) -> tuple[Creature, Scene]:
    creature = creatures.resolve(name)
    fluid_model = search_fluid(fluid, clearance)
    return creature, make_scene(creature, resolution, cell_size, fluid=fluid_model)


def search_fluid(fluid: str, clearance: float | None) -> FluidModel:
    """The fluid model an objective swims in: by name; the Euler fluid with its clearance,
    on a grid that does not grow (a sample that leaves it is penalized)."""
    if fluid == "euler":
        return EulerFluid(grow=False, clearance=CLEARANCE if clearance is None else clearance)
    return fluid_model(fluid)


@dataclass(frozen=True)
class JointLimits:
    """``feasible(params) -> bool``: the gait's sines stay within the joint limits (picklable)."""

    creature: str
    maneuver: str = STRAIGHT
    free_period: bool = False

    def __call__(self, params) -> bool:
        creature = creatures.resolve(self.creature)
        spec = creature.spec(self.maneuver, self.free_period)
        return not spec.limit_violations(params, *creature.gait_limits(self.maneuver))


@dataclass(frozen=True, eq=False)
class OptimizationSetup:
    """Everything an optimization needs, resolved and checked.

    Attributes:
        creature: the creature.
        objective: the swim objective the samples are ranked by.
        problem: start, bounds, feasibility and groups for the optimizer; in a
            coarse-to-fine search ``problem.refine`` is the swim on the target
            grid and ``objective`` the one on the coarse grid.
        settings: population, generations, seed, evaluation cap, convergence rule.
        notes: what to know about the search (a coarse grid that may rank poorly).
        start: the gait the search started from (a file or a shipped gait's name),
            None for the default start.
        step: the initial standard deviation as a fraction of each range, None
            for the default (a quarter).
    """

    creature: Creature
    objective: SwimObjective
    problem: Problem
    settings: Settings
    notes: tuple[str, ...] = ()
    start: str | None = None
    step: float | None = None

    @property
    def target(self) -> SwimObjective:
        """The swim the search is for: the refined one in a coarse-to-fine search."""
        return self.problem.refine or self.objective

    def config(self) -> dict:
        """The resolved settings, for ``config.json``."""
        o, s = self.objective, self.settings
        return dict(
            creature=self.creature.name, maneuver=o.maneuver,
            axis=None if o.axis is None else list(o.axis), fluid=o.fluid,
            fluid_settings=o.fluid_model().settings(),
            resolution=o.resolution,
            cell_size=o.cell_size, clearance=o.clearance, seconds_per_sample=o.seconds,
            direction=list(o.direction), objective=o.objective, min_speed=o.min_speed,
            free_period=o.free_period, cycles_per_sample=o.cycles,
            turn_limit=None if o.axis is None else o.turn_limit,
            reference_cost_of_transport=o.reference_cost,
            cruise_cycles=objectives.EFFICIENCY_WINDOW if o.objective == "efficiency" else None,
            weights=vars(o.weights), energy_bound=self.creature.energy_bound,
            popsize=s.popsize, generations=s.generations, seed=s.seed,
            populations=self.populations(), max_evaluations=s.max_evaluations,
            patience=s.patience, tolerance=s.tolerance,
            parameters=list(self.problem.names), start=self.start, step=self.step,
            x0=self.problem.x0.tolist(),
            lower=self.problem.lower.tolist(), upper=self.problem.upper.tolist(),
            sigma0=self.problem.sigma0,
            target_grid=None if self.problem.refine is None else
            [self.target.resolution, self.target.cell_size],
            refine_top=None if self.problem.refine is None else s.refine_top,
            surrogate=s.surrogate, surrogate_batch=s.surrogate_batch if s.surrogate else None,
            **o.scene_config(),
        )  # fmt: skip

    def populations(self) -> list[int]:
        """Samples per generation of each group in turn (one entry without groups)."""
        return [self.settings.for_group(len(group))[0] for group in self.problem.phases()]

    def budget(self) -> str:
        """When the search stops, in words (for the first line of ``aquagait optimize``)."""
        s = self.settings
        popsizes = sorted(set(self.populations()))
        words = [f"population {'/'.join(map(str, popsizes))}"]
        if s.generations is not None:
            words.append(f"at most {s.generations} generations")
        patience = sorted({s.for_group(len(g))[1] or 0 for g in self.problem.phases()})
        if patience != [0]:
            words.append(
                f"until the best improves less than {100 * s.tolerance:g} % in "
                f"{'/'.join(map(str, patience))} generations"
            )
        if s.max_evaluations is not None:
            words.append(f"at most {s.max_evaluations} evaluations")
        if s.surrogate:
            words.append(f"lq-CMA-ES surrogate, swimming {s.surrogate_batch} or more at a time")
        return ", ".join(words)


def prepare_optimization(
    name: str,
    generations: int | None = None,
    popsize: int | None = None,
    seed: int = 0,
    resolution=None,
    cell_size: float | None = None,
    fluid: str = "euler",
    cycles: float | None = None,
    coarse: float | None = None,
    refine_top: int = 2,
    maneuver: str = STRAIGHT,
    start=None,
    step: float | None = None,
    energy_weight: float | None = None,
    deviation_weight: float | None = None,
    max_evaluations: int | None = None,
    patience: int | None = None,
    objective: str = "distance",
    min_speed: float | None = None,
    free_period: bool = False,
    turn_limit: float | None = None,
    surrogate: bool = False,
    surrogate_batch: int = 2,
) -> OptimizationSetup:
    """Resolve and check an optimization of a library creature's gait.

    By default the search is fitted to the problem (``aquagait.optimize.Settings``):
    CMA-ES's population for the number of parameters, and no fixed number of
    generations; it stops when its best has stopped improving. The paper's
    budget is ``popsize=16`` (2D) or 31 (3D) with ``generations=100``.

    Args:
        name: a library creature (``aquagait creatures``) or the path of an MJCF file.
        generations: the most CMA-ES generations (per group, for grouped gaits);
            None: no cap. A count given turns the convergence rule off unless
            ``patience`` is given too (the paper's fixed budget, as before).
        popsize: samples per generation; None: CMA-ES's ``4 + floor(3 ln n)`` for
            the ``n`` parameters of each group (``aquagait.optimize.default_popsize``).
        seed: random seed: the same seed gives the same gait, serial or parallel.
        resolution: the fluid grid's cells per axis; default the creature's.
        cell_size: the fluid grid's cell size h [m]; default the creature's.
        fluid: 'euler', 'simple' or 'none'.
        cycles: gait cycles simulated per sample; None: ``DEFAULT_CYCLES`` (distance)
            or ``EFFICIENCY_CYCLES`` (efficiency).
        coarse: rank the samples on a grid this many times coarser
            (``aquagait.app.coarse``) and swim each generation's best
            ``refine_top`` again on the target grid; None: the target grid only.
        refine_top: samples refined per generation in a coarse-to-fine search.
        maneuver: what to learn (paper §5): ``straight``, or a turn or pitch
            (``objectives.MANEUVERS``): its offsets freed, the desired direction
            half way to the turn, a reward for rotating about its axis
            (``objectives.total``); the search starts from the straight gait.
        start: where the search starts: a ``gait.json`` or the name of a shipped gait
            (``aquagait.app.resolve.find_gait``), turned into ``maneuver``'s
            parameters; None: the shipped gait (straight) or the straight gait (a
            manoeuvre). From a good gait with a small ``step``: a local polish.
        step: the initial standard deviation of each parameter, as a fraction of
            its range (0 < step <= 1); None: a quarter (``Problem.sigma0``).
        energy_weight: the objective's energy weight [1/J] (``objectives.Weights``);
            None: the creature's (``Creature.energy_weight``, 1 unless its side-car says).
        deviation_weight: the weight of ``E_deviation`` (drift [m] plus turning [rad])
            (``objectives.Weights``); None: the paper's 0.2. Heavier, with more
            ``cycles``, charges a gait that slowly pitches or turns.
        max_evaluations: the most swims of the whole search (the start's included);
            None: no cap.
        patience: generations without a ``Settings.tolerance`` improvement of the
            best before a group stops; None: ``aquagait.optimize.default_patience``
            unless ``generations`` is given, then off.
        objective: 'distance' (the paper's) or 'efficiency': the cost of transport over
            the last ``objectives.EFFICIENCY_WINDOW`` cycles, at or above ``min_speed``
            (``objectives.efficiency_total``; straight swimming only). Its unit, the
            starting gait's cost, is measured here by swimming it once.
        min_speed: efficiency: the cruising speed [m/s] to keep; None:
            ``MIN_SPEED_SHARE`` of the starting gait's.
        free_period: search the period too, one for every DOF, within
            ``aquagait.control.gait.FREE_PERIOD`` times the creature's (straight
            swimming only). The distance objective swims each sample for the same
            time (``cycles`` of the creature's period), so a faster rhythm is paid
            for in energy; the efficiency objective swims each sample ``cycles`` of
            its own period and measures the last whole ones.
        turn_limit: a manoeuvre: the most rotation about its axis the objective rewards
            over a sample [rad]; None: the creature's (``Creature.turn_limit``: 90 degrees,
            ``objectives.TURN``, unless its side-car says; the manta's is 0.25 rad).
            Smaller, a slow turner's search buys travel past it instead of more rotation
            (a radian is worth a metre, more than a small creature's length).
        surrogate: lq-CMA-ES (``aquagait.optimize.surrogate``): a quadratic model of the
            objective ranks each generation and only the samples it cannot vouch for
            are swum.
        surrogate_batch: with ``surrogate``, the fewest samples swum at a time; at least
            the number of workers, so that none idles (it is part of the search: the
            same seed and batch give the same gait on any executor).

    Raises:
        OptimizationSetupError: with what was wrong and what would be right.
    """
    try:
        creature = find_creature(name)
    except SetupError as err:
        raise OptimizationSetupError(str(err)) from None
    key = creature_key(creature)  # what workers resolve
    name = creature.name
    for flag, value, least in [("generations", generations, 1), ("popsize", popsize, 2),
                               ("max evaluations", max_evaluations, 1)]:  # fmt: skip
        if value is not None and value < least:
            raise OptimizationSetupError(f"{flag} must be at least {least}, got {value}")
    if resolution is not None and len(resolution) != creature.dim:
        raise OptimizationSetupError(
            f"{name} is {creature.dim}D: give {creature.dim} numbers to --resolution, "
            f"got {list(resolution)}"
        )
    try:  # build the scene now, so a bad grid fails before any worker starts
        _, scene = _scene(key, _tuple(resolution), cell_size, fluid)
    except ValueError as err:
        raise OptimizationSetupError(str(err)) from None
    try:
        direction, axis = objectives.maneuver_goal(maneuver, creature.dim, creature.model.planar)
    except ValueError as err:
        raise OptimizationSetupError(str(err)) from None
    _check_free_period(creature, maneuver, free_period)
    turn_limit = _turn_limit(maneuver, turn_limit, creature.turn_limit)
    gait = creature.spec(maneuver, free_period)
    x0 = _start(creature, maneuver, start, free_period)
    if step is not None and not 0 < step <= 1:
        raise OptimizationSetupError(f"step must be in (0, 1], a share of each range; got {step}")
    weights = objectives.Weights(
        _weight(deviation_weight, objectives.Weights.deviation,
                "deviation weight", "per metre of drift and radian of turning"),
        _weight(energy_weight, creature.energy_weight, "energy weight",
                "per joule, once past the bound"),
    )  # fmt: skip
    check_objective(objective, maneuver, min_speed, cycles)
    if cycles is None:
        cycles = EFFICIENCY_CYCLES if objective == "efficiency" else DEFAULT_CYCLES
    period = float(np.max(gait.unpack(x0).period))
    seconds = cycles * period
    kind = objective
    objective = SwimObjective(
        key, _tuple(resolution), cell_size, fluid, seconds, tuple(direction.tolist()),
        weights=weights, maneuver=maneuver,
        axis=None if axis is None else tuple(axis.tolist()), objective=kind,
        free_period=free_period,
        cycles=float(cycles) if free_period and kind == "efficiency" else None,
        turn_limit=turn_limit,
    )  # fmt: skip
    efficiency_notes = ()
    if kind == "efficiency":
        objective, efficiency_notes = efficiency_unit(objective, x0, min_speed)
    refine, notes = None, ()
    if coarse is not None:
        objective, refine, notes = _coarse_to_fine(creature, objective, coarse)
    groups = gait.groups or ()
    problem = Problem(
        objective=objective,
        x0=x0,
        lower=gait.lower,
        upper=gait.upper,
        sigma0=None if step is None else step * float(np.mean(gait.upper - gait.lower)),
        feasible=JointLimits(key, maneuver, free_period),
        groups=tuple(gait.group_indices(k) for k in range(len(groups))) if len(groups) > 1 else (),
        names=gait.names,
        refine=refine,
    )
    try:
        settings = Settings(popsize=popsize, generations=generations, seed=seed,
                            refine_top=refine_top, max_evaluations=max_evaluations,
                            patience=patience, surrogate=surrogate,
                            surrogate_batch=surrogate_batch)  # fmt: skip
    except ValueError as err:
        raise OptimizationSetupError(str(err)) from None
    notes += efficiency_notes + _room_notes(scene, gait, problem)
    start = None if start is None else str(start)
    return OptimizationSetup(creature, objective, problem, settings, notes, start, step)


def _weight(value, default: float, what: str, unit: str) -> float:
    """An objective term's weight: ``default`` for None, else a number >= 0 (``unit`` says
    what it is per, for the message)."""
    if value is None:
        return float(default)
    if not (np.isfinite(value) and value >= 0):
        raise OptimizationSetupError(f"{what} must be a number >= 0 ({unit}), got {value}")
    return float(value)


def check_objective(objective: str, maneuver: str, min_speed, cycles) -> None:
    if objective not in OBJECTIVES:
        raise OptimizationSetupError(
            f"unknown objective {objective!r}; objectives: {', '.join(OBJECTIVES)}"
        )
    if objective == "efficiency" and maneuver != STRAIGHT:
        raise OptimizationSetupError(
            f"the efficiency objective is for swimming straight; a {maneuver} is learned "
            "with the distance objective (leave out --objective)"
        )
    if min_speed is not None and objective != "efficiency":
        raise OptimizationSetupError("--min-speed is for --objective efficiency")
    if min_speed is not None and not (np.isfinite(min_speed) and min_speed > 0):
        raise OptimizationSetupError(f"min speed must be a speed > 0 [m/s], got {min_speed}")
    least = objectives.EFFICIENCY_WINDOW + 1
    if objective == "efficiency" and cycles is not None and cycles < least:
        raise OptimizationSetupError(
            f"the efficiency objective measures the last {objectives.EFFICIENCY_WINDOW} "
            f"cycles of a swim from rest: give at least {least} cycles, got {cycles:g}"
        )


def _turn_limit(maneuver: str, limit, own: float) -> float:
    """The rotation a manoeuvre is rewarded for, at most [rad]: ``limit`` checked, or the
    creature's ``own``."""
    if limit is None:
        return own
    if maneuver == STRAIGHT:
        raise OptimizationSetupError(
            "--turn-limit is for a manoeuvre (--maneuver turn-left, pitch-up, ...): "
            "swimming straight rewards no rotation"
        )
    if not (np.isfinite(limit) and limit > 0):
        raise OptimizationSetupError(
            f"turn limit must be an angle > 0 [rad] (the creature's is {own:.4g}), got {limit}"
        )
    return float(limit)


def _check_free_period(creature: Creature, maneuver: str, free_period: bool) -> None:
    if not free_period:
        return
    if maneuver != STRAIGHT:
        raise OptimizationSetupError(
            f"--free-period is for swimming straight: a {maneuver} keeps the straight gait's "
            "period, as the path follower switches between them at whole cycles"
        )
    if creature.gait.free_period:
        raise OptimizationSetupError(
            f"{creature.name}'s gait has its period free already (its side-car's gait.free: "
            f"{', '.join(creature.gait.free)}); leave out --free-period"
        )


def efficiency_unit(objective: SwimObjective, x0, min_speed) -> tuple[SwimObjective, tuple]:
    """The efficiency objective with its unit (the start's cost of transport) and its
    speed (given, or ``MIN_SPEED_SHARE`` of the start's), and notes saying which."""
    speed, cost, distances = objective.cruise(x0)
    if not (np.isfinite(cost) and cost > 0):
        raise OptimizationSetupError(
            f"the starting gait swims {speed:.3g} m/s over its last "
            f"{objectives.EFFICIENCY_WINDOW} cycles: it does not swim forward, so it has no "
            "cost of transport to measure economy by; start from a gait that swims (--start)"
        )
    note = (f"efficiency: the starting gait cruises at {speed:.3g} m/s for "
            f"{cost:.3g} J/(kg m), the cost term's unit")  # fmt: skip
    if min_speed is None:
        min_speed = MIN_SPEED_SHARE * speed
        note += f"; the minimum speed is {MIN_SPEED_SHARE:.0%} of its speed, {min_speed:.3g} m/s"
    notes = (note,)
    if settled_cycle(distances) is None:
        notes += (
            f"the starting gait, swum as a sample, is {unsettled(distances)}: the search "
            "would rank gaits by figures from before their cruise; give more --cycles",
        )
    return replace(objective, min_speed=float(min_speed), reference_cost=float(cost)), notes


def search_notes(setup: OptimizationSetup, run: SwimRun, out) -> tuple[str, ...]:
    """What the best gait's swim (``best_swim``, as long as a sample) says about the
    search: an efficiency search whose best gait has not settled at cruise within the
    sample's cycles ranked its gaits before their cruise (its start may have settled
    in time, and ``prepare_optimization``'s note then said nothing)."""
    if setup.objective.objective != "efficiency" or run.metrics.get("settled"):
        return ()
    cycles = len(run.metrics["cycle_distances"])
    return (
        f"an efficiency search: the best gait has not settled within a sample's {cycles} "
        "cycles (above), so the search ranked its gaits by figures from before their cruise; "
        f"search again with more --cycles, from it (--start {Path(out) / 'gait.json'} "
        "--step 0.1)",
    )


ROOM_DRAWS = 64
"""Gaits drawn around the start to judge whether the grid holds the search's samples."""

ROOM_SHARE = 0.75
"""Below this share of those draws fitting the grid, ``prepare_optimization`` says so."""


def _room_notes(scene: Scene, gait, problem: Problem) -> tuple[str, ...]:
    """A note when many gaits drawn around the start, as CMA-ES's first generation spreads
    them, would not fit the grid: each such sample costs a swim and scores the penalty.

    The draws are the start plus each coordinate's initial spread (``sigma0``
    scaled by its range, as ``optimize`` gives pycma) times a normal number,
    clipped to the bounds, from a fixed generator (a diagnostic, not a
    search); each is judged by its widest box over a cycle (``widest_box``),
    centred, against the grid less the clearance on either side.
    """
    if scene.grid is None or not hasattr(scene.fluid, "clearance"):
        return ()
    grid, clearance = scene.grid, scene.fluid.clearance
    width = problem.upper - problem.lower
    spread = problem.sigma0 * width / width.mean()
    draws = np.random.default_rng(0).standard_normal((ROOM_DRAWS, len(problem.x0)))
    needed = []
    for z in draws:
        x = np.clip(problem.x0 + spread * z, problem.lower, problem.upper)
        needed.append(cells_for(widest_box(scene, gait.unpack(x)), grid.cell_size, clearance))
    needed = np.array(needed)
    fits = np.all(needed <= np.asarray(grid.shape), axis=1)
    if fits.mean() >= ROOM_SHARE:
        return ()
    wider = np.maximum(np.ceil(np.percentile(needed, 90, axis=0)).astype(int), grid.shape)
    return (
        f"{np.count_nonzero(~fits)} of {ROOM_DRAWS} gaits drawn around the start would not fit "
        f"the {'x'.join(map(str, grid.shape))} grid of {grid.cell_size:g} m cells with "
        f"{clearance:g} cells of water on every side (their widest poses over a cycle): such "
        f"a sample costs a whole swim and scores the penalty, and the search learns the grid's "
        f"size, not the swimming. --resolution {' '.join(map(str, wider))} would hold about 90% "
        "of them (or larger cells: --cell-size)",
    )


def _start(creature: Creature, maneuver: str, start, free_period: bool = False) -> np.ndarray:
    """``prepare_optimization``'s start, in ``maneuver``'s parameters (with the period,
    if ``free_period``): an admissible gait (inside their bounds and the joint limits)."""
    if start is None:
        return maneuver_start(creature, maneuver, free_period=free_period)
    try:
        params, _, kind, own_period = find_gait(creature, start)
    except SetupError as err:
        raise OptimizationSetupError(str(err)) from None
    if own_period and not free_period:
        raise OptimizationSetupError(
            f"the start {start} sets its own period: search with --free-period, or the "
            f"search would start at {creature.name}'s period instead"
        )
    gait = creature.spec(kind, own_period).unpack(params)
    x0 = maneuver_start(creature, maneuver, gait, free_period)
    spec = creature.spec(maneuver, free_period)
    problems = gait_problems(spec, x0, *creature.gait_limits(maneuver))
    if problems:
        raise OptimizationSetupError(f"{creature.name}'s start {start} " + "; ".join(problems))
    return x0


def run_optimization(
    setup: OptimizationSetup, run_dir=None, executor=None, resume: bool = False, progress=None
) -> Result:
    """Run CMA-ES on the setup (see ``aquagait.optimize.optimize``)."""
    return optimize(
        setup.problem, setup.settings, executor=executor, run_dir=run_dir, resume=resume,
        progress=progress,
    )  # fmt: skip


def _coarse_to_fine(creature: Creature, objective: SwimObjective, factor: float):
    """The swim on a grid ``factor`` times coarser that ranks the samples, the swim on the
    target grid that refines the best, and notes on the coarse grid."""
    resolution = objective.resolution or creature.resolution
    cell_size = objective.cell_size or creature.cell_size
    try:
        grid = coarse_grid(creature, resolution, cell_size, factor)
    except ValueError as err:
        raise OptimizationSetupError(f"the coarse grid: {err}") from None
    refine = replace(objective, resolution=tuple(resolution), cell_size=cell_size)
    coarse = replace(objective, resolution=grid.resolution, cell_size=grid.cell_size,
                     clearance=grid.clearance)  # fmt: skip
    return coarse, refine, grid.notes


def write_optimization(setup: OptimizationSetup, result: Result, out, plot: bool = True) -> Path:
    """Write the best gait (``gait.json``) and, if ``plot``, ``convergence.png`` into ``out``.

    ``optimization.csv`` and the checkpoint are written by the optimizer
    after every generation; the plot needs the ``viz`` extra.
    """
    from aquagait.optimize import LOG

    out = Path(out)
    objective = setup.objective
    write_gait(out / "gait.json", setup.creature, result.best_x, objective.maneuver,
               objective.free_period)  # fmt: skip
    if plot:
        from aquagait.viz import plot_convergence

        plot_convergence(out / LOG, out / "convergence.png", title=setup.creature.name)
    return out


def best_swim(
    setup: OptimizationSetup, out, default_grid: bool = False, seconds: float | None = None
) -> SwimSetup:
    """The swim of the gait in ``out/gait.json``, on the optimization's (target) grid and fluid.

    Args:
        setup: the optimization.
        out: its run directory (holding ``gait.json``).
        default_grid: swim on the creature's default grid instead (the demo
            searches on a coarse grid, then swims on the fine one).
        seconds: simulated time [s]; default the optimization's per sample (a sample's
            cycles of the best gait's own period, if each sample swims its own).
    """
    objective = setup.target  # a coarse-to-fine search is for its target grid
    resolution, cell_size = (
        (None, None) if default_grid else (objective.resolution, objective.cell_size)
    )
    swim = prepare_swim(
        objective.creature, gait=Path(out) / "gait.json", seconds=seconds or objective.seconds,
        fluid=objective.fluid, resolution=resolution, cell_size=cell_size,
    )  # fmt: skip
    if seconds is None and objective.cycles is not None:  # a sample swims its own cycles
        swim = replace(swim, seconds=objective.cycles * swim.period)
    return swim


def _tuple(resolution):
    return None if resolution is None else tuple(int(n) for n in resolution)
