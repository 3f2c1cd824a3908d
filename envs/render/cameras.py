"""Many cameras in one call: every eye of a batch of worlds drawn by one Numba kernel, cameras
split over threads.

:func:`draw_cameras` draws C cameras, each looking at one of N worlds' prepared triangles
((N, T, 3, 3) m, the same count T in every world), with exactly the passes of
:meth:`animat.envs.render.camera.Camera.draw` (the seabed ray-cast, the triangles through the
depth buffer, the water and its haze: :func:`~animat.envs.render.raster.draw_picture`), so a
camera gives bit for bit the picture :class:`~animat.envs.render.camera.Camera` gives, whatever
else is in the batch. What it saves is the Python around each camera (about half of a retina's
time when drawn one camera at a time) and one core's idleness: ``prange`` over chunks of
cameras, each chunk drawn on one work space (:func:`~animat.envs.render.raster.canvas`); and
each world's triangles are bounded once, group by group (runs of consecutive triangles unless
the caller groups them in space), so that every camera leaves out the groups it cannot see
(:func:`~animat.envs.render.raster.seen_groups`: the same pictures; the fovea sees about a
hundredth of the scene).

The fish's and the scenery's colours are flat-shaded by
:func:`~animat.envs.render.camera.shade`, as :meth:`~animat.envs.render.camera.Scene.prepare`
shades them.
"""

from __future__ import annotations

import numba
import numpy as np
from numba import njit, prange

from .camera import FAR, NEAR, SAND, SHADOW_COLOUR, WATER_BOTTOM, WATER_TOP
from .raster import canvas, chunk_groups, draw_picture_into, group_spheres

CHUNKS_PER_THREAD = 4  # chunks of cameras per thread: few canvases, and the threads balanced


@njit(cache=True, parallel=True)
def _bound(triangles, groups, spheres) -> None:
    """Each world's groups of triangles (N, T, 3, 3), ``groups`` (N, T), bounded once for all
    its cameras, worlds over threads: ``spheres`` (N, G, 4)
    (:func:`~animat.envs.render.raster.group_spheres`)."""
    for w in prange(triangles.shape[0]):
        group_spheres(triangles[w], groups[w], spheres[w])


@njit(cache=True, parallel=True)
def _draw(triangles, colours, spheres, groups, world, eyes, rotations, focals, seabed_z,
          tiles, visibility, sand, top, bottom, far, near, images, chunks) -> None:
    levels, height, width = images.shape[3], images.shape[1], images.shape[2]
    for k in prange(chunks):  # each chunk of cameras on one canvas
        image = np.empty((height, width, 3), np.uint8)  # contiguous while it is drawn
        work = canvas(height, width, triangles.shape[1])
        for c in range(k, len(world), chunks):  # every chunks-th camera: worlds mixed
            w = world[c]
            draw_picture_into(triangles[w], colours[w], eyes[c], rotations[c], focals[c],
                              seabed_z[w], tiles[w], visibility[w], sand, top, bottom, far,
                              near, image, work, spheres[w], groups[w])
            images[c // levels, :, :, c % levels] = image


def draw_cameras(triangles: np.ndarray, colours: np.ndarray, world: np.ndarray,
                 eyes: np.ndarray, rotations: np.ndarray, focals: np.ndarray,
                 seabed_z: np.ndarray, tiles: np.ndarray, visibility: np.ndarray,
                 size: tuple[int, int], levels: int = 1,
                 groups: np.ndarray | None = None) -> np.ndarray:
    """(C / levels, height, width, levels, 3) uint8: C pinhole cameras in groups of
    ``levels`` (an eye's coaxial cameras: camera c is level ``c % levels`` of eye
    ``c // levels``, its picture ``[c // levels, :, :, c % levels]``, the layout an eye's
    stacked levels take without a copy). Camera c is at ``eyes[c]`` (3,) m with
    ``rotations[c]`` (3, 3) (rows right, down, forward) and ``focals[c]`` pixels, looking at
    world ``world[c]`` of the N worlds: triangles (N, T, 3, 3) m with colours (N, T, 3)
    uint8, each world's seabed height ``seabed_z`` (N,) m, sand tiles ``tiles`` (N,) m and
    haze ``visibility`` (N,) m. ``size``: (height, width) pixels. ``groups`` (N, T) int:
    each triangle's group, culled together (:mod:`~animat.envs.render.raster`; groups near in
    space cull best); None: runs of consecutive triangles
    (:func:`~animat.envs.render.raster.chunk_groups`)."""
    count = len(world)
    if count % levels:
        raise ValueError(f"{count} cameras are not groups of {levels} levels")
    images = np.empty((count // levels, size[0], size[1], levels, 3), np.uint8)
    triangles = np.ascontiguousarray(triangles, float)
    if groups is None:
        groups = np.broadcast_to(chunk_groups(triangles.shape[1]), triangles.shape[:2])
    groups = np.ascontiguousarray(groups, np.int64)
    if groups.shape != triangles.shape[:2] or (groups.size and groups.min() < 0):
        raise ValueError(f"groups must be {triangles.shape[:2]} integers >= 0, one a triangle")
    spheres = np.empty((len(triangles), int(groups.max(initial=-1)) + 1, 4))
    _bound(triangles, groups, spheres)
    _draw(triangles, np.ascontiguousarray(colours, np.uint8), spheres, groups,
          np.ascontiguousarray(world, np.int64), np.ascontiguousarray(eyes, float),
          np.ascontiguousarray(rotations, float), np.ascontiguousarray(focals, float),
          np.ascontiguousarray(seabed_z, float), np.ascontiguousarray(tiles, float),
          np.ascontiguousarray(visibility, float), SAND, WATER_TOP, WATER_BOTTOM, FAR, NEAR,
          images, max(1, min(count, CHUNKS_PER_THREAD * numba.get_num_threads())))
    return images


def groups_in_space(centres: np.ndarray, cell: float, size: int) -> np.ndarray:
    """(Q,) int: groups of at most ``size`` of the Q things whose ``centres`` (Q, 2+) m lie
    near each other: ranked along a Z-order curve through square cells of ``cell`` m in the
    first two coordinates (x, y), then taken ``size`` at a time, so that a group's bounding
    sphere is small and the cameras that cannot see it leave it out whole."""
    if len(centres) == 0:
        return np.zeros(0, np.int64)
    cells = np.floor((centres[:, :2] - centres[:, :2].min(axis=0)) / cell).astype(np.int64)
    code = _spread(cells[:, 0]) | (_spread(cells[:, 1]) << 1)
    rank = np.empty(len(code), np.int64)
    rank[np.argsort(code, kind="stable")] = np.arange(len(code))
    return rank // size


def _spread(values: np.ndarray) -> np.ndarray:
    """Each value's low 16 bits spread to the even bits (one coordinate of a Z-order code)."""
    v = values & 0xFFFF
    v = (v | (v << 8)) & 0x00FF00FF
    v = (v | (v << 4)) & 0x0F0F0F0F
    v = (v | (v << 2)) & 0x33333333
    return (v | (v << 1)) & 0x55555555


SHADOW = np.array(SHADOW_COLOUR, np.uint8)
