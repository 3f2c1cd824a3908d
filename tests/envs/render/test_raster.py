"""The rasterizer's work space: a picture drawn on a canvas kept from camera to camera is the
picture drawn on a fresh one, bit for bit, whatever the cameras before it saw; and leaving out
the chunks of triangles a camera cannot see changes no pixel."""

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
from animat.envs.render.cameras import groups_in_space
from animat.envs.render.raster import (
    canvas,
    chunk_groups,
    draw_picture,
    draw_picture_into,
    group_spheres,
    seen_groups,
)


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
        draw_picture_into(*args, work, np.zeros((0, 4)), np.zeros(0, np.int64))
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
    groups = chunk_groups(len(frame.triangles) - 1)  # one triangle without its group
    spheres = np.zeros((groups.max() + 1, 4))
    with pytest.raises(ValueError, match="one group a triangle"):
        draw_picture_into(frame.triangles, frame.colours, np.array([-0.1, -0.9, 0.1]),
                          np.eye(3), 40.0, float(frame.seabed_z), float(frame.tile),
                          float(frame.visibility), SAND, WATER_TOP, WATER_BOTTOM, FAR, NEAR,
                          np.zeros((64, 64, 3), np.uint8), canvas(64, 64, len(frame.triangles)),
                          spheres, groups)


@pytest.mark.parametrize("grouping", ["runs", "in space"])
def test_culling_the_groups_a_camera_cannot_see_changes_no_pixel(grouping):
    """Groups of consecutive triangles, or of triangles near each other but far apart in the
    list (drawn in the list's order all the same): every corner lies in its group's sphere,
    some camera leaves some group out, and no camera's picture changes by a pixel."""
    frame = _frame(6)
    count = len(frame.triangles)
    groups = (chunk_groups(count) if grouping == "runs" else
              groups_in_space(frame.triangles.mean(axis=1), 0.05, 16))
    spheres = np.empty((groups.max() + 1, 4))
    group_spheres(frame.triangles, groups, spheres)
    for g, box in enumerate(spheres):  # every corner inside its group's sphere
        inside = frame.triangles[groups == g].reshape(-1, 3) - box[:3]
        assert np.linalg.norm(inside, axis=1).max() <= box[3]
    culled_any = False
    for eye, focal in (([-0.1, -0.9, 0.1], 40.0), ([-0.1, -0.9, 0.1], 240.0),
                       ([0.9, 0.3, 0.05], 120.0), ([0.05, 0.3, 0.0], 60.0)):
        eye = np.array(eye)
        rotation = np.ascontiguousarray(look_at(eye, np.array([-0.1, 0.2, 0.0])))
        pictures = []
        for bounds in (np.zeros((0, 4)), spheres):
            image = np.zeros((64, 64, 3), np.uint8)
            draw_picture_into(frame.triangles, frame.colours, eye, rotation, focal,
                              float(frame.seabed_z), float(frame.tile),
                              float(frame.visibility), SAND, WATER_TOP, WATER_BOTTOM, FAR,
                              NEAR, image, canvas(64, 64, count), bounds, groups)
            pictures.append(image)
        np.testing.assert_array_equal(pictures[0], pictures[1])
        seen = np.empty(len(spheres), np.bool_)
        seen_groups(spheres, eye, rotation, focal, (64, 64), NEAR, seen)
        culled_any |= not seen.all()
    assert culled_any  # some camera left some group out


def test_a_group_without_triangles_is_never_seen():
    frame = _frame(1)
    groups = chunk_groups(len(frame.triangles)) + 1  # group 0 is empty
    spheres = np.empty((groups.max() + 1, 4))
    group_spheres(frame.triangles, groups, spheres)
    seen = np.empty(len(spheres), np.bool_)
    seen_groups(spheres, np.array([-0.1, -0.9, 0.1]), np.eye(3), 40.0, (64, 64), NEAR, seen)
    assert spheres[0, 3] == -1.0 and not seen[0]
