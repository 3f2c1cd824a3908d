"""The per-pixel passes of a camera's picture, along its pixels' rays (Numba).

:func:`pixel_rays` computes each pixel's :func:`pixel_ray` and its length once for both
passes: :func:`seabed_into` first (the seabed plane, ray-cast, with a sand texture of tiles),
before the triangles are rasterised (:mod:`~animat.envs.render.raster`), and
:func:`water_into` last (the water's colour by the ray's elevation, and depth haze:
everything fades into that colour as ``exp(-distance / visibility)``).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, inline="always")
def pixel_ray(rotation, focal, height, width, i, j):
    """The world direction (dx, dy, dz) of the ray through the centre of pixel (i, j) (row i
    down, column j right) of a ``height`` x ``width`` image seen by a pinhole camera with
    ``rotation`` (3, 3) (rows right, down, forward; world frame) and ``focal`` pixels: not
    normalised, but of unit depth along the camera's axis, so a point at depth d m (what a
    depth buffer holds) lies at d times it from the camera (and the ray's length is
    ``sqrt(dx^2 + dy^2 + dz^2)`` m of path per metre of depth)."""
    rx, ry = (j + 0.5 - 0.5 * width) / focal, (i + 0.5 - 0.5 * height) / focal
    return (rotation[0, 0] * rx + rotation[1, 0] * ry + rotation[2, 0],
            rotation[0, 1] * rx + rotation[1, 1] * ry + rotation[2, 1],
            rotation[0, 2] * rx + rotation[1, 2] * ry + rotation[2, 2])


@njit(cache=True)
def pixel_rays(rotation, focal, rays) -> None:
    """Fill ``rays`` (4, H, W) with every pixel's :func:`pixel_ray` (dx, dy, dz) and its
    length ``sqrt(dx^2 + dy^2 + dz^2)`` (the same numbers, each pixel's division by ``focal``
    done once per row and column): what :func:`seabed_into` and :func:`water_into` share."""
    height, width = rays.shape[1], rays.shape[2]
    for i in range(height):
        ry = (i + 0.5 - 0.5 * height) / focal
        for j in range(width):
            rx = (j + 0.5 - 0.5 * width) / focal
            dx = rotation[0, 0] * rx + rotation[1, 0] * ry + rotation[2, 0]
            dy = rotation[0, 1] * rx + rotation[1, 1] * ry + rotation[2, 1]
            dz = rotation[0, 2] * rx + rotation[1, 2] * ry + rotation[2, 2]
            rays[0, i, j], rays[1, i, j], rays[2, i, j] = dx, dy, dz
            rays[3, i, j] = np.sqrt(dx * dx + dy * dy + dz * dz)


@njit(cache=True, error_model="numpy")
def seabed_into(image, zbuffer, eye, rays, seabed_z, tile, sand, far, shades) -> None:
    """Ray-cast the seabed (the plane z = ``seabed_z``, m) into ``image`` and ``zbuffer`` where
    it is nearer than what is there and within ``far`` m, along the camera at ``eye`` (3,)'s
    pixel ``rays`` (:func:`pixel_rays`): ``sand`` (3,) RGB in square tiles of ``tile`` m, each
    tile's brightness a checker plus a hash of its indices (texture that optical flow can lock
    onto). ``shades`` (H * W,) is work space.

    Two passes over the pixels: every pixel's hit, depth and shade computed branch-free (a
    pixel that misses computes on 0 and is not kept), which runs in SIMD, then the hits'
    colours written (the same numbers as one pass with a branch per pixel)."""
    if eye[2] <= seabed_z:
        return
    pixels = zbuffer.size
    depths, ray = zbuffer.reshape(pixels), rays.reshape(4, pixels)
    drop, x0, y0 = seabed_z - eye[2], eye[0], eye[1]
    for p in range(pixels):
        dz = ray[2, p]
        depth = drop / dz  # inf or negative where the ray does not go down: not kept
        hit = (dz < 0.0) & (depth < depths[p]) & (depth * ray[3, p] <= far)
        u = int(np.floor((x0 + depth * ray[0, p]) / tile if hit else 0.0))
        v = int(np.floor((y0 + depth * ray[1, p]) / tile if hit else 0.0))
        noise = ((u * 73856093) ^ (v * 19349663)) & 1023
        shades[p] = 0.78 + 0.1 * ((u + v) & 1) + 0.14 * noise / 1023.0 if hit else -1.0
        depths[p] = depth if hit else depths[p]
    colours = image.reshape(pixels, 3)
    for p in range(pixels):
        if shades[p] >= 0.0:
            for c in range(3):
                colours[p, c] = min(255.0, sand[c] * shades[p])


HAZE_STEPS = 64  # table entries per unit of distance / visibility
HAZE_TABLE = np.exp(-np.arange(16 * HAZE_STEPS + 2) / HAZE_STEPS)  # exp(-u), u in [0, 16]


@njit(cache=True, error_model="numpy")
def water_into(image, zbuffer, rays, top, bottom, visibility, keeps, ups) -> None:
    """The water, along the camera's pixel ``rays`` (:func:`pixel_rays`): a pixel that shows
    nothing takes the water's colour along its ray (``top`` (3,) RGB looking straight up,
    ``bottom`` straight down, blended by the ray's elevation); a pixel showing something at
    distance d (m, along the ray) is hazed toward that colour, keeping ``exp(-d /
    visibility)`` of its own (from :data:`HAZE_TABLE`, linearly interpolated: within 1e-4 of
    the exponential; nothing is kept beyond 16 visibilities). ``keeps``, ``ups`` (H * W,)
    are work space: each pixel's elevation and distance in table steps in a first SIMD pass,
    its share kept read from the table in a second (a gather, which would keep the first
    from SIMD), then the blend in a third (the same numbers as one pass)."""
    pixels = zbuffer.size
    depths, ray = zbuffer.reshape(pixels), rays.reshape(4, pixels)
    last = HAZE_TABLE.shape[0] - 2
    for p in range(pixels):
        length = ray[3, p]
        ups[p] = 0.5 * (1.0 + ray[2, p] / length)
        keeps[p] = min(depths[p] * length / visibility, 16.0) * HAZE_STEPS
    for p in range(pixels):
        u = keeps[p]
        k = min(int(u), last)
        keep = HAZE_TABLE[k] + (u - k) * (HAZE_TABLE[k + 1] - HAZE_TABLE[k])
        keeps[p] = 0.0 if u >= 16.0 * HAZE_STEPS else keep
    t0, t1, t2, b0, b1, b2 = top[0], top[1], top[2], bottom[0], bottom[1], bottom[2]
    channels = image.reshape(3 * pixels)  # the three channels in one loop: it runs in SIMD
    for p in range(pixels):
        up, keep = ups[p], keeps[p]
        w0, w1, w2 = b0 + up * (t0 - b0), b1 + up * (t1 - b1), b2 + up * (t2 - b2)
        channels[3 * p] = np.uint8(w0 + keep * (np.float64(channels[3 * p]) - w0) + 0.5)
        channels[3 * p + 1] = np.uint8(w1 + keep * (np.float64(channels[3 * p + 1]) - w1) + 0.5)
        channels[3 * p + 2] = np.uint8(w2 + keep * (np.float64(channels[3 * p + 2]) - w2) + 0.5)
