"""Swimming in the Euler fluid: a travelling wave propels, symmetry holds (paper §3, §7)."""

import numpy as np
import pytest

import aquagait as ag
from aquagait.control import GaitSpec, StablePD
from aquagait.sim import SimulationDiverged

# 2D, mirror-symmetric about the x axis: a body with two legs whose hinges
# are mirrored, so a mirrored gait moves it symmetrically
FROG2D = """<mujoco><custom><numeric name="aquagait_depth" data="0.04"/></custom>
  <worldbody><body name="body">
    <joint type="slide" axis="1 0 0"/><joint type="slide" axis="0 1 0"/>
    <joint type="hinge" axis="0 0 1"/>
    <geom type="box" size=".06 .03 .02" density="1000"/>
    <body name="left" pos="-.06 .02 0">
      <joint name="left" type="hinge" axis="0 0 1" range="-80 80"/>
      <geom type="box" size=".05 .01 .02" pos="-.05 0 0" density="1000"/></body>
    <body name="right" pos="-.06 -.02 0">
      <joint name="right" type="hinge" axis="0 0 1" range="-80 80"/>
      <geom type="box" size=".05 .01 .02" pos="-.05 0 0" density="1000"/></body>
  </body></worldbody></mujoco>"""


def swim(creature, params, seconds, resolution=None, cell_size=None):
    scene = ag.make_scene(creature, resolution, cell_size, fluid="euler")
    return ag.rollout(scene, ag.init_state(scene), creature.policy(params), seconds)


def test_eel_swims_forward_with_a_head_to_tail_wave_and_backward_with_the_reverse():
    eel = ag.creatures.get("eel2d")
    forward = eel.gait.unpack(eel.default_gait)  # phases lag towards the tail
    backward = eel.gait.pack(amplitude=forward.amplitude, phase=-forward.phase)
    ahead = swim(eel, eel.default_gait, 1.0, (80, 40), 0.016).qpos[:, 0]
    behind = swim(eel, backward, 1.0, (80, 40), 0.016).qpos[:, 0]
    length = eel.model.body_length
    print(f"eel2d 1 s: wave {ahead[-1] - ahead[0]:+.4f} m, reverse {behind[-1] - behind[0]:+.4f} m")
    # measured +0.062 m and -0.038 m: a tenth of a body length each way
    assert ahead[-1] - ahead[0] > 0.05 * length
    assert behind[-1] - behind[0] < -0.03 * length


def frog2d_asymmetry(tolerance):
    """frog2d's legs sweeping out and in together for 1 s: the root's largest sideways
    drift [m] and turn [rad], and how far it swam [m]."""
    model = ag.load_model(FROG2D)
    spec = GaitSpec(dofs=("left", "right"), mirror=(("right", "left", -1.0),))
    gait = spec.unpack([0.6, 0.0])  # legs sweep out and in together
    policy = StablePD.tuned(model, gait, natural_frequency=100.0, damping_ratio=1.5)
    fluid = ag.EulerFluid(tolerance=tolerance)
    scene = ag.make_scene(model, (64, 40), 0.008, fluid=fluid)  # room for the legs
    traj = ag.rollout(scene, ag.init_state(scene), policy, seconds=1.0)
    x, y, theta = traj.qpos[:, 0], traj.qpos[:, 1], traj.qpos[:, 2]
    print(f"frog2d 1 s, tolerance {tolerance:g}: x {x[-1] - x[0]:+.4f} m, "
          f"|y| {np.abs(y).max():.2e} m, |theta| {np.abs(theta).max():.2e} rad")  # fmt: skip
    return np.abs(y).max(), np.abs(theta).max(), x[-1] - x[0]


def test_symmetric_creature_with_a_mirrored_gait_does_not_drift_sideways_or_turn():
    """Mirror symmetry holds to the pressure solve's tolerance, not to round-off (the
    red-black smoother's colours are not mirror images), and the wake's
    mirror-asymmetric modes grow from that error: nothing holds the water next
    to the body to it any more (the per-step hold went with the closure of thin
    parts). So the drift falls with the tolerance, to nothing. Measured: |theta|
    2.2e-3 rad at the default 1e-4, 1.3e-4 at 1e-6, 3.4e-6 at 1e-8 (with the
    hold, 1.05e-5 at 1e-4); |y| 7.5e-4, 6.1e-6 and 1.0e-7 m."""
    loose_y, loose_theta, _ = frog2d_asymmetry(1e-6)
    y, theta, swum = frog2d_asymmetry(1e-8)
    assert abs(swum) > 0.005  # it does move
    assert theta < 1e-5 and y < 1e-6
    assert theta < loose_theta / 10 and y < loose_y / 10


def test_fish_with_a_tail_beat_swims_forward_in_3d():
    fish = ag.creatures.get("fish")
    traj = swim(fish, fish.default_gait, 1.5, (40, 24, 28), 0.005)
    forward = traj.qpos[-1, 0] - traj.qpos[0, 0]
    sideways = np.abs(traj.qpos[-1, 1:3] - traj.qpos[0, 1:3]).max()  # net, past the recoil
    print(f"fish 1.5 s: forward {forward:+.4f} m, sideways {sideways:.4f} m")
    # measured 7.7 mm forward and 0.3 mm sideways: slow from rest at 1 Hz, but steady
    assert forward > 0.05 * fish.model.body_length
    assert sideways < forward / 4


def test_a_run_that_blows_up_says_when_and_how_fast_instead_of_writing_nans():
    eel = ag.creatures.get("eel2d")
    scene = ag.make_scene(eel, (64, 32), 0.02, fluid="euler")

    def flail(t, q, qd):  # a joint torque no eel has: 1 kN m
        tau = np.zeros(eel.model.nv)
        tau[eel.model.actuated_dofs] = 1e3
        return tau

    with pytest.raises(SimulationDiverged, match=r"diverged at t = [\d.]+ s: in one step the body"):
        ag.rollout(scene, ag.init_state(scene), flail, seconds=1.0)


def eel_distance(cells: int, dt: float) -> float:
    """eel2d's hand-set gait's distance over 2 s from rest, in one 1.28 x 0.64 m domain (the
    grid convergence table (docs/method-coupling.md))."""
    eel = ag.creatures.get("eel2d")
    scene = ag.make_scene(eel, (cells, cells // 2), 1.28 / cells, fluid="euler")
    policy = eel.policy(eel.gaits["hand-set"].params)
    traj = ag.rollout(scene, ag.init_state(scene), policy, 2.0, dt=dt, record_fluid=False)
    return float(traj.qpos[-1, 0] - traj.qpos[0, 0])


@pytest.mark.slow
def test_the_eel_s_distance_converges_with_the_grid():
    """Sub-cell boundaries, steps of 1/270 s (the default 1/90 s adds a first-order
    time-step error of ~9% at 128x64: docs/method-coupling.md): the change per
    halving of h shrinks by half or more, and the default grid is within 5% of
    512x256. Measured 0.3225, 0.3445, 0.3380 m at 128, 256 and 512 cells."""
    coarse, middle, fine = (eel_distance(n, 1 / 270) for n in (128, 256, 512))
    print(f"eel2d 2 s, dt 1/270 s: {coarse:.4f}, {middle:.4f}, {fine:.4f} m")
    assert abs(fine - middle) <= 0.5 * abs(middle - coarse)
    assert abs(coarse - fine) < 0.05 * fine
