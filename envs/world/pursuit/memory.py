"""The pursuer's visual memory of its prey: the colour histograms it detects the prey by
(:func:`prey_model_histogram`), and what it knows of its world's still background
(:func:`background_histogram`), whose colours are left out of the memory.

The prey is remembered as the paper's fish remembers a target, by model images' colour
histograms (:func:`animat.envs.vision.active_vision.model_histogram`): here the prey in open
water seen from all round at several distances. What the prey's images share with the
background (the water, the seabed's sand, rocks and plants; the shaded and hazed tones of a
far fish are the water's and the rocks' tones) is evidence for everything and for nothing, so
those colours are dropped: what is left are the prey's own colours. The other fish of the
pursuit (its distractor and passers) are not part of that background: the memory does not
know them.
"""

from __future__ import annotations

import numpy as np

from ...bodies.fish import fish_body
from ...render.camera import Scene, fish_skin, posed
from ...render.scenery import furnish
from ...vision.active_vision import model_histogram
from ...vision.perception import colour_histogram
from ...vision.retina import RetinaParams, gaze_rotation, render_eye
from .start import PREY_COLOUR, SEABED_Z, scenery

MODEL_VIEWS = tuple((distance, np.radians(yaw)) for distance in (0.7, 1.2, 2.0, 3.0, 4.0)
                    for yaw in range(0, 360, 45))  # (m, rad): the prey's poses in memory
MIN_VIEW_PIXELS = 8  # a view with fewer pixels of the prey's own colours is not kept
BACKGROUND_SHARE = 0.002  # a colour this common in the background is not the prey's
BACKGROUND_LAYOUTS = 3  # seeded sceneries the background is learned from (seeds 10 000 on)
BACKGROUND_GAZES = tuple((np.radians(theta), np.radians(phi)) for theta in (-60, -30, 0, 30, 60)
                         for phi in (-30, -10, 10))  # (rad, rad) the eye looked along


def background_histogram(retina: RetinaParams = RetinaParams()) -> np.ndarray:
    """(B, B, B) the share of each colour in what the eye sees of the still world without
    fish: ``BACKGROUND_LAYOUTS`` seeded sceneries of the pursuit (seabed, occluders), each
    from the start point along each of ``BACKGROUND_GAZES``, every retina level."""
    total = np.zeros(colour_histogram(np.zeros((1, 1, 3), np.uint8)).shape, np.float64)
    for seed in range(BACKGROUND_LAYOUTS):
        things = scenery(np.random.default_rng(10_000 + seed), occluders=True)
        scene = furnish(Scene(seabed_z=SEABED_Z), things)
        for theta, phi in BACKGROUND_GAZES:
            levels = render_eye(scene, np.zeros(3), gaze_rotation(np.eye(3), theta, phi), retina)
            total += sum(colour_histogram(level) for level in levels)
    return total / total.sum()


def background_colours(retina: RetinaParams = RetinaParams()) -> np.ndarray:
    """(BINS) bool: the colours that make up ``BACKGROUND_SHARE`` or more of the background
    (:func:`background_histogram`)."""
    return background_histogram(retina) >= BACKGROUND_SHARE


def prey_model_histogram(retina: RetinaParams = RetinaParams()) -> np.ndarray:
    """The visual memory of the prey: (V, B, B, B) the colour histograms of its model images,
    the prey in open water seen through the 30 deg level from all round (every 45 deg of its
    heading) at five distances, 0.7-4 m (only what differs from the empty water), so that it
    is known from behind as well as broadside, by its lit side and its shaded one, near and
    through the haze of up to 4 m; without the colours that make up ``BACKGROUND_SHARE`` or
    more of the background (:func:`background_histogram`), and without the views left with
    fewer than ``MIN_VIEW_PIXELS`` pixels."""
    body, level = fish_body(), retina.levels - 2  # the whole fish fits at 30 deg
    skin, eye = fish_skin(body, PREY_COLOUR), np.zeros(3)
    rotation = gaze_rotation(np.eye(3), 0.0, 0.0)
    empty = render_eye(Scene(seabed_z=SEABED_Z), eye, rotation, retina)[level]
    common = background_colours(retina)
    views = []
    for distance, yaw in MODEL_VIEWS:
        scene = Scene(seabed_z=SEABED_Z).add(body, posed(body, [distance, 0.0, 0.0], yaw), skin)
        seen = render_eye(scene, eye, rotation, retina)[level]
        view = model_histogram(seen, background=np.all(seen == empty, -1))
        view[common] = 0.0
        if view.sum() >= MIN_VIEW_PIXELS:
            views.append(view)
    return np.stack(views)
