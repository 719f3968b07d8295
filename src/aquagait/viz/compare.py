"""Pictures of one gait in two fluids: root displacement over time, and a side-by-side video.

    plot_displacement(runs, "runs/compare/displacement.png")
    render_side_by_side(runs, model, "runs/compare/compare.mp4")

``runs`` maps a fluid's name to a swim (anything with a ``trajectory``), as
``aquagait.app.compare.swim_both`` returns. matplotlib and imageio are imported
inside the functions (the ``viz`` extra).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from aquagait.viz.style import save_plot
from aquagait.viz.swim import swim_frames


def plot_displacement(runs: dict, path, title: str = "") -> Path:
    """Root displacement along x [m] against time [s], one line per fluid."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axis = plt.subplots(figsize=(6, 3.5))
    for fluid, run in runs.items():
        traj = run.trajectory
        axis.plot(traj.time, traj.qpos[:, 0] - traj.qpos[0, 0], label=f"{fluid} fluid")
    axis.axhline(0.0, color="0.7", linewidth=0.8)
    axis.set_xlabel("time [s]")
    axis.set_ylabel("root displacement along x [m]")
    axis.set_title(title)
    axis.legend(frameon=False)
    return save_plot(fig, path)


def render_side_by_side(runs: dict, model, path, progress=None) -> Path:
    """One video, the fluids' swims side by side (each as ``render_swim`` draws it)."""
    import imageio.v2 as imageio

    streams = [swim_frames(run.trajectory, model) for run in runs.values()]
    total = min(len(run.trajectory.time) for run in runs.values())
    fps = next(iter(runs.values())).trajectory.fps
    path = Path(path)
    with imageio.get_writer(path, fps=fps, macro_block_size=1) as writer:
        for done, frames in enumerate(zip(*streams, strict=False), start=1):
            height = max(f.shape[0] for f in frames)
            padded = [np.pad(f, ((0, height - f.shape[0]), (0, 0), (0, 0)), constant_values=255)
                      for f in frames]  # fmt: skip
            writer.append_data(np.hstack(padded))
            if progress is not None:
                progress(done, total)
    return path
