"""Pictures of the world, split into what is there and how it is seen.

* :class:`Scene`: the bodies (their faces at the current node positions, each flat-coloured
  or with a textured skin), rigid meshes (obstacles, plants, food), the seabed and the water's
  haze, all in the world frame, m.
* :class:`Camera`: a pinhole camera (image size, focal length, pose) that draws a scene
  through :mod:`animat.envs.render.raster`: the sand-tiled seabed, then the shadows and faces, flat
  shaded,
  through a depth buffer (per-pixel occlusion), then the water and its depth haze.

:class:`BodyRenderer` is the envs' third-person view: a camera that follows one body's centre of
mass from behind and to the side. The eyes (a later sensor) are cameras on the head looking at
the same scene.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from ..bodies.spec import BodySpec
from .raster import draw_picture, quads_to_triangles

FISH_COLOUR = (250, 140, 60)  # RGB
SHADOW_COLOUR = (25, 40, 45)
SHADOW_LIFT = 0.002  # m: shadows lie this far above the seabed (no fight for its pixels)
SAND = np.array([150.0, 135.0, 100.0])  # RGB of the seabed
WATER_TOP, WATER_BOTTOM = np.array([60.0, 130.0, 180.0]), np.array([8.0, 35.0, 70.0])
FAR = 40.0  # m: the seabed is not drawn beyond this (it has faded into the water by then)
NEAR = 0.01  # m: faces with a corner nearer to a camera than this are not drawn


def look_at(eye: np.ndarray, target: np.ndarray) -> np.ndarray:
    """(3, 3) rotation whose rows are the camera's right, down and forward axes (world frame)."""
    forward = target - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    return np.stack([right, down, forward])


class Frame(NamedTuple):
    """A scene prepared for one instant (:meth:`Scene.prepare`), shared by every camera that
    looks at it: world triangles (T, 3, 3) m, their shaded colours (T, 3) uint8, and the
    seabed and water of :class:`Scene`."""

    triangles: np.ndarray
    colours: np.ndarray
    seabed_z: float
    tile: float
    visibility: float


@dataclass
class Scene:
    """What there is to see: bodies at node positions, rigid meshes, the seabed and the water.

    Attributes:
        bodies: [(body, x (N, 3) m, colour)]: colour is RGB (3,) for a flat-coloured body, or a
            skin (4F, 3) from :func:`fish_skin` (each face drawn as 2 x 2 sub-faces).
        meshes: [(corners (F, 4, 3) m, RGB colour)]: rigid things (obstacles, plants, food), as
            quads (a triangle repeats a corner).
        seabed_z: the seabed's height, m (world frame).
        grid: the seabed's sand tiles, m.
        visibility: the water's haze, m: what is d away keeps exp(-d / visibility) of its
            colour.
    """

    bodies: list[tuple[BodySpec, np.ndarray, object]] = field(default_factory=list)
    meshes: list[tuple[np.ndarray, tuple[int, int, int]]] = field(default_factory=list)
    seabed_z: float = -0.3
    grid: float = 0.1
    visibility: float = 8.0
    light: np.ndarray = field(default_factory=lambda: np.array([0.3, -0.4, 0.87]))

    def add(self, body: BodySpec, x: np.ndarray, colour=FISH_COLOUR) -> Scene:
        self.bodies.append((body, x, colour))
        return self

    def add_mesh(self, corners: np.ndarray, colour) -> Scene:
        self.meshes.append((np.asarray(corners, float), colour))
        return self

    def _solids(self) -> tuple[list[np.ndarray], list[np.ndarray]]:
        """Quads (F, 4, 3) and their base colours (F, 3) of every body and mesh."""
        quads, colours = [], []
        for body, x, colour in self.bodies:
            faces, base = x[body.faces], np.asarray(colour, float)
            if base.ndim == 2:  # a skin: one colour per sub-face
                faces = subdivide(faces)
            quads.append(faces)
            colours.append(np.broadcast_to(base, (len(faces), 3)))
        for corners, colour in self.meshes:
            quads.append(corners)
            colours.append(np.broadcast_to(np.asarray(colour, float), (len(corners), 3)))
        return quads, colours

    def prepare(self) -> Frame:
        """This instant's triangles: every face flat-shaded by the light, and the bodies'
        shadows just above the seabed (compute once per frame and hand to
        :meth:`Camera.draw`)."""
        quads, base = self._solids()
        if not quads:
            return Frame(np.zeros((0, 3, 3)), np.zeros((0, 3), np.uint8), self.seabed_z,
                         self.grid, self.visibility)
        quads, base = np.concatenate(quads), np.concatenate(base)
        shadow = np.concatenate([np.zeros((0, 4, 3))]
                                + [x[body.faces] for body, x, _ in self.bodies])
        shadow[..., 2] = self.seabed_z + SHADOW_LIFT
        colours = np.concatenate([np.tile(np.uint8(SHADOW_COLOUR), (len(shadow), 1)),
                                  shade(quads, base, self.light)])
        return Frame(quads_to_triangles(np.concatenate([shadow, quads])),
                     np.concatenate([colours, colours]), self.seabed_z, self.grid,
                     self.visibility)


def shade(quads: np.ndarray, base: np.ndarray, light: np.ndarray) -> np.ndarray:
    """(..., 3) uint8: quads (..., 4, 3) m of base colours (..., 3) RGB, flat-shaded by the
    ``light`` (3,) direction (a quarter of the light is ambient)."""
    u, v = quads[..., 2, :] - quads[..., 0, :], quads[..., 3, :] - quads[..., 1, :]
    # u x v and its length, with np.cross's and np.linalg.norm's arithmetic in fewer passes
    normals = np.empty(u.shape)
    normals[..., 0] = u[..., 1] * v[..., 2] - u[..., 2] * v[..., 1]
    normals[..., 1] = u[..., 2] * v[..., 0] - u[..., 0] * v[..., 2]
    normals[..., 2] = u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
    x, y, z = normals[..., 0], normals[..., 1], normals[..., 2]
    normals /= np.maximum(np.sqrt(x * x + y * y + z * z), 1e-12)[..., None]
    lit = 0.35 + 0.65 * np.maximum(0.0, normals @ light)
    return np.minimum(lit[..., None] * base, 255.0).astype(np.uint8)


_HALF = np.array([[1, 0, 0, 0], [.5, .5, 0, 0], [.25, .25, .25, .25], [.5, 0, 0, .5],
                  [.5, .5, 0, 0], [0, 1, 0, 0], [0, .5, .5, 0], [.25, .25, .25, .25],
                  [.25, .25, .25, .25], [0, .5, .5, 0], [0, 0, 1, 0], [0, 0, .5, .5],
                  [.5, 0, 0, .5], [.25, .25, .25, .25], [0, 0, .5, .5], [0, 0, 0, 1]])


def subdivide(quads: np.ndarray) -> np.ndarray:
    """(F, 4, 3) quads (corners a, b, c, d) -> (4F, 4, 3): each split into 2 x 2 by its edge
    midpoints and centre (face k's four parts are rows 4k .. 4k + 3)."""
    return (_HALF @ quads).reshape(-1, 4, 3)


def fish_skin(body: BodySpec, colour) -> np.ndarray:
    """(4F, 3) RGB per sub-face (:func:`subdivide`): ``colour`` countershaded (darker on the
    back, lighter on the belly, by the rest-shape face normal) with dark bands every sixth
    of the body length and a light checker between sub-faces: texture for optical flow."""
    rest = subdivide(body.rest_positions[body.faces])
    centres = rest.mean(axis=1)
    normals = np.cross(rest[:, 2] - rest[:, 0], rest[:, 3] - rest[:, 1])
    up = normals[:, 2] / np.maximum(np.linalg.norm(normals, axis=1), 1e-12)
    along = (body.rest_positions[0, 0] - centres[:, 0]) / body.length  # 0 nose .. 1 tail
    bands = 1.0 - 0.3 * (np.cos(2 * np.pi * 6 * along) > 0.5)
    checker = 1.0 + 0.12 * (np.arange(len(rest)) % 2)
    brightness = (1.0 - 0.18 * up) * bands * checker
    return np.minimum(brightness[:, None] * np.asarray(colour, float), 255.0)


def yaw_matrix(yaw: float) -> np.ndarray:
    """(3, 3) rotation by ``yaw`` rad about the world's z axis (positive: to the left)."""
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def posed(body: BodySpec, centre, yaw: float = 0.0) -> np.ndarray:
    """(N, 3) node positions, m: the body's rest shape with the mean of its nodes at
    ``centre`` (3,), turned by ``yaw`` about z (0: heading +x). For staging scenes."""
    x = body.rest_positions - body.rest_positions.mean(axis=0)
    return x @ yaw_matrix(yaw).T + np.asarray(centre, float)


BOX_FACES = np.array([(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (1, 2, 6, 5),
                      (0, 4, 7, 3)])  # quads of box_corners, ordered so normals point out


def box_corners(centre, size) -> np.ndarray:
    """(8, 3) corners of an axis-aligned box: the bottom four, then the top four."""
    signs = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                      [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]])
    return np.asarray(centre, float) + signs * 0.5 * np.asarray(size, float)


def box(centre, size) -> np.ndarray:
    """(6, 4, 3) the faces of an axis-aligned box, corners ordered so normals point out."""
    return box_corners(centre, size)[BOX_FACES]


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

    def render(self, scene: Scene) -> np.ndarray:
        """(height, width, 3) uint8 RGB picture of ``scene``."""
        return self.draw(scene.prepare())

    def draw(self, frame: Frame) -> np.ndarray:
        """The picture of a prepared scene: the seabed (ray-cast), then the triangles through
        the depth buffer (:func:`animat.envs.render.raster.rasterize`), then the water and its
        haze."""
        image = np.empty((self.height, self.width, 3), np.uint8)
        draw_picture(frame.triangles, frame.colours, np.asarray(self.eye, float),
                     np.ascontiguousarray(self.rotation, float), float(self.focal),
                     float(frame.seabed_z), float(frame.tile), float(frame.visibility), SAND,
                     WATER_TOP, WATER_BOTTOM, FAR, NEAR, image)
        return image


class BodyRenderer:
    """Renders (height, width, 3) uint8 RGB frames of one body, seen by a camera that follows
    its centre of mass from behind and to the side.

    Args:
        body: the body description (its faces are drawn).
        width, height: image size, pixels.
        seabed_depth: the seabed's distance below the start depth, m.
        grid: the seabed's sand tiles, m.
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
        return camera.render(scene)
