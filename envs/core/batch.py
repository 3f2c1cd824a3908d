"""The batched core of every fish environment: state, step, observation, reward.

:class:`BodyBatch` holds B fish (B = 1 for a single env) and advances them together with
:func:`animat.envs.physics.integrator.step_batch`. The single env
(:class:`animat.envs.core.env.BodyEnv`) and the native vector env
(:class:`animat.envs.core.env.BodyVectorEnv`) are thin shells around it, so the physics, the
observation and the reward exist once.

Reward (the paper's Eq. 1, per env step of ``dt`` seconds):
``r = -(mu1 E_u + mu2 E_v) dt``, ``E_u = (nu1 |du/dt|^2 + nu2 |d^2u/dt^2|^2) / 2`` over the six
actuations u in [0, 1] (finite differences over env steps), E_v from the task.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import NamedTuple

import numpy as np
from numba import njit

from ..bodies.fish import fish_body
from ..bodies.spec import BodySpec
from ..checks import check_flag, check_integer, check_number, shown
from ..motor.fish import FinParams
from ..physics.integrator import step_batch
from ..physics.observe import body_state, momenta
from ..physics.observe import proprioception as write_proprioception
from ..physics.system import DEFAULT_DT, System, Water
from ..tasks.base import Task, World

OBS_LIMIT = 1e4  # observation entries are clipped to +-OBS_LIMIT
DEFAULT_FRAME_SKIP = 40  # integration steps per env step: 40 x 1.25 ms = 0.05 s
# What a batch accepts, so that a step and an episode cost a bounded time (one integration
# step of one fish takes ~5 us): one env step at most MAX_FRAME_SKIP integration steps (~0.05 s
# a fish), an episode at most MAX_DURATION s and MAX_EPISODE_SUBSTEPS integration steps.
MAX_FRAME_SKIP = 10_000
MAX_DURATION = 86_400.0  # s, a simulated day
MAX_EPISODE_SUBSTEPS = 10**9  # duration / physics_dt
MIN_PHYSICS_DT, MAX_PHYSICS_DT = 1e-6, 1.0  # s (the body's stability bound is lower: System)
MAX_NUM_ENVS = 65_536
MAX_RESET_NOISE = 0.1  # BL
MAX_REWARD_WEIGHT = 1e6


@dataclass(frozen=True)
class RewardWeights:
    """Weights of Eq. (1): mu1 (controller), mu2 (trajectory); nu1 (|du/dt|^2), nu2
    (|d^2u/dt^2|^2). Each a finite number in [0, ``MAX_REWARD_WEIGHT``] (1e6)."""

    mu1: float = 1e-4
    mu2: float = 1.0
    nu1: float = 1.0
    nu2: float = 0.01

    def __post_init__(self) -> None:
        for name in ("mu1", "mu2", "nu1", "nu2"):
            check_number(f"reward_weights.{name}", getattr(self, name), 0.0, MAX_REWARD_WEIGHT)

    @classmethod
    def from_value(cls, value: RewardWeights | dict | None) -> RewardWeights:
        """The weights of an env's ``reward_weights`` argument: None (the defaults), weights,
        or a dict of some of mu1, mu2, nu1, nu2; anything else, or an unknown name, is a
        ValueError of one line naming it."""
        if value is None or isinstance(value, RewardWeights):
            return value or cls()
        if not isinstance(value, dict):
            raise ValueError(f"reward_weights must be a dict of mu1, mu2, nu1, nu2, got "
                             f"{shown(value)}")
        unknown = sorted(map(str, set(value) - {"mu1", "mu2", "nu1", "nu2"}))
        if unknown:
            raise ValueError(f"reward_weights: unknown weight(s) {shown(unknown)}; known: "
                             "['mu1', 'mu2', 'nu1', 'nu2']")
        return cls(**value)


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


@dataclass
class BodyState:
    """Everything that changes while B fish move (arrays changed in place by
    :meth:`BodyBatch.step` and :meth:`BodyBatch.reset_rows`).

    Attributes:
        x, v: (B, N, 3) node positions (m) and velocities (m/s), world frame.
        u_prev, u_prev2: (B, A) the actuations of the last two env steps, in [0, 1].
        fins: (B, P) fin angles held over the current env step, rad.
        steps: (B,) env steps since each episode began.
        origin: (B, 3) centre of mass at each episode's start, m.
        targets: (B, T) each episode's task parameters (:meth:`animat.envs.tasks.base.Task.sample`).
        splash: (B,) the splash of the last env step: the impact momentum of the faces that
            went under the surface, kg m/s (:func:`animat.envs.physics.forces.add_face_forces`).
        memory: (B, M) what the task keeps over an episode (``Task.memory_size``).
        ball: (B, 6) the beach ball's position (m) and velocity (m/s), if the task has one.
        touch: (B, 3) the ball's contact impulse with each body part this episode, N s.
    """

    x: np.ndarray
    v: np.ndarray
    u_prev: np.ndarray
    u_prev2: np.ndarray
    fins: np.ndarray
    steps: np.ndarray
    origin: np.ndarray
    targets: np.ndarray
    splash: np.ndarray
    memory: np.ndarray
    ball: np.ndarray
    touch: np.ndarray

    @classmethod
    def zeros(cls, num_envs: int, body: BodySpec, task: Task) -> BodyState:
        n, a, p = body.num_nodes, body.num_actuators, body.fin_nodes.shape[0]
        return cls(np.zeros((num_envs, n, 3)), np.zeros((num_envs, n, 3)),
                   np.zeros((num_envs, a)), np.zeros((num_envs, a)), np.zeros((num_envs, p)),
                   np.zeros(num_envs, dtype=np.int64), np.zeros((num_envs, 3)),
                   np.zeros((num_envs, task.target_size)), np.zeros(num_envs),
                   np.zeros((num_envs, task.memory_size)), np.zeros((num_envs, 6)),
                   np.zeros((num_envs, 3)))


class Kinematics(NamedTuple):
    """What :meth:`BodyBatch.measure` computed and :meth:`BodyBatch.observe` reuses: centre of
    mass (B, 3) m, its velocity (B, 3) m/s, body frames (B, 3, 3) (rows forward, left, up)."""

    com: np.ndarray
    com_vel: np.ndarray
    frames: np.ndarray


def check_arguments(num_envs: int, physics_dt: float, frame_skip: int, duration: float,
                    reset_noise_scale: float, fins: bool, fin_max_angle: float) -> None:
    """Check a batch's arguments (:class:`BodyBatch`), each a ValueError of one line naming
    it: ``num_envs`` an integer in [1, 65536]; ``physics_dt`` a finite number in [1e-6, 1] s
    (:class:`~envs.physics.system.System` refuses one above the body's stability bound);
    ``frame_skip`` an integer in [1, 10000]; ``duration`` a finite number in (0, 86400] s
    and at most 1e9 integration steps (``duration / physics_dt``); ``reset_noise_scale`` in
    [0, 0.1] BL; ``fins`` a bool; ``fin_max_angle`` in [0, pi/2] rad."""
    check_integer("num_envs", num_envs, 1, MAX_NUM_ENVS)
    dt = check_number("physics_dt", physics_dt, MIN_PHYSICS_DT, MAX_PHYSICS_DT, "s")
    check_integer("frame_skip", frame_skip, 1, MAX_FRAME_SKIP)
    longest = min(MAX_DURATION, MAX_EPISODE_SUBSTEPS * dt)
    note = "" if longest == MAX_DURATION else (
        f"at most {MAX_EPISODE_SUBSTEPS:.0e} steps of physics_dt {dt:g} s an episode")
    check_number("duration", duration, 0.0, longest, "s", low_open=True, note=note)
    check_number("reset_noise_scale", reset_noise_scale, 0.0, MAX_RESET_NOISE, "BL")
    check_flag("fins", fins)
    check_number("fin_max_angle", fin_max_angle, 0.0, np.pi / 2, "rad")


class BodyBatch:
    """B fish doing one task: a :class:`~envs.physics.system.System` (fixed), a
    :class:`BodyState` (``state``, what changes) and the step, measurement and observation
    functions on them.

    Args:
        num_envs: B.
        task: the :class:`~envs.tasks.base.Task`.
        body: the body description (default: :func:`animat.envs.bodies.fish.fish_body`).
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

    The numbers are checked (:func:`check_arguments`): a bad one is a ValueError of one line
    naming it.
    """

    def __init__(self, num_envs: int, task: Task, body: BodySpec | None = None,
                 water: Water | dict | None = None, physics_dt: float = DEFAULT_DT,
                 frame_skip: int = DEFAULT_FRAME_SKIP,
                 duration: float = 10.0, reset_noise_scale: float = 0.005,
                 weights: RewardWeights = RewardWeights(), fins: bool = False,
                 fin_max_angle: float = FinParams().max_angle) -> None:
        check_arguments(num_envs, physics_dt, frame_skip, duration, reset_noise_scale, fins,
                        fin_max_angle)
        self.task, self.weights = task, weights
        self.system = System(body or fish_body(), Water.from_dict(water), dt=physics_dt)
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
        self.action_size = a + (self.state.fins.shape[1] if self.fin_actions else 0)

    @property
    def num_envs(self) -> int:
        return self.state.x.shape[0]

    def reset_rows(self, rows: np.ndarray, rngs: list[np.random.Generator]) -> None:
        """Start new episodes in ``rows``, drawing row k's noise and task from ``rngs[k]``."""
        state, length = self.state, self.body.length
        start = self.task.place(self.body)
        start_v = self.task.start_velocity(self.body)
        for row, rng in zip(rows, rngs):
            noise = rng.uniform(-1.0, 1.0, self.body.rest_positions.shape)
            state.x[row] = start + self.reset_noise_scale * length * noise
            state.v[row] = start_v
            state.targets[row] = self.task.sample(rng)
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
        return {f.name: getattr(self.state, f.name).copy() for f in fields(BodyState)}

    def set_state(self, saved: dict[str, np.ndarray]) -> None:
        """Continue from ``saved`` (:meth:`get_state`'s dict); ValueError naming the first
        entry that does not fit this batch (wrong name, dtype or shape; bodies not finite), before
        anything is changed."""
        names = [f.name for f in fields(BodyState)]
        if sorted(saved) != sorted(names):
            raise ValueError(f"a fish state has the entries {names}, got {sorted(saved)}")
        arrays = {}
        for name in names:
            current, value = getattr(self.state, name), np.asarray(saved[name])
            if value.shape != current.shape or value.dtype != current.dtype:
                raise ValueError(f"fish state {name!r} must be {current.dtype} of shape "
                                 f"{current.shape}, got {value.dtype} of shape {value.shape}")
            if name in ("x", "v") and not np.isfinite(value).all():  # (task memory may be)
                raise ValueError(f"fish state {name!r} is not finite")
            arrays[name] = value.copy()
        for name, value in arrays.items():
            setattr(self.state, name, value)

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
                     surface_z=self.system.water.surface_z, body=self.body, dt=self.dt)

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
