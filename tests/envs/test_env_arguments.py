"""Every env keyword argument is checked where it enters: a bad value (wrong type, NaN or
infinite, out of its physical range, or a size that would make a step or an episode cost
without bound) is a ValueError of one line naming the argument and the value, when the env is
made, not NaN observations or a step that runs for ever later; every shipped config's
arguments, and the bounds themselves, still make envs that give finite numbers."""

from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import yaml

from animat.envs.bodies import make_body
from animat.envs.core.arguments import MAX_RESET_NOISE
from animat.envs.physics.system import (
    MAX_ADDED_MASS,
    MAX_REACTIVE_DENSITY,
    STABILITY_MARGIN,
    stable_step,
)
from animat.envs.registration import DOLPHIN_ENVS, FISH_ENVS

NAN, INF = float("nan"), float("inf")
FISH_IDS = tuple(FISH_ENVS) + tuple(DOLPHIN_ENVS)  # the BodyEnv ids
CONFIGS = sorted((Path(__file__).parents[2] / "configs").rglob("*.yaml"))

# (kwargs, the name the message must give, the bad value it must show): any fish or dolphin id
CORE_CASES = [
    ({"reset_noise_scale": -1.0}, "reset_noise_scale", -1.0),
    ({"reset_noise_scale": 10.0}, "reset_noise_scale", 10.0),
    ({"reset_noise_scale": NAN}, "reset_noise_scale", NAN),
    ({"frame_skip": 10**9}, "frame_skip", 10**9),
    ({"frame_skip": 2.5}, "frame_skip", 2.5),
    ({"duration": INF}, "duration", INF),
    ({"duration": "long"}, "duration", "long"),
    ({"physics_dt": 1e-9}, "physics_dt", 1e-9),
    ({"physics_dt": 1e-6, "duration": 5000.0}, "duration", 5000.0),
    ({"fins": "no"}, "fins", "no"),
    ({"reward_weights": {"mu1": NAN}}, "reward_weights.mu1", NAN),
    ({"reward_weights": {"mu2": -1.0}}, "reward_weights.mu2", -1.0),
    ({"reward_weights": {"nu1": "big"}}, "reward_weights.nu1", "big"),
    ({"reward_weights": {"nu2": INF}}, "reward_weights.nu2", INF),
    ({"reward_weights": {"mu3": 1.0}}, "reward_weights", "mu3"),
    ({"reward_weights": [1.0, 2.0]}, "reward_weights", [1.0, 2.0]),
    ({"water": {"current": (1e6, 0.0, 0.0)}}, "Water.current", (1e6, 0.0, 0.0)),
    ({"water": {"current": 5.0}}, "Water.current", 5.0),
    ({"water": {"density": 1e9}}, "Water.density", 1e9),
    ({"water": {"density": 1200.0}}, "Water.density", 1200.0),  # the reactive water's bound
    ({"water": {"added_mass": 2.0}}, "Water.density x added_mass", 2000.0),
    ({"water": {"gravity": 1e4}}, "Water.gravity", 1e4),
    ({"water": {"fluid_coefficient": 1e9}}, "Water.fluid_coefficient", 1e9),
    ({"water": {"air_pressure": 1e12}}, "Water.air_pressure", 1e12),
    ({"water": {"surface_z": -INF}}, "Water.surface_z", -INF),
    ({"sensors": "abc"}, "sensors", "abc"),
    ({"body": ["fish"]}, "body", ["fish"]),
]
# (env id, kwargs, name, bad value): a task's own arguments, the pursuit's and the world's
TASK_CASES = [
    ("Animat/FishSwim-v0", {"ball_height": 1.0}, "ball_height", "ball_height"),
    ("Animat/FishSwim-v0", {"target_speed": "fast"}, "target_speed", "fast"),
    ("Animat/FishTurn-v0", {"angle_deg": "90"}, "angle_deg", "90"),
    ("Animat/FishReach-v0", {"distance_bl": (1.0, 1e9)}, "distance_bl", (1.0, 1e9)),
    ("Animat/FishReach-v0", {"bearing_deg": (-1e9, 0.0)}, "bearing_deg", (-1e9, 0.0)),
    ("Animat/FishReach-v0", {"final_weight": NAN}, "final_weight", NAN),
    ("Animat/DolphinLeap-v0", {"start_depth": 1e9}, "start_depth", 1e9),
    ("Animat/DolphinLeap-v0", {"start_pitch_deg": "up"}, "start_pitch_deg", "up"),
    ("Animat/DolphinForward-v0", {"start_speed": 1e9}, "start_speed", 1e9),
    ("Animat/DolphinTurn-v0", {"angle_deg": "45"}, "angle_deg", "45"),
    ("Animat/DolphinArc-v0", {"radius_bl": 1e9}, "radius_bl", 1e9),
    ("Animat/DolphinTailBall-v0", {"ball_height": NAN}, "ball_height", NAN),
    ("Animat/DolphinTailBall-v0", {"ball_x": INF}, "ball_x", INF),
    ("Animat/DolphinNoseBall-v0", {"ball_y": "abc"}, "ball_y", "abc"),
    ("Animat/DolphinNoseBall-v0", {"ball_radius": 1e6}, "ball_radius", 1e6),
    ("Animat/FishPursuit-v0", {"start_distance_bl": (0.0, 0.0)}, "start_distance_bl",
     (0.0, 0.0)),
    ("Animat/FishPursuit-v0", {"flee_distance_bl": NAN}, "flee_distance_bl", NAN),
    ("Animat/FishPursuit-v0", {"prey_speed": 5.0}, "prey_speed", 5.0),
    ("Animat/FishPursuit-v0", {"bearing_deg": (30.0, -30.0)}, "bearing_deg", (30.0, -30.0)),
    ("Animat/FishPursuit-v0", {"oracle": "yes"}, "oracle", "yes"),
    ("Animat/FishPursuit-v0", {"bearing_deg": (-200.0, 200.0)}, "bearing_deg", (-200.0, 200.0)),
    ("Animat/FishPursuit-v0", {"distractors": 1.5}, "distractors", 1.5),
    ("Animat/FishPursuit-v0", {"passers": 9}, "passers", 9),
    ("Animat/FishPursuit-v0", {"occluders": 1}, "occluders", 1),
    ("Animat/FishPursuit-v0", {"duration": INF}, "duration", INF),
    ("Animat/MarineWorld-v0", {"agent": True}, "agent", True),
    ("Animat/MarineWorld-v0", {"species": {"minnow": 2.5}}, "species.minnow", 2.5),
    ("Animat/MarineWorld-v0", {"species": {"minnow": -1}}, "species.minnow", -1),
    ("Animat/MarineWorld-v0", {"species": {"minnow": 1001}}, "species.minnow", 1001),
    ("Animat/MarineWorld-v0", {"species": [1]}, "species", [1]),
    ("Animat/MarineWorld-v0", {"food": 10**4 + 1}, "food", 10**4 + 1),
    ("Animat/MarineWorld-v0", {"obstacles": 1001}, "obstacles", 1001),
    ("Animat/MarineWorld-v0", {"tank_size": 0.5}, "tank_size", 0.5),
    ("Animat/MarineWorld-v0", {"duration": "x"}, "duration", "x"),
    ("Animat/MarineWorld-v0", {"duration": INF}, "duration", INF),
]
VECTOR_CASES = [({"num_envs": 2.5}, "num_envs", 2.5), ({"num_envs": True}, "num_envs", True),
                ({"num_envs": 2, "frame_skip": 10**9}, "frame_skip", 10**9),
                ({"num_envs": 2, "reset_noise_scale": NAN}, "reset_noise_scale", NAN)]


def _refused(make, name: str, bad) -> None:
    """``make()`` raises a ValueError of one line that names ``name`` and shows ``bad``."""
    with pytest.raises(ValueError) as error:
        make()
    message = str(error.value)
    assert "\n" not in message, message
    assert name in message and repr(bad) in message, message


@pytest.mark.parametrize("env_id", FISH_IDS)
@pytest.mark.parametrize("kwargs, name, bad", CORE_CASES, ids=lambda v: repr(v)[:40])
def test_a_bad_core_argument_is_one_line_naming_it(env_id, kwargs, name, bad):
    _refused(lambda: gym.make(env_id, **kwargs), name, bad)


@pytest.mark.parametrize("env_id, kwargs, name, bad", TASK_CASES, ids=lambda v: repr(v)[:40])
def test_a_bad_task_pursuit_or_world_argument_is_one_line_naming_it(env_id, kwargs, name, bad):
    _refused(lambda: gym.make(env_id, **kwargs), name, bad)


@pytest.mark.parametrize("kwargs, name, bad", VECTOR_CASES, ids=lambda v: repr(v)[:40])
def test_a_bad_vector_env_argument_is_one_line_naming_it(kwargs, name, bad):
    _refused(lambda: gym.make_vec("Animat/FishSwim-v0", **kwargs), name, bad)


@pytest.mark.parametrize("path", CONFIGS, ids=lambda p: p.relative_to(p.parents[1]).as_posix())
def test_every_shipped_configs_env_arguments_still_make_its_env(path):
    env = yaml.safe_load(path.read_text())["env"]
    gym.make(env["id"], **env.get("kwargs", {})).close()


EXTREMES = {"fluid_coefficient": 2e4, "air_coefficient": 2e4, "friction_coefficient": 50.0,
            "air_friction_coefficient": 50.0, "gravity": 100.0, "current": (-20.0, 20.0, 20.0),
            "air_pressure": 1e7, "surface_z": -0.2}
WATERS_AT_BOUNDS = {  # the reactive water's own bound on density and added mass (Water)
    "resistive": {**EXTREMES, "model": "resistive", "density": 2e4},
    "reactive, dense": {**EXTREMES, "density": MAX_REACTIVE_DENSITY},
    "reactive, added mass": {**EXTREMES, "density": MAX_REACTIVE_DENSITY / MAX_ADDED_MASS,
                             "added_mass": MAX_ADDED_MASS}}


@pytest.mark.parametrize("water", WATERS_AT_BOUNDS.values(), ids=WATERS_AT_BOUNDS.keys())
@pytest.mark.parametrize("env_id, body", [("Animat/FishSwim-v0", "fish"),
                                          ("Animat/DolphinLeap-v0", "dolphin")])
def test_the_largest_values_accepted_still_give_finite_numbers(env_id, body, water):
    """Every water field, the reset noise and the reward weights at their bounds at once, the
    current against the fish, at the largest step the body takes, half in air, from three
    seeded starts: the bounds lie inside what the integrator keeps finite."""
    largest = 0.999 * STABILITY_MARGIN * stable_step(make_body(body))
    for seed in range(3):
        env = gym.make(env_id, water=water, reset_noise_scale=MAX_RESET_NOISE,
                       physics_dt=largest,
                       reward_weights={"mu1": 1e6, "mu2": 1e6, "nu1": 1e6, "nu2": 1e6}).unwrapped
        env.reset(seed=seed)
        rng = np.random.default_rng(seed)
        for _ in range(100):
            obs, reward, *_ = env.step(rng.uniform(-1, 1, env.action_space.shape))
            assert np.all(np.isfinite(obs)) and np.abs(obs).max() < 1e4 and np.isfinite(reward)
    for kwargs in ({"frame_skip": 10_000, "physics_dt": 1e-5}, {"water": {"surface_z": INF}},
                   {"reset_noise_scale": 0.0, "duration": 86_400.0}):
        assert gym.make(env_id, **kwargs).unwrapped.core.frame_skip >= 1
