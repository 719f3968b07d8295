"""The simple fluid's force: quadratic drag on every surface patch (paper §7).

docs/compare-fluids.md compares it with the Euler fluid.

No grid and no flow: the water is at rest, and a patch of area ``A`` with
outward normal ``n`` whose centre moves at ``v`` (the link's rigid velocity
there) feels, where it moves into the water (``v_n = v . n > 0``),

    f = -k rho A v_n^2 n          (= -k rho A |v_n| v_n n)

and nothing where it moves away (the wake side). The generalized force is
``sum_i J_i^T f_i`` with ``J_i`` the Jacobian of patch centre ``i``
(``Dynamics.point_jacobians``).

The coefficient ``k``: a flat plate moving broadside meets the textbook
pressure drag ``f = 1/2 Cd rho A v^2`` with ``Cd ~ 2`` (a long plate normal to
the flow at high Reynolds number; Hoerner, *Fluid-Dynamic Drag*, 1965), so
``k = Cd / 2 = 1``. It is an upper value: a square plate has ``Cd ~ 1.2``
(``k ~ 0.6``), and a surface in the shadow of another gets the same force as
one in the open. Nothing here is tangential: a plate sliding along itself
feels no force (no skin friction).

This module joins the body's geometry (``aquagait.body.surface``) with the
fluid's density; it sits at the coupling layer (docs/development.md) and never
imports the grid fluid.
"""

from __future__ import annotations

import numpy as np

from aquagait.body.dynamics import Dynamics
from aquagait.body.surface import Surface, surface_world

DRAG_COEFFICIENT = 1.0
"""``k`` in ``f = -k rho A v_n^2 n``: a broadside flat plate's ``Cd / 2`` with ``Cd ~ 2``."""


def patch_forces(
    surface: Surface, dynamics: Dynamics, q, qd, density: float, k: float = DRAG_COEFFICIENT
) -> tuple[np.ndarray, np.ndarray]:
    """The drag on every patch at ``(q, qd)``: world centres (m, 3) [m] and forces (m, 3) [N].

    Args:
        surface: the body's patches (``body_surface``).
        dynamics: the body's dynamics (link poses and point velocities).
        q: (nq,) positions; qd: (nv,) velocities.
        density: fluid density rho [kg/m^3].
        k: drag coefficient (module docstring).
    Returns:
        patch centres and ``f_i = -k rho A_i max(v_n, 0)^2 n_i``.
    """
    centre, normal = surface_world(surface, *dynamics.link_poses(q))
    velocity = dynamics.point_velocities(q, qd, centre, surface.link)
    into_water = np.maximum(np.einsum("mi,mi->m", velocity, normal), 0.0)
    force = -(k * density * surface.area * into_water**2)[:, None] * normal
    return centre, force


def drag_force(
    surface: Surface, dynamics: Dynamics, q, qd, density: float, k: float = DRAG_COEFFICIENT
) -> np.ndarray:
    """The simple fluid's generalized force on the body, (nv,) [N, N m] (module docstring).

    Args: as for ``patch_forces``.
    Returns:
        ``sum_i J_i^T f_i`` over the patches. With ``J_i = Jp_k - [r_i]x Jr_k``
        (``Dynamics.point_jacobians``) this is summed per link ``k`` as its
        force ``F_k = sum f_i`` and torque about its origin
        ``T_k = sum r_i x f_i``: ``sum_k Jp_k^T F_k + Jr_k^T T_k``, the same
        number without an (m, 3, nv) array (a third of the cost for the fish).
    """
    centre, force = patch_forces(surface, dynamics, q, qd, density, k)
    link_pos, _ = dynamics.link_poses(q)
    torque = np.cross(centre - link_pos[surface.link], force)
    jacp, jacr = dynamics.link_jacobians(q)
    link_force = _per_link(surface.link, force, len(jacp))
    link_torque = _per_link(surface.link, torque, len(jacr))
    return np.einsum("ki,kij->j", link_force, jacp) + np.einsum("ki,kij->j", link_torque, jacr)


def _per_link(link: np.ndarray, values: np.ndarray, nlinks: int) -> np.ndarray:
    """Sum (m, 3) patch values into (nlinks, 3) per-link totals."""
    return np.stack([np.bincount(link, values[:, i], nlinks) for i in range(3)], axis=1)
