"""What the eyes see besides fish: the seabed, the water's haze, rocks, plants, food, and the
texture that optical flow locks onto."""

import numpy as np
import pytest

from animat.envs.bodies.fish import fish_body
from animat.envs.render.camera import WATER_BOTTOM, WATER_TOP, Scene, fish_skin, posed
from animat.envs.render.scenery import SceneryParams, furnish, scatter
from animat.envs.vision.perception import translational_flow
from animat.envs.vision.retina import RetinaParams, gaze_rotation, render_eye

HEAD, EYE = np.eye(3), np.zeros(3)


def test_scatter_stands_rocks_and_plants_on_the_seabed_and_floats_the_food():
    params = SceneryParams(rocks=4, plants=3, food=5)
    things = scatter(np.random.default_rng(1), -0.5, params)
    assert len(things) == 12
    rocks, plants, food = things[:4], things[4:7], things[7:]
    for corners, colours in rocks:
        assert corners.shape == (6, 4, 3) and colours.shape == (6, 3)
        assert corners[..., 2].min() == -0.5 and corners[..., 2].max() <= -0.5 + 0.25
    for corners, _ in plants:
        assert corners[..., 2].min() == -0.5 and corners[..., 2].max() <= -0.5 + 0.35 + 1e-9
    for corners, _ in food:
        assert abs(corners[..., 2].mean()) <= params.food_depth
    again = scatter(np.random.default_rng(1), -0.5, params)
    assert all(np.array_equal(a[0], b[0]) for a, b in zip(things, again))  # seeded
    scene = furnish(Scene(seabed_z=-0.5), things)
    assert len(scene.meshes) == 1 and len(scene.meshes[0][0]) == 4 * 6 + 3 * 8 + 5 * 6


def test_the_seabed_is_textured_below_the_horizon_and_the_water_brightens_upward():
    level0 = render_eye(Scene(seabed_z=-0.5), EYE, gaze_rotation(HEAD, 0.0, 0.0))[0]
    sand, water = level0[40:].astype(float), level0[:28].astype(float)
    assert (sand[..., 0] > sand[..., 2]).mean() > 0.9  # sand is yellowish near the eye
    assert sand[8:20].std(axis=(0, 1)).min() > 3  # tiles of different brightness
    assert (water[..., 2] > water[..., 0]).all()  # blue water
    assert water[0, :, 2].mean() > water[-1, :, 2].mean()  # brighter toward the surface


def test_depth_haze_fades_a_far_fish_toward_the_water():
    body = fish_body()
    centres = []
    for distance in (0.5, 4.0):
        scene = Scene(seabed_z=-5.0).add(body, posed(body, [distance, 0.0, 0.0], np.pi / 2),
                                         (220, 50, 40))
        centres.append(render_eye(scene, EYE, gaze_rotation(HEAD, 0.0, 0.0))[3][32, 32])
    near, far = np.asarray(centres, float)
    water = 0.5 * (WATER_TOP + WATER_BOTTOM)  # a horizontal ray's water colour
    assert np.all(np.abs(far - water) < np.abs(near - water))  # every channel nearer the water
    keep = (far[0] - water[0]) / (near[0] - water[0])  # 3.5 m more water between
    assert keep == pytest.approx(np.exp(-3.5 / Scene().visibility), abs=0.05)


def test_optical_flow_recovers_a_small_gaze_turn_on_the_rendered_textured_fish():
    body, retina = fish_body(), RetinaParams()
    x = posed(body, [0.6, 0.0, 0.0], np.pi / 2)
    scene = Scene(seabed_z=-0.5).add(body, x, fish_skin(body, (220, 50, 40)))
    before = render_eye(scene, EYE, gaze_rotation(HEAD, 0.0, 0.0))[3]
    turn = np.radians(0.3)  # to the left: the image moves right
    after = render_eye(scene, EYE, gaze_rotation(HEAD, turn, 0.0))[3]
    dx, dy = translational_flow(before, after)
    expected = retina.focal(3) * np.tan(turn)
    assert abs(dx - expected) < 0.5 and abs(dy) < 0.5, (dx, dy, expected)


def test_a_skin_gives_a_fish_many_shades_of_its_colour():
    body = fish_body()
    skin = fish_skin(body, (220, 50, 40))
    assert skin.shape == (4 * len(body.faces), 3)
    assert len(np.unique(np.round(skin[:, 0]))) >= 6 and skin.max() <= 255
