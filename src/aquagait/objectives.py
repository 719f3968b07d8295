"""The swimming objective: a trajectory in, one number out (paper §4, docs/method-search.md).

Over a run of (by default) two gait cycles, minimized:

    E = E_distance + w_dev E_deviation + w_energy(E) E_energy + w_col E_collision

- ``E_distance = -d . dp``: the root's displacement ``dp`` along the desired
  direction ``d`` (a unit vector), negated [m].
- ``E_deviation = |dp - (d . dp) d| + |dtheta|``: sideways drift [m] plus the
  root's change of orientation as an exponential map (its angle) [rad], from
  the start to its mean orientation over the last gait cycle, so that the
  body's recoil within a cycle does not count (``rotation_vector``).
- ``E_energy``: actuator work, the integral of ``sum_i |tau_i qd_i| dt`` [J];
  its weight is 0 while the work stays below the creature's energy bound and
  ``w_energy`` (1) above it, so that within the bound only speed counts.
  The step adds ``|tau_i qd_i| dt`` to the trajectory's cumulative ``energy``
  at every simulation step, with the velocity that moves the positions, so
  the work is the cumulative energy's change from the first frame to the
  last: exact for the integrator, with no quadrature over frames.
- ``E_collision``: the volume where non-adjacent links overlap, integrated
  over time [m^3 s], from a lattice of about 100 points along the body. The
  volume is a snapshot per sampled frame, so it is integrated by the
  trapezoid rule over the sampled frames' times (the last frame included).

A manoeuvre (paper §5, docs/follow.md: ``MANEUVERS``) adds ``E_turn =
-min(r . dtheta, TURN)``, the root's rotation vector ``dtheta`` along the
desired axis ``r`` negated [rad], with the desired direction ``d`` half way
to the turn, and its ``E_deviation`` counts only the unwanted rotation,
``|dtheta - (r . dtheta) r|``. The reward stops at ``TURN`` (90 degrees over
the run, twice the angle to ``d``): uncapped, rotation in radians outweighs
distance in metres and the search finds gaits that spin on the spot (the
eel learned to turn 4.1 rad in two cycles and went backwards), which no
path can be followed with.

Each term is a function of a ``Trajectory``; weights and direction are
``Weights`` and an argument. The units mix, as in the paper: the weights
(0.2 and 100) were chosen for them.

The efficiency objective (``efficiency_total``, ``aquagait optimize
--objective efficiency``) asks for economy instead of distance: over a run
long enough to reach cruise, minimized

    E = C / C_ref + w_speed max(0, 1 - U / U_min) + w_dev E_deviation + w_col E_collision

with ``U`` [m/s] the root's speed along ``d`` and ``C`` [J/(kg m)] the cost
of transport (work over mass times distance) over the run's last
``EFFICIENCY_WINDOW`` whole gait cycles (``cruise``), ``C_ref`` the
starting gait's (so the first term starts near 1 and needs no unit),
``U_min`` the speed it must cruise at or above, and ``w_speed =
SPEED_WEIGHT``: a gait 10 % too slow pays as much as the whole reference
cost. The energy bound does not apply: economy is the objective itself.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aquagait.body.model import Model
from aquagait.body.overlap import overlap_volume
from aquagait.body.rotations import quat_conj, quat_log, quat_mul
from aquagait.body.voxelize import BodyShape
from aquagait.sim import Scene, Trajectory

COLLISION_POINTS = 100
"""Lattice points along the body's length for ``E_collision`` (about 100^3 over the creature)."""

EFFICIENCY_WINDOW = 2
"""Whole gait cycles at the end of a run over which the efficiency objective measures."""

OBJECTIVES = ("distance", "efficiency")
"""What a search minimizes: the paper's objective (``objectives.total``, the default), or
the cost of transport at cruise above a speed (``objectives.efficiency_total``)."""

EFFICIENCY_CYCLES = 6.0
"""Gait cycles simulated per sample of the efficiency objective: eel2d and the other 2D
creatures settle at cruise by their fourth (docs/library.md), and the last
``EFFICIENCY_WINDOW`` cycles are measured. A 3D creature that settles later
needs ``cycles`` to match (the fish's straight gait: 13, settled from its 11th);
``prepare_optimization`` notes a start that has not settled."""

MIN_SPEED_SHARE = 0.75
"""Without ``min_speed``, the efficiency objective asks for this share of the starting
gait's speed over the same cycles."""

SPEED_WEIGHT = 10.0
"""The efficiency objective's weight of the speed shortfall (module docstring)."""

COST_CAP = 10.0
"""The efficiency objective's cost term is at most this (in units of the reference cost):
a gait that hardly moves forward is ranked by its speed shortfall, not by a cost that
diverges as its distance vanishes."""

COLLISION_FRAME_STRIDE = 2
"""Overlap is measured every this many frames (15 a second) and at the last one, and integrated."""


@dataclass(frozen=True)
class Weights:
    """Weights of the objective's terms (paper §4 defaults).

    Attributes:
        deviation: of ``E_deviation``.
        energy: of ``E_energy`` when the work exceeds the energy bound.
        collision: of ``E_collision``.
    """

    deviation: float = 0.2
    energy: float = 1.0
    collision: float = 100.0


def root_displacement(model: Model, traj: Trajectory) -> np.ndarray:
    """The root link's displacement from the first to the last frame, (dim,) [m]."""
    held = 2 if model.planar else model.dim  # a planar root's qpos: x, y, then its heading
    position = np.zeros((len(traj.qpos), model.dim))
    position[:, :held] = traj.qpos[:, :held]
    return position[-1] - position[0]


STRAIGHT = "straight"
"""Swimming straight ahead: the manoeuvre every creature has, its default gait."""

MANEUVERS = {
    STRAIGHT: ((1.0, 0.0, 0.0), None),
    "turn-left": ((1.0, 1.0, 0.0), (0.0, 0.0, 1.0)),
    "turn-right": ((1.0, -1.0, 0.0), (0.0, 0.0, -1.0)),
    "pitch-up": ((1.0, 0.0, 1.0), (0.0, -1.0, 0.0)),
    "pitch-down": ((1.0, 0.0, -1.0), (0.0, 1.0, 0.0)),
}
"""Per manoeuvre, the desired direction ``d`` (half way from facing +x to the turn's
direction) and axis of rotation ``r`` (None: no turn wanted), for a creature that faces +x
with z up. Pitching up turns the nose (+x) towards +z: a rotation about -y."""


TURN = np.pi / 2
"""The rotation a manoeuvre is rewarded for over its run, at most [rad]: twice the angle
between facing +x and its desired direction ``d``."""


def maneuver_goal(
    name: str, dim: int, planar: bool | None = None
) -> tuple[np.ndarray, np.ndarray | None]:
    """``(d, r)`` of the manoeuvre ``name`` in ``dim`` dimensions (``MANEUVERS``).

    ``planar``: the creature's root moves in the x-y plane (default: in 2D only).

    Raises:
        ValueError: an unknown manoeuvre, or a pitch asked of a planar creature.
    """
    if name not in MANEUVERS:
        raise ValueError(f"unknown manoeuvre {name!r}; manoeuvres: {', '.join(MANEUVERS)}")
    if (dim == 2 if planar is None else planar) and name.startswith("pitch"):
        what = "a 2D creature" if dim == 2 else "a creature held to its plane"
        raise ValueError(f"{what} turns in its plane; {name!r} is for 3D creatures (a free root)")
    direction, axis = MANEUVERS[name]
    d = _unit(direction[:dim], dim)
    return d, None if axis is None else np.asarray(axis, dtype=float)


def rotation_vector(model: Model, traj: Trajectory, period: float | None = None) -> np.ndarray:
    """The root's change of orientation over the run as a world rotation vector (3,) [rad].

    From the first frame to the last; with ``period`` [s], to the root's mean
    orientation over the last ``period`` seconds instead: free of the body's
    recoil within a gait cycle. (The fish's head yaws +-0.15-0.3 rad every tail
    beat: measured at the last frame, its change swings from -0.08 to +0.29 rad
    with the moment of the beat at which the run ends, which a search then
    tunes through the gait's common phase instead of swimming straighter.)

    A planar root (2D, or 3D held to its plane): ``(0, 0, dtheta)``, its hinge
    angle's change; a free root: the
    exponential map of ``q_end q_start^-1``, ``q_end`` the chordal mean of the
    last cycle's orientations.
    """
    if period is None:
        last = np.array([len(traj.time) - 1])
    else:
        last = cycle_frames(traj, traj.time[-1], period)
    return rotation_between(model, traj, np.array([0]), last)


def cycle_frames(traj: Trajectory, end: float, period: float) -> np.ndarray:
    """The indices of the frames in the cycle of ``period`` [s] that ends at ``end`` [s]: one
    cycle's frames, each phase of the beat once."""
    return np.flatnonzero((traj.time > end - period + 1e-9 * period)
                          & (traj.time <= end + 1e-9 * period))  # fmt: skip


def rotation_between(model: Model, traj: Trajectory, first, last) -> np.ndarray:
    """The root's change of orientation from its mean over the frames ``first`` to its mean
    over the frames ``last`` (index arrays), as a world rotation vector (3,) [rad]
    (``rotation_vector``: planar roots by their hinge angle, free ones by the chordal
    mean of their quaternions)."""
    if model.planar:
        return np.array([0.0, 0.0, traj.qpos[last, 2].mean() - traj.qpos[first, 2].mean()])
    start, end = (_mean_quat(traj.qpos[frames, 3:7]) for frames in (first, last))
    return quat_log(quat_mul(end, quat_conj(start)))


def _mean_quat(quats: np.ndarray) -> np.ndarray:
    """The chordal mean of unit quaternions (k, 4), on the last one's hemisphere."""
    quats = quats * np.where(quats @ quats[-1] < 0, -1.0, 1.0)[:, None]
    mean = quats.mean(axis=0)
    return mean / np.linalg.norm(mean)


def root_rotation(model: Model, traj: Trajectory) -> float:
    """The angle of the root's change of orientation over the run [rad] (``rotation_vector``)."""
    return float(np.linalg.norm(rotation_vector(model, traj)))


def turning(
    model: Model, traj: Trajectory, axis, limit: float = TURN, period: float | None = None
) -> float:
    """``E_turn = -min(r . dtheta, limit)`` [rad]: more negative is more rotation about the
    axis ``r``, up to ``limit`` (``dtheta``: ``rotation_vector`` with ``period``)."""
    rotation = rotation_vector(model, traj, period)
    return -min(float(np.asarray(axis, dtype=float) @ rotation), limit)


def distance(model: Model, traj: Trajectory, direction) -> float:
    """``E_distance = -d . dp`` [m]: more negative is farther along ``direction``."""
    return -float(_unit(direction, model.dim) @ root_displacement(model, traj))


def deviation(
    model: Model, traj: Trajectory, direction, axis=None, period: float | None = None
) -> float:
    """``E_deviation = |dp - (d . dp) d| + |dtheta|``: drift [m] plus turning [rad]
    (``dtheta``: ``rotation_vector`` with ``period``).

    With a manoeuvre's ``axis`` ``r``, only the unwanted rotation counts:
    ``|dtheta - (r . dtheta) r|``.
    """
    d = _unit(direction, model.dim)
    dp = root_displacement(model, traj)
    rotation = rotation_vector(model, traj, period)
    if axis is not None:
        r = np.asarray(axis, dtype=float)
        rotation = rotation - (r @ rotation) * r
    return float(np.linalg.norm(dp - (d @ dp) * d) + np.linalg.norm(rotation))


def work(traj: Trajectory) -> float:
    """Actuator work over the run, ``sum_i |tau_i qd_i| dt`` [J].

    The difference of the cumulative energy between the last and first
    frames: the step sums the work per simulation step (module docstring).
    """
    return float(traj.energy[-1].sum() - traj.energy[0].sum())


def energy(traj: Trajectory, bound: float, weight: float = 1.0) -> float:
    """``w2 E_energy``: the work [J] times 0 below ``bound`` [J] and ``weight`` above it."""
    spent = work(traj)
    return weight * spent if spent > bound else 0.0


def collision(scene: Scene, traj: Trajectory, stride: int = COLLISION_FRAME_STRIDE) -> float:
    """``E_collision``: overlap of non-adjacent links integrated over time [m^3 s].

    The overlap volume [m^3] is measured every ``stride`` frames and at the
    last frame, and integrated by the trapezoid rule over those frames' times
    [s]: a constant overlap V over a run of T seconds gives V T.
    """
    shape = scene.shape if scene.shape is not None else _shape(scene)
    spacing = scene.model.body_length / COLLISION_POINTS
    frames = sampled_frames(len(traj.time), stride)
    volumes = [
        overlap_volume(shape, *scene.dynamics.link_poses(traj.qpos[f]), spacing) for f in frames
    ]
    return float(np.trapezoid(volumes, traj.time[frames]))


def sampled_frames(count: int, stride: int) -> np.ndarray:
    """Indices of every ``stride``-th of ``count`` frames, the last frame always included."""
    if stride < 1:
        raise ValueError(f"stride must be a whole number of frames >= 1, got {stride!r}")
    return np.unique(np.r_[np.arange(0, count, stride), count - 1])


def total(
    scene: Scene,
    traj: Trajectory,
    direction,
    energy_bound: float,
    weights: Weights = Weights(),  # noqa: B008 (frozen)
    axis=None,
    period: float | None = None,
    turn_limit: float = TURN,
) -> float:
    """The objective ``E`` of a run (module docstring); a manoeuvre's with its ``axis``,
    its rotation rewarded up to ``turn_limit`` [rad]; with the gait's ``period`` [s], the
    rotation is measured free of recoil (``rotation_vector``)."""
    model = scene.model
    value = distance(model, traj, direction)
    value += weights.deviation * deviation(model, traj, direction, axis, period)
    if axis is not None:
        value += turning(model, traj, axis, turn_limit, period)
    value += energy(traj, energy_bound, weights.energy)
    if weights.collision:
        value += weights.collision * collision(scene, traj)
    return value


def cruise(model: Model, traj: Trajectory, direction, period: float,
           cycles: int = EFFICIENCY_WINDOW) -> tuple[float, float]:  # fmt: skip
    """The root's speed along ``direction`` [m/s] and the cost of transport [J/(kg m)]
    (actuator work over mass times that distance; inf if it went nowhere forward) over
    the run's last ``cycles`` whole gait cycles of ``period`` [s].

    Raises:
        ValueError: the run is shorter than ``cycles`` periods.
    """
    end = float(traj.time[-1])
    start = end - cycles * period
    if start < traj.time[0] - 1e-9 * period:
        raise ValueError(
            f"the run lasts {end - traj.time[0]:.4g} s, less than the {cycles} cycles of "
            f"{period:.4g} s its cruise is measured over"
        )
    held = 2 if model.planar else model.dim
    position = np.zeros((len(traj.time), model.dim))
    position[:, :held] = traj.qpos[:, :held]
    before = np.array([np.interp(start, traj.time, position[:, a]) for a in range(model.dim)])
    ahead = float(_unit(direction, model.dim) @ (position[-1] - before))
    total_work = traj.energy.sum(axis=1)
    spent = float(total_work[-1] - np.interp(start, traj.time, total_work))
    cost = spent / (model.mass * ahead) if ahead > 0 else np.inf
    return ahead / (end - start), cost


def efficiency(model: Model, traj: Trajectory, direction, period: float, min_speed: float,
               reference_cost: float, cycles: int = EFFICIENCY_WINDOW) -> float:  # fmt: skip
    """``C / C_ref + w_speed max(0, 1 - U / U_min)`` (module docstring): ``U`` and ``C``
    over the last ``cycles`` cycles of ``period`` [s] (``cruise``); ``min_speed`` [m/s];
    ``reference_cost`` [J/(kg m)]; the cost term capped at ``COST_CAP``."""
    speed, cost = cruise(model, traj, direction, period, cycles)
    shortfall = max(0.0, 1.0 - speed / min_speed)  # above 1 when it swims backwards
    return min(cost / reference_cost, COST_CAP) + SPEED_WEIGHT * shortfall


def efficiency_total(scene: Scene, traj: Trajectory, direction, period: float,
                     min_speed: float, reference_cost: float,
                     weights: Weights = Weights(),  # noqa: B008 (frozen)
                     cycles: int = EFFICIENCY_WINDOW) -> float:  # fmt: skip
    """The efficiency objective of a run (module docstring): ``efficiency`` plus the
    paper's deviation (drift and turning over the whole run, free of recoil) and
    collision terms."""
    model = scene.model
    value = efficiency(model, traj, direction, period, min_speed, reference_cost, cycles)
    value += weights.deviation * deviation(model, traj, direction, period=period)
    if weights.collision:
        value += weights.collision * collision(scene, traj)
    return value


def _unit(direction, dim: int) -> np.ndarray:
    d = np.asarray(direction, dtype=float)
    if d.shape != (dim,) or not np.linalg.norm(d) > 0:
        raise ValueError(f"direction must be a nonzero vector of {dim} numbers, got {direction!r}")
    return d / np.linalg.norm(d)


_SHAPES: dict[int, tuple[Model, BodyShape]] = {}


def _shape(scene: Scene) -> BodyShape:
    """A scene without voxel geometry (vacuum, simple fluid) gets it baked once per model."""
    from aquagait.body.voxelize import body_shape

    model = scene.model
    if id(model) not in _SHAPES or _SHAPES[id(model)][0] is not model:
        _SHAPES[id(model)] = (model, body_shape(model, model.body_length / COLLISION_POINTS))
    return _SHAPES[id(model)][1]
