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
each world's triangles are bounded once, in chunks of consecutive ones, so that every camera
leaves out the chunks it cannot see (:func:`~animat.envs.render.raster.seen_chunks`: the same
pictures; the fovea sees about a hundredth of the scene).

The fish's and the scenery's colours are flat-shaded by
:func:`~animat.envs.render.camera.shade`, as :meth:`~animat.envs.render.camera.Scene.prepare`
shades them.
"""

from __future__ import annotations

import numba
import numpy as np
from numba import njit, prange

from .camera import FAR, NEAR, SAND, SHADOW_COLOUR, WATER_BOTTOM, WATER_TOP
from .raster import CULL_CHUNK, canvas, chunk_spheres, draw_picture_into

CHUNKS_PER_THREAD = 4  # chunks of cameras per thread: few canvases, and the threads balanced


@njit(cache=True)
def _bound(triangles, spheres) -> None:
    """Each world's chunks of triangles (N, T, 3, 3) bounded once, for all its cameras:
    ``spheres`` (N, C, 4) (:func:`~animat.envs.render.raster.chunk_spheres`)."""
    for w in range(triangles.shape[0]):
        chunk_spheres(triangles[w], spheres[w])


@njit(cache=True, parallel=True)
def _draw(triangles, colours, spheres, world, eyes, rotations, focals, seabed_z, tiles,
          visibility, sand, top, bottom, far, near, images, chunks) -> None:
    levels, height, width = images.shape[3], images.shape[1], images.shape[2]
    for k in prange(chunks):  # each chunk of cameras on one canvas
        image = np.empty((height, width, 3), np.uint8)  # contiguous while it is drawn
        work = canvas(height, width, triangles.shape[1])
        for c in range(k, len(world), chunks):  # every chunks-th camera: worlds mixed
            w = world[c]
            draw_picture_into(triangles[w], colours[w], eyes[c], rotations[c], focals[c],
                              seabed_z[w], tiles[w], visibility[w], sand, top, bottom, far,
                              near, image, work, spheres[w])
            images[c // levels, :, :, c % levels] = image


def draw_cameras(triangles: np.ndarray, colours: np.ndarray, world: np.ndarray,
                 eyes: np.ndarray, rotations: np.ndarray, focals: np.ndarray,
                 seabed_z: np.ndarray, tiles: np.ndarray, visibility: np.ndarray,
                 size: tuple[int, int], levels: int = 1) -> np.ndarray:
    """(C / levels, height, width, levels, 3) uint8: C pinhole cameras in groups of
    ``levels`` (an eye's coaxial cameras: camera c is level ``c % levels`` of eye
    ``c // levels``, its picture ``[c // levels, :, :, c % levels]``, the layout an eye's
    stacked levels take without a copy). Camera c is at ``eyes[c]`` (3,) m with
    ``rotations[c]`` (3, 3) (rows right, down, forward) and ``focals[c]`` pixels, looking at
    world ``world[c]`` of the N worlds: triangles (N, T, 3, 3) m with colours (N, T, 3)
    uint8, each world's seabed height ``seabed_z`` (N,) m, sand tiles ``tiles`` (N,) m and
    haze ``visibility`` (N,) m. ``size``: (height, width) pixels."""
    count = len(world)
    if count % levels:
        raise ValueError(f"{count} cameras are not groups of {levels} levels")
    images = np.empty((count // levels, size[0], size[1], levels, 3), np.uint8)
    triangles = np.ascontiguousarray(triangles, float)
    spheres = np.empty((len(triangles), -(-triangles.shape[1] // CULL_CHUNK), 4))
    _bound(triangles, spheres)
    _draw(triangles, np.ascontiguousarray(colours, np.uint8), spheres,
          np.ascontiguousarray(world, np.int64), np.ascontiguousarray(eyes, float),
          np.ascontiguousarray(rotations, float), np.ascontiguousarray(focals, float),
          np.ascontiguousarray(seabed_z, float), np.ascontiguousarray(tiles, float),
          np.ascontiguousarray(visibility, float), SAND, WATER_TOP, WATER_BOTTOM, FAR, NEAR,
          images, max(1, min(count, CHUNKS_PER_THREAD * numba.get_num_threads())))
    return images


SHADOW = np.array(SHADOW_COLOUR, np.uint8)
