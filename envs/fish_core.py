"""The batched core of every fish environment: state, step, observation, reward.

:class:`FishBatch` holds B fish (B = 1 for a single env) and advances them together with
:func:`envs.physics.integrator.step_batch`. The single env (:class:`envs.fish_env.FishEnv`) and
the native vector env (:class:`envs.fish_env.FishVectorEnv`) are thin shells around it, so the
physics, the observation and the reward exist once.

Reward (the paper's Eq. 1, per env step of ``dt`` seconds):
``r = -(mu1 E_u + mu2 E_v) dt``, ``E_u = (nu1 |du/dt|^2 + nu2 |d^2u/dt^2|^2) / 2`` over the six
actuations u in [0, 1] (finite differences over env steps), E_v from the task.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from envs.body import BodySpec
from envs.fish import fish_body
from envs.motor import FinParams
from envs.physics.integrator import step_batch
from envs.physics.observe import body_state, momenta, proprioception
from envs.physics.system import DEFAULT_DT, System, Water
from envs.tasks import Task

OBS_LIMIT = 1e4  # observation entries are clipped to +-OBS_LIMIT
DEFAULT_FRAME_SKIP = 40  # integration steps per env step: 40 x 1.25 ms = 0.05 s


@dataclass(frozen=True)
class RewardWeights:
    """Weights of Eq. (1): mu1 (controller), mu2 (trajectory); nu1 (|du/dt|^2), nu2
    (|d^2u/dt^2|^2)."""

    mu1: float = 1e-4
    mu2: float = 1.0
    nu1: float = 1.0
    nu2: float = 0.01


def validate_actions(actions: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    """Return ``actions`` as float64 of ``shape``, clipped to [-1, 1]; raise ValueError naming
    the problem for a wrong shape, NaN or infinity (before anything is changed)."""
    array = np.asarray(actions, dtype=np.float64)
    if array.shape != shape:
        raise ValueError(f"action must have shape {shape}, got {array.shape}")
    clipped = np.empty_like(array)
    if not _clip_finite(array.reshape(-1), clipped.reshape(-1)):
        bad = "NaN" if np.isnan(array).any() else "infinite"
        raise ValueError(f"action contains {bad} values: {np.asarray(actions).tolist()}")
    return clipped


@njit(cache=True)
def _clip_finite(values, out) -> bool:
    """out = values clipped to [-1, 1]; False if any value is NaN or infinite (one pass)."""
    for k in range(values.shape[0]):
        value = values[k]
        if not np.isfinite(value):
            return False
        out[k] = min(max(value, -1.0), 1.0)
    return True


@njit(cache=True)
def control_energy(u, u_prev, u_prev2, dt, nu1, nu2):
    """(B,) E_u = (nu1 |du/dt|^2 + nu2 |d^2u/dt^2|^2) / 2 by finite differences over env steps
    of ``dt`` s, actuations u, u_prev, u_prev2 (B, A) at this and the two previous steps."""
    out = np.zeros(u.shape[0])
    for b in range(u.shape[0]):
        first = second = 0.0
        for k in range(u.shape[1]):
            du = (u[b, k] - u_prev[b, k]) / dt
            ddu = (u[b, k] - 2.0 * u_prev[b, k] + u_prev2[b, k]) / (dt * dt)
            first += du * du
            second += ddu * ddu
        out[b] = 0.5 * (nu1 * first + nu2 * second)
    return out


class FishBatch:
    """B fish doing one task.

    Args:
        num_envs: B.
        task: the :class:`~envs.tasks.Task`.
        body: the body description (default: :func:`envs.fish.fish_body`).
        water: the medium, a :class:`~envs.physics.system.Water` or a dict of its fields
            (default: still fresh water, no surface).
        physics_dt: integration step, s.
        frame_skip: integration steps per env step (env ``dt = physics_dt * frame_skip``).
        duration: simulated seconds per episode (then truncated).
        reset_noise_scale: uniform noise on each start node coordinate, body lengths.
        weights: reward weights.
        fins: if True the actions carry the pectoral fin angles too: (B, A + P), the last P
            entries in [-1, 1] setting fin p to ``fin_max_angle`` (rad) times the entry.
        fin_max_angle: rad, the fin angle of an action entry of 1 (the fin-MC's gain).
    """

    def __init__(self, num_envs: int, task: Task, body: BodySpec | None = None,
                 water: Water | dict | None = None, physics_dt: float = DEFAULT_DT,
                 frame_skip: int = DEFAULT_FRAME_SKIP,
                 duration: float = 10.0, reset_noise_scale: float = 0.005,
                 weights: RewardWeights = RewardWeights(), fins: bool = False,
                 fin_max_angle: float = FinParams().max_angle) -> None:
        if int(frame_skip) < 1:
            raise ValueError(f"frame_skip must be >= 1, got {frame_skip!r}")
        if not duration > 0:
            raise ValueError(f"duration must be > 0 seconds, got {duration!r}")
        self.task, self.weights = task, weights
        self.system = System(body or fish_body(), Water.from_dict(water), dt=physics_dt)
        self.body = self.system.body
        self.frame_skip = int(frame_skip)
        self.dt = self.system.dt * self.frame_skip
        self.episode_steps = max(1, int(round(duration / self.dt)))
        self.reset_noise_scale = float(reset_noise_scale)
        n, a = self.body.num_nodes, self.body.num_actuators
        self.x = np.zeros((num_envs, n, 3))
        self.v = np.zeros((num_envs, n, 3))
        self.u_prev = np.zeros((num_envs, a))
        self.u_prev2 = np.zeros((num_envs, a))
        self.fins = np.zeros((num_envs, self.body.fin_nodes.shape[0]))
        self.steps = np.zeros(num_envs, dtype=np.int64)
        self.origin = np.zeros((num_envs, 3))
        self.targets = np.zeros((num_envs, task.target_size))
        self.obs_size = 2 * n * 3 + 6 + a + task.obs_size
        self.fin_actions = bool(fins)
        self.fin_max_angle = float(fin_max_angle)
        self.action_size = a + (self.fins.shape[1] if self.fin_actions else 0)

    @property
    def num_envs(self) -> int:
        return self.x.shape[0]

    def reset_rows(self, rows: np.ndarray, rngs: list[np.random.Generator]) -> None:
        """Start new episodes in ``rows``, drawing row k's noise and task from ``rngs[k]``."""
        length = self.body.length
        for row, rng in zip(rows, rngs):
            noise = rng.uniform(-1.0, 1.0, self.body.rest_positions.shape)
            self.x[row] = self.body.rest_positions + self.reset_noise_scale * length * noise
            self.v[row] = 0.0
            self.targets[row] = self.task.sample(rng)
        self.u_prev[rows] = 0.0
        self.u_prev2[rows] = 0.0
        self.steps[rows] = 0
        self.origin[rows] = self.centre_of_mass()[rows]

    def centre_of_mass(self) -> np.ndarray:
        """(B, 3) centre of mass, m."""
        return body_state(self.x, self.v, self.body.masses, *self._frame_nodes())[0]

    def _frame_nodes(self) -> tuple:
        b = self.body
        return b.frame_front, b.frame_back, b.frame_up, b.frame_down

    def step(self, actions: np.ndarray) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """Advance every fish one env step with actions (B, ``action_size``) in [-1, 1] (already
        validated). Returns the reward (B,) and the info arrays (each (B, ...))."""
        a = self.body.num_actuators
        u = 0.5 * (actions[:, :a] + 1.0)
        if self.fin_actions:
            self.fins[:] = self.fin_max_angle * actions[:, a:]
        step_batch(self.x, self.v, self.u_prev, u, self.fins, self.frame_skip,
                   self.system.kernel_args)
        w = self.weights
        e_u = control_energy(u, self.u_prev, self.u_prev2, self.dt, w.nu1, w.nu2)
        self.u_prev2, self.u_prev = self.u_prev, u
        self.steps += 1
        info = self.measure(last=self.truncated)
        reward_ctrl = -w.mu1 * e_u * self.dt
        reward_task = -w.mu2 * info["E_v"] * self.dt
        info.update(E_u=e_u, reward_ctrl=reward_ctrl, reward_task=reward_task)
        return reward_ctrl + reward_task, info

    @property
    def truncated(self) -> np.ndarray:
        """(B,) whether each episode has used its ``duration``."""
        return self.steps >= self.episode_steps

    def measure(self, last: np.ndarray | None = None) -> dict[str, np.ndarray]:
        """Info arrays: ``com`` (B, 3) m, ``forward`` (B, 3), ``linear_momentum`` (B, 3) kg m/s
        and ``angular_momentum`` (B, 3) kg m^2/s (world frame, about the centre of mass),
        ``time`` (B,) s, ``E_v`` (B,) and the task's metrics (B,); caches what :meth:`observe`
        needs."""
        com, com_vel, frames = body_state(self.x, self.v, self.body.masses, *self._frame_nodes())
        linear, angular = momenta(self.x, self.v, self.body.masses, com)
        self._cache = (com, com_vel, frames)
        last = np.zeros(self.num_envs, dtype=bool) if last is None else last
        e_v, metrics = self.task.terms(com - self.origin, com_vel, frames, self.targets,
                                       self.body.length, last)
        return {"com": com, "forward": frames[:, 0].copy(), "linear_momentum": linear,
                "angular_momentum": angular, "time": self.steps * self.dt,
                "E_v": e_v, **metrics}

    def observe(self) -> np.ndarray:
        """(B, obs_size) float32: node positions and velocities relative to the centre of mass
        in the body frame (BL, BL/s), the centre-of-mass velocity in the body frame (BL/s), the
        world's up direction in the body frame, the current actuations, the task's entries.
        Uses the quantities of the last :meth:`measure`; entries are clipped to +-OBS_LIMIT."""
        com, com_vel, frames = self._cache
        obs = np.empty((self.num_envs, self.obs_size), dtype=np.float32)
        proprioception(self.x, self.v, self.u_prev, com, com_vel, frames, self.body.length,
                       OBS_LIMIT, obs)
        if self.task.obs_size:
            task_obs = self.task.observe(com - self.origin, com_vel, frames, self.targets,
                                         self.body.length)
            obs[:, self.obs_size - self.task.obs_size:] = np.clip(task_obs, -OBS_LIMIT,
                                                                  OBS_LIMIT)
        return obs
