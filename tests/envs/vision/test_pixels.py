"""Retinal observations sized for learners: the same eyes' cameras, fewer and smaller, and the
target's backprojection; in the pursuit, named in its sensors and stacked channel-first."""

import cv2
import gymnasium as gym
import numpy as np
import pytest

import animat  # noqa: F401
from animat.envs.bodies.fish import fish_body
from animat.envs.core.sensors import make_sensor, register_sensor
from animat.envs.render.camera import Scene, fish_skin, posed
from animat.envs.vision.perception import (
    BINS,
    backproject,
    backproject_layers,
    colour_bins,
    colour_histogram,
    scaled,
)
from animat.envs.vision.pixels import RetinaPixels, TargetEvidence, grey
from animat.envs.vision.retina import Retina, RetinaParams, gaze_rotation, render_eye
from animat.envs.world.pursuit.memory import prey_model_histogram
from animat.envs.world.pursuit.start import PREY_COLOUR, SEABED_Z

HEAD = np.eye(3)  # rows forward (+x), left (+y), up (+z)


class PreyAhead:
    """Two observers with eyes: the first looks at the pursuit's prey 1 m ahead, broadside
    on, the second away from it."""

    def scene(self):
        body = fish_body()
        return Scene(seabed_z=SEABED_Z).add(body, posed(body, [1.0, 0.0, 0.0], np.pi / 2),
                                             fish_skin(body, PREY_COLOUR))

    def eye_poses(self, kinematics):
        ahead, behind = gaze_rotation(HEAD, 0.0, 0.0), gaze_rotation(HEAD, np.pi, 0.0)
        positions = np.array([[[0.0, 0.01, 0.0], [0.0, -0.01, 0.0]]] * 2)
        return positions, np.array([[ahead, ahead], [behind, behind]])


def _retina_images(source):
    """(B, 2, 4, 64, 64, 3) uint8: every level of both eyes of each observer."""
    return Retina().images(source, None)


def test_pixels_are_the_chosen_cameras_of_both_eyes_channel_first():
    source, full = PreyAhead(), _retina_images(PreyAhead())
    colour = RetinaPixels(levels=[3, 0], size=64, colour=True)
    assert colour.space(source).shape == (12, 64, 64)
    seen = colour.read(source, None)
    for b in range(2):
        for eye in range(2):
            for k, level in enumerate((3, 0)):
                picture = seen[b, 6 * eye + 3 * k:6 * eye + 3 * k + 3]
                np.testing.assert_array_equal(picture, full[b, eye, level].transpose(2, 0, 1))
    luma = RetinaPixels(levels=[0, 3], size=64).read(source, None)
    assert luma.shape == (2, 4, 64, 64) and luma.dtype == np.uint8
    np.testing.assert_array_equal(luma[0, 3], grey(full[0, 1, 3]))
    assert grey(np.array([[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]],
                         np.uint8)).tolist() == [76, 150, 29, 255]


def test_grey_is_bt601_luma_rounded_for_every_colour():
    axis = np.arange(256)
    rgb = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)
    exact = np.floor((rgb @ np.array([299.0, 587.0, 114.0])) / 1000.0 + 0.5)
    np.testing.assert_array_equal(grey(rgb.astype(np.uint8)), exact.astype(np.uint8))


def test_smaller_pictures_are_the_same_cameras_with_fewer_pixels():
    source = PreyAhead()
    small = RetinaPixels(levels=[0, 3], size=32, colour=True).read(source, None)
    drawn = render_eye(source.scene(), np.array([0.0, 0.01, 0.0]), gaze_rotation(HEAD, 0, 0),
                       RetinaParams(size=32, drawn=(0, 3)))
    np.testing.assert_array_equal(small[0, 3:6], drawn[1].transpose(2, 0, 1))
    fovea = small[0, 3:6].transpose(1, 2, 0)  # the left eye's fovea, on the prey
    plain = render_eye(Scene(seabed_z=SEABED_Z), np.array([0.0, 0.01, 0.0]),
                       gaze_rotation(HEAD, 0, 0), RetinaParams(size=32, drawn=(3,)))[0]
    assert (np.abs(fovea.astype(int) - plain).sum(-1)[12:20, 12:20] > 30).mean() > 0.5


def test_evidence_is_the_backprojection_of_the_memory_high_on_the_prey():
    source, full = PreyAhead(), _retina_images(PreyAhead())
    memory = prey_model_histogram()
    sensor = TargetEvidence(memory, levels=[0, 2], size=64)
    maps = sensor.read(source, None)
    assert sensor.space(source).shape == (4, 64, 64) and maps.dtype == np.uint8
    whole = scaled(sensor.memory, 64 * 64)
    expected = backproject(full[0, 1, 2], whole, 2)
    np.testing.assert_array_equal(maps[0, 3], np.clip(np.rint(255 * expected), 0, 255))
    centre, rim = maps[0, 1, 24:40, 24:40], maps[0, 1, :8]
    assert centre.mean() > 60 and rim.mean() < 5  # the prey at the 30 deg level's centre
    assert maps[1].max() < 5  # looking away: nothing of the prey's colours
    small = TargetEvidence(memory, levels=[0, 2], size=16).read(source, None)
    assert small.shape == (2, 4, 16, 16) and abs(small[0, 1].mean() - maps[0, 1].mean()) < 2


def _backprojected(image, model, radius):
    """Swain and Ballard's backprojection written plainly in NumPy and OpenCV: the reference
    the compiled one must equal."""
    bins = colour_bins(image)
    counts = np.bincount(np.ravel_multi_index(bins, BINS).ravel(),
                         minlength=int(np.prod(BINS))).reshape(BINS).astype(np.float32)
    ratio = np.minimum(model / np.maximum(counts, 1e-6), 1.0).astype(np.float32)
    size = 2 * radius + 1
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (size, size)).astype(np.float32)
    return cv2.filter2D(ratio[bins], -1, disk / disk.sum(), borderType=cv2.BORDER_CONSTANT)


def test_many_backprojections_at_once_are_each_one_alone():
    rng = np.random.default_rng(0)
    images = rng.integers(0, 256, (6, 32, 32, 3), dtype=np.uint8)
    images[:2] //= 64  # a few colours, many pixels each
    model = colour_histogram(images[0]) + rng.random((16, 16, 8)).astype(np.float32)
    layers = backproject_layers(images.reshape(3, 2, 32, 32, 3).transpose(0, 2, 3, 1, 4),
                                model, 3)
    for k, image in enumerate(images):
        np.testing.assert_array_equal(layers[:, :, k], _backprojected(image, model, 3))
        np.testing.assert_array_equal(backproject(image, model, 3), layers[:, :, k])
    wide = (rng.random((16, 16, 8)) * 50).astype(np.float64)  # a float64 memory, as detect's
    np.testing.assert_array_equal(backproject(images[0], wide, 2),
                                  _backprojected(images[0], wide, 2))


def test_the_pursuit_takes_sensors_by_name_and_stacks_pictures_channel_first():
    sensors = [{"name": "pixels", "levels": [0, 3], "size": 32}, "gaze", "proprioception"]
    env = gym.make("Animat/FishPursuit-v0", duration=1.0, frames=3, sensors=sensors)
    space = env.observation_space
    assert space["pixels"].shape == (12, 32, 32) and "left_eye" not in space.spaces
    obs, _ = env.reset(seed=3)
    assert space.contains(obs)
    np.testing.assert_array_equal(obs["pixels"][:4], obs["pixels"][8:])  # a reset fills it
    action = np.array([0.5, 0.0, 0.0, 0.6, -0.2, -0.5, 0.1], np.float32)
    first, *_ = env.step(action)
    second, *_ = env.step(action)
    np.testing.assert_array_equal(second["pixels"][:8], first["pixels"][4:])  # oldest first
    vector = gym.make_vec("Animat/FishPursuit-v0", num_envs=2, duration=1.0, frames=3,
                          sensors=sensors)
    batch, _ = vector.reset(seed=3)
    np.testing.assert_array_equal(batch["pixels"][0], obs["pixels"])


def test_bad_sensors_are_refused_in_one_line():
    bad = [("nose", "unknown sensor 'nose'"),
           ({"name": "pixels", "levels": [0, 4]}, "levels must be distinct levels"),
           ({"name": "pixels", "levels": [1, 1]}, "levels must be distinct levels"),
           ({"name": "pixels", "size": 65}, "size must be an integer in [8, 64]"),
           ({"name": "pixels", "colour": "yes"}, "colour must be true or false"),
           ({"name": "pixels", "zoom": 2}, "sensor 'pixels': "),
           ({"name": "evidence", "radius": -1}, "radius must be an integer in [0, 16]")]
    for spec, message in bad:
        with pytest.raises(ValueError) as error:
            gym.make("Animat/FishPursuit-v0", sensors=[spec, "gaze"])
        assert message in str(error.value) and "\n" not in str(error.value)
    with pytest.raises(ValueError, match="the eyes' pictures need an observer with eyes"):
        gym.make("Animat/FishSwim-v0", sensors=["proprioception", "pixels"])
    with pytest.raises(ValueError, match="sensor name 'pixels' is taken"):
        register_sensor("pixels", lambda: None)
    with pytest.raises(ValueError, match="every colour histogram must hold some counts"):
        TargetEvidence(np.zeros((16, 16, 8)))


def test_a_registered_sensor_is_made_by_name():
    made = make_sensor({"name": "pixels", "levels": [2], "size": 16, "colour": True})
    assert (made.levels, made.size, made.colour) == ((2,), 16, True)
    sentinel = object()
    assert make_sensor(sentinel) is sentinel  # a sensor given as itself is used as it is
