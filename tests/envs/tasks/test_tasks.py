"""The one task API: every task in ``TASKS`` reads a real :class:`World` of a real
:class:`BodyBatch` through ``terms`` and ``observe`` and returns the documented shapes; the World
is built by keyword and frozen; the observation is the body's proprioception, then the task's."""

import dataclasses

import numpy as np
import pytest

from animat.envs.bodies import make_body
from animat.envs.core.batch import OBS_LIMIT, BodyBatch
from animat.envs.tasks import TASKS
from animat.envs.tasks.base import Task, World

B = 3


def _core(name: str) -> BodyBatch:
    """B dolphins 3 m under a surface (the default, reactive, water) doing task ``name``, a few
    env steps into an episode."""
    core = BodyBatch(B, TASKS[name](), body=make_body("dolphin"), physics_dt=5e-4,
                     water={"surface_z": 0.0}, duration=1.0)
    core.reset_rows(np.arange(B), [np.random.default_rng(k) for k in range(B)])
    rng = np.random.default_rng(0)
    for _ in range(3):
        core.step(rng.uniform(-1.0, 1.0, (B, core.action_size)))
    return core


@pytest.mark.parametrize("name", sorted(TASKS))
def test_every_task_implements_terms_and_observe_of_the_world(name):
    core = _core(name)
    task, kinematics = core.task, core.kinematics()
    assert type(task).terms is not Task.terms, "each task defines its own terms"
    assert not hasattr(task, "world_terms") and not hasattr(task, "world_observe")
    world = core.world(kinematics)
    last = np.array([False, True, False])
    e_v, metrics, memory = task.terms(world, last)
    assert e_v.shape == (B,) and np.isfinite(e_v).all()
    assert set(task.mean_metrics) <= set(metrics)
    assert all(np.shape(value) == (B,) for value in metrics.values()), metrics
    assert memory.shape == (B, task.memory_size)
    obs = task.observe(world)
    assert obs.shape == (B, task.obs_size) and np.isfinite(obs).all()
    expected = np.clip(obs, -OBS_LIMIT, OBS_LIMIT).astype(np.float32)
    assert np.array_equal(core.task_observation(kinematics), expected)


@pytest.mark.parametrize("name", ["swim", "reach", "ball"])
def test_the_observation_is_the_body_s_proprioception_then_the_task_s_entries(name):
    core = _core(name)
    kinematics = core.kinematics()
    obs = core.observe(kinematics)
    assert obs.dtype == np.float32 and obs.shape == (B, core.obs_size)
    body = core.proprioception(kinematics)
    assert body.shape == (B, core.proprioception_size)
    assert core.obs_size == core.proprioception_size + core.task.obs_size
    assert np.array_equal(obs, np.concatenate([body, core.task_observation(kinematics)], 1))


def test_the_world_is_built_by_keyword_and_frozen():
    core = _core("leap")
    world = core.world(core.kinematics())
    values = [getattr(world, f.name) for f in dataclasses.fields(World)]
    with pytest.raises(TypeError):
        World(*values)
    with pytest.raises(dataclasses.FrozenInstanceError):
        world.length = 1.0
    assert world.length == core.body.length and world.memory is core.state.memory


def test_a_turn_scores_its_path_by_default_and_its_end_and_settling_with_a_final_weight():
    """E_v = path_weight e^2 + final_weight (e^2 + (settle_s w)^2) on the last step, w the yaw
    rate of the body: a rigid rotation at w rad/s about the vertical reads w."""
    from animat.envs.tasks.locomotion import TurnTask, yaw_rate

    core = BodyBatch(2, TurnTask(angle_deg=90.0), start_spread="point", reset_noise_scale=0.0)
    core.reset_rows(np.arange(2), [np.random.default_rng(k) for k in range(2)])
    w = np.array([0.5, -1.0])  # rad/s, to the left and to the right
    com = core.kinematics().com
    arm = core.state.x - com[:, None]
    core.state.v[:] = w[:, None, None] * np.stack(
        [-arm[..., 1], arm[..., 0], np.zeros(arm.shape[:2])], axis=-1)
    world = core.world(core.kinematics())
    assert np.allclose(yaw_rate(world), w, rtol=1e-12)
    error = np.radians(-90.0)
    last = np.array([False, True])
    e_v, metrics, _ = TurnTask(angle_deg=90.0).terms(world, last)
    assert np.allclose(e_v, error**2)  # the paper's: the squared error, whatever the step
    assert np.allclose(metrics["yaw_rate_deg_s"], np.degrees(w))
    task = TurnTask(angle_deg=90.0, path_weight=0.0, final_weight=20.0, settle_s=0.5)
    e_v, _, _ = task.terms(world, last)
    assert e_v[0] == 0.0 and e_v[1] == pytest.approx(20.0 * (error**2 + (0.5 * w[1]) ** 2))
    for bad in ({"final_weight": -1.0}, {"settle_s": 11.0}, {"path_weight": float("nan")}):
        with pytest.raises(ValueError, match=next(iter(bad))):
            TurnTask(**bad)


def test_a_half_turn_to_the_left_is_not_one_to_the_right():
    """The turn task follows the heading through the episode: the hand MC's 180 deg left turn
    ends near 0 deg off as a left turn and near 360 deg off as a right one (a wrapped heading
    could not tell them apart)."""
    from animat.envs.core.env import BodyVectorEnv
    from animat.envs.motor.fish import to_action

    errors = {}
    for direction in ("left", "right"):
        env = BodyVectorEnv(1, "turn", angle_deg=180.0, direction=direction, duration=5.0,
                            start_spread="point")
        env.reset(seed=0)
        controller = TASKS["turn"](angle_deg=180.0, direction="left").hand_controller()
        for k in range(env.episode_steps):
            info = env.step(to_action(controller((k + 1) * env.dt))[None])[4]
        errors[direction] = float(info["heading_error_deg"][0])
    assert abs(errors["left"]) < 60.0 and errors["right"] > 300.0, errors
    assert errors["right"] - errors["left"] == pytest.approx(360.0)


def test_a_goal_passed_within_reached_bl_counts_as_reached_wherever_the_fish_ends():
    """The reach keeps the closest the fish has come (its memory): a fish swimming straight
    through a goal 1 BL ahead ends beyond it, yet has reached it; one with the goal behind
    has not."""
    from animat.envs.core.env import BodyVectorEnv
    from animat.envs.motor.fish import to_action

    env = BodyVectorEnv(2, "reach", distance_bl=(1.0, 1.0), bearing_deg=(0.0, 0.0),
                        duration=3.0, start_spread="point")
    env.reset(seed=0)
    env.core.state.targets[1] = -env.core.state.targets[1]  # the second goal behind
    swim = TASKS["swim"]().hand_controller()
    distances, infos = [], []
    for k in range(env.episode_steps):
        info = env.step(np.tile(to_action(swim((k + 1) * env.dt)), (2, 1)))[4]
        distances.append(info["distance_bl"].copy())
        infos.append(info)
    distances = np.array(distances)
    np.testing.assert_allclose(infos[-1]["closest_bl"], distances.min(axis=0))
    summary = TASKS["reach"]().final_metrics(infos[-1])
    assert summary["closest_bl"][0] < 0.5 < summary["final_distance_bl"][0]
    assert summary["reached"].tolist() == [1.0, 0.0]


def test_a_goal_counts_as_held_only_when_the_fish_ends_within_reach_and_stays_there():
    """``held`` asks for the last ``hold_s`` within ``reached_bl`` without a break: a fish
    resting 0.3 BL from its goal holds it; one that passes through and ends beyond it, or
    that came within reach only for the last step, does not."""
    from animat.envs.core.env import BodyVectorEnv
    from animat.envs.motor.fish import to_action

    env = BodyVectorEnv(2, "reach", distance_bl=(0.3, 0.3), bearing_deg=(0.0, 0.0),
                        duration=2.0, start_spread="point", hold_s=1.0)
    env.reset(seed=0)
    swim = TASKS["swim"]().hand_controller()
    for k in range(env.episode_steps):
        action = np.stack([np.full(6, -1.0), to_action(swim((k + 1) * env.dt))])
        info = env.step(action)[4]
    summary = TASKS["reach"](hold_s=1.0).final_metrics(info)
    assert info["within_s"][0] == pytest.approx(2.0)
    assert summary["reached"].tolist() == [1.0, 1.0]
    assert summary["held"].tolist() == [1.0, 0.0]
    late = {**info, "within_s": np.array([env.dt, env.dt]), "distance_bl": np.array([0.1, 0.1])}
    assert TASKS["reach"](hold_s=1.0).final_metrics(late)["held"].tolist() == [0.0, 0.0]
    assert TASKS["reach"](hold_s=0.0).final_metrics(late)["held"].tolist() == [1.0, 1.0]


def test_the_reach_objective_weighs_the_path_the_end_and_the_closest_approach():
    """E_v = path_weight d every step + (final_weight d + closest_weight closest) on the last,
    d the distance to the goal and closest the closest the fish has come, at every step."""
    from animat.envs.core.env import BodyVectorEnv

    weights = {"path_weight": 0.5, "final_weight": 2.0, "closest_weight": 3.0}
    env = BodyVectorEnv(1, "reach", duration=1.0, start_spread="point", **weights)
    env.reset(seed=0)
    for k in range(env.episode_steps):
        info = env.step(np.full((1, 6), -1.0))[4]
        last = k == env.episode_steps - 1
        d, closest = info["distance_bl"][0], info["closest_bl"][0]
        expected = 0.5 * d + (2.0 * d + 3.0 * closest if last else 0.0)
        assert info["E_v"][0] == pytest.approx(expected, rel=1e-12)
