"""manta: the paper's ray of plates (Table 1), mirrored fins, plates on the grid, and it swims."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.app.check import prepare_check, run_check
from aquagait.body.dynamics import Dynamics
from aquagait.body.geometry import link_volumes
from aquagait.body.meshes import link_meshes
from aquagait.creatures import get

RHO = 1000.0
LEFT = ("l1a", "l1b", "l2a", "l2b", "l3a", "l3b", "l4a")
RIGHT = tuple("r" + d[1:] for d in LEFT)


@pytest.fixture(scope="module")
def manta():
    return get("manta")


def test_matches_table_1_of_the_paper(manta):
    """14 DOFs, 21 dims: the right fin mirrors the left's 7 hinges, each with a free
    amplitude, phase and offset (the paper does not say which; module docstring)."""
    assert manta.dim == 3
    assert len(manta.model.actuated_dofs) == 14
    assert manta.gait.size == 21
    assert manta.resolution == (64, 32, 32)
    assert manta.gait.free == ("amplitude", "phase", "offset")
    assert manta.gait.period == 1.0
    assert manta.gait.independent == LEFT
    assert manta.gait.groups == ()  # one group: all seven together


def test_right_fin_is_the_mirror_image_of_the_left(manta):
    """Same geometry and limits on both sides; the gait drives q_right = -q_left
    (both fins' hinges turn about +x: positive lifts the left fin, lowers the right)."""
    model = manta.model
    assert manta.gait.mirror == tuple((r, l, -1) for r, l in zip(RIGHT, LEFT, strict=True))
    mass = dict(zip(model.links, model.link_mass, strict=True))
    for name in model.links[1:8]:
        assert name.startswith("left") and mass[name] == pytest.approx(
            mass[name.replace("left", "right")], rel=1e-9
        )
    hinges = {j.name: j for j in model.joints if j.name != "root"}
    for d in LEFT + RIGHT:
        np.testing.assert_allclose(hinges[d].axis, [1, 0, 0])
    sines = manta.gait.unpack(manta.default_gait)
    for t in (0.1, 0.37, 0.8):
        q = dict(zip(sines.dofs, sines.angles(t), strict=True))
        assert all(q[r] == -q[l] for r, l in zip(RIGHT, LEFT, strict=True))
    # a gait with offsets: the dihedral is symmetric too
    x = manta.default_gait.copy()
    x[14:] = 0.2
    gait = manta.gait.unpack(x)
    np.testing.assert_allclose(gait.offset, [0.2] * 7 + [-0.2] * 7)


def test_is_a_small_ray_of_water(manta):
    """About 0.34 m across (model.extent over-reports the swept plates: see the module),
    thin in z, every link of water density, and the fins together heavier than the body
    (45 mm plates, thicker than a real fin so that the 25 mm cells see them)."""
    model = manta.model
    width, depth = model.extent[1], model.extent[2]
    assert 0.3 < width < 0.4 and depth == pytest.approx(0.054, rel=1e-3)
    np.testing.assert_allclose(model.link_mass, RHO * link_volumes(model), rtol=1e-6)
    body = model.link_mass[model.links.index("body")]
    assert 0.3 < body / model.mass < 0.4
    assert 2.0 < model.mass < 3.5


def test_every_plate_is_at_least_one_and_a_half_cells_thick():
    """Measured as ``aquagait check`` does, on the default 25 mm grid."""
    links = run_check(prepare_check("manta")).numbers["links"]
    thickness = {link["name"]: link["thickness_cells"] for link in links}
    assert min(thickness.values()) >= 1.5, thickness


def test_shipped_gait_swims_forward_and_straight(manta):
    """One cycle from rest in the Euler fluid on the default grid: flapping with a wave
    running front to back pushes the ray towards +x; the gait and the body are mirror
    symmetric, so it neither turns nor rolls nor drifts sideways (up to the grid's
    placement, a fraction of a cell). The energy bound is for two cycles (the slow library
    test swims them: 2.06 of 2.09 J); the first, from rest, spends 1.65 J of it."""
    scene = ag.make_scene(manta, fluid="euler")
    traj = ag.rollout(scene, ag.init_state(scene), manta.policy(), 1.0, record_fluid=False)
    step = traj.qpos[-1, :3] - traj.qpos[0, :3]
    assert step[0] > 0.05 * manta.model.body_length  # measured 0.148 L in the first cycle
    assert abs(step[1]) < 0.02 * step[0]
    w, x, y, z = traj.qpos[-1, 3:7]
    roll, yaw = (
        np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)),
        np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)),
    )
    assert abs(roll) < np.deg2rad(1) and abs(yaw) < np.deg2rad(1)
    assert 0 < traj.energy[-1].sum() < manta.energy_bound


def test_its_visual_body_is_a_thin_wing_over_its_thick_plates(manta):
    """From the front the drawn fins are a few millimetres thick where the fluid's plates
    are 45 mm; from above they span the same width within a 25 mm cell."""
    model = manta.model
    pos, rot = Dynamics(model.mj).link_poses(model.qpos0)

    def extent(meshes, links):
        world = np.concatenate([pos[k] + meshes[k].vertices @ rot[k].T for k in links])
        return np.ptp(world, axis=0)

    fins = range(1, len(model.links))
    drawn, shape = link_meshes(model), link_meshes(model, visual=False)
    assert extent(shape, fins)[2] == pytest.approx(0.045)
    assert extent(drawn, fins)[2] <= 0.0071  # the wing root's 7 mm
    assert extent(drawn, fins)[1] == pytest.approx(extent(shape, fins)[1], abs=0.025)
