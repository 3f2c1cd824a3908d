"""The Gymnasium environments: checkers, contracts, vector equivalence, bad input, video."""


import gymnasium as gym
import numpy as np
import pytest

from animat.envs.motor.fish import swim_mc, to_action
from animat.envs.registration import FISH_ENVS

ENV_IDS = tuple(FISH_ENVS)
VECTOR_IDS = ENV_IDS + ("Animat/DolphinLeap-v0", "Animat/DolphinNoseBall-v0")  # (a ball too)


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_contract_info_and_attributes(env_id):
    env = gym.make(env_id)
    obs, _ = env.reset(seed=0)
    assert env.action_space == gym.spaces.Box(-1, 1, (6,), np.float32)
    assert env.unwrapped.dt == pytest.approx(0.05)
    assert env.unwrapped.body_length == pytest.approx(0.30)
    _, reward, _, _, info = env.step(env.action_space.sample())
    assert info["com"].shape == (3,) and info["forward"].shape == (3,)
    assert np.linalg.norm(info["forward"]) == pytest.approx(1.0)
    assert reward == pytest.approx(info["reward_ctrl"] + info["reward_task"])
    for key in ("E_u", "E_v"):
        assert np.isfinite(info[key])


def test_fish_starts_heading_plus_x_with_left_plus_y():
    env = gym.make("Animat/FishSwim-v0", reset_noise_scale=0.0, start_spread="point")
    _, info = env.reset(seed=0)
    np.testing.assert_allclose(info["forward"], [1, 0, 0], atol=1e-12)
    frames = env.unwrapped.core.kinematics().frames
    np.testing.assert_allclose(frames[0, 1], [0, 1, 0], atol=1e-12)


@pytest.mark.parametrize("bad, message", [
    (np.zeros(5), "shape"), (np.full(6, np.nan), "NaN"), (np.array([0, 0, np.inf, 0, 0, 0]),
                                                           "infinite")])
def test_invalid_actions_raise_and_leave_state_unchanged(bad, message):
    env = gym.make("Animat/FishSwim-v0").unwrapped
    env.reset(seed=0)
    env.step(np.zeros(6, np.float32))
    state = env.core.state
    before = (state.x.copy(), state.v.copy(), state.steps.copy())
    with pytest.raises(ValueError, match=message):
        env.step(bad)
    assert np.array_equal(state.x, before[0]) and np.array_equal(state.v, before[1])
    assert np.array_equal(state.steps, before[2])


@pytest.mark.parametrize("env_id", VECTOR_IDS)
def test_a_saved_state_continues_exactly_in_a_fresh_env(env_id):
    """get_state() at any moment (here mid-episode, with an autoreset pending) given to a
    fresh env of the same arguments: both go on bit for bit, across episode ends."""
    rng = np.random.default_rng(1)
    actions = rng.uniform(-1, 1, (30, 2, 6)).astype(np.float32)
    first = gym.make_vec(env_id, num_envs=2, duration=0.5)
    first.reset(seed=7)
    for step in actions[:10]:  # the episode's last step: an autoreset pending
        first.step(step)
    second = gym.make_vec(env_id, num_envs=2, duration=0.5)
    second.set_state(first.get_state())
    for step in actions[10:]:
        for a, b in zip(first.step(step), second.step(step)):
            if isinstance(a, dict):
                assert all(np.array_equal(a[k], b[k]) for k in a if not k.startswith("_"))
            else:
                np.testing.assert_array_equal(a, b)
    single, again = gym.make(env_id, duration=0.5), gym.make(env_id, duration=0.5)
    single.reset(seed=3)
    single.step(actions[0, 0])
    again.reset()  # gym.make's order check wants a reset before the state is set
    again.unwrapped.set_state(single.unwrapped.get_state())
    for step in actions[1:, 0]:
        np.testing.assert_array_equal(single.step(step)[0], again.step(step)[0])
        if single.unwrapped.core.truncated[0]:
            np.testing.assert_array_equal(single.reset()[0], again.reset()[0])


def test_a_state_that_does_not_fit_is_refused_before_anything_changes():
    env = gym.make_vec("Animat/FishSwim-v0", num_envs=2)
    env.reset(seed=0)
    saved = env.get_state()
    before = env.get_state()
    for broken, message in [
            ({**saved, "rngs": saved["rngs"][:1]}, "a state of 1 sub-envs, not 2"),
            ({**saved, "rngs": [{"bit_generator": "MT19937"}] * 2}, "not a PCG64"),
            ({**saved, "core": {**saved["core"], "x": saved["core"]["x"][:1]}},
             "fish state 'x' must be float64 of shape"),
            ({**saved, "core": {**saved["core"], "v": saved["core"]["v"] * np.nan}},
             "fish state 'v' is not finite")]:
        with pytest.raises(ValueError, match=message):
            gym.make_vec("Animat/FishSwim-v0", num_envs=2).set_state(broken)
        with pytest.raises(ValueError):
            env.set_state(broken)
        np.testing.assert_array_equal(env.get_state()["core"]["x"], before["core"]["x"])


def test_vector_env_rejects_bad_batch():
    vec = gym.make_vec("Animat/FishSwim-v0", num_envs=3)
    vec.reset(seed=0)
    x = vec.core.state.x.copy()
    with pytest.raises(ValueError, match="shape"):
        vec.step(np.zeros((2, 6)))
    bad = np.zeros((3, 6))
    bad[1, 2] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        vec.step(bad)
    assert np.array_equal(vec.core.state.x, x)


@pytest.mark.parametrize("water", [None, {"model": "reactive"}], ids=["default", "reactive"])
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_1e5_random_steps_on_the_native_batch_stay_finite(env_id, water):
    """256 envs x 400 steps = 102,400 env steps of uniformly random actions, across episode
    ends, on both waters: observations, rewards, every info entry and the body state stay
    finite. (On the reactive water, central half-way fluxes instead of the upwind ones blew up
    a FishTurn body at step 178: the caudal fin's sway grew 5% a step.)"""
    vec = gym.make_vec(env_id, num_envs=256, water=water)
    obs, _ = vec.reset(seed=0)
    rng = np.random.default_rng(0)
    for _ in range(400):
        obs, reward, _, _, info = vec.step(rng.uniform(-1, 1, (256, 6)).astype(np.float32))
        assert np.isfinite(obs).all() and np.isfinite(reward).all()
        assert all(np.isfinite(np.asarray(value, dtype=float)).all() for value in info.values())
    assert np.isfinite(vec.core.state.x).all() and np.isfinite(vec.core.state.v).all()


def test_render_and_record_video(tmp_path):
    env = gym.make("Animat/FishSwim-v0", render_mode="rgb_array", duration=1.0)
    assert env.metadata["render_fps"] == 20
    env = gym.wrappers.RecordVideo(env, str(tmp_path / "videos"), episode_trigger=lambda e: True,
                                   disable_logger=True)
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (360, 480, 3) and frame.dtype == np.uint8
    assert frame.std() > 5  # a picture, not a blank
    truncated = False
    while not truncated:
        _, _, _, truncated, _ = env.step(env.action_space.sample())
    env.close()
    videos = list((tmp_path / "videos").glob("*.mp4"))
    assert videos and videos[0].stat().st_size > 1000


def test_water_is_a_public_argument_and_momentum_is_in_info():
    """``water=`` a dict of Water fields; in a vacuum (``density`` 0: no water carried by the
    reactive force either) the env's own info shows both momenta staying put while the muscles
    work."""
    vacuum = {"fluid_coefficient": 0, "air_coefficient": 0, "friction_coefficient": 0,
              "gravity": 0, "density": 0}
    env = gym.make("Animat/FishSwim-v0", water=vacuum)
    _, start = env.reset(seed=0)  # gliding and yawing (the start spread)
    assert start["linear_momentum"].shape == (3,) and start["angular_momentum"].shape == (3,)
    assert np.abs(start["linear_momentum"]).max() > 1e-3
    rng = np.random.default_rng(0)
    for _ in range(40):
        info = env.step(rng.uniform(-1, 1, 6).astype(np.float32))[4]
    for key in ("linear_momentum", "angular_momentum"):
        assert np.abs(info[key] - start[key]).max() < 1e-12, key
    with pytest.raises(ValueError, match="unknown field"):
        gym.make("Animat/FishSwim-v0", water={"gravty": 0})


def test_fins_in_the_action_space_change_depth():
    env = gym.make("Animat/FishSwim-v0", fins=True)
    assert env.action_space.shape == (8,)
    depths = []
    for pitch in (1.0, -1.0):
        env.reset(seed=0)
        for k in range(60):
            action = np.append(to_action(swim_mc(1.0, (k + 1) * 0.05)), [pitch, pitch])
            info = env.step(action.astype(np.float32))[4]
        depths.append(info["com"][2])
    assert depths[0] > 0.05 * 0.3 and depths[1] < -0.05 * 0.3  # +-0.05 BL in 3 s at least
