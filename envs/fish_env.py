"""Gymnasium environments of the artificial fish: a single env and a native batched vector env,
both thin shells over :class:`envs.fish_core.FishBatch` (the same step code).

## Description
A 0.30 m, 0.52 kg mass-spring fish (23 nodes, 91 Voigt elements, 12 muscles in 6 actuators;
:mod:`envs.fish`) in still water. It moves only by pushing water with its body faces (the
reaction force on faces moving into the water, in its cross-flow form by default, plus skin
friction; :mod:`envs.physics.forces`). Tasks: ``swim`` (forward, optionally at a target
speed), ``turn`` (by an angle, left or right), ``reach`` (a goal point). World frame: right
handed, z up, gravity -z; the fish starts at the origin heading +x, its left is +y.

## Action Space
``Box(-1, 1, (6,), float32)``; activation ``u = (a + 1) / 2`` in [0, 1] of the actuators
left-front, left-middle, left-back, right-front, right-middle, right-back. Within an env step
the activation ramps linearly from the previous action to this one (actions are piecewise
linear in time). Out-of-range values are clipped; a wrong shape, NaN or infinity raises
``ValueError`` and leaves the state unchanged. With ``fins=True``: ``(8,)``, the last two
the left and right pectoral fin angles, ``30 deg`` times the entry (held over the env step).

## Observation Space
``Box(-1e4, 1e4, (150 + task entries,), float32)`` (clipped): the 23 node positions and velocities
relative to the centre of mass, in the body frame (BL and BL/s, 69 + 69), the centre-of-mass
velocity in the body frame (BL/s, 3), the world's up direction in the body frame (3), the six
current activations (6), then the task's entries (swim with a target speed: the target, 1;
turn: sin and cos of the heading error, 2; reach: the goal in the body frame, BL, 3).

## Rewards
``r = -(mu1 E_u + mu2 E_v) dt`` (the paper's Eq. 1), ``E_u = (nu1 |du/dt|^2 + nu2 |d^2u/dt^2|^2)
/ 2``. E_v: swim ``-u`` (u: velocity along the start heading +x, BL/s) or
``(u - target)^2``; turn: squared heading
error (rad^2); reach: distance to the goal (BL), plus ``final_weight`` times it on the last
step. ``info`` holds ``E_u``, ``E_v``, ``reward_ctrl``, ``reward_task`` (the two summands of the
reward), ``com`` (3,) m, ``forward`` (3,), ``linear_momentum`` (3,) kg m/s and
``angular_momentum`` (3,) kg m^2/s (world frame, about the centre of mass), ``time`` s,
and the task's metrics (swim:
``speed_bl_per_s``, ``heading_deg``, ``distance_bl``; turn: ``heading_deg``,
``heading_error_deg``; reach: ``distance_bl``).

## Starting State
The rest shape at the origin heading +x, each node coordinate moved by uniform noise of
``reset_noise_scale`` body lengths; at rest; muscles relaxed. Reach goals are drawn per episode.

## Episode End
No termination; truncation after ``duration`` simulated seconds.

## Arguments
``duration`` (s), ``physics_dt`` (s, integration step, default 1/800 s, refused above 75% of
the body's stability bound), ``frame_skip`` (integration steps per env step, default 40;
``dt = physics_dt * frame_skip`` = 0.05 s), ``water`` (dict of
:class:`~envs.physics.system.Water` fields, e.g. a vacuum), ``fins`` (bool: fin angles in the
action space), ``reset_noise_scale`` (BL),
``reward_weights`` (:class:`~envs.fish_core.RewardWeights`), ``render_mode`` (``"rgb_array"``),
and the task's own arguments (swim: ``target_speed``; turn: ``angle_deg``, ``direction``;
reach: ``distance_bl``, ``bearing_deg``, ``final_weight``). The env exposes ``dt`` and
``body_length`` (m).
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from envs.fish_core import (
    DEFAULT_FRAME_SKIP,
    OBS_LIMIT,
    FishBatch,
    RewardWeights,
    validate_actions,
)
from envs.physics.system import DEFAULT_DT
from envs.render import BodyRenderer
from envs.tasks import ReachTask, SwimTask, TurnTask

TASKS = {"swim": SwimTask, "turn": TurnTask, "reach": ReachTask}
DEFAULT_DURATION = {"swim": 10.0, "turn": 5.0, "reach": 20.0}
RENDER_FPS = 20



def _make_core(num_envs: int, task: str, task_kwargs: dict, duration: float | None,
               physics_dt: float, frame_skip: int, reset_noise_scale: float,
               reward_weights: RewardWeights | dict | None, water: dict | None,
               fins: bool) -> FishBatch:
    if task not in TASKS:
        raise ValueError(f"unknown task {task!r}; choose one of {sorted(TASKS)}")
    weights = reward_weights if isinstance(reward_weights, RewardWeights) else RewardWeights(
        **(reward_weights or {}))
    return FishBatch(num_envs, TASKS[task](**task_kwargs), water=water, physics_dt=physics_dt,
                     frame_skip=frame_skip, reset_noise_scale=reset_noise_scale,
                     duration=DEFAULT_DURATION[task] if duration is None else duration,
                     weights=weights, fins=fins)


def _spaces(core: FishBatch) -> tuple[gym.spaces.Box, gym.spaces.Box]:
    action = gym.spaces.Box(-1.0, 1.0, (core.action_size,), np.float32)
    observation = gym.spaces.Box(-OBS_LIMIT, OBS_LIMIT, (core.obs_size,), np.float32)
    return action, observation


class FishEnv(gym.Env):
    """One fish doing one task (see the module docstring for the full description)."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": RENDER_FPS}

    def __init__(self, task: str = "swim", render_mode: str | None = None,
                 duration: float | None = None, physics_dt: float = DEFAULT_DT,
                 frame_skip: int = DEFAULT_FRAME_SKIP, water: dict | None = None,
                 fins: bool = False,
                 reset_noise_scale: float = 0.005,
                 reward_weights: RewardWeights | dict | None = None, **task_kwargs: Any) -> None:
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        self.core = _make_core(1, task, task_kwargs, duration, physics_dt, frame_skip,
                               reset_noise_scale, reward_weights, water, fins)
        self.action_space, self.observation_space = _spaces(self.core)
        self.render_mode = render_mode
        self.dt = self.core.dt
        self.body_length = self.core.body.length
        self.metadata = {**self.metadata, "render_fps": int(round(1.0 / self.dt))}
        self._renderer: BodyRenderer | None = None
        self._started = False

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        self.core.reset_rows(np.array([0]), [self.np_random])
        info = {k: v[0] for k, v in self.core.measure().items()}
        self._started = True
        return self.core.observe()[0], info

    def step(self, action):
        if not self._started:
            raise RuntimeError("call reset() before step()")
        actions = validate_actions(action, self.action_space.shape)[None]
        reward, info = self.core.step(actions)
        obs = self.core.observe()[0]
        return obs, float(reward[0]), False, bool(self.core.truncated[0]), {
            k: v[0] for k, v in info.items()}

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        if self._renderer is None:
            self._renderer = BodyRenderer(self.core.body)
        return self._renderer.render(self.core.x[0])


class FishSwimEnv(FishEnv):
    """``Animat/FishSwim-v0``: swim forward (optionally at ``target_speed`` BL/s)."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(task="swim", **kwargs)


class FishTurnEnv(FishEnv):
    """``Animat/FishTurn-v0``: turn by ``angle_deg`` (default 90) to ``direction``."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(task="turn", **kwargs)


class FishReachEnv(FishEnv):
    """``Animat/FishReach-v0``: reach a goal point drawn per episode."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(task="reach", **kwargs)


def _autoreset_mode(value: str | AutoresetMode) -> AutoresetMode:
    names = {"next_step": AutoresetMode.NEXT_STEP, "same_step": AutoresetMode.SAME_STEP}
    if value in names.values():
        return value
    if value not in names:
        raise ValueError(f"autoreset_mode must be 'next_step' or 'same_step', got {value!r}")
    return names[value]


class FishVectorEnv(VectorEnv):
    """B fish in one batched simulation.

    Sub-env i seeded with ``seed + i`` draws exactly what a single :class:`FishEnv` reset with
    that seed draws, and steps bit for bit like it. ``autoreset_mode``: Gymnasium's
    ``next_step`` (default: the step after an episode's end resets it) or ``same_step`` (it is
    reset at once; the last observation is in ``info["final_obs"]``, masked by
    ``info["_final_obs"]``), the form stable-baselines3 expects.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": RENDER_FPS,
                "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs: int = 1, task: str = "swim", render_mode: str | None = None,
                 duration: float | None = None, physics_dt: float = DEFAULT_DT,
                 frame_skip: int = DEFAULT_FRAME_SKIP, water: dict | None = None,
                 fins: bool = False,
                 reset_noise_scale: float = 0.005,
                 reward_weights: RewardWeights | dict | None = None,
                 autoreset_mode: str | AutoresetMode = AutoresetMode.NEXT_STEP,
                 **task_kwargs: Any) -> None:
        mode = _autoreset_mode(autoreset_mode)
        self.autoreset_mode = mode
        self.metadata = {**self.metadata, "autoreset_mode": mode}
        if int(num_envs) < 1:
            raise ValueError(f"num_envs must be >= 1, got {num_envs!r}")
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        self.num_envs = int(num_envs)
        self.core = _make_core(self.num_envs, task, task_kwargs, duration, physics_dt,
                               frame_skip, reset_noise_scale, reward_weights, water, fins)
        self.single_action_space, self.single_observation_space = _spaces(self.core)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.render_mode = render_mode
        self.dt = self.core.dt
        self.body_length = self.core.body.length
        self._rngs = [seeding.np_random(None)[0] for _ in range(self.num_envs)]
        self._autoreset = np.zeros(self.num_envs, dtype=bool)
        self._renderer: BodyRenderer | None = None
        self._started = False

    def reset(self, *, seed: int | list[int | None] | None = None, options: dict | None = None):
        seeds = self._seeds(seed)
        if seeds is not None:
            self._rngs = [seeding.np_random(s)[0] for s in seeds]
        self.core.reset_rows(np.arange(self.num_envs), self._rngs)
        self._autoreset[:] = False
        self._started = True
        info = self._with_masks(self.core.measure())
        return self.core.observe(), info

    def _seeds(self, seed):
        if seed is None:
            return None
        if isinstance(seed, (int, np.integer)):
            return [int(seed) + i for i in range(self.num_envs)]
        if len(seed) != self.num_envs:
            raise ValueError(f"seed list must have {self.num_envs} entries, got {len(seed)}")
        return list(seed)

    def step(self, actions):
        if not self._started:
            raise RuntimeError("call reset() before step()")
        actions = validate_actions(actions, self.action_space.shape)
        reward, info = self.core.step(actions)
        truncated = self.core.truncated.copy()
        rows = np.flatnonzero(self._autoreset)
        if rows.size:
            self.core.reset_rows(rows, [self._rngs[r] for r in rows])
            fresh = self.core.measure()
            for key, value in info.items():
                value[rows] = fresh[key][rows] if key in fresh else 0.0
            reward[rows] = 0.0
            truncated[rows] = False
        obs = self.core.observe()
        terminated = np.zeros(self.num_envs, dtype=bool)
        if self.autoreset_mode == AutoresetMode.SAME_STEP:
            return self._reset_finished(obs, reward, terminated, truncated, info)
        self._autoreset = truncated
        return obs, reward, terminated, truncated, self._with_masks(info)

    def _reset_finished(self, obs, reward, terminated, truncated, info):
        """Same-step autoreset: restart finished episodes now, keeping their last obs."""
        done = terminated | truncated
        info = self._with_masks(info)
        rows = np.flatnonzero(done)
        if rows.size:
            info["final_obs"], info["_final_obs"] = obs.copy(), done.copy()
            self.core.reset_rows(rows, [self._rngs[r] for r in rows])
            self.core.measure()
            obs = self.core.observe()
        return obs, reward, terminated, truncated, info

    def _with_masks(self, info: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        mask = np.ones(self.num_envs, dtype=bool)
        return {**info, **{f"_{k}": mask for k in info}}

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        if self._renderer is None:
            self._renderer = BodyRenderer(self.core.body)
        return tuple(self._renderer.render(x) for x in self.core.x)


def make_swim_vector(num_envs: int = 1, **kwargs: Any) -> FishVectorEnv:
    return FishVectorEnv(num_envs, task="swim", **kwargs)


def make_turn_vector(num_envs: int = 1, **kwargs: Any) -> FishVectorEnv:
    return FishVectorEnv(num_envs, task="turn", **kwargs)


def make_reach_vector(num_envs: int = 1, **kwargs: Any) -> FishVectorEnv:
    return FishVectorEnv(num_envs, task="reach", **kwargs)
