"""The pursuit's native vector env: N worlds in one batch, every observer's eyes in one call.

``gym.make_vec("Animat/FishPursuit-v0", num_envs=N, ...)`` makes a
:class:`FishPursuitVectorEnv` of the single env's arguments (see
:mod:`animat.envs.world.pursuit.env`). World i reset with ``seed + i`` steps bit for bit as a
single env reset with that seed: both run :class:`~animat.envs.world.pursuit.worlds.PursuitWorlds`
(the single env with N = 1). Observations are the single env's ``Dict`` with a leading N axis;
``info`` is Gymnasium's dict of arrays, each key with its ``_key`` mask.

Every episode has the same length and :meth:`reset` starts them all, so the worlds end, and
restart, together. Its state (:meth:`get_state`) is how the running episodes began (each
world's generator then) and the actions since: :meth:`set_state` replays them, so a
checkpointed learner resumes exactly.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from ...checks import check_integer
from ...core.shell import generator_from_state, parse_autoreset_mode, sub_env_seeds
from .senses import ObserverView
from .shell import (
    DEFAULT_DURATION,
    FrameStack,
    check_render_mode,
    observe,
    pursuit_observer,
    pursuit_params,
    render_world,
    world_infos,
)
from .worlds import PursuitWorlds

MAX_WORLDS = 1024


class FishPursuitVectorEnv(VectorEnv):
    """``num_envs`` pursuit worlds stepped together (see the module docstring).
    ``autoreset_mode``: ``next_step`` (default) or ``same_step`` (the last observation in
    ``info["final_obs"]``), as :class:`animat.envs.core.env.BodyVectorEnv`'s."""

    default_duration = DEFAULT_DURATION  # s
    metadata = {"render_modes": ["rgb_array", "retina"], "render_fps": 20,
                "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs: int = 1, render_mode: str | None = None,
                 duration: float = DEFAULT_DURATION,
                 start_distance_bl: tuple[float, float] | None = None,
                 bearing_deg: tuple[float, float] = (-60.0, 60.0),
                 flee_distance_bl: float = 2.5, prey_speed: float = 0.5,
                 distractors: int = 1, passers: int = 3, occluders: bool = True,
                 glances: int = 1, sensors: list | None = None, water: dict | None = None,
                 oracle: bool = False, eyes: bool = True, frames: int = 1,
                 autoreset_mode: str | AutoresetMode = AutoresetMode.NEXT_STEP) -> None:
        self.autoreset_mode = parse_autoreset_mode(autoreset_mode)
        self.metadata = {**self.metadata, "autoreset_mode": self.autoreset_mode}
        self.render_mode = check_render_mode(render_mode)
        self.num_envs = check_integer("num_envs", num_envs, 1, MAX_WORLDS)
        params = pursuit_params(duration, start_distance_bl, bearing_deg, flee_distance_bl,
                                prey_speed, distractors, passers, occluders, glances, water)
        self.worlds = PursuitWorlds(self.num_envs, params)
        self.core, self.dt, self.body_length = self.worlds.core, self.worlds.dt, \
            self.worlds.body_length
        self.view = ObserverView(self.worlds)
        self.observer, space = pursuit_observer(self.view, sensors, oracle, eyes)
        self.stack = FrameStack(frames, space, self.observer.channels_first)
        self.single_observation_space = self.stack.space(space)
        self.single_action_space = gym.spaces.Box(-1.0, 1.0, (7,), np.float32)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self._rngs = [seeding.np_random(None)[0] for _ in range(self.num_envs)]
        self._autoreset = False
        # each world's generator as its episode began (before the first reset: as it is now)
        self._began = [rng.bit_generator.state for rng in self._rngs]
        self._actions: list[np.ndarray] = []  # the actions since
        self._started = False

    @property
    def episode_steps(self) -> int:
        """Env steps per episode (``duration / dt``, times ``glances``)."""
        return self.core.episode_steps * self.worlds.params.glances

    def reset(self, *, seed: int | list[int | None] | None = None, options: dict | None = None):
        seeds = sub_env_seeds(seed, self.num_envs)
        if seeds is not None:
            self._rngs = [seeding.np_random(s)[0] for s in seeds]
        kinematics = self._restart()
        self._started = True
        return self._observe(kinematics, fresh=True), self._infos(kinematics, True)

    def _restart(self):
        self._began = [rng.bit_generator.state for rng in self._rngs]
        self._actions, self._autoreset = [], False
        return self.worlds.reset(range(self.num_envs), self._rngs)

    def step(self, actions):
        if not self._started:
            raise RuntimeError("call reset() before step()")
        actions = np.asarray(actions, dtype=np.float64)
        if actions.shape != (self.num_envs, 7) or not np.all(np.isfinite(actions)):
            raise ValueError(f"actions must be ({self.num_envs}, 7) finite numbers, got shape "
                             f"{actions.shape}")
        if self._autoreset:  # next-step autoreset: this step starts the new episodes
            kinematics = self._restart()
            zeros = np.zeros(self.num_envs, bool)
            return (self._observe(kinematics, True), np.zeros(self.num_envs), zeros, zeros.copy(),
                    self._infos(kinematics, True))
        self._actions.append(actions.copy())
        clipped = np.clip(actions, -1.0, 1.0)
        closed, moved, kinematics = self.worlds.step(clipped, self._rngs)
        info = self._infos(kinematics, moved)
        reward = closed / self.body_length + 0.05 * info["target_in_fovea"]
        if not moved:  # a look within the frame earns nothing, as in the single env
            reward = np.zeros(self.num_envs)
        truncated = self.worlds.truncated.copy() if moved else np.zeros(self.num_envs, bool)
        terminated = np.zeros(self.num_envs, bool)
        obs = self._observe(kinematics)
        if truncated.any() and self.autoreset_mode == AutoresetMode.SAME_STEP:
            info["final_obs"], info["_final_obs"] = self.observer.copy(obs), truncated.copy()
            info["final_info"], info["_final_info"] = dict(info), truncated.copy()
            obs = self._observe(self._restart(), fresh=True)
        else:
            self._autoreset = bool(truncated.any())
        return obs, reward, terminated, truncated, info

    def _observe(self, kinematics, fresh: bool = False) -> dict[str, np.ndarray]:
        return observe(self.observer, self.view, kinematics, self.stack, fresh)

    def _infos(self, kinematics, moved: bool) -> dict:
        infos = world_infos(self.worlds, kinematics, self.worlds.eye_poses(kinematics), moved)
        mask = np.ones(self.num_envs, bool)
        out: dict = {}
        for key, value in infos.items():
            out[key], out[f"_{key}"] = value, mask
        return out

    def render(self):
        if self.render_mode is None:
            return None
        return tuple(render_world(self.worlds, self.render_mode, w)
                     for w in range(self.num_envs))

    def get_state(self) -> dict:
        """How the running episodes began (each world's generator's state then), the
        actions since (T, N, 7), whether the next step restarts them, and whether
        :meth:`reset` was called: plain data, for :meth:`set_state` on a vector env of the
        same arguments."""
        actions = np.array(self._actions).reshape(-1, self.num_envs, 7)
        return {"began": list(self._began), "actions": actions,
                "autoreset": self._autoreset, "started": self._started}

    def set_state(self, saved: dict) -> None:
        """Continue from ``saved`` (:meth:`get_state`'s dict): the episodes restarted from
        how they began and the actions replayed; ValueError naming what does not fit, before
        anything is changed."""
        if len(saved["began"]) != self.num_envs:
            raise ValueError(f"a state of {len(saved['began'])} worlds, not {self.num_envs}")
        rngs = [generator_from_state(state) for state in saved["began"]]
        actions = np.asarray(saved["actions"], dtype=np.float64)
        if actions.ndim != 3 or actions.shape[1:] != (self.num_envs, 7):
            raise ValueError(f"actions must be (T, {self.num_envs}, 7), got {actions.shape}")
        self._started, self._rngs = bool(saved["started"]), rngs
        if not self._started:  # the next reset draws what the saved env's would
            self._began = [rng.bit_generator.state for rng in rngs]
            return
        self._restart()
        for step in actions:
            self.step(step)
        self._autoreset = bool(saved["autoreset"])
