"""The batched core of every fish environment: the step, the measurements and the observation.

:class:`BodyBatch` holds B fish (B = 1 for a single env) and advances them together with
:func:`animat.envs.physics.integrator.step_batch`. The single env
(:class:`animat.envs.core.env.BodyEnv`) and the native vector env
(:class:`animat.envs.core.env.BodyVectorEnv`) are thin shells around it, so the physics, the
observation and the reward exist once. Its state is :class:`~animat.envs.core.state.BodyState`,
its reward that of :mod:`animat.envs.core.reward` (Eq. 1), its arguments checked by
:mod:`animat.envs.core.arguments`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..bodies.fish import fish_body
from ..bodies.spec import BodySpec
from ..motor.fish import FinParams
from ..physics.integrator import step_batch
from ..physics.observe import body_state, momenta
from ..physics.observe import proprioception as write_proprioception
from ..physics.system import DEFAULT_DT, System, Water
from ..tasks.base import Task, World
from ..tasks.start import StartSpread, spread_start
from .arguments import check_arguments
from .reward import RewardWeights, control_energy
from .state import BodyState

OBS_LIMIT = 1e4  # observation entries are clipped to +-OBS_LIMIT
DEFAULT_FRAME_SKIP = 40  # integration steps per env step: 40 x 1.25 ms = 0.05 s


class Kinematics(NamedTuple):
    """What :meth:`BodyBatch.measure` computed and :meth:`BodyBatch.observe` reuses: centre of
    mass (B, 3) m, its velocity (B, 3) m/s, body frames (B, 3, 3) (rows forward, left, up)."""

    com: np.ndarray
    com_vel: np.ndarray
    frames: np.ndarray


class BodyBatch:
    """B fish doing one task: a :class:`~envs.physics.system.System` (fixed), a
    :class:`BodyState` (``state``, what changes) and the step, measurement and observation
    functions on them.

    Args:
        num_envs: B.
        task: the :class:`~envs.tasks.base.Task`.
        body: the body description (default: :func:`animat.envs.bodies.fish.fish_body`).
        water: the medium, a :class:`~envs.physics.system.Water` or a dict of its fields
            (default: still fresh water, no surface, the reactive model).
        physics_dt: integration step, s.
        frame_skip: integration steps per env step (env ``dt = physics_dt * frame_skip``).
        duration: simulated seconds per episode (then truncated).
        reset_noise_scale: uniform noise on each start node coordinate, body lengths.
        start_spread: the spread of the episodes' starts (:mod:`animat.envs.tasks.start`): None
            the task's own (``task.start_spread``), ``"point"`` none, a dict its fields over
            the task's.
        weights: reward weights.
        fins: if True the actions carry the pectoral fin angles too: (B, A + P), the last P
            entries in [-1, 1] setting fin p to ``fin_max_angle`` (rad) times the entry.
        fin_max_angle: rad, the fin angle of an action entry of 1 (the fin-MC's gain).
        integrator: ``"explicit"`` (symplectic Euler) or ``"implicit"`` (the linearised
            theta-method), :class:`~envs.physics.system.System`'s.

    The numbers are checked (:func:`check_arguments`): a bad one is a ValueError of one line
    naming it.
    """

    def __init__(self, num_envs: int, task: Task, body: BodySpec | None = None,
                 water: Water | dict | None = None, physics_dt: float = DEFAULT_DT,
                 frame_skip: int = DEFAULT_FRAME_SKIP,
                 duration: float = 10.0, reset_noise_scale: float = 0.005,
                 weights: RewardWeights = RewardWeights(), fins: bool = False,
                 fin_max_angle: float = FinParams().max_angle,
                 start_spread: StartSpread | dict | str | None = None,
                 integrator: str = "explicit") -> None:
        check_arguments(num_envs, physics_dt, frame_skip, duration, reset_noise_scale, fins,
                        fin_max_angle)
        self.start_spread = task.start_spread.over(start_spread)
        task.check_start_spread(self.start_spread)
        self.task, self.weights = task, weights
        self.system = System(body or fish_body(), Water.from_dict(water), dt=physics_dt,
                             integrator=integrator)
        self.body = self.system.body
        self.frame_skip = int(frame_skip)
        self.dt = self.system.dt * self.frame_skip
        self.episode_steps = max(1, int(round(duration / self.dt)))
        self.reset_noise_scale = float(reset_noise_scale)
        self.state = BodyState.zeros(num_envs, self.body, task)
        self.ball = task.ball
        self._ball_args = None if self.ball is None else self.ball.as_args()
        n, a = self.body.num_nodes, self.body.num_actuators
        self.proprioception_size = 2 * n * 3 + 6 + a
        self.obs_size = self.proprioception_size + task.obs_size
        self.fin_actions = bool(fins)
        self.fin_max_angle = float(fin_max_angle)
        self.action_size = self.body.action_size(self.fin_actions)

    @property
    def num_envs(self) -> int:
        return self.state.x.shape[0]

    def reset_rows(self, rows: np.ndarray, rngs: list[np.random.Generator]) -> None:
        """Start new episodes in ``rows``, drawing row k's noise, task and start
        (:func:`~animat.envs.tasks.start.spread_start`) from ``rngs[k]``, in that order."""
        state, length = self.state, self.body.length
        start = self.task.place(self.body)
        start_v = self.task.start_velocity(self.body)
        for row, rng in zip(rows, rngs):
            noise = rng.uniform(-1.0, 1.0, self.body.rest_positions.shape)
            state.targets[row] = self.task.sample(rng)
            x, v, yaw = spread_start(start, start_v, self.body, self.start_spread, rng)
            state.x[row] = x + self.reset_noise_scale * length * noise
            state.v[row] = v
            state.start_yaw[row] = yaw
        state.u_prev[rows] = 0.0
        state.u_prev2[rows] = 0.0
        state.steps[rows] = 0
        state.splash[rows] = 0.0
        state.memory[rows] = self.task.initial_memory()
        state.touch[rows] = 0.0
        if self.ball is not None:
            state.ball[rows] = np.concatenate([self.ball.rest, np.zeros(3)])
        state.origin[rows] = self.kinematics().com[rows]

    def get_state(self) -> dict[str, np.ndarray]:
        """A copy of everything that changes (:class:`BodyState`'s arrays by name): given to
        :meth:`set_state` of a batch of the same config, it continues exactly from here."""
        return self.state.copy_arrays()

    def set_state(self, saved: dict[str, np.ndarray]) -> None:
        """Continue from ``saved`` (:meth:`get_state`'s dict); ValueError naming the first
        entry that does not fit this batch (wrong name, dtype or shape; bodies not finite), before
        anything is changed (:meth:`BodyState.restore`). A state saved before its task kept an
        episode memory (the turn's, since it follows the heading) restores with the task's
        initial memory, from which the task reads the body as it is."""
        memory = np.asarray(saved.get("memory", self.state.memory))
        if memory.shape == (self.num_envs, 0) and self.task.memory_size:
            saved = {**saved, "memory": np.tile(self.task.initial_memory(), (self.num_envs, 1))}
        self.state.restore(saved)

    def kinematics(self) -> Kinematics:
        """Centre of mass, its velocity and the body frames of the current state."""
        b = self.body
        return Kinematics(*body_state(self.state.x, self.state.v, b.masses, b.frame_front,
                                      b.frame_back, b.frame_up, b.frame_down))

    def step(self, actions: np.ndarray) -> tuple[np.ndarray, dict[str, np.ndarray], Kinematics]:
        """Advance every fish one env step with actions (B, ``action_size``) in [-1, 1] (already
        validated). Returns the reward (B,), the info arrays (each (B, ...)) and the
        kinematics of the new state (for :meth:`observe`)."""
        state, a = self.state, self.body.num_actuators
        u = 0.5 * (actions[:, :a] + 1.0)
        if self.fin_actions:
            state.fins[:] = self.fin_max_angle * actions[:, a:]
        state.splash[:] = 0.0
        ball = None if self.ball is None else (state.ball, state.touch, self._ball_args,
                                               self.body.face_parts)
        step_batch(state.x, state.v, state.u_prev, u, state.fins, self.frame_skip,
                   self.system.kernel_args, state.splash, ball)
        w = self.weights
        e_u = control_energy(u, state.u_prev, state.u_prev2, self.dt, w.nu1, w.nu2)
        state.u_prev2, state.u_prev = state.u_prev, u
        state.steps += 1
        info, kinematics = self.measure(last=self.truncated, commit=True)
        reward_ctrl = -w.mu1 * e_u * self.dt
        reward_task = -w.mu2 * info["E_v"] * self.dt
        info.update(E_u=e_u, reward_ctrl=reward_ctrl, reward_task=reward_task)
        return reward_ctrl + reward_task, info, kinematics

    @property
    def truncated(self) -> np.ndarray:
        """(B,) whether each episode has used its ``duration``."""
        return self.state.steps >= self.episode_steps

    def world(self, kinematics: Kinematics) -> World:
        """What a task may read of the current state (:class:`animat.envs.tasks.base.World`)."""
        state, (com, com_vel, frames) = self.state, kinematics
        return World(com=com - state.origin, com_vel=com_vel, frames=frames,
                     targets=state.targets, length=self.body.length, position=com,
                     x=state.x, v=state.v, splash=state.splash, memory=state.memory,
                     ball=state.ball, touch=state.touch,
                     surface_z=self.system.water.surface_z, body=self.body, dt=self.dt,
                     start_yaw=state.start_yaw)

    def measure(self, last: np.ndarray | None = None, commit: bool = False
                ) -> tuple[dict[str, np.ndarray], Kinematics]:
        """Info arrays of the current state: ``com`` (B, 3) m, ``forward`` (B, 3),
        ``linear_momentum`` (B, 3) kg m/s and ``angular_momentum`` (B, 3) kg m^2/s (world frame,
        about the centre of mass), ``time`` (B,) s, ``E_v`` (B,) and the task's metrics (B,);
        and the kinematics they were computed from. ``commit``: keep the task's updated
        episode memory (once per env step, by :meth:`step`)."""
        state = self.state
        kinematics = self.kinematics()
        com, com_vel, frames = kinematics
        linear, angular = momenta(state.x, state.v, self.body.masses, com)
        last = np.zeros(self.num_envs, dtype=bool) if last is None else last
        e_v, metrics, memory = self.task.terms(self.world(kinematics), last)
        if commit and state.memory.size:
            state.memory[:] = memory
        info = {"com": com, "forward": frames[:, 0].copy(), "linear_momentum": linear,
                "angular_momentum": angular, "time": state.steps * self.dt,
                "E_v": e_v, **metrics}
        return info, kinematics

    def proprioception(self, kinematics: Kinematics) -> np.ndarray:
        """(B, proprioception_size) float32, the body's own state: node positions and
        velocities relative to the centre of mass in the body frame (BL, BL/s, 3N each), the
        centre-of-mass velocity in the body frame (BL/s, 3), the world's up direction in the
        body frame (3), the current actuations (A); clipped to +-OBS_LIMIT."""
        state, (com, com_vel, frames) = self.state, kinematics
        obs = np.empty((self.num_envs, self.proprioception_size), dtype=np.float32)
        write_proprioception(state.x, state.v, state.u_prev, com, com_vel, frames,
                             self.body.length, OBS_LIMIT, obs)
        return obs

    def task_observation(self, kinematics: Kinematics) -> np.ndarray:
        """(B, task.obs_size) float32, the task's entries (:meth:`Task.observe` of the
        :meth:`world`), clipped to +-OBS_LIMIT."""
        if not self.task.obs_size:
            return np.empty((self.num_envs, 0), dtype=np.float32)
        task_obs = self.task.observe(self.world(kinematics))
        return np.clip(task_obs, -OBS_LIMIT, OBS_LIMIT).astype(np.float32)

    def observe(self, kinematics: Kinematics) -> np.ndarray:
        """(B, obs_size) float32: the body's :meth:`proprioception`, then the task's entries
        (:meth:`task_observation`). ``kinematics`` are the current state's (from
        :meth:`measure` or :meth:`step`)."""
        body = self.proprioception(kinematics)
        if not self.task.obs_size:
            return body
        return np.concatenate([body, self.task_observation(kinematics)], axis=1)
