"""An env's clock without the env: :func:`animat.envs.registration.timing` reckons ``dt`` (s)
and ``episode_steps`` of every registered id from its registered kwargs and the user's, and
builds nothing; what it reckons equals what the env built with the same kwargs reports, and a
bad argument is the same error (type and one-line message) the env gives. Likewise its body and
task (:func:`~animat.envs.registration.body_of`, :func:`~animat.envs.registration.task_of`) and
the length of its action (:func:`~animat.envs.registration.action_size_of`)."""

import dataclasses

import gymnasium as gym
import numpy as np
import pytest

import animat  # noqa: F401
from animat.envs.registration import (
    ENVS,
    MARINE,
    PURSUIT,
    Timing,
    action_size_of,
    body_of,
    built_timing,
    task_of,
    timing,
)

NAN = float("nan")
IDS = sorted(ENVS)
CORE_IDS = [i for i in IDS if ENVS[i]["entry_point"] not in (PURSUIT["entry_point"], MARINE)]
# kwargs every id takes; then kwargs only the core's ids (fish and dolphin) take
ANY_KWARGS = [{}, {"duration": 0.5}, {"duration": 3}, {"duration": 7.37}, {"duration": 0.01}]
CORE_KWARGS = [{"frame_skip": 20}, {"frame_skip": 7, "duration": 2.0}, {"frame_skip": 40.0},
               {"water": {"model": "resistive"}}, {"water": {"density": 1100.0}, "duration": 2.0},
               {"base_water": {"surface_z": 1.0}},
               {"duration": None}, {"fins": True, "reset_noise_scale": 0.0,
                                    "reward_weights": {"mu1": 0.0}}]
TASK_KWARGS = [("Animat/FishSwim-v0", {"target_speed": 0.5}),
               ("Animat/FishTurn-v0", {"angle_deg": 45.0, "duration": 2.0}),
               ("Animat/DolphinTailBall-v0", {"duration": 9.0, "ball_x": 15.2, "ball_y": 0.3,
                                              "ball_height": 1.3})]
# arguments timing() cannot vouch for: it builds the env, and reads the same clock
BUILT_KWARGS = [("Animat/FishSwim-v0", {"physics_dt": 0.001}),
                ("Animat/FishSwim-v0", {"task": "turn"}),
                ("Animat/DolphinLeap-v0", {"physics_dt": 0.05 / 100, "frame_skip": 100}),
                ("Animat/FishPursuit-v0", {"prey_speed": 0.3, "duration": 2.0}),
                ("Animat/MarineWorld-v0", {"food": 3, "duration": 2.0})]
BAD_KWARGS = [{"duration": -1.0}, {"duration": NAN}, {"duration": "long"}, {"duration": 1e6},
              {"duration": True}, {"frame_skip": 0}, {"frame_skip": 2.5},
              {"reset_noise_scale": 10.0}, {"fins": "no"}, {"reward_weights": {"mu1": -1.0}},
              {"nonsense": 1}, {"duration": -1.0, "reward_weights": {"mu1": NAN}},
              {"target_speed": -5.0}, {"num_envs": 2}, {"water": "salty"},
              {"water": {"saltiness": 1.0}}, {"water": {"density": -5.0}},
              {"base_water": [1.0]}, {"water": {"nonsense": 1}, "duration": -1.0},
              {"water": {"density": -5.0}, "start_spread": {"nonsense": 1}}]


@pytest.fixture
def no_builds(monkeypatch):
    """Any env made while the test runs fails it."""
    def refuse(*args, **kwargs):
        raise AssertionError(f"an env was built: {args} {kwargs}")

    monkeypatch.setattr(gym, "make", refuse)
    monkeypatch.setattr(gym, "make_vec", refuse)


def built_clock(env_id: str, kwargs: dict) -> tuple[float, int]:
    """(dt, episode_steps) of the env built with ``kwargs``, as the env reports them."""
    env = gym.make(env_id, **kwargs)
    try:
        return env.unwrapped.dt, env.unwrapped.episode_steps
    finally:
        env.close()


def error_of(make, env_id: str, kwargs: dict) -> tuple[type, str]:
    with pytest.raises(Exception) as caught:
        make(env_id, kwargs)
    return caught.type, str(caught.value)


VALID = ([(i, k) for i in IDS for k in ANY_KWARGS] + [(i, k) for i in CORE_IDS
                                                      for k in CORE_KWARGS] + TASK_KWARGS)


def test_every_registered_id_is_covered():
    worlds = {PURSUIT["entry_point"], MARINE}
    assert len(IDS) == 14 and worlds < {e["entry_point"] for e in ENVS.values()}


@pytest.mark.parametrize(("env_id", "kwargs"), VALID)
def test_timing_is_the_built_envs_clock_without_building_it(env_id, kwargs, monkeypatch):
    expected = built_clock(env_id, kwargs)
    with monkeypatch.context() as patch:
        patch.setattr(gym, "make", lambda *a, **k: pytest.fail(f"built {a} {k}"))
        reckoned = timing(env_id, kwargs)
    assert isinstance(reckoned, Timing) and type(reckoned.dt) is float
    assert type(reckoned.episode_steps) is int
    assert tuple(reckoned) == expected  # exactly: the same float, the same int
    assert reckoned == built_timing(env_id, kwargs)


@pytest.mark.parametrize(("env_id", "kwargs"), BUILT_KWARGS)
def test_arguments_it_cannot_vouch_for_build_the_env_for_its_clock(env_id, kwargs):
    assert tuple(timing(env_id, kwargs)) == built_clock(env_id, kwargs)


@pytest.mark.parametrize("kwargs", BAD_KWARGS, ids=repr)
@pytest.mark.parametrize("env_id", IDS)
def test_a_bad_argument_is_the_envs_own_error(env_id, kwargs):
    expected = error_of(lambda i, k: gym.make(i, **k), env_id, kwargs)
    assert error_of(timing, env_id, kwargs) == expected


def test_an_unknown_id_is_gymnasiums_error():
    expected = error_of(lambda i, k: gym.make(i, **k), "Animat/Nothing-v0", {})
    assert error_of(timing, "Animat/Nothing-v0", {}) == expected


def test_the_shipped_durations_build_nothing(no_builds):
    assert timing("Animat/FishSwim-v0", {"duration": 5.0}) == Timing(0.05, 100)
    assert timing("Animat/DolphinSomersault-v0", {"duration": 9.0}) == Timing(0.05, 180)
    assert timing("Animat/FishPursuit-v0", {"duration": 20.0}) == Timing(0.05, 400)
    assert timing("Animat/MarineWorld-v0", {"duration": 60.0}) == Timing(0.05, 1200)


# the body and the task an env is built with, read without building it (body_of, task_of)
BODY_TASK_KWARGS = ([(i, {}) for i in IDS if i != "Animat/MarineWorld-v0"] + TASK_KWARGS
                    + [("Animat/FishSwim-v0", {"task": "turn", "angle_deg": 30.0}),
                       ("Animat/DolphinSpin-v0", {"direction": "up", "duration": 2.0})])


def built_body_and_task(env_id: str, kwargs: dict):
    """(body, task) of the env built with ``kwargs`` (the pursuit's: its core's)."""
    env = gym.make(env_id, **kwargs)
    try:
        core = env.unwrapped.core
        return core.body, core.task
    finally:
        env.close()


def same_body(a, b) -> bool:
    return type(a) is type(b) and all(
        np.array_equal(getattr(a, f.name), getattr(b, f.name)) for f in dataclasses.fields(a))


@pytest.mark.parametrize(("env_id", "kwargs"), BODY_TASK_KWARGS)
def test_body_of_and_task_of_are_the_built_envs(env_id, kwargs, monkeypatch):
    body, task = built_body_and_task(env_id, kwargs)
    with monkeypatch.context() as patch:
        if env_id in CORE_IDS:
            patch.setattr(gym, "make", lambda *a, **k: pytest.fail(f"built {a} {k}"))
        assert same_body(body_of(env_id, kwargs), body)
        assert task_of(env_id, kwargs) == task and type(task_of(env_id, kwargs)) is type(task)
    assert body_of(env_id, kwargs).actuator_names == body.actuator_names


@pytest.mark.parametrize(("env_id", "kwargs"), [(i, k) for i in IDS for k in ({}, {"fins": True})
                                                if k == {} or i in CORE_IDS])
def test_action_size_of_is_the_built_envs(env_id, kwargs, monkeypatch):
    env = gym.make(env_id, **kwargs)
    size = env.action_space.shape[0]
    env.close()
    with monkeypatch.context() as patch:
        if env_id in CORE_IDS:
            patch.setattr(gym, "make", lambda *a, **k: pytest.fail(f"built {a} {k}"))
        assert action_size_of(env_id, kwargs) == size
    if env_id in CORE_IDS:
        with pytest.raises(ValueError, match="frame_skip"):
            action_size_of(env_id, {**kwargs, "frame_skip": 0})


def test_body_of_and_task_of_refuse_what_the_env_refuses():
    with pytest.raises(ValueError, match="unknown body"):
        body_of("Animat/FishSwim-v0", {"body": "whale"})
    with pytest.raises(ValueError, match="unknown task"):
        task_of("Animat/FishSwim-v0", {"task": "fly"})
    with pytest.raises(ValueError, match="has no argument"):
        task_of("Animat/FishSwim-v0", {"nonsense": 1})
    with pytest.raises(ValueError, match="Animat/MarineWorld-v0 has no body to read"):
        body_of("Animat/MarineWorld-v0")
