"""How well a creature swims: distance, speed, energy, cost of transport, Strouhal number.

Measured on a ``Trajectory`` (docs/swim.md; paper §6 reports speed in
body lengths per cycle). A swim starts from rest, so there are two kinds of
figure, named apart:

- *from rest*, over the whole swim (any trajectory of two frames or more):
  the net displacement of the centre of mass between the first and last
  frames, ``distance`` [m]; the mean ``speed_from_rest`` U0 = distance /
  duration [m/s]; ``body_lengths_per_cycle_from_rest`` = U0 T / L; the
  actuator ``energy`` spent, ``E = sum_i E_i(end) - E_i(start)`` with ``E_i``
  the trajectory's cumulative ``|tau_i qd_i|`` work [J] (the step sums it at
  every simulation step, so the difference is exact: no quadrature over
  frames); and the ``cost_of_transport`` E / (m d) [J/(kg m)] (2D: m is the
  mass of the prism).
- *steady*, over the steady window (needs two whole gait cycles): the last
  whole cycles after the first. A swim of n >= 2 whole cycles of period T
  ending at ``t_end`` is measured over the frames from ``t_end - (n - 1) T``
  to ``t_end``: ``steady_start`` and ``steady_end`` [s] (the window's first
  and last frame times), ``steady_cycles`` = n - 1, the mean
  ``steady_speed`` U over the window [m/s],
  ``steady_body_lengths_per_cycle`` = U T / L, the tail tip's peak-to-peak
  lateral excursion ``tail_amplitude`` A [m] and the Strouhal number
  St = f A / U with f = 1 / T. The first cycle is left out because the body
  accelerates from rest through it; whole cycles because the speed surges
  within a stroke and averages out only over whole ones; the window ends at
  the last frame because the latest cycles are the steadiest.
- *at cruise*, once the swim has settled (``cruise_metrics``; most 3D
  creatures need ten cycles or more from rest, so the steady window of a
  short swim still holds the start). The whole cycles from the start, k = 1,
  2, ..., n, each swim a distance d_k (the centre of mass's displacement over
  it); the swim has settled from the first cycle k with |d_{k+2} - d_k| <=
  ``SETTLED`` d_{k+2} (its distance per cycle changes by less than 2 % over
  two cycles), and the cruise window is cycles k to n: ``cruise_start``,
  ``cruise_end``, ``cruise_cycles``, ``cruise_speed`` (the sum of the
  window's d_k over its duration: a swimmer that turns is measured along its
  path, cycle by cycle, not by where it ended up),
  ``cruise_body_lengths_per_cycle``, ``cruise_tail_amplitude``,
  ``cruise_strouhal`` and ``cruise_cost_of_transport`` over it (the energy
  spent in the window over that distance). ``settled`` says
  whether it settled, ``settled_cycle`` from which cycle (``nan`` and the
  cruise figures ``nan`` when it did not), ``cycle_distances`` the d_k.
- *attitude*, in 3D: the root's orientation against its orientation at rest,
  averaged over the last whole cycle (a body's head yaws and rolls within a
  stroke): ``heading``, ``pitch`` and ``roll`` [deg], the z-y-x Euler angles
  of the turn from rest in the world frame (z up, the creature facing +x at
  rest): turning left about the vertical, nose up (the turn about +y with
  its sign flipped), rolling about the long axis (right-handed about +x);
  and the largest ``|pitch|`` and ``|roll|`` of any whole cycle. In 2D only
  the turn in the plane, ``heading``.

The tail amplitude is measured cycle by cycle, each across the tip's own
displacement over that cycle (the chord of its mean path: on a curve the
tail's chord is not the centre of mass's), and averaged: over many cycles a
slow turn of the heading would otherwise count as beat.

The centre of mass, not the root, because the root (usually the head) sways;
in vacuum the centre of mass stays put, whatever the gait does. Lateral means
perpendicular to the swimming direction over the window (the centre of
mass's displacement over it), along the principal axis of the tip's motion
in that perpendicular plane (in 2D simply the in-plane normal; the tail
amplitude takes the tip's own displacement, below). The tail tip
is ``aquagait.body.geometry.tail_tip``: the rearmost point of the body along
its long axis at the reference pose, fixed to its link.

Undefined values (St of a body that does not move, cost of transport over no
distance) are ``nan`` or ``inf``; they are never silently zero. A body moved
by less than ``STILL`` body lengths has not moved.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from aquagait.body.dynamics import Dynamics
from aquagait.body.geometry import tail_tip_path
from aquagait.body.model import Model
from aquagait.sim import Trajectory

UNITS = {
    "duration": "s",
    "period": "s",
    "distance": "m",
    "speed_from_rest": "m/s",
    "body_lengths_per_cycle_from_rest": "1",
    "energy": "J",
    "cost_of_transport": "J/(kg m)",
    "mass": "kg",
    "body_length": "m",
    "steady_start": "s",
    "steady_end": "s",
    "steady_cycles": "1",
    "steady_speed": "m/s",
    "steady_body_lengths_per_cycle": "1",
    "tail_amplitude": "m",
    "strouhal": "1",
    "cycles": "1",
    "cycle_distances": "m",
    "settled": "1",
    "settled_cycle": "1",
    "cruise_start": "s",
    "cruise_end": "s",
    "cruise_cycles": "1",
    "cruise_speed": "m/s",
    "cruise_body_lengths_per_cycle": "1",
    "cruise_tail_amplitude": "m",
    "cruise_strouhal": "1",
    "cruise_cost_of_transport": "J/(kg m)",
    "heading": "deg",
    "pitch": "deg",
    "roll": "deg",
    "max_pitch": "deg",
    "max_roll": "deg",
}
"""The unit of each entry of ``swim_metrics``'s result."""

PATH_UNITS = {
    "path_distance_mean": "m",
    "path_distance_max": "m",
    "path_distance_final": "m",
    "path_distance_mean_body_lengths": "1",
    "path_distance_max_body_lengths": "1",
    "path_distance_final_body_lengths": "1",
    "path_progress": "m",
    "path_progress_body_lengths": "1",
    "unlearned_requests": "1",
    "path_finished": "1",
    "path_followed_seconds": "s",
}
"""The unit of each entry a path following adds (``aquagait.app.follow``): the root's
distance to the path over the frames until it reached the path's end (``final``: at that
frame, or the last), how far along it got, cycles swum straight for want of a learned
manoeuvre, whether it reached the end and after how long."""

STILL = 1e-9
"""Displacements below this many body lengths are rounding noise: the body did not move."""

STARTING_CYCLES = 1
"""Whole gait cycles at the start that the steady window leaves out (acceleration from rest)."""


SETTLED = 0.02
"""The share by which a settled swim's distance per cycle may change over two cycles."""

SETTLING_CYCLES = 3
"""The fewest whole cycles in which settling can be told: a cycle, and the one two later."""


class NoSteadyWindow(ValueError):
    """The trajectory is too short for steady figures; the message says how long it must be."""


def swim_metrics(model: Model, trajectory: Trajectory, period: float = 1.0) -> dict:
    """All swim metrics: from rest (``travel_metrics``), steady (``steady_metrics``), at
    cruise (``cruise_metrics``) and attitude (``attitude_metrics``).

    Args:
        model: the creature that swam.
        trajectory: its trajectory; at least two whole gait cycles long.
        period: gait period T [s].

    Returns:
        A dict of floats keyed as in ``UNITS``.

    Raises:
        NoSteadyWindow: the trajectory is shorter than two whole cycles.
        ValueError: the trajectory does not fit the model.
    """
    return {
        **travel_metrics(model, trajectory, period),
        **steady_metrics(model, trajectory, period),
        **cruise_metrics(model, trajectory, period),
        **attitude_metrics(model, trajectory, period),
    }


def travel_metrics(model: Model, trajectory: Trajectory, period: float = 1.0) -> dict:
    """The from-rest figures over the whole swim (module docstring); needs two frames or more.

    Returns:
        ``duration`` [s], ``period`` [s], ``distance`` [m], ``speed_from_rest``
        [m/s], ``body_lengths_per_cycle_from_rest`` [1], ``energy`` [J],
        ``cost_of_transport`` [J/(kg m)], ``mass`` [kg], ``body_length`` [m].
    """
    _check(model, trajectory, period)
    com = _centre_of_mass(model, trajectory.qpos[[0, -1]])
    duration = float(trajectory.time[-1] - trajectory.time[0])
    distance = _rounded(np.linalg.norm(com[-1] - com[0]), model)
    speed = distance / duration
    energy = float(np.sum(trajectory.energy[-1] - trajectory.energy[0]))
    return {
        "duration": duration,
        "period": float(period),
        "distance": distance,
        "speed_from_rest": speed,
        "body_lengths_per_cycle_from_rest": speed * period / model.body_length,
        "energy": energy,
        "cost_of_transport": _ratio(energy, model.mass * distance),
        "mass": float(model.mass),
        "body_length": float(model.body_length),
    }


def steady_metrics(model: Model, trajectory: Trajectory, period: float = 1.0) -> dict:
    """The steady figures over the steady window (module docstring).

    Returns:
        ``steady_start``, ``steady_end`` [s], ``steady_cycles`` [1],
        ``steady_speed`` [m/s], ``steady_body_lengths_per_cycle`` [1],
        ``tail_amplitude`` [m], ``strouhal`` [1].

    Raises:
        NoSteadyWindow: the trajectory is shorter than two whole cycles.
    """
    _check(model, trajectory, period)
    window = steady_window(trajectory, period)
    time = trajectory.time[window]
    qpos = trajectory.qpos[window]
    com = _centre_of_mass(model, qpos)
    displacement = com[-1] - com[0]
    start, end = float(time[0]), float(time[-1])
    speed = _rounded(np.linalg.norm(displacement), model) / (end - start)
    cycles = Cycles(model, Trajectory(time, qpos, *_rest(trajectory, window)), period)
    amplitude = float(np.mean(cycles.tail_amplitudes()))
    return {
        "steady_start": start,
        "steady_end": end,
        "steady_cycles": float(_whole_cycles(trajectory.time, period) - STARTING_CYCLES),
        "steady_speed": speed,
        "steady_body_lengths_per_cycle": speed * period / model.body_length,
        "tail_amplitude": amplitude,
        "strouhal": _ratio(amplitude / period, speed),
    }


def cruise_metrics(model: Model, trajectory: Trajectory, period: float = 1.0) -> dict:
    """The figures at cruise, once the swim has settled (module docstring).

    Returns:
        ``cycles`` [1] and ``cycle_distances`` [m] (a list, one per whole cycle from
        the start), ``settled`` (bool), ``settled_cycle`` [1] (counted from 1, ``nan``
        if the swim did not settle), and ``cruise_start``, ``cruise_end`` [s],
        ``cruise_cycles`` [1], ``cruise_speed`` [m/s], ``cruise_body_lengths_per_cycle``
        [1], ``cruise_tail_amplitude`` [m], ``cruise_strouhal`` [1] and
        ``cruise_cost_of_transport`` [J/(kg m)], ``nan`` if it did not settle.
    """
    _check(model, trajectory, period)
    cycles = Cycles(model, trajectory, period)
    distances = cycles.distances()
    first = settled_cycle(distances)
    figures = dict.fromkeys(
        ("cruise_start", "cruise_end", "cruise_cycles", "cruise_speed",
         "cruise_body_lengths_per_cycle", "cruise_tail_amplitude", "cruise_strouhal",
         "cruise_cost_of_transport"),
        float("nan"),
    )  # fmt: skip
    if first is not None:
        window = slice(first - 1, None)
        start, end = cycles.starts[first - 1], cycles.starts[-1] + period
        distance = _rounded(float(np.sum(distances[window])), model)
        speed = distance / (end - start)
        amplitude = float(np.mean(cycles.tail_amplitudes()[window]))
        figures = {
            "cruise_start": start,
            "cruise_end": end,
            "cruise_cycles": float(distances.size - first + 1),
            "cruise_speed": speed,
            "cruise_body_lengths_per_cycle": speed * period / model.body_length,
            "cruise_tail_amplitude": amplitude,
            "cruise_strouhal": _ratio(amplitude / period, speed),
            "cruise_cost_of_transport": _ratio(cycles.energy(start, end), model.mass * distance),
        }
    return {
        "cycles": float(distances.size),
        "cycle_distances": [float(d) for d in distances],
        "settled": first is not None,
        "settled_cycle": float("nan") if first is None else float(first),
        **figures,
    }


def settled_cycle(distances) -> int | None:
    """The first cycle (counted from 1) from which a swim is settled at cruise: its distance
    ``d_k`` and ``d_{k+2}`` differ by at most ``SETTLED`` of ``d_{k+2}``; None if none is.

    Args:
        distances: (n,) distance swum in each whole cycle from the start [m].
    """
    d = np.asarray(distances, dtype=float)
    for k in range(d.size - 2):
        if d[k + 2] > 0 and abs(d[k + 2] - d[k]) <= SETTLED * d[k + 2]:
            return k + 1
    return None


def attitude_metrics(model: Model, trajectory: Trajectory, period: float = 1.0) -> dict:
    """The root's heading, pitch and roll [deg] over the last whole cycle, and the largest
    pitch and roll of any whole cycle (module docstring); 2D: ``heading`` only.

    Raises:
        NoSteadyWindow: the trajectory is shorter than one whole cycle.
    """
    _check(model, trajectory, period)
    cycles = Cycles(model, trajectory, period)
    if cycles.starts.size == 0:
        raise NoSteadyWindow(
            f"the swim lasts less than a gait cycle of {period:.4g} s: no attitude, which is "
            "averaged over a whole cycle"
        )
    angles = cycles.attitudes()  # (n, 3): heading, pitch, roll per cycle
    if model.dim == 2:
        return {"heading": float(angles[-1, 0])}
    return {
        "heading": float(angles[-1, 0]),
        "pitch": float(angles[-1, 1]),
        "roll": float(angles[-1, 2]),
        "max_pitch": float(np.max(np.abs(angles[:, 1]))),
        "max_roll": float(np.max(np.abs(angles[:, 2]))),
    }


def course(trajectory: Trajectory, dim: int, seconds: float) -> float:
    """Degrees between +x (where a creature faces at rest) and the way its root travelled
    over the last ``seconds`` of ``trajectory`` ([0, 180]): over whole gait cycles, the
    course it holds, free of the body's recoil within a cycle (where ``heading`` is where
    it faces).

    Args:
        trajectory: the swim; its root's position is ``qpos[:, :dim]`` [m] (a free or
            planar root, as every creature has).
        dim: 2 or 3, the creature's.
        seconds: how far back from the last frame [s], rounded to whole frames.

    Raises:
        ValueError: ``seconds`` is not more than a frame and less than the swim.
    """
    frames = int(round(seconds * trajectory.fps))
    if not 0 < frames < len(trajectory.time):
        raise ValueError(
            f"a course over the last {seconds:.4g} s needs a swim longer than that: this "
            f"one has {len(trajectory.time)} frames at {trajectory.fps:.4g} a second"
        )
    travel = trajectory.qpos[-1, :dim] - trajectory.qpos[-1 - frames, :dim]
    return float(np.degrees(np.arccos(np.clip(travel[0] / np.linalg.norm(travel), -1, 1))))


class Cycles:
    """A trajectory cut into whole gait cycles from its first frame: ``starts`` (n,) [s].

    Positions and energies between frames are interpolated linearly, so cycles need not
    begin on a frame.
    """

    def __init__(self, model: Model, trajectory: Trajectory, period: float):
        self.model, self.trajectory, self.period = model, trajectory, float(period)
        time = trajectory.time
        self.starts = time[0] + period * np.arange(_whole_cycles(time, period))
        self._com = None

    def distances(self) -> np.ndarray:
        """(n,) the centre of mass's displacement over each cycle [m]."""
        return np.array([self.displacement(s, s + self.period) for s in self.starts])

    def displacement(self, start: float, end: float) -> float:
        """The centre of mass's displacement from ``start`` to ``end`` [s], [m]."""
        a, b = self._at((start, end), self.com)
        return float(np.linalg.norm(b - a))

    def energy(self, start: float, end: float) -> float:
        """Actuator work spent from ``start`` to ``end`` [s], [J]."""
        a, b = self._at((start, end), self.trajectory.energy.sum(axis=1)[:, None])
        return float(b[0] - a[0])

    def tail_amplitudes(self) -> np.ndarray:
        """(n,) the tail tip's peak-to-peak excursion in each cycle across its own
        displacement over the cycle (the chord of its mean path)."""
        tail = tail_tip_path(self.model, self.trajectory.qpos)
        out = []
        for s in self.starts:
            a, b = self._at((s, s + self.period), tail)
            out.append(lateral_excursion(tail[self._frames(s)], b - a))
        return np.array(out)

    def attitudes(self) -> np.ndarray:
        """(n, 3) the root's mean heading, pitch and roll [deg] over each cycle, against
        its orientation at rest (module docstring)."""
        dynamics = Dynamics(self.model.mj)
        rest = dynamics.link_poses(self.model.qpos0)[1][0]
        turned = np.array([dynamics.link_poses(q)[1][0] @ rest.T for q in self.trajectory.qpos])
        out = []
        for s in self.starts:
            u, _, vt = np.linalg.svd(turned[self._frames(s)].mean(axis=0))
            mean = u @ np.diag([1.0, 1.0, np.linalg.det(u @ vt)]) @ vt  # nearest rotation
            out.append(Rotation.from_matrix(mean).as_euler("ZYX", degrees=True))
        return np.array(out) * [1.0, -1.0, 1.0]  # about +y is nose down: pitch counts up

    @property
    def com(self) -> np.ndarray:
        if self._com is None:
            self._com = _centre_of_mass(self.model, self.trajectory.qpos)
        return self._com

    def _frames(self, start: float) -> np.ndarray:
        """The frames of the cycle from ``start`` [s], both ends included (rounding forgiven)."""
        time, slack = self.trajectory.time, 1e-9 * self.period
        return np.flatnonzero((time >= start - slack) & (time <= start + self.period + slack))

    def _at(self, times, values: np.ndarray) -> np.ndarray:
        """``values`` (F, k) per frame, interpolated linearly at ``times``."""
        time = self.trajectory.time
        return np.stack([np.interp(times, time, column) for column in values.T], axis=1)


def steady_window(trajectory: Trajectory, period: float = 1.0) -> np.ndarray:
    """The frames of the steady window (module docstring), a (F,) bool mask.

    Raises:
        NoSteadyWindow: fewer than two whole cycles, or fewer than two frames in the window.
    """
    time = np.asarray(trajectory.time, dtype=float)
    duration = time[-1] - time[0]
    cycles = _whole_cycles(time, period) - STARTING_CYCLES
    if cycles < 1:
        least = (STARTING_CYCLES + 1) * period
        raise NoSteadyWindow(
            f"the swim lasts {duration:.4g} s, less than two gait cycles of {period:.4g} s: "
            "no steady figures (steady speed, tail amplitude, Strouhal number), which leave "
            f"out the first cycle from rest; simulate at least {least:.4g} s"
        )
    window = time >= time[-1] - cycles * period - 1e-9 * period
    if np.count_nonzero(window) < 2:
        raise NoSteadyWindow(
            f"the steady window of {cycles} cycle(s) of {period:.4g} s holds one frame; "
            "record more frames per cycle"
        )
    return window


def lateral_excursion(points, direction) -> float:
    """Peak-to-peak extent [m] of ``points`` (F, d) across ``direction`` (d,).

    The points' components along ``direction`` are removed; what is left is
    measured along its principal axis. A zero direction measures the raw
    principal extent.
    """
    points = np.asarray(points, dtype=float)
    direction = np.asarray(direction, dtype=float)
    norm = np.linalg.norm(direction)
    across = points - points.mean(axis=0)
    if norm > 0:
        d = direction / norm
        across = across - np.outer(across @ d, d)
    if not np.any(across):
        return 0.0
    axis = np.linalg.svd(across, full_matrices=False)[2][0]
    along = across @ axis
    return float(along.max() - along.min())


def centre_of_mass_path(model: Model, trajectory: Trajectory) -> np.ndarray:
    """Centre of mass per frame, (F, dim) [m] (the swim plane in 2D)."""
    return _centre_of_mass(model, trajectory.qpos)


def _centre_of_mass(model: Model, qpos) -> np.ndarray:
    dynamics = Dynamics(model.mj)
    return np.array([dynamics.center_of_mass(q)[: model.dim] for q in qpos])


def _rest(trajectory: Trajectory, frames) -> tuple:
    """The trajectory's other per-frame arrays at ``frames``, and its dt and fps."""
    t = trajectory
    return t.qvel[frames], t.torque[frames], t.energy[frames], t.dt, t.fps


def _whole_cycles(time, period: float) -> int:
    """Whole gait cycles in the frames' time span (rounding noise forgiven)."""
    return int(np.floor((time[-1] - time[0]) / period + 1e-9))


def _rounded(distance: float, model: Model) -> float:
    """A distance [m], with less than ``STILL`` body lengths (rounding noise) read as none."""
    return float(distance) if distance >= STILL * model.body_length else 0.0


def _ratio(numerator: float, denominator: float) -> float:
    if denominator > 0:
        return float(numerator / denominator)
    return float("nan") if numerator == 0 else float("inf")


def _check(model: Model, trajectory: Trajectory, period: float) -> None:
    if not (np.isfinite(period) and period > 0):
        raise ValueError(f"period must be a positive number of seconds, got {period!r}")
    time = np.asarray(trajectory.time)
    if time.ndim != 1 or time.size < 2:
        raise ValueError(f"a trajectory needs two frames or more to measure; got {time.size}")
    if np.any(np.diff(time) <= 0):
        raise ValueError("trajectory times must increase from frame to frame")
    if trajectory.qpos.shape != (time.size, model.nq):
        raise ValueError(
            f"trajectory qpos has shape {trajectory.qpos.shape}; for {model.source} "
            f"with {time.size} frames it must be ({time.size}, {model.nq})"
        )
