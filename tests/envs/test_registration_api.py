"""The registration calls a user's module makes (``animat.envs.register_body``,
``register_task``, ``register_env``): each a plain call and (the first two) a decorator; a name
taken, a bad object, each refused in one line; and a user's task, body and sensor registered
as an env id that passes Gymnasium's env checker, with its native vector env. Every test runs
inside :func:`tests.support.registries.restored_registries` (the fixture
``registries_restored``), so that nothing registered here reaches another test."""

from dataclasses import dataclass

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import animat  # noqa: F401
from animat.envs import register_body, register_env, register_task
from animat.envs.core.sensors import Proprioception
from animat.envs.registration import ENVS, body_of, task_of, timing
from animat.envs.tasks import TASKS, make_task
from tests.support.bodies import eel_body
from tests.support.registries import DiveTask, restored_registries
from tests.support.sensors import DepthGauge

USER_ID = "UserAnimals/EelDive-v0"
pytestmark = pytest.mark.usefixtures("registries_restored")


def test_the_registries_are_restored_after_each_test():
    from animat.envs.bodies import BODIES

    assert "eel" not in BODIES and "dive" not in TASKS and USER_ID not in ENVS
    assert USER_ID not in gym.registry
    with restored_registries():
        register_body("eel", eel_body)
        register_task("dive", DiveTask)
        register_env(USER_ID, task="dive", body="eel")
    assert "eel" not in BODIES and "dive" not in TASKS and USER_ID not in ENVS
    assert USER_ID not in gym.registry


def test_a_body_registered_by_call_or_decorator_is_taken_by_name():
    from animat.envs.bodies import BODIES, make_body

    assert register_body("eel", eel_body) is eel_body
    assert register_body("eel", eel_body) is eel_body  # the same again: no change
    env = gym.make("Animat/FishSwim-v0", body="eel", duration=0.5)
    assert env.action_space.shape == (4,) and env.unwrapped.body.num_nodes == 14

    @register_body("short_eel")
    def short_eel():
        return eel_body(sections=False)

    assert BODIES["short_eel"] is short_eel and make_body("short_eel").name == "eel"


@pytest.mark.parametrize("name, factory, message", [
    ("fish", eel_body, "body name 'fish' is taken"),
    ("", eel_body, "the name must be a non-empty string"),
    (3, eel_body, "the name must be a non-empty string"),
    ("eel", eel_body(), "the factory must be a function returning a BodySpec"),
    ("eel", lambda: "an eel", "the factory returned 'an eel', not a BodySpec"),
])
def test_a_body_is_refused_in_one_line(name, factory, message):
    from animat.envs.bodies import BODIES

    before = dict(BODIES)
    with pytest.raises(ValueError, match=message) as error:
        register_body(name, factory)
    assert "\n" not in str(error.value) and BODIES == before


def test_a_task_registered_by_call_or_decorator_is_made_by_name():
    assert register_task("dive", DiveTask) is DiveTask
    assert register_task("dive", DiveTask) is DiveTask
    assert DiveTask.name == "dive"  # it set none of its own
    assert make_task("dive", weight=2.0).weight == 2.0
    with pytest.raises(ValueError, match="task 'dive' has no argument"):
        make_task("dive", depth=1.0)

    @register_task("deep_dive")
    @dataclass
    class DeepDive(DiveTask):
        default_duration = 2.0

    assert TASKS["deep_dive"] is DeepDive and DeepDive.name == "deep_dive"
    env = gym.make("Animat/FishSwim-v0", task="deep_dive", duration=0.5)
    assert env.unwrapped.task.name == "deep_dive" and env.observation_space.shape == (151,)


class Named(DiveTask):
    name = "plunge"


@pytest.mark.parametrize("name, cls, message", [
    ("swim", DiveTask, "task name 'swim' is taken \\(by SwimTask\\)"),
    ("dive", DiveTask(), "not a subclass of animat.envs.tasks.base.Task"),
    ("dive", dict, "not a subclass of animat.envs.tasks.base.Task"),
    ("dive", Named, "the class is named 'plunge'"),
    (None, DiveTask, "the name must be a non-empty string"),
])
def test_a_task_is_refused_in_one_line(name, cls, message):
    before = dict(TASKS)
    with pytest.raises(ValueError, match=message) as error:
        register_task(name, cls)
    assert "\n" not in str(error.value) and TASKS == before


def test_a_user_task_body_and_sensor_make_an_env_the_checker_passes_with_a_vector_env():
    register_body("eel", eel_body)
    register_task("dive", DiveTask)
    register_env(USER_ID, task="dive", body="eel", sensors=[Proprioception(), DepthGauge()])
    register_env(USER_ID, task="dive", body="eel",
                 sensors=ENVS[USER_ID]["kwargs"]["sensors"])  # the same again: no change
    env = gym.make(USER_ID, weight=2.0)
    check_env(env.unwrapped, skip_render_check=True)
    assert set(env.observation_space.spaces) == {"proprioception", "depth"}
    assert env.observation_space["proprioception"].shape == (2 * 14 * 3 + 6 + 4 + 1,)
    assert env.unwrapped.task.weight == 2.0
    assert timing(USER_ID) == (env.unwrapped.dt, env.unwrapped.episode_steps)
    assert body_of(USER_ID).num_nodes == 14 and task_of(USER_ID).name == "dive"
    vec = gym.make_vec(USER_ID, num_envs=3)
    assert type(vec).__name__ == "BodyVectorEnv"
    obs, _ = vec.reset(seed=0)
    obs, reward, _, _, info = vec.step(np.zeros((3, 4), np.float32))
    assert obs["depth"].shape == (3, 1) and reward.shape == (3,)
    assert np.all(np.isfinite(info["depth_bl"]))


@pytest.mark.parametrize("env_id, kwargs, message", [
    ("Animat/FishSwim-v0", {"task": "swim"}, "env id 'Animat/FishSwim-v0' is taken"),
    (USER_ID, {"task": "nothing"}, "unknown task 'nothing'; register it first"),
    (USER_ID, {"task": "swim", "body": "nobody"}, "unknown body 'nobody'; register it first"),
    ("not an id//x", {"task": "swim"}, "register_env: Malformed environment ID"),
    (7, {"task": "swim"}, "the env id must be a string"),
    (USER_ID, {"task": "swim", "duration": -1.0}, "duration must be"),
    (USER_ID, {"task": "swim", "sensors": [object()]}, "sensors: each must have a name"),
])
def test_an_env_id_is_refused_in_one_line_and_nothing_is_registered(env_id, kwargs, message):
    before, ids = dict(ENVS), set(gym.registry)
    with pytest.raises(ValueError, match=message) as error:
        register_env(env_id, **kwargs)
    assert "\n" not in str(error.value)
    assert ENVS == before and set(gym.registry) == ids
