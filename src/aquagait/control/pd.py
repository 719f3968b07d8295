"""PD servos that track a gait: explicit, and the stable (implicit) form (DESIGN.md §2.2).

A servo is a policy in the sense of ``aquagait.sim``: ``policy(t, q, qd) -> tau``
(nv,) with

    tau = -Kp (q - qbar(t)) - Kd qd

on the actuated DOFs and zero on the root. ``PD`` is applied explicitly: the
step uses the force at the start of the step. ``StablePD`` also exposes its
``damping`` (= Kd), which tells the step to evaluate it at the *end* of the
step and to treat the damping implicitly (Tan, Liu and Turk 2011; paper §3.2):

    (M + dt Kd) qdd = -c - Kp (q + dt qd - qbar(t + dt)) - Kd qd

which stays stable for gains far beyond what the explicit form survives at
the fluid's time step. Stability, per servo mode with ``Kp = w^2 I`` and
``Kd = 2 zeta w I`` (semi-implicit Euler, linearized; Jury's criterion on the
2x2 step map), with ``x = w dt``:

    explicit PD:  x^2 + 4 zeta x < 4      (zeta = 1: x < 0.83)
    stable PD:    3 x^2 < 4 + 4 zeta x    (zeta = 1: x < 2; large x: Kd > 1.5 Kp dt)

Because §2.2 drops the ``dt^2 Kp`` term of the full linearization, the stable
form is not unconditionally stable: give it enough damping for the step. The
step records the force actually applied, ``tau - dt Kd qdd = -Kp (...) - Kd
qd^{n+1}``, and the energy ``|tau_i qd_i| dt``.

For a ball joint the gait drives the three components of a rotation vector
``r`` (``"name:x|y|z"``), the reference orientation is ``exp(r)``, and the
position error is the rotation vector of ``exp(r)^-1 q`` in the child frame
(MuJoCo's ball velocities are in that frame). An actuated DOF that the gait
does not drive is held at 0.

Gains: ``StablePD.tuned`` sets ``Kp = w^2 I``, ``Kd = 2 zeta w I`` per DOF from
a natural frequency ``w`` [rad/s] and damping ratio ``zeta``, with ``I =
1/(M^-1)_ii`` the DOF's apparent inertia at the reference pose (all other DOFs
free); Kp in N m/rad, Kd in N m s/rad.
"""

from __future__ import annotations

import numpy as np

from aquagait.body.dynamics import Dynamics
from aquagait.body.model import Model
from aquagait.body.rotations import quat_conj, quat_exp, quat_log, quat_mul
from aquagait.control.gait import SineGait


class PD:
    """Explicit PD servo tracking a sine gait on a model's actuated DOFs.

    Args:
        model: the creature.
        gait: per-DOF sines; its DOF names must be actuated DOFs of the model.
        kp: (nv,) stiffness [N m/rad]; zero on the root DOFs.
        kd: (nv,) damping [N m s/rad]; zero on the root DOFs.
    """

    def __init__(self, model: Model, gait: SineGait, kp, kd):
        self.gait = gait
        self.kp, self.kd = _check_gains(model, kp, kd)
        actuated = {model.dof_names[d] for d in model.actuated_dofs}
        unknown = [d for d in gait.dofs if d not in actuated]
        if unknown:
            raise ValueError(
                f"{model.source}: gait drives {unknown}, which are not actuated DOFs; "
                f"actuated: {sorted(actuated)}"
            )
        slot = {name: i for i, name in enumerate(gait.dofs)}
        actuated_dofs = set(model.actuated_dofs.tolist())
        hinges = [j for j in model.joints if j.kind == "hinge" and j.dof in actuated_dofs]
        self._hinge_q = np.array([j.qpos for j in hinges], dtype=int)
        self._hinge_dof = np.array([j.dof for j in hinges], dtype=int)
        self._hinge_slot = np.array([slot.get(model.dof_names[j.dof], -1) for j in hinges], int)
        self._balls = [
            (j.qpos, j.dof, np.array([slot.get(model.dof_names[j.dof + i], -1) for i in range(3)]))
            for j in model.joints
            if j.kind == "ball"
        ]
        self.nv = model.nv

    def _slots(self, slots, t) -> np.ndarray:
        return np.where(slots >= 0, self.gait.angles(t)[slots], 0.0)

    def error(self, t: float, q) -> np.ndarray:
        """Position error ``q - qbar(t)`` on the actuated DOFs, zero elsewhere, (nv,) [rad]."""
        q = np.asarray(q, dtype=float)
        err = np.zeros(self.nv)
        err[self._hinge_dof] = q[self._hinge_q] - self._slots(self._hinge_slot, t)
        for qadr, dof, slots in self._balls:
            target = quat_exp(self._slots(slots, t))
            err[dof : dof + 3] = quat_log(quat_mul(quat_conj(target), q[qadr : qadr + 4]))
        return err

    def __call__(self, t: float, q, qd) -> np.ndarray:
        """Generalized force ``-Kp (q - qbar(t)) - Kd qd``, (nv,) [N m]."""
        return -self.kp * self.error(t, q) - self.kd * np.asarray(qd, dtype=float)

    @classmethod
    def tuned(cls, model: Model, gait: SineGait, natural_frequency: float, damping_ratio=1.0):
        """A servo with gains from a natural frequency [rad/s] and a damping ratio (module doc)."""
        kp, kd = gains(model, natural_frequency, damping_ratio)
        return cls(model, gait, kp, kd)


class StablePD(PD):
    """The stable PD servo: as ``PD``, but the step treats it implicitly.

    ``damping`` (nv,) = Kd [N m s/rad] is the seam with ``aquagait.sim.step``:
    a policy that has it is evaluated at ``(t + dt, q + dt qd, qd)`` and its
    damping enters the mass matrix as ``M + dt Kd``.
    """

    @property
    def damping(self) -> np.ndarray:
        return self.kd


def joint_angles(model: Model, q) -> np.ndarray:
    """The actuated DOFs' positions, (na,) in ``model.actuated_dofs`` order.

    A hinge's angle [rad] (a slide's position [m]); for a ball joint the three
    components of its rotation vector [rad], the coordinates its gait drives
    (module docstring).
    """
    q = np.asarray(q, dtype=float)
    positions = np.zeros(model.nv)
    for joint in model.joints:
        if joint.kind in ("hinge", "slide"):
            positions[joint.dof] = q[joint.qpos]
        elif joint.kind == "ball":
            positions[joint.dof : joint.dof + 3] = quat_log(q[joint.qpos : joint.qpos + 4])
    return positions[model.actuated_dofs]


def gains(model: Model, natural_frequency: float, damping_ratio: float = 1.0):
    """Per-DOF PD gains ``(kp, kd)``, each (nv,), zero on the root DOFs.

    Args:
        model: the creature; its mass matrix at ``qpos0`` sets the inertia scale.
        natural_frequency: w [rad/s] of each servo about its apparent inertia.
        damping_ratio: zeta; 1 is critical damping.
    """
    if not natural_frequency > 0 or not damping_ratio >= 0:
        raise ValueError(
            f"natural_frequency must be > 0 rad/s and damping_ratio >= 0; got "
            f"{natural_frequency}, {damping_ratio}"
        )
    mass = Dynamics(model.mj).mass_matrix(model.qpos0)
    inertia = 1.0 / np.diag(np.linalg.inv(mass))
    kp, kd = np.zeros(model.nv), np.zeros(model.nv)
    dofs = model.actuated_dofs
    kp[dofs] = natural_frequency**2 * inertia[dofs]
    kd[dofs] = 2 * damping_ratio * natural_frequency * inertia[dofs]
    return kp, kd


def _check_gains(model: Model, kp, kd):
    kp = np.broadcast_to(np.asarray(kp, dtype=float), (model.nv,)).copy()
    kd = np.broadcast_to(np.asarray(kd, dtype=float), (model.nv,)).copy()
    if np.any(kp < 0) or np.any(kd < 0):
        raise ValueError("PD gains must be >= 0")
    if np.any(kp[model.root_dofs]) or np.any(kd[model.root_dofs]):
        raise ValueError(
            "PD gains must be zero on the root DOFs: the root is free, only joints are servoed"
        )
    return kp, kd
