"""Quaternions and rotation vectors: exact rotations, inverses and the group identities."""

import numpy as np
import pytest

from aquagait.body.rotations import quat_conj, quat_exp, quat_from_matrix, quat_log, quat_mul

IDENTITY = np.array([1.0, 0, 0, 0])


def rotate(q, v):
    """The vector ``v`` (3,) rotated by unit quaternion ``q``: the vector part of q (0, v) q*."""
    return quat_mul(quat_mul(q, np.r_[0.0, v]), quat_conj(q))[1:]


def rotation_vectors(count=8, seed=0):
    """Random rotation vectors with angles spread over (0, pi)."""
    rng = np.random.default_rng(seed)
    axes = rng.normal(size=(count, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    return axes * rng.uniform(0.01, np.pi - 0.01, size=(count, 1))


def test_exp_and_log_are_inverse():
    for r in rotation_vectors():
        q = quat_exp(r)
        assert np.linalg.norm(q) == pytest.approx(1.0, abs=1e-15)
        np.testing.assert_allclose(quat_log(q), r, atol=1e-12)
        np.testing.assert_allclose(quat_exp(quat_log(q)), q, atol=1e-15)
    np.testing.assert_allclose(quat_log(quat_exp(np.zeros(3))), 0.0, atol=0)
    tiny = np.array([1e-14, -2e-14, 3e-14])  # below the small-angle switch: first order is exact
    np.testing.assert_allclose(quat_log(quat_exp(tiny)), tiny, rtol=1e-12)


def test_log_takes_the_short_way_round():
    # q and -q are the same rotation; the log of either has an angle in [0, pi]
    for r in rotation_vectors(seed=1):
        q = quat_exp(r)
        np.testing.assert_allclose(quat_log(-q), r, atol=1e-12)
    beyond = np.array([0, 0, 1.5 * np.pi])  # 270 degrees about z is 90 degrees about -z
    np.testing.assert_allclose(quat_log(quat_exp(beyond)), [0, 0, -0.5 * np.pi], atol=1e-12)


def test_a_quarter_turn_about_z_maps_x_to_y():
    q = quat_exp([0, 0, np.pi / 2])
    np.testing.assert_allclose(q, [np.sqrt(0.5), 0, 0, np.sqrt(0.5)], atol=1e-15)
    np.testing.assert_allclose(rotate(q, [1, 0, 0]), [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(rotate(q, [0, 0, 2]), [0, 0, 2], atol=1e-15)


def test_rotation_matches_rodrigues_formula():
    rng = np.random.default_rng(2)
    for r in rotation_vectors(seed=2):
        v = rng.normal(size=3)
        angle, n = np.linalg.norm(r), r / np.linalg.norm(r)
        expected = (
            v * np.cos(angle) + np.cross(n, v) * np.sin(angle) + n * (n @ v) * (1 - np.cos(angle))
        )
        np.testing.assert_allclose(rotate(quat_exp(r), v), expected, atol=1e-14)


def test_product_and_conjugate_obey_the_group_identities():
    a, b, c = (quat_exp(r) for r in rotation_vectors(3, seed=3))
    np.testing.assert_allclose(quat_mul(quat_conj(a), a), IDENTITY, atol=1e-15)
    np.testing.assert_allclose(quat_mul(a, quat_conj(a)), IDENTITY, atol=1e-15)
    np.testing.assert_allclose(quat_mul(IDENTITY, a), a, atol=0)
    np.testing.assert_allclose(quat_mul(a, IDENTITY), a, atol=0)
    np.testing.assert_allclose(quat_conj(quat_conj(a)), a, atol=0)
    np.testing.assert_allclose(
        quat_conj(quat_mul(a, b)), quat_mul(quat_conj(b), quat_conj(a)), atol=1e-15
    )
    np.testing.assert_allclose(quat_mul(quat_mul(a, b), c), quat_mul(a, quat_mul(b, c)), atol=1e-15)
    # a * b rotates by b first, then by a
    v = np.array([0.3, -1.2, 0.7])
    np.testing.assert_allclose(rotate(quat_mul(a, b), v), rotate(a, rotate(b, v)), atol=1e-14)


def test_rotations_about_one_axis_add_their_angles():
    n = np.array([2.0, -1.0, 0.5]) / np.linalg.norm([2.0, -1.0, 0.5])
    product = quat_mul(quat_exp(0.4 * n), quat_exp(1.1 * n))
    np.testing.assert_allclose(quat_log(product), 1.5 * n, atol=1e-14)


def test_quaternions_from_matrices_rotate_as_the_matrices_do():
    rng = np.random.default_rng(3)
    vectors = rng.normal(size=(5, 3))
    quats = np.array([quat_exp(v) for v in vectors])
    quats *= np.sign(quats[:, :1])
    mats = np.array([np.stack([rotate(q, e) for e in np.eye(3)], axis=1) for q in quats])
    np.testing.assert_allclose(quat_from_matrix(mats), quats, atol=1e-12)
    assert quat_from_matrix(np.eye(3)).tolist() == [1.0, 0.0, 0.0, 0.0]
