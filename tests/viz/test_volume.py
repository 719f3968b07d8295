"""3D swim pictures: the fish where the camera says, traces where the water turns, nowhere else."""

import sys

import numpy as np
import pytest

import aquagait as ag
from aquagait.body.geometry import body_boxes
from aquagait.sim import FluidFrames, Trajectory
from aquagait.sim.vortices import q_level
from aquagait.viz.camera import VIEWS, project
from aquagait.viz.gl import RenderUnavailable
from aquagait.viz.volume import BODY_SHARE, Look3D, _cameras, volume_pictures, vortex_surfaces

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
        return list(volume_pictures(traj, fish, **{"width": WIDTH, "height": HEIGHT, **look}))
    except RenderUnavailable as err:
        pytest.skip(f"no headless OpenGL here: {err}")


def test_the_fish_is_where_its_projected_box_says_and_moves_frame_to_frame(gliding):
    fish, traj = gliding
    bare = Trajectory(traj.time, traj.qpos, traj.qvel, traj.torque, traj.energy, traj.dt, traj.fps)
    drawn = pictures(fish, bare, view="side", ground=False)
    cameras, _ = _cameras(fish, bare, Look3D(view="side", width=WIDTH, height=HEIGHT))
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
    look = dict(view="top", particles=3000, lifetime=100, wake="traces", legend=False)
    with_wake = pictures(fish, traj, **look)[-1].astype(int)
    bare = Trajectory(traj.time, traj.qpos, traj.qvel, traj.torque, traj.energy, traj.dt, traj.fps)
    body_only = pictures(fish, bare, **look)[-1].astype(int)
    traced = np.abs(with_wake - body_only).sum(-1) > 30
    assert traced.sum() > 50
    camera = _cameras(fish, traj, Look3D(width=WIDTH, height=HEIGHT, **look))[0][-1]
    centre = project(camera, [SWIRL_AT], WIDTH, HEIGHT)[0]
    pixels_per_metre = np.linalg.norm(project(camera, [SWIRL_AT + [0.01, 0, 0]], WIDTH, HEIGHT)[0]
                                      - centre) / 0.01  # fmt: skip
    rows, cols = np.nonzero(traced)
    distance = np.hypot(cols + 0.5 - centre[0], rows + 0.5 - centre[1]) / pixels_per_metre
    assert np.percentile(distance, 95) < 3 * CORE  # the blob's vorticity: within ~2.5 cores


def ring_flow(radius, core, n, h, circulation=0.01, segments=256):
    """A vortex ring of ``radius`` about +z in the plane z = 0, its core a Rosenhead-Moore
    blob of ``core`` [m]: the velocity at the cell centres of an n^3 lattice centred on it
    (Biot-Savart over ``segments`` pieces of the ring); (3, n, n, n) and the lattice's origin."""
    origin = -np.full(3, n * h / 2)
    centres = origin + (np.moveaxis(np.indices((n, n, n)), 0, -1) + 0.5) * h
    angle = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    ring = radius * np.stack([np.cos(angle), np.sin(angle), 0 * angle], -1)
    step = (
        radius * (2 * np.pi / segments) * np.stack([-np.sin(angle), np.cos(angle), 0 * angle], -1)
    )
    velocity = np.zeros(centres.shape)
    for at, dl in zip(ring, step, strict=True):
        r = centres - at
        velocity += np.cross(dl, r) / ((r**2).sum(-1) + core**2)[..., None] ** 1.5
    return np.moveaxis(velocity * circulation / (4 * np.pi), -1, 0), origin


def test_the_vortex_surfaces_of_a_ring_enclose_its_core():
    """A vortex ring's Q-surface at half the peak is a tube around its core circle: every
    point of the core circle lies inside (Q above the level), every vertex lies within a
    few core radii of the circle, and the tube goes all the way round."""
    pytest.importorskip("skimage")
    radius, core, n, h = 0.04, 0.008, 40, 0.0025
    velocity, origin = ring_flow(radius, core, n, h)
    fluid = FluidFrames(h, origin[None], velocity[None].astype(np.float16),
                        np.zeros((1, n, n, n), bool))  # fmt: skip
    level = q_level(fluid, 0.5)
    (mesh,) = vortex_surfaces(fluid, 0, level, axis=2)
    v = mesh.vertices
    from_circle = np.hypot(np.hypot(v[:, 0], v[:, 1]) - radius, v[:, 2])
    assert from_circle.max() < 2.5 * core and from_circle.min() > 0.2 * core
    azimuth = np.arctan2(v[:, 1], v[:, 0])
    assert np.histogram(azimuth, bins=36, range=(-np.pi, np.pi))[0].min() > 0
    from aquagait.sim.particles import sample
    from aquagait.sim.vortices import frame_q

    angle = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    circle = radius * np.stack([np.cos(angle), np.sin(angle), 0 * angle], -1)
    assert np.all(sample(frame_q(fluid, 0), origin, h, circle) > level)
    # the ring turns about its tangent: seen along z its vorticity has no z part on the core
    assert np.abs(mesh.colours[:, :3] - [0.5, 0.5, 0.52]).max() < 0.2


@pytest.fixture(scope="module")
def beating():
    """One second of the fish's shipped gait from rest: the tail beats, the body moves."""
    creature = ag.creatures.get("fish")
    scene = ag.make_scene(creature, fluid="euler")
    return creature.model, ag.rollout(scene, ag.init_state(scene), creature.policy(), 1.0,
                                      record_fluid=False)  # fmt: skip


@pytest.mark.parametrize("view", ["follow", "side", "top", "side-above"])
def test_framing_keeps_the_swimmer_at_its_share_of_the_picture(beating, view):
    """Across the swim the body's projected box spans a third to a half of the picture's
    width (``BODY_SHARE`` 40 % on the swim's median frame) and stays inside it."""
    fish, traj = beating
    look = Look3D(view=view)
    cameras, _ = _cameras(fish, traj, look)
    for camera, (low, high) in zip(cameras, body_boxes(fish, traj.qpos), strict=True):
        corners = np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1])
                            for z in (low[2], high[2])])  # fmt: skip
        p = project(camera, corners, look.width, look.height)
        share = np.ptp(p[:, 0]) / look.width
        assert 1 / 3 <= share <= 1 / 2, (view, share, BODY_SHARE)
        assert p.min() >= 0 and p[:, 0].max() <= look.width and p[:, 1].max() <= look.height


@pytest.mark.parametrize("view", list(VIEWS))
def test_every_view_renders_the_fish_with_its_wake(gliding, view):
    fish, traj = gliding
    pytest.importorskip("skimage")
    picture = pictures(fish, traj, view=view, wake="both")[-1]
    assert (picture < 200).any(axis=-1).sum() > 200  # the body, the vortex, the grid


def test_the_legend_sits_in_the_lower_left_of_pictures_wide_enough_for_it(gliding):
    fish, traj = gliding
    pytest.importorskip("skimage")
    pytest.importorskip("matplotlib")
    size = dict(width=720, height=404)
    with_legend, without = (
        pictures(fish, traj, frames=[len(traj.time) - 1], legend=shown, **size)[0].astype(int)
        for shown in (True, False)
    )
    changed = np.abs(with_legend - without).sum(-1) > 60
    rows, cols = np.nonzero(changed)
    assert len(rows) > 300  # its text and colour bar
    assert rows.min() > 404 / 2 and cols.max() < 720 / 2
    small = pictures(fish, traj, frames=[len(traj.time) - 1])[0]  # a thumbnail: none
    bare = pictures(fish, traj, frames=[len(traj.time) - 1], legend=False)[0]
    assert np.array_equal(small, bare)


def test_without_scikit_image_the_vortex_surfaces_say_what_to_install(gliding, monkeypatch):
    fish, traj = gliding
    monkeypatch.setitem(sys.modules, "skimage.measure", None)  # an import of it fails
    with pytest.raises(RenderUnavailable, match=r"need scikit-image.*aquagait\[render\]"):
        list(volume_pictures(traj, fish, width=WIDTH, height=HEIGHT, wake="q"))
