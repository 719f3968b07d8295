"""Library creatures drawn as animals: visual-only geoms change none of their physics.

A creature whose fluid shape is a thickened stand-in (the manta's 45 mm
plates, the turtle's 120 mm flippers, the frog's 7 mm web, the alien's 8 mm
wings) carries a visual body: massless geoms of class ``visual`` beside the
massive ones (``aquagait.body.reshape``). Loaded with them or with them cut
out of its file, it must be the same creature to the last bit that matters:
masses, inertias, the fluid's shape, the voxels on its default grid.
"""

import re
from pathlib import Path

import numpy as np
import pytest

from aquagait import creatures
from aquagait.body import Dynamics, load_model
from aquagait.body.shape import body_shape
from aquagait.body.surface import body_surface
from aquagait.body.voxelize import voxelize
from aquagait.grid import Grid

LIBRARY = Path(creatures.__file__).parent
VISUAL = re.compile(r'\s*<geom [^>]*class="visual"[^>]*/>')
DRAWN = {"alien", "frog", "manta", "turtle3d"}
"""The creatures with a visual body: those whose plates are thickened to the grid's cells."""


@pytest.fixture(scope="module", params=creatures.names())
def pair(request):
    """A library creature as shipped, and the model of its file without the visual geoms."""
    creature = creatures.get(request.param)
    text = (LIBRARY / f"{request.param}.xml").read_text()
    return creature, load_model(VISUAL.sub("", text))


def test_the_creatures_with_thickened_plates_have_a_visual_body(pair):
    creature, bare = pair
    text = (LIBRARY / f"{creature.name}.xml").read_text()
    looks = [v for link in creature.model.visuals for v in link]
    assert bool(looks) == (creature.name in DRAWN) == bool(VISUAL.search(text))
    assert len(looks) == len(VISUAL.findall(text))
    assert all(link == () for link in bare.visuals)
    header = text[: text.index("-->")]
    assert ("Visual geoms" in header) == (creature.name in DRAWN)


def test_masses_and_inertias_are_those_without_the_visual_body(pair):
    creature, bare = pair
    model = creature.model
    np.testing.assert_array_equal(model.link_mass, bare.link_mass)
    np.testing.assert_allclose(model.mj.body_inertia, bare.mj.body_inertia, rtol=1e-12)
    np.testing.assert_allclose(model.mj.body_ipos, bare.mj.body_ipos, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(np.abs(model.mj.body_iquat @ bare.mj.body_iquat.T).diagonal(), 1,
                               rtol=1e-12)  # fmt: skip
    np.testing.assert_array_equal(model.bounds, bare.bounds)


def test_the_fluid_sees_the_same_solid_on_the_default_grid(pair):
    creature, bare = pair
    model, h = creature.model, creature.cell_size
    shapes = body_shape(model, h), body_shape(bare, h)
    np.testing.assert_array_equal(shapes[0].sdf, shapes[1].sdf)
    dynamics = Dynamics(model.mj)
    centre = dynamics.center_of_mass(model.qpos0)[: model.dim]
    size = np.asarray(creature.resolution) * h
    grid = Grid(creature.resolution, h, tuple(centre - size / 2))
    pos, rot = dynamics.link_poses(model.qpos0)
    cells = [voxelize(shape, grid, pos, rot) for shape in shapes]
    assert cells[0].solid.sum() > 0
    np.testing.assert_array_equal(cells[0].owner, cells[1].owner)
    np.testing.assert_array_equal(cells[0].face_index, cells[1].face_index)
    patches = body_surface(model), body_surface(bare)
    np.testing.assert_array_equal(patches[0].centre, patches[1].centre)
    np.testing.assert_array_equal(patches[0].area, patches[1].area)
