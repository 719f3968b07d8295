"""The stable PD's step: the sampled form follows the continuous servo, the paper's does not.

A wheel on a hinge, centred on its axis and on the root's, in a vacuum: the
mass matrix is constant and the bias zero, so the hinge is exactly one DOF
of inertia ``I = 1/(M^-1)_jj`` (``apparent_inertia``) under a linear servo,
and every figure below comes from the step map in
``aquagait.control.discretization``'s docstring.
"""

import numpy as np
import pytest
from scipy.optimize import brentq

import aquagait as ag
from aquagait.control import StablePD, apparent_inertia, end_of_step, sampled

WHEEL = """<mujoco><custom><numeric name="aquagait_depth" data="0.04"/></custom>
  <worldbody><body name="base">
    <joint type="slide" axis="1 0 0"/><joint type="slide" axis="0 1 0"/>
    <joint type="hinge" axis="0 0 1"/>
    <geom type="box" size=".1 .1 .02" density="1000"/>
    <body name="wheel"><joint name="j" type="hinge" axis="0 0 1"/>
      <geom type="cylinder" size=".05 .02" density="1000"/></body>
  </body></worldbody></mujoco>"""

DT = 0.01
START = 1e-2
"""The hinge's first angle [rad], at rest, with the target at 0."""


class Target:
    """A gait for the hinge: ``angles(t) = [amplitude sin(frequency t)]`` [rad]."""

    dofs = ("j",)

    def __init__(self, amplitude=0.0, frequency=0.0):
        self.amplitude, self.frequency = amplitude, frequency

    def angles(self, t):
        return np.array([self.amplitude * np.sin(self.frequency * t)])


@pytest.fixture(scope="module")
def wheel():
    model = ag.load_model(WHEEL)
    return model, ag.make_scene(model), apparent_inertia(model)[3]


def run(wheel, x, zeta, discretize, steps, target=None, qpos=START):
    """The hinge's angle at every step, (steps + 1,) [rad], for a servo with w dt = x."""
    model, scene, _ = wheel
    servo = StablePD.tuned(model, target or Target(), x / DT, zeta, discretize=discretize)
    state = ag.init_state(scene, qpos=[0, 0, 0, qpos])
    angles = [state.qpos[3]]
    for _ in range(steps):
        state = ag.step(scene, state, DT, servo)
        angles.append(state.qpos[3])
    return np.array(angles)


def continuous_samples(x, zeta, steps):
    """The continuous servo ``e'' + 2 zeta w e' + w^2 e = 0`` at t = n dt, n = 0..steps,
    on the solution through ``e(-dt) = e(0) = START``: what the step's state
    ``(e, dt qd) = (START, 0)`` means (positions move with the new velocity, so
    ``dt qd`` is the last step's change of ``e``)."""
    roots = np.roots([1, 2 * zeta * x, x * x]).astype(complex)  # lambda dt
    z = np.exp(roots)
    c = np.linalg.solve([[1, 1], 1 / z], [START, START])
    n = np.arange(steps + 1)[:, None]
    return (c * z**n).sum(axis=1).real


@pytest.mark.parametrize("x, zeta", [(0.1, 1.5), (1.1, 1.5), (3.0, 1.5), (1.1, 0.7), (2.0, 1.2)])
def test_sampled_servo_is_the_continuous_servo_sampled(wheel, x, zeta):
    """Sample for sample, to round-off: 60 steps of a 2x2 map with entries of order 1
    (the mass matrix and the solve in float64) may lose a few hundred ulps of START
    (1.7e-18 each; measured: 1-3 ulps)."""
    angles = run(wheel, x, zeta, sampled, 60)
    np.testing.assert_allclose(angles, continuous_samples(x, zeta, 60), rtol=0, atol=1e-15)


def test_end_of_step_servo_is_not(wheel):
    """At w dt = 1.1, zeta = 1.5 the paper's form has a complex pair of roots
    (-235 +- 283i rad/s) and a slow one at -27.8 rad/s where the continuous
    servo has -262 and -38.2: after 60 steps (0.6 s) its error is
    exp((38.2 - 27.8) 0.6) = 500 times the continuous servo's."""
    angles = run(wheel, 1.1, 1.5, end_of_step, 60)
    assert abs(angles[-1]) > 100 * abs(continuous_samples(1.1, 1.5, 60)[-1])


def test_sampled_servo_is_stable_where_the_end_of_step_form_diverges(wheel):
    """zeta = 1 at w dt = 3: beyond end_of_step's bound (x < 2, control/pd.py); the
    sampled servo decays as the continuous one does, exp(-w t) (1 + w t)."""
    assert abs(run(wheel, 3.0, 1.0, sampled, 100)[-1]) < 1e-100
    try:
        grew = abs(run(wheel, 3.0, 1.0, end_of_step, 100)[-1]) / START
    except ag.sim.SimulationDiverged:
        grew = np.inf
    assert grew > 1e3


def steady_response(wheel, x, zeta, discretize, frequency):
    """The hinge's steady reply to a target ``sin(frequency t)``: the complex gain
    fitted to one period after the start has decayed."""
    period_steps = int(round(2 * np.pi / frequency / DT))
    target = Target(1e-2, frequency)
    angles = run(wheel, x, zeta, discretize, 6 * period_steps, target, qpos=0.0)
    t = DT * np.arange(len(angles))[-period_steps:]
    basis = np.column_stack([np.sin(frequency * t), np.cos(frequency * t)])
    sin_part, cos_part = np.linalg.lstsq(basis, angles[-period_steps:], rcond=None)[0]
    return complex(sin_part, cos_part) / 1e-2  # q = Re(H A e^{i W t}) = A (Re H sin + Im H cos)


@pytest.mark.parametrize("frequency", [2 * np.pi, 6 * np.pi])
def test_a_gait_beat_is_followed_as_the_continuous_servo_follows_it(wheel, frequency):
    """At w dt = 1.1, zeta = 1.5, against ``H = w^2 / (w^2 - W^2 + 2i zeta w W)``:
    sampled within (W dt)^2 / 8 (module docstring); end_of_step's extra mass dt Kd
    moves it by about W^2 dt Kd / Kp, more than half of which is asserted."""
    x, zeta = 1.1, 1.5
    w = x / DT
    continuous = w * w / (w * w - frequency**2 + 2j * zeta * w * frequency)
    near = steady_response(wheel, x, zeta, sampled, frequency)
    assert abs(near / continuous - 1) < (frequency * DT) ** 2 / 8
    far = steady_response(wheel, x, zeta, end_of_step, frequency)
    assert abs(far / continuous - 1) > 0.5 * frequency**2 * DT * 2 * zeta / w


@pytest.mark.parametrize("zeta", [0.7, 1.0, 1.5, 3.0])
def test_as_dt_shrinks_the_step_tends_to_its_series(zeta):
    """``theta = zeta w dt / 6 + O(dt^3)``, ``D = Kd / 2 + (4 zeta^2 + 1) w^2 I dt / 12
    + O(dt^2)`` (module docstring): the remainders shrink as the next power of w dt."""
    w, inertia = 100.0, 2e-3
    kp, kd = np.array([w * w * inertia]), np.array([2 * zeta * w * inertia])
    theta_err, damping_err = [], []
    for x in (1e-2, 1e-3, 1e-4):
        step = sampled(kp, kd, [inertia], x / w)
        theta_err.append(abs(step.look_ahead[0] - zeta * x / 6))
        series = kd[0] / 2 + (4 * zeta**2 + 1) * w * inertia * x / 12
        damping_err.append(abs(step.damping[0] - series) / kd[0])
    assert theta_err[2] < 1e-5 * zeta * 1e-4  # O(x^3) against the leading x
    assert damping_err[0] > 50 * damping_err[1] and damping_err[1] > 50 * damping_err[2]
    assert damping_err[2] < 1e-6


def test_both_forms_tend_to_the_same_continuous_servo(wheel):
    """At w = 100 rad/s, zeta = 1.5 and dt = 1e-4 s (w dt = 0.01), the paper's form is
    a continuous servo of mass I + dt Kd = 1.03 I: after 0.03 s its step response is
    within 1% of the sampled one's (measured 0.41%), and ten times closer at dt / 10
    (first order in dt)."""
    _, scene, _ = wheel
    gaps = []
    for dt in (1e-4, 1e-5):
        ends = []
        for discretize in (sampled, end_of_step):
            servo = StablePD.tuned(wheel[0], Target(), 100.0, 1.5, discretize=discretize)
            state = ag.init_state(scene, qpos=[0, 0, 0, START])
            state = ag.sim.advance(scene, state, servo, 0.03, dt)
            ends.append(state.qpos[3])
        gaps.append(abs(ends[0] - ends[1]) / abs(ends[0]))
    assert gaps[0] < 0.01 and gaps[1] < gaps[0] / 8


def test_an_underdamped_servo_it_cannot_follow_is_refused():
    """zeta = 0.3: it needs cos(w_d dt) > exp(-zeta w dt), up to w dt = 0.62."""
    zeta, inertia = 0.3, 1.0
    bound = brentq(
        lambda x: np.cos(x * np.sqrt(1 - zeta**2)) - np.exp(-zeta * x), 0.1, 1.5
    )  # fmt: skip
    kp, kd = [1.0], [2 * zeta]
    step = sampled(kp, kd, [inertia], 0.99 * bound)
    assert np.all(step.damping > 0)
    with pytest.raises(ValueError, match=r"damping ratio 0.3, w dt = 0.626.*shorten the step"):
        sampled(kp, kd, [inertia], 1.01 * bound)


def test_bad_steps_and_inertias_are_refused(wheel):
    with pytest.raises(ValueError, match="positive number of seconds"):
        sampled([1.0], [1.0], [1.0], 0.0)
    with pytest.raises(ValueError, match=r"DOF 0: a servo's inertia must be > 0"):
        sampled([1.0], [1.0], [0.0], 0.01)
    model = wheel[0]
    with pytest.raises(ValueError, match="nominal inertia must be > 0 on every actuated DOF"):
        StablePD(model, Target(), [0, 0, 0, 1.0], [0, 0, 0, 0.1], inertia=-1.0)


def test_unservoed_dofs_keep_the_plain_step():
    """Zero gains (the root): look-ahead 1, no implicit damping; a pure damper's
    ``I + dt D = Kd dt / (1 - exp(-Kd dt / I))``, its exact decay of velocity."""
    step = sampled([0.0, 0.0], [0.0, 3.0], [1.0, 2.0], 0.1)
    np.testing.assert_array_equal(step.look_ahead, [1.0, 1.0])
    assert step.damping[0] == 0.0
    assert 2.0 + 0.1 * step.damping[1] == pytest.approx(0.3 / -np.expm1(-0.15), rel=1e-14)
