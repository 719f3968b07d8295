"""3D swim pictures: the fish where the camera says, traces where the water turns, nowhere else."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.body.geometry import body_boxes
from aquagait.sim import FluidFrames, Trajectory
from aquagait.viz.camera import project
from aquagait.viz.gl import RenderUnavailable
from aquagait.viz.volume import Look3D, _cameras, volume_pictures

H, SHAPE, FRAMES = 0.01, (40, 20, 20), 8
WIDTH, HEIGHT = 192, 144
SWIRL_AT, CORE = np.array([-0.1, 0.0, 0.0]), 0.02  # a vortex behind the fish, fixed in the world


def swirl(points):
    """Velocity (..., 3) of a blob of water spinning about z at 5 rad/s, a Gaussian of radius
    ``CORE`` about ``SWIRL_AT``: still water a few cores away, vorticity only within them."""
    r = points - SWIRL_AT
    fade = np.exp(-(r**2).sum(-1) / CORE**2)[..., None]
    return 5.0 * np.stack([-r[..., 1], r[..., 0], 0 * r[..., 2]], -1) * fade


@pytest.fixture(scope="module")
def gliding():
    """The fish gliding along +x at 0.1 m/s past the vortex, the lattice following it."""
    fish = ag.creatures.get("fish").model
    time = np.arange(FRAMES) / 30
    qpos = np.tile(fish.qpos0, (FRAMES, 1))
    qpos[:, 0] += 0.1 * time
    n = np.array(SHAPE)
    origin = np.floor((qpos[:, :3] - n * H / 2) / H) * H
    velocity = np.zeros((FRAMES, 3, *SHAPE), np.float16)
    for f in range(FRAMES):
        centres = origin[f] + (np.moveaxis(np.indices(SHAPE), 0, -1) + 0.5) * H
        velocity[f] = np.moveaxis(swirl(centres), -1, 0)
    fluid = FluidFrames(H, origin, velocity, np.zeros((FRAMES, *SHAPE), bool))
    zeros = np.zeros((FRAMES, fish.nv))
    return fish, Trajectory(time, qpos, zeros, zeros, zeros, dt=1 / 90, fps=30.0, fluid=fluid)


def pictures(fish, traj, **look):
    try:
        return list(volume_pictures(traj, fish, width=WIDTH, height=HEIGHT, **look))
    except RenderUnavailable as err:
        pytest.skip(f"no headless OpenGL here: {err}")


def test_the_fish_is_where_its_projected_box_says_and_moves_frame_to_frame(gliding):
    fish, traj = gliding
    bare = Trajectory(traj.time, traj.qpos, traj.qvel, traj.torque, traj.energy, traj.dt, traj.fps)
    drawn = pictures(fish, bare, view="side")
    cameras = _cameras(fish, bare, Look3D(view="side", width=WIDTH, height=HEIGHT))
    boxes = body_boxes(fish, bare.qpos)
    for f in (0, FRAMES - 1):
        low, high = boxes[f]
        corners = np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1])
                            for z in (low[2], high[2])])  # fmt: skip
        box = project(cameras[f], corners, WIDTH, HEIGHT)
        rows, cols = np.nonzero((drawn[f] < 250).any(axis=-1))
        assert len(rows) > 200
        assert cols.min() >= box[:, 0].min() - 1 and cols.max() <= box[:, 0].max() + 1
        assert rows.min() >= box[:, 1].min() - 1 and rows.max() <= box[:, 1].max() + 1
    assert np.abs(drawn[0].astype(int) - drawn[-1]).sum() > 0  # it moves against the camera


def test_traces_appear_where_the_water_turns_and_not_in_still_water(gliding):
    fish, traj = gliding
    look = dict(view="top", particles=3000, lifetime=100)
    with_wake = pictures(fish, traj, **look)[-1].astype(int)
    bare = Trajectory(traj.time, traj.qpos, traj.qvel, traj.torque, traj.energy, traj.dt, traj.fps)
    body_only = pictures(fish, bare, **look)[-1].astype(int)
    traced = np.abs(with_wake - body_only).sum(-1) > 30
    assert traced.sum() > 50
    camera = _cameras(fish, traj, Look3D(width=WIDTH, height=HEIGHT, **look))[-1]
    centre = project(camera, [SWIRL_AT], WIDTH, HEIGHT)[0]
    pixels_per_metre = np.linalg.norm(project(camera, [SWIRL_AT + [0.01, 0, 0]], WIDTH, HEIGHT)[0]
                                      - centre) / 0.01  # fmt: skip
    rows, cols = np.nonzero(traced)
    distance = np.hypot(cols + 0.5 - centre[0], rows + 0.5 - centre[1]) / pixels_per_metre
    assert np.percentile(distance, 95) < 3 * CORE  # the blob's vorticity: within ~2.5 cores
