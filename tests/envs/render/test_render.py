"""Scene and camera: what is there, and how it is seen."""

import numpy as np

from animat.envs.bodies.fish import fish_body
from animat.envs.render.camera import Camera, Scene, look_at


def _camera(eye, target, size=200):
    eye, target = np.asarray(eye, float), np.asarray(target, float)
    return Camera(size, size, 0.9 * size, eye, look_at(eye, target))


def test_a_nearer_body_hides_the_one_behind_it():
    body = fish_body()
    behind = body.rest_positions + [0.0, 0.0, 0.0]
    front = body.rest_positions + [0.0, -0.3, 0.0]  # between the camera and the first fish
    camera = _camera([-0.15, -1.0, 0.0], [-0.15, 0.0, 0.0])
    alone = camera.render(Scene().add(body, behind, (255, 0, 0)))
    both = camera.render(Scene().add(body, behind, (255, 0, 0)).add(body, front, (0, 0, 255)))
    red_alone = (alone[..., 0] > 120) & (alone[..., 2] < 60)
    red_both = (both[..., 0] > 120) & (both[..., 2] < 60)
    blue_both = (both[..., 2] > 120) & (both[..., 0] < 60)
    assert red_alone.sum() > 100 and blue_both.sum() > red_alone.sum()  # nearer looks bigger
    assert red_both.sum() < 0.2 * red_alone.sum()  # and covers the fish behind it


def test_projection_puts_the_target_at_the_image_centre():
    camera = _camera([1.0, 2.0, 0.5], [0.0, 0.0, 0.0], size=100)
    pixels, depth = camera.project(np.zeros(3))
    np.testing.assert_allclose(pixels, [50.0, 50.0], atol=1e-9)
    assert abs(depth - np.linalg.norm([1.0, 2.0, 0.5])) < 1e-12
