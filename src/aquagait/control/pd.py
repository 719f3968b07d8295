"""PD servos that track a gait: explicit, and the stable (implicit) form (docs/method-bodies.md).

A servo is a policy in the sense of ``aquagait.sim``: ``policy(t, q, qd) -> tau``
(nv,) with

    tau = -Kp (q - qbar(t)) - Kd qd

on the actuated DOFs and zero on the root. ``PD`` is applied explicitly: the
step uses the force at the start of the step. ``StablePD`` also has
``implicit(dt)``, which tells the step to treat it implicitly (Tan, Liu and
Turk 2011; paper §3.2): the position error is read a fraction ``theta`` of the
way through the step and an implicit damping ``D`` joins the mass,

    (M + dt D) qdd = -c - Kp [theta e(t + dt, q + dt qd) + (1 - theta) e(t, q)] - Kd qd

How ``theta`` and ``D`` are chosen is ``StablePD(discretize=...)``
(``aquagait.control.discretization``): ``sampled``, the default, makes the
step follow the continuous servo ``I e'' + Kd e' + Kp e = 0`` sample for
sample at any dt for the DOF's nominal inertia I, so a servo's natural
frequency and damping ratio mean the same at every step; ``end_of_step`` is
the paper's form (``theta = 1, D = Kd``), kept for comparison, whose servo is
a continuous one only as dt -> 0. Both keep the servo's stiffness ``Kp`` and
its lag ``Kd / Kp`` at the gait's frequencies.

Stability, per servo mode with ``Kp = w^2 I`` and ``Kd = 2 zeta w I``
(semi-implicit Euler, linearized; Jury's criterion on the 2x2 step map), with
``x = w dt``:

    explicit PD:              x^2 + 4 zeta x < 4      (zeta = 1: x < 0.83)
    end_of_step stable PD:    3 x^2 < 4 + 4 zeta x    (zeta = 1: x < 2; large x: Kd > 1.5 Kp dt)
    sampled stable PD:        any x for zeta >= 1, for the nominal inertia and any heavier

(an underdamped ``sampled`` servo is refused at steps it cannot follow:
``aquagait.control.discretization``). The step records the force actually
applied, ``tau - dt D qdd``, and the energy ``|tau_i qd_i| dt``.

For a ball joint the gait drives the three components of a rotation vector
``r`` (``"name:x|y|z"``), the reference orientation is ``exp(r)``, and the
position error is the rotation vector of ``exp(r)^-1 q`` in the child frame
(MuJoCo's ball velocities are in that frame). An actuated DOF that the gait
does not drive is held at 0.

Gains: ``StablePD.tuned`` sets ``Kp = w^2 I``, ``Kd = 2 zeta w I`` per DOF from
a natural frequency ``w`` [rad/s] and damping ratio ``zeta``, with ``I =
1/(M^-1)_ii`` the DOF's apparent inertia at the reference pose (all other DOFs
free, ``apparent_inertia``); Kp in N m/rad, Kd in N m s/rad. The same I is the
nominal inertia ``sampled`` matches. In water a joint also moves water: its
inertia there is ``1/((M + M_a)^-1)_ii`` (``aquagait.sim.inertia``), and
``servo_figures`` says what w and zeta the same gains have about it
(``aquagait check NAME`` prints both).
"""

from __future__ import annotations

import numpy as np

from aquagait.body.dynamics import Dynamics
from aquagait.body.model import Model
from aquagait.body.rotations import quat_conj, quat_exp, quat_log, quat_mul
from aquagait.control.discretization import ServoStep, sampled
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
    """The stable PD servo: as ``PD``, but the step treats it implicitly (module docstring).

    ``implicit(dt)`` is the seam with ``aquagait.sim.step``: per DOF, the
    look-ahead theta at which the step reads the position error and the
    implicit damping D [N m s/rad] it adds to the mass as ``M + dt D``.

    Args:
        model: as ``PD``.
        gait: as ``PD``.
        kp: as ``PD``.
        kd: as ``PD``.
        inertia: (nv,) the nominal inertia each servo's step is matched for
            [kg m^2 or kg]; default ``apparent_inertia(model)`` (the one
            ``tuned`` sets the gains about). Only ``sampled`` uses it.
        discretize: ``discretize(kp, kd, inertia, dt) -> ServoStep``
            (``aquagait.control.discretization``): ``sampled`` (default) or
            ``end_of_step`` (the paper's form, before issue 49).
    """

    def __init__(self, model: Model, gait: SineGait, kp, kd, inertia=None, discretize=sampled):
        super().__init__(model, gait, kp, kd)
        self.inertia = (
            apparent_inertia(model) if inertia is None else _check_inertia(model, inertia)
        )
        self.discretize = discretize

    def implicit(self, dt: float) -> tuple[np.ndarray, np.ndarray]:
        """``(look_ahead, damping)`` for a step of ``dt`` [s], each (nv,) (``ServoStep``).

        Raises:
            ValueError: the discretization cannot take this step (``sampled``'s message).
        """
        step: ServoStep = self.discretize(self.kp, self.kd, self.inertia, dt)
        return step.look_ahead, step.damping

    @classmethod
    def tuned(cls, model: Model, gait: SineGait, natural_frequency: float, damping_ratio=1.0,
              discretize=sampled):  # fmt: skip
        """A servo with gains from a natural frequency [rad/s] and a damping ratio about each
        DOF's apparent inertia (module doc), its step chosen by ``discretize``."""
        kp, kd = gains(model, natural_frequency, damping_ratio)
        return cls(model, gait, kp, kd, discretize=discretize)


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


def apparent_inertia(model: Model) -> np.ndarray:
    """Each DOF's apparent inertia ``1/(M^-1)_ii`` at ``qpos0``, all other DOFs free, (nv,)
    [kg m^2 for a hinge, kg for a slide]: the inertia a servo on that DOF drives in a vacuum."""
    mass = Dynamics(model.mj).mass_matrix(model.qpos0)
    return 1.0 / np.diag(np.linalg.inv(mass))


def gains(model: Model, natural_frequency: float, damping_ratio: float = 1.0):
    """Per-DOF PD gains ``(kp, kd)``, each (nv,), zero on the root DOFs.

    Args:
        model: the creature; its mass matrix at ``qpos0`` sets the inertia scale
            (``apparent_inertia``).
        natural_frequency: w [rad/s] of each servo about its apparent inertia.
        damping_ratio: zeta; 1 is critical damping.
    """
    if not natural_frequency > 0 or not damping_ratio >= 0:
        raise ValueError(
            f"natural_frequency must be > 0 rad/s and damping_ratio >= 0; got "
            f"{natural_frequency}, {damping_ratio}"
        )
    inertia = apparent_inertia(model)
    kp, kd = np.zeros(model.nv), np.zeros(model.nv)
    dofs = model.actuated_dofs
    kp[dofs] = natural_frequency**2 * inertia[dofs]
    kd[dofs] = 2 * damping_ratio * natural_frequency * inertia[dofs]
    return kp, kd


def servo_figures(kp, kd, inertia) -> tuple[np.ndarray, np.ndarray]:
    """The natural frequency [rad/s] and damping ratio of servos with gains ``kp``, ``kd``
    about ``inertia`` (each (n,)): ``w = sqrt(Kp / I)``, ``zeta = Kd / (2 sqrt(Kp I))``;
    ``gains`` inverted, for any inertia (in water: ``aquagait.sim.inertia``). NaN where
    ``Kp = 0``."""
    kp, kd, inertia = (np.asarray(x, dtype=float) for x in (kp, kd, inertia))
    with np.errstate(divide="ignore", invalid="ignore"):
        w = np.where(kp > 0, np.sqrt(kp / inertia), np.nan)
        zeta = np.where(kp > 0, kd / (2 * np.sqrt(kp * inertia)), np.nan)
    return w, zeta


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


def _check_inertia(model: Model, inertia) -> np.ndarray:
    inertia = np.broadcast_to(np.asarray(inertia, dtype=float), (model.nv,)).copy()
    dofs = model.actuated_dofs
    if not np.all(np.isfinite(inertia[dofs]) & (inertia[dofs] > 0)):
        raise ValueError(
            f"a servo's nominal inertia must be > 0 on every actuated DOF; got "
            f"{inertia[dofs].tolist()}"
        )
    return inertia
