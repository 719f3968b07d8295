"""How well a creature swims: distance, speed, energy, cost of transport, Strouhal number.

Measured on a ``Trajectory`` (DESIGN.md §1 step 3; paper §6 reports speed in
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

The centre of mass, not the root, because the root (usually the head) sways;
in vacuum the centre of mass stays put, whatever the gait does. Lateral means
perpendicular to the swimming direction over the window (the centre of
mass's displacement over it), along the principal axis of the tip's motion
in that perpendicular plane (in 2D simply the in-plane normal). The tail tip
is ``aquagait.body.geometry.tail_tip``: the rearmost point of the body along
its long axis at the reference pose, fixed to its link.

Undefined values (St of a body that does not move, cost of transport over no
distance) are ``nan`` or ``inf``; they are never silently zero. A body moved
by less than ``STILL`` body lengths has not moved.
"""

from __future__ import annotations

import numpy as np

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
}
"""The unit of each entry a path following adds (``aquagait.app.follow``): the root's
distance to the path over the frames, how far along it got, cycles swum straight for want
of a learned manoeuvre."""

STILL = 1e-9
"""Displacements below this many body lengths are rounding noise: the body did not move."""

STARTING_CYCLES = 1
"""Whole gait cycles at the start that the steady window leaves out (acceleration from rest)."""


class NoSteadyWindow(ValueError):
    """The trajectory is too short for steady figures; the message says how long it must be."""


def swim_metrics(model: Model, trajectory: Trajectory, period: float = 1.0) -> dict:
    """All swim metrics: from rest (``travel_metrics``) and steady (``steady_metrics``).

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
    amplitude = lateral_excursion(tail_tip_path(model, qpos), displacement)
    return {
        "steady_start": start,
        "steady_end": end,
        "steady_cycles": float(_whole_cycles(trajectory.time, period) - STARTING_CYCLES),
        "steady_speed": speed,
        "steady_body_lengths_per_cycle": speed * period / model.body_length,
        "tail_amplitude": amplitude,
        "strouhal": _ratio(amplitude / period, speed),
    }


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
