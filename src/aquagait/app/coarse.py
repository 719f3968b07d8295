"""The coarse grid of a coarse-to-fine search (docs/optimize.md; ``Problem.refine``).

Samples are ranked on a grid ``factor`` times coarser (in 3D, ``factor^3``
fewer cells, and the CFL step grows with h), and the best of every
generation are swum again on the target grid. The coarse grid spans at least
the same water, and keeps the same metres of clearance between the body and
the walls (``CLEARANCE / factor`` coarse cells): keeping 8 coarse cells made
the fish's coarse grid 36x26x30 instead of 32x16x18, only 2x cheaper to swim
than the target grid. A link thinner than about two coarse cells is resolved
only by the sub-cell boundary's fractions, so the coarse swim may rank gaits
unlike the fine one: that is said in a note.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from aquagait.body.shape import body_shape, link_thickness
from aquagait.creatures import Creature
from aquagait.creatures.creature import smallest_grid
from aquagait.creatures.defaults import ROOM
from aquagait.sim import CLEARANCE, EulerFluid, make_scene

THIN_CELLS = 2.0
"""Below this many coarse cells a link's thickness earns a note."""


@dataclass(frozen=True)
class CoarseGrid:
    """A coarse grid: ``resolution`` cells of ``cell_size`` [m], the ``clearance`` its
    swims keep [cells], and what to know about it."""

    resolution: tuple[int, ...]
    cell_size: float
    clearance: float
    notes: tuple[str, ...] = ()


def coarse_grid(creature: Creature, resolution, cell_size: float, factor: float) -> CoarseGrid:
    """The grid ``factor`` (> 1) times coarser than ``resolution`` x ``cell_size``.

    Each axis keeps at least the target grid's extent and holds the creature,
    centred on its centre of mass, with as much water on every side as the
    target grid's ``CLEARANCE`` cells and ``ROOM`` cells more for the body to
    sweep as it swims (a grid just holding the straight eel loses every sample
    when its tail swings).
    """
    if not (np.isfinite(factor) and factor > 1):
        raise ValueError(f"the coarse grid's factor must be a number > 1, got {factor!r}")
    h = float(cell_size) * factor
    clearance = CLEARANCE / factor
    body = smallest_grid(creature.model, h, clearance + ROOM / factor)
    coarse = tuple(
        _even(max(math.ceil(n / factor), m)) for n, m in zip(resolution, body, strict=True)
    )
    make_scene(creature, coarse, h, fluid=EulerFluid(clearance=clearance))  # raises if too small
    return CoarseGrid(coarse, h, clearance, _thin_notes(creature, h))


def _even(n: int) -> int:
    """``n`` rounded up to an even number of cells (the multigrid halves them)."""
    return n + n % 2


def _thin_notes(creature: Creature, h: float) -> tuple[str, ...]:
    thickness = link_thickness(body_shape(creature.model, h))
    thin = [k for k, t in enumerate(thickness) if 0 < t < THIN_CELLS * h]
    if not thin:
        return ()
    k = min(thin, key=lambda k: thickness[k])
    return (
        f"{len(thin)} of {len(thickness)} links are under {THIN_CELLS:g} coarse cells thick "
        f"(thinnest: {creature.model.links[k]!r}, {thickness[k] * 1000:.3g} mm = "
        f"{thickness[k] / h:.2f} cells of {h * 1000:.3g} mm): the coarse swims may rank "
        "gaits unlike the target grid's",
    )
