"""Pictures of the air-water world: the dolphin, its beach ball and support, the sky, the water
surface and the water below it, seen from beside the pool.

The bodies go through the shared rasterizer (:func:`animat.envs.render.raster.rasterize_world`, a
depth buffer); then :func:`surface_into` colours each pixel by where its ray goes: a ray that
meets nothing shows the sky above the horizon and the water's colour below it; the part of a
ray's path under the surface hazes what it meets (``exp(-d / visibility)`` kept, d the path
under water); where a ray crosses the surface before meeting anything, the surface's sheen is
blended in, so the waterline is visible across the dolphin as it leaves the water.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..bodies.spec import BodySpec
from ..physics.ball import BallParams
from .camera import Camera, Scene, box, look_at
from .raster import rasterize_world
from .rays import pixel_ray

DOLPHIN_COLOUR = (105, 120, 140)
BALL_COLOURS = ((230, 40, 40), (250, 250, 250), (40, 90, 230), (250, 210, 40))
SUPPORT_COLOUR = (120, 110, 100)
SKY_TOP, SKY_HORIZON = np.array([90.0, 150.0, 230.0]), np.array([200.0, 225.0, 245.0])
WATER_TOP, WATER_BOTTOM = np.array([40.0, 120.0, 160.0]), np.array([5.0, 30.0, 60.0])
SHEEN = np.array([170.0, 210.0, 230.0])  # the surface seen from above
SHEEN_SHARE = 0.35


@njit(cache=True)
def surface_into(image, zbuffer, eye, rotation, focal, surface_z, visibility) -> None:
    """Sky, surface and water for every pixel of ``image`` (H, W, 3) uint8 with its depth
    buffer ``zbuffer`` (H, W) (depth along the camera axis, m; inf: nothing there), camera at
    ``eye`` (3,) with ``rotation`` (rows right, down, forward) and ``focal`` pixels."""
    height, width = zbuffer.shape
    for i in range(height):
        for j in range(width):
            dx, dy, dz = pixel_ray(rotation, focal, height, width, i, j)
            length = np.sqrt(dx * dx + dy * dy + dz * dz)
            hit = zbuffer[i, j]
            crossing = (surface_z - eye[2]) / dz if dz != 0.0 else np.inf
            if crossing <= 0.0:
                crossing = np.inf  # the ray never meets the surface
            below = eye[2] < surface_z
            if below:
                wet = min(hit, crossing)
            else:
                wet = max(hit - crossing, 0.0) if crossing < hit else 0.0
            up = 0.5 * (1.0 + dz / length)
            for c in range(3):
                water = WATER_BOTTOM[c] + up * (WATER_TOP[c] - WATER_BOTTOM[c])
                if hit == np.inf and (dz > 0.0) != below:
                    sky = SKY_HORIZON[c] + min(dz / length * 3.0, 1.0) * (
                        SKY_TOP[c] - SKY_HORIZON[c])
                    value = sky
                elif hit == np.inf:
                    value = water
                else:
                    keep = np.exp(-wet * length / visibility)
                    value = water + keep * (np.float64(image[i, j, c]) - water)
                if crossing < hit and not below:
                    value = value + SHEEN_SHARE * (SHEEN[c] - value)
                image[i, j, c] = np.uint8(min(max(value, 0.0), 255.0) + 0.5)


def sphere_quads(centre: np.ndarray, radius: float, bands: int = 8, sectors: int = 12
                 ) -> np.ndarray:
    """(bands * sectors, 4, 3) quads of a UV sphere, m."""
    theta = np.linspace(0.0, np.pi, bands + 1)
    phi = np.linspace(0.0, 2.0 * np.pi, sectors + 1)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    points = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1)
    points = np.asarray(centre) + radius * points
    return np.stack([points[:-1, :-1], points[:-1, 1:], points[1:, 1:], points[1:, :-1]],
                    axis=2).reshape(-1, 4, 3)


class SeaWorldRenderer:
    """Frames (height, width, 3) uint8 of the dolphin (and its ball), seen from beside the
    pool: the camera at ``camera_height`` m above the surface, ``distance`` body lengths to
    the dolphin's right, following it along x and looking level at the waterline."""

    def __init__(self, body: BodySpec, ball: BallParams | None = None, width: int = 480,
                 height: int = 360, distance: float = 3.0, camera_height: float = 0.4,
                 surface_z: float = 0.0, visibility: float = 8.0) -> None:
        self.body, self.ball = body, ball
        self.width, self.height = int(width), int(height)
        self.distance, self.camera_height = float(distance), float(camera_height)
        self.surface_z, self.visibility = float(surface_z), float(visibility)
        self.focal = 0.8 * self.width

    def scene(self, x: np.ndarray, ball: np.ndarray | None = None) -> Scene:
        scene = Scene(seabed_z=-1e3).add(self.body, x, DOLPHIN_COLOUR)
        if self.ball is not None and ball is not None:
            quads = sphere_quads(ball[:3], self.ball.radius)
            for k, colour in enumerate(BALL_COLOURS):  # four coloured segments
                scene.add_mesh(quads.reshape(8, 12, 4, 3)[:, 3 * k:3 * k + 3].reshape(-1, 4, 3),
                               colour)
            top = np.array(self.ball.support)
            scene.add_mesh(box(top - [0.0, 0.0, 0.5 * (top[2] + 3.0)],
                               [0.1, 0.1, top[2] + 3.0]), SUPPORT_COLOUR)
        return scene

    def render(self, x: np.ndarray, ball: np.ndarray | None = None) -> np.ndarray:
        """The picture of the body at node positions ``x`` (N, 3) m and the ball (6,)."""
        centre = self.body.masses @ x / self.body.total_mass
        target = np.array([centre[0], centre[1], self.surface_z + self.camera_height])
        eye = target - np.array([0.0, self.distance * self.body.length, 0.0])
        camera = Camera(self.width, self.height, self.focal, eye, look_at(eye, target))
        frame = self.scene(x, ball).prepare()
        image = np.zeros((self.height, self.width, 3), np.uint8)
        zbuffer = np.full((self.height, self.width), np.inf)
        keep = frame.triangles[:, :, 2].max(axis=1) > -1e2  # the shadows lie on the far seabed
        rasterize_world(frame.triangles[keep], frame.colours[keep], eye,
                        np.ascontiguousarray(camera.rotation), float(self.focal), image,
                        zbuffer, 0.01)
        surface_into(image, zbuffer, eye, camera.rotation, float(self.focal), self.surface_z,
                     self.visibility)
        return image
