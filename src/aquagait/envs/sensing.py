"""Flow sensing: a lateral line of body-fixed points on the creature's flanks.

Fish feel the water along their flanks (the lateral line: pressure and the
flow past the skin). ``LateralLine`` places ``count`` sensors, half on each
flank, and reads at each the fluid's pressure [Pa] and its velocity relative
to the skin [m/s] in the creature's frame.

Where the sensors sit: on each flank, ``count / 2`` stations evenly spaced
from head to tail at the height of the centre of mass; at each, the body's
surface patch (``aquagait.body.surface``) nearest it among those that face
that flank at the rest pose (the outward normal's sideways component, along
+y for the left flank and -y for the right, at least ``FLANK``). A body
symmetric left to right gets sensors in mirror pairs. Each sensor sits
``OFFSET`` cells out from its patch along the normal, so
that it reads water rather than the body's solid cells (where the pressure is
not defined). The points are fixed in their links' frames and move with them.
The fluid's fields are sampled multilinearly between cell centres
(``aquagait.sim.particles.sample``).

In a group (``aquagait.body.group``) each creature has its own line: the
sensors are placed on the member's own body at its own rest pose, as if it
swam alone, and then read through the group's links, so a follower's line
feels the water its leader shed.
"""

from __future__ import annotations

import numpy as np

from aquagait.body.dynamics import Dynamics
from aquagait.body.surface import body_surface
from aquagait.fluid.operators import cell_centered
from aquagait.sim import Scene, State
from aquagait.sim.particles import sample

FLANK = 0.5
"""Least sideways component of a patch's outward normal (at rest) for it to carry a sensor."""

OFFSET = 1.5
"""How far a sensor sits out from its patch, in cells."""

DEFAULT_SENSORS = 16


class LateralLine:
    """``count`` body-fixed flow sensors, half on each flank (module docstring).

    Args:
        scene: the creature (facing +x at rest) in a fluid with a grid, or a group's.
        count: sensors, even, >= 2.
        member: in a group's scene, the member (``aquagait.body.group.Member``) whose
            line this is; None: the scene's one creature.

    Raises:
        ValueError: an odd or too small count, a scene without a grid, or a body with
            too few patches on a flank.
    """

    def __init__(self, scene: Scene, count: int = DEFAULT_SENSORS, member=None):
        if int(count) != count or count < 2 or count % 2:
            raise ValueError(f"sensors must be an even whole number >= 2, got {count!r}")
        if scene.grid is None:
            raise ValueError("flow sensing needs a fluid grid: fluid='euler'")
        cell_size = scene.grid.cell_size
        model, dynamics, first = scene.model, scene.dynamics, 0
        if member is not None:  # placed on the member alone, read through the group's links
            model, dynamics, first = member.model, Dynamics(member.model.mj), member.links.start
        surface = body_surface(model)
        rest_pos, rest_rot = dynamics.link_poses(model.qpos0)
        rot = rest_rot[surface.link]
        centre = rest_pos[surface.link] + np.einsum("mij,mj->mi", rot, surface.centre)
        normal = np.einsum("mij,mj->mi", rot, surface.normal)
        middle = dynamics.center_of_mass(model.qpos0)[2]
        links, points = [], []
        for side in (1.0, -1.0):  # left (+y), then right
            flank = np.flatnonzero(side * normal[:, 1] >= FLANK)
            if len(flank) < count // 2:
                raise ValueError(
                    f"{model.source}: only {len(flank)} surface patches face its "
                    f"{'left' if side > 0 else 'right'} flank at rest, too few for "
                    f"{count // 2} sensors a side: ask for fewer sensors"
                )
            head, tail = centre[flank, 0].max(), centre[flank, 0].min()
            stations = np.linspace(head, tail, count // 2)
            off = np.hypot(centre[flank, 0][None] - stations[:, None],
                           centre[flank, 2][None] - middle)  # fmt: skip
            # the nearest; of two as near (above and below the middle), the upper one
            rise = -centre[flank, 2]
            chosen = flank[[np.lexsort((rise, np.round(row, 9)))[0] for row in off]]
            local = surface.centre[chosen] + OFFSET * cell_size * surface.normal[chosen]
            links.append(surface.link[chosen])
            points.append(local)
        self.link = np.concatenate(links) + first
        self.local = np.concatenate(points)
        self.dim = model.dim

    @property
    def count(self) -> int:
        return len(self.link)

    @property
    def names(self) -> tuple[str, ...]:
        axes = "xyz"[: self.dim]
        half = self.count // 2
        labels = [f"{side}{k}" for side in ("left", "right") for k in range(half)]
        return tuple(f"pressure:{s}" for s in labels) + tuple(
            f"flow:{s}:{a}" for s in labels for a in axes
        )

    def world(self, scene: Scene, q) -> np.ndarray:
        """The sensors' world positions at ``q``, (count, 3) [m]."""
        pos, rot = scene.dynamics.link_poses(q)
        return pos[self.link] + np.einsum("mij,mj->mi", rot[self.link], self.local)

    def read(self, scene: Scene, state: State, frame: np.ndarray) -> np.ndarray:
        """Pressure at each sensor [Pa], then the water's velocity past each [m/s] in the
        creature's ``frame`` (3, 3): ``count * (1 + dim)`` numbers, in ``names`` order."""
        if state.velocity is None:
            raise ValueError("flow sensing needs a fluid with a flow: fluid='euler'")
        grid = state.grid
        points = self.world(scene, state.qpos)
        at = points[:, : self.dim]
        pressure = sample(state.pressure, grid.origin, grid.cell_size, at)
        flow = sample(cell_centered(grid, state.velocity), grid.origin, grid.cell_size, at).T
        skin = scene.dynamics.point_velocities(state.qpos, state.qvel, points, self.link)
        past = np.zeros((self.count, 3))
        past[:, : self.dim] = flow - skin[:, : self.dim]
        local = (past @ frame)[:, : self.dim]  # frame^T v, row by row
        return np.concatenate([pressure, local.ravel()])
