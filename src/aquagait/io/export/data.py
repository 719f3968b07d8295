"""What every export writes: one swim as frames of link poses, link meshes and traces.

``swim_export(trajectory, model)`` gathers it once from a run; each format's
writer (``usd``, ``gltf``, ``vtk``, ``html``) only translates it. World
coordinates in metres, +z up (a 2D swim lies in the plane z = 0, its links
prisms of the model's depth centred on it), time in seconds from the
trajectory's first frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aquagait.body.dynamics import Dynamics, describe
from aquagait.body.meshes import LinkMesh, link_meshes
from aquagait.body.model import Model
from aquagait.body.rotations import quat_from_matrix
from aquagait.sim import FluidFrames, Trajectory
from aquagait.sim.particles import wake

TRACES = 1000
"""Particles traced for an export by default: a third of the video's, files stay small."""


@dataclass(frozen=True, eq=False)
class SwimExport:
    """One swim, ready to write in any format.

    F frames, nl links, N particle traces of L positions.

    Attributes:
        name: the creature's name.
        dim: 2 or 3 (the simulation's; the export itself is always 3D).
        fps: frames per second.
        time: (F,) seconds from the first frame [s].
        link_names: (nl,) the links' names, in MJCF order.
        link_pos: (F, nl, 3) world origin of each link's frame [m].
        link_rot: (F, nl, 3, 3) world rotation of each link's frame.
        link_quat: (F, nl, 4) the same rotations as unit quaternions (w, x, y, z),
            sign-continuous from frame to frame (no flips for interpolation).
        meshes: (nl,) each link's triangles in its own frame (``LinkMesh``).
        traces: (F, N, L, 3) float32 world positions [m], oldest first, NaN
            where a trace is younger than L frames; None without a flow.
        trace_alpha: (F, N, L) float32 opacity in [0, 1] from the vorticity
            (``aquagait.sim.particles.wake``); None without a flow.
        fluid: the recorded flow (``FluidFrames``), or None.
    """

    name: str
    dim: int
    fps: float
    time: np.ndarray
    link_names: tuple[str, ...]
    link_pos: np.ndarray
    link_rot: np.ndarray
    link_quat: np.ndarray
    meshes: list[LinkMesh]
    traces: np.ndarray | None
    trace_alpha: np.ndarray | None
    fluid: FluidFrames | None

    @property
    def frames(self) -> int:
        return len(self.time)


def swim_export(
    trajectory: Trajectory, model: Model, name: str, traces: int = TRACES, seed: int = 0
) -> SwimExport:
    """Gather a swim for export: poses per frame, meshes, and ``traces`` particle traces.

    Args:
        trajectory: the swim (``aquagait.io.read_run(dir).trajectory``).
        model: its creature.
        name: the creature's name.
        traces: particles traced (0: none); only where the trajectory has fluid frames.
        seed: the particles' placement.
    """
    dynamics = Dynamics(model.mj)
    poses = [dynamics.link_poses(q) for q in trajectory.qpos]
    link_pos = np.array([p for p, _ in poses])
    link_rot = np.array([r for _, r in poses])
    lines = alpha = None
    if trajectory.fluid is not None and traces > 0:
        frames = list(wake(trajectory, model, count=traces, seed=seed))
        lines = np.array([t for t, _, _ in frames], np.float32)
        alpha = np.array([a for _, a, _ in frames], np.float32)
        if lines.shape[-1] == 2:  # a 2D swim's traces lie in the plane z = 0
            z = np.where(np.isnan(lines[..., :1]), np.nan, 0.0).astype(np.float32)
            lines = np.concatenate([lines, z], axis=-1)
    return SwimExport(
        name=name,
        dim=model.dim,
        fps=float(trajectory.fps),
        time=np.asarray(trajectory.time, float) - trajectory.time[0],
        link_names=describe(model.mj).link_names,
        link_pos=link_pos,
        link_rot=link_rot,
        link_quat=_continuous(quat_from_matrix(link_rot)),
        meshes=link_meshes(model),
        traces=lines,
        trace_alpha=alpha,
        fluid=trajectory.fluid,
    )


def _continuous(quat: np.ndarray) -> np.ndarray:
    """Quaternions (F, nl, 4) with each frame's sign chosen nearest the previous frame's."""
    quat = quat.copy()
    for f in range(1, len(quat)):
        flip = (quat[f] * quat[f - 1]).sum(-1) < 0
        quat[f, flip] *= -1
    return quat
