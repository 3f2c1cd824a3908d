"""The active-vision algorithms of the paper's Section 3.2, as pure functions on images.

* Colour histograms on Swain & Ballard's opponent colour axes (``rg = r - g``,
  ``by = 2b - r - g``, ``wb = r + g + b``; ``BINS`` = 16, 16 and 8 bins: fine in colour,
  coarse in brightness), and their histogram intersection ``sum min(I, M) / sum M`` (1 for an
  image against its own histogram), with the model histogram scaled to the number of pixels a
  target covers at a retina level.
* Localisation by histogram backprojection: each pixel gets the ratio ``min(M / I, 1)`` of its
  colour bin, the result is blurred with a disk of the target's size, and its peak is where
  the target is.
* Stabilisation by least-squares translational optical flow between successive images
  (Lucas-Kanade over the whole image, refined by a few warps).
* Range by triangulation from the two eyes' gaze angles and their baseline.

Images are (H, W, 3) uint8 RGB; pixel positions are (x right, y down) in pixels.
"""

from __future__ import annotations

import cv2
import numpy as np
from numba import njit

BINS = (16, 16, 8)  # histogram bins on the rg, by and wb axes
CV_CHANNELS = 128  # images blurred in one OpenCV call (its filters take up to 512 channels)


def opponent(image: np.ndarray) -> np.ndarray:
    """(H, W, 3) uint8: an RGB image's colours on Swain & Ballard's opponent axes, each mapped
    onto 0..255: ``(r - g + 255) / 2``, ``(2b - r - g + 510) / 4``, ``(r + g + b) / 3``."""
    r, g, b = (np.asarray(image[..., k], np.int32) for k in range(3))
    return np.stack([(r - g + 255) // 2, (2 * b - r - g + 510) // 4, (r + g + b) // 3],
                    axis=-1).astype(np.uint8)


def colour_bins(image: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each pixel's histogram bin, (H, W) ints per axis (:data:`BINS`)."""
    axes = opponent(image).astype(np.intp)
    return tuple(axes[..., k] * BINS[k] // 256 for k in range(3))  # type: ignore[return-value]


def colour_histogram(image: np.ndarray, mask: np.ndarray | None = None) -> np.ndarray:
    """``BINS`` float32 counts of the image's colours (optionally where ``mask``)."""
    mask8 = None if mask is None else mask.astype(np.uint8)
    return cv2.calcHist([opponent(image)], [0, 1, 2], mask8, list(BINS), [0, 256] * 3)


def intersection(image_hist: np.ndarray, model_hist: np.ndarray) -> float:
    """Swain & Ballard's match score ``sum min(I, M) / sum M`` in [0, 1]."""
    total = float(model_hist.sum())
    if total <= 0.0:
        raise ValueError("the model histogram is empty")
    return float(np.minimum(image_hist, model_hist).sum() / total)


def scaled(model_hist: np.ndarray, pixels: float) -> np.ndarray:
    """The model histogram rescaled to cover ``pixels`` pixels (the target's expected size at
    one retina level)."""
    return model_hist * (pixels / float(model_hist.sum()))


def backproject(image: np.ndarray, model_hist: np.ndarray, radius: int) -> np.ndarray:
    """(H, W) float32 evidence for the model at each pixel: the ratio histogram
    ``min(M / I, 1)`` of each pixel's colour, blurred by a disk of ``radius`` pixels
    (:func:`backproject_layers` of the one image)."""
    image = np.asarray(image, np.uint8)
    return np.ascontiguousarray(
        backproject_layers(image[None, :, :, None, :], model_hist, radius)[:, :, 0])


@njit(cache=True)
def _ratios(images: np.ndarray, model: np.ndarray) -> np.ndarray:
    """(H, W, E L) float32: each pixel's ``min(M / I, 1)`` for its colour bin, as
    :func:`backproject` computes it, each of the E L images (``images`` (E, H, W, L, 3) uint8:
    E eyes of L levels each, layer ``e L + l``) with its own histogram I; ``model``: the flat
    bins."""
    eyes, height, width, levels = images.shape[0], images.shape[1], images.shape[2], \
        images.shape[3]
    out = np.empty((height, width, eyes * levels), np.float32)
    index = np.empty((height, width), np.int64)
    tiny = np.float32(1e-6)
    for e in range(eyes):
        for level in range(levels):
            hist = np.zeros(model.size, np.int64)
            for y in range(height):
                for x in range(width):
                    r = np.int64(images[e, y, x, level, 0])
                    g = np.int64(images[e, y, x, level, 1])
                    b = np.int64(images[e, y, x, level, 2])
                    rg = (r - g + 255) // 2 * BINS[0] // 256
                    by = (2 * b - r - g + 510) // 4 * BINS[1] // 256
                    wb = (r + g + b) // 3 * BINS[2] // 256
                    k = (rg * BINS[1] + by) * BINS[2] + wb
                    index[y, x] = k
                    hist[k] += 1
            layer = e * levels + level
            for y in range(height):
                for x in range(width):
                    k = index[y, x]
                    out[y, x, layer] = min(model[k] / max(np.float32(hist[k]), tiny), 1.0)
    return out


def backproject_layers(images: np.ndarray, model_hist: np.ndarray, radius: int) -> np.ndarray:
    """(H, W, E L) float32: :func:`backproject` of each image of ``images`` (E, H, W, L, 3)
    uint8 (E eyes' L levels, in any memory layout, e.g. the cameras' own) with the same model,
    the same numbers, as the layers of one image (layer ``e L + l``): the ratios in one
    compiled pass, the blur over :data:`CV_CHANNELS` layers an OpenCV call."""
    model = np.ascontiguousarray(model_hist).reshape(-1)  # float32 or float64, as backproject
    if model.dtype not in (np.float32, np.float64):
        model = model.astype(np.float64)
    layers = _ratios(images, model)
    size = 2 * int(radius) + 1
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (size, size)).astype(np.float32)
    for start in range(0, layers.shape[2], CV_CHANNELS):
        chunk = np.ascontiguousarray(layers[:, :, start:start + CV_CHANNELS])
        blurred = cv2.filter2D(chunk, -1, disk / disk.sum(), borderType=cv2.BORDER_CONSTANT)
        layers[:, :, start:start + CV_CHANNELS] = blurred.reshape(chunk.shape)
    return layers


def locate(image: np.ndarray, model_hist: np.ndarray, radius: int) -> tuple[float, float, float]:
    """(x, y, strength): where the backprojection peaks, pixels, and its value there."""
    evidence = backproject(image, model_hist, radius)
    y, x = np.unravel_index(int(np.argmax(evidence)), evidence.shape)
    return float(x) + 0.5, float(y) + 0.5, float(evidence[y, x])


def translational_flow(previous: np.ndarray, current: np.ndarray, iterations: int = 4
                       ) -> tuple[float, float]:
    """(dx, dy) pixels: the shift that best maps ``previous`` onto ``current`` in the least-
    squares sense (grey levels, central differences, Gauss-Newton with re-warping)."""
    a = cv2.cvtColor(previous, cv2.COLOR_RGB2GRAY).astype(np.float32)
    b = cv2.cvtColor(current, cv2.COLOR_RGB2GRAY).astype(np.float32)
    a, b = cv2.GaussianBlur(a, (5, 5), 1.0), cv2.GaussianBlur(b, (5, 5), 1.0)
    gx = cv2.Sobel(a, cv2.CV_32F, 1, 0, ksize=3) / 8.0
    gy = cv2.Sobel(a, cv2.CV_32F, 0, 1, ksize=3) / 8.0
    inner = (slice(4, -4), slice(4, -4))
    gx, gy = gx[inner], gy[inner]
    normal = np.array([[np.sum(gx * gx), np.sum(gx * gy)], [np.sum(gx * gy), np.sum(gy * gy)]])
    if np.linalg.cond(normal) > 1e8:
        return 0.0, 0.0  # no texture: nothing to lock onto
    shift = np.zeros(2)
    height, width = b.shape
    for _ in range(iterations):
        back = np.float32([[1, 0, shift[0]], [0, 1, shift[1]]])  # sample b at x + shift
        warped = cv2.warpAffine(b, back, (width, height),
                                flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                                borderMode=cv2.BORDER_REPLICATE)
        difference = (warped - a)[inner]
        step = np.linalg.solve(normal, [-np.sum(gx * difference), -np.sum(gy * difference)])
        shift += step
        if np.abs(step).max() < 1e-3:
            break
    return float(shift[0]), float(shift[1])


def triangulate(theta_left: float, theta_right: float, baseline: float) -> float:
    """Range (m) from the midpoint between the eyes to the point both eyes fixate: eyes
    ``baseline`` m apart on the lateral axis (the left one at +baseline/2), gaze angles from
    straight ahead, rad, positive to the left. The vergence angle is theta_right -
    theta_left (positive when verged on a point ahead)."""
    vergence = np.tan(theta_right) - np.tan(theta_left)
    if vergence <= 0.0:
        return float("inf")
    forward = baseline / vergence
    lateral = forward * np.tan(theta_left) + 0.5 * baseline
    return float(np.hypot(forward, lateral))
