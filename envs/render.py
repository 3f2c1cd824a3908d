"""Pictures of the world (OpenCV), split into what is there and how it is seen.

* :class:`Scene`: the bodies (their faces at the current node positions, each with a colour)
  and the seabed, all in the world frame, m.
* :class:`Camera`: a pinhole camera (image size, focal length, pose) that rasterises a scene:
  water background, seabed grid, then the bodies' shadows on the seabed and their faces, flat
  shaded, through a depth buffer (:mod:`envs.raster`, per-pixel occlusion).

:class:`BodyRenderer` is the envs' third-person view: a camera that follows one body's centre of
mass from behind and to the side. The eyes (a later sensor) are cameras on the head looking at
the same scene.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np

from envs.body import BodySpec
from envs.raster import quads_to_triangles, rasterize

FISH_COLOUR = (250, 140, 60)  # RGB
SHADOW_COLOUR = (25, 40, 45)
NEAR = 0.01  # m: faces with a corner nearer to a camera than this are not drawn


def look_at(eye: np.ndarray, target: np.ndarray) -> np.ndarray:
    """(3, 3) rotation whose rows are the camera's right, down and forward axes (world frame)."""
    forward = target - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    return np.stack([right, down, forward])


@dataclass
class Scene:
    """What there is to see: bodies at node positions, and a seabed grid.

    Attributes:
        bodies: [(body, x (N, 3) m, RGB colour)].
        seabed_z: the seabed's height, m (world frame).
        grid: seabed grid spacing, m.
    """

    bodies: list[tuple[BodySpec, np.ndarray, tuple[int, int, int]]] = field(default_factory=list)
    seabed_z: float = -0.3
    grid: float = 0.1

    def add(self, body: BodySpec, x: np.ndarray, colour=FISH_COLOUR) -> Scene:
        self.bodies.append((body, x, colour))
        return self


@dataclass
class Camera:
    """A pinhole camera: ``width`` x ``height`` pixels, ``focal`` length in pixels, at ``eye``
    (3,) m with ``rotation`` (3, 3) rows right, down, forward (:func:`look_at`)."""

    width: int
    height: int
    focal: float
    eye: np.ndarray
    rotation: np.ndarray
    light: np.ndarray = field(default_factory=lambda: np.array([0.3, -0.4, 0.87]))

    def project(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pixels (..., 2) and depths (..., ) of world points (..., 3)."""
        cam = (points - self.eye) @ self.rotation.T
        depth = cam[..., 2]
        safe = np.maximum(depth, 1e-6)
        pixels = np.stack([self.width / 2 + self.focal * cam[..., 0] / safe,
                           self.height / 2 + self.focal * cam[..., 1] / safe], axis=-1)
        return pixels, depth

    def render(self, scene: Scene, centre: np.ndarray) -> np.ndarray:
        """(height, width, 3) uint8 RGB picture of ``scene``, the seabed grid drawn around
        ``centre`` (3,) m: background and grid first, then the shadows and the bodies' faces
        through the depth buffer (:func:`envs.raster.rasterize`)."""
        image = self._background()
        self._draw_seabed(image, scene, centre)
        zbuffer = np.full((self.height, self.width), np.inf)
        corners, colours = self._faces(scene)
        if len(corners):
            triangles = quads_to_triangles(corners)
            pixels, depth = self.project(triangles)
            rasterize(pixels, depth, np.concatenate([colours, colours]), image, zbuffer, NEAR)
        return image

    def _faces(self, scene: Scene) -> tuple[np.ndarray, np.ndarray]:
        """(F, 4, 3) world corners of every body's faces and of their shadows on the seabed,
        and (F, 3) uint8 flat-shaded colours."""
        corners, colours = [], []
        for body, x, colour in scene.bodies:
            quads = x[body.faces]
            shadow = quads.copy()
            shadow[..., 2] = scene.seabed_z
            normals = np.cross(quads[:, 2] - quads[:, 0], quads[:, 3] - quads[:, 1])
            normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
            shade = 0.35 + 0.65 * np.maximum(0.0, normals @ self.light)
            corners += [shadow, quads]
            colours += [np.tile(SHADOW_COLOUR, (len(quads), 1)),
                        (shade[:, None] * np.array(colour, float)).astype(np.uint8)]
        if not corners:
            return np.zeros((0, 4, 3)), np.zeros((0, 3), np.uint8)
        return np.concatenate(corners), np.concatenate(colours).astype(np.uint8)

    def _background(self) -> np.ndarray:
        rows = (np.arange(self.height) + 0.5)[:, None] / self.height
        top, bottom = np.array([40, 110, 170.0]), np.array([10, 40, 80.0])
        column = (1 - rows) * top + rows * bottom
        return np.repeat(column[:, None, :], self.width, axis=1).astype(np.uint8)

    def _draw_seabed(self, image, scene: Scene, centre) -> None:
        grid, z = scene.grid, scene.seabed_z
        span = 8 * grid
        start = np.floor((centre[:2] - span) / grid) * grid
        ticks = np.arange(0, 2 * span + 1e-9, grid)
        for axis in (0, 1):
            for tick in ticks:
                a, b = np.zeros(3), np.zeros(3)
                a[axis] = b[axis] = start[axis] + tick
                a[1 - axis], b[1 - axis] = start[1 - axis], start[1 - axis] + 2 * span
                a[2] = b[2] = z
                (pa, pb), (da, db) = self.project(np.stack([a, b]))
                if da > NEAR and db > NEAR:
                    cv2.line(image, tuple(np.int32(pa)), tuple(np.int32(pb)), (90, 130, 140), 1,
                             cv2.LINE_AA)


class BodyRenderer:
    """Renders (height, width, 3) uint8 RGB frames of one body, seen by a camera that follows
    its centre of mass from behind and to the side.

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

    def render(self, x: np.ndarray) -> np.ndarray:
        """(height, width, 3) uint8 picture of the body with node positions ``x`` (N, 3), m."""
        centre = (self.body.masses[:, None] * x).sum(axis=0) / self.body.total_mass
        eye = centre + self.offset
        camera = Camera(self.width, self.height, self.focal, eye, look_at(eye, centre))
        scene = Scene(seabed_z=self.seabed_z, grid=self.grid).add(self.body, x)
        return camera.render(scene, centre)
