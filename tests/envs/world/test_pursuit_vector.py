"""The pursuit's native vector env: N worlds in one batch that step bit for bit as N single envs
(glances, the oracle's entry, both autoreset modes, the info's observer entries), resume
exactly from their saved state, and refuse bad input in one line."""

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

import animat  # noqa: F401
from animat.learners.ppo.vec_envs import NativeVecEnv

SHORT = {"duration": 0.3, "glances": 2, "oracle": True, "distractors": 2, "passers": 1,
         "frames": 2}


def _rows_equal(batch: dict, single: dict, i: int) -> None:
    for key, value in single.items():
        np.testing.assert_array_equal(batch[key][i], value, err_msg=key)


@pytest.mark.parametrize("mode", ["next_step", "same_step"])
def test_worlds_step_bit_for_bit_as_single_envs_across_an_autoreset(mode):
    num = 3
    vec = gym.make_vec("Animat/FishPursuit-v0", num_envs=num, autoreset_mode=mode, **SHORT)
    singles = [gym.make("Animat/FishPursuit-v0", **SHORT) for _ in range(num)]
    obs, info = vec.reset(seed=20)
    for i, env in enumerate(singles):
        o, inf = env.reset(seed=20 + i)
        _rows_equal(obs, o, i)
        _rows_equal(info, {k: inf[k] for k in ("com", "forward", "target_distance")}, i)
    assert vec.single_observation_space.contains({k: v[0] for k, v in obs.items()})
    rng, ends, pending = np.random.default_rng(1), 0, False
    for _ in range(2 * 12 + 3):  # 6 frames of 2 glances an episode: crosses two episode ends
        actions = rng.uniform(-1.2, 1.2, (num, 7)).astype(np.float32)
        obs, reward, terminated, truncated, info = vec.step(actions)
        for i, env in enumerate(singles):
            if pending:  # next-step autoreset: this step began the new episodes
                (o, inf), r, t = env.reset(), 0.0, False
            else:
                o, r, _, t, inf = env.step(actions[i])
                if t and mode == "same_step":
                    _rows_equal(info["final_obs"], o, i)
                    o = env.reset()[0]
            _rows_equal(obs, o, i)
            assert reward[i] == r and truncated[i] == t and not terminated[i]
            if not pending:
                np.testing.assert_array_equal(info["com"][i], inf["com"])
                np.testing.assert_array_equal(info["forward"][i], inf["forward"])
                assert info["target_in_fovea"][i] == inf["target_in_fovea"]
        ends += int(truncated.any())
        pending = bool(truncated.any()) and mode == "next_step"
    assert ends == 2 and info["_com"].all()


def test_a_saved_batch_resumes_exactly_where_it_was():
    kwargs = {**SHORT, "duration": 1.0}
    vec = gym.make_vec("Animat/FishPursuit-v0", num_envs=2, **kwargs)
    vec.reset(seed=3)
    rng = np.random.default_rng(0)
    for _ in range(7):
        vec.step(rng.uniform(-1, 1, (2, 7)).astype(np.float32))
    saved = vec.unwrapped.get_state()
    other = gym.make_vec("Animat/FishPursuit-v0", num_envs=2, **kwargs)
    other.unwrapped.set_state(saved)
    for _ in range(5):
        actions = rng.uniform(-1, 1, (2, 7)).astype(np.float32)
        a, b = vec.step(actions)[0], other.step(actions)[0]
        for key in a:
            np.testing.assert_array_equal(a[key], b[key], err_msg=key)
    fresh = gym.make_vec("Animat/FishPursuit-v0", num_envs=2, **kwargs)
    unreset = gym.make_vec("Animat/FishPursuit-v0", num_envs=2, **kwargs)
    unreset.unwrapped.set_state(fresh.unwrapped.get_state())  # saved before any reset
    np.testing.assert_array_equal(fresh.reset()[0]["left_eye"], unreset.reset()[0]["left_eye"])
    with pytest.raises(ValueError, match="a state of 2 worlds, not 3"):
        gym.make_vec("Animat/FishPursuit-v0", num_envs=3, **kwargs).unwrapped.set_state(saved)


def test_bad_input_is_one_line():
    vec = gym.make_vec("Animat/FishPursuit-v0", num_envs=2, duration=0.2)
    with pytest.raises(RuntimeError, match="call reset"):
        vec.step(np.zeros((2, 7)))
    vec.reset(seed=0)
    with pytest.raises(ValueError, match=r"actions must be \(2, 7\) finite numbers"):
        vec.step(np.zeros((3, 7)))
    with pytest.raises(ValueError, match="num_envs must be"):
        gym.make_vec("Animat/FishPursuit-v0", num_envs=0)
    with pytest.raises(ValueError, match="glances must be"):
        gym.make_vec("Animat/FishPursuit-v0", num_envs=2, glances=9)
    with pytest.raises(ValueError, match="frames must be"):
        gym.make_vec("Animat/FishPursuit-v0", num_envs=2, frames=0)
    with pytest.raises(ValueError, match="give sensors or eyes, not both"):
        gym.make("Animat/FishPursuit-v0", eyes=False, sensors=[])
    assert vec.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP


def test_stable_baselines3_steps_it_as_a_vec_env_with_channel_first_images():
    from stable_baselines3.common.vec_env import VecTransposeImage

    venv = VecTransposeImage(NativeVecEnv("Animat/FishPursuit-v0", 2, {"duration": 0.2}))
    obs = venv.reset()
    assert obs["left_eye"].shape == (2, 12, 64, 64) and obs["left_eye"].dtype == np.uint8
    done_seen = False
    for _ in range(5):
        venv.step_async(np.zeros((2, 7), np.float32))
        obs, reward, done, infos = venv.step_wait()
        if done.any():
            done_seen = True
            assert infos[0]["terminal_observation"]["left_eye"].shape == (12, 64, 64)
    assert done_seen and reward.dtype == np.float32


def test_frames_stack_the_retinas_oldest_first_and_a_blind_state_needs_no_eyes():
    env = gym.make("Animat/FishPursuit-v0", duration=0.2, frames=3)
    first, _ = env.reset(seed=4)
    assert first["left_eye"].shape == (64, 64, 36)
    np.testing.assert_array_equal(first["left_eye"][..., :12], first["left_eye"][..., 24:])
    now = env.step(np.zeros(7, np.float32))[0]
    np.testing.assert_array_equal(now["left_eye"][..., :24], first["left_eye"][..., 12:])
    alone = gym.make("Animat/FishPursuit-v0", duration=0.2).reset(seed=4)[0]
    np.testing.assert_array_equal(first["right_eye"][..., 24:], alone["right_eye"])
    state = gym.make("Animat/FishPursuit-v0", eyes=False, oracle=True)
    assert set(state.observation_space.spaces) == {"gaze", "proprioception", "prey"}


def test_a_look_within_a_frame_earns_nothing_in_the_batch_as_alone():
    """With glances the first look of a frame moves only the eyes, and its reward is 0 even
    with the prey in both foveas (the oracle's gaze holds it there)."""
    from animat.envs.world.pursuit.policy import OraclePolicy

    kwargs = {"duration": 1.0, "glances": 2, "oracle": True}
    vec = gym.make_vec("Animat/FishPursuit-v0", num_envs=2, **kwargs)
    singles = [gym.make("Animat/FishPursuit-v0", **kwargs) for _ in range(2)]
    vec.reset(seed=7)
    obs = [env.reset(seed=7 + i)[0] for i, env in enumerate(singles)]
    policy, looked = OraclePolicy(), 0
    for _ in range(20):
        actions = np.stack([policy.predict(o)[0] for o in obs])
        _, reward, _, _, _ = vec.step(actions)
        for i, env in enumerate(singles):
            obs[i], single_reward, _, _, info = env.step(actions[i])
            assert reward[i] == single_reward
            looked += int(not info["moved"] and info["target_in_fovea"])
    assert looked >= 10  # the case that matters happened
