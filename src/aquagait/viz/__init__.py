"""Pictures and videos of swims (docs/pictures.md); the ``viz`` extra.

    from aquagait.viz import render_swim
    render_swim(trajectory, creature.model, "runs/eel2d/swim.mp4")

Reads Trajectory only; matplotlib, imageio and moderngl (3D, the ``render``
extra) are imported inside the functions that draw, so importing this
package needs none of them. Only the jobs import it (docs/development.md,
"Layers").
"""

from aquagait.viz.compare import plot_displacement, render_side_by_side
from aquagait.viz.convergence import plot_budgets, plot_convergence
from aquagait.viz.plane import Look
from aquagait.viz.swim import contact_sheet, render_swim, swim_frames
from aquagait.viz.volume import Look3D
from aquagait.viz.voxels import plot_voxels

__all__ = [
    "Look",
    "Look3D",
    "contact_sheet",
    "plot_budgets",
    "plot_convergence",
    "plot_displacement",
    "plot_voxels",
    "render_side_by_side",
    "render_swim",
    "swim_frames",
]
