"""The retina: coaxial foveated cameras, pure functions of the scene and the eye poses."""

import gymnasium as gym
import numpy as np
import pytest

import animat  # noqa: F401
from animat.envs.bodies.fish import fish_body
from animat.envs.core.sensors import Proprioception
from animat.envs.render.camera import Scene, posed
from animat.envs.vision.retina import (
    Retina,
    RetinaParams,
    Sighted,
    composite,
    eye_poses,
    eye_positions,
    gaze_rotation,
    render_eye,
    render_eyes,
    stack_levels,
)

HEAD = np.eye(3)  # rows forward (+x), left (+y), up (+z)
EYE = np.zeros(3)


def _fish_at(centre, colour, yaw=np.pi / 2):
    """A fish body broadside on (turned ``yaw`` about z), its mid-body at ``centre``."""
    body = fish_body()
    return body, posed(body, centre, yaw), colour


def _red(image):
    return (image[..., 0] > 70) & (image[..., 1] < 30) & (image[..., 2] < 30)


def _scene(*fishes):
    scene = Scene(seabed_z=-5.0)
    for fish in fishes:
        scene.add(*fish)
    return scene


def test_an_object_straight_ahead_is_at_the_centre_of_every_level():
    scene = _scene(_fish_at([1.0, 0.0, 0.0], (255, 0, 0)))
    levels = render_eye(scene, EYE, gaze_rotation(HEAD, 0.0, 0.0))
    assert levels.shape == (4, 64, 64, 3) and levels.dtype == np.uint8
    for image in levels:
        assert _red(image)[30:34, 30:34].any()  # at the centre of every level
    assert _red(levels[3])[28:36, 28:36].all()
    sizes = [_red(image).sum() for image in levels]
    assert sizes == sorted(sizes)  # each level magnifies twice as much


def test_an_object_40_degrees_off_axis_is_seen_by_level_0_and_not_the_fovea():
    angle = np.radians(40.0)
    scene = _scene(_fish_at([np.cos(angle), np.sin(angle), 0.0], (255, 0, 0), yaw=angle + 1.57))
    levels = render_eye(scene, EYE, gaze_rotation(HEAD, 0.0, 0.0))
    assert _red(levels[0]).sum() > 5
    assert _red(levels[3]).sum() == 0
    turned = render_eye(scene, EYE, gaze_rotation(HEAD, angle, 0.0))  # gaze 40 deg left
    assert _red(turned[3])[30:34, 30:34].all()


def test_a_nearer_object_occludes_a_farther_one():
    near, far = _fish_at([0.8, 0.0, 0.0], (0, 0, 255)), _fish_at([1.6, 0.0, 0.0], (255, 0, 0))
    alone = _red(render_eye(_scene(far), EYE, gaze_rotation(HEAD, 0.0, 0.0))[3]).sum()
    seen = []
    for order in ((near, far), (far, near)):  # whatever order the scene lists them in
        fovea = render_eye(_scene(*order), EYE, gaze_rotation(HEAD, 0.0, 0.0))[3]
        assert (fovea[28:36, 28:36, 2] > 70).all() and not _red(fovea)[28:36, 28:36].any()
        seen.append(_red(fovea).sum())
    assert seen[0] == seen[1] < 0.1 * alone  # the far fish shows only past the near one's tail


def test_gaze_up_looks_up_and_the_composite_stacks_the_levels():
    rotation = gaze_rotation(HEAD, 0.0, np.radians(30.0))
    np.testing.assert_allclose(rotation[2], [np.cos(np.radians(30)), 0.0, np.sin(np.radians(30))])
    np.testing.assert_allclose(np.linalg.det(rotation), 1.0)
    levels = np.stack([np.full((64, 64, 3), 40 * (k + 1), np.uint8) for k in range(4)])
    out = composite(levels)
    assert out.shape == (512, 512, 3)
    assert out[0, 0, 0] == 40 and out[256, 256, 0] == 160 and out[200, 200, 0] == 120


def test_retina_params_are_checked():
    with pytest.raises(ValueError, match="field_of_view"):
        RetinaParams(field_of_view=200.0)
    assert RetinaParams().focal(3) == pytest.approx(32.0 / np.tan(np.radians(7.5)))


class TwoObservers:
    """A :class:`~animat.envs.vision.retina.Sighted` of two observers at the origin: the first
    looks along +x at a red fish, the second's eyes look along -x, away from it."""

    def scene(self):
        return _scene(_fish_at([1.0, 0.0, 0.0], (255, 0, 0)))

    def eye_poses(self, kinematics):
        ahead, behind = gaze_rotation(HEAD, 0.0, 0.0), gaze_rotation(HEAD, np.pi, 0.0)
        positions = np.array([[[0.0, 0.01, 0.0], [0.0, -0.01, 0.0]]] * 2)
        return positions, np.array([[ahead, ahead], [behind, behind]])


def test_the_retina_sensor_reads_both_eyes_of_every_observer_stacked():
    retina = Retina(RetinaParams(size=32))
    space = retina.space(TwoObservers())
    assert set(space.spaces) == {"left_eye", "right_eye"}
    assert space["left_eye"].shape == (32, 32, 12) and space["left_eye"].dtype == np.uint8
    reading = retina.read(TwoObservers(), None)
    assert reading["left_eye"].shape == (2, 32, 32, 12)
    assert space.contains({k: v[0] for k, v in reading.items()})
    levels = render_eye(TwoObservers().scene(), np.array([0.0, 0.01, 0.0]),
                        gaze_rotation(HEAD, 0.0, 0.0), RetinaParams(size=32))
    np.testing.assert_array_equal(reading["left_eye"][0], np.concatenate(list(levels), -1))
    fovea = reading["right_eye"][:, :, :, 9:12]  # the last level's RGB
    assert _red(fovea[0])[14:18, 14:18].all() and not _red(fovea[1]).any()
    assert stack_levels(levels[None]).shape == (1, 32, 32, 12)


def test_eye_poses_place_both_eyes_and_the_retina_renders_them_as_render_eyes():
    gaze = np.radians([[20.0, -5.0], [-10.0, 8.0]])
    head, length = np.array([0.3, -0.2, 0.1]), 0.5
    positions, rotations = eye_poses(HEAD, head, length, gaze)
    np.testing.assert_array_equal(positions, eye_positions(HEAD, head, length))
    for rotation, angles in zip(rotations, gaze):
        np.testing.assert_array_equal(rotation, gaze_rotation(HEAD, *angles))
    observers = TwoObservers()
    images = Retina(RetinaParams(size=32)).images(observers, None)
    for places, turns, seen in zip(*observers.eye_poses(None), images):
        np.testing.assert_array_equal(seen, render_eyes(observers.scene(), places, turns,
                                                        RetinaParams(size=32)))


def test_the_retina_is_refused_in_one_line_where_there_are_no_eyes():
    assert isinstance(TwoObservers(), Sighted)
    with pytest.raises(ValueError) as error:
        gym.make("Animat/FishSwim-v0", sensors=[Proprioception(), Retina()])
    assert str(error.value) == ("sensors: the retina needs an observer with eyes (e.g. "
                                "Animat/FishPursuit-v0), got a BodyBatch")
