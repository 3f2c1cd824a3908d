"""The rasterizer's work space: a picture drawn on a canvas kept from camera to camera is the
picture drawn on a fresh one, bit for bit, whatever the cameras before it saw."""

import numpy as np
import pytest

from animat.envs.bodies.fish import fish_body
from animat.envs.render.camera import (
    FAR,
    NEAR,
    SAND,
    WATER_BOTTOM,
    WATER_TOP,
    Camera,
    Scene,
    look_at,
)
from animat.envs.render.raster import canvas, draw_picture, draw_picture_into


def _frame(fish: int):
    body, scene = fish_body(), Scene()
    for k in range(fish):
        scene.add(body, body.rest_positions + [0.0, 0.12 * k, 0.02 * k], (200, 40 * k, 60))
    return scene.prepare()


def _draw(frame, eye, work=None):
    camera = Camera(64, 64, 40.0, eye, look_at(eye, np.array([-0.1, 0.2, 0.0])))
    image = np.full((64, 64, 3), 7, np.uint8)
    args = (frame.triangles, frame.colours, np.asarray(eye, float),
            np.ascontiguousarray(camera.rotation), 40.0, float(frame.seabed_z),
            float(frame.tile), float(frame.visibility), SAND, WATER_TOP, WATER_BOTTOM, FAR,
            NEAR, image)
    if work is None:
        draw_picture(*args)
    else:
        draw_picture_into(*args, work)
    return image


def test_a_kept_canvas_draws_what_a_fresh_one_draws():
    crowded, sparse = _frame(4), _frame(1)
    work = canvas(64, 64, crowded.triangles.shape[0])
    eyes = (np.array([-0.1, -0.9, 0.1]), np.array([0.6, -0.5, 0.3]))
    pictures = []
    for frame, eye in ((crowded, eyes[0]), (sparse, eyes[1]), (crowded, eyes[1])):
        kept, fresh = _draw(frame, eye, work), _draw(frame, eye)
        assert np.array_equal(kept, fresh)
        assert len(np.unique(fresh.reshape(-1, 3), axis=0)) > 20  # fish, seabed and water
        pictures.append(fresh)
    assert not np.array_equal(pictures[1], pictures[2])  # the crowd is in the picture


def test_a_canvas_too_small_is_refused():
    frame = _frame(2)
    with pytest.raises(ValueError, match="canvas is for fewer triangles"):
        _draw(frame, np.array([-0.1, -0.9, 0.1]), canvas(64, 64, frame.triangles.shape[0] - 1))
    with pytest.raises(ValueError, match="other pixels"):
        _draw(frame, np.array([-0.1, -0.9, 0.1]), canvas(32, 64, frame.triangles.shape[0]))
