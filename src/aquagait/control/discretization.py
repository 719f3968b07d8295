"""How a stable PD servo is applied over one step: its look-ahead and implicit damping.

The step treats a servo ``tau = -Kp (q - qbar(t)) - Kd qd`` implicitly
(``aquagait.sim.servo``): per DOF it reads the position error a fraction
``theta`` (the *look-ahead*) of the way through the step, and adds an
implicit damping ``D`` [N m s/rad] to the mass,

    (M + dt D) qdd = -Kp [theta e(t + dt, q + dt qd) + (1 - theta) e(t, q)] - Kd qd - c

with ``e(t, q) = q - qbar(t)``. Tan, Liu and Turk's stable PD (paper §3.2,
docs/method-bodies.md) is ``theta = 1, D = Kd`` (``end_of_step``).

One DOF of inertia I, ``a = Kp``, ``b = Kd``, a still target: semi-implicit
Euler maps ``(e, dt qd)`` by ``[[1 - p, 1 - p - s], [-p, 1 - p - s]]`` with

    p = a dt^2 / (I + dt D),   s = (b dt - (1 - theta) a dt^2) / (I + dt D),

so its two eigenvalues have trace ``2 - 2p - s`` and product ``1 - p - s``.
Tracking a target ``qbar(t)``, the map's transfer function is
``H(z) = p z (theta z + 1 - theta) / (z^2 - (2 - 2p - s) z + 1 - p - s)``:
``H(1) = 1`` and, at low frequency, a lag of exactly ``b / a`` for every
``theta`` and ``D``, which is the continuous servo's ``Kd / Kp``; against an
external torque its stiffness at rest is ``a``. So the look-ahead and the
implicit damping change neither the servo's stiffness nor its lag at the
gait's frequencies; they only place the two eigenvalues, the servo's own
transient.

``sampled`` (the default) places them where the continuous servo
``I e'' + b e' + a e = 0`` sampled every dt has them: ``z = exp(lambda dt)``
for its roots lambda, trace ``T = z1 + z2``, product ``P = z1 z2 = exp(-b dt
/ I)``; so ``p = 1 - T + P = (1 - z1)(1 - z2)``, ``s = T - 2P``, hence

    I + dt D = a dt^2 / p,        theta = 1 + s / p - b / (a dt).

For the DOF's nominal inertia the sampled servo then follows the continuous
one sample for sample at any dt: each position satisfies the continuous
samples' recurrence ``e[n+1] = T e[n] - P e[n-1]``, and a gait's beat at
frequency W is followed within ``(W dt)^2 / 8`` of the continuous servo's
amplitude and phase (checked for damping ratios 0.7-3, w dt up to 4, W up
to w / 2; ``end_of_step``: about ``W^2 dt Kd / Kp`` off, the effect of its
extra mass ``dt Kd``). With ``Kp = w^2 I``, ``Kd = 2 zeta w
I``, as dt -> 0

    theta = zeta w dt / 6 + O(dt^3),   D = Kd / 2 + (4 zeta^2 + 1) w^2 I dt / 12 + O(dt^2)

(the servo read at the start of the step, half its damping implicit); at
100 rad/s, damping ratio 1.5 and dt = 1/90 s (w dt = 1.1): ``theta =
0.25``, ``D = 0.83 Kd``. ``D >= 0`` always (``|1 - e^u| <= |u|`` for Re u
<= 0), so ``M + dt D`` stays SPD. A heavier joint than the nominal (water's
added mass) scales ``p`` and ``s`` down together, which keeps the map
stable when ``s > 0`` (for damping ratio >= 1 it stays stable down to
1e-4 of the nominal inertia too, checked up to w dt = 30); ``s > 0``
holds for every real pair of roots (damping ratio >= 1) and, for an
underdamped servo with roots
``-zeta w +- i w_d``, where ``cos(w_d dt) > exp(-zeta w dt)``; elsewhere
(an undamped servo at any dt; zeta = 0.3 beyond w dt = 0.62, 0.5 beyond
1.1, 0.7 beyond 1.8) ``sampled`` refuses the step with a message.

``end_of_step`` keeps today's form for comparison. Its eigenvalues are the
continuous servo's only as dt -> 0: at w dt = 1.1, zeta = 1.5 it has mass
``I + dt Kd = 4.3 I`` and a complex pair ``-235 +- 283i`` rad/s where the
continuous servo has ``-262`` and ``-38``. It is stable only where ``3 x^2 <
4 + 4 zeta x`` (``x = w dt``; ``aquagait.control.pd``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class ServoStep:
    """A stable PD servo's terms for one step, per DOF (module docstring).

    Attributes:
        look_ahead: (nv,) theta [1]: the position error is read this fraction
            of the way through the step (1: at its end).
        damping: (nv,) D [N m s/rad]: the step's mass is ``M + dt D``.
    """

    look_ahead: np.ndarray
    damping: np.ndarray


def end_of_step(kp, kd, inertia, dt: float) -> ServoStep:
    """Tan et al.'s stable PD: the servo at the end of the step, ``D = Kd`` (module docstring).

    Args:
        kp: (nv,) stiffness [N m/rad].
        kd: (nv,) damping [N m s/rad].
        inertia: (nv,) unused (the form does not depend on it).
        dt: the step [s].
    """
    kd = np.asarray(kd, dtype=float)
    return ServoStep(look_ahead=np.ones_like(kd), damping=kd.copy())


def sampled(kp, kd, inertia, dt: float) -> ServoStep:
    """The step whose servo follows the continuous servo's samples (module docstring).

    Args:
        kp: (nv,) stiffness [N m/rad], >= 0.
        kd: (nv,) damping [N m s/rad], >= 0.
        inertia: (nv,) the inertia each servo is matched for [kg m^2 or kg],
            > 0 where a gain is not zero.
        dt: the step [s], > 0.
    Raises:
        ValueError: a non-positive dt or inertia, or an underdamped servo the
            form cannot follow at this dt (the message says which and what to change).
    """
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"time step dt must be a positive number of seconds, got {dt!r}")
    kp, kd, inertia = np.broadcast_arrays(
        *(np.atleast_1d(np.asarray(x, float)) for x in (kp, kd, inertia))
    )
    look_ahead, damping = np.ones(kp.shape), np.zeros(kp.shape)
    for i in np.flatnonzero((kp > 0) | (kd > 0)):
        look_ahead[i], damping[i] = _sampled_dof(kp[i], kd[i], inertia[i], dt, i)
    return ServoStep(look_ahead=look_ahead, damping=damping)


def _sampled_dof(a: float, b: float, inertia: float, dt: float, dof: int) -> tuple[float, float]:
    """``(theta, D)`` for one DOF: ``I + dt D = a dt^2 / p``, ``theta = 1 + s/p - b/(a dt)``."""
    if not inertia > 0:
        raise ValueError(
            f"DOF {dof}: a servo's inertia must be > 0 kg m^2 to match its step, got {inertia!r}"
        )
    p, s = _sampled_map(a, b, inertia, dt)
    if not s > 0:
        w, zeta = math.sqrt(a / inertia), b / (2 * math.sqrt(a * inertia))
        raise ValueError(
            f"DOF {dof}: the sampled stable PD cannot follow a servo this lightly damped at "
            f"this step (damping ratio {zeta:.3g}, w dt = {w * dt:.3g}: it needs "
            f"cos(w_d dt) > exp(-zeta w dt)); shorten the step, raise the damping ratio, "
            "or use StablePD(..., discretize=end_of_step)"
        )
    if a == 0:  # a pure damper: theta does not matter, I + dt D = b dt / s
        return 1.0, (b * dt / s - inertia) / dt
    return 1.0 + s / p - b / (a * dt), (a * dt * dt / p - inertia) / dt


def _sampled_map(a: float, b: float, inertia: float, dt: float) -> tuple[float, float]:
    """``p = (1 - z1)(1 - z2)`` and ``s = T - 2P`` of the continuous servo sampled every dt,
    written without cancellation (expm1) so they stay accurate as dt -> 0."""
    sigma = b / (2 * inertia)  # zeta w [1/s]
    disc = sigma * sigma - a / inertia  # w^2 (zeta^2 - 1) [1/s^2]
    if disc >= 0:  # two real roots
        root = math.sqrt(disc)
        one_minus = [-math.expm1(-(sigma + root) * dt), -math.expm1(-(sigma - root) * dt)]
        z = [1 - one_minus[0], 1 - one_minus[1]]
        return one_minus[0] * one_minus[1], z[0] * one_minus[1] + z[1] * one_minus[0]
    decay, half = -math.expm1(-sigma * dt), math.sin(math.sqrt(-disc) * dt / 2) ** 2
    r = 1 - decay  # |z| = exp(-zeta w dt)
    return decay * decay + 4 * r * half, 2 * r * (decay - 2 * half)
