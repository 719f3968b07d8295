"""The inertia each DOF has in its fluid: ``1/((M + M_a)^-1)_ii``, measured by one step each.

A servo on a joint drives the joint's links and, in water, the water they
push: at rest that water acts as an added mass ``M_a`` (nv x nv; potential
flow, docs/method-coupling.md), so the joint's apparent inertia, all other
DOFs free, is ``1/((M + M_a)^-1)_ii`` rather than the vacuum's
``1/(M^-1)_ii``. The coupled solve conserves the momentum of fluid plus body
(``aquagait.coupling``): a generalized impulse ``j e_i`` given to the body
at rest in still water leaves it moving at ``j (M + M_a)^-1 e_i``, the water
around it carrying the rest. So one step from rest per DOF, under a force
``j e_i / dt`` applied over it, measures column i of ``(M + M_a)^-1``, on the
scene's own grid, voxels and coupling: the added mass the simulation gives
the body, not potential-flow theory's. In a ``Vacuum`` (or the simple
fluid, whose drag vanishes at rest) it is ``1/(M^-1)_ii``.
"""

from __future__ import annotations

import numpy as np

from aquagait.sim.rollout import step
from aquagait.sim.scene import Scene, init_state

IMPULSE_TIME = 1e-3
"""The step [s] that carries the impulse; the result does not depend on it
(the pressure scales as 1/dt), it only sets how far the body moves meanwhile."""


def inertia_in_fluid(scene: Scene, qpos=None, dofs=None) -> np.ndarray:
    """Each DOF's apparent inertia in the scene's fluid, ``1/((M + M_a)^-1)_ii``.

    Args:
        scene: the scene; its fluid gives ``M_a`` (none in a ``Vacuum``).
        qpos: (nq,) the pose [m, quaternion, rad]; default the model's reference pose.
        dofs: the DOF indices to measure; default every DOF (one step each).
    Returns:
        (len(dofs),) inertia [kg m^2 for a hinge, kg for a slide], in ``dofs`` order.
    """
    model = scene.model
    state = init_state(scene, qpos=qpos)
    dofs = np.arange(model.nv) if dofs is None else np.asarray(dofs, dtype=int)
    vacuum = 1.0 / np.diag(np.linalg.inv(scene.dynamics.mass_matrix(state.qpos)))
    inertia = np.empty(len(dofs))
    for n, i in enumerate(dofs):
        impulse = np.zeros(model.nv)
        impulse[i] = vacuum[i] * 1.0  # moves the DOF at about 1 rad/s (1 m/s), vacuum or less
        moved = step(scene, state, IMPULSE_TIME, _Impulse(impulse / IMPULSE_TIME))
        inertia[n] = impulse[i] / moved.qvel[i]
    return inertia


class _Impulse:
    """An explicit policy: the constant generalized force ``force`` (nv,) [N or N m]."""

    def __init__(self, force: np.ndarray):
        self.force = force

    def __call__(self, t, q, qd) -> np.ndarray:
        return self.force
