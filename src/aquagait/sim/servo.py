"""The body's half of every step: the policy's force, the stable PD prediction, the work done.

The controller seam (docs/development.md, "How the code reads"). A *policy*
is any callable

    policy(t, q, qd) -> tau    # (nv,) generalized force [N or N m]

applied over the step. Plain callables are explicit: ``tau`` is evaluated at
the start of the step. A servo may also say how the step should treat it
implicitly, with a method

    policy.implicit(dt) -> (look_ahead, damping)    # each (nv,): theta [1], D [N m s/rad]

The step then evaluates it at the start of the step and at the predicted end,
``(t + dt, q + dt qd, qd)``, blends the two per DOF, and solves

    (M + dt D) qdd = theta tau(t + dt, q + dt qd, qd) + (1 - theta) tau(t, q, qd) - c

so that with ``tau = -Kp (q - qbar) - Kd qd`` the servo reads its position
error theta of the way through the step (``aquagait.control.discretization``
derives theta and D so that the step follows the continuous servo). A policy
with a ``damping`` attribute (nv,) instead is the special case ``theta = 1,
D = damping``: Tan et al.'s stable PD (paper §3.2, docs/method-bodies.md),
evaluated only at the end of the step. The force actually applied is ``tau -
D (qd^{n+1} - qd^n)``; the step records it and adds ``|tau_i qd_i| dt`` per
DOF to the energy. ``policy=None`` applies nothing. ``aquagait.control``
provides such policies; this package never imports it.

Time integration is semi-implicit Euler: ``qd += dt qdd``, then ``q`` moves
with the new ``qd`` (quaternions on the unit sphere).
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from aquagait.sim.scene import Scene, State


class SimulationError(RuntimeError):
    """A simulation cannot go on; the message says when, where and what to change."""


class SimulationDiverged(SimulationError):
    """The state stopped being finite; the message says when and where."""


def servo_forces(scene: Scene, state: State, dt: float, policy) -> tuple[np.ndarray, np.ndarray]:
    """The policy's force and implicit damping D for this step, each (nv,) (module docstring).

    A servo (``implicit`` or ``damping``) is evaluated at the predicted end of
    the step, ``(t + dt, q + dt qd, qd)``, and, where its look-ahead is below
    1, also at ``(t, q, qd)``; any other policy at ``(t, q, qd)``.
    """
    nv = scene.model.nv
    if policy is None:
        return np.zeros(nv), np.zeros(nv)
    look_ahead, damping = implicit_terms(policy, dt, nv)
    if damping is None:
        return _force(policy(state.time, state.qpos, state.qvel), nv), np.zeros(nv)
    ahead = scene.dynamics.integrate(state.qpos, state.qvel, dt)
    tau = _force(policy(state.time + dt, ahead, state.qvel), nv)
    if np.any(look_ahead != 1):
        now = _force(policy(state.time, state.qpos, state.qvel), nv)
        tau = look_ahead * tau + (1 - look_ahead) * now
    return tau, damping


def implicit_terms(policy, dt: float, nv: int):
    """``(look_ahead, damping)`` of a servo for a step of ``dt``, each (nv,); ``(None, None)``
    for an explicit policy (module docstring)."""
    implicit = getattr(policy, "implicit", None)
    if implicit is not None:
        look_ahead, damping = implicit(dt)
    else:
        damping = getattr(policy, "damping", None)
        if damping is None:
            return None, None
        look_ahead = np.ones(nv)
    look_ahead = np.asarray(look_ahead, dtype=float)
    damping = np.asarray(damping, dtype=float)
    if look_ahead.shape != (nv,) or damping.shape != (nv,):
        raise ValueError(
            f"policy gave look_ahead {look_ahead.shape} and damping {damping.shape} for the "
            f"step; both must be ({nv},)"
        )
    return look_ahead, damping


def _force(tau, nv: int) -> np.ndarray:
    tau = np.asarray(tau, dtype=float)
    if tau.shape != (nv,):
        raise ValueError(f"policy returned tau {tau.shape}; it must be ({nv},)")
    return tau


def servo_mass(scene: Scene, q, dt: float, damping) -> np.ndarray:
    """``Mt = M(q) + dt D``, (nv, nv): the mass the stable PD's implicit damping adds to."""
    mass = scene.dynamics.mass_matrix(q)
    mass[np.diag_indices_from(mass)] += dt * damping
    return mass


def predict_body(scene: Scene, state: State, dt: float, tau, damping) -> np.ndarray:
    """Accelerations qdd (nv,) from ``(M + dt D) qdd = tau - c``.

    Step 3 of the coupled step (docs/method-coupling.md, "The coupled step").
    """
    mass = servo_mass(scene, state.qpos, dt, damping)
    force = tau - scene.dynamics.bias(state.qpos, state.qvel)
    try:
        qdd = np.linalg.solve(mass, force)
    except np.linalg.LinAlgError:
        qdd = np.full(len(force), np.nan)
    if not np.all(np.isfinite(qdd)):
        raise SimulationDiverged(
            f"simulation diverged at t = {state.time:.4g} s: no finite acceleration "
            f"(|q| up to {np.abs(state.qpos).max():.3g}, |tau| up to {np.abs(tau).max():.3g}); "
            "gains too stiff for dt?"
        )
    return qdd


def account_work(state: State, dt: float, tau, damping, qvel):
    """The force applied over the step and the energy so far, each (nv,).

    The implicit damping adds ``-D (qd^{n+1} - qd^n)`` to the policy's force
    (``-dt D qdd``); the work is counted as ``|tau_i qd_i| dt`` with the
    velocity that moves the positions, so spending and braking both cost
    (docs/method-search.md, E_energy).
    """
    applied = tau - damping * (qvel - state.qvel)
    return applied, state.energy + dt * np.abs(applied * qvel)


def move_body(scene: Scene, state: State, dt: float, tau, damping, qvel) -> State:
    """``q^{n+1}`` from ``qd^{n+1}``, the force applied and the work done; checked finite."""
    qpos = scene.dynamics.integrate(state.qpos, qvel, dt)
    torque, energy = account_work(state, dt, tau, damping, qvel)
    new = replace(
        state, time=state.time + dt, qpos=qpos, qvel=qvel, torque=torque, energy=energy,
        steps=state.steps + 1,
    )  # fmt: skip
    return _check_finite(scene, new)


def _check_finite(scene: Scene, state: State) -> State:
    if np.all(np.isfinite(state.qvel)) and np.all(np.isfinite(state.qpos)):
        return state
    bad = np.flatnonzero(~np.isfinite(state.qvel))
    where = ", ".join(scene.model.dof_names[i] for i in bad[:3]) if bad.size else "qpos"
    raise SimulationDiverged(
        f"simulation diverged at t = {state.time:.4g} s: non-finite state at {where} "
        "(gains too stiff for dt? use a stable PD or a smaller dt)"
    )
