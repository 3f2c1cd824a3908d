"""A stable-baselines3 ``VecEnv`` over the native batched fish env (SB3 cannot take a
Gymnasium ``VectorEnv``): the same batched step, with SB3's same-step reset conventions."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from stable_baselines3.common.vec_env.base_vec_env import VecEnv

import animat  # noqa: F401


class NativeVecEnv(VecEnv):
    """``num_envs`` fish of ``env_id`` in one :class:`animat.envs.fish_env.FishVectorEnv`."""

    def __init__(self, env_id: str, num_envs: int, env_kwargs: dict | None = None,
                 seed: int = 0) -> None:
        self.venv = gym.make_vec(env_id, num_envs=num_envs, autoreset_mode="same_step",
                                 **(env_kwargs or {}))
        super().__init__(num_envs, self.venv.single_observation_space,
                         self.venv.single_action_space)
        self._seed = int(seed)
        self._actions: np.ndarray | None = None

    def reset(self) -> np.ndarray:
        obs, _ = self.venv.reset(seed=self._seed)
        self._seed += self.num_envs  # a later reset() starts new episodes, not the same ones
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = np.asarray(actions, dtype=np.float32)

    def step_wait(self):
        obs, reward, terminated, truncated, info = self.venv.step(self._actions)
        dones = terminated | truncated
        infos: list[dict[str, Any]] = [{} for _ in range(self.num_envs)]
        for i in np.flatnonzero(dones):
            infos[i]["terminal_observation"] = info["final_obs"][i]
            infos[i]["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
        return obs, reward.astype(np.float32), dones, infos

    def close(self) -> None:
        self.venv.close()

    def seed(self, seed: int | None = None):
        self._seed = 0 if seed is None else int(seed)
        return [self._seed + i for i in range(self.num_envs)]

    def get_attr(self, attr_name: str, indices=None) -> list[Any]:
        return [getattr(self.venv, attr_name)] * len(self._indices(indices))

    def set_attr(self, attr_name: str, value: Any, indices=None) -> None:
        setattr(self.venv, attr_name, value)

    def env_method(self, method_name: str, *args, indices=None, **kwargs) -> list[Any]:
        return [getattr(self.venv, method_name)(*args, **kwargs)] * len(self._indices(indices))

    def env_is_wrapped(self, wrapper_class, indices=None) -> list[bool]:
        return [False] * len(self._indices(indices))

    def _indices(self, indices) -> list[int]:
        if indices is None:
            return list(range(self.num_envs))
        return [indices] if isinstance(indices, int) else list(indices)
