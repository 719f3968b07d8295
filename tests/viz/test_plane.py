"""2D swim pictures and the video they go to: synthetic flows written and read back."""

import imageio.v2 as imageio
import numpy as np
import pytest

import aquagait as ag
from aquagait.body.geometry import geom_points
from aquagait.sim import FluidFrames, Trajectory
from aquagait.viz import render_swim, swim_frames


def vortex_pair(points, behind, size):
    """Velocity (..., 2) of a counter-clockwise vortex above ``behind`` and a clockwise one below.

    Lamb-Oseen vortices ``0.3 size`` apart with cores of ``0.1 size``, swirling at about 0.1 m/s.
    """
    gap, core = 0.3 * size, 0.1 * size
    strength = 2 * np.pi * core * 0.1
    total = np.zeros(points.shape)
    for sign in (1, -1):
        r = points - (behind + [0, sign * gap / 2])
        r2 = (r**2).sum(-1, keepdims=True) + 1e-12
        swirl = sign * strength / (2 * np.pi * r2) * (1 - np.exp(-r2 / core**2))
        total += swirl * np.stack([-r[..., 1], r[..., 0]], -1)
    return total


def gliding(name, frames, shape, cell_size, speed):
    """A creature gliding along +x, its wake a vortex pair, the grid following it by whole cells."""
    creature = ag.creatures.get(name)
    model = creature.model
    time = np.arange(frames) / 30
    qpos = np.tile(model.qpos0, (frames, 1))
    qpos[:, 0] += speed * time
    n = np.array(shape)
    rear = geom_points(model, world=True)[1][:, 0].min()
    length = model.body_length
    origin = np.floor((np.outer(speed * time, [1, 0]) - n * cell_size / 2) / cell_size) * cell_size
    velocity = np.zeros((frames, 2, *shape))
    solid = np.zeros((frames, *shape), bool)
    for f in range(frames):
        centres = origin[f] + (np.moveaxis(np.indices(shape), 0, -1) + 0.5) * cell_size
        tail = np.array([rear + speed * time[f], 0.0])
        velocity[f] = np.moveaxis(vortex_pair(centres, tail - [0.3 * length, 0], length), -1, 0)
        along = (centres[..., 0] - tail[0]) / length
        solid[f] = (along > 0) & (along < 1) & (np.abs(centres[..., 1]) < 0.04 * length)
    fluid = FluidFrames(cell_size=cell_size, origin=origin, velocity=velocity, solid=solid)
    zeros = np.zeros((frames, model.nv))
    return model, Trajectory(time, qpos, zeros, zeros, zeros, dt=1 / 300, fps=30.0, fluid=fluid)


def test_a_video_has_one_picture_per_frame(tmp_path):
    shape = (48, 24)
    model, traj = gliding("eel2d", 3, shape, 0.02, speed=0.1)
    path = render_swim(traj, model, tmp_path / "out" / "swim.mp4", pixels_per_cell=4)
    assert path.is_file()
    with imageio.get_reader(path) as video:
        assert video.count_frames() == 3
        assert video.get_data(0).shape == (shape[1] * 4, shape[0] * 4, 3)


def test_pictures_show_the_vortices_in_their_colours_and_the_body():
    model, traj = gliding("eel2d", 8, (64, 32), 0.02, speed=0.2)
    pictures = list(swim_frames(traj, model, pixels_per_cell=4))
    last = pictures[-1].astype(int)
    r, g, b = last[..., 0], last[..., 1], last[..., 2]
    red = (r > b + 60) & (r > g + 60)
    blue = (b > r + 60) & (b > g + 20)
    dark = last.sum(-1) < 200
    assert red.sum() > 20 and blue.sum() > 20 and dark.sum() > 200
    rows = np.flatnonzero(red.any(axis=1)).mean(), np.flatnonzero(blue.any(axis=1)).mean()
    assert rows[0] < rows[1]  # image rows run downwards: the counter-clockwise vortex is on top


def test_a_vacuum_swim_shows_the_body_alone(tmp_path):
    model, traj = gliding("eel2d", 3, (16, 8), 0.05, speed=0.2)
    bare = Trajectory(traj.time, traj.qpos, traj.qvel, traj.torque, traj.energy, traj.dt, traj.fps)
    path = render_swim(bare, model, tmp_path / "swim.mp4")
    with imageio.get_reader(path) as video:
        assert video.count_frames() == 3
    with pytest.raises(ValueError, match="needs the model"):
        swim_frames(bare, None)


def test_importing_viz_needs_no_extra():
    import subprocess
    import sys

    code = (
        "import sys, aquagait.viz; assert 'matplotlib' not in sys.modules, 'matplotlib'; "
        "assert 'imageio' not in sys.modules, 'imageio'"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
