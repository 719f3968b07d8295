"""The vacuum simulation: conservation laws, symmetry, the policy seam, rollouts and errors."""

import pickle

import numpy as np
import pytest

import aquagait as ag
from aquagait.control import GaitSpec, StablePD
from aquagait.sim import SimulationDiverged, advance

# 3D, left-right symmetric: two flippers whose hinge axes are mirror images
PADDLER = """<mujoco><worldbody><body name="shell"><freejoint/>
    <geom type="ellipsoid" size=".2 .12 .05" density="1000"/>
    <body name="left" pos=".05 .12 0">
      <joint name="left" type="hinge" axis="1 0 0" range="-60 60"/>
      <geom type="box" size=".06 .1 .01" pos="0 .1 0" density="1000"/></body>
    <body name="right" pos=".05 -.12 0">
      <joint name="right" type="hinge" axis="-1 0 0" range="-60 60"/>
      <geom type="box" size=".06 .1 .01" pos="0 -.1 0" density="1000"/></body>
  </body></worldbody></mujoco>"""


@pytest.fixture(scope="module", params=["eel2d", "fish"])
def creature(request):
    return ag.creatures.get(request.param)


# --- scenes and states ---------------------------------------------------------------


def test_scene_grid_defaults_to_the_creature_and_is_centred_on_it(creature):
    scene = ag.make_scene(creature)
    assert scene.fluid.name == "none"
    assert scene.grid.shape == creature.resolution and scene.grid.cell_size == creature.cell_size
    centre = np.asarray(scene.grid.origin) + np.asarray(scene.grid.shape) * scene.grid.cell_size / 2
    com = scene.dynamics.center_of_mass(creature.model.qpos0)[: creature.dim]
    np.testing.assert_allclose(centre, com, atol=1e-12)
    assert ag.make_scene(creature.model).grid is None  # a bare model has no default grid
    placed = ag.make_scene(creature.model, (16,) * creature.dim, 0.1, origin=(1,) * creature.dim)
    assert placed.grid.origin == (1.0,) * creature.dim


def test_scene_arguments_are_checked(creature):
    with pytest.raises(ValueError, match="drag_coefficient must be >= 0"):
        ag.make_scene(creature, fluid="simple", drag_coefficient=-1)
    with pytest.raises(ValueError, match="'euler' needs a grid"):
        ag.make_scene(creature.model, fluid="euler")
    with pytest.raises(ValueError, match="unknown fluid 'water'"):
        ag.make_scene(creature, fluid="water")
    with pytest.raises(TypeError, match=r"use aquagait.creatures.get\(name\)"):
        ag.make_scene("eel2d")
    with pytest.raises(ValueError, match=f"is {creature.dim}D"):
        ag.make_scene(creature, resolution=(8,) * (5 - creature.dim))


def test_new_state_is_at_rest_in_still_fluid(creature):
    state = ag.init_state(ag.make_scene(creature))
    assert state.time == 0.0 and state.velocity is None and state.pressure is None
    np.testing.assert_array_equal(state.qpos, creature.model.qpos0)
    assert not state.qvel.any() and not state.energy.any()


def test_init_state_checks_shapes_and_quaternions():
    scene = ag.make_scene(ag.creatures.get("fish"))
    with pytest.raises(ValueError, match=r"must be \(10,\) and \(9,\)"):
        ag.init_state(scene, qpos=np.zeros(3))
    with pytest.raises(ValueError, match=r"qpos\[3:7\] \(quaternion of joint 'root'\) has norm 0"):
        ag.init_state(scene, qpos=np.zeros(10))


def test_scene_and_state_pickle_for_workers(creature):
    scene = ag.make_scene(creature)
    state = ag.step(scene, ag.init_state(scene), 0.01, creature.policy())
    scene2, state2 = pickle.loads(pickle.dumps((scene, state)))
    policy = pickle.loads(pickle.dumps(creature.policy()))
    np.testing.assert_array_equal(
        ag.step(scene2, state2, 0.01, policy).qpos,
        ag.step(scene, state, 0.01, creature.policy()).qpos,
    )


# --- invariants -----------------------------------------------------------------


def test_a_body_at_rest_without_actuation_stays_at_rest(creature):
    scene = ag.make_scene(creature)
    state = ag.init_state(scene)
    for _ in range(10):
        state = ag.step(scene, state, 0.01)
    np.testing.assert_array_equal(state.qpos, creature.model.qpos0)
    assert not state.qvel.any()


def momentum_drift(creature, dt, seconds=2.0):
    """Largest |P|, |L about the CoM| and CoM travel over a gait started from rest.

    P is relative to the sum of the links' momentum magnitudes, L to that times
    the body length, the CoM travel to the body length.
    """
    hand_set = creature.gaits.get("hand-set", creature.gaits["straight"])  # the figures' gait
    scene, policy = ag.make_scene(creature), creature.policy(hand_set.params)
    length = creature.model.body_length
    dyn = scene.dynamics
    state = ag.init_state(scene)
    com0 = dyn.center_of_mass(state.qpos)
    drift, scale = np.zeros(3), 0.0
    links = np.arange(dyn.nlinks)
    while state.time < seconds - 1e-9:
        state = ag.step(scene, state, dt, policy)
        p, angular = dyn.momentum(state.qpos, state.qvel)
        com = dyn.center_of_mass(state.qpos)
        origins, _ = dyn.link_poses(state.qpos)
        speeds = np.linalg.norm(
            dyn.point_velocities(state.qpos, state.qvel, origins, links), axis=1
        )
        scale = max(scale, dyn.link_mass @ speeds)
        now = [
            np.linalg.norm(p),
            np.linalg.norm(angular - np.cross(com, p)),
            np.linalg.norm(com - com0),
        ]
        drift = np.maximum(drift, now)
    return drift / [scale, scale * length, length]


def test_internal_torques_conserve_momentum_and_keep_the_centre_of_mass(creature):
    """In vacuum the joint torques are internal: P = L = 0 and the CoM stays put.

    Semi-implicit Euler in generalized coordinates conserves them to first
    order: halving dt halves the drift. Measured at dt = 2.5 ms over 2 s of the
    hand-set gait: eel2d P 2.8 %, L 0.03 %, CoM 0.14 % L; fish 2.6 %, 0.14 %, 0.18 % L
    (eel2d's optimized gait, which bends more: 3.8 %, 0.05 %, 0.67 % L, also first order).
    """
    coarse, fine = momentum_drift(creature, 0.005), momentum_drift(creature, 0.0025)
    np.testing.assert_array_less(fine, [0.04, 2e-3, 3e-3])
    np.testing.assert_allclose(coarse / fine, 2.0, rtol=0.15)  # first order


def test_free_rigid_body_keeps_energy_and_angular_momentum_to_first_order():
    """Torque-free tumbling of an asymmetric box (the Coriolis terms of a free joint)."""
    model = ag.load_model(
        "<mujoco><worldbody><body><freejoint/><geom type='box' size='.3 .2 .1' density='1000'/>"
        "</body></worldbody></mujoco>"
    )
    scene = ag.make_scene(model)

    def drift(dt):
        state = ag.init_state(scene, qvel=[0.1, 0, 0, 0.2, 3.0, 0.1])  # near the unstable axis
        kinetic = lambda s: 0.5 * s.qvel @ scene.dynamics.mass_matrix(s.qpos) @ s.qvel  # noqa: E731
        e0, l0 = kinetic(state), scene.dynamics.momentum(state.qpos, state.qvel)[1]
        while state.time < 1.0 - 1e-9:
            state = ag.step(scene, state, dt)
        l1 = scene.dynamics.momentum(state.qpos, state.qvel)[1]
        return abs(kinetic(state) / e0 - 1), np.linalg.norm(l1 - l0) / np.linalg.norm(l0)

    coarse, fine = np.array(drift(0.002)), np.array(drift(0.001))
    np.testing.assert_array_less(fine, 1e-3)  # measured at dt = 1 ms: energy 6e-6, L 1e-4
    np.testing.assert_allclose(coarse / fine, 2.0, rtol=0.2)


def test_planar_creature_stays_in_its_plane():
    eel = ag.creatures.get("eel2d")
    scene = ag.make_scene(eel)
    traj = ag.rollout(scene, ag.init_state(scene), eel.policy(), 1.0)
    for q in traj.qpos[::5]:
        origins, rotations = scene.dynamics.link_poses(q)
        assert not origins[:, 2].any()
        np.testing.assert_allclose(rotations[:, :, 2], [[0, 0, 1]] * len(origins), atol=1e-15)


def test_top_bottom_symmetric_fish_with_yaw_joints_stays_in_the_plane():
    fish = ag.creatures.get("fish")
    scene = ag.make_scene(fish)
    traj = ag.rollout(scene, ag.init_state(scene), fish.policy(), 1.0)
    assert np.abs(traj.qpos[:, 2]).max() < 1e-12  # z
    assert np.abs(traj.qpos[:, 4:6]).max() < 1e-12  # roll and pitch parts of the quaternion
    assert np.abs(traj.qpos[:, 1]).max() > 1e-4  # while it does sway sideways


def test_mirrored_gait_gives_the_mirrored_motion(creature):
    """Reflect y: negated joint angles make y, the yaw and the joints change sign."""
    scene = ag.make_scene(creature)
    gait = creature.gait.unpack(creature.default_gait)
    a, b = (
        ag.rollout(scene, ag.init_state(scene), StablePD.tuned(creature.model, g, 100.0, 1.5), 1.0)
        for g in (gait, gait.mirrored())
    )
    if creature.dim == 2:
        flip = np.array([1, -1, -1, -1, -1, -1, -1])  # x, y, theta, j1..j4
    else:
        flip = np.array([1, -1, 1, 1, -1, 1, -1, -1, -1, -1])  # x y z, quat w x y z, j1..j3
    np.testing.assert_allclose(b.qpos, a.qpos * flip, atol=1e-9)
    assert np.abs(a.qpos[:, 1]).max() > 1e-4  # the motion is not trivially symmetric


def test_symmetric_gait_on_a_symmetric_creature_does_not_turn_or_roll():
    model = ag.load_model(PADDLER)
    spec = GaitSpec(dofs=("left", "right"), mirror=(("right", "left", 1.0),))
    servo = StablePD.tuned(model, spec.unpack([0.5, 0.3]), 100.0, 1.5)
    scene = ag.make_scene(model)
    traj = ag.rollout(scene, ag.init_state(scene), servo, 1.0)
    np.testing.assert_allclose(traj.qpos[:, 7], traj.qpos[:, 8], atol=1e-12)  # flippers together
    assert np.abs(traj.qpos[:, [1, 4, 6]]).max() < 1e-12  # y, roll and yaw stay zero
    assert np.abs(traj.qpos[:, 2]).max() > 1e-4  # while it heaves


# --- the policy seam and the energy account -------------------------------------------------


class Spy:
    """A policy that remembers where it was evaluated."""

    def __init__(self, nv, damping=None):
        self.calls, self.nv = [], nv
        if damping is not None:
            self.damping = damping

    def __call__(self, t, q, qd):
        self.calls.append((t, q.copy(), qd.copy()))
        return np.zeros(self.nv)


def test_a_policy_with_damping_is_evaluated_at_the_end_of_the_step():
    eel = ag.creatures.get("eel2d")
    scene = ag.make_scene(eel)
    state = ag.init_state(scene, qvel=[0.1, 0.2, 0.3, 0.4, 0, 0, 0])
    plain, servo = Spy(7), Spy(7, damping=np.zeros(7))
    ag.step(scene, state, 0.01, plain)
    ag.step(scene, state, 0.01, servo)
    assert plain.calls[0][0] == 0.0
    np.testing.assert_array_equal(plain.calls[0][1], state.qpos)
    assert servo.calls[0][0] == 0.01
    np.testing.assert_allclose(servo.calls[0][1], state.qpos + 0.01 * state.qvel, atol=1e-15)
    np.testing.assert_array_equal(servo.calls[0][2], state.qvel)


class Stepped(Spy):
    """A servo that says how the step should treat it (``implicit``) and returns t [s]
    on every DOF, so that the force applied shows where it was read."""

    def __init__(self, nv, look_ahead):
        super().__init__(nv)
        self.look_ahead = np.asarray(look_ahead, dtype=float)

    def implicit(self, dt):
        return self.look_ahead, np.zeros(self.nv)

    def __call__(self, t, q, qd):
        super().__call__(t, q, qd)
        return np.full(self.nv, t)


def test_a_servo_is_read_its_look_ahead_of_the_way_through_the_step():
    """``implicit(dt) -> (theta, D)``: the policy at the start and at the predicted end,
    blended per DOF, ``theta tau(t + dt) + (1 - theta) tau(t)`` (sim/servo.py)."""
    eel = ag.creatures.get("eel2d")
    scene = ag.make_scene(eel)
    state = ag.init_state(scene, qvel=[0.1, 0.2, 0.3, 0.4, 0, 0, 0])
    look_ahead = np.linspace(0, 1, 7)
    servo = Stepped(7, look_ahead)
    new = ag.step(scene, state, 0.01, servo)
    assert [c[0] for c in servo.calls] == [0.01, 0.0]
    np.testing.assert_allclose(servo.calls[0][1], state.qpos + 0.01 * state.qvel, atol=1e-15)
    np.testing.assert_array_equal(servo.calls[1][1], state.qpos)
    np.testing.assert_allclose(new.torque, 0.01 * look_ahead, rtol=1e-14)
    at_the_end = Stepped(7, np.ones(7))  # the paper's stable PD: read once, at the end
    ag.step(scene, state, 0.01, at_the_end)
    assert [c[0] for c in at_the_end.calls] == [0.01]


def test_a_servo_with_the_wrong_shapes_is_refused():
    eel = ag.creatures.get("eel2d")
    scene = ag.make_scene(eel)
    with pytest.raises(ValueError, match=r"look_ahead \(3,\) and damping \(7,\).*must be \(7,\)"):
        ag.step(scene, ag.init_state(scene), 0.01, Stepped(7, np.ones(3)))


def test_energy_is_the_work_of_the_joint_torque(two_links):
    """A constant internal torque tau: the energy account is |tau| |dtheta| exactly,
    and the kinetic energy gained equals that work to first order in dt."""
    model = ag.load_model(two_links)
    scene = ag.make_scene(model)
    tau = np.array([0, 0, 0, 0.02])
    state = ag.init_state(scene)
    for _ in range(50):
        state = ag.step(scene, state, 0.002, lambda t, q, qd: tau)
    work = tau[3] * state.qpos[3]
    assert state.energy[3] == pytest.approx(work, rel=1e-12)
    assert not state.energy[:3].any()
    np.testing.assert_array_equal(state.torque, tau)
    kinetic = 0.5 * state.qvel @ scene.dynamics.mass_matrix(state.qpos) @ state.qvel
    assert kinetic == pytest.approx(work, rel=0.05)


def test_applied_torque_includes_the_implicit_damping(creature):
    scene = ag.make_scene(creature)
    servo = creature.policy()
    state = ag.init_state(scene)
    new = ag.step(scene, state, 0.01, servo)
    ahead = scene.dynamics.integrate(state.qpos, state.qvel, 0.01)
    qdd = (new.qvel - state.qvel) / 0.01
    look_ahead, damping = servo.implicit(0.01)
    read = look_ahead * servo(0.01, ahead, state.qvel) + (1 - look_ahead) * servo(
        0.0, state.qpos, state.qvel
    )
    expected = read - 0.01 * damping * qdd
    np.testing.assert_allclose(new.torque, expected, rtol=1e-12, atol=1e-15)
    # and it is what moves the body: M qdd + c = applied torque
    mass, bias = scene.dynamics.mass_matrix(state.qpos), scene.dynamics.bias(state.qpos, state.qvel)
    np.testing.assert_allclose(mass @ qdd + bias, new.torque, atol=1e-9 * np.abs(new.torque).max())


# --- rollouts and failures ---------------------------------------------------------


def test_rollout_samples_30_frames_per_second_with_a_step_that_divides_a_frame(creature):
    scene = ag.make_scene(creature)
    traj = ag.rollout(scene, ag.init_state(scene), creature.policy(), 0.5, dt=0.01)
    assert traj.fps == 30 and traj.dt == 0.01
    frame = advance(scene, ag.init_state(scene), creature.policy(), 1 / 30, dt=0.01)
    assert frame.steps == 4 and frame.time == 1 / 30  # four equal steps of 1/120 s
    nq, nv = creature.model.nq, creature.model.nv
    assert traj.qpos.shape == (16, nq) and traj.energy.shape == (16, nv)
    np.testing.assert_allclose(traj.time, np.arange(16) / 30, atol=1e-12)
    assert np.all(np.diff(traj.energy.sum(axis=1)) >= 0) and traj.energy[-1].sum() > 0


def test_divergence_says_when(two_links):
    scene = ag.make_scene(ag.load_model(two_links))
    state = ag.init_state(scene)
    with pytest.raises(SimulationDiverged, match=r"diverged at t = 0(\.\d+)? s"):
        for _ in range(100):
            state = ag.step(scene, state, 0.01, lambda t, q, qd: np.r_[0, 0, 0, 1e308])


def test_bad_step_arguments(two_links):
    scene = ag.make_scene(ag.load_model(two_links))
    state = ag.init_state(scene)
    with pytest.raises(ValueError, match="dt must be a positive"):
        ag.step(scene, state, 0.0)
    with pytest.raises(ValueError, match=r"policy returned tau \(2,\).*must be \(4,\)"):
        ag.step(scene, state, 0.01, lambda t, q, qd: np.zeros(2))
