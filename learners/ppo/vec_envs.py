"""stable-baselines3 VecEnvs whose state can be saved and restored as data, so that a
checkpointed PPO run resumes exactly (:mod:`animat.learners.ppo.checkpoint`).

- :class:`NativeVecEnv`: a native batched env (the fish's, the pursuit's; SB3 cannot take a
  Gymnasium ``VectorEnv``): the same batched step, with SB3's same-step reset conventions; its
  state is the vector env's own (:meth:`animat.envs.core.env.BodyVectorEnv.get_state`,
  :meth:`animat.envs.world.pursuit.vector.FishPursuitVectorEnv.get_state`).
- :class:`ReplayVecEnv`: single envs stepped one after another (SB3's ``DummyVecEnv``), for
  envs without a batched form (the living world); an env's state is how its episode began and the
  actions since (:class:`EpisodeReplay`), replayed into a fresh env on restore.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from stable_baselines3.common.vec_env import DummyVecEnv
from stable_baselines3.common.vec_env.base_vec_env import VecEnv

import animat  # noqa: F401


class NativeVecEnv(VecEnv):
    """``num_envs`` sub-envs of ``env_id`` in its native vector env (``gym.make_vec``)."""

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

    def get_state(self) -> dict:
        """The vector env's state and the seed of the next reset."""
        return {"venv": self.venv.get_state(), "seed": self._seed}

    def set_state(self, saved: dict) -> None:
        """Continue from ``saved`` (:meth:`get_state`'s dict)."""
        self.venv.set_state(saved["venv"])
        self._seed = int(saved["seed"])

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = np.asarray(actions, dtype=np.float32)

    def step_wait(self):
        obs, reward, terminated, truncated, info = self.venv.step(self._actions)
        dones = terminated | truncated
        infos: list[dict[str, Any]] = [{} for _ in range(self.num_envs)]
        final = info.get("final_obs")
        for i in np.flatnonzero(dones):
            infos[i]["terminal_observation"] = (
                {key: value[i] for key, value in final.items()} if isinstance(final, dict)
                else final[i])
            infos[i]["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
            if "is_success" in info:  # a task that says whether it was done: SB3's success rate
                infos[i]["is_success"] = bool(info["is_success"][i])
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


class EpisodeReplay(gym.Wrapper):
    """Keeps how the current episode began (its reset's seed, or the random generator's state
    before an unseeded reset) and every action since: what brings a fresh env of the same
    arguments to the same moment (:meth:`set_state` replays them), for any env that is
    deterministic given its generator and actions, as every Animat env is."""

    def __init__(self, env: gym.Env) -> None:
        super().__init__(env)
        self._start: dict | None = None
        self._actions: list[np.ndarray] = []

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        if options:
            raise ValueError("EpisodeReplay keeps no reset options")
        self._start = ({"seed": int(seed)} if seed is not None else
                       {"rng": self.env.unwrapped.np_random.bit_generator.state})
        self._actions = []
        return self.env.reset(seed=seed)

    def step(self, action):
        self._actions.append(np.array(action, copy=True))
        return self.env.step(action)

    def get_state(self) -> dict:
        """{``start``: the episode's seed or generator state, ``actions``: (T, *action
        shape) since, of the type they were given in}."""
        if not self._actions:
            return {"start": self._start, "actions": np.zeros((0, *self.action_space.shape))}
        return {"start": self._start, "actions": np.array(self._actions)}

    def set_state(self, saved: dict) -> None:
        """Begin the episode as ``saved`` says and replay its actions (T env steps)."""
        start, actions = saved["start"], np.asarray(saved["actions"])
        if start is None:  # saved before its first reset
            return
        if "seed" in start:
            self.env.reset(seed=int(start["seed"]))
        else:
            self.env.unwrapped.np_random.bit_generator.state = start["rng"]
            self.env.reset()
        for action in actions:
            self.env.step(action)
        self._start, self._actions = start, list(actions)


class ReplayVecEnv(DummyVecEnv):
    """``num_envs`` single envs of ``env_id``, each in :class:`EpisodeReplay`, seeded
    ``seed`` onward at the first reset; their state saved and restored as data."""

    def __init__(self, env_id: str, num_envs: int, env_kwargs: dict | None = None,
                 seed: int = 0) -> None:
        super().__init__([lambda: EpisodeReplay(gym.make(env_id, **(env_kwargs or {})))]
                         * int(num_envs))
        self.seed(seed)

    def get_state(self) -> dict:
        return {"envs": [env.get_state() for env in self.envs]}

    def set_state(self, saved: dict) -> None:
        if len(saved["envs"]) != self.num_envs:
            raise ValueError(f"a state of {len(saved['envs'])} envs, not {self.num_envs}")
        for env, state in zip(self.envs, saved["envs"]):
            env.set_state(state)
        self._reset_seeds()  # the first reset's seeds were used by the run saved
