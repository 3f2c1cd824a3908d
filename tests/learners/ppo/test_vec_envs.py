"""The SB3 adapter of the native batch: an episode's end carries what SB3 reads off it."""

import numpy as np

from animat.learners.ppo.vec_envs import NativeVecEnv


def test_a_stunts_end_carries_is_success_which_sb3_counts_into_its_success_rate():
    """A leap of relaxed muscles 3 m down never clears the surface: every episode ends with
    is_success False, which SB3's ``_update_info_buffer`` reads; the fish's swim, which does
    not say, ends without the key."""
    venv = NativeVecEnv("Animat/DolphinLeap-v0", 2, {"duration": 0.2})
    venv.seed(0)
    venv.reset()
    ends = []
    for _ in range(4):
        _, _, dones, infos = venv.step(-np.ones((2, 6), np.float32))
        ends += [info for info, done in zip(infos, dones) if done]
    assert len(ends) == 2 and all(info["is_success"] is False for info in ends)
    venv = NativeVecEnv("Animat/FishSwim-v0", 1, {"duration": 0.05})
    venv.reset()
    _, _, dones, infos = venv.step(np.zeros((1, 6), np.float32))
    assert dones[0] and "terminal_observation" in infos[0] and "is_success" not in infos[0]
