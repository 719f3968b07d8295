"""The MuJoCo adapter against MuJoCo's own routines and finite differences of the kinematics."""

import pickle
import sys
import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import mujoco
import numpy as np
import pytest

import aquagait
from aquagait.body import Dynamics, load_model

CREATURES = Path(aquagait.__file__).resolve().parent / "creatures"
EPS = 1e-6  # finite-difference step: central differences err ~EPS^2, rounding ~1e-16/EPS


@pytest.fixture(scope="module")
def eel():
    return load_model(CREATURES / "eel2d.xml")


def random_state(model, dynamics, seed, speed=1.0):
    """A random configuration (reached by integrating from qpos0) and velocity."""
    rng = np.random.default_rng(seed)
    q = dynamics.integrate(model.qpos0, rng.normal(size=model.nv), 0.3)
    return q, speed * rng.normal(size=model.nv)


def mujoco_reference(model, q, qd, qacc):
    """M, c and M qacc + c from MuJoCo's full forward and inverse passes."""
    data = mujoco.MjData(model.mj)
    data.qpos[:], data.qvel[:], data.qacc[:] = q, qd, qacc
    mujoco.mj_forward(model.mj, data)
    mass = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model.mj, data, mass)
    bias = data.qfrc_bias.copy()
    data.qacc[:] = qacc
    mujoco.mj_inverse(model.mj, data)
    return mass, bias, data.qfrc_inverse.copy(), data


@pytest.mark.parametrize("which", ["snake", "eel"])
def test_mass_matrix_and_bias_match_mujoco(which, snake, eel):
    model = snake if which == "snake" else eel
    dynamics = Dynamics(model.mj)
    for seed in range(3):
        q, qd = random_state(model, dynamics, seed)
        qacc = np.random.default_rng(seed + 10).normal(size=model.nv)
        mass, bias, inverse, _ = mujoco_reference(model, q, qd, qacc)
        ours_mass, ours_bias = dynamics.mass_matrix(q), dynamics.bias(q, qd)
        np.testing.assert_allclose(ours_mass, mass, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(ours_bias, bias, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(ours_mass @ qacc + ours_bias, inverse, rtol=1e-10, atol=1e-13)


def test_mass_matrix_is_symmetric_positive_definite(snake, snake_dynamics):
    q, _ = random_state(snake, snake_dynamics, 1)
    mass = snake_dynamics.mass_matrix(q)
    np.testing.assert_allclose(mass, mass.T, atol=1e-15)
    assert np.linalg.eigvalsh(mass).min() > 0


def attached_points(model, dynamics, q, seed, count=20):
    """Random points rigidly attached to random links: (links, local offsets, world points)."""
    rng = np.random.default_rng(seed)
    links = rng.integers(0, dynamics.nlinks, size=count)
    local = 0.1 * rng.normal(size=(count, 3))
    return links, local, world_points(dynamics, q, links, local)


def world_points(dynamics, q, links, local):
    pos, rot = dynamics.link_poses(q)
    return pos[links] + np.einsum("nij,nj->ni", rot[links], local)


def test_point_jacobians_match_mj_jac(snake, snake_dynamics):
    q, _ = random_state(snake, snake_dynamics, 2)
    links, _, points = attached_points(snake, snake_dynamics, q, 3)
    ours = snake_dynamics.point_jacobians(q, points, links)
    data = mujoco.MjData(snake.mj)
    data.qpos[:] = q
    mujoco.mj_forward(snake.mj, data)
    for i, (point, link) in enumerate(zip(points, links, strict=True)):
        jacp = np.zeros((3, snake.nv))
        mujoco.mj_jac(snake.mj, data, jacp, None, point, int(link) + 1)
        np.testing.assert_allclose(ours[i], jacp, rtol=1e-12, atol=1e-14)


@pytest.mark.parametrize("which", ["snake", "eel"])
def test_point_velocities_match_finite_differences_of_positions(which, snake, eel):
    model = snake if which == "snake" else eel
    dynamics = Dynamics(model.mj)
    q, qd = random_state(model, dynamics, 4)
    links, local, points = attached_points(model, dynamics, q, 5)
    ahead = world_points(dynamics, dynamics.integrate(q, qd, EPS), links, local)
    behind = world_points(dynamics, dynamics.integrate(q, qd, -EPS), links, local)
    fd = (ahead - behind) / (2 * EPS)
    velocities = dynamics.point_velocities(q, qd, points, links)
    jacobians = dynamics.point_jacobians(q, points, links)
    np.testing.assert_allclose(velocities, fd, rtol=1e-7, atol=1e-8)
    np.testing.assert_allclose(np.einsum("nij,j->ni", jacobians, qd), velocities, atol=1e-14)


def test_angular_jacobians_match_finite_differences_of_rotations(snake, snake_dynamics):
    q, qd = random_state(snake, snake_dynamics, 6)
    _, rot_ahead = snake_dynamics.link_poses(snake_dynamics.integrate(q, qd, EPS))
    _, rot_behind = snake_dynamics.link_poses(snake_dynamics.integrate(q, qd, -EPS))
    _, jacr = snake_dynamics.link_jacobians(q)
    for k in range(snake_dynamics.nlinks):
        delta = rot_ahead[k] @ rot_behind[k].T  # small rotation by 2 EPS * omega
        omega = np.array([delta[2, 1] - delta[1, 2], delta[0, 2] - delta[2, 0],
                          delta[1, 0] - delta[0, 1]]) / (4 * EPS)  # fmt: skip
        np.testing.assert_allclose(jacr[k] @ qd, omega, rtol=1e-7, atol=1e-8)


def kinetic_energy_from_kinematics(model, dynamics, q, qd):
    """Sum over links of 1/2 m |v_com|^2 + 1/2 w.I w, velocities by finite differences."""
    data = mujoco.MjData(model.mj)

    def frames(qq):
        data.qpos[:] = qq
        mujoco.mj_kinematics(model.mj, data)
        return data.xipos[1:].copy(), data.ximat[1:].reshape(-1, 3, 3).copy()

    com_a, rot_a = frames(dynamics.integrate(q, qd, EPS))
    com_b, rot_b = frames(dynamics.integrate(q, qd, -EPS))
    com, rot = frames(q)
    v = (com_a - com_b) / (2 * EPS)
    delta = np.einsum("kij,klj->kil", rot_a, rot_b)
    w = np.stack([delta[:, 2, 1] - delta[:, 1, 2], delta[:, 0, 2] - delta[:, 2, 0],
                  delta[:, 1, 0] - delta[:, 0, 1]], axis=1) / (4 * EPS)  # fmt: skip
    w_body = np.einsum("kji,kj->ki", rot, w)  # principal inertia frame
    inertia = model.mj.body_inertia[1:]
    return 0.5 * (model.link_mass @ (v**2).sum(1) + (inertia * w_body**2).sum())


@pytest.mark.parametrize("which", ["snake", "eel"])
def test_mass_matrix_gives_the_kinetic_energy_of_the_kinematics(which, snake, eel):
    model = snake if which == "snake" else eel
    dynamics = Dynamics(model.mj)
    for seed in range(3):
        q, qd = random_state(model, dynamics, 20 + seed)
        expected = kinetic_energy_from_kinematics(model, dynamics, q, qd)
        assert 0.5 * qd @ dynamics.mass_matrix(q) @ qd == pytest.approx(expected, rel=1e-7)


def test_bias_matches_lagrange_equations_by_finite_differences(eel):
    """Planar coordinates are true generalized coordinates: c = Mdot qd - dT/dq."""
    dynamics = Dynamics(eel.mj)
    q, qd = random_state(eel, dynamics, 7)
    h = 1e-5
    mass_dot = (dynamics.mass_matrix(q + h * qd) - dynamics.mass_matrix(q - h * qd)) / (2 * h)
    grad = np.zeros(eel.nv)
    for i in range(eel.nv):
        step = h * np.eye(eel.nv)[i]
        grad[i] = 0.5 * qd @ (dynamics.mass_matrix(q + step) - dynamics.mass_matrix(q - step)) @ qd
    expected = mass_dot @ qd - grad / (2 * h)
    np.testing.assert_allclose(dynamics.bias(q, qd), expected, rtol=1e-6, atol=1e-9)


def test_free_motion_under_the_bias_conserves_momentum_and_energy(snake, snake_dynamics):
    """3D with quaternions: with qdd = -M^-1 c, d/dt of P, L and T vanish (central differences)."""
    dyn = snake_dynamics
    q, qd = random_state(snake, dyn, 8)
    qdd = -np.linalg.solve(dyn.mass_matrix(q), dyn.bias(q, qd))
    h = 1e-5

    def invariants(sign):
        qq, vv = dyn.integrate(q, qd, sign * h), qd + sign * h * qdd
        p, angular = dyn.momentum(qq, vv)
        return np.r_[p, angular, 0.5 * vv @ dyn.mass_matrix(qq) @ vv]

    rate = (invariants(1) - invariants(-1)) / (2 * h)
    scale = np.abs(invariants(1)).max() * np.abs(qd).max()
    assert np.abs(rate).max() < 1e-7 * scale
    # without the bias the same test fails: the check has teeth
    qdd = np.zeros(snake.nv)
    assert np.abs((invariants(1) - invariants(-1)) / (2 * h)).max() > 1e-2 * scale


def test_momentum_and_centre_of_mass_match_mujoco(snake, snake_dynamics):
    q, qd = random_state(snake, snake_dynamics, 9)
    _, _, _, data = mujoco_reference(snake, q, qd, np.zeros(snake.nv))
    mujoco.mj_subtreeVel(snake.mj, data)
    com = data.subtree_com[1]
    p_ref = snake.mass * data.subtree_linvel[1]
    l_ref = data.subtree_angmom[1] + np.cross(com, p_ref)  # about the origin, not the CoM
    p, angular = snake_dynamics.momentum(q, qd)
    np.testing.assert_allclose(snake_dynamics.center_of_mass(q), com, atol=1e-14)
    np.testing.assert_allclose(p, p_ref, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(angular, l_ref, rtol=1e-10, atol=1e-14)


def test_point_velocities_are_vectorized_over_many_points(snake, snake_dynamics):
    q, qd = random_state(snake, snake_dynamics, 10)
    links, local, points = attached_points(snake, snake_dynamics, q, 11, count=20000)
    velocities = snake_dynamics.point_velocities(q, qd, points, links)
    assert velocities.shape == (20000, 3)
    one = snake_dynamics.point_velocities(q, qd, points[:1], links[:1])
    np.testing.assert_allclose(velocities[0], one[0], atol=1e-15)


def test_integrate_keeps_quaternions_unit_and_difference_inverts_it(snake, snake_dynamics):
    q, qd = random_state(snake, snake_dynamics, 12, speed=5.0)
    moved = snake_dynamics.integrate(q, qd, 0.1)  # rotations under pi: invertible
    assert np.linalg.norm(moved[3:7]) == pytest.approx(1, abs=1e-12)
    assert np.linalg.norm(moved[7:11]) == pytest.approx(1, abs=1e-12)
    np.testing.assert_allclose(snake_dynamics.difference(moved, q, 0.1), qd, rtol=1e-9)


def test_dynamics_pickles_without_its_scratch_data(snake, snake_dynamics):
    q, _ = random_state(snake, snake_dynamics, 13)
    copy = pickle.loads(pickle.dumps(snake_dynamics))
    np.testing.assert_array_equal(copy.mass_matrix(q), snake_dynamics.mass_matrix(q))


def test_bad_arguments_say_what_is_expected(snake, snake_dynamics):
    with pytest.raises(ValueError, match=r"nq = 13"):
        snake_dynamics.mass_matrix(np.zeros(3))
    with pytest.raises(ValueError, match=r"link indices must lie in \[0, 4\)"):
        snake_dynamics.point_velocities(snake.qpos0, np.zeros(snake.nv), np.zeros((1, 3)), [7])


def test_threads_sharing_one_dynamics_get_their_serial_numbers(snake, snake_dynamics):
    """The MuJoCo scratch data and its cache belong to the thread (docs/development.md, "Layers").

    Two threads ask for M, c and point Jacobians at their own states, the
    interpreter switching between them every microsecond; with one scratch
    MjData for the object (as it was) one thread reads the other's kinematics.
    """
    states = [random_state(snake, snake_dynamics, seed) for seed in (21, 22)]
    points, links = np.array([[0.1, 0.0, 0.0], [0.0, 0.05, 0.02]]), np.array([0, 3])

    def ask(q, qd):
        d = snake_dynamics
        return [d.mass_matrix(q), d.bias(q, qd), d.point_jacobians(q, points, links)]

    serial = [ask(*state) for state in states]
    barrier = threading.Barrier(2)

    def many(state):
        barrier.wait()
        return [ask(*state) for _ in range(300)]

    before = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)
    try:
        with ThreadPoolExecutor(2) as pool:
            threaded = list(pool.map(many, states))
    finally:
        sys.setswitchinterval(before)
    for answers, expected in zip(threaded, serial, strict=True):
        for answer in answers:
            assert all(np.array_equal(a, e) for a, e in zip(answer, expected, strict=True))
