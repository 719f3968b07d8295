"""How well a creature swims: distance, speed, energy, cost of transport, Strouhal number.

Measured on a ``Trajectory`` (DESIGN.md §1 step 3; paper §6 reports speed in
body lengths per cycle). Two groups:

- *travel* (any trajectory of two frames or more): the net displacement of the
  centre of mass between the first and last frames, ``distance`` [m], the
  mean ``speed`` U = distance / duration [m/s], ``body_lengths_per_cycle`` =
  U T / L, the actuator ``energy`` spent, ``E = sum_i E_i(end) - E_i(start)``
  with ``E_i`` the trajectory's cumulative ``|tau_i qd_i|`` work [J], and the
  ``cost_of_transport`` E / (m d) [J/(kg m)] (2D: m is the mass of the prism).
  The centre of mass, not the root, because the root (usually the head)
  sways; in vacuum the centre of mass stays put, whatever the gait does.
- *stroke* (needs one full gait cycle): over the last cycle, the tail tip's
  peak-to-peak lateral excursion ``tail_amplitude`` A [m] and the Strouhal
  number St = f A / U with f = 1 / T. Lateral means perpendicular to the
  swimming direction of that cycle (the centre of mass's displacement over
  it), along the principal axis of the tip's motion in that perpendicular
  plane (in 2D simply the in-plane normal). U here is ``cycle_speed``, the
  mean speed over the same last cycle: a swim that starts from rest is slower
  over its first cycle than in steady swimming, which St is about.

The tail tip is ``aquagait.body.geometry.tail_tip``: the rearmost point of the
body along its long axis at the reference pose, fixed to its link.

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
    "speed": "m/s",
    "body_lengths_per_cycle": "1",
    "energy": "J",
    "cost_of_transport": "J/(kg m)",
    "mass": "kg",
    "body_length": "m",
    "cycle_speed": "m/s",
    "tail_amplitude": "m",
    "strouhal": "1",
}
"""The unit of each entry of ``swim_metrics``'s result."""

STILL = 1e-9
"""Displacements below this many body lengths are rounding noise: the body did not move."""


def swim_metrics(model: Model, trajectory: Trajectory, period: float = 1.0) -> dict:
    """All swim metrics: travel (see ``travel_metrics``) and stroke (``stroke_metrics``).

    Args:
        model: the creature that swam.
        trajectory: its trajectory; at least one full cycle long.
        period: gait period T [s].

    Returns:
        A dict of floats keyed as in ``UNITS``.

    Raises:
        ValueError: the trajectory is shorter than one cycle, or does not fit the model.
    """
    return {
        **travel_metrics(model, trajectory, period),
        **stroke_metrics(model, trajectory, period),
    }


def travel_metrics(model: Model, trajectory: Trajectory, period: float = 1.0) -> dict:
    """Distance, speed, body lengths per cycle, energy and cost of transport (module docstring).

    Needs two frames or more, not a full cycle.
    """
    _check(model, trajectory, period)
    com = centre_of_mass_path(model, trajectory)
    duration = float(trajectory.time[-1] - trajectory.time[0])
    distance = _rounded(np.linalg.norm(com[-1] - com[0]), model)
    speed = distance / duration
    energy = float(np.sum(trajectory.energy[-1] - trajectory.energy[0]))
    return {
        "duration": duration,
        "period": float(period),
        "distance": distance,
        "speed": speed,
        "body_lengths_per_cycle": speed * period / model.body_length,
        "energy": energy,
        "cost_of_transport": _ratio(energy, model.mass * distance),
        "mass": float(model.mass),
        "body_length": float(model.body_length),
    }


def stroke_metrics(model: Model, trajectory: Trajectory, period: float = 1.0) -> dict:
    """Speed, tail-tip amplitude and Strouhal number over the last full cycle.

    Raises:
        ValueError: the trajectory is shorter than one cycle.
    """
    _check(model, trajectory, period)
    duration = trajectory.time[-1] - trajectory.time[0]
    if duration < period * (1 - 1e-9):
        raise ValueError(
            f"the trajectory lasts {duration:.4g} s, less than one gait cycle of {period:.4g} s; "
            "the Strouhal number needs a full cycle (simulate longer)"
        )
    last = trajectory.time >= trajectory.time[-1] - period * (1 + 1e-9)
    cycle = _frames(trajectory, last)
    com = centre_of_mass_path(model, cycle)
    tip = tail_tip_path(model, cycle.qpos)
    displacement = com[-1] - com[0]
    cycle_speed = _rounded(np.linalg.norm(displacement), model) / float(np.ptp(cycle.time))
    amplitude = lateral_excursion(tip, displacement)
    return {
        "cycle_speed": cycle_speed,
        "tail_amplitude": amplitude,
        "strouhal": _ratio(amplitude / period, cycle_speed),
    }


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
    dynamics = Dynamics(model.mj)
    return np.array([dynamics.center_of_mass(q)[: model.dim] for q in trajectory.qpos])


def _frames(trajectory: Trajectory, keep) -> Trajectory:
    return Trajectory(
        time=trajectory.time[keep],
        qpos=trajectory.qpos[keep],
        qvel=trajectory.qvel[keep],
        torque=trajectory.torque[keep],
        energy=trajectory.energy[keep],
        dt=trajectory.dt,
        fps=trajectory.fps,
    )


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
