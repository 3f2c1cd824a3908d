"""PPO (stable-baselines3) on the native batch, the modern baseline.

Hyperparameters take rl-baselines3-zoo's names (``n_envs``, ``n_steps``, ``batch_size``,
``n_epochs``, ``gamma``, ``gae_lambda``, ``learning_rate``, ``clip_range``, ``ent_coef``,
``vf_coef``, ``max_grad_norm``, ``policy``, ``policy_kwargs``, ``normalize``). The policy is
evaluated every ``eval_every`` env steps, deterministically, from the same seeded start state
the black-box learners are scored on (``eval/return`` and the task's ``eval/<metric>``); the
evaluation's own env steps are not charged to the budget.
"""

from __future__ import annotations

import ast
import json
import time
from dataclasses import asdict, dataclass, fields
from pathlib import Path

import gymnasium as gym
import numpy as np

from envs.tasks import EpisodeSummary
from learners.agents import PolicyAgent
from learners.base import BudgetError, Learner, LearnResult, typed_params
from learners.rollout import START_STATES, score_episode, spread


@dataclass(frozen=True)
class PPOParams:
    """rl-baselines3-zoo's hyperparameter names and defaults of this project, plus
    ``eval_every`` (env steps between evaluations), ``torch_threads`` and
    ``checkpoint_every`` (env steps). ``policy_kwargs`` is a mapping or the zoo's
    ``dict(...)`` string."""

    n_envs: int = 64
    n_steps: int = 64
    batch_size: int = 1024
    n_epochs: int = 10
    gamma: float = 0.99
    gae_lambda: float = 0.95
    learning_rate: float = 3e-4
    clip_range: float = 0.2
    ent_coef: float = 0.0
    vf_coef: float = 0.5
    max_grad_norm: float = 0.5
    policy: str = "MlpPolicy"
    policy_kwargs: str | dict = "dict(net_arch=[128, 128], log_std_init=-1.0)"
    normalize: bool = True
    eval_every: int = 50_000
    torch_threads: int = 1
    checkpoint_every: int = 200_000

    def __post_init__(self) -> None:
        counts = ("n_envs", "n_steps", "batch_size", "n_epochs", "eval_every", "torch_threads",
                  "checkpoint_every")
        for name in counts:
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be a positive integer, got {getattr(self, name)!r}")
        parse_policy_kwargs(self.policy_kwargs)


OWN_KEYS = {"eval_every", "torch_threads", "checkpoint_every"}
ZOO_KEYS = {f.name for f in fields(PPOParams)} - OWN_KEYS  # what SB3's PPO is given


def parse_policy_kwargs(value) -> dict:
    """rl-baselines3-zoo writes policy_kwargs as a string such as ``dict(net_arch=[64, 64])``."""
    if isinstance(value, dict):
        return value
    tree = ast.parse(str(value), mode="eval").body
    if not (isinstance(tree, ast.Call) and getattr(tree.func, "id", None) == "dict"
            and not tree.args):
        raise ValueError(f"policy_kwargs must look like dict(key=value, ...), got {value!r}")
    return {kw.arg: ast.literal_eval(kw.value) for kw in tree.keywords}


class PPOLearner(Learner):
    name = "ppo"

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.hp = asdict(typed_params(PPOParams, self.params, f"learner {self.name!r}"))

    def agent(self, artefacts: dict, folder: Path) -> PolicyAgent:
        """The saved network, deterministic, with the run's observation normalisation."""
        from stable_baselines3 import PPO
        from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

        saved = Path(folder) / "checkpoints"
        if not (saved / "model.zip").exists():
            raise FileNotFoundError(f"{saved / 'model.zip'}: the run saved no model")
        model = PPO.load(saved / "model.zip", device="cpu")
        normalize = None
        if (saved / "vecnormalize.pkl").exists():
            venv = DummyVecEnv([lambda: gym.make(self.env_id, **self.env_kwargs)])
            stats = VecNormalize.load(str(saved / "vecnormalize.pkl"), venv)
            stats.training, stats.norm_reward = False, False
            normalize = stats.normalize_obs
        return PolicyAgent(model, self.env_id, self.env_kwargs, normalize)

    def check_budget(self, budget_env_steps: int) -> None:
        """One rollout (``n_envs`` x ``n_steps`` env steps) must fit."""
        rollout = int(self.hp["n_envs"]) * int(self.hp["n_steps"])
        if budget_env_steps < rollout:
            raise BudgetError(f"{budget_env_steps} is less than one PPO rollout ({rollout} env "
                              f"steps: n_envs {self.hp['n_envs']} x n_steps {self.hp['n_steps']})")

    def _model(self, venv, checkpoint: Path | None):
        import torch
        from stable_baselines3 import PPO

        torch.set_num_threads(int(self.hp["torch_threads"]))
        if checkpoint is not None:
            return PPO.load(checkpoint / "model.zip", env=venv, device="cpu")
        keys = ZOO_KEYS - {"n_envs", "policy", "policy_kwargs", "normalize"}
        return PPO(self.hp["policy"], venv, seed=self.seed, device="cpu", verbose=0,
                   policy_kwargs=parse_policy_kwargs(self.hp["policy_kwargs"]),
                   **{k: self.hp[k] for k in keys})

    def _native(self) -> bool:
        """Whether the env has a native batched vector env (the fish envs) or is stepped as
        ``n_envs`` single envs (e.g. the pursuit)."""
        return gym.spec(self.env_id).vector_entry_point is not None

    def _venv(self, checkpoint: Path | None):
        from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

        from learners.sb3_adapter import NativeVecEnv

        n_envs = int(self.hp["n_envs"])
        if self._native():
            venv = NativeVecEnv(self.env_id, n_envs, self.env_kwargs, self.seed)
        else:
            venv = DummyVecEnv([lambda: gym.make(self.env_id, **self.env_kwargs)] * n_envs)
            venv.seed(self.seed)
        if not self.hp["normalize"]:
            return venv
        if checkpoint is not None:
            return VecNormalize.load(str(checkpoint / "vecnormalize.pkl"), venv)
        space = venv.observation_space
        keys = None  # a Dict observation: normalise its non-image entries only
        if isinstance(space, gym.spaces.Dict):
            keys = [k for k, sub in space.spaces.items() if sub.dtype != np.uint8]
        return VecNormalize(venv, gamma=float(self.hp["gamma"]), norm_obs_keys=keys)

    def evaluate(self, model, venv) -> dict[str, float]:
        """Deterministic episodes from the black-box learners' start states (seeds ``seed`` ..
        ``seed + START_STATES - 1``): means, and ``_std`` the spread over them."""
        if not self._native():
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
        ``episode_summary()`` (:func:`learners.rollout.score_episode`)."""
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
        from stable_baselines3.common.callbacks import BaseCallback

        self.check_budget(budget_env_steps)
        folder = Path(checkpoint_dir) if checkpoint_dir else None
        saved = folder if folder and (folder / "model.zip").exists() else None
        state = json.loads((saved / "state.json").read_text()) if saved else {
            "wall": 0.0, "metrics": {}}
        venv = self._venv(saved)
        model = self._model(venv, saved)
        if saved is None:
            self.log_hparams()
        learner, start = self, time.perf_counter() - state["wall"]

        class Progress(BaseCallback):
            def __init__(self) -> None:
                super().__init__()
                self.next_eval = (model.num_timesteps // learner.hp["eval_every"] + 1) * \
                    learner.hp["eval_every"]
                self.next_save = model.num_timesteps + learner.hp["checkpoint_every"]

            def _on_step(self) -> bool:
                if self.num_timesteps >= self.next_eval:
                    state["metrics"] = learner.evaluate(model, venv)
                    learner.logger.scalars(state["metrics"], self.num_timesteps)
                    self.next_eval += learner.hp["eval_every"]
                if folder and self.num_timesteps >= self.next_save:
                    learner._save(folder, model, venv, state, start)
                    self.next_save += learner.hp["checkpoint_every"]
                return True

        rollout = int(self.hp["n_envs"]) * int(self.hp["n_steps"])
        # SB3 collects whole rollouts: as many as fit, so the budget is never overrun
        remaining = budget_env_steps // rollout * rollout - model.num_timesteps
        if remaining > 0:
            model.learn(remaining, callback=Progress(), reset_num_timesteps=saved is None)
        state["metrics"] = self.evaluate(model, venv)
        self.logger.scalars(state["metrics"], model.num_timesteps)
        if folder:
            self._save(folder, model, venv, state, start)
        return LearnResult(env_steps=int(model.num_timesteps),
                           wall_seconds=time.perf_counter() - start, metrics=state["metrics"],
                           artefacts={"hyperparameters": {k: self.hp[k] for k in sorted(
                               self.hp)}})

    @staticmethod
    def _save(folder: Path, model, venv, state: dict, start: float) -> None:
        folder.mkdir(parents=True, exist_ok=True)
        model.save(folder / "model.zip")
        if hasattr(venv, "save"):
            venv.save(str(folder / "vecnormalize.pkl"))
        state["wall"] = time.perf_counter() - start
        (folder / "state.json").write_text(json.dumps(state))
