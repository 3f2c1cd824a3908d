"""The pursuit env and the navigation layer under it."""


import gymnasium as gym
import numpy as np
import pytest

import animat  # noqa: F401
from animat.envs.core.env import BodyEnv
from animat.envs.core.sensors import Proprioception, TaskEntries
from animat.envs.motor.navigation import Navigator, navigation_for
from animat.envs.physics.system import WATER_MODELS
from animat.envs.render.camera import Scene
from animat.envs.vision.retina import (
    Retina,
    RetinaParams,
    eye_positions,
    gaze_rotation,
    render_eyes,
)
from animat.envs.world.pursuit.senses import default_sensors
from animat.envs.world.pursuit.shell import in_foveas
from animat.envs.world.pursuit.start import OBSERVER
from animat.envs.world.pursuit.summary import PursuitSummary


def test_pursuit_observation_info_and_renders():
    env = gym.make("Animat/FishPursuit-v0", render_mode="retina", duration=1.0).unwrapped
    obs, info = env.reset(seed=3)
    assert obs["left_eye"].shape == (64, 64, 12) and obs["left_eye"].dtype == np.uint8
    assert set(info) >= {"target_in_fovea", "target_distance", "gaze", "vergence",
                         "range_estimate", "passer_in_fovea", "distractor_in_fovea"}
    assert env.render().shape == (512, 1024, 3)
    env.render_mode = "rgb_array"
    assert env.render().shape == (360, 480, 3)
    with pytest.raises(ValueError, match="7 finite numbers"):
        env.step(np.full(7, np.nan))
    steps = 0
    while True:
        *_, truncated, info = env.step(env.action_space.sample())
        steps += 1
        if truncated:
            break
    assert steps == 20 and info["time"] == pytest.approx(1.0)


@pytest.mark.parametrize("model", WATER_MODELS)
def test_a_left_turn_command_turns_the_fish_left_then_it_swims_on(model):
    """At the pursuit's speed (0.6), in either water with its MCs, one full turn command turns
    the fish left by 60-120 deg, and it swims on. (The turn-MC is calibrated from rest: from a
    full-speed swim it turns further, about 150 deg in the reactive water and 107 in the
    resistive.)"""
    env = BodyEnv("swim", duration=8.0, fins=True, water={"model": model})
    env.reset(seed=0)
    navigator = Navigator(1, navigation_for(env.core.system.water))
    headings = []
    for k in range(160):
        command = [[0.6, 1.0 if k == 20 else 0.0, 0.0]]  # one full turn command at 1 s
        headings.append(env.step(navigator.actions(command, k * env.dt)[0])[4]["heading_deg"])
    headings = np.degrees(np.unwrap(np.radians(headings)))
    assert 60.0 < headings[100] - headings[19] < 120.0
    assert abs(headings[-1] - headings[100]) < 30.0  # swimming on, not turning


def test_the_pursuit_summary_counts_after_the_first_foveation():
    summary = PursuitSummary(body_length=0.3, start_distance=0.9, dt=0.05)
    for frame in range(400):
        held = 10 <= frame < 300  # first foveation at frame 10, lost for good at 300
        summary.update({"target_in_fovea": held, "passer_in_fovea": False,
                        "target_distance": 0.9 - 0.001 * frame, "vergence": np.radians(2.0),
                        "range_estimate": np.inf if frame == 20 else 0.95 * (0.9 - 0.001 * frame)
                        })
    out = summary.summary()
    assert out["first_foveation_frame"] == 10
    assert out["fovea_fraction"] == pytest.approx(290 / 400)  # of the whole episode
    assert out["fovea_fraction_after_first"] == pytest.approx(290 / 390)
    assert out["fovea_fraction_150"] == 1.0
    assert out["first_foveation_s"] == pytest.approx(0.5)
    assert out["captured"] == 0.0  # it came within 0.501 m, 1.67 BL
    assert out["distance_closed_bl"] == pytest.approx(0.399 / 0.3)
    assert out["vergence_first_deg"] == pytest.approx(2.0)
    assert out["range_error"] == pytest.approx(0.05)  # the one infinite range is left out
    never = PursuitSummary(0.3, 0.9, 0.05)
    for distance in (0.9, 0.14, 0.6):  # within 0.5 BL (0.15 m) once: captured
        never.update({"target_in_fovea": False, "passer_in_fovea": True,
                      "target_distance": distance, "vergence": 0.0, "range_estimate": np.inf})
    out = never.summary()
    assert out["fovea_fraction"] == 0.0 and np.isnan(out["range_error"])
    assert out["fovea_fraction_after_first"] == 0.0
    assert out["first_foveation_s"] == pytest.approx(0.15)
    assert out["captured"] == 1.0


@pytest.mark.parametrize("bearing", [(-60.0, -60.0), (45.0, 45.0)])
def test_the_prey_starts_at_the_bearing_drawn_from_bearing_deg(bearing):
    env = gym.make("Animat/FishPursuit-v0", duration=1.0, bearing_deg=bearing).unwrapped
    env.reset(seed=3)
    to_prey = env.core.state.x[1, 0] - env.core.state.x[OBSERVER, 0]  # head to head
    assert np.degrees(np.arctan2(to_prey[1], to_prey[0])) == pytest.approx(bearing[0], abs=1.0)


def _stepped(env, steps: int = 4):
    """The observation after a reset and ``steps`` steps of a fixed action that turns the eyes."""
    obs, _ = env.reset(seed=5)
    for _ in range(steps):
        obs, *_ = env.step(np.array([0.5, 0.0, 0.0, 0.4, -0.2, -0.3, 0.1], np.float32))
    return obs


def test_the_eyes_in_the_pursuit_observation_are_the_retina_sensors_reading():
    env = gym.make("Animat/FishPursuit-v0", duration=1.0).unwrapped
    obs = _stepped(env)
    kinematics = env.core.kinematics()
    reading = Retina().read(env.view, kinematics)
    assert set(reading) == {"left_eye", "right_eye"}
    frame, head = kinematics.frames[OBSERVER], env.core.state.x[OBSERVER, 0]
    angles = np.radians([[24.0, -6.0], [-18.0, 3.0]])  # the gaze commanded, in degrees
    rotations = np.stack([gaze_rotation(frame, *a) for a in angles])
    images = render_eyes(env.scene(), eye_positions(frame, head, env.body_length), rotations)
    for k, eye in enumerate(("left_eye", "right_eye")):
        np.testing.assert_array_equal(obs[eye], reading[eye][0])
        np.testing.assert_array_equal(obs[eye], np.concatenate(list(images[k]), axis=-1))
    assert obs["left_eye"].std() > 0 and not np.array_equal(obs["left_eye"], obs["right_eye"])
    # a retina of other cameras, passed as a sensor, is what the env observes with
    small = Retina(RetinaParams(levels=2, size=16))
    env = gym.make("Animat/FishPursuit-v0", duration=1.0,
                   sensors=[small, *default_sensors()[1:]]).unwrapped
    assert env.observation_space["left_eye"].shape == (16, 16, 6)
    obs = _stepped(env)
    assert env.observation_space.contains(obs)
    np.testing.assert_array_equal(obs["right_eye"],
                                  small.read(env.view, env.core.kinematics())["right_eye"][0])


class HeadDepth:
    """The observer's nose below the start, m: a sensor added to the pursuit's."""

    name = "depth"

    def space(self, view):
        return gym.spaces.Box(-1e4, 1e4, (1,), np.float32)

    def read(self, view, kinematics):
        return -view.core.state.x[view.rows, 0, 2:3].astype(np.float32)


class LeftEye(HeadDepth):
    """A sensor whose name is an entry the retina gives."""

    name = "left_eye"


def test_a_sensor_added_to_the_pursuit_shows_up_in_its_observation():
    env = gym.make("Animat/FishPursuit-v0", duration=1.0,
                   sensors=[*default_sensors(), HeadDepth()]).unwrapped
    assert set(env.observation_space.spaces) == {"left_eye", "right_eye", "gaze",
                                                 "proprioception", "depth"}
    obs = _stepped(env)
    assert env.observation_space.contains(obs)
    assert obs["depth"][0] == np.float32(-env.core.state.x[OBSERVER, 0, 2])
    np.testing.assert_array_equal(obs["gaze"], np.float32([0.4, -0.2, -0.3, 0.1]))
    assert obs["proprioception"].shape == (150,)
    with pytest.raises(ValueError, match="sensors: entry names must be unique"):
        gym.make("Animat/FishPursuit-v0", sensors=[*default_sensors(), LeftEye()])
    with pytest.raises(ValueError, match="sensors must be a list"):
        gym.make("Animat/FishPursuit-v0", sensors="retina")
    assert isinstance(env.view.scene(), Scene)


def test_the_observers_own_state_and_the_task_entries_read_apart_in_the_pursuit():
    apart = gym.make("Animat/FishPursuit-v0", duration=1.0, sensors=[
        *default_sensors()[:2], Proprioception(task_entries=False), TaskEntries()]).unwrapped
    obs = _stepped(apart)
    assert obs["task"].shape == (0,) and apart.observation_space.contains(obs)
    kinematics = apart.core.kinematics()
    np.testing.assert_array_equal(obs["proprioception"],
                                  apart.core.proprioception(kinematics)[OBSERVER])
    default = _stepped(gym.make("Animat/FishPursuit-v0", duration=1.0).unwrapped)
    np.testing.assert_array_equal(obs["proprioception"], default["proprioception"])


def test_the_pursuer_keeps_its_distance_by_its_own_vergence_and_searches_where_it_lost_sight():
    """With both eyes verged on a target d ahead, the policy swims at ``speed`` beyond
    ``hold_range_bl + range_ramp_bl``, slower nearer, and stops at ``hold_range_bl``; with the
    target out of view for ``search_after`` frames it turns toward where it saw it last."""
    from animat.envs.world.pursuit.policy import ActiveVisionParams, ActiveVisionPolicy

    policy = ActiveVisionPolicy(ActiveVisionParams(hold_range_bl=1.0, range_ramp_bl=2.0))
    length, half = policy.body.length, 0.5 * policy.baseline

    def verged(distance_bl):
        angle = np.arctan(half / (distance_bl * length))
        return np.array([[-angle, 0.0], [angle, 0.0]])

    speeds = [policy._speed(verged(d), True) for d in (5.0, 3.0, 2.0, 1.0, 0.5)]
    assert speeds == pytest.approx([0.6, 0.6, 0.3, 0.0, 0.0])
    assert policy._speed(verged(0.5), False) == 0.6  # one eye alone gives no range
    policy.reset()
    assert policy._search([0, 1], np.radians(-30.0)) == 0.0  # seen, on the right
    turns = [policy._search([], 0.0) for _ in range(policy.params.search_after)]
    assert turns[:-1] == [0.0] * (policy.params.search_after - 1) and turns[-1] == -1.0


def test_the_benchmark_has_a_salmon_distractor_three_passers_and_occluders_in_the_layer():
    """Six fish by default (observer, prey, one distractor, three passers), the prey and the
    distractor within the field's bearings at 1-4 m; kelp and boulders rising through the
    swimming layer (z = 0) only with ``occluders``."""
    from animat.envs.world.pursuit.start import DISTRACTOR_COLOUR, PREY_COLOUR

    env = gym.make("Animat/FishPursuit-v0", duration=1.0).unwrapped
    assert env.fish == 6 and env.core.num_envs == 6
    assert np.allclose(env.skins[1].max(axis=0), PREY_COLOUR, atol=60)
    assert np.allclose(env.skins[2].max(axis=0), DISTRACTOR_COLOUR, atol=60)
    for seed in range(8):
        env.reset(seed=seed)
        kinematics = env.core.kinematics()
        for row in (1, 2):  # the prey and the distractor: nose-to-centre bearing and range
            offset = kinematics.com[row] - env.core.state.x[0, 0]
            assert abs(np.degrees(np.arctan2(offset[1], offset[0]))) < 63.0
            assert 0.8 < np.linalg.norm(offset) < 4.3
        assert _rising(env._scenery) >= 3  # rooted on the seabed, through z = 0
    bare = gym.make("Animat/FishPursuit-v0", duration=1.0, occluders=False, distractors=0,
                    passers=1).unwrapped
    bare.reset(seed=0)
    assert bare.fish == 3 and _rising(bare._scenery) == 0


def _rising(things) -> int:
    """How many of the scenery's things stand on the seabed (0.5 m below) and reach z = 0."""
    return sum(corners[..., 2].min() < -0.45 and corners[..., 2].max() > 0.0
               for corners, _ in things)


def test_a_glance_moves_the_eyes_alone_and_the_frame_counts_once():
    """With ``glances=2`` the first step of each frame turns the eyes and renders them again,
    the world still (time, bodies, reward 0); the second moves everything; the summary counts
    the frame once."""
    env = gym.make("Animat/FishPursuit-v0", duration=1.0, glances=2).unwrapped
    obs, _ = env.reset(seed=4)
    assert obs["glance"][0] == 1.0 and env.episode_steps == 40
    x = env.core.state.x.copy()
    look = np.array([0.0, 0.0, 0.0, 0.5, 0.0, -0.5, 0.0], np.float32)
    seen, reward, _, _, info = env.step(look)
    assert reward == 0.0 and not info["moved"] and info["time"] == 0.0
    np.testing.assert_array_equal(env.core.state.x, x)
    assert seen["glance"][0] == 0.0 and not np.array_equal(seen["left_eye"], obs["left_eye"])
    np.testing.assert_allclose(seen["gaze"], look[3:])
    moved, _, _, _, info = env.step(look)
    assert info["moved"] and info["time"] == pytest.approx(0.05) and moved["glance"][0] == 1.0
    summary = PursuitSummary(0.3, 1.0, 0.05)
    for step_info in ({**info, "moved": False}, info):
        summary.update(step_info)
    assert summary.frames == 1
    assert "glance" not in gym.make("Animat/FishPursuit-v0").observation_space.spaces


def test_in_foveas_needs_both_eyes_within_7_5_degrees_of_their_axes():
    rng = np.random.default_rng(0)
    turned = np.stack([np.linalg.qr(rng.normal(size=(3, 3)))[0] for _ in range(5)])
    rotations = np.stack([turned, turned], axis=1)  # parallel eyes 5 cm apart
    left = rng.normal(size=(5, 3))
    positions = np.stack([left, left + 0.05 * turned[:, 0]], axis=1)
    near = positions[:, :1] + rotations[:, :1, 2] * 3.0  # on the left eye's axis
    points = np.concatenate([near + rng.normal(scale=0.2, size=(5, 40, 3)),
                             positions[:, :1]], axis=1)  # and the left eye itself
    with np.errstate(invalid="ignore"):  # the eye itself: no direction, a NaN cosine
        inside = in_foveas(points, positions, rotations)
    for n in range(5):
        for k in range(41):
            with np.errstate(invalid="ignore"):
                cosines = [(points[n, k] - p) @ r[2] / np.linalg.norm(points[n, k] - p)
                           for p, r in zip(positions[n], rotations[n])]
            assert inside[n, k] == all(c >= np.cos(np.radians(7.5)) for c in cosines) or (
                np.isnan(cosines).any() and inside[n, k])
    assert inside.any() and not inside.all()
