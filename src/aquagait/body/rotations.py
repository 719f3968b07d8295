"""Unit quaternions (w, x, y, z), MuJoCo's convention, rotation vectors and matrices.

A rotation by angle ``a`` [rad] about unit axis ``n`` is the quaternion
``(cos(a/2), sin(a/2) n)`` and the rotation vector (exponential map) ``a n``.
``quat_exp`` and ``quat_log`` convert between them; ``quat_log`` takes the
short way round (angle in [0, pi]), so ``quat_log(quat_exp(r)) == r`` for
``|r| <= pi``. Used by the ball-joint servos (docs/method-bodies.md) and by the
objective's change of orientation (docs/method-search.md, ``E_deviation``).
"""

from __future__ import annotations

import numpy as np


def quat_mul(a, b) -> np.ndarray:
    """Hamilton product ``a * b`` of quaternions (4,): rotate by ``b``, then by ``a``."""
    aw, av, bw, bv = a[0], np.asarray(a[1:]), b[0], np.asarray(b[1:])
    return np.r_[aw * bw - av @ bv, aw * bv + bw * av + np.cross(av, bv)]


def quat_conj(q) -> np.ndarray:
    """Conjugate of a quaternion (4,): the inverse of a unit quaternion."""
    return np.r_[q[0], -np.asarray(q[1:])]


def quat_exp(r) -> np.ndarray:
    """Unit quaternion (4,) of rotation vector ``r`` (3,) [rad]."""
    angle = np.linalg.norm(r)
    if angle < 1e-12:
        return np.r_[1.0, 0.5 * np.asarray(r)]
    return np.r_[np.cos(angle / 2), np.sin(angle / 2) * np.asarray(r) / angle]


def quat_log(q) -> np.ndarray:
    """Rotation vector (3,) [rad] of a unit quaternion (4,), the short way round."""
    q = np.asarray(q, dtype=float) * (1 if q[0] >= 0 else -1)
    s = np.linalg.norm(q[1:])
    if s < 1e-12:
        return 2 * q[1:]
    return 2 * np.arctan2(s, q[0]) * q[1:] / s


def quat_from_matrix(rot) -> np.ndarray:
    """Unit quaternions (..., 4), w >= 0, of rotation matrices (..., 3, 3)."""
    from scipy.spatial.transform import Rotation

    rot = np.asarray(rot, dtype=float)
    xyzw = Rotation.from_matrix(rot.reshape(-1, 3, 3)).as_quat()
    wxyz = np.concatenate([xyzw[:, 3:], xyzw[:, :3]], axis=1)
    wxyz *= np.where(wxyz[:, :1] < 0, -1.0, 1.0)
    return wxyz.reshape(*rot.shape[:-2], 4)
