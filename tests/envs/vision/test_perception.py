"""Active-vision primitives: histograms, backprojection, optical flow, triangulation."""

import cv2
import numpy as np
import pytest

from animat.envs.bodies.fish import fish_body
from animat.envs.render.camera import Scene, posed
from animat.envs.vision.perception import (
    colour_histogram,
    intersection,
    locate,
    scaled,
    translational_flow,
    triangulate,
)
from animat.envs.vision.retina import RetinaParams, gaze_rotation, render_eye


def _textured(seed=0, size=64):
    rng = np.random.default_rng(seed)
    noise = rng.uniform(0, 255, (size // 4, size // 4, 3)).astype(np.uint8)
    return cv2.resize(noise, (size, size), interpolation=cv2.INTER_CUBIC)


def test_histogram_intersection_of_an_image_with_itself_is_one():
    image = _textured()
    assert intersection(colour_histogram(image), colour_histogram(image)) == pytest.approx(1.0)
    other = np.zeros_like(image)
    assert intersection(colour_histogram(other), colour_histogram(image)) < 0.1
    model = colour_histogram(image)
    assert scaled(model, 100.0).sum() == pytest.approx(100.0)


def test_backprojection_of_a_red_target_peaks_on_the_target():
    body = fish_body()
    x = posed(body, [1.0, 0.25, 0.05], np.pi / 2)
    scene = Scene(seabed_z=-0.4).add(body, x, (220, 40, 40))
    decoy = posed(body, [1.2, -0.3, 0.0])
    scene.add(body, decoy, (230, 210, 40))  # a yellow fish elsewhere
    image = render_eye(scene, np.zeros(3), gaze_rotation(np.eye(3), 0.0, 0.0))[1]  # 60 deg
    red = (image[..., 0] > 70) & (image[..., 1] < 40) & (image[..., 2] < 40)
    close_up = render_eye(Scene(seabed_z=-0.4).add(body, x, (220, 40, 40)), np.zeros(3),
                          gaze_rotation(np.eye(3), np.radians(14.0), np.radians(3.0)))[2]
    target = (close_up[..., 0] > 70) & (close_up[..., 1] < 40) & (close_up[..., 2] < 40)
    model = scaled(colour_histogram(close_up, target), float(red.sum()))  # the model image
    px, py, strength = locate(image, model, radius=2)
    ys, xs = np.nonzero(red)
    assert red.sum() > 15 and strength > 0
    assert abs(px - xs.mean()) < 3 and abs(py - ys.mean()) < 3  # on the red fish, not the yellow


@pytest.mark.parametrize("shift", [(1.3, -0.7), (-2.6, 1.9), (0.4, 0.0)])
def test_optical_flow_recovers_a_known_shift_within_half_a_pixel(shift):
    image = _textured(seed=3)
    moved = cv2.warpAffine(image, np.float32([[1, 0, shift[0]], [0, 1, shift[1]]]), (64, 64),
                           flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REFLECT)
    dx, dy = translational_flow(image, moved)
    assert abs(dx - shift[0]) < 0.5 and abs(dy - shift[1]) < 0.5, (dx, dy)


def test_triangulated_range_of_a_verged_target_at_two_body_lengths_is_within_ten_percent():
    length, baseline = 0.30, 2 * RetinaParams().eye_offset[1] * 0.30
    target = np.array([2.0 * length, 0.1 * length])  # ahead, a little to the left
    angles = [np.arctan2(target[1] - side * baseline / 2, target[0]) for side in (1, -1)]
    estimate = triangulate(angles[0], angles[1], baseline)
    assert estimate == pytest.approx(np.hypot(*target), rel=0.1)
    assert triangulate(0.1, 0.1, baseline) == float("inf")  # parallel gaze: no range


def test_backprojection_keeps_fractional_ratios():
    """A colour the model has half as often as the image gets evidence 0.5, not 0."""
    from animat.envs.vision.perception import backproject

    image = np.zeros((16, 16, 3), np.uint8)
    image[:, :8] = (200, 30, 30)
    model = colour_histogram(image) * 0.5
    evidence = backproject(image, model, radius=0)
    assert evidence[8, 2] == pytest.approx(0.5, abs=0.01)
    assert evidence[8, 12] == pytest.approx(0.5, abs=0.01)


def test_backprojection_lights_the_pixels_of_each_bin_and_no_other():
    """Every pixel's evidence is its own colour bin's ratio (cv2.calcBackProject read a
    three-dimensional NumPy histogram as a two-dimensional image of many channels, and lit
    the wrong pixels)."""
    from animat.envs.vision.perception import backproject, colour_bins

    image = np.zeros((8, 8, 3), np.uint8)
    image[:] = (52, 35, 46)  # a dark fish
    image[:4] = (34, 82, 125)  # the water
    image[0, 0] = (200, 50, 40)
    for pixel in [(5, 5), (1, 1), (0, 0)]:
        model = np.zeros_like(colour_histogram(image))
        model[tuple(axis[pixel] for axis in colour_bins(image))] = 1000.0
        evidence = backproject(image, model, radius=0)
        same = np.all(image == image[pixel], axis=-1)
        np.testing.assert_allclose(evidence[same], 1.0)
        assert not evidence[~same].any()


def test_red_and_salmon_fall_in_different_bins_in_the_light_and_in_the_shade():
    """The prey's red and its distractor's salmon, at each shade a fish skin has (0.57-1)."""
    from animat.envs.vision.perception import colour_bins

    for shade in (1.0, 0.85, 0.7, 0.57):
        image = (np.array([[(220, 50, 40), (240, 120, 110)]]) * shade).astype(np.uint8)
        bins = [tuple(int(axis[0, k]) for axis in colour_bins(image)) for k in range(2)]
        assert bins[0] != bins[1]
