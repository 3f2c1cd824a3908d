"""The pursuit env and the navigation layer under it."""


import gymnasium as gym
import numpy as np
import pytest

import animat  # noqa: F401
from animat.envs.core.env import BodyEnv
from animat.envs.motor.navigation import Navigator
from animat.envs.world.pursuit.env import PursuitSummary


def test_pursuit_observation_info_and_renders():
    env = gym.make("Animat/FishPursuit-v0", render_mode="retina", duration=1.0).unwrapped
    obs, info = env.reset(seed=3)
    assert obs["left_eye"].shape == (64, 64, 12) and obs["left_eye"].dtype == np.uint8
    assert set(info) >= {"target_in_fovea", "target_distance", "gaze", "vergence",
                         "range_estimate", "passer_in_fovea"}
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


def test_a_left_turn_command_turns_the_fish_left_then_it_swims_on():
    env = BodyEnv("swim", duration=8.0, fins=True)
    env.reset(seed=0)
    navigator = Navigator(1)
    headings = []
    for k in range(160):
        command = [[1.0, 1.0 if k == 20 else 0.0, 0.0]]  # one full turn command at 1 s
        headings.append(env.step(navigator.actions(command, k * env.dt)[0])[4]["heading_deg"])
    assert 60.0 < headings[100] - headings[19] < 120.0
    assert abs(headings[-1] - headings[100]) < 30.0  # swimming on, not turning


def test_the_pursuit_summary_counts_after_the_first_foveation():
    summary = PursuitSummary(body_length=0.3, start_distance=0.9)
    for frame in range(400):
        held = 10 <= frame < 300  # first foveation at frame 10, lost for good at 300
        summary.update({"target_in_fovea": held, "passer_in_fovea": False,
                        "target_distance": 0.9 - 0.001 * frame, "vergence": np.radians(2.0),
                        "range_estimate": np.inf if frame == 20 else 0.95 * (0.9 - 0.001 * frame)
                        })
    out = summary.summary()
    assert out["first_foveation_frame"] == 10
    assert out["fovea_fraction"] == pytest.approx(290 / 390)
    assert out["fovea_fraction_150"] == 1.0
    assert out["distance_closed_bl"] == pytest.approx(0.399 / 0.3)
    assert out["vergence_first_deg"] == pytest.approx(2.0)
    assert out["range_error"] == pytest.approx(0.05)  # the one infinite range is left out
    never = PursuitSummary(0.3, 0.9)
    never.update({"target_in_fovea": False, "passer_in_fovea": True, "target_distance": 0.9,
                  "vergence": 0.0, "range_estimate": np.inf})
    assert never.summary()["fovea_fraction"] == 0.0 and np.isnan(never.summary()["range_error"])
