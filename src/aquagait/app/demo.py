"""The main job, ``aquagait demo``: a gait found from scratch, then swum and filmed.

CMA-ES optimizes the eel's gait on a coarse grid (the ranking of samples is
what the search needs, and a coarse grid gives it several times faster),
then the best gait swims four cycles on the eel's default grid. Last, the
fish swims two cycles of its shipped gait in 3D, filmed in 3D
(``aquagait.viz.volume``: the shaded fish and its wake as particle traces).
"""

from __future__ import annotations

from aquagait.app.optimize import OptimizationSetup, prepare_optimization
from aquagait.app.swim import SwimSetup, prepare_swim

CREATURE = "eel2d"

GRID = ((64, 32), 0.02)
"""The search grid: cells and cell size [m]."""

SWIM_SECONDS = 4.0
"""Seconds the best gait swims on the default grid (four cycles)."""


def prepare_demo(generations: int = 20, seed: int = 0) -> OptimizationSetup:
    """The demo's optimization: eel2d on the coarse grid (see ``prepare_optimization``)."""
    resolution, cell_size = GRID
    return prepare_optimization(
        CREATURE, generations=generations, seed=seed, resolution=resolution, cell_size=cell_size
    )


CREATURE_3D = "fish"
SWIM_SECONDS_3D = 2.0
"""Seconds the 3D creature swims its shipped gait on its default grid (two cycles)."""


def prepare_demo_3d() -> SwimSetup:
    """The demo's 3D swim: the fish's shipped gait on its default grid."""
    return prepare_swim(CREATURE_3D, seconds=SWIM_SECONDS_3D)
