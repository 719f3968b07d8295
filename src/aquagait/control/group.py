"""One policy for a group of creatures: each member's own, on its own slice (docs/schools.md).

A group is one composed model (``aquagait.body.group``); the step asks one
policy for the group's force. ``GroupPolicy`` asks each member's policy
(any of ``aquagait.sim.servo``'s kinds, or None: no force) for its own, at
its own positions and velocities, and puts each where the member's DOFs lie
in the group's. A servo's implicit terms are the members' side by side; a
member with an explicit policy reads, in the servo's blend, as one that
looks nowhere ahead (``look_ahead = 0``, no damping), which the step
evaluates at the start of the step, exactly as it would alone.
"""

from __future__ import annotations

import numpy as np

from aquagait.body.group import Group
from aquagait.sim.servo import implicit_terms

__all__ = ["GroupPolicy"]


class GroupPolicy:
    """The group's policy, ``policy(t, q, qd) -> tau`` (nv,), from one policy per member.

    Args:
        group: the group.
        policies: one per member, in order: ``policy(t, q_i, qd_i) -> tau_i`` on the
            member's own positions and velocities, or None (no force).
    """

    def __init__(self, group: Group, policies):
        policies = tuple(policies)
        if len(policies) != len(group.members):
            raise ValueError(
                f"the group has {len(group.members)} creatures but {len(policies)} policies "
                "were given: one per creature, in order (None for no force)"
            )
        self.group, self.policies = group, policies

    def __call__(self, t: float, q, qd) -> np.ndarray:
        tau = np.zeros(self.group.model.nv)
        for member, policy in zip(self.group.members, self.policies, strict=True):
            if policy is not None:
                tau[member.dofs] = policy(t, q[member.qpos], qd[member.dofs])
        return tau

    def implicit(self, dt: float) -> tuple[np.ndarray, np.ndarray]:
        """Each member's ``(look_ahead, damping)`` side by side (module doc)."""
        nv = self.group.model.nv
        look_ahead, damping = np.zeros(nv), np.zeros(nv)
        for member, policy in zip(self.group.members, self.policies, strict=True):
            if policy is None:
                continue
            ahead, damp = implicit_terms(policy, dt, member.model.nv)
            if ahead is not None:
                look_ahead[member.dofs], damping[member.dofs] = ahead, damp
        return look_ahead, damping
