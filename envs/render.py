"""Third-person picture of a body in water (OpenCV): the deforming hydrodynamic faces, flat
shaded and depth sorted, over a world-fixed seabed grid with the body's shadow, seen by a
camera that follows the centre of mass from behind and to the side."""

from __future__ import annotations

import cv2
import numpy as np

from envs.body import BodySpec


def look_at(eye: np.ndarray, target: np.ndarray) -> np.ndarray:
    """(3, 3) rotation whose rows are the camera's right, down and forward axes (world frame)."""
    forward = target - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    return np.stack([right, down, forward])


class BodyRenderer:
    """Renders (height, width, 3) uint8 RGB frames of one body.

    Args:
        body: the body description (its faces are drawn).
        width, height: image size, pixels.
        seabed_depth: the seabed's distance below the start depth, m.
        grid: seabed grid spacing, m.
    """

    def __init__(self, body: BodySpec, width: int = 480, height: int = 360,
                 seabed_depth: float = 0.3, grid: float = 0.1) -> None:
        self.body, self.width, self.height = body, int(width), int(height)
        self.seabed_z, self.grid = -float(seabed_depth), float(grid)
        self.focal = 0.9 * self.width
        self.offset = np.array([-1.2, -2.4, 1.0]) * body.length
        self.light = np.array([0.3, -0.4, 0.87])

    def _project(self, points: np.ndarray, eye: np.ndarray, rot: np.ndarray):
        cam = (points - eye) @ rot.T
        depth = cam[..., 2]
        safe = np.maximum(depth, 1e-6)
        pixels = np.stack([self.width / 2 + self.focal * cam[..., 0] / safe,
                           self.height / 2 + self.focal * cam[..., 1] / safe], axis=-1)
        return pixels, depth

    def _background(self) -> np.ndarray:
        rows = np.linspace(0.0, 1.0, self.height)[:, None]
        top, bottom = np.array([40, 110, 170.0]), np.array([10, 40, 80.0])
        column = (1 - rows) * top + rows * bottom
        return np.repeat(column[:, None, :], self.width, axis=1).astype(np.uint8)

    def _draw_seabed(self, image, centre, eye, rot) -> None:
        span, z = 8 * self.grid, self.seabed_z
        start = np.floor((centre[:2] - span) / self.grid) * self.grid
        ticks = np.arange(0, 2 * span + 1e-9, self.grid)
        for axis in (0, 1):
            for tick in ticks:
                a, b = np.zeros(3), np.zeros(3)
                a[axis] = b[axis] = start[axis] + tick
                a[1 - axis], b[1 - axis] = start[1 - axis], start[1 - axis] + 2 * span
                a[2] = b[2] = z
                (pa, pb), (da, db) = self._project(np.stack([a, b]), eye, rot)
                if da > 0.05 and db > 0.05:
                    cv2.line(image, tuple(np.int32(pa)), tuple(np.int32(pb)), (90, 130, 140), 1,
                             cv2.LINE_AA)

    def _draw_faces(self, image, x, eye, rot, shadow: bool) -> None:
        faces = self.body.faces
        corners = x[faces]  # (F, 4, 3)
        if shadow:
            corners = corners.copy()
            corners[..., 2] = self.seabed_z
        pixels, depth = self._project(corners, eye, rot)
        normals = np.cross(corners[:, 2] - corners[:, 0], corners[:, 3] - corners[:, 1])
        normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
        order = np.argsort(-depth.mean(axis=1))
        for k in order:
            if np.any(depth[k] <= 0.05):
                continue
            if shadow:
                colour = (25, 40, 45)
            else:
                shade = 0.35 + 0.65 * max(0.0, float(normals[k] @ self.light))
                colour = tuple(int(c * shade) for c in (250, 140, 60))
            cv2.fillPoly(image, [np.int32(np.round(pixels[k]))], colour, cv2.LINE_AA)

    def render(self, x: np.ndarray) -> np.ndarray:
        """(height, width, 3) uint8 picture of the body with node positions ``x`` (N, 3), m."""
        centre = (self.body.masses[:, None] * x).sum(axis=0) / self.body.total_mass
        eye = centre + self.offset
        rot = look_at(eye, centre)
        image = self._background()
        self._draw_seabed(image, centre, eye, rot)
        self._draw_faces(image, x, eye, rot, shadow=True)
        self._draw_faces(image, x, eye, rot, shadow=False)
        return image
