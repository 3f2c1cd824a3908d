"""Foveation, vergence and range: the paper's active-vision loop (Fig. 4) for one target.

An eye looks through :func:`envs.retina.render_eye` at gaze angles (theta, phi). To foveate a
target known by a model image (its colour histogram), the eye searches its levels from the
fovea outward: the first level whose histogram intersection with the model (scaled to the
target's expected size at that level) passes ``detect_threshold`` is the one the target is
located in, by backprojection; the eye then saccades by the angle of that location from the
image centre. After a saccade from the periphery, a second pass in the fovea centres the
target precisely; a target too big for the fovea is centred in the finest level that sees all
of it. With both eyes foveated, the vergence angle is theta_R - theta_L and the
range follows by triangulation (:func:`envs.perception.triangulate`).

``look(theta, phi)`` stands for the world: it returns the eye's levels (L, S, S, 3) at those
gaze angles, so the same code runs on a static scene (tests, figures) and in an env.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from envs.perception import backproject, colour_histogram, intersection, scaled, triangulate
from envs.retina import RetinaParams


@dataclass(frozen=True)
class VisionParams:
    """detect_threshold: histogram intersection for a detection; model_level: the level the
    model image was taken at (its size there); saccades: gaze moves per foveation at most;
    centred: pixels from the fovea's centre that count as foveated; radius: the backprojection
    disk, pixels."""

    detect_threshold: float = 0.3
    model_level: int = 3
    saccades: int = 4
    centred: float = 2.0
    radius: int = 2


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


def detect(levels: np.ndarray, model: np.ndarray, params: VisionParams = VisionParams()
           ) -> tuple[int, float, float]:
    """(level, x, y): the finest level that sees the whole target, and where the target is
    there (pixels: the centre of the extent of its backprojection above half its peak), or
    (-1, nan, nan). A level detects
    the target when the histogram intersection with the model, scaled to the level by the
    area ratio 4^(level - model_level), passes ``detect_threshold``; a finer level whose
    evidence touches the image border sees only part of it, and the next coarser one is
    used."""
    count = float(model.sum())
    for level in range(levels.shape[0] - 1, -1, -1):
        expected = scaled(model, max(count * 4.0 ** (level - params.model_level), 1.0))
        if intersection(colour_histogram(levels[level]), expected) < params.detect_threshold:
            continue
        evidence = backproject(levels[level], expected, params.radius)
        if evidence.max() <= 0:
            continue
        target = evidence >= 0.5 * evidence.max()
        edge = target[0].any() or target[-1].any() or target[:, 0].any() or target[:, -1].any()
        if edge and level > 0:
            continue
        ys, xs = np.nonzero(target)  # the centre of the target's extent in the image
        return level, 0.5 * (xs.min() + xs.max()) + 0.5, 0.5 * (ys.min() + ys.max()) + 0.5
    return -1, float("nan"), float("nan")


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


def verge(left: Fixation, right: Fixation, baseline: float) -> tuple[float, float]:
    """(vergence angle theta_R - theta_L, rad; range, m) of two foveated eyes ``baseline`` m
    apart: triangulated in the head's horizontal plane, then along the mean elevation."""
    flat = triangulate(left.theta, right.theta, baseline)
    return right.theta - left.theta, flat / float(np.cos(0.5 * (left.phi + right.phi)))
