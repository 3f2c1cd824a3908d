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
from envs.raster import quads_to_triangles, rasterize_world

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
        meshes: [(corners (F, 4, 3) m, RGB colour)]: rigid things (obstacles, food), as quads
            (a triangle repeats a corner).
        seabed_z: the seabed's height, m (world frame).
        grid: seabed grid spacing, m.
    """

    bodies: list[tuple[BodySpec, np.ndarray, tuple[int, int, int]]] = field(default_factory=list)
    meshes: list[tuple[np.ndarray, tuple[int, int, int]]] = field(default_factory=list)
    seabed_z: float = -0.3
    grid: float = 0.1
    light: np.ndarray = field(default_factory=lambda: np.array([0.3, -0.4, 0.87]))

    def add(self, body: BodySpec, x: np.ndarray, colour=FISH_COLOUR) -> Scene:
        self.bodies.append((body, x, colour))
        return self

    def add_mesh(self, corners: np.ndarray, colour) -> Scene:
        self.meshes.append((np.asarray(corners, float), colour))
        return self

    def triangles(self) -> tuple[np.ndarray, np.ndarray]:
        """(T, 3, 3) world triangles of every face and of its shadow on the seabed, and
        (T, 3) uint8 their flat-shaded colours (the same for every camera: compute once per
        frame and hand to :meth:`Camera.draw`)."""
        things = [(x[body.faces], colour) for body, x, colour in self.bodies] + self.meshes
        if not things:
            return np.zeros((0, 3, 3)), np.zeros((0, 3), np.uint8)
        quads = np.concatenate([q for q, _ in things])
        base = np.concatenate([np.tile(np.array(c, float), (len(q), 1)) for q, c in things])
        shadow = quads.copy()
        shadow[..., 2] = self.seabed_z
        normals = np.cross(quads[:, 2] - quads[:, 0], quads[:, 3] - quads[:, 1])
        normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
        shade = 0.35 + 0.65 * np.maximum(0.0, normals @ self.light)
        colours = np.concatenate([np.tile(SHADOW_COLOUR, (len(quads), 1)),
                                  shade[:, None] * base]).astype(np.uint8)
        return (quads_to_triangles(np.concatenate([shadow, quads])),
                np.concatenate([colours, colours]))

    def grid_segments(self, centre: np.ndarray) -> np.ndarray:
        """(G, 2, 3) the seabed grid lines within 8 spacings of ``centre`` (3,) m."""
        span, z = 8 * self.grid, self.seabed_z
        start = np.floor((np.asarray(centre)[:2] - span) / self.grid) * self.grid
        ticks = np.arange(0, 2 * span + 1e-9, self.grid)
        segments = []
        for axis in (0, 1):
            a = np.zeros((len(ticks), 3))
            a[:, axis] = start[axis] + ticks
            a[:, 1 - axis] = start[1 - axis]
            a[:, 2] = z
            b = a.copy()
            b[:, 1 - axis] += 2 * span
            segments.append(np.stack([a, b], axis=1))
        return np.concatenate(segments)


def yaw_matrix(yaw: float) -> np.ndarray:
    """(3, 3) rotation by ``yaw`` rad about the world's z axis (positive: to the left)."""
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def posed(body: BodySpec, centre, yaw: float = 0.0) -> np.ndarray:
    """(N, 3) node positions, m: the body's rest shape with the mean of its nodes at
    ``centre`` (3,), turned by ``yaw`` about z (0: heading +x). For staging scenes."""
    x = body.rest_positions - body.rest_positions.mean(axis=0)
    return x @ yaw_matrix(yaw).T + np.asarray(centre, float)


def box(centre, size) -> np.ndarray:
    """(6, 4, 3) the faces of an axis-aligned box, corners ordered so normals point out."""
    c, h = np.asarray(centre, float), 0.5 * np.asarray(size, float)
    signs = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                      [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]])
    corners = c + signs * h
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (1, 2, 6, 5), (0, 4, 7, 3)]
    return corners[np.array(faces)]


@dataclass
class Camera:
    """A pinhole camera: ``width`` x ``height`` pixels, ``focal`` length in pixels, at ``eye``
    (3,) m with ``rotation`` (3, 3) rows right, down, forward (:func:`look_at`)."""

    width: int
    height: int
    focal: float
    eye: np.ndarray
    rotation: np.ndarray

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
        ``centre`` (3,) m."""
        return self.draw(*scene.triangles(), scene.grid_segments(centre))

    def draw(self, triangles: np.ndarray, colours: np.ndarray, segments: np.ndarray
             ) -> np.ndarray:
        """The picture of prepared geometry (:meth:`Scene.triangles`,
        :meth:`Scene.grid_segments`): background and grid lines first, then the triangles
        through the depth buffer (:func:`envs.raster.rasterize`)."""
        image = self._background()
        pixels, depth = self.project(segments)
        for (a, b), (da, db) in zip(np.int32(pixels), depth):
            if da > NEAR and db > NEAR:
                cv2.line(image, tuple(a), tuple(b), (90, 130, 140), 1, cv2.LINE_AA)
        if len(triangles):
            zbuffer = np.full((self.height, self.width), np.inf)
            rasterize_world(triangles, colours, np.asarray(self.eye, float),
                            np.ascontiguousarray(self.rotation, float), float(self.focal), image,
                            zbuffer, NEAR)
        return image

    def _background(self) -> np.ndarray:
        key = (self.width, self.height)
        if key not in _BACKGROUNDS:
            rows = (np.arange(self.height) + 0.5)[:, None] / self.height
            top, bottom = np.array([40, 110, 170.0]), np.array([10, 40, 80.0])
            column = (1 - rows) * top + rows * bottom
            _BACKGROUNDS[key] = np.repeat(column[:, None, :], self.width, axis=1).astype(np.uint8)
        return _BACKGROUNDS[key].copy()


_BACKGROUNDS: dict[tuple[int, int], np.ndarray] = {}


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
