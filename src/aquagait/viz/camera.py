"""The 3D pictures' camera: a pinhole, its matrices, the views that frame a swimmer.

Image convention (``project``, ``aquagait.viz.gl.Renderer.draw``): x to the
right and y down from the top-left corner; pixel ``[row, col]`` covers x in
[col, col + 1) and y in [row, row + 1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

VIEWS = {
    "side": (np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0])),
    "top": (np.array([0.0, 0.0, -1.0]), np.array([0.0, 1.0, 0.0])),
    "follow": (np.array([1.0, 1.0, -0.7]) / math.sqrt(2.49), np.array([0.0, 0.0, 1.0])),
    "side-above": (np.array([0.25, 1.0, -0.6]) / math.sqrt(1.4225), np.array([0.0, 0.0, 1.0])),
    "front-above": (np.array([-0.8, 0.35, -0.7]) / math.sqrt(1.2525), np.array([0.0, 0.0, 1.0])),
}
"""Per view: the direction the camera looks and the world direction that is up
on screen. 'side' looks along +y (a fish swimming along +x faces right, z up),
'top' looks down -z with +y up, 'follow' looks from behind (-x), beside (-y)
and above (+z); 'side-above' from the side and above, a little behind (a
turtle's flippers); 'front-above' from in front, above and a little beside
(a ray's wings)."""


@dataclass(frozen=True)
class Camera:
    """A pinhole camera: ``eye``, ``target`` and ``up`` (3,) [m, world], vertical ``fov`` [deg].

    Clipping planes sit at 1/50 and 50 times the eye-target distance.
    """

    eye: np.ndarray
    target: np.ndarray
    up: np.ndarray
    fov: float = 30.0

    def __post_init__(self):
        for name in ("eye", "target", "up"):
            object.__setattr__(self, name, np.asarray(getattr(self, name), dtype=float))

    def basis(self) -> np.ndarray:
        """(3, 3) rows: the screen's right, up, and the viewing direction, unit, world."""
        forward = unit(self.target - self.eye)
        right = unit(np.cross(forward, self.up))
        return np.stack([right, np.cross(right, forward), forward])

    def view_matrix(self) -> np.ndarray:
        """(4, 4) world to camera coordinates (OpenGL: the camera looks down -z)."""
        right, up, forward = self.basis()
        rotation = np.stack([right, up, -forward])
        view = np.eye(4)
        view[:3, :3], view[:3, 3] = rotation, -rotation @ self.eye
        return view

    def projection_matrix(self, aspect: float) -> np.ndarray:
        """(4, 4) camera to clip coordinates, ``aspect`` = width / height (OpenGL's perspective)."""
        distance = float(np.linalg.norm(self.target - self.eye))
        near, far = distance / 50, distance * 50
        f = 1 / math.tan(math.radians(self.fov) / 2)
        return np.array([[f / aspect, 0, 0, 0], [0, f, 0, 0],
                         [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)],
                         [0, 0, -1, 0]])  # fmt: skip


def view_camera(
    view: str, center, extent, aspect: float, fov: float = 30.0, fill: float = 0.85
) -> Camera:
    """A camera that looks at a box from one of ``VIEWS`` and frames it.

    The eye backs off along the view direction until every corner of the box
    lies within ``fill`` of the half-width and half-height of the picture.

    Args:
        view: one of ``VIEWS``.
        center: (3,) the box's centre [m]; the camera looks at it.
        extent: (3,) the box's sides [m].
        aspect: picture width / height.
        fov: vertical field of view [deg].
        fill: the share of the picture's half-sides the box may reach.
    """
    if view not in VIEWS:
        raise ValueError(f"unknown view {view!r}; choose one of {', '.join(VIEWS)}")
    forward, up = VIEWS[view]
    right = unit(np.cross(forward, up))
    screen_up = np.cross(right, forward)
    corners = (
        np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
        * np.asarray(extent)
        / 2
    )
    tan_y = fill * math.tan(math.radians(fov) / 2)
    # a corner at depth d + c.forward is inside if |c.right| <= tan_x (d + c.forward)
    depth = corners @ forward
    needed = np.concatenate([np.abs(corners @ right) / (tan_y * aspect) - depth,
                             np.abs(corners @ screen_up) / tan_y - depth])  # fmt: skip
    distance = max(float(needed.max()), 1e-6)
    center = np.asarray(center, dtype=float)
    return Camera(eye=center - distance * forward, target=center, up=up, fov=fov)


def project(camera: Camera, points, width: int, height: int) -> np.ndarray:
    """Where world ``points`` (N, 3) [m] land in a ``width`` x ``height`` picture.

    Returns:
        (N, 2) pixel coordinates: x to the right, y down from the top-left corner
        (the centre of pixel ``[row, col]`` is ``(col + 0.5, row + 0.5)``).
    """
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    transform = camera.projection_matrix(width / height) @ camera.view_matrix()
    clip = np.c_[points, np.ones(len(points))] @ transform.T
    ndc = clip[:, :2] / clip[:, 3:]
    return np.stack([(ndc[:, 0] + 1) / 2 * width, (1 - ndc[:, 1]) / 2 * height], -1)


def unit(vector) -> np.ndarray:
    """``vector`` scaled to length 1."""
    vector = np.asarray(vector, dtype=float)
    return vector / np.linalg.norm(vector)
