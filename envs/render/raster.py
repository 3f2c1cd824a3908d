"""The one rasterizer: flat-coloured triangles into an RGB image with a depth buffer (Numba).

Every picture of the world (the third-person view and the eyes' cameras) is made by
:func:`rasterize`: triangles already projected to pixel coordinates, each with its vertices'
camera-space depths and one colour; a pixel takes the colour of the nearest triangle that
covers its centre (depth interpolated as 1/z across the triangle, which is exact for planar
triangles under perspective). Occlusion is therefore per pixel, whatever order the triangles
come in. Triangles with a vertex nearer than ``near`` are dropped (no clipping).

Around the triangles go the two per-pixel passes along the camera's rays
(:mod:`~animat.envs.render.rays`): the seabed first, the water and its haze last.
:func:`draw_picture` is the three in order, a camera's whole picture
(:func:`draw_picture_into` the same on work space kept from camera to camera, and given the
triangles' groups and each group's bounding sphere, :func:`group_spheres`, it leaves out the
groups the camera cannot see, :func:`seen_groups`: the same picture for less work). A group
is any set of triangles (:func:`chunk_groups`: runs of consecutive ones); the triangles are
drawn in their own order whatever their groups, so the depth test's ties fall as without
culling.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .rays import pixel_rays, seabed_into, water_into

CULL_CHUNK = 32  # the triangles of a group of consecutive ones (chunk_groups)


def chunk_groups(count: int) -> np.ndarray:
    """(count,) int64: triangle t in group t // :data:`CULL_CHUNK`, runs of consecutive
    triangles (what a list of triangles in no spatial order culls by)."""
    return np.arange(count, dtype=np.int64) // CULL_CHUNK


@njit(cache=True)
def group_spheres(triangles, groups, spheres) -> None:
    """Fill ``spheres`` (G, 4) with a bounding sphere (centre m, radius m) of each group of
    ``triangles`` (T, 3, 3) m, triangle t in group ``groups[t]`` (T,) of G: the centre of the
    group's corners' bounding box, the radius the farthest corner from it (enlarged by a
    micrometre, against rounding). A group without triangles gets radius -1 (never seen)."""
    count = spheres.shape[0]
    low, high = np.full((count, 3), np.inf), np.full((count, 3), -np.inf)
    for t in range(triangles.shape[0]):
        g = groups[t]
        for k in range(3):
            for a in range(3):
                low[g, a] = min(low[g, a], triangles[t, k, a])
                high[g, a] = max(high[g, a], triangles[t, k, a])
    far = np.full(count, -1.0)
    for g in range(count):
        for a in range(3):
            spheres[g, a] = 0.5 * (low[g, a] + high[g, a]) if low[g, a] <= high[g, a] else 0.0
    for t in range(triangles.shape[0]):
        g = groups[t]
        for k in range(3):
            dx = triangles[t, k, 0] - spheres[g, 0]
            dy = triangles[t, k, 1] - spheres[g, 1]
            dz = triangles[t, k, 2] - spheres[g, 2]
            far[g] = max(far[g], dx * dx + dy * dy + dz * dz)
    for g in range(count):
        spheres[g, 3] = np.sqrt(far[g]) + 1e-6 if far[g] >= 0.0 else -1.0


@njit(cache=True)
def seen_groups(spheres, eye, rotation, focal, shape, near, seen) -> None:
    """``seen`` (G,) bool: whether group g's sphere (``spheres`` (G, 4), :func:`group_spheres`)
    may show in the picture of a pinhole camera at ``eye`` with ``rotation`` (rows right, down,
    forward) and ``focal`` pixels, of ``shape`` (height, width). A group is left out only where
    its sphere lies wholly nearer than ``near`` or wholly beyond one side of the picture
    (widened by a pixel each way), where :func:`rasterize` would draw none of its triangles: so
    the picture is the same, bit for bit (an empty group, radius -1, is left out)."""
    half_h, half_w = 0.5 * shape[0] + 1.0, 0.5 * shape[1] + 1.0
    norm_w, norm_h = np.sqrt(focal * focal + half_w * half_w), np.sqrt(
        focal * focal + half_h * half_h)
    for c in range(spheres.shape[0]):
        d0, d1, d2 = spheres[c, 0] - eye[0], spheres[c, 1] - eye[1], spheres[c, 2] - eye[2]
        x = rotation[0, 0] * d0 + rotation[0, 1] * d1 + rotation[0, 2] * d2
        y = rotation[1, 0] * d0 + rotation[1, 1] * d1 + rotation[1, 2] * d2
        z = rotation[2, 0] * d0 + rotation[2, 1] * d1 + rotation[2, 2] * d2
        r = spheres[c, 3]
        seen[c] = r >= 0.0 and not (z + r < near or focal * x - half_w * z > r * norm_w
                                    or -focal * x - half_w * z > r * norm_w
                                    or focal * y - half_h * z > r * norm_h
                                    or -focal * y - half_h * z > r * norm_h)


@njit(cache=True, error_model="numpy")
def rasterize(xs, ys, depths, colours, image, zbuffer, near, seen, groups) -> None:
    """Draw triangles into ``image`` (H, W, 3) uint8 where they are nearer than ``zbuffer``
    (H, W) float, updating it.

    Each row of a triangle's bounding box in two passes: every pixel's barycentric test and
    depth, branch-free (SIMD), then the covered pixels that pass the depth test written (the
    same pictures as testing pixel by pixel: a pixel is inside when no barycentric coordinate
    is negative, and one that is NaN gives a NaN depth, which never passes).

    Args:
        xs, ys: (3T,) vertex positions, pixels (x right, y down; pixel (i, j) has its centre
            at (j + 0.5, i + 0.5)); triangle t's corners are 3t, 3t + 1, 3t + 2.
        depths: (3T,) vertex depths along the camera's axis, m.
        colours: (T, 3) uint8 RGB.
        near: triangles with a vertex nearer than this (m) are skipped.
        seen: (G,) bool, whether each group of triangles may be seen (:func:`seen_groups`;
            its triangles left out otherwise, and their projections not read); empty: every
            triangle is drawn.
        groups: (T,) int, each triangle's group (read only where ``seen`` is not empty).
    """
    height, width = zbuffer.shape
    inside, row = np.empty(width, np.bool_), np.empty(width)  # a row's tests and depths
    culled = seen.shape[0] > 0
    for t in range(colours.shape[0]):
        if culled and not seen[groups[t]]:
            continue
        z0, z1, z2 = depths[3 * t], depths[3 * t + 1], depths[3 * t + 2]
        if z0 < near or z1 < near or z2 < near:
            continue
        x0, y0 = xs[3 * t], ys[3 * t]
        x1, y1 = xs[3 * t + 1], ys[3 * t + 1]
        x2, y2 = xs[3 * t + 2], ys[3 * t + 2]
        area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
        if area == 0.0:
            continue
        left = max(int(np.floor(min(x0, x1, x2))), 0)
        right = min(int(np.ceil(max(x0, x1, x2))), width - 1)
        top = max(int(np.floor(min(y0, y1, y2))), 0)
        bottom = min(int(np.ceil(max(y0, y1, y2))), height - 1)
        w0, w1, w2 = 1.0 / z0, 1.0 / z1, 1.0 / z2
        for i in range(top, bottom + 1):
            py = i + 0.5
            for j in range(left, right + 1):
                px = j + 0.5
                b0 = ((x1 - px) * (y2 - py) - (x2 - px) * (y1 - py)) / area
                b1 = ((x2 - px) * (y0 - py) - (x0 - px) * (y2 - py)) / area
                b2 = 1.0 - b0 - b1
                inside[j] = (b0 >= 0.0) & (b1 >= 0.0) & (b2 >= 0.0)
                row[j] = 1.0 / (b0 * w0 + b1 * w1 + b2 * w2)
            for j in range(left, right + 1):
                if inside[j] and row[j] < zbuffer[i, j]:
                    zbuffer[i, j] = row[j]
                    image[i, j, 0] = colours[t, 0]
                    image[i, j, 1] = colours[t, 1]
                    image[i, j, 2] = colours[t, 2]


@njit(cache=True)
def rasterize_world(triangles, colours, eye, rotation, focal, image, zbuffer, near) -> None:
    """:func:`rasterize` of world-frame triangles (T, 3, 3) m seen by a pinhole camera at
    ``eye`` (3,) with ``rotation`` (3, 3) (rows right, down, forward) and ``focal`` pixels,
    projected by :func:`project`."""
    count = 3 * triangles.shape[0]
    xs, ys, depths = np.empty(count), np.empty(count), np.empty(count)
    everything, none = np.zeros(0, np.bool_), np.zeros(0, np.int64)  # no group culled
    project(triangles, eye, rotation, focal, zbuffer.shape, xs, ys, depths, everything, none)
    rasterize(xs, ys, depths, colours, image, zbuffer, near, everything, none)


@njit(cache=True)
def project(triangles, eye, rotation, focal, shape, xs, ys, depths, seen, groups) -> None:
    """Project world-frame triangles (T, 3, 3) m for a pinhole camera at ``eye`` (3,) with
    ``rotation`` (3, 3) (rows right, down, forward), ``focal`` pixels and image ``shape``
    (height, width): corner k of triangle t to pixel (``xs``, ``ys``)[3t + k] and depth
    ``depths``[3t + k] m (each (3T,)); only the triangles whose group (``groups`` (T,)) is
    ``seen`` (:func:`rasterize`), all where ``seen`` is empty."""
    height, width = shape
    r00, r01, r02 = rotation[0, 0], rotation[0, 1], rotation[0, 2]
    r10, r11, r12 = rotation[1, 0], rotation[1, 1], rotation[1, 2]
    r20, r21, r22 = rotation[2, 0], rotation[2, 1], rotation[2, 2]
    e0, e1, e2 = eye[0], eye[1], eye[2]
    culled = seen.shape[0] > 0
    for t in range(triangles.shape[0]):
        if culled and not seen[groups[t]]:
            continue
        for k in range(3):
            d0, d1, d2 = triangles[t, k, 0] - e0, triangles[t, k, 1] - e1, triangles[t, k, 2] - e2
            cx = r00 * d0 + r01 * d1 + r02 * d2
            cy = r10 * d0 + r11 * d1 + r12 * d2
            cz = r20 * d0 + r21 * d1 + r22 * d2
            safe = max(cz, 1e-6)
            v = 3 * t + k
            xs[v] = 0.5 * width + focal * cx / safe
            ys[v] = 0.5 * height + focal * cy / safe
            depths[v] = cz


@njit(cache=True)
def canvas(height, width, triangles):
    """Work space for :func:`draw_picture_into`: a camera of ``height`` x ``width`` pixels
    seeing up to ``triangles`` triangles (a tuple of arrays, allocated once and used for camera
    after camera: allocating its half megabyte for each picture costs a share of a camera's
    time, more on two threads)."""
    return (np.empty((height, width)), np.empty((4, height, width)),
            np.empty((2, height * width)), np.empty((3, 3 * triangles)),
            np.empty(triangles, np.bool_))  # as many groups as triangles at most


@njit(cache=True)
def draw_picture(triangles, colours, eye, rotation, focal, seabed_z, tile, visibility, sand,
                 top, bottom, far, near, image) -> None:
    """A camera's whole picture into ``image`` (H, W, 3) uint8 (drawn over, whatever it
    held): :func:`draw_picture_into` on a :func:`canvas` of its own, nothing culled."""
    work = canvas(image.shape[0], image.shape[1], triangles.shape[0])
    draw_picture_into(triangles, colours, eye, rotation, focal, seabed_z, tile, visibility,
                      sand, top, bottom, far, near, image, work, np.zeros((0, 4)),
                      np.zeros(0, np.int64))


@njit(cache=True)
def draw_picture_into(triangles, colours, eye, rotation, focal, seabed_z, tile, visibility,
                      sand, top, bottom, far, near, image, work, spheres, groups) -> None:
    """A camera's whole picture into ``image`` (H, W, 3) uint8 (drawn over, whatever it
    held), on the work space ``work`` (:func:`canvas`, for at least as many triangles): its
    pixel rays (:func:`pixel_rays`), the seabed (:func:`seabed_into`), the triangles (T, 3, 3)
    m with colours (T, 3) uint8 projected (:func:`project`) and through the depth buffer
    (:func:`rasterize`), then the water and its haze (:func:`water_into`). ``spheres``
    (G, 4): the bounding spheres of the triangles' groups ``groups`` (T,), each in [0, G)
    (:func:`group_spheres`), to leave out the groups the camera cannot see
    (:func:`seen_groups`: the same picture); none, (0, 4): every triangle drawn."""
    zbuffer, rays, pixels, projected, seen = work
    count = 3 * triangles.shape[0]
    if projected.shape[1] < count or zbuffer.shape != image.shape[:2]:
        raise ValueError("draw_picture_into: the canvas is for fewer triangles or other pixels")
    if seen.shape[0] < spheres.shape[0]:
        raise ValueError("draw_picture_into: more groups than the canvas has triangles")
    if spheres.shape[0] > 0 and groups.shape[0] != triangles.shape[0]:
        raise ValueError("draw_picture_into: groups must name one group a triangle")
    image[:] = 0
    zbuffer[:] = np.inf
    pixel_rays(rotation, focal, rays)
    seabed_into(image, zbuffer, eye, rays, seabed_z, tile, sand, far, pixels[0])
    xs, ys, depths = projected[0, :count], projected[1, :count], projected[2, :count]
    shown = seen[:spheres.shape[0]]
    if spheres.shape[0] > 0:
        seen_groups(spheres, eye, rotation, focal, zbuffer.shape, near, shown)
    project(triangles, eye, rotation, focal, zbuffer.shape, xs, ys, depths, shown, groups)
    rasterize(xs, ys, depths, colours, image, zbuffer, near, shown, groups)
    water_into(image, zbuffer, rays, top, bottom, visibility, pixels[0], pixels[1])


def quads_into(triangles: np.ndarray, start: int, quads: np.ndarray) -> None:
    """Write ``quads`` (..., Q, 4, 3) (corners a, b, c, d; a triangle repeats a corner) into a
    buffer of T triangles ``triangles`` (..., T, 3, 3), in the order every picture takes them:
    quad q's first triangle (a, b, c) at ``start`` + q, its second (a, c, d) T / 2 further on."""
    half, stop = triangles.shape[-3] // 2, start + quads.shape[-3]
    triangles[..., start:stop, :, :] = quads[..., :3, :]
    triangles[..., half + start:half + stop, 0, :] = quads[..., 0, :]
    triangles[..., half + start:half + stop, 1:, :] = quads[..., 2:, :]


def quads_to_triangles(corners: np.ndarray) -> np.ndarray:
    """(F, 4, 3) quads -> (2F, 3, 3) triangles: (0, 1, 2) of every quad, then (0, 2, 3)
    (:func:`quads_into`)."""
    out = np.empty((2 * len(corners), 3, 3), corners.dtype)
    quads_into(out, 0, corners)
    return out
