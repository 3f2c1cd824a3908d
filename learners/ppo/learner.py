"""PPO (stable-baselines3) on the native batch, the modern baseline.

Hyperparameters take rl-baselines3-zoo's names and value forms (:mod:`animat.learners.ppo.zoo`:
``lin_3e-4`` schedules, ``policy_kwargs`` strings with ``nn.Tanh``, a ``normalize`` mapping).
The policy is
evaluated every ``eval_every`` env steps, deterministically, from the same seeded start state
the black-box learners are scored on (``eval/return`` and the task's ``eval/<metric>``); the
evaluation's own env steps are not charged to the budget.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import gymnasium as gym
import numpy as np
from pydantic import ValidationError

from animat.envs.registration import CORE
from animat.envs.tasks.base import EpisodeSummary

from ..agents import PolicyAgent
from ..base import Learner, LearnResult
from ..rollout import START_STATES, score_episode, spread
from ..storage.files import read_json
from ..storage.pickles import UntrustedPickle
from ..validation import BudgetError, check_memory
from . import checkpoint as ppo_checkpoint
from .allocator import keep_freed_memory
from .hooks import progress_callback, sb3_logger
from .threads import set_threads, torch_loaded_late, update_threads
from .zoo import PPOParams, normalize_kwargs, policy_kwargs, schedule

OWN_KEYS = {"eval_every", "torch_threads", "update_threads", "checkpoint_every"}

ZOO_KEYS = set(PPOParams.model_fields) - OWN_KEYS  # what SB3's PPO is given


def ppo_params(params: dict, owner: str) -> PPOParams:
    """The typed params, or ValueError naming the first bad one in one line."""
    if "n_timesteps" in params:
        raise ValueError(f"{owner}: n_timesteps is the run's budget here: set budget.env_steps")
    try:
        return PPOParams.model_validate(params)
    except ValidationError as error:
        first = error.errors()[0]
        where = ".".join(str(p) for p in first["loc"])
        message = ("unknown parameter" if first["type"] == "extra_forbidden"
                   else first["msg"].removeprefix("Value error, "))
        raise ValueError(f"{owner}: {where}: {message}") from None


class PPOLearner(Learner):
    name = "ppo"

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        # unset keys left out (update_threads), so a config without them records what it did
        self.hp = ppo_params(self.params, f"learner {self.name!r}").model_dump(exclude_none=True)
        if update_threads(self.hp) > 1 and torch_loaded_late():
            print("animat: warning: Numba's threads started before torch was imported, so "
                  "PPO's updates on more than one thread will contend with them: import torch "
                  "before the first env step", file=sys.stderr)

    def agent(self, artefacts: dict, folder: Path) -> PolicyAgent:
        """The saved network, deterministic, with the run's observation normalisation: the
        model rebuilt from the config, its weights and statistics read as data
        (:mod:`animat.learners.ppo.checkpoint`)."""
        checkpoints = Path(folder) / "checkpoints"
        saved = ppo_checkpoint.latest(checkpoints)
        if saved is None and self._legacy(checkpoints):
            return self._legacy_agent(checkpoints)
        if saved is None:
            raise FileNotFoundError(f"{checkpoints}: the run saved no model")
        venv = self._venv()
        model = self._model(venv)
        ppo_checkpoint.restore(model, venv, saved, with_optimizer=False)
        normalize = None
        if hasattr(venv, "normalize_obs"):
            venv.training, venv.norm_reward = False, False
            normalize = venv.normalize_obs
        return PolicyAgent(model, self.env_id, self.env_kwargs, normalize)

    def _legacy(self, checkpoints: Path) -> bool:
        """Whether the folder holds an older version's pickled checkpoint (model.zip); refused
        unless ``trust_pickles``: unpickling runs whatever code its writer put in it."""
        if not (checkpoints / "model.zip").exists():
            return False
        if not self.trust_pickles:
            raise UntrustedPickle(checkpoints / "model.zip")
        return True

    def _legacy_agent(self, saved: Path) -> PolicyAgent:
        from stable_baselines3 import PPO
        from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

        model = PPO.load(saved / "model.zip", device="cpu")
        normalize = None
        if (saved / "vecnormalize.pkl").exists():
            venv = DummyVecEnv([lambda: gym.make(self.env_id, **self.env_kwargs)])
            stats = VecNormalize.load(str(saved / "vecnormalize.pkl"), venv)
            stats.training, stats.norm_reward = False, False
            normalize = stats.normalize_obs
        return PolicyAgent(model, self.env_id, self.env_kwargs, normalize)

    def check_budget(self, budget_env_steps: int) -> None:
        """One rollout (``n_envs`` x ``n_steps`` env steps) must fit the budget, its buffer
        this machine's memory, and the policy the env's observations."""
        rollout = int(self.hp["n_envs"]) * int(self.hp["n_steps"])
        if budget_env_steps < rollout:
            raise BudgetError(f"{budget_env_steps} is less than one PPO rollout ({rollout} env "
                              f"steps: n_envs {self.hp['n_envs']} x n_steps {self.hp['n_steps']})")
        self._check_fits_env(rollout)

    def _check_fits_env(self, rollout: int) -> None:
        """ValueError in one line when the policy cannot take the env's observations (a Dict
        space takes ``MultiInputPolicy``, and only it does), or when a rollout's buffer (every
        observation entry as float32, as SB3 keeps them) would not fit this machine's memory."""
        env = gym.make(self.env_id, **self.env_kwargs)
        space = env.observation_space
        env.close()
        policy, is_dict = self.hp["policy"], isinstance(space, gym.spaces.Dict)
        if is_dict != (policy == "MultiInputPolicy"):
            wanted = "MultiInputPolicy" if is_dict else "MlpPolicy (or CnnPolicy for images)"
            raise ValueError(f"policy {policy} cannot take {self.env_id}'s "
                             f"{type(space).__name__} observations: use {wanted}")
        entries = sum(int(np.prod(sub.shape)) for sub in (
            space.spaces.values() if is_dict else [space]))
        check_memory(4 * entries * rollout, f"a rollout of n_envs {self.hp['n_envs']} x n_steps "
                                            f"{self.hp['n_steps']} observations of {entries} "
                                            f"entries")

    def _model(self, venv, legacy: Path | None = None):
        """A fresh model of the config's hyperparameters on ``venv`` (``legacy``: an older,
        trusted pickled checkpoint's folder to load instead)."""
        import torch
        from stable_baselines3 import PPO

        torch.set_num_threads(int(self.hp["torch_threads"]))
        if legacy is not None:
            model = PPO.load(legacy / "model.zip", env=venv, device="cpu")
            model.set_logger(sb3_logger(self.logger))
            return model
        keys = ZOO_KEYS - {"n_envs", "policy", "policy_kwargs", "normalize", "learning_rate",
                           "clip_range"}
        model = PPO(self.hp["policy"], venv, seed=self.seed, device="cpu", verbose=0,
                    policy_kwargs=policy_kwargs(self.hp["policy_kwargs"]),
                    learning_rate=schedule(self.hp["learning_rate"]),
                    clip_range=schedule(self.hp["clip_range"]),
                    **{k: self.hp[k] for k in keys})
        model.set_logger(sb3_logger(self.logger))
        return model

    def _native(self) -> bool:
        """Whether the env has a native batched vector env (the fish envs, the pursuit) or is
        stepped as ``n_envs`` single envs (e.g. the living world)."""
        return gym.spec(self.env_id).vector_entry_point is not None

    def _batch_scored(self) -> bool:
        """Whether evaluation runs the native vector env with its task's batched summary (the
        body envs), or scores one episode at a time by the env's own ``episode_summary()``
        (the pursuit, whose summary is its own)."""
        return self._native() and gym.spec(self.env_id).entry_point == CORE["entry_point"]

    def _venv(self, legacy: Path | None = None):
        """The training envs (their state saved with each checkpoint), normalised as the
        config says."""
        from stable_baselines3.common.vec_env import VecNormalize

        from .vec_envs import NativeVecEnv, ReplayVecEnv

        n_envs = int(self.hp["n_envs"])
        kind = NativeVecEnv if self._native() else ReplayVecEnv
        venv = kind(self.env_id, n_envs, self.env_kwargs, self.seed)
        normalize = normalize_kwargs(self.hp["normalize"])
        if normalize is None:
            return venv
        if legacy is not None:
            return VecNormalize.load(str(legacy / "vecnormalize.pkl"), venv)
        space = venv.observation_space
        keys = None  # a Dict observation: normalise its non-image entries only
        if isinstance(space, gym.spaces.Dict):
            keys = [k for k, sub in space.spaces.items() if sub.dtype != np.uint8]
        return VecNormalize(venv, gamma=float(self.hp["gamma"]), norm_obs_keys=keys,
                            **normalize)

    def evaluate(self, model, venv) -> dict[str, float]:
        """Deterministic episodes from the black-box learners' start states (seeds ``seed`` ..
        ``seed + START_STATES - 1``): means, and ``_std`` the spread over them."""
        if not self._batch_scored():
            return self._evaluate_singly(model, venv)
        if getattr(self, "_eval_env", None) is None:
            self._eval_env = gym.make_vec(self.env_id, num_envs=START_STATES, **self.env_kwargs)
        env = self._eval_env
        obs, _ = env.reset(seed=[self.seed + k for k in range(START_STATES)])
        total, summary = np.zeros(START_STATES), EpisodeSummary(env.task, START_STATES)
        for _ in range(env.episode_steps):
            if hasattr(venv, "normalize_obs"):
                obs = venv.normalize_obs(obs)
            action, _ = model.predict(obs, deterministic=True)
            obs, reward, _, _, info = env.step(action)
            total += reward
            summary.update(info)
        metrics = summary.summary()
        return {"eval/return": float(total.mean()),
                **{f"eval/{k}": float(v.mean()) for k, v in metrics.items()},
                **{f"eval/{k}_std": float(v.std()) for k, v in metrics.items()}}

    def _evaluate_singly(self, model, venv) -> dict[str, float]:
        """The same protocol, one episode at a time, scored by the env's own
        ``episode_summary()`` (:func:`animat.learners.rollout.score_episode`)."""
        if getattr(self, "_eval_env", None) is None:
            self._eval_env = gym.make(self.env_id, **self.env_kwargs)

        class Deterministic:
            def predict(self, obs):
                seen = venv.normalize_obs(obs) if hasattr(venv, "normalize_obs") else obs
                return model.predict(seen, deterministic=True)

        return spread([score_episode(self._eval_env, Deterministic(), self.seed + k)
                       for k in range(START_STATES)])

    def learn(self, budget_env_steps: int, checkpoint_dir: str | Path | None = None
              ) -> LearnResult:
        self.check_budget(budget_env_steps)
        folder = Path(checkpoint_dir) if checkpoint_dir else None
        saved = ppo_checkpoint.latest(folder) if folder else None
        legacy = folder if saved is None and folder and self._legacy(folder) else None
        venv = self._venv(legacy)
        model = self._model(venv, legacy)
        state = {"wall": 0.0, "metrics": {}}
        if saved is not None:
            state = ppo_checkpoint.restore(model, venv, saved)
            if not ppo_checkpoint.restore_progress(model, venv, saved):
                print(f"animat: warning: {saved}: no {ppo_checkpoint.RESUME} (an older "
                      "version's checkpoint): the run goes on from fresh episodes, not exactly "
                      "where it was", file=sys.stderr)
        elif legacy is not None:
            state = read_json(legacy / "state.json")
        resumed = saved is not None or legacy is not None
        if not resumed:
            self.log_hparams()
        start = time.perf_counter() - state["wall"]
        rollout = int(self.hp["n_envs"]) * int(self.hp["n_steps"])
        # SB3 collects whole rollouts: as many as fit, so the budget is never overrun
        remaining = (budget_env_steps - model.num_timesteps) // rollout * rollout
        if remaining > 0:
            progress = progress_callback(self, model, venv, folder, state, start,
                                         final=model.num_timesteps + remaining)
            keep_freed_memory()  # each minibatch reuses the memory the last one freed
            model.learn(remaining, callback=progress, reset_num_timesteps=not resumed)
            set_threads(int(self.hp["torch_threads"]))  # the last update left update_threads
        state["metrics"] = self.evaluate(model, venv)  # the policy the run returns
        self.logger.scalars(state["metrics"], model.num_timesteps)
        if folder:
            self.save_checkpoint(folder, model, venv, state, start)
        return LearnResult(env_steps=int(model.num_timesteps),
                           wall_seconds=time.perf_counter() - start, metrics=state["metrics"],
                           artefacts={"hyperparameters": {k: self.hp[k] for k in sorted(
                               self.hp)}})

    @staticmethod
    def save_checkpoint(folder: Path, model, venv, state: dict, start: float) -> None:
        """A new checkpoint (:func:`animat.learners.ppo.checkpoint.save`: data, written whole
        before it replaces the last)."""
        state["wall"] = time.perf_counter() - start
        ppo_checkpoint.save(folder, model, venv, {"wall": state["wall"],
                                                  "metrics": state["metrics"]})
