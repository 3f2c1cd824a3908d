"""Foveation, vergence and range: the paper's active-vision loop (Fig. 4) for one target.

An eye looks through :func:`animat.envs.vision.retina.render_eye` at gaze angles (theta, phi). To
foveate a
target known by a model image (its colour histogram), the eye searches its levels from the
fovea outward: the first level whose histogram intersection with the model (scaled to the
target's expected size at that level) passes ``detect_threshold`` is the one the target is
located in, by backprojection; the eye then saccades by the angle of that location from the
image centre. After a saccade from the periphery, a second pass in the fovea centres the
target precisely; a target too big for the fovea is centred in the finest level that sees all
of it. With both eyes foveated, the vergence angle is theta_R - theta_L and the
range follows by triangulation (:func:`animat.envs.vision.perception.triangulate`).

``look(theta, phi)`` stands for the world: it returns the eye's levels (L, S, S, 3) at those
gaze angles, so the same code runs on a static scene (tests, figures) and in an env.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import cv2
import numpy as np

from .perception import (
    backproject,
    colour_bins,
    colour_histogram,
    intersection,
    scaled,
    translational_flow,
    triangulate,
)
from .retina import RetinaParams


@dataclass(frozen=True)
class VisionParams:
    """detect_threshold: histogram intersection for a detection; model_level: the level the
    model image was taken at (its size there); saccades: gaze moves per foveation at most;
    centred: pixels from the fovea's centre that count as foveated; radius: the backprojection
    disk, pixels; min_evidence: the backprojection's peak below which a level sees nothing;
    size_ratio: with a background (:func:`detect`), how far a thing's size may be from a
    view's for the two to be matched."""

    detect_threshold: float = 0.3
    model_level: int = 3
    saccades: int = 4
    centred: float = 2.0
    radius: int = 1
    min_evidence: float = 0.5
    size_ratio: float = 2.0


@dataclass
class Fixation:
    """The result of foveating with one eye: gaze angles (rad), whether the target ended
    centred (within ``centred`` pixels, in the finest level that sees all of it: the fovea
    for a small or distant target), the level of each detection (-1: not found)."""

    theta: float
    phi: float
    foveated: bool
    levels: list[int]


def model_histogram(model_image: np.ndarray, background: np.ndarray | None = None) -> np.ndarray:
    """The target's colour histogram from its model image (S, S, 3), without the pixels marked
    in ``background`` (S, S) bool."""
    mask = None if background is None else ~background
    return colour_histogram(model_image, mask)


def detect(levels: np.ndarray, model: np.ndarray, params: VisionParams = VisionParams(),
           background: np.ndarray | None = None) -> tuple[int, float, float]:
    """(level, x, y): the finest level that sees the whole target, and where the target is
    there (pixels: the centre of the extent of its evidence), or (-1, nan, nan).

    ``model``: the visual memory, one histogram (B, B, B) or one per model image (V, B, B, B),
    e.g. the target from several sides. At each level, from the fovea outward: the
    backprojection of all the views together (each weighted alike, scaled to the whole image
    so that every pixel of a target colour is evidence however big the target looks) marks
    the candidate region, where the evidence is above half its peak (the peak at least
    ``min_evidence``). The level detects the target when the histogram intersection of that
    region with a view's histogram scaled to the level passes ``detect_threshold`` for some
    view: scaled by the area ratio 4^(level - model_level), or to the region's own size if
    the target looks smaller than that (farther away). A finer level whose region touches
    the image border sees only part of the target, and the next coarser one is used.

    ``background``: a bool mask of the histogram's bins (``BINS``), the colours known as the
    world's background. Given it, the region matched is the whole thing around the candidate:
    every pixel of another colour within ``params.radius`` + 1 pixels of the candidate's box,
    so that a thing that shares some colours with the target but has colours of its own as
    well (a fish of a similar hue) matches less than the target does; and it is matched
    against the views of about its size only (:func:`_match`)."""
    views = model.reshape((-1,) + model.shape[-3:])
    counts = views.reshape(len(views), -1).sum(axis=1)
    if np.any(counts <= 0):
        raise ValueError("a model histogram is empty")
    image_pixels = float(levels.shape[1] * levels.shape[2])
    whole = scaled((views / counts[:, None, None, None]).sum(axis=0), image_pixels)
    for level in range(levels.shape[0] - 1, -1, -1):
        evidence = backproject(levels[level], whole, params.radius)
        peak = float(evidence.max())
        if peak < params.min_evidence:
            continue
        sizes = counts * 4.0 ** (level - params.model_level)
        known = None if background is None else background[colour_bins(levels[level])]
        score, target = max(_candidates(levels[level], evidence >= 0.5 * peak, evidence, views,
                                        sizes, known, params), key=lambda c: c[0])
        if score < params.detect_threshold:
            continue
        edge = target[0].any() or target[-1].any() or target[:, 0].any() or target[:, -1].any()
        if edge and level > 0:
            continue
        ys, xs = np.nonzero(target)  # the centre of the target's extent in the image
        return level, 0.5 * (xs.min() + xs.max()) + 0.5, 0.5 * (ys.min() + ys.max()) + 0.5
    return -1, float("nan"), float("nan")


def _candidates(image: np.ndarray, mask: np.ndarray, evidence: np.ndarray, views: np.ndarray,
                sizes: np.ndarray, known: np.ndarray | None, params: VisionParams
                ) -> list[tuple[float, np.ndarray]]:
    """[(match, region (S, S) bool)]: without ``known`` (S, S), the pixels of a background
    colour, the connected part of ``mask``
    (8-neighbours) that holds the evidence's peak, so that evidence elsewhere in the image
    neither joins the target's region nor moves its centre; with it, every connected part
    whose evidence reaches ``min_evidence``, each matched as the whole thing around it, so that
    a thing of similar colours with more evidence does not hide the target beside it."""
    count, labels = cv2.connectedComponents(mask.astype(np.uint8), connectivity=8)
    if known is None:
        peak = np.unravel_index(int(np.argmax(evidence)), evidence.shape)
        parts = [labels == labels[peak]]
    else:
        parts = [part for part in (labels == k for k in range(1, count))
                 if evidence[part].max() >= params.min_evidence]
    out = []
    for part in parts:
        matched = part if known is None else _thing_around(part, known, params.radius + 1)
        pixels = float(matched.sum())
        score = _match(colour_histogram(image, matched), pixels, views, sizes,
                       params.size_ratio if known is not None else None)
        out.append((score, part))
    return out


def _match(region: np.ndarray, pixels: float, views: np.ndarray, sizes: np.ndarray,
           size_ratio: float | None) -> float:
    """The best histogram intersection of ``region`` (``pixels`` of them) with the ``views``,
    each of ``sizes`` pixels at this level: with ``size_ratio``, among the views whose size
    is within that factor of the region's, each scaled to the region's size (0 when there is
    none); without, each scaled to its size or to the region's if that is smaller (a target
    farther away than the view)."""
    if size_ratio is None:
        return max(intersection(region, scaled(view, max(min(size, pixels), 1.0)))
                   for view, size in zip(views, sizes))
    near = [view for view, size in zip(views, sizes)
            if size / size_ratio <= pixels <= size * size_ratio]
    return max((intersection(region, scaled(view, pixels)) for view in near), default=0.0)


def _thing_around(target: np.ndarray, known: np.ndarray, margin: int) -> np.ndarray:
    """(S, S) bool: the pixels not ``known`` (S, S: of a background colour) within ``margin``
    pixels of ``target``'s bounding box (``target`` itself always)."""
    ys, xs = np.nonzero(target)
    box = np.zeros_like(target)
    box[max(ys.min() - margin, 0):ys.max() + margin + 1,
        max(xs.min() - margin, 0):xs.max() + margin + 1] = True
    return target | (box & ~known)


def saccade(theta: float, phi: float, level: int, x: float, y: float,
            retina: RetinaParams = RetinaParams()) -> tuple[float, float]:
    """Gaze angles that bring pixel (x, y) of ``level`` to the optical axis (x right: a
    target right of centre turns the eye right, i.e. theta decreases)."""
    focal, centre = retina.focal(level), 0.5 * retina.size
    return (theta - float(np.arctan((x - centre) / focal)),
            phi - float(np.arctan((y - centre) / focal)))


def foveate(look: Callable[[float, float], np.ndarray], model: np.ndarray, theta: float = 0.0,
            phi: float = 0.0, params: VisionParams = VisionParams(),
            retina: RetinaParams = RetinaParams()) -> Fixation:
    """Saccade until the target sits within ``params.centred`` pixels of the fovea's centre
    (or ``params.saccades`` moves were made, or it is lost)."""
    found = []
    for _ in range(params.saccades):
        level, x, y = detect(look(theta, phi), model, params)
        found.append(level)
        if level < 0:
            return Fixation(theta, phi, False, found)
        centre = 0.5 * retina.size
        if np.hypot(x - centre, y - centre) <= params.centred:
            return Fixation(theta, phi, True, found)
        theta, phi = saccade(theta, phi, level, x, y, retina)
    level, x, y = detect(look(theta, phi), model, params)
    centre = 0.5 * retina.size
    foveated = level >= 0 and np.hypot(x - centre, y - centre) <= params.centred
    return Fixation(theta, phi, bool(foveated), found + [level])


def correlate(left_fovea: np.ndarray, look_right: Callable[[float, float], np.ndarray],
              right: Fixation, retina: RetinaParams = RetinaParams(), moves: int = 3,
              tolerance: float = 0.25) -> Fixation:
    """The right eye turned onto the point the left eye fixates (the paper: "the two retinal
    images must be correlated to keep them verged accurately"): the translational offset of
    the left fovea's image ``left_fovea`` (S, S, 3) in the right one
    (:func:`animat.envs.vision.perception.translational_flow`) taken as a saccade in the fovea,
    repeated
    up to ``moves`` times until it is below ``tolerance`` pixels."""
    theta, phi, fovea, centre = right.theta, right.phi, retina.levels - 1, 0.5 * retina.size
    for _ in range(moves):
        dx, dy = translational_flow(left_fovea, look_right(theta, phi)[fovea])
        if np.hypot(dx, dy) < tolerance:
            break
        theta, phi = saccade(theta, phi, fovea, centre + dx, centre + dy, retina)
    return Fixation(theta, phi, right.foveated, right.levels)


def verge(left: Fixation, right: Fixation, baseline: float) -> tuple[float, float]:
    """(vergence angle theta_R - theta_L, rad; range, m) of two foveated eyes ``baseline`` m
    apart: triangulated in the head's horizontal plane, then along the mean elevation."""
    flat = triangulate(left.theta, right.theta, baseline)
    return right.theta - left.theta, flat / float(np.cos(0.5 * (left.phi + right.phi)))
