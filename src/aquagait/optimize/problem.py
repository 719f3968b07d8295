"""What the optimizer is asked (Problem, Settings) and what it answers (Result, reports).

The optimizer knows nothing of physics (docs/development.md): a problem is a
function `objective(x) -> float` of a parameter vector `x` of shape (n,)
inside a box, to be minimized, plus an optional feasibility test (joint
limits, paper §4).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

# Paper §4: population 16 for 2D creatures, 31 for 3D ones, up to 100 generations.
PAPER_POPSIZE = {2: 16, 3: 31}
PAPER_GENERATIONS = 100


def _vector(name: str, value, n: int | None = None) -> np.ndarray:
    if np.ndim(value) != 1:
        raise ValueError(f"Problem.{name} must be a 1-D vector, got shape {np.shape(value)}")
    array = np.array(value, dtype=float)
    if n is not None and array.shape != (n,):
        raise ValueError(f"Problem.{name} has {array.size} entries; x0 has {n}")
    if not np.all(np.isfinite(array)):
        raise ValueError(f"Problem.{name} must be finite, got {array}")
    array.setflags(write=False)
    return array


def _group(index: int, group, n: int) -> np.ndarray:
    members = np.array(group).reshape(-1)
    if members.size == 0 or not np.issubdtype(members.dtype, np.integer):
        raise ValueError(f"Problem.groups[{index}] must be a non-empty set of integer indices")
    if members.min() < 0 or members.max() >= n:
        raise ValueError(f"Problem.groups[{index}] = {members.tolist()} leaves 0..{n - 1}")
    if np.unique(members).size != members.size:
        raise ValueError(f"Problem.groups[{index}] = {members.tolist()} repeats an index")
    members = members.astype(np.intp)
    members.setflags(write=False)
    return members


@dataclass(frozen=True, eq=False)
class Problem:
    """A box-bounded minimization of a black-box objective (paper §4).

    Args:
        objective: `f(x) -> float` with `x` of shape (n,), minimized. It must be
            picklable to run in other processes (a module-level function or an
            instance of a module-level class) and deterministic for the same `x`.
            A call that raises, or returns nan or inf, is a failure: the sample
            gets `Settings.penalty` and the run goes on.
        x0: (n,) start of the search (the CMA-ES mean); inside the bounds.
        lower: (n,) lower box bounds, finite.
        upper: (n,) upper box bounds, finite, `lower < upper`. Every sample
            handed to `objective` lies inside the box: pycma's `BoundTransform`
            maps the Gaussian samples into the box (a smooth, piecewise
            quadratic fold near each bound), so no evaluation is wasted outside.
        sigma0: initial step size, in units of `x` for a coordinate whose bound
            width is the mean width. Each coordinate's initial standard deviation
            is `sigma0 * width_i / mean(width)`, so coordinates of different
            scales (an amplitude in [0, 1] rad, a phase in [0, 2 pi]) start
            with the same share of their range. None: `0.25 * mean(width)`,
            a quarter of each coordinate's range.
        feasible: `feasible(x) -> bool`, checked in this process BEFORE any
            evaluation (e.g. joint limits). An infeasible sample is redrawn up
            to `Settings.max_resamples` times; one still infeasible gets
            `Settings.penalty` without being evaluated.
        groups: index sets optimized in turn (paper §4, frog: hind legs, then
            fore legs). Each group runs its own CMA-ES over its coordinates for
            up to `Settings.generations` generations, the other coordinates
            frozen at the best point found so far; the next group starts from
            that best point. Empty: all coordinates at once.
        names: (n,) parameter names for the log; empty gives x0, x1, ...
        refine: coarse-to-fine search. `refine(x) -> float` is the objective
            the search is for (e.g. the swim on the target grid) and
            `objective` a cheaper model of it that only ranks the samples
            (the swim on a coarser grid, docs/optimize.md). CMA-ES learns from
            `objective`; the best `Settings.refine_top` samples of every
            generation are also evaluated with `refine`, and the answer is the
            best point by `refine`. None: `objective` is the objective.
    """

    objective: Callable[[np.ndarray], float]
    x0: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    sigma0: float | None = None
    feasible: Callable[[np.ndarray], bool] | None = None
    groups: tuple[np.ndarray, ...] = ()
    names: tuple[str, ...] = ()
    refine: Callable[[np.ndarray], float] | None = None

    def __post_init__(self):
        if not callable(self.objective):
            raise TypeError(f"Problem.objective must be callable, got {self.objective!r}")
        if self.refine is not None and not callable(self.refine):
            raise TypeError(f"Problem.refine must be callable or None, got {self.refine!r}")
        if self.feasible is not None and not callable(self.feasible):
            raise TypeError(f"Problem.feasible must be callable or None, got {self.feasible!r}")
        x0 = _vector("x0", self.x0)
        n = x0.size
        if n == 0:
            raise ValueError("Problem.x0 is empty: there is nothing to optimize")
        lower, upper = _vector("lower", self.lower, n), _vector("upper", self.upper, n)
        if np.any(lower >= upper):
            bad = np.flatnonzero(lower >= upper).tolist()
            raise ValueError(f"Problem bounds need lower < upper; coordinates {bad} break it")
        if np.any((x0 < lower) | (x0 > upper)):
            bad = np.flatnonzero((x0 < lower) | (x0 > upper)).tolist()
            raise ValueError(f"Problem.x0 lies outside the bounds at coordinates {bad}")
        width = upper - lower
        sigma0 = 0.25 * float(width.mean()) if self.sigma0 is None else float(self.sigma0)
        if not (np.isfinite(sigma0) and sigma0 > 0):
            raise ValueError(f"Problem.sigma0 must be a positive number, got {self.sigma0!r}")
        groups = tuple(_group(i, g, n) for i, g in enumerate(self.groups))
        names = tuple(str(name) for name in self.names) or tuple(f"x{i}" for i in range(n))
        if len(names) != n:
            raise ValueError(f"Problem.names has {len(names)} names for {n} parameters")
        for name, value in [("x0", x0), ("lower", lower), ("upper", upper), ("sigma0", sigma0)]:
            object.__setattr__(self, name, value)
        object.__setattr__(self, "groups", groups)
        object.__setattr__(self, "names", names)

    @property
    def size(self) -> int:
        """n, the number of parameters."""
        return self.x0.size

    def phases(self) -> tuple[np.ndarray, ...]:
        """The index sets optimized in turn: `groups`, or all indices at once."""
        return self.groups or (np.arange(self.size),)


def default_popsize(n: int) -> int:
    """CMA-ES's recommended population for ``n`` parameters, ``4 + floor(3 ln n)`` (Hansen's
    default, pycma's ``popsize``): 10 for eel2d's 8, 9 for the fish's 6, 13 for the manta's 21."""
    return 4 + int(3 * math.log(n))


def default_patience(n: int, popsize: int) -> int:
    """Generations the best may stall before a search stops, ``10 + ceil(30 n / popsize)``: the
    horizon of pycma's ``tolfunhist``, about the generations CMA-ES needs to adapt its step size
    and covariance to ``n`` parameters from ``popsize`` samples each."""
    return 10 + math.ceil(30 * n / popsize)


@dataclass(frozen=True)
class Settings:
    """How the CMA-ES search runs, and when it stops.

    By default the search is fitted to the problem: CMA-ES's own population for
    each group's number of parameters (``default_popsize``) and no fixed number
    of generations; a group stops when it has converged (``patience``), and the
    whole search at ``max_evaluations`` if given. The paper's budget (§4: 16 in
    2D, 31 in 3D, 100 generations) is ``Settings.paper(dim)``.

    Args:
        popsize: samples per generation; None: ``default_popsize`` of each group's size.
        generations: the most generations per group (all at once: per run); None: no cap.
        seed: seeds the only random generator the search draws from.
        max_evaluations: the most evaluations of the objective in the whole run,
            the start's included (refinements by ``Problem.refine`` are counted
            apart); None: no cap. The last generation is cut short to meet it
            exactly: its samples are evaluated in order up to the cap, count
            towards the best, and are not told to CMA-ES (the run ends there).
        patience: a group has converged, and stops, when its best objective
            improved by no more than ``tolerance`` times its size over the last
            ``patience`` generations (a rule on the best value, which CMA-ES's
            own criteria, tuned for exact convergence, do not give). None:
            ``default_patience`` of the group's size and population when
            ``generations`` is None; off when a generation count is given (a
            fixed budget, as the paper's: only ``generations`` and pycma's
            criteria stop it). Give both for a capped search that may stop early.
        tolerance: the relative improvement of the best that still counts as
            progress over ``patience`` generations (0.01: 1 % of the distance a
            gait swims is below the swim's own time-step and grid error).
        max_resamples: redraws of an infeasible sample before it gets `penalty`.
        penalty: the value given to a failed sample (objective raised, returned
            nan/inf, or its worker died `retries + 1` times) and to an infeasible
            one after `max_resamples` redraws. Finite, and worse than any real
            value of the objective, so CMA-ES ranks such samples last.
        retries: re-submissions of a sample whose worker died (a process pool
            broke, Dask's KilledWorker, a lost connection) before it gets
            `penalty`. An objective that raises is not retried: the simulation
            is deterministic and would raise again.
        tolfun: pycma's stopping tolerance on the spread of recent objective values.
        tolx: pycma's stopping tolerance on the step size in x.
        refine_top: with `Problem.refine`, how many of every generation's best
            samples (by `objective`) are evaluated with `refine`.
        surrogate: lq-CMA-ES (``optimize.surrogate``): a quadratic model of the objective
            over the samples evaluated so far ranks each generation, and only the samples
            whose ranks it cannot vouch for are evaluated. ``max_evaluations``, the
            history's ``evaluations`` and the patience rule count real evaluations and
            generations as without it.
        surrogate_batch: with ``surrogate``, the fewest samples evaluated at a time: the
            number of workers that should stay busy. Part of the search (it decides which
            samples are evaluated), so the same seed and batch give the same result on any
            executor.
    """

    popsize: int | None = None
    generations: int | None = None
    seed: int = 0
    max_evaluations: int | None = None
    patience: int | None = None
    tolerance: float = 0.01
    max_resamples: int = 20
    penalty: float = 1e6
    retries: int = 1
    tolfun: float = 1e-11
    tolx: float = 1e-11
    refine_top: int = 2
    surrogate: bool = False
    surrogate_batch: int = 2

    def __post_init__(self):
        checks = [
            ("popsize", self.popsize, 2),
            ("refine_top", self.refine_top, 1),
            ("generations", self.generations, 1),
            ("seed", self.seed, 0),
            ("max_evaluations", self.max_evaluations, 1),
            ("patience", self.patience, 1),
            ("max_resamples", self.max_resamples, 0),
            ("retries", self.retries, 0),
            ("surrogate_batch", self.surrogate_batch, 1),
        ]
        for name, value, least in checks:
            if value is None and name in OPTIONAL:
                continue
            if not isinstance(value, int | np.integer) or value < least:
                none = " or None" if name in OPTIONAL else ""
                raise ValueError(
                    f"Settings.{name} must be an integer >= {least}{none}, got {value!r}"
                )
        if not isinstance(self.surrogate, bool | np.bool_):
            raise ValueError(f"Settings.surrogate must be True or False, got {self.surrogate!r}")
        if not np.isfinite(self.penalty):
            raise ValueError(f"Settings.penalty must be finite, got {self.penalty!r}")
        for name in ("tolfun", "tolx", "tolerance"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"Settings.{name} must be >= 0, got {getattr(self, name)!r}")

    @classmethod
    def paper(cls, dim: int, **overrides) -> Settings:
        """The paper's fixed budget (§4): population 16 in 2D or 31 in 3D, 100 generations,
        no convergence rule (pycma's own criteria still apply)."""
        if dim not in PAPER_POPSIZE:
            raise ValueError(f"dim must be 2 or 3, got {dim!r}")
        budget = {"popsize": PAPER_POPSIZE[dim], "generations": PAPER_GENERATIONS}
        return cls(**{**budget, **overrides})

    for_dim = paper  # its name before the fitted budget (issue 29)

    def for_group(self, n: int) -> tuple[int, int | None]:
        """``(popsize, patience)`` of a group of ``n`` parameters (None: no patience rule)."""
        popsize = default_popsize(n) if self.popsize is None else int(self.popsize)
        patience = self.patience
        if patience is None and self.generations is None:
            patience = default_patience(n, popsize)
        return popsize, patience

    def as_dict(self) -> dict:
        """The settings as plain Python values (for config files and checkpoints)."""
        return {
            k: v.item() if hasattr(v, "item") else v for k, v in dataclasses.asdict(self).items()
        }


OPTIONAL = {"popsize", "generations", "max_evaluations", "patience"}
"""Settings that may be None (the default: fitted to the problem, or no cap)."""


LOSS_WARNING = 1 / 8
"""A generation whose failed and lost samples are more than this share of its
population is worth a warning (`GenerationReport.lossy`)."""


@dataclass(frozen=True)
class GenerationReport:
    """Progress after one generation, handed to `optimize(progress=...)`.

    Attributes:
        generation: generations done so far, over all groups (1-based).
        planned: the most generations the run can take (`generations * groups`);
            None when no generation count is set (the search stops by itself).
        group: index of the group being optimized (0 without groups).
        best: best objective value so far (inf while no sample succeeded).
        mean: mean of this generation's successful values (nan if none).
        sigma: CMA-ES step size after this generation.
        evaluations: samples evaluated so far (infeasible ones are not).
        failures: samples of this generation evaluated without a value, `failed + lost`.
        elapsed: seconds spent so far, over every session of a resumed run.
        remaining: estimated seconds left if the run takes all `planned` generations,
            or all `max_evaluations`; nan when neither bounds it.
        samples: the generation's population.
        failed: samples whose objective raised or returned nan/inf (penalty).
        lost: samples whose worker died `retries + 1` times (penalty).
        infeasible: samples still infeasible after the redraws (penalty, not evaluated).
        reasons: why each failed or lost sample got its penalty, in sample order,
            e.g. "sample 3 failed: FloatingPointError: simulation diverged".
    """

    generation: int
    planned: int | None
    group: int
    best: float
    mean: float
    sigma: float
    evaluations: int
    failures: int
    elapsed: float
    remaining: float
    samples: int = 0
    failed: int = 0
    lost: int = 0
    infeasible: int = 0
    reasons: tuple[str, ...] = ()

    @property
    def lossy(self) -> bool:
        """More than `LOSS_WARNING` of the population failed or was lost."""
        return self.failed + self.lost > LOSS_WARNING * self.samples


@dataclass(frozen=True, eq=False)
class Result:
    """The outcome of `optimize`.

    Attributes:
        best_x: (n,) the best parameters evaluated (x0 if no sample succeeded).
        best_f: its objective value (inf if no sample succeeded); with
            `Problem.refine`, its `refine` value, and best_x the best by it.
        history: one dict per generation with keys generation, group,
            evaluations, best, mean, generation_best, sigma, failures (failed
            + lost), failed, lost, infeasible, resamples, samples (the
            population drawn), elapsed, best_x (a list), refinements
            (evaluations of `refine` so far) and penalized: one dict per
            sample that got the penalty, with its index ("sample"), "status"
            ("failed", "lost" or "infeasible"), "reason" and "x" (a list). Every entry but `elapsed`
            is a deterministic function of the problem and settings, unless a
            worker died (lost samples, and the messages of lost tasks).
        evaluations: samples evaluated (each counted once, retries included).
        stopped: why the search ended, per group ("generations (100)",
            "converged: best improved 0.3 % in 24 generations", "max_evaluations
            (200)", "tolfun=1e-11", ...).
        refinements: evaluations of `Problem.refine` (0 without it).
        start_f: the start x0's value (by `refine`, if any), evaluated before
            the first generation; None if it was not (infeasible, failed, or a
            run resumed from before starts were scored). best_f <= start_f.
    """

    best_x: np.ndarray
    best_f: float
    history: list[dict] = field(repr=False)
    evaluations: int
    stopped: str
    refinements: int = 0
    start_f: float | None = None

    @property
    def generations(self) -> int:
        """Generations run, over all groups."""
        return len(self.history)
