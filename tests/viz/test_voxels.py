"""The voxel picture: each link's cells in its tint, its true outline in its colour, 2D and 3D."""

import imageio.v2 as imageio
import numpy as np

import aquagait as ag
from aquagait.body.dynamics import Dynamics
from aquagait.body.shape import body_shape
from aquagait.body.voxelize import voxelize
from aquagait.grid import Grid
from aquagait.viz import plot_voxels
from aquagait.viz.voxels import _colours, _tint

BALL_AND_TAIL = """<mujoco><worldbody><body name="ball"><freejoint/>
    <geom type="sphere" size=".03" density="1000"/>
    <body name="tail" pos="-.03 0 0"><joint name="j" type="hinge" axis="0 0 1" range="-30 30"/>
      <geom type="capsule" fromto="-.01 0 0 -.07 0 0" size=".012" density="1000"/></body>
  </body></worldbody></mujoco>"""


def draw(mjcf, shape, path):
    """Voxelize a model at its reference pose on a grid centred on the origin and draw it."""
    model = ag.load_model(mjcf)
    h = 0.01
    grid = Grid(shape, cell_size=h, origin=tuple(-0.5 * h * np.asarray(shape)))
    pos, rot = Dynamics(model.mj).link_poses(model.qpos0)
    voxels = voxelize(body_shape(model, h), grid, pos, rot)
    fine = body_shape(model, h, refine=16)  # outlines of parts thinner than h / 4
    plot_voxels(fine, grid, voxels, pos, rot, path, title="test")
    panels = imageio.imread(path)[:-60, :, :3]  # the legend (tinted patches) is at the bottom
    return panels.astype(float) / 255, voxels


def pixels_of(picture, colour) -> int:
    return int(np.count_nonzero(np.abs(picture - colour).max(axis=-1) < 2.5 / 255))


def test_cells_are_tinted_per_link_and_an_unresolved_plate_is_an_outline_only(tmp_path, fin_plate):
    picture, voxels = draw(fin_plate, (40, 20), tmp_path / "plate.png")
    block, fin = _colours(2)
    assert np.count_nonzero(voxels.owner == 0) == 40 and np.count_nonzero(voxels.owner == 1) == 0
    assert pixels_of(picture, _tint(block)) > 1000
    assert pixels_of(picture, _tint(fin)) == 0  # no cells: no tint
    assert pixels_of(picture, fin) > 20  # but its outline is drawn


def test_a_3d_body_is_drawn_in_slices(tmp_path):
    picture, voxels = draw(BALL_AND_TAIL, (24, 16, 16), tmp_path / "ball.png")
    for k, colour in enumerate(_colours(2)):
        assert np.count_nonzero(voxels.owner == k) > 0
        assert pixels_of(picture, _tint(colour)) > 200
        assert pixels_of(picture, colour) > 20
