"""PD servos: the error they see, their gains, and why the stable form exists.

The stable PD's step itself (``sampled`` against ``end_of_step``) is
``test_discretization``'s."""

from functools import partial

import numpy as np
import pytest

import aquagait as ag
from aquagait.body import Dynamics
from aquagait.body.rotations import quat_exp, quat_mul
from aquagait.control import (
    PD,
    GaitSpec,
    StablePD,
    apparent_inertia,
    end_of_step,
    gains,
    sampled,
    servo_figures,
)
from aquagait.sim import SimulationDiverged

DT = 0.01
# 3D: a free root and a ball joint
BALL = """<mujoco><worldbody><body name="shell"><freejoint/>
    <geom type="ellipsoid" size=".2 .15 .05" density="1000"/>
    <body name="flipper" pos="0 .15 0"><joint name="shoulder" type="ball" range="0 60"/>
      <geom type="box" size=".05 .1 .01" pos="0 .1 0" density="1000"/></body>
  </body></worldbody></mujoco>"""


def eel_gait(amplitude=0.3):
    spec = GaitSpec(dofs=("j1", "j2", "j3", "j4"))
    return spec.unpack(spec.pack(amplitude=amplitude, phase=-1.5 * np.arange(4)))


def test_on_the_reference_only_damping_acts(eel):
    gait = eel_gait()
    servo = StablePD.tuned(eel.model, gait, 100.0)
    q = eel.model.qpos0.copy()
    q[3:] = gait.angles(0.3)
    qd = np.arange(7.0)
    np.testing.assert_allclose(servo.error(0.3, q), 0, atol=1e-15)
    np.testing.assert_allclose(servo(0.3, q, qd), -servo.kd * qd)
    assert np.all(servo.kd[:3] == 0) and np.all(servo.kp[:3] == 0)


def test_gains_set_each_servo_natural_frequency_on_its_apparent_inertia(eel):
    kp, kd = gains(eel.model, 50.0, 0.7)
    mass = Dynamics(eel.model.mj).mass_matrix(eel.model.qpos0)
    inertia = 1 / np.diag(np.linalg.inv(mass))
    np.testing.assert_allclose(kp[3:], 50.0**2 * inertia[3:])
    np.testing.assert_allclose(kd[3:], 2 * 0.7 * 50.0 * inertia[3:])


def test_servo_figures_invert_the_gains_about_any_inertia(eel):
    """About the inertia they were tuned for, the gains give back w and zeta; about
    four times it (a joint moving water), w / 2 and zeta / 2."""
    kp, kd = gains(eel.model, 50.0, 0.7)
    inertia = apparent_inertia(eel.model)
    w, zeta = servo_figures(kp[3:], kd[3:], inertia[3:])
    np.testing.assert_allclose(w, 50.0, rtol=1e-14)
    np.testing.assert_allclose(zeta, 0.7, rtol=1e-14)
    w, zeta = servo_figures(kp[3:], kd[3:], 4 * inertia[3:])
    np.testing.assert_allclose([w, zeta], [[25.0] * 4, [0.35] * 4], rtol=1e-14)
    assert np.isnan(servo_figures(kp[:3], kd[:3], inertia[:3])[0]).all()  # the root


def test_only_stable_pd_tells_the_step_how_to_treat_it(eel):
    """``implicit(dt)``: the paper's form is look-ahead 1 and D = Kd; the default,
    ``sampled`` about the DOFs' apparent inertia. The explicit PD has neither."""
    gait = eel_gait()
    kp, kd = gains(eel.model, 100.0)
    look_ahead, damping = StablePD.tuned(eel.model, gait, 100.0, discretize=end_of_step).implicit(
        0.01
    )
    assert np.array_equal(look_ahead, np.ones(7)) and np.array_equal(damping, kd)
    step = sampled(kp, kd, apparent_inertia(eel.model), 0.01)
    look_ahead, damping = StablePD.tuned(eel.model, gait, 100.0).implicit(0.01)
    np.testing.assert_array_equal(look_ahead, step.look_ahead)
    np.testing.assert_array_equal(damping, step.damping)
    assert np.all(look_ahead[3:] < 1) and np.array_equal(look_ahead[:3], np.ones(3))
    explicit = PD.tuned(eel.model, gait, 100.0)
    assert not hasattr(explicit, "implicit") and not hasattr(explicit, "damping")


def test_bad_servos_are_refused(eel):
    gait = eel_gait()
    with pytest.raises(ValueError, match="zero on the root DOFs"):
        PD(eel.model, gait, np.ones(7), np.zeros(7))
    spec = GaitSpec(dofs=("j1", "root_x"))
    with pytest.raises(ValueError, match=r"gait drives \['root_x'\], which are not actuated"):
        PD(eel.model, spec.unpack([0.1, 0.1, 0, 0]), 0.0, 0.0)


def test_ball_joint_error_is_the_rotation_from_reference_in_the_child_frame():
    model = ag.load_model(BALL)
    spec = GaitSpec(dofs=("shoulder:x", "shoulder:y", "shoulder:z"))
    gait = spec.unpack(spec.pack(amplitude=[0.3, 0.2, 0.1], phase=[0.5, 1, 1.5]))
    servo = StablePD.tuned(model, gait, 100.0)
    t, delta = 0.2, np.array([0.01, -0.02, 0.005])
    q = model.qpos0.copy()
    q[7:11] = quat_mul(quat_exp(gait.angles(t)), quat_exp(delta))
    np.testing.assert_allclose(servo.error(t, q)[6:9], delta, atol=1e-12)
    # on the reference, the error grows at the ball's angular velocity (MuJoCo's qvel,
    # child frame), so -Kd qd damps the error it sees
    dyn = Dynamics(model.mj)
    q[7:11] = quat_exp(gait.angles(t))
    qd, h = np.r_[np.zeros(6), 0.3, -0.1, 0.2], 1e-6
    ahead, behind = (
        servo.error(t, dyn.integrate(q, qd, h)),
        servo.error(t, dyn.integrate(q, qd, -h)),
    )
    np.testing.assert_allclose((ahead - behind)[6:9] / (2 * h), qd[6:9], rtol=1e-8)


def decay_ratio(two_links, tuned, x, steps=100, zeta=1.0):
    """|joint error| after ``steps`` over its start, for a servo ``tuned(model, gait, w,
    zeta)`` with w dt = x."""
    model = ag.load_model(two_links)
    spec = GaitSpec(dofs=("j",))
    servo = tuned(model, spec.unpack([0.0, 0.0]), x / DT, zeta)
    scene = ag.make_scene(model)
    state = ag.init_state(scene, qpos=np.r_[0, 0, 0, 1e-3])
    try:
        for _ in range(steps):
            state = ag.step(scene, state, DT, servo)
    except SimulationDiverged:
        return np.inf
    return abs(state.qpos[3]) / 1e-3


PAPERS_STABLE_PD = partial(StablePD.tuned, discretize=end_of_step)
"""The stable PD as the paper steps it (before issue 49)."""


def test_explicit_pd_stability_bound_matches_the_simulation(two_links):
    """x^2 + 4 zeta x < 4: at zeta = 1, x < 2 (sqrt 2 - 1) = 0.83 (see control/pd.py)."""
    assert decay_ratio(two_links, PD.tuned, 0.78) < 1
    assert decay_ratio(two_links, PD.tuned, 0.88) > 1e3


def test_papers_stable_pd_stability_bound_matches_the_simulation(two_links):
    """3 x^2 < 4 + 4 zeta x: at zeta = 1, x < 2 (see control/pd.py)."""
    assert decay_ratio(two_links, PAPERS_STABLE_PD, 1.9) < 1
    assert decay_ratio(two_links, PAPERS_STABLE_PD, 2.1) > 1e3


def test_sampled_stable_pd_has_no_such_bound(two_links):
    """Critically damped at w dt = 2.1 and 10, it decays as the continuous servo,
    exp(-x n) (1 + x n) after n steps, until the root's leftover spin (1e-10
    rad/s, pose-dependent coupling) holds the joint near 1e-40 of its start."""
    assert decay_ratio(two_links, StablePD.tuned, 2.1) < 1e-30
    assert decay_ratio(two_links, StablePD.tuned, 10.0) < 1e-30


def track(model, servo, gait, seconds=3.0):
    """Largest tracking error after the first second, and when it first passed 100 x amplitude."""
    scene = ag.make_scene(model)
    state, worst, blow_up = ag.init_state(scene), 0.0, None
    amplitude = np.abs(gait.amplitude).max()
    try:
        while state.time < seconds - 1e-9:
            state = ag.step(scene, state, DT, servo)
            error = np.abs(servo.error(state.time, state.qpos)).max()
            if state.time > 1.0:
                worst = max(worst, error)
            if blow_up is None and error > 100 * amplitude:
                blow_up = state.time
    except SimulationDiverged:
        blow_up = state.time if blow_up is None else blow_up
    return worst, blow_up


def test_stable_pd_tracks_a_1hz_sine_with_stiff_gains_where_explicit_pd_diverges(eel):
    """w = 400 rad/s at dt = 0.01 s (w dt = 4), zeta = 3.

    The stable PD follows the 1 Hz gait with the lag of a first-order servo,
    time constant Kd / Kp = 2 zeta / w = 15 ms: error ~ A 2 pi f 2 zeta / w
    = 0.094 A. The explicit PD with the same gains (stable only for w dt <
    0.17 at zeta = 3) is 100 times off within a few steps.
    """
    gait, w, zeta = eel_gait(0.3), 400.0, 3.0
    error, blow_up = track(eel.model, StablePD.tuned(eel.model, gait, w, zeta), gait)
    lag = 0.3 * 2 * np.pi * 1.0 * 2 * zeta / w
    assert blow_up is None
    assert error < 1.1 * lag  # measured: 1.00 lag (the paper's form, end_of_step: 1.00)
    _, blow_up = track(eel.model, PD.tuned(eel.model, gait, w, zeta), gait, seconds=0.5)
    assert blow_up is not None and blow_up <= 0.05  # measured: 0.02 s, two steps
