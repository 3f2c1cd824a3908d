"""The per-pixel passes along a camera's rays: the rays themselves, the seabed, the haze."""

import numpy as np

from animat.envs.render.rays import pixel_ray, pixel_rays, seabed_into, water_into

DOWN = np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]])  # right, down, forward
AHEAD = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])  # looking along +x


def _rays(rotation, focal=20.0, size=16):
    rays = np.empty((4, size, size))
    pixel_rays(rotation, focal, rays)
    return rays


def test_every_pixels_ray_is_its_pixel_ray_and_its_length():
    rays = _rays(AHEAD, size=8)
    for i in range(8):
        for j in range(8):
            ray = pixel_ray(AHEAD, 20.0, 8, 8, i, j)
            np.testing.assert_array_equal(rays[:3, i, j], ray)
            assert rays[3, i, j] == np.sqrt(sum(d * d for d in ray))
    assert rays[0].min() == 1.0  # unit depth along the camera's axis, +x


def test_the_seabed_is_met_at_the_cameras_height_and_not_from_below_it():
    image, zbuffer = np.zeros((16, 16, 3), np.uint8), np.full((16, 16), np.inf)
    shades = np.empty(256)  # work space
    sand = np.array([200.0, 180.0, 120.0])
    seabed_into(image, zbuffer, np.array([0.0, 0.0, 1.5]), _rays(DOWN), -0.5, 0.25, sand,
                50.0, shades)
    np.testing.assert_allclose(zbuffer, 2.0)  # depth along the axis: every pixel 2 m down
    assert image.min() > 0 and image.max() <= 255
    below = np.full((16, 16), np.inf)
    seabed_into(image, below, np.array([0.0, 0.0, -1.0]), _rays(DOWN), -0.5, 0.25, sand,
                50.0, shades)
    assert np.isinf(below).all()


def test_the_haze_keeps_exp_of_minus_distance_over_visibility():
    top, bottom, visibility = np.array([40.0, 120.0, 200.0]), np.array([0.0, 20.0, 60.0]), 8.0
    rays = _rays(AHEAD, size=16)
    depth = np.full((16, 16), np.inf)
    depth[8, :] = [0.5 * k for k in range(16)]  # a row of things at growing distances
    image = np.full((16, 16, 3), 255, np.uint8)
    keeps, ups = np.empty(256), np.empty(256)
    water_into(image, depth, rays, top, bottom, visibility, keeps, ups)
    up = 0.5 * (1.0 + rays[2] / rays[3])
    water = bottom + up[..., None] * (top - bottom)  # the water's colour along each ray
    np.testing.assert_array_equal(image[0], np.floor(water[0] + 0.5).astype(np.uint8))
    distance = depth[8] * rays[3, 8]
    keep = np.exp(-distance / visibility)[:, None]
    expected = water[8] + keep * (255.0 - water[8])
    assert np.abs(image[8] - expected).max() <= 0.5 + 255 * 1e-4
    assert image[8, 0, 0] == 255 and image[8, -1, 0] < image[8, 1, 0]
